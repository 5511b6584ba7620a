//! The report's sampled-environment section: on each scene lit by an environment, the
//! split sum and the sampled mode (`ShadingOptions::environment_samples`) at each count
//! of [`SAMPLE_COUNTS`], and frames of successive seeds averaged ([`ACCUMULATED`]),
//! against the f64 rendering equation — at one pixel in [`ORACLE`]'s stride², integrated
//! with its samples of each strategy (their own standard error reported beside) — at
//! their GPU cost. Written as `environment-sampling.csv` and a section of `report.md`.

use std::fmt::Write as _;

use combustion_optics::environment::Estimate;
use combustion_renderer::reference::{EnvironmentSampling, ReferenceShading, RADIANCE_FLOOR};
use combustion_renderer::{
    Frame, FrameInputs, PassTimings, Readback, Renderer, RendererSettings, ShadingOptions,
};
use combustion_scene::Environment;

use super::{md_cell, time_frames_with, ReportDesc, Spread};
use crate::end_to_end::relative;
use crate::{check_validation, Error};

/// The sample counts measured, one frame each (0, the split sum, is measured apart).
pub const SAMPLE_COUNTS: [u32; 5] = [1, 4, 16, 64, 256];

/// Frames of successive seeds averaged, and their samples a pixel each: 16 × 64, the
/// progressive accumulation of a still render (`render --accumulate-until`).
pub const ACCUMULATED: (u32, u32) = (16, 64);

/// The oracle: 40,000 samples of each strategy at one pixel in 32 × 32, twenty times the
/// main table's, since the sampled mode's error at its largest counts is below that
/// table's oracle noise (its own noise is a column of the section).
pub const ORACLE: EnvironmentSampling = EnvironmentSampling {
    iterations: 40_000,
    stride: 32,
};

/// How the environment term was computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Prefiltered radiance × the albedo tables (`environment_samples` 0).
    SplitSum,
    /// N samples a pixel in one frame.
    Sampled(u32),
    /// The mean of `frames` frames of `samples` each, successive seeds.
    Accumulated {
        /// Frames averaged.
        frames: u32,
        /// Samples a pixel in each.
        samples: u32,
    },
}

impl Mode {
    /// `split sum`, `sampled`, `accumulated`.
    pub fn name(self) -> &'static str {
        match self {
            Mode::SplitSum => "split sum",
            Mode::Sampled(_) => "sampled",
            Mode::Accumulated { .. } => "accumulated",
        }
    }

    /// Samples a pixel in all (0 for the split sum).
    pub fn samples(self) -> u32 {
        match self {
            Mode::SplitSum => 0,
            Mode::Sampled(n) => n,
            Mode::Accumulated { frames, samples } => frames * samples,
        }
    }

    /// Frames it takes.
    pub fn frames(self) -> u32 {
        match self {
            Mode::Accumulated { frames, .. } => frames,
            _ => 1,
        }
    }

    /// Every mode measured, cheapest first.
    pub fn all() -> Vec<Mode> {
        let (frames, samples) = ACCUMULATED;
        std::iter::once(Mode::SplitSum)
            .chain(SAMPLE_COUNTS.map(Mode::Sampled))
            .chain([Mode::Accumulated { frames, samples }])
            .collect()
    }
}

/// One scene and mode.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentSamplingRow {
    /// The scene's label.
    pub scene: String,
    /// The mode.
    pub mode: Mode,
    /// Pixels compared.
    pub compared: usize,
    /// Relative error against the oracle, over the compared pixels (largest channel).
    pub mean_relative: f64,
    /// Median.
    pub median_relative: f64,
    /// Largest.
    pub max_relative: f64,
    /// The oracle's own standard error, relative, mean over the compared pixels.
    pub oracle_sigma_mean: f64,
    /// GPU time of one frame's lighting pass.
    pub lighting: Spread,
    /// GPU time of one frame (an accumulated row takes [`Mode::frames`] of them).
    pub total: Spread,
}

/// Measures every [`Mode`] on each scene of `scenes` lit by an environment, at the
/// report's size; `progress(what)` before each scene.
pub(super) fn measure(
    scenes: &[(String, combustion_scene::Scene)],
    desc: &ReportDesc,
    threads: usize,
    mut progress: impl FnMut(&str),
) -> Result<Vec<EnvironmentSamplingRow>, Error> {
    let mut rows = Vec::new();
    let mut headless = desc.headless(RendererSettings::default())?;
    let renderer = headless.renderer();
    let size = (desc.width, desc.height);
    for (label, scene) in scenes.iter().filter(|(_, s)| s.environment.is_some()) {
        progress(&format!("{label} environment samples"));
        let gpu = renderer.upload(scene)?;
        let inputs = FrameInputs::of_scene(&gpu, 1.0);
        let environment = gpu
            .scene()
            .environment
            .clone()
            .expect("lit by an environment");
        let mut oracle = None;
        // GPU times per sample count: an accumulated row's frames are the sampled
        // mode's at its count, timed once.
        let mut timed: Vec<(u32, Vec<PassTimings>)> = Vec::new();
        for mode in Mode::all() {
            // Samples a pixel in each frame (0: the split sum).
            let samples = mode.samples() / mode.frames();
            renderer.set_shading(
                ShadingOptions {
                    environment_samples: samples,
                    ..ShadingOptions::DEFAULT
                },
                &[&gpu],
            )?;
            let frame = frame_of(renderer, &gpu, &inputs, size, mode)?;
            // The G-buffer is the same in every mode: one oracle per scene.
            let oracle = match &oracle {
                Some(o) => o,
                None => oracle.insert(integrate(scene, &inputs, &frame, &environment, threads)),
            };
            let errors = compare(&frame, oracle);
            let timings = match timed.iter().find(|(n, _)| *n == samples) {
                Some((_, timings)) => timings.clone(),
                None => {
                    let timings = time_frames_with(renderer, &gpu, &inputs, size, desc.frames)?;
                    timed.push((samples, timings.clone()));
                    timings
                }
            };
            rows.push(EnvironmentSamplingRow {
                scene: label.clone(),
                mode,
                compared: errors.len(),
                mean_relative: mean(errors.iter().map(|e| e.0)),
                median_relative: Spread::of(errors.iter().map(|e| e.0).collect()).median,
                max_relative: errors.iter().map(|e| e.0).fold(0.0, f64::max),
                oracle_sigma_mean: mean(errors.iter().map(|e| e.1)),
                lighting: Spread::of(
                    timings
                        .iter()
                        .map(|t| t.ms_or_zero(PassTimings::LIGHTING))
                        .collect(),
                ),
                total: Spread::of(timings.iter().map(|t| t.total_ms).collect()),
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

/// The frame of `mode`: one frame, or the mean radiance of successive seeds' frames.
fn frame_of(
    renderer: &mut Renderer,
    gpu: &combustion_renderer::GpuScene,
    inputs: &FrameInputs<'_>,
    size: (u32, u32),
    mode: Mode,
) -> Result<Frame, Error> {
    mean_of_seeds(renderer, gpu, inputs, size, mode.frames())
}

/// The frame of seed 0 (its G-buffer read back) with its radiance replaced by the mean of
/// `frames` frames of successive seeds from 0 (one frame: itself).
pub(super) fn mean_of_seeds(
    renderer: &mut Renderer,
    gpu: &combustion_renderer::GpuScene,
    inputs: &FrameInputs<'_>,
    (width, height): (u32, u32),
    frames: u32,
) -> Result<Frame, Error> {
    let mut frame = renderer.render_with(gpu, inputs, width, height, Readback::ALL)?;
    if frames > 1 {
        let mut sum: Vec<[f64; 3]> = frame
            .hdr
            .iter()
            .map(|p| [p[0], p[1], p[2]].map(f64::from))
            .collect();
        for seed in 1..frames {
            let seeded = FrameInputs {
                environment_seed: seed,
                ..*inputs
            };
            let images = Readback::IMAGES;
            let next = renderer.render_with(gpu, &seeded, width, height, images)?;
            for (s, p) in sum.iter_mut().zip(&next.hdr) {
                for c in 0..3 {
                    s[c] += f64::from(p[c]);
                }
            }
        }
        for (p, s) in frame.hdr.iter_mut().zip(&sum) {
            for c in 0..3 {
                p[c] = (s[c] / f64::from(frames)) as f32;
            }
        }
    }
    Ok(frame)
}

/// The oracle at every compared pixel of `frame` (its G-buffer), on `threads` threads:
/// pixel index and estimate, the stored emission added as the lighting pass adds it.
fn integrate(
    scene: &combustion_scene::Scene,
    inputs: &FrameInputs<'_>,
    frame: &Frame,
    environment: &Environment,
    threads: usize,
) -> Vec<(usize, Estimate)> {
    let reference = ReferenceShading::new(scene, inputs, frame.width, frame.height);
    integrate_with(&reference, frame, environment, ORACLE, threads)
}

/// [`integrate`] with `reference` (its environment's visibility, say) and `sampling`'s
/// stride and samples.
pub(super) fn integrate_with(
    reference: &ReferenceShading,
    frame: &Frame,
    environment: &Environment,
    sampling: EnvironmentSampling,
    threads: usize,
) -> Vec<(usize, Estimate)> {
    let gbuffer = frame.gbuffer.as_ref().expect("the G-buffer was read back");
    let step = sampling.stride as usize;
    let pixels: Vec<(u32, u32)> = (step / 2..frame.height as usize)
        .step_by(step)
        .flat_map(|y| {
            (step / 2..frame.width as usize)
                .step_by(step)
                .map(move |x| (x as u32, y as u32))
        })
        .collect();
    let chunk = pixels.len().div_ceil(threads.max(1)).max(1);
    std::thread::scope(|s| {
        let handles: Vec<_> = pixels
            .chunks(chunk)
            .map(|part| {
                s.spawn(move || {
                    part.iter()
                        .filter_map(|&(x, y)| {
                            let i = (y * frame.width + x) as usize;
                            reference
                                .shade_environment(
                                    &gbuffer.texels[i],
                                    x,
                                    y,
                                    environment,
                                    sampling.iterations,
                                )
                                .map(|mut e| {
                                    // The emission the lighting pass adds, as stored.
                                    for c in 0..3 {
                                        e.mean[c] += gbuffer.texels[i].emissive_occlusion[c];
                                    }
                                    (i, e)
                                })
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("an oracle thread"))
            .collect()
    })
}

/// Per compared pixel: the relative error of `frame` against the oracle and the
/// oracle's relative standard error (the largest channel's of each; relative to the
/// value, or absolutely below the radiance floor).
pub(super) fn compare(frame: &Frame, oracle: &[(usize, Estimate)]) -> Vec<(f64, f64)> {
    oracle
        .iter()
        .map(|(i, estimate)| {
            let gpu = frame.hdr[*i];
            let error = relative([gpu[0], gpu[1], gpu[2]].map(f64::from), estimate.mean);
            let sigma = (0..3)
                .map(|c| estimate.standard_error[c] / estimate.mean[c].abs().max(RADIANCE_FLOOR))
                .fold(0.0, f64::max);
            (error, sigma)
        })
        .collect()
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 {
        f64::NAN
    } else {
        sum / n as f64
    }
}

/// `environment-sampling.csv`: one line per scene and mode.
pub fn csv(rows: &[EnvironmentSamplingRow]) -> String {
    let mut table = combustion_report_csv::Table::new(&[
        "scene",
        "mode",
        "samples",
        "frames",
        "pixels_compared",
        "mean_relative_error",
        "median_relative_error",
        "max_relative_error",
        "oracle_sigma_mean",
        "lighting_ms",
        "total_ms",
    ]);
    for r in rows {
        table.row([
            r.scene.clone(),
            r.mode.name().to_string(),
            r.mode.samples().to_string(),
            r.mode.frames().to_string(),
            r.compared.to_string(),
            format!("{:.4e}", r.mean_relative),
            format!("{:.4e}", r.median_relative),
            format!("{:.4e}", r.max_relative),
            format!("{:.3e}", r.oracle_sigma_mean),
            format!("{:.3}", r.lighting.median),
            format!("{:.3}", r.total.median),
        ]);
    }
    table.finish()
}

/// The report's sampled-environment section (empty without rows).
pub fn markdown(rows: &[EnvironmentSamplingRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut out = format!(
        "## Environment lighting: the split sum and the sampled mode against the rendering equation\n\nScenes lit by an environment alone, default variant set otherwise: the split sum, the sampled mode at N samples a pixel in one frame (`--environment-samples N`: a GGX visible-normal and a cosine direction per sample, balance heuristic), and {} frames of {} samples of successive seeds averaged (`render --accumulate-until`), against the f64 rendering equation at one pixel in {s}×{s} ({} samples of each strategy; its mean relative standard error beside). Independent samples' error falls as 1/√N (\"× √N\" level); a pixel's samples here are one Hammersley set, stratified, so theirs falls faster (\"× √N\" falling) until what remains is the radiance cube's texels and the oracle's own noise; frames of successive seeds are independent of each other. Frame ms: one frame's GPU median (an accumulated row takes its frames × that).\n\n| scene | mode | samples a pixel | mean rel. error | × √N | median | max | oracle σ (mean) | lighting ms | frame ms |\n|---|---|---|---|---|---|---|---|---|---|\n",
        ACCUMULATED.0,
        ACCUMULATED.1,
        ORACLE.iterations,
        s = ORACLE.stride,
    );
    for r in rows {
        let samples = r.mode.samples();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.2e} | {} | {:.2e} | {:.2e} | {:.1e} | {:.2} | {:.2} |",
            md_cell(&r.scene),
            r.mode.name(),
            if samples == 0 {
                "—".to_owned()
            } else {
                samples.to_string()
            },
            r.mean_relative,
            if samples == 0 {
                "—".to_owned()
            } else {
                format!("{:.3}", r.mean_relative * f64::from(samples).sqrt())
            },
            r.median_relative,
            r.max_relative,
            r.oracle_sigma_mean,
            r.lighting.median,
            r.total.median,
        );
    }
    out + "\n"
}
