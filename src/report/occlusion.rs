//! The report's environment-occlusion section: on each scene lit by an environment, the
//! frame without occlusion, with the screen-space pass (`ambient-occlusion`) and, on a
//! device with ray queries, with the traced pass (`ray-traced-occlusion`, [`TRACED_SEEDS`]
//! frames averaged), each against the f64 reference that blocks the environment by the
//! same definition (`ReferenceShading::with_environment_visibility`, [`VISIBILITY_RAYS`]²
//! rays a pixel) at one pixel in [`ENVIRONMENT_SAMPLING`]'s stride² — mean and 95th
//! percentile of the relative error — at their GPU cost (the frame's and the pass's
//! medians). Written as `occlusion.csv` and a section of `report.md`.

use std::fmt::Write as _;
use std::sync::Arc;

use combustion_reference::SceneBvh;
use combustion_renderer::reference::ReferenceShading;
use combustion_renderer::{
    optional_pass, FrameInputs, OptionalPasses, Renderer, RendererSettings, ShadingOptions,
};

use super::environment_sampling::{compare, integrate_with, mean_of_seeds};
use super::{md_cell, time_frames_with, ReportDesc, Spread, ENVIRONMENT_SAMPLING};
use crate::{check_validation, Error};

/// Rays per axis of the reference's visibility at each compared pixel.
pub const VISIBILITY_RAYS: u32 = 24;

/// Frames of successive seeds the traced row averages (its noise), and the frames it
/// times (at most the report's: a traced frame costs tens of lavapipe frames).
pub const TRACED_SEEDS: u32 = 8;

/// One scene and occlusion method.
#[derive(Clone, Debug, PartialEq)]
pub struct OcclusionRow {
    /// The scene's label.
    pub scene: String,
    /// `none`, `screen-space` or `ray-traced`.
    pub method: &'static str,
    /// Whole frame's GPU time.
    pub total: Spread,
    /// The occlusion pass's GPU time ([`Spread::NONE`] without one).
    pub pass: Spread,
    /// Pixels compared.
    pub compared: usize,
    /// Mean relative error against the reference with the environment's visibility.
    pub mean_relative: f64,
    /// Its 95th percentile.
    pub p95_relative: f64,
}

/// One method: its name, its optional pass and that pass's timings' name, and the seeds
/// its row averages.
struct Method {
    name: &'static str,
    pass: Option<(&'static str, &'static str)>,
    seeds: u32,
}

/// The methods measured on `renderer`'s device.
fn methods(renderer: &Renderer) -> Vec<Method> {
    let mut methods = vec![
        Method {
            name: "none",
            pass: None,
            seeds: 1,
        },
        Method {
            name: "screen-space",
            pass: Some(("ambient-occlusion", "ambient occlusion")),
            seeds: 1,
        },
    ];
    if renderer.device().ray_queries() {
        methods.push(Method {
            name: "ray-traced",
            pass: Some(("ray-traced-occlusion", "ray-traced occlusion")),
            seeds: TRACED_SEEDS,
        });
    }
    methods
}

/// Measures every method on each scene of `scenes` lit by an environment.
pub(super) fn measure(
    scenes: &[(String, combustion_scene::Scene)],
    desc: &ReportDesc,
    threads: usize,
    mut progress: impl FnMut(&str),
) -> Result<Vec<OcclusionRow>, Error> {
    let mut rows = Vec::new();
    let mut headless = desc.headless(RendererSettings::default())?;
    let renderer = headless.renderer();
    let (width, height) = (desc.width, desc.height);
    for (label, scene) in scenes.iter().filter(|(_, s)| s.environment.is_some()) {
        let gpu = renderer.upload(scene)?;
        let inputs = FrameInputs::of_scene(&gpu, 1.0);
        let environment = scene.environment.clone().expect("lit by an environment");
        let reference = ReferenceShading::new(scene, &inputs, width, height)
            .with_environment_visibility(
                Arc::new(SceneBvh::shadow_casters(scene)),
                VISIBILITY_RAYS,
            );
        let mut oracle = None;
        for Method { name, pass, seeds } in methods(renderer) {
            progress(&format!("{label} occlusion {name}"));
            let passes = pass
                .and_then(|(option, _)| optional_pass(option))
                .map_or(OptionalPasses::NONE, |p| OptionalPasses::NONE.with(p, true));
            renderer.set_shading(
                ShadingOptions {
                    optional_passes: passes,
                    ..ShadingOptions::DEFAULT
                },
                &[&gpu],
            )?;
            let frame = mean_of_seeds(renderer, &gpu, &inputs, (width, height), seeds)?;
            // The G-buffer is the same with every method: one oracle per scene.
            let oracle = match &oracle {
                Some(o) => o,
                None => oracle.insert(integrate_with(
                    &reference,
                    &frame,
                    &environment,
                    ENVIRONMENT_SAMPLING,
                    threads,
                )),
            };
            let mut errors: Vec<f64> = compare(&frame, oracle).into_iter().map(|e| e.0).collect();
            let frames = if seeds > 1 {
                desc.frames.min(5)
            } else {
                desc.frames
            };
            let timings = time_frames_with(renderer, &gpu, &inputs, (width, height), frames)?;
            let compared = errors.len();
            errors.sort_by(f64::total_cmp);
            rows.push(OcclusionRow {
                scene: label.clone(),
                method: name,
                total: Spread::of(timings.iter().map(|t| t.total_ms).collect()),
                pass: pass.map_or(Spread::NONE, |(_, timed)| {
                    Spread::of(timings.iter().filter_map(|t| t.ms(timed)).collect())
                }),
                compared,
                mean_relative: errors.iter().sum::<f64>() / compared.max(1) as f64,
                p95_relative: errors
                    .get((compared * 95 / 100).min(compared.saturating_sub(1)))
                    .copied()
                    .unwrap_or(f64::NAN),
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

/// `occlusion.csv`: a row per scene and method.
pub fn csv(rows: &[OcclusionRow]) -> String {
    let mut table = combustion_report_csv::Table::new(&[
        "scene",
        "occlusion",
        "total_ms",
        "pass_ms",
        "pixels_compared",
        "mean_relative_error",
        "p95_relative_error",
    ]);
    for r in rows {
        table.row([
            r.scene.clone(),
            r.method.to_string(),
            format!("{:.3}", r.total.median),
            if r.pass.median.is_finite() {
                format!("{:.3}", r.pass.median)
            } else {
                String::new()
            },
            r.compared.to_string(),
            format!("{:.4e}", r.mean_relative),
            format!("{:.4e}", r.p95_relative),
        ]);
    }
    table.finish()
}

/// The report's occlusion section (empty without rows).
pub fn markdown(rows: &[OcclusionRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "## Environment occlusion (scenes lit by an environment)\n\nThe environment blocked by the scene: no occlusion, the screen-space pass (`--environment-occlusion gtao`) and the traced pass (`--environment-occlusion ray-traced`, devices with ray queries; 8 seeds averaged, its frame time over at most 5 frames), against the f64 reference that blocks it by the same definition (24² cosine rays a pixel against the scene's triangles, applied as the split sum applies occlusion; docs/occlusion.md). The split sum's own error against the rendering equation is in every row. Frame and pass: GPU medians; the cost as a ratio to the frame without occlusion.\n\n| scene | occlusion | frame ms | × none | pass ms | mean rel. error | p95 |\n|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let none = rows
            .iter()
            .find(|n| n.scene == r.scene && n.method == "none")
            .map_or(f64::NAN, |n| n.total.median);
        let _ = writeln!(
            out,
            "| {} | {} | {:.2} | {:.2} | {} | {:.2e} | {:.2e} |",
            md_cell(&r.scene),
            r.method,
            r.total.median,
            r.total.median / none,
            if r.pass.median.is_finite() {
                format!("{:.2}", r.pass.median)
            } else {
                "—".into()
            },
            r.mean_relative,
            r.p95_relative
        );
    }
    out + "\n"
}
