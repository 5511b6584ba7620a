//! The report's anti-aliasing section: on each scene, each way of smoothing edges —
//! none, FXAA in the output pass, and N×N supersampling of a still frame — against the
//! same frame supersampled 4×4 (16 samples a pixel, box-filtered radiance: the exact
//! pixel up to its own sampling), by mean FLIP of the display images, at its GPU cost.
//! Written as `anti-aliasing.csv` and a section of `report.md`.

use std::fmt::Write as _;

use combustion_renderer::{
    AntiAliasing, Frame, FrameInputs, PassTimings, Readback, RendererSettings,
};

use super::{flip_against_radiance, md_cell, time_frames_with, PassSpreads, ReportDesc, Spread};
use crate::{check_validation, Error};

/// The reference's samples per side: 4×4 a pixel.
pub const REFERENCE_SUPERSAMPLE: u32 = 4;

/// A way of smoothing edges the report measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The output pass's [`AntiAliasing`] on a frame of one sample a pixel.
    OutputPass(AntiAliasing),
    /// N×N samples a pixel (`Renderer::render_supersampled`).
    Supersample(u32),
    /// Temporal anti-aliasing (the `temporal-anti-aliasing` pass) on a still camera: the
    /// last of one period of its jitter (16 frames).
    Temporal,
}

impl Method {
    /// Every method measured: none, FXAA, temporal, 2×2 and 3×3 supersampling.
    pub const ALL: [Method; 5] = [
        Method::OutputPass(AntiAliasing::None),
        Method::OutputPass(AntiAliasing::Fxaa),
        Method::Temporal,
        Method::Supersample(2),
        Method::Supersample(3),
    ];

    /// `none`, `fxaa`, `supersample 2x2`, …
    pub fn name(self) -> String {
        match self {
            Method::OutputPass(a) => a.name().to_owned(),
            Method::Supersample(n) => format!("supersample {n}x{n}"),
            Method::Temporal => "temporal".to_owned(),
        }
    }
}

/// One scene and method.
#[derive(Clone, Debug, PartialEq)]
pub struct AntiAliasingRow {
    /// The scene's label.
    pub scene: String,
    /// The method.
    pub method: Method,
    /// Mean FLIP of its display image against the 4×4-supersampled frame's.
    pub flip_mean: f64,
    /// The output pass's GPU time (of the large frame, for supersampling).
    pub output: Spread,
    /// The whole frame's GPU time (the large frame's, for supersampling).
    pub total: Spread,
}

/// Measures every [`Method`] on every scene of `scenes` at the report's size, default
/// settings; `progress(what)` before each scene.
pub(super) fn measure(
    scenes: &[(String, combustion_scene::Scene)],
    desc: &ReportDesc,
    mut progress: impl FnMut(&str),
) -> Result<Vec<AntiAliasingRow>, Error> {
    let mut rows = Vec::new();
    let mut headless = desc.headless(RendererSettings::default())?;
    let renderer = headless.renderer();
    let exposure = renderer.settings().exposure;
    let size = (desc.width, desc.height);
    for (label, scene) in scenes {
        progress(&format!("{label} anti-aliasing"));
        let gpu = renderer.upload(scene)?;
        let inputs = FrameInputs::of_scene(&gpu, exposure);
        let reference =
            renderer.render_supersampled(&gpu, &inputs, size.0, size.1, REFERENCE_SUPERSAMPLE)?;
        let radiance: Vec<[f32; 3]> = reference.hdr.iter().map(|p| [p[0], p[1], p[2]]).collect();
        let flip =
            |frame: &Frame| flip_against_radiance(frame, &radiance, exposure, inputs.tone_mapping);
        for method in Method::ALL {
            let (frame, timings) = match method {
                Method::OutputPass(anti_aliasing) => {
                    let asked = FrameInputs {
                        anti_aliasing,
                        ..inputs
                    };
                    let frame =
                        renderer.render_with(&gpu, &asked, size.0, size.1, Readback::IMAGES)?;
                    (
                        frame,
                        time_frames_with(renderer, &gpu, &asked, size, desc.frames)?,
                    )
                }
                Method::Supersample(n) => {
                    let frame = renderer.render_supersampled(&gpu, &inputs, size.0, size.1, n)?;
                    let large = (size.0 * n, size.1 * n);
                    (
                        frame,
                        time_frames_with(renderer, &gpu, &inputs, large, desc.frames)?,
                    )
                }
                Method::Temporal => temporal(renderer, &gpu, &inputs, size, desc.frames)?,
            };
            let passes = PassSpreads::of(&timings);
            rows.push(AntiAliasingRow {
                scene: label.clone(),
                method,
                flip_mean: flip(&frame),
                output: passes.get(PassTimings::OUTPUT),
                total: Spread::of(timings.iter().map(|t| t.total_ms).collect()),
            });
        }
        renderer.retire(gpu);
    }
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    Ok(rows)
}

/// A still frame of temporal anti-aliasing (the last of one period of its jitter) and
/// the timings of `frames` more, the pass switched on for them and off again.
fn temporal(
    renderer: &mut combustion_renderer::Renderer,
    gpu: &combustion_renderer::GpuScene,
    inputs: &FrameInputs<'_>,
    size: (u32, u32),
    frames: u32,
) -> Result<(Frame, Vec<PassTimings>), Error> {
    let plain = renderer.shading();
    let taa = combustion_renderer::optional_pass("temporal-anti-aliasing")
        .expect("the temporal anti-aliasing pass");
    let mut shading = plain;
    shading.optional_passes = shading.optional_passes.with(taa, true);
    renderer.set_shading(shading, &[gpu])?;
    for _ in 1..combustion_renderer::TEMPORAL_JITTER_PERIOD {
        renderer.render_with(gpu, inputs, size.0, size.1, Readback::default())?;
    }
    let frame = renderer.render_with(gpu, inputs, size.0, size.1, Readback::IMAGES)?;
    let timings = time_frames_with(renderer, gpu, inputs, size, frames)?;
    renderer.set_shading(plain, &[gpu])?;
    Ok((frame, timings))
}

/// `anti-aliasing.csv`: one line per scene and method.
pub fn csv(rows: &[AntiAliasingRow]) -> String {
    let mut table = combustion_report_csv::Table::new(&[
        "scene",
        "method",
        "flip_mean_against_4x4",
        "output_ms",
        "total_ms",
    ]);
    for r in rows {
        table.row([
            r.scene.clone(),
            r.method.name().to_string(),
            format!("{:.4e}", r.flip_mean),
            format!("{:.3}", r.output.median),
            format!("{:.3}", r.total.median),
        ]);
    }
    table.finish()
}

/// The report's anti-aliasing section (empty without rows).
pub fn markdown(rows: &[AntiAliasingRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "## Anti-aliasing\n\nEach way of smoothing edges against the same frame supersampled 4×4 (16 samples a pixel, their radiance averaged, then exposed and tone-mapped): mean FLIP of the display images. `fxaa`: FXAA in the output pass (a pipeline of its own, for frames that ask for it); `temporal`: temporal anti-aliasing on the still camera, the last of one period of its jitter (16 frames; docs/camera.md measures it in motion against 16×16 supersampling); `supersample N×N`: the frame rendered N times as wide and high, its radiance averaged per pixel (the frame and output times are the large frame's). Times: GPU medians. FLIP weighs every pixel an edge blend moves: FXAA moves the pixels it changes nearer the reference on the whole but by little in FLIP (tests/anti_aliasing.rs).\n\n| scene | method | mean FLIP against 4×4 | output ms | frame ms |\n|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "| {} | {} | {:.2e} | {:.2} | {:.2} |",
            md_cell(&r.scene),
            r.method.name(),
            r.flip_mean,
            r.output.median,
            r.total.median,
        );
    }
    out + "\n"
}
