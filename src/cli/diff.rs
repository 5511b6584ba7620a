//! `combustion diff A B`: two images compared (`combustion::diff`), with criteria.

use std::path::Path;

use combustion::diff::{compare, heat_map_with_legend, open_image, Comparison};
use combustion::{output, Error};

use super::*;
use super::{write_stdout, CliError};

pub(crate) fn diff(o: &DiffArgs) -> Result<(), CliError> {
    // The heat map's destination is checked before any image is read.
    if let Some(heatmap) = &o.heatmap {
        output::check_extension(heatmap, "--heatmap", "PNG", &["png"])?;
        output::check_writable(heatmap)?;
        let mut inputs = vec![
            ("first image", o.a.as_path()),
            ("second image", o.b.as_path()),
        ];
        if let Some(file) = &o.criteria_file {
            inputs.push(("criteria file", file.as_path()));
        }
        output::check_not_an_input(heatmap, &inputs)?;
    }
    // Like is compared with like, by the extensions the reader goes by: said before a
    // byte is read, as a usage error.
    let kind = |path: &Path| {
        path.extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .filter(|e| e == "png" || e == "exr")
    };
    if let (Some(ka), Some(kb)) = (kind(&o.a), kind(&o.b)) {
        if ka != kb {
            return Err(Error::Usage(format!(
                "{} is {} and {} is {}: compare a PNG with a PNG (display values) or an OpenEXR with an OpenEXR (radiance)",
                combustion::shortened(&o.a.display().to_string()),
                if ka == "png" { "a PNG" } else { "an OpenEXR" },
                combustion::shortened(&o.b.display().to_string()),
                if kb == "png" { "a PNG" } else { "an OpenEXR" },
            ))
            .into());
        }
    }
    let named = |path: &Path, e: String| {
        CliError::Failed(format!(
            "{}: {e}",
            combustion::shortened(&path.display().to_string())
        ))
    };
    let open = |path: &Path| open_image(path).map_err(|e| named(path, e));
    let from_file = match &o.criteria_file {
        Some(path) => {
            let name = combustion::shortened(&path.display().to_string());
            let text = combustion::input::read_text(
                path,
                combustion::input::MAX_CRITERIA_BYTES,
                "a criteria file",
            )
            .map_err(|e| CliError::Failed(format!("--criteria-file {name}: {e}")))?;
            let criteria = combustion::diff::Criteria::parse_file_text(&text)
                .map_err(|e| Error::Usage(format!("--criteria-file {name}: {e}")))?;
            Some(criteria)
        }
        None => None,
    };
    if let (Some(criteria), Some(extension)) =
        (o.criteria.as_ref().or(from_file.as_ref()), kind(&o.a))
    {
        let radiance = extension == "exr";
        if let Some(term) = criteria.wrong_kind(radiance) {
            return Err(Error::Usage(format!(
                "criterion `{term}` does not apply to {}: use {}",
                if radiance {
                    "OpenEXR images (radiance)"
                } else {
                    "PNG images (display values)"
                },
                if radiance {
                    "max-relative-diff X on at most P% of pixels"
                } else {
                    "max-channel-diff N/255 on at most P% of pixels"
                }
            ))
            .into());
        }
    }
    // Both headers before either image is decoded: sizes that differ are said at once
    // (two images were decoded whole to say so).
    let (file_a, file_b) = (open(&o.a)?, open(&o.b)?);
    if (file_a.width, file_a.height) != (file_b.width, file_b.height) {
        return Err(CliError::Failed(format!(
            "the images differ in size: {}x{} and {}x{}",
            file_a.width, file_a.height, file_b.width, file_b.height
        )));
    }
    let a = file_a.decode().map_err(|e| named(&o.a, e))?;
    drop(file_a);
    let b = file_b.decode().map_err(|e| named(&o.b, e))?;
    drop(file_b);
    let comparison = compare(&a, &b).map_err(CliError::Failed)?;
    if let Some(heatmap) = &o.heatmap {
        let (height, pixels) = heat_map_with_legend(&comparison).map_err(CliError::Failed)?;
        output::write_png(heatmap, comparison.width, height, &pixels)?;
    }
    let verdict = o
        .criteria
        .as_ref()
        .or(from_file.as_ref())
        .map(|c| c.check(&comparison));
    if o.json {
        write_stdout(format_args!("{}\n", json(&comparison, verdict.as_ref())));
    } else {
        write_stdout(format_args!("{}\n", summary(&comparison)));
    }
    match verdict {
        Some(Err(why)) => Err(CliError::Failed(format!(
            "the images differ beyond the criteria: {why}"
        ))),
        _ => Ok(()),
    }
}

fn summary(c: &Comparison) -> String {
    let largest = if c.radiance {
        format!(
            "largest relative channel difference {:.3e}",
            c.max_channel_diff()
        )
    } else {
        format!("largest channel difference {}/255", c.max_channel_diff())
    };
    format!(
        "{}x{} {}: {largest} ({:.4}% of pixels differ); FLIP mean {:.4e}, median {:.4e}, p99 {:.4e}, max {:.4e}",
        c.width,
        c.height,
        if c.radiance { "radiance (OpenEXR)" } else { "display (PNG)" },
        c.share_above(0.0) * 100.0,
        c.mean_flip(),
        c.flip_quantile(0.5),
        c.flip_quantile(0.99),
        c.flip_quantile(1.0),
    )
}

fn json(c: &Comparison, verdict: Option<&Result<(), String>>) -> String {
    let number =
        |x: f64| serde_json::Number::from_f64(x).map_or(serde_json::Value::Null, Into::into);
    let mut value = serde_json::json!({
        "width": c.width,
        "height": c.height,
        "kind": if c.radiance { "radiance" } else { "display" },
        "max_channel_diff": number(c.max_channel_diff()),
        "channel_diff_unit": if c.radiance { "relative" } else { "8-bit steps" },
        "share_of_pixels_differing": number(c.share_above(0.0)),
        "flip": {
            "mean": number(c.mean_flip()),
            "median": number(c.flip_quantile(0.5)),
            "p95": number(c.flip_quantile(0.95)),
            "p99": number(c.flip_quantile(0.99)),
            "max": number(c.flip_quantile(1.0)),
        },
    });
    if let Some(verdict) = verdict {
        value["pass"] = verdict.is_ok().into();
        if let Err(why) = verdict {
            value["failed"] = why.clone().into();
        }
    }
    value.to_string()
}
