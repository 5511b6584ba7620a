//! The report's light-transport section: on each scene, on a device with ray queries, the
//! real-time frame against light that bounces — the frame path traced (`--path-trace on`,
//! [`ReportDesc::path_traced_frames`] frames of successive seeds averaged: the converged
//! image, its own noise stated) — for the default shading and each traced setting the
//! scene can use (ray-traced shadows where it has lights, ray-traced occlusion and
//! reflections where an environment lights it, ray-traced refraction where it has
//! glass): over the pixels the default frame shows a surface at, the
//! mean and 95th percentile of each pixel's relative error, the RMS relative error with
//! the reference's own noise removed in quadrature (E[(a − r̂)²] = (a − r)² + σ²: an
//! unbiased estimate of the squared error against the converged image), and the frame's
//! mean radiance against the path-traced one, at their GPU cost as a ratio to the default
//! frame. One path-traced frame of another seed beside them says what a frame of the
//! tracer costs and how far one frame is. Written as `light-transport.csv` and a section
//! of `report.md`.

use std::fmt::Write as _;

use combustion_renderer::reference::RADIANCE_FLOOR;
use combustion_renderer::{
    optional_pass, FrameInputs, OptionalPasses, Readback, Renderer, RendererSettings,
    ShadingOptions,
};

use super::environment_sampling::mean_of_seeds;
use super::{md_cell, time_frames_with, ReportDesc, Spread};
use crate::frame_mean::FrameMean;
use crate::{check_validation, Error};

/// One scene and real-time setting against the path-traced frame.
#[derive(Clone, Debug, PartialEq)]
pub struct LightTransportRow {
    /// The scene's label.
    pub scene: String,
    /// `default`, `ray-traced shadows`, `ray-traced occlusion`, `ray-traced reflections`,
    /// `ray-traced refraction`, or `path traced (1 frame)`.
    pub setting: &'static str,
    /// Whole frame's GPU time.
    pub total: Spread,
    /// Lit pixels compared (where the default frame shows a surface).
    pub compared: usize,
    /// Mean relative error against the path-traced frame.
    pub mean_relative: f64,
    /// Its 95th percentile.
    pub p95_relative: f64,
    /// The RMS relative error with the path-traced frame's noise removed in quadrature.
    pub rms_relative: f64,
    /// The frame's mean radiance over the compared pixels relative to the path-traced
    /// frame's, less 1 (negative: darker than light that bounces).
    pub mean_radiance: f64,
    /// The path-traced frame's own mean relative standard error over the same pixels.
    pub reference_noise: f64,
}

/// A setting: its name, its optional pass, whether the scene can use it, and the seeds
/// its frame averages.
struct Setting {
    name: &'static str,
    pass: Option<&'static str>,
    applies: fn(&combustion_scene::Scene) -> bool,
    seeds: u32,
}

const SETTINGS: [Setting; 6] = [
    Setting {
        name: "default",
        pass: None,
        applies: |_| true,
        seeds: 1,
    },
    Setting {
        name: "ray-traced shadows",
        pass: Some("ray-traced-shadows"),
        applies: |scene| !scene.lights.is_empty(),
        seeds: 1,
    },
    Setting {
        name: "ray-traced occlusion",
        pass: Some("ray-traced-occlusion"),
        applies: |scene| scene.environment.is_some(),
        seeds: super::occlusion::TRACED_SEEDS,
    },
    Setting {
        name: "ray-traced reflections",
        pass: Some("ray-traced-reflections"),
        applies: |scene| scene.environment.is_some(),
        seeds: 1,
    },
    Setting {
        name: "ray-traced refraction",
        pass: Some("ray-traced-refraction"),
        applies: |scene| scene.materials.iter().any(|m| m.transmission > 0.0),
        seeds: 1,
    },
    Setting {
        name: "path traced (1 frame)",
        pass: Some("path-trace"),
        applies: |_| true,
        seeds: 1,
    },
];

/// Steps of the measurement on `scenes` (one per scene and setting that applies).
pub(super) fn steps(scenes: &[(String, combustion_scene::Scene)]) -> usize {
    scenes
        .iter()
        .map(|(_, scene)| 1 + SETTINGS.iter().filter(|s| (s.applies)(scene)).count())
        .sum()
}

/// `renderer`'s shading with the optional pass `pass` (or none).
fn shading_with(pass: Option<&str>) -> ShadingOptions {
    ShadingOptions {
        optional_passes: pass
            .and_then(optional_pass)
            .map_or(OptionalPasses::NONE, |p| OptionalPasses::NONE.with(p, true)),
        ..ShadingOptions::DEFAULT
    }
}

/// The converged image: `frames` path-traced frames (seeds 0 to `frames` − 1) averaged.
fn path_traced(
    renderer: &mut Renderer,
    gpu: &combustion_renderer::GpuScene,
    inputs: &FrameInputs<'_>,
    (width, height): (u32, u32),
    frames: u32,
) -> Result<FrameMean, Error> {
    let mut averaged = FrameMean::new((width * height) as usize);
    let images = Readback::IMAGES;
    for seed in 0..frames {
        let seeded = FrameInputs {
            environment_seed: seed,
            ..*inputs
        };
        averaged.add(
            &renderer
                .render_with(gpu, &seeded, width, height, images)?
                .hdr,
        );
    }
    Ok(averaged)
}

/// A row's error figures (its [`LightTransportRow`] fields).
struct Errors {
    compared: usize,
    mean_relative: f64,
    p95_relative: f64,
    rms_relative: f64,
    mean_radiance: f64,
    reference_noise: f64,
}

/// The error figures of `frame` (RGBA per pixel) against `reference` over the pixels
/// `lit`.
fn errors(frame: &[[f32; 4]], reference: &FrameMean, lit: &[bool]) -> Errors {
    let mut relative = Vec::new();
    let (mut squares, mut noise_squares, mut noise) = (0.0, 0.0, 0.0);
    let (mut sum, mut reference_sum) = (0.0, 0.0);
    for (((p, r), s), _) in frame
        .iter()
        .zip(reference.mean())
        .zip(&reference.standard_errors())
        .zip(lit)
        .filter(|(_, &lit)| lit)
    {
        let mut largest: f64 = 0.0;
        let mut noisiest: f64 = 0.0;
        for c in 0..3 {
            let scale = r[c].abs().max(RADIANCE_FLOOR);
            let e = (f64::from(p[c]) - r[c]) / scale;
            largest = largest.max(e.abs());
            noisiest = noisiest.max(s[c] / scale);
            squares += e * e / 3.0;
            noise_squares += (s[c] / scale).powi(2) / 3.0;
            sum += f64::from(p[c]);
            reference_sum += r[c];
        }
        relative.push(largest);
        noise += noisiest;
    }
    let n = relative.len();
    relative.sort_by(f64::total_cmp);
    let count = n.max(1) as f64;
    Errors {
        compared: n,
        mean_relative: relative.iter().sum::<f64>() / count,
        p95_relative: relative
            .get((n * 95 / 100).min(n.saturating_sub(1)))
            .copied()
            .unwrap_or(f64::NAN),
        rms_relative: ((squares - noise_squares).max(0.0) / count).sqrt(),
        mean_radiance: sum / reference_sum - 1.0,
        reference_noise: noise / count,
    }
}

/// Measures every setting that applies on each scene of `scenes` (none on a device
/// without ray queries).
pub(super) fn measure(
    scenes: &[(String, combustion_scene::Scene)],
    desc: &ReportDesc,
    mut progress: impl FnMut(&str),
) -> Result<Vec<LightTransportRow>, Error> {
    let mut rows = Vec::new();
    let mut headless = desc.headless(RendererSettings::default())?;
    let renderer = headless.renderer();
    if !renderer.device().ray_queries() {
        log::warn!(
            "the light-transport section needs ray queries (lavapipe from Mesa 24.1): left out"
        );
        return Ok(rows);
    }
    let size = (desc.width, desc.height);
    for (label, scene) in scenes {
        let gpu = renderer.upload(scene)?;
        let inputs = FrameInputs::of_scene(&gpu, 1.0);
        progress(&format!("{label} path traced"));
        renderer.set_shading(shading_with(Some("path-trace")), &[&gpu])?;
        let frames = desc.path_traced_frames;
        let reference = path_traced(renderer, &gpu, &inputs, size, frames)?;
        let mut lit: Vec<bool> = Vec::new();
        for setting in SETTINGS.iter().filter(|s| (s.applies)(scene)) {
            progress(&format!(
                "{label} against light transport: {}",
                setting.name
            ));
            renderer.set_shading(shading_with(setting.pass), &[&gpu])?;
            let frame = if setting.pass == Some("path-trace") {
                // One frame of a seed the mean did not average.
                let seeded = FrameInputs {
                    environment_seed: frames,
                    ..inputs
                };
                let images = Readback::IMAGES;
                renderer.render_with(&gpu, &seeded, size.0, size.1, images)?
            } else {
                mean_of_seeds(renderer, &gpu, &inputs, size, setting.seeds)?
            };
            if lit.is_empty() {
                // The default frame's surfaces (alpha 0: the background, the lighting
                // pass's mark).
                lit = frame.hdr.iter().map(|p| p[3] != 0.0).collect();
            }
            let e = errors(&frame.hdr, &reference, &lit);
            let timed = if setting.seeds > 1 || setting.pass == Some("path-trace") {
                desc.frames.min(5)
            } else {
                desc.frames
            };
            let timings = time_frames_with(renderer, &gpu, &inputs, size, timed)?;
            rows.push(LightTransportRow {
                scene: label.clone(),
                setting: setting.name,
                total: Spread::of(timings.iter().map(|t| t.total_ms).collect()),
                compared: e.compared,
                mean_relative: e.mean_relative,
                p95_relative: e.p95_relative,
                rms_relative: e.rms_relative,
                mean_radiance: e.mean_radiance,
                reference_noise: e.reference_noise,
            });
        }
        renderer.set_shading(ShadingOptions::DEFAULT, &[&gpu])?;
        renderer.retire(gpu);
    }
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    Ok(rows)
}

/// `light-transport.csv`: a row per scene and setting.
pub fn csv(rows: &[LightTransportRow]) -> String {
    let mut table = combustion_report_csv::Table::new(&[
        "scene",
        "setting",
        "total_ms",
        "pixels_compared",
        "mean_relative_error",
        "p95_relative_error",
        "rms_relative_error_noise_removed",
        "mean_radiance_relative",
        "reference_noise",
    ]);
    for r in rows {
        table.row([
            r.scene.clone(),
            r.setting.to_string(),
            format!("{:.3}", r.total.median),
            r.compared.to_string(),
            format!("{:.4e}", r.mean_relative),
            format!("{:.4e}", r.p95_relative),
            format!("{:.4e}", r.rms_relative),
            format!("{:.4e}", r.mean_radiance),
            format!("{:.4e}", r.reference_noise),
        ]);
    }
    table.finish()
}

/// The report's light-transport section (empty without rows).
pub fn markdown(rows: &[LightTransportRow], frames: u32) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut out = format!(
        "## Against light that bounces (devices with ray queries)\n\nEach real-time setting against the frame path traced (`--path-trace on`: {frames} frames of {} paths a pixel averaged; docs/path-tracing.md), over the pixels the default frame shows a surface at: the mean and 95th percentile of the relative error (the largest channel's; below {RADIANCE_FLOOR:e} absolute); the RMS relative error with the reference's own noise removed in quadrature (an unbiased estimate of the squared error against the converged image); the frame's mean radiance against the path-traced one (negative: darker than light that bounces). Reference noise: the path-traced mean's own relative standard error, averaged over those pixels — mean and p95 errors near it are within the reference's noise. The last row of each scene is one path-traced frame of another seed. Frame: GPU median; × default: its ratio to the default frame.\n\n| scene | setting | frame ms | × default | mean rel. error | p95 | RMS, noise removed | mean radiance | reference noise |\n|---|---|---|---|---|---|---|---|---|\n",
        combustion_renderer::PATHS_PER_FRAME
    );
    for r in rows {
        let default = rows
            .iter()
            .find(|d| d.scene == r.scene && d.setting == "default")
            .map_or(f64::NAN, |d| d.total.median);
        let _ = writeln!(
            out,
            "| {} | {} | {:.2} | {:.2} | {:.2e} | {:.2e} | {:.2e} | {:+.1} % | {:.2e} |",
            md_cell(&r.scene),
            r.setting,
            r.total.median,
            r.total.median / default,
            r.mean_relative,
            r.p95_relative,
            r.rms_relative,
            100.0 * r.mean_radiance,
            r.reference_noise
        );
    }
    out + "\n"
}
