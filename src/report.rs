//! `combustion bench --report DIR`: speed against error. For each scene and each
//! *variant set* (Fresnel model, HDR storage, lighting pipeline, masking term: the
//! default, each term changed alone, and all the cheap choices together), the GPU time of every
//! pass over N frames after a warm-up (median, p10, p90; timestamps), and the error of
//! one frame against the f64 reference (`combustion_renderer::reference`: every pixel
//! re-shaded from its own G-buffer with the full Fresnel equations; max, mean and RMS
//! relative error); and per scene, in the same run, the measurement floors
//! (`MeasurementFloor`) every pass is stated as a multiple of. Written as `report.md`,
//! `report.csv`, `floors.csv` and `speed-vs-error.png` (one point per variant set — time
//! and error averaged over the scenes — with the Pareto front).

use std::fmt::Write as _;
use std::path::Path;

use combustion_plots::{pareto_front, plot_speed_vs_error, SpeedErrorPoint};
use combustion_renderer::reference::{error_map, ReferenceShading};
use combustion_renderer::{
    FrameInputs, FresnelModel, GpuScene, HdrFormat, Masking, MeasurementFloor, PassTimings,
    Readback, Renderer, RendererSettings,
};
use combustion_vk::DeviceDesc;

use crate::{check_validation, output, Error, Headless, HeadlessDesc, SceneSource};

/// One combination of the renderer's measured options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VariantSet {
    pub fresnel: FresnelModel,
    pub hdr: HdrFormat,
    /// Lighting pipeline specialised to the scene (else the general one).
    pub specialised: bool,
    pub masking: Masking,
}

impl VariantSet {
    /// The renderer's defaults: the exact model, f32 HDR, specialised pipeline.
    pub const DEFAULT: VariantSet = VariantSet {
        fresnel: FresnelModel::Full,
        hdr: HdrFormat::Rgba32Float,
        specialised: true,
        masking: Masking::HeightCorrelated,
    };

    /// Every set the report measures: the default; each term changed alone (the general
    /// pipeline, Schlick's Fresnel, f16 HDR, the separable and the approximate masking
    /// term); and every cheap choice at once.
    pub fn all() -> Vec<VariantSet> {
        let d = Self::DEFAULT;
        vec![
            d,
            VariantSet {
                specialised: false,
                ..d
            },
            VariantSet {
                fresnel: FresnelModel::Schlick,
                ..d
            },
            VariantSet {
                hdr: HdrFormat::Rgba16Float,
                ..d
            },
            VariantSet {
                masking: Masking::Separable,
                ..d
            },
            VariantSet {
                masking: Masking::Approximate,
                ..d
            },
            VariantSet {
                fresnel: FresnelModel::Schlick,
                hdr: HdrFormat::Rgba16Float,
                masking: Masking::Approximate,
                ..d
            },
        ]
    }

    /// A short name, e.g. `full/f32/specialised/correlated`.
    pub fn name(&self) -> String {
        format!(
            "{}/{}/{}/{}",
            match self.fresnel {
                FresnelModel::Full => "full",
                FresnelModel::Schlick => "schlick",
            },
            match self.hdr {
                HdrFormat::Rgba32Float => "f32",
                HdrFormat::Rgba16Float => "f16",
            },
            if self.specialised {
                "specialised"
            } else {
                "general"
            },
            self.masking.name()
        )
    }
}

/// Median and spread of one pass's GPU time, ms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spread {
    pub median: f64,
    pub p10: f64,
    pub p90: f64,
}

impl Spread {
    fn of(mut values: Vec<f64>) -> Spread {
        if values.is_empty() {
            return Spread::default();
        }
        values.sort_by(f64::total_cmp);
        let at = |p: f64| values[((values.len() - 1) as f64 * p).round() as usize];
        Spread {
            median: at(0.5),
            p10: at(0.1),
            p90: at(0.9),
        }
    }
}

/// One scene under one variant set.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportRow {
    pub scene: String,
    pub set: VariantSet,
    pub gbuffer: Spread,
    pub lighting: Spread,
    pub output: Spread,
    pub total: Spread,
    /// Frames timed.
    pub frames: usize,
    pub max_relative: f64,
    pub mean_relative: f64,
    pub rms_relative: f64,
    /// Pixels compared with the reference.
    pub compared: usize,
}

/// A scene's measurement floors (f32 HDR, full Fresnel, specialised pipeline), ms.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorRow {
    pub scene: String,
    /// G-buffer pass with a trivial fragment stage.
    pub geometry: Spread,
    /// Lighting pass that only fetches the G-buffer and writes.
    pub fetch: Spread,
    /// Lighting pass with a plain GGX + Smith + full conductor Fresnel per light.
    pub plain_ggx: Spread,
}

/// Everything measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurements {
    pub rows: Vec<ReportRow>,
    pub floors: Vec<FloorRow>,
    pub device: String,
}

/// GPU timings of `frames` frames of `scene` (after the frames already taken).
fn time_frames(
    renderer: &mut Renderer,
    scene: &GpuScene,
    width: u32,
    height: u32,
    frames: u32,
) -> Result<Vec<PassTimings>, Error> {
    renderer.take_completed_timings();
    for _ in 0..frames {
        renderer.submit_offscreen(scene, width, height)?;
    }
    renderer.finish_offscreen()?;
    Ok(renderer.take_completed_timings())
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct ReportDesc {
    pub scenes: Vec<SceneSource>,
    pub sets: Vec<VariantSet>,
    pub width: u32,
    pub height: u32,
    /// Frames timed per scene and set (after one warm-up frame).
    pub frames: u32,
    pub device: DeviceDesc,
    /// Measure each scene's floors too.
    pub floors: bool,
}

/// Measures every scene under every variant set, and each scene's floors (with the
/// f32 renderer); `progress(done, total, what)` is called before each measurement.
pub fn measure(
    desc: &ReportDesc,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<Measurements, Error> {
    let mut device_name = String::new();
    let mut floors = Vec::new();
    let scenes = desc
        .scenes
        .iter()
        .map(|source| Ok((source.label(), source.load()?)))
        .collect::<Result<Vec<_>, Error>>()?;
    let total = scenes.len() * (desc.sets.len() + usize::from(desc.floors));
    let mut rows = Vec::with_capacity(total);
    // One renderer per HDR format (a renderer's HDR storage is fixed at creation).
    for hdr in [HdrFormat::Rgba32Float, HdrFormat::Rgba16Float] {
        let sets: Vec<VariantSet> = desc.sets.iter().copied().filter(|s| s.hdr == hdr).collect();
        if sets.is_empty() {
            continue;
        }
        let mut headless = Headless::new(&HeadlessDesc {
            device: desc.device.clone(),
            settings: RendererSettings {
                hdr_format: hdr,
                ..RendererSettings::default()
            },
        })?;
        let renderer = headless.renderer();
        device_name.clone_from(&renderer.device().info().name);
        for (label, scene) in &scenes {
            let gpu = renderer.upload(scene)?;
            if desc.floors && hdr == HdrFormat::Rgba32Float {
                progress(rows.len() + floors.len(), total, &format!("{label} floors"));
                renderer.set_fresnel(FresnelModel::Full);
                renderer.set_specialised(true);
                renderer.set_masking(Masking::HeightCorrelated);
                let mut spreads = Vec::new();
                for floor in [
                    MeasurementFloor::Geometry,
                    MeasurementFloor::LightingFetch,
                    MeasurementFloor::LightingPlainGgx,
                ] {
                    renderer.set_measurement_floor(Some(floor));
                    renderer.prepare(&gpu)?;
                    renderer.render(&gpu, desc.width, desc.height, Readback::default())?;
                    let timings =
                        time_frames(renderer, &gpu, desc.width, desc.height, desc.frames)?;
                    spreads.push(Spread::of(
                        timings
                            .iter()
                            .map(|t| match floor {
                                MeasurementFloor::Geometry => t.gbuffer_ms,
                                _ => t.lighting_ms,
                            })
                            .collect(),
                    ));
                }
                renderer.set_measurement_floor(None);
                floors.push(FloorRow {
                    scene: label.clone(),
                    geometry: spreads[0],
                    fetch: spreads[1],
                    plain_ggx: spreads[2],
                });
            }
            for set in &sets {
                progress(
                    rows.len() + floors.len(),
                    total,
                    &format!("{label} {}", set.name()),
                );
                renderer.set_fresnel(set.fresnel);
                renderer.set_specialised(set.specialised);
                renderer.set_masking(set.masking);
                renderer.prepare(&gpu)?;
                // The error of one frame (read back), which is also the warm-up.
                let inputs = FrameInputs::of_scene(&gpu, 1.0);
                let frame = renderer.render_with(
                    &gpu,
                    &inputs,
                    desc.width,
                    desc.height,
                    Readback {
                        images: true,
                        gbuffer: true,
                    },
                )?;
                let reference = ReferenceShading::new(&gpu.scene, &inputs, desc.width, desc.height);
                let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
                let map = error_map(&frame, &reference, threads);
                let timings = time_frames(renderer, &gpu, desc.width, desc.height, desc.frames)?;
                if timings.is_empty() {
                    return Err(Error::Usage(
                        "this device gives no GPU timestamps; the report needs them".into(),
                    ));
                }
                let pick = |f: fn(&combustion_renderer::PassTimings) -> f64| {
                    Spread::of(timings.iter().map(f).collect())
                };
                rows.push(ReportRow {
                    scene: label.clone(),
                    set: *set,
                    gbuffer: pick(|t| t.gbuffer_ms),
                    lighting: pick(|t| t.lighting_ms),
                    output: pick(|t| t.tonemap_ms),
                    total: pick(|t| t.total_ms),
                    frames: timings.len(),
                    max_relative: map.max_relative,
                    mean_relative: map.mean_relative,
                    rms_relative: map.rms_relative,
                    compared: map.lit_pixels,
                });
            }
            renderer.retire(gpu);
        }
        let validation = headless.validation_log();
        drop(headless);
        check_validation(&validation)?;
    }
    progress(total, total, "done");
    Ok(Measurements {
        rows,
        floors,
        device: device_name,
    })
}

/// What an accuracy budget chose for a scene ([`choose`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// The fastest set whose mean relative error is within the budget (`None`: none is).
    pub chosen: Option<VariantSet>,
    /// Every set measured, fastest first.
    pub candidates: Vec<ReportRow>,
}

/// The accuracy budget: measures every variant set on `scene` (without floors) and
/// picks the fastest whose mean relative error against the f64 reference is at most
/// `max_error`.
pub fn choose(
    scene: &SceneSource,
    max_error: f64,
    width: u32,
    height: u32,
    frames: u32,
    device: DeviceDesc,
) -> Result<Choice, Error> {
    let desc = ReportDesc {
        scenes: vec![scene.clone()],
        sets: VariantSet::all(),
        width,
        height,
        frames,
        device,
        floors: false,
    };
    let mut candidates = measure(&desc, |_, _, _| {})?.rows;
    candidates.sort_by(|a, b| a.total.median.total_cmp(&b.total.median));
    let chosen = candidates
        .iter()
        .find(|r| r.mean_relative <= max_error)
        .map(|r| r.set);
    Ok(Choice { chosen, candidates })
}

impl Choice {
    /// What was chosen and why: every candidate with its time and errors.
    pub fn explain(&self, max_error: f64) -> String {
        let mut out = format!(
            "accuracy budget: mean relative error ≤ {max_error:.1e} against the f64 reference\n"
        );
        for r in &self.candidates {
            let verdict = if Some(r.set) == self.chosen {
                "chosen: the fastest within the budget"
            } else if r.mean_relative <= max_error {
                "within, slower"
            } else {
                "over the budget"
            };
            let _ = writeln!(
                out,
                "  {:<38} {:>8.2} ms  mean {:.2e}  max {:.2e}  {verdict}",
                r.set.name(),
                r.total.median,
                r.mean_relative,
                r.max_relative
            );
        }
        if self.chosen.is_none() {
            out += "  no variant set is within the budget\n";
        }
        out
    }
}

/// Per variant set: its name, the mean over scenes of the total frame time's median and
/// of the mean relative error, and the largest max relative error.
pub fn summarise(rows: &[ReportRow]) -> Vec<(VariantSet, f64, f64, f64)> {
    let mut sets: Vec<VariantSet> = Vec::new();
    for row in rows {
        if !sets.contains(&row.set) {
            sets.push(row.set);
        }
    }
    sets.into_iter()
        .map(|set| {
            let of: Vec<&ReportRow> = rows.iter().filter(|r| r.set == set).collect();
            let n = of.len() as f64;
            let ms = of.iter().map(|r| r.total.median).sum::<f64>() / n;
            let mean = of.iter().map(|r| r.mean_relative).sum::<f64>() / n;
            let max = of.iter().map(|r| r.max_relative).fold(0.0, f64::max);
            (set, ms, mean, max)
        })
        .collect()
}

/// One plot point per variant set: its mean frame time and mean relative error.
fn points(rows: &[ReportRow]) -> Vec<SpeedErrorPoint> {
    summarise(rows)
        .iter()
        .map(|(set, ms, mean, _)| SpeedErrorPoint {
            label: set.name(),
            ms: *ms,
            error: *mean,
        })
        .collect()
}

/// The CSV: one row per scene and variant set.
pub fn csv(rows: &[ReportRow]) -> String {
    let mut out = String::from(
        "scene,fresnel,hdr,pipeline,masking,frames,gbuffer_ms,gbuffer_p10,gbuffer_p90,lighting_ms,lighting_p10,lighting_p90,output_ms,output_p10,output_p90,total_ms,total_p10,total_p90,max_relative_error,mean_relative_error,rms_relative_error,pixels_compared\n",
    );
    for r in rows {
        let name = r.set.name();
        let parts: Vec<&str> = name.split('/').collect();
        let _ = write!(
            out,
            "{},{},{},{},{},{}",
            csv_field(&r.scene),
            parts[0],
            parts[1],
            parts[2],
            parts[3],
            r.frames
        );
        for s in [r.gbuffer, r.lighting, r.output, r.total] {
            let _ = write!(out, ",{:.3},{:.3},{:.3}", s.median, s.p10, s.p90);
        }
        let _ = writeln!(
            out,
            ",{:.3e},{:.3e},{:.3e},{}",
            r.max_relative, r.mean_relative, r.rms_relative, r.compared
        );
    }
    out
}

/// `text` for a Markdown table cell.
fn md_cell(text: &str) -> String {
    text.replace('|', "\\|")
}

fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

/// The floors' CSV: one row per scene.
pub fn floors_csv(floors: &[FloorRow]) -> String {
    let mut out = String::from(
        "scene,geometry_floor_ms,geometry_floor_p10,geometry_floor_p90,fetch_floor_ms,fetch_floor_p10,fetch_floor_p90,plain_ggx_ms,plain_ggx_p10,plain_ggx_p90\n",
    );
    for f in floors {
        let _ = write!(out, "{}", csv_field(&f.scene));
        for s in [f.geometry, f.fetch, f.plain_ggx] {
            let _ = write!(out, ",{:.3},{:.3},{:.3}", s.median, s.p10, s.p90);
        }
        out.push('\n');
    }
    out
}

/// The floors and each pass of the default set ([`VariantSet::DEFAULT`]) as a multiple of
/// them, per scene.
fn floors_markdown(m: &Measurements) -> String {
    let mut out = String::from(
        "## Against the floors (same run)\n\nFloors: the G-buffer pass with a trivial fragment stage (geometry), the lighting pass that only fetches the G-buffer and writes (fetch), and a lighting pass with a plain isotropic GGX, height-correlated Smith and the full conductor Fresnel per light (plain GGX); the same scene, lights, size and frames. Passes of the default set, full/f32/specialised/correlated.\n\n| scene | geometry floor ms | G-buffer ms (× floor) | fetch floor ms | plain GGX ms | lighting ms (× fetch, × plain GGX) |\n|---|---|---|---|---|---|\n",
    );
    let default = VariantSet::DEFAULT;
    for f in &m.floors {
        let Some(r) = m
            .rows
            .iter()
            .find(|r| r.scene == f.scene && r.set == default)
        else {
            continue;
        };
        let _ = writeln!(
            out,
            "| {} | {:.2} | {:.2} (×{:.2}) | {:.2} | {:.2} | {:.2} (×{:.1}, ×{:.2}) |",
            md_cell(&f.scene),
            f.geometry.median,
            r.gbuffer.median,
            r.gbuffer.median / f.geometry.median,
            f.fetch.median,
            f.plain_ggx.median,
            r.lighting.median,
            r.lighting.median / f.fetch.median,
            r.lighting.median / f.plain_ggx.median
        );
    }
    out + "\n"
}

/// The Markdown report.
pub fn markdown(m: &Measurements, desc: &ReportDesc) -> String {
    let (rows, device) = (&m.rows[..], &m.device);
    let mut out = format!(
        "# Speed against error\n\n{device}, {}×{}, GPU timestamps over {} frames after one warm-up frame per scene and variant set. Error: every lit pixel of one frame re-shaded in f64 from its own G-buffer with the full Fresnel equations (`combustion_renderer::reference`); relative error per pixel = largest channel |gpu − f64| / max(|f64|, 1e-4).\n\nVariant sets (fresnel/hdr/pipeline/masking): Fresnel `full` (the equations with complex η + ik and the outside medium) or `schlick` (Schlick's curve through the exact normal-incidence reflectance); HDR storage `f32` or `f16`; lighting pipeline `specialised` to the scene's materials or `general`; masking–shadowing `correlated` (Smith height-correlated, the reference's), `separable` (G₁·G₁) or `approximate` (Hammon 2017). The default, each term changed alone, and every cheap choice at once.\n\n",
        desc.width, desc.height, desc.frames
    );
    let summary = summarise(rows);
    let front = pareto_front(&points(rows));
    let _ = write!(
        out,
        "Pareto front, fastest first: each set less wrong, by more than {:.0} % of the error, than the front's previous set (errors closer than that differ by rounding).\n\n",
        combustion_plots::PARETO_ERROR_TOLERANCE * 100.0
    );
    out += "## Variant sets (mean over the scenes)\n\n| variant set | frame ms | mean relative error | largest max relative error | Pareto front |\n|---|---|---|---|---|\n";
    for (i, (set, ms, mean, max)) in summary.iter().enumerate() {
        let _ = writeln!(
            out,
            "| {} | {ms:.2} | {mean:.2e} | {max:.2e} | {} |",
            set.name(),
            if front.contains(&i) { "yes" } else { "" }
        );
    }
    out += "\n![speed against error](speed-vs-error.png)\n\n";
    out += &floors_markdown(m);
    out += "## Per scene\n\n| scene | variant set | G-buffer ms | lighting ms (p10–p90) | output ms | total ms | max rel. error | mean | RMS | pixels |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let _ = writeln!(
            out,
            "| {} | {} | {:.2} | {:.2} ({:.2}–{:.2}) | {:.2} | {:.2} | {:.2e} | {:.2e} | {:.2e} | {} |",
            md_cell(&r.scene),
            r.set.name(),
            r.gbuffer.median,
            r.lighting.median,
            r.lighting.p10,
            r.lighting.p90,
            r.output.median,
            r.total.median,
            r.max_relative,
            r.mean_relative,
            r.rms_relative,
            r.compared
        );
    }
    out
}

/// Writes `report.md`, `report.csv`, `floors.csv` and `speed-vs-error.png` into `dir`
/// (made if needed).
pub fn write(dir: &Path, m: &Measurements, desc: &ReportDesc) -> Result<(), Error> {
    let (rows, device) = (&m.rows[..], &m.device);
    std::fs::create_dir_all(dir).map_err(|e| {
        Error::Output(output::OutputError::Io {
            path: dir.to_path_buf(),
            source: e,
        })
    })?;
    let png = plot_speed_vs_error(
        "Speed against error",
        &format!(
            "{device}, {}×{}; each point a variant set, mean over {} scene(s); red: Pareto front",
            desc.width,
            desc.height,
            desc.scenes.len()
        ),
        "frame time, GPU ms (median)",
        &points(rows),
        1000,
        620,
    )?;
    output::write_file_atomically(&dir.join("speed-vs-error.png"), &png.bytes)?;
    output::write_file_atomically(&dir.join("report.csv"), csv(rows).as_bytes())?;
    output::write_file_atomically(&dir.join("floors.csv"), floors_csv(&m.floors).as_bytes())?;
    output::write_file_atomically(&dir.join("report.md"), markdown(m, desc).as_bytes())?;
    Ok(())
}
