//! `combustion batch MANIFEST -o DIR`: every job of a manifest ([`super::manifest`])
//! rendered in one process on one device, each scene uploaded once for all the jobs
//! that show it; outputs compared with goldens by the jobs' criteria; results written as
//! JSON and JUnit XML; `--merge` combines shards' results.
//!
//! Its arithmetic cannot overflow and it indexes nothing unchecked: clippy's
//! `arithmetic_side_effects` and `indexing_slicing` are denied here.
#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde_json::{json, Map, Value};

use combustion::diff::{compare, heat_map_with_legend, read_image, Comparison, Criteria};
use combustion::optics::readable::readable;
use combustion::renderer::{
    FrameInputs, GBufferStorage, HdrFormat, Readback, Renderer, RendererSettings,
};
use combustion::{output, report, shortened, Error};

use super::manifest::{Job, Manifest};
use super::*;
use super::{write_stdout, CliError};

/// The results file each run writes in its folder (and `--merge` reads).
pub(crate) const RESULTS_FILE: &str = "results.json";

/// The JUnit XML file each run writes in its folder.
pub(crate) const JUNIT_FILE: &str = "junit.xml";

/// How a job ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Status {
    /// Rendered, and every output within its criteria against its golden.
    Passed,
    /// Rendered, with no goldens to compare against.
    Rendered,
    /// Rendered, and its goldens written (`--update-goldens`).
    GoldensWritten,
    /// Rendered, but an output is beyond its criteria, or its golden is missing or of
    /// another size.
    Failed,
    /// Not rendered: the scene, an option or the device refused it.
    Error,
}

impl Status {
    fn name(self) -> &'static str {
        match self {
            Status::Passed => "passed",
            Status::Rendered => "rendered",
            Status::GoldensWritten => "goldens-written",
            Status::Failed => "failed",
            Status::Error => "error",
        }
    }

    fn from_name(name: &str) -> Option<Status> {
        [
            Status::Passed,
            Status::Rendered,
            Status::GoldensWritten,
            Status::Failed,
            Status::Error,
        ]
        .into_iter()
        .find(|s| s.name() == name)
    }

    fn ok(self) -> bool {
        !matches!(self, Status::Failed | Status::Error)
    }
}

/// A job's result, as results.json keeps it.
struct JobResult {
    index: usize,
    name: String,
    scene: String,
    status: Status,
    /// Why it failed, or did not render: one line.
    message: Option<String>,
    seconds: f64,
    /// Per output: kind, file, and the comparison's figures.
    outputs: Vec<Value>,
    physics: Option<Value>,
}

impl JobResult {
    fn json(&self) -> Value {
        json!({
            "index": self.index,
            "name": self.name,
            "scene": self.scene,
            "status": self.status.name(),
            "message": self.message,
            "seconds": self.seconds,
            "outputs": self.outputs,
            "physics_error": self.physics,
        })
    }

    fn from_json(value: &Value) -> Option<JobResult> {
        Some(JobResult {
            index: usize::try_from(value.get("index")?.as_u64()?).ok()?,
            name: value.get("name")?.as_str()?.to_owned(),
            scene: value.get("scene")?.as_str()?.to_owned(),
            status: Status::from_name(value.get("status")?.as_str()?)?,
            // Read from a file: on one line, control characters escaped, before the
            // table or junit.xml shows it.
            message: value.get("message")?.as_str().map(super::one_line),
            seconds: value.get("seconds")?.as_f64()?,
            outputs: value.get("outputs")?.as_array()?.clone(),
            physics: value.get("physics_error").filter(|v| !v.is_null()).cloned(),
        })
    }
}

/// Where a run writes and what it compares with.
struct Folders<'a> {
    output: &'a Path,
    goldens: Option<&'a Path>,
    update_goldens: bool,
}

pub(crate) fn batch(o: &BatchArgs) -> Result<(), CliError> {
    if !o.merge.is_empty() {
        return merge(&o.merge, &o.output);
    }
    let manifest_path = o
        .manifest
        .as_ref()
        .ok_or_else(|| Error::Usage("batch needs a MANIFEST (or --merge)".into()))?;
    let mut manifest = Manifest::read(manifest_path)?;
    if let Some(shard) = o.shard {
        manifest.keep_shard(shard);
        if manifest.jobs.is_empty() {
            log::warn!(
                "--shard {}/{}: no job of {} falls to this shard (more shards than jobs); its results list none",
                shard.index,
                shard.count,
                manifest_path.display()
            );
        }
    }
    if let Some(goldens) = &o.goldens {
        if !o.update_goldens && !goldens.is_dir() {
            return Err(Error::Usage(format!(
                "--goldens {}: no such folder (--update-goldens writes it)",
                goldens.display()
            ))
            .into());
        }
    }
    if let Some(goldens) = &o.goldens {
        if !o.update_goldens && output::same_existing_file(&o.output, goldens) {
            return Err(Error::Usage(format!(
                "-o {} and --goldens {} are one folder: the renders would replace the goldens they are compared with; give -o a folder of its own",
                o.output.display(),
                goldens.display()
            ))
            .into());
        }
    }
    prepare_folder(&o.output, "-o")?;
    if let (Some(goldens), true) = (&o.goldens, o.update_goldens) {
        prepare_folder(goldens, "--goldens")?;
    }
    let folders = Folders {
        output: &o.output,
        goldens: o.goldens.as_deref(),
        update_goldens: o.update_goldens,
    };
    let started = Instant::now();
    let results = run_jobs(&manifest, &folders, &o.device)?;
    let seconds = started.elapsed().as_secs_f64();
    let run = json!({
        "manifest": manifest.name,
        "manifest_digest": manifest.digest,
        "shard": o.shard.map(|s| json!({"index": s.index, "count": s.count})),
        "seconds": seconds,
        "jobs": results.iter().map(JobResult::json).collect::<Vec<_>>(),
    });
    finish(&run, &results, &manifest.name, &o.output)
}

/// Writes results.json and junit.xml into `folder`, prints the table and the summary,
/// and fails (exit 1) if a job did not pass.
fn finish(run: &Value, results: &[JobResult], suite: &str, folder: &Path) -> Result<(), CliError> {
    let seconds = run["seconds"].as_f64().unwrap_or(0.0);
    output::write_files_atomically(&[
        (folder.join(RESULTS_FILE), format!("{run:#}\n").into_bytes()),
        (
            folder.join(JUNIT_FILE),
            junit(suite, results, seconds).into_bytes(),
        ),
    ])?;
    write_stdout(format_args!("{}", table(results)));
    let bad: Vec<&str> = results
        .iter()
        .filter(|r| !r.status.ok())
        .map(|r| r.name.as_str())
        .collect();
    let count = |status: Status| results.iter().filter(|r| r.status == status).count();
    write_stdout(format_args!(
        "{} jobs in {seconds:.1} s: {} passed, {} rendered without goldens, {} goldens written, {} failed, {} errors; {}, {}\n",
        results.len(),
        count(Status::Passed),
        count(Status::Rendered),
        count(Status::GoldensWritten),
        count(Status::Failed),
        count(Status::Error),
        crate::escaped(&folder.join(RESULTS_FILE).display().to_string()),
        crate::escaped(&folder.join(JUNIT_FILE).display().to_string()),
    ));
    if bad.is_empty() {
        Ok(())
    } else {
        let listed: Vec<&str> = bad.iter().take(10).copied().collect();
        Err(CliError::Failed(format!(
            "{} of {} jobs did not pass: {}{}",
            bad.len(),
            results.len(),
            listed.join(", "),
            if bad.len() > listed.len() {
                ", …"
            } else {
                ""
            }
        )))
    }
}

/// Makes `folder` (and its parents) and checks that it takes new files.
fn prepare_folder(folder: &Path, option: &str) -> Result<(), Error> {
    output::make_folder(folder)
        .map_err(|e| Error::Usage(format!("{option} {}: {e}", folder.display())))?;
    output::check_writable(&folder.join(RESULTS_FILE))?;
    if option == "-o" {
        // Both reports are checked before any job renders (junit.xml was checked only
        // once every job had rendered).
        output::check_writable(&folder.join(JUNIT_FILE))?;
        remove_earlier_outputs(folder)?;
    }
    Ok(())
}

/// Removes from `folder` the images and heat maps an earlier run's results.json there
/// lists (plain file names in the folder, nothing else), so that none of them stands
/// beside the new results as if this run had written it. A results.json that cannot be
/// read as one leaves the folder as it is.
fn remove_earlier_outputs(folder: &Path) -> Result<(), Error> {
    let results = folder.join(RESULTS_FILE);
    let Ok(text) = combustion::input::read_text(
        &results,
        super::manifest::MAX_MANIFEST_BYTES * 4,
        "an earlier run's results",
    ) else {
        return Ok(());
    };
    let Ok(run) = combustion::input::parse_json(&text) else {
        return Ok(());
    };
    let listed = run
        .get("jobs")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|job| job.get("outputs").and_then(Value::as_array))
        .flatten()
        .flat_map(|output| [output.get("file"), output.get("heat_map")])
        .flatten()
        .filter_map(Value::as_str);
    for name in listed {
        let plain = Path::new(name)
            .file_name()
            .is_some_and(|file| file == std::ffi::OsStr::new(name));
        let path = folder.join(name);
        if plain && path.symlink_metadata().is_ok_and(|m| m.is_file()) {
            std::fs::remove_file(&path).map_err(|e| {
                Error::Usage(format!(
                    "-o {}: cannot remove the earlier run's {name}: {e}",
                    folder.display()
                ))
            })?;
        }
    }
    Ok(())
}

/// A renderer for each combination of the settings fixed when one is made.
struct Renderers {
    device: std::sync::Arc<combustion::vk::Device>,
    made: Vec<((HdrFormat, GBufferStorage), Renderer)>,
}

impl Renderers {
    fn get(&mut self, settings: RendererSettings) -> Result<&mut Renderer, Error> {
        let key = (settings.hdr_format, settings.gbuffer);
        if !self.made.iter().any(|(k, _)| *k == key) {
            let renderer = Renderer::new(self.device.clone(), settings)?;
            self.made.push((key, renderer));
        }
        let (_, renderer) = self
            .made
            .iter_mut()
            .find(|(k, _)| *k == key)
            .expect("a renderer of these settings is made above");
        Ok(renderer)
    }
}

/// The jobs that share a scene upload: the same renderer, scene, file camera,
/// environment, light rig and metal colours.
fn group_key(job: &Job, settings: &RendererSettings) -> String {
    let file_camera = match job.render.camera.camera {
        CameraChoice::File(index) => Some(index),
        _ => None,
    };
    format!(
        "{:?} {:?} {:?} {file_camera:?} {:?} {} {} {}",
        settings.hdr_format,
        settings.gbuffer,
        job.render.scene.source(),
        job.render.shading.environment,
        job.render.shading.light_rig,
        job.render.shading.scene_lights,
        job.render.shading.metal_colour.name()
    )
}

fn run_jobs(
    manifest: &Manifest,
    folders: &Folders<'_>,
    device: &DeviceArgs,
) -> Result<Vec<JobResult>, CliError> {
    // A shard of more shards than jobs may hold none: it renders nothing (no device is
    // made) and its results say so, so the split still merges.
    let Some(first) = manifest.jobs.first().map(|job| &job.render) else {
        return Ok(Vec::new());
    };
    let (desc, _) = device_and_settings(device, &first.frame, 1)?;
    let device = combustion::vk::Device::new(&desc).map_err(Error::from)?;
    let validation = device.validation_log();
    let mut renderers = Renderers {
        device,
        made: Vec::new(),
    };
    // Groups in the order of their first job; jobs in the manifest's order within each.
    let mut groups: Vec<(String, Vec<&Job>)> = Vec::new();
    for job in &manifest.jobs {
        let settings = renderer_settings(&job.render.frame, 1);
        let key = group_key(job, &settings);
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, jobs)) => jobs.push(job),
            None => groups.push((key, vec![job])),
        }
    }
    let total = manifest.jobs.len();
    let terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let mut results = Vec::with_capacity(total);
    for (_, jobs) in &groups {
        let started = Instant::now();
        let Some(first_job) = jobs.first() else {
            continue;
        };
        let first = &first_job.render;
        let source = first.scene.source();
        let loaded = loaded_as_asked(&source, first.camera.camera, &first.shading);
        let settings = renderer_settings(&first.frame, 1);
        let uploaded = loaded.and_then(|scene| {
            let renderer = renderers.get(settings)?;
            let gpu = renderer.upload(&scene)?;
            Ok((scene, gpu))
        });
        let upload_seconds = started.elapsed().as_secs_f64();
        for job in jobs {
            if terminal {
                eprint!(
                    "\r\x1b[2K[{:>3}/{total}] {}",
                    results.len().saturating_add(1),
                    job.name
                );
            }
            let started = Instant::now();
            let seen = validation.messages().len();
            let mut result = match &uploaded {
                Ok((scene, gpu)) => {
                    let renderer = renderers.get(settings)?;
                    run_job(job, scene, gpu, renderer, folders)
                }
                Err(e) => JobResult::error(job, e),
            };
            if let Some(message) = validation.messages().get(seen) {
                result.status = Status::Error;
                result.message = Some(format!("validation: {}", shortened(message)));
            }
            // The group's loading and upload is charged to its first job.
            result.seconds = started.elapsed().as_secs_f64()
                + if std::ptr::eq(job, first_job) {
                    upload_seconds
                } else {
                    0.0
                };
            results.push(result);
        }
        if let Ok((_, gpu)) = uploaded {
            renderers.get(settings)?.retire(gpu);
        }
    }
    if terminal {
        eprint!("\r\x1b[2K");
    }
    results.sort_by_key(|r| r.index);
    Ok(results)
}

impl JobResult {
    fn new(job: &Job) -> JobResult {
        JobResult {
            index: job.index,
            name: job.name.clone(),
            scene: job.render.scene.source().label(),
            status: Status::Rendered,
            message: None,
            seconds: 0.0,
            outputs: Vec::new(),
            physics: None,
        }
    }

    fn error(job: &Job, e: &Error) -> JobResult {
        JobResult {
            status: Status::Error,
            message: Some(super::one_line(&e.to_string())),
            ..JobResult::new(job)
        }
    }
}

/// Renders `job` of the uploaded `scene` and writes, compares or updates its outputs.
fn run_job(
    job: &Job,
    scene: &combustion::scene::Scene,
    gpu: &combustion::renderer::GpuScene,
    renderer: &mut Renderer,
    folders: &Folders<'_>,
) -> JobResult {
    match render_job(job, scene, gpu, renderer, folders) {
        Ok(result) => result,
        Err(e) => JobResult::error(job, &e),
    }
}

fn render_job(
    job: &Job,
    scene: &combustion::scene::Scene,
    gpu: &combustion::renderer::GpuScene,
    renderer: &mut Renderer,
    folders: &Folders<'_>,
) -> Result<JobResult, Error> {
    let o = &job.render;
    let settings = renderer_settings(&o.frame, 1);
    renderer.set_shading(o.shading.options(settings.shading), &[gpu])?;
    let camera = o.camera.camera.place(scene);
    let mut lights = scene.lights.clone();
    lights.extend(o.shading.light_rig(&camera));
    let pose = o.animation.pose(scene)?;
    let tone_mapping = o.picture.tone_mapping_for(&o.scene.source());
    let inputs = FrameInputs {
        camera,
        lights: &lights,
        background: o.picture.background_for(scene),
        tone_mapping,
        // A job whose physics error is measured compares its picture with the
        // reference's pixel by pixel: unsmoothed unless it asks otherwise.
        anti_aliasing: if job.error {
            o.picture
                .anti_aliasing
                .unwrap_or(combustion::renderer::AntiAliasing::None)
        } else {
            o.picture.anti_aliasing_for(o.supersample)
        },
        pose: pose.as_ref(),
        auto_exposure: o.frame.auto_exposure()?,
        bloom_intensity: o.frame.bloom_intensity(super::render::pass_asked(
            &o.shading.optional.passes,
            "bloom",
        ))?,
        ..FrameInputs::of_scene(gpu, settings.exposure)
    };
    let readback = Readback {
        images: true,
        gbuffer: job.error,
    };
    let until = super::render::frames_averaged(o)?;
    let frame = if let Some(until) = until {
        if job.error {
            return Err(Error::Usage(format!(
                "job `{}`: \"error\": true cannot be combined with samples or accumulate-until (the error is measured against one frame's surfaces): give one",
                job.name
            )));
        }
        let size = (o.frame.width, o.frame.height);
        super::render::accumulate(renderer, gpu, &inputs, size, until)?.0
    } else if o.supersample > 1 {
        if job.error || o.picture.smoothing_asked().is_some() {
            return Err(Error::Usage(format!(
                "job `{}`: supersample {} cannot be combined with {}: give one",
                job.name,
                o.supersample,
                if job.error {
                    "\"error\": true (the error is measured per pixel of one sample)"
                } else {
                    "anti-aliasing"
                }
            )));
        }
        renderer
            .render_supersampled(gpu, &inputs, o.frame.width, o.frame.height, o.supersample)
            .map_err(|e| {
                super::render::supersampled_size_error(
                    e,
                    o.supersample,
                    (o.frame.width, o.frame.height),
                )
            })?
    } else {
        renderer.render_with(gpu, &inputs, o.frame.width, o.frame.height, readback)?
    };
    let count = frame.overflowed_pixels(settings.hdr_format);
    if count > 0 {
        return Err(Error::NonFiniteFrame {
            count,
            pixels: frame.hdr.len(),
        });
    }
    let mut result = JobResult::new(job);
    if job.error {
        let drawn = combustion::scene::Scene {
            camera,
            lights: lights.clone(),
            ..scene.as_drawn(pose.as_ref()).into_owned()
        };
        let error = report::frame_physics_error(
            &drawn,
            &frame,
            settings.gbuffer,
            // The exposure the frame's picture was made with (metered, or given).
            renderer.exposure_shown(&inputs),
            tone_mapping,
        );
        result.physics = Some(json!({
            "compared_pixels": error.compared,
            "wrong_surface_pixels": error.wrong_surface,
            "mean_relative": finite(error.relative.mean),
            "max_relative": finite(error.relative.max),
            "flip_mean": error.flip_mean.map(finite),
        }));
    }
    let kinds = [
        ("png", job.png, &job.criteria),
        ("exr", job.exr, &job.hdr_criteria),
    ];
    for (kind, wanted, criteria) in kinds {
        if !wanted {
            continue;
        }
        let file = folders.output.join(format!("{}.{kind}", job.name));
        match kind {
            "png" => output::write_png(&file, frame.width, frame.height, &frame.ldr)?,
            _ => output::write_exr(&file, frame.width, frame.height, &frame.hdr)?,
        }
        let outcome = check_output(&file, kind, job, criteria, folders);
        if outcome.failed.is_some() && result.status != Status::Failed {
            result.status = Status::Failed;
            result.message = outcome.failed.clone();
        } else if outcome.golden_written && result.status == Status::Rendered {
            result.status = Status::GoldensWritten;
        } else if outcome.compared && result.status == Status::Rendered {
            result.status = Status::Passed;
        }
        result.outputs.push(Value::Object(outcome.json));
    }
    Ok(result)
}

/// An output checked against its golden.
struct OutputOutcome {
    json: Map<String, Value>,
    compared: bool,
    golden_written: bool,
    failed: Option<String>,
}

fn finite(x: f64) -> Value {
    serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number)
}

fn check_output(
    file: &Path,
    kind: &str,
    job: &Job,
    criteria: &Criteria,
    folders: &Folders<'_>,
) -> OutputOutcome {
    let file_name = format!("{}.{kind}", job.name);
    let mut outcome = OutputOutcome {
        json: Map::from_iter([
            ("kind".to_owned(), Value::from(kind)),
            ("file".to_owned(), Value::from(file_name.as_str())),
        ]),
        compared: false,
        golden_written: false,
        failed: None,
    };
    let Some(goldens) = folders.goldens else {
        return outcome;
    };
    let golden = goldens.join(&file_name);
    outcome
        .json
        .insert("golden".into(), golden.display().to_string().into());
    if folders.update_goldens {
        let written = std::fs::read(file)
            .map_err(|e| e.to_string())
            .and_then(|bytes| {
                output::write_file_atomically(&golden, &bytes).map_err(|e| e.to_string())
            });
        match written {
            Ok(()) => outcome.golden_written = true,
            Err(e) => outcome.failed = Some(format!("{file_name}: golden not written: {e}")),
        }
        return outcome;
    }
    if !golden.is_file() {
        outcome.failed = Some(format!(
            "{file_name}: no golden {} (--update-goldens writes it)",
            golden.display()
        ));
        return outcome;
    }
    let compared = read_image(file)
        .and_then(|rendered| Ok((rendered, read_image(&golden)?)))
        .and_then(|(rendered, golden)| compare(&rendered, &golden));
    let comparison = match compared {
        Ok(comparison) => comparison,
        Err(e) => {
            outcome.failed = Some(format!("{file_name} against its golden: {e}"));
            return outcome;
        }
    };
    outcome.compared = true;
    outcome
        .json
        .insert("comparison".into(), figures(&comparison));
    if let Err(why) = criteria.check(&comparison) {
        outcome.failed = Some(format!("{file_name}: {why}"));
        outcome.json.insert("failed".into(), why.into());
        // The heat map shows where: NAME.flip.png, NAME.exr.flip.png.
        let map_name = match kind {
            "png" => format!("{}.flip.png", job.name),
            _ => format!("{}.exr.flip.png", job.name),
        };
        if let Ok((height, pixels)) = heat_map_with_legend(&comparison) {
            let map = folders.output.join(&map_name);
            if output::write_png(&map, comparison.width, height, &pixels).is_ok() {
                outcome.json.insert("heat_map".into(), map_name.into());
            }
        }
    }
    outcome
}

/// A comparison's figures, as `diff --json` gives them.
fn figures(c: &Comparison) -> Value {
    json!({
        "max_channel_diff": finite(c.max_channel_diff()),
        "channel_diff_unit": if c.radiance { "relative" } else { "8-bit steps" },
        "share_of_pixels_differing": finite(c.share_above(0.0)),
        "flip_mean": finite(c.mean_flip()),
        "flip_max": finite(c.flip_quantile(1.0)),
    })
}

/// The summary table: one row a job.
fn table(results: &[JobResult]) -> String {
    let width = results
        .iter()
        .map(|r| r.name.len())
        .max()
        .unwrap_or(3)
        .max(3);
    let mut text = format!(
        "{:<width$}  {:<15}  {:>10}  {:>10}  {:>10}  {:>8}\n",
        "job", "status", "max diff", "FLIP mean", "phys. err", "seconds"
    );
    for r in results {
        let comparison = r.outputs.iter().find_map(|o| o.get("comparison"));
        let max_diff = comparison.map_or("-".into(), |c| {
            let x = c["max_channel_diff"].as_f64().unwrap_or(f64::NAN);
            if c["channel_diff_unit"] == "relative" {
                format!("{x:.2e}")
            } else {
                format!("{x}/255")
            }
        });
        let flip = comparison.map_or("-".into(), |c| {
            format!("{:.4}", c["flip_mean"].as_f64().unwrap_or(f64::NAN))
        });
        let physics = r.physics.as_ref().map_or("-".into(), |p| {
            format!("{:.2e}", p["mean_relative"].as_f64().unwrap_or(f64::NAN))
        });
        text += &format!(
            "{:<width$}  {:<15}  {max_diff:>10}  {flip:>10}  {physics:>10}  {:>8.2}\n",
            r.name,
            r.status.name(),
            r.seconds
        );
        if let Some(message) = &r.message {
            text += &format!("{:<width$}    {message}\n", "");
        }
    }
    text
}

/// A job's figures in words, a line each: the scene, each output against its golden,
/// the physics error.
fn described(r: &JobResult) -> String {
    let number = |v: &Value| v.as_f64().map_or("-".into(), |x| format!("{x:.3e}"));
    let mut lines = vec![format!("{}: {}", r.scene, r.status.name())];
    for o in &r.outputs {
        let file = o["file"].as_str().unwrap_or_default();
        match o.get("comparison") {
            Some(c) => lines.push(format!(
                "{file}: largest channel difference {} ({}), {} of pixels differ, FLIP mean {} max {}",
                number(&c["max_channel_diff"]),
                c["channel_diff_unit"].as_str().unwrap_or_default(),
                number(&c["share_of_pixels_differing"]),
                number(&c["flip_mean"]),
                number(&c["flip_max"]),
            )),
            None => lines.push(format!("{file}: not compared")),
        }
    }
    if let Some(p) = &r.physics {
        lines.push(format!(
            "error against the f64 reference: mean relative {}, max {} over {} pixels; FLIP mean {}",
            number(&p["mean_relative"]),
            number(&p["max_relative"]),
            p["compared_pixels"],
            number(&p["flip_mean"]),
        ));
    }
    lines.join("\n")
}

/// `text` with every character XML 1.0 cannot hold replaced: control characters other
/// than tab, newline and carriage return by a space, the non-characters U+FFFE and
/// U+FFFF by U+FFFD (the escaping of `&`, `<`, `>` and quotes is quick-xml's).
fn xml_text(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            '\t' | '\n' | '\r' => c,
            c if c < ' ' => ' ',
            '\u{FFFE}' | '\u{FFFF}' => '\u{FFFD}',
            c => c,
        })
        .collect()
}

/// JUnit XML (the schema CI systems read: Jenkins, GitLab, GitHub reporters): one
/// test case a job; `failure` for a job beyond its criteria, `error` for one that did
/// not render; the figures as the case's standard output. Written by quick-xml.
fn junit(suite: &str, results: &[JobResult], seconds: f64) -> String {
    use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};
    let failures = results
        .iter()
        .filter(|r| r.status == Status::Failed)
        .count()
        .to_string();
    let errors = results
        .iter()
        .filter(|r| r.status == Status::Error)
        .count()
        .to_string();
    let (tests, time) = (results.len().to_string(), format!("{seconds:.3}"));
    let suite = xml_text(suite);
    let class = format!("combustion.batch.{suite}");
    let mut writer = quick_xml::Writer::new_with_indent(Vec::new(), b' ', 2);
    // Writing into memory cannot fail.
    let mut write = |event: Event<'_>| writer.write_event(event).expect("writing into memory");
    write(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)));
    write(Event::Start(BytesStart::new("testsuites").with_attributes(
        [
            ("name", "combustion batch"),
            ("tests", tests.as_str()),
            ("failures", failures.as_str()),
            ("errors", errors.as_str()),
            ("time", time.as_str()),
        ],
    )));
    write(Event::Start(BytesStart::new("testsuite").with_attributes(
        [
            ("name", suite.as_str()),
            ("tests", tests.as_str()),
            ("failures", failures.as_str()),
            ("errors", errors.as_str()),
            ("skipped", "0"),
            ("time", time.as_str()),
        ],
    )));
    for r in results {
        let (name, seconds) = (xml_text(&r.name), format!("{:.3}", r.seconds));
        write(Event::Start(BytesStart::new("testcase").with_attributes([
            ("name", name.as_str()),
            ("classname", class.as_str()),
            ("time", seconds.as_str()),
        ])));
        let message = xml_text(r.message.as_deref().unwrap_or_default());
        let problem = match r.status {
            Status::Failed => Some(("failure", "criteria")),
            Status::Error => Some(("error", "render")),
            _ => None,
        };
        if let Some((element, kind)) = problem {
            write(Event::Empty(BytesStart::new(element).with_attributes([
                ("message", message.as_str()),
                ("type", kind),
            ])));
        }
        write(Event::Start(BytesStart::new("system-out")));
        write(Event::Text(BytesText::new(&xml_text(&described(r)))));
        write(Event::End(BytesEnd::new("system-out")));
        write(Event::End(BytesEnd::new("testcase")));
    }
    write(Event::End(BytesEnd::new("testsuite")));
    write(Event::End(BytesEnd::new("testsuites")));
    let mut xml = String::from_utf8(writer.into_inner()).expect("UTF-8 in, UTF-8 out");
    xml.push('\n');
    xml
}

/// `--merge DIR…`: the shards' results.json combined into `folder`'s results.json and
/// junit.xml, jobs in the manifest's order; every shard of the split must be there,
/// once, from the same manifest.
fn merge(shards: &[PathBuf], folder: &Path) -> Result<(), CliError> {
    let mut texts = Vec::with_capacity(shards.len());
    for shard in shards {
        let file = shard.join(RESULTS_FILE);
        let text = combustion::input::read_text(
            &file,
            super::manifest::MAX_MANIFEST_BYTES * 4,
            "a shard's results",
        )
        .map_err(|e| {
            CliError::Failed(format!(
                "--merge {}: {e}",
                shortened(&file.display().to_string())
            ))
        })?;
        texts.push((shard.clone(), text));
    }
    let merged = MergedShards::of(&texts).map_err(CliError::Failed)?;
    prepare_folder(folder, "-o")?;
    finish(&merged.results_json(), &merged.jobs, &merged.suite, folder)
}

/// `I/N` as messages show numbers (a results file may hold any 64-bit count).
fn shard_label(index: u64, count: u64) -> String {
    format!("{}/{}", readable(index as f64), readable(count as f64))
}

/// The results of every shard of one batch run, combined (`batch --merge`).
pub struct MergedShards {
    /// The manifest's name (JUnit's suite name).
    suite: String,
    /// How many shards the jobs were split into.
    shard_count: u64,
    /// The longest shard's run time.
    seconds: f64,
    /// Every job's result, in the manifest's order.
    jobs: Vec<JobResult>,
}

impl MergedShards {
    /// Combines the shards' results: each a shard's folder and the text of its
    /// results.json. The error is one line naming the shard's file at fault, if one is:
    /// every shard of the split must be there, once, from the same manifest, and each job
    /// once.
    pub fn of(shards: &[(PathBuf, String)]) -> Result<MergedShards, String> {
        let mut manifest_name: Option<String> = None;
        let mut digest: Option<String> = None;
        let mut count: Option<u64> = None;
        let mut seen = Vec::new();
        let mut jobs: Vec<JobResult> = Vec::new();
        let mut seconds = 0.0f64;
        for (shard, text) in shards {
            let label = shortened(&shard.join(RESULTS_FILE).display().to_string());
            let bad = |why: &str| format!("--merge {label}: {why}");
            let run: Value =
                combustion::input::parse_json(text).map_err(|e| bad(&format!("not JSON: {e}")))?;
            let field = |key: &str| run.get(key).unwrap_or(&Value::Null);
            let name = field("manifest")
                .as_str()
                .ok_or_else(|| bad("no `manifest`"))?;
            if *manifest_name.get_or_insert_with(|| name.to_owned()) != name {
                return Err(bad(&format!(
                    "the results of manifest `{}`, not `{}`",
                    shortened(name),
                    shortened(&manifest_name.unwrap_or_default())
                )));
            }
            // Two manifests of one file name are told apart by their text.
            let ran = field("manifest_digest").as_str().ok_or_else(|| {
                bad("no `manifest_digest` (results of an older combustion: run the shard again)")
            })?;
            if *digest.get_or_insert_with(|| ran.to_owned()) != ran {
                return Err(bad(&format!(
                    "the results of another manifest named `{}` (its text differs from the first shard's)",
                    shortened(name)
                )));
            }
            let shard_number = |key: &str| field("shard").get(key).and_then(Value::as_u64);
            let shard_of = (shard_number("index"), shard_number("count"));
            let (Some(index), Some(n)) = shard_of else {
                return Err(bad("not a shard's results (run with --shard I/N)"));
            };
            if n == 0 || index == 0 || index > n {
                return Err(bad(&format!(
                    "shard {} is no shard (I is 1 to N, N at least 1)",
                    shard_label(index, n)
                )));
            }
            if *count.get_or_insert(n) != n {
                return Err(bad(&format!(
                    "shard {} of another split than {}",
                    shard_label(index, n),
                    readable(count.unwrap_or(0) as f64)
                )));
            }
            if seen.contains(&index) {
                return Err(bad(&format!(
                    "shard {} is given twice",
                    shard_label(index, n)
                )));
            }
            seen.push(index);
            seconds = seconds.max(field("seconds").as_f64().unwrap_or(0.0));
            for job in field("jobs")
                .as_array()
                .ok_or_else(|| bad("no `jobs` list"))?
            {
                let mut job =
                    JobResult::from_json(job).ok_or_else(|| bad("a job's result is malformed"))?;
                // Its name names files: the manifest's rule, as when it ran.
                super::manifest::check_name(&job.name)
                    .map_err(|why| bad(&format!("a job's result: {why}")))?;
                // Files are named from the merged folder's point of view: the shard's folder.
                for fields in job.outputs.iter_mut().filter_map(Value::as_object_mut) {
                    if let Some(file) = fields.get("file").and_then(Value::as_str) {
                        let joined = shard.join(file).display().to_string();
                        fields.insert("file".into(), joined.into());
                    }
                }
                jobs.push(job);
            }
        }
        let n = count.unwrap_or(0);
        if let Some(missing) = (1..=n).find(|i| !seen.contains(i)) {
            return Err(format!(
                "--merge: shard {} is missing (give every shard's folder)",
                shard_label(missing, n)
            ));
        }
        jobs.sort_by_key(|r| r.index);
        let twice = jobs.windows(2).find_map(|pair| match pair {
            [a, b] if a.index == b.index => Some(a),
            _ => None,
        });
        if let Some(job) = twice {
            return Err(format!(
                "--merge: job {} (`{}`) is in two shards' results",
                readable(job.index as f64),
                shortened(&job.name)
            ));
        }
        Ok(MergedShards {
            suite: manifest_name.unwrap_or_default(),
            shard_count: n,
            seconds,
            jobs,
        })
    }

    /// Each job's position in the manifest and name, in the manifest's order.
    pub fn jobs(&self) -> impl Iterator<Item = (usize, &str)> {
        self.jobs.iter().map(|j| (j.index, j.name.as_str()))
    }

    /// The merged results.json's content.
    pub fn results_json(&self) -> Value {
        json!({
            "manifest": self.suite,
            "shard": Value::Null,
            "merged_shards": self.shard_count,
            "seconds": self.seconds,
            "jobs": self.jobs.iter().map(JobResult::json).collect::<Vec<_>>(),
        })
    }

    /// The merged junit.xml's text.
    pub fn junit(&self) -> String {
        junit(&self.suite, &self.jobs, self.seconds)
    }
}

#[cfg(test)]
#[allow(clippy::indexing_slicing)] // a test fails by a panic
mod tests {
    use super::*;

    #[test]
    fn junit_escapes_and_counts() {
        let result = |name: &str, status, message: Option<&str>| JobResult {
            index: 0,
            name: name.into(),
            scene: "builtin:spheres".into(),
            status,
            message: message.map(str::to_owned),
            seconds: 0.5,
            outputs: Vec::new(),
            physics: None,
        };
        let xml = junit(
            "m<&>",
            &[
                result("a", Status::Passed, None),
                result(
                    "b",
                    Status::Failed,
                    Some("mean-flip <= 0.01: \"0.02\" & more"),
                ),
                result("c", Status::Error, Some("no such file\u{1}")),
            ],
            1.5,
        );
        assert!(
            xml.contains("tests=\"3\" failures=\"1\" errors=\"1\""),
            "{xml}"
        );
        assert!(xml.contains("name=\"m&lt;&amp;&gt;\""), "{xml}");
        assert!(
            xml.contains("<failure message=\"mean-flip &lt;= 0.01: &quot;0.02&quot; &amp; more\""),
            "{xml}"
        );
        assert!(xml.contains("<error message=\"no such file \""), "{xml}");
        assert_eq!(xml.matches("<testcase ").count(), 3);
        // Characters XML 1.0 cannot hold (a job named from a file name, a message
        // quoting one): the non-characters U+FFFE and U+FFFF become U+FFFD, and the
        // document reads back whole.
        let odd = junit(
            "s\u{FFFF}",
            &[result(
                "x\u{FFFE}y",
                Status::Error,
                Some("bad \u{FFFF}\u{1b} byte"),
            )],
            0.1,
        );
        assert!(
            !odd.contains('\u{FFFE}') && !odd.contains('\u{FFFF}'),
            "{odd}"
        );
        assert!(odd.contains("name=\"x\u{FFFD}y\""), "{odd}");
        assert!(odd.contains("message=\"bad \u{FFFD}  byte\""), "{odd}");
        let mut reader = quick_xml::Reader::from_str(&odd);
        let mut elements = 0;
        loop {
            match reader.read_event() {
                Ok(quick_xml::events::Event::Eof) => break,
                Ok(quick_xml::events::Event::Start(_) | quick_xml::events::Event::Empty(_)) => {
                    elements += 1
                }
                Ok(_) => {}
                Err(e) => panic!("{e}: {odd}"),
            }
        }
        assert_eq!(elements, 5, "{odd}");
    }

    #[test]
    fn a_result_reads_back_as_written() {
        let result = JobResult {
            index: 7,
            name: "a".into(),
            scene: "x.glb".into(),
            status: Status::GoldensWritten,
            message: Some("m".into()),
            seconds: 1.25,
            outputs: vec![json!({"kind": "png", "file": "a.png"})],
            physics: Some(json!({"mean_relative": 1e-4})),
        };
        let back = JobResult::from_json(&result.json()).unwrap();
        assert_eq!(back.json(), result.json());
    }
}
