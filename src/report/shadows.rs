//! The report's shadow section: on each scene with lights, the cost of each
//! shadow setting (frames of a static camera, whose maps are kept, and of a camera
//! moving every frame, whose maps are rendered again each frame) and its error against
//! exact visibility (`combustion_reference`'s f64 ray casts): the share of pixels whose
//! shadow verdict is wrong, and the frame's error against the reference with exact
//! visibility. Written as `shadows.csv` and a section of `report.md`.

use std::fmt::Write as _;
use std::sync::Arc;

use combustion_reference::SceneBvh;
use combustion_renderer::reference::{error_map, shadow_mismatch, ReferenceShading};
use combustion_renderer::{
    DebugView, FrameInputs, GpuScene, PassTimings, Readback, Renderer, ShadingOptions,
    ShadowFilter, ShadowSettings,
};

use combustion_plots::{pareto_front, plot_speed_vs_error, Png, SpeedErrorPoint};

use super::{md_cell, time_frames, PassSpreads, ReportDesc, Spread, ENVIRONMENT_SAMPLING};
use crate::Error;

/// The shadow settings the report measures: none (the frame without shadows), the
/// default (4 cascades of 2048², local lights' maps of 1024², hard), PCF over 16 taps,
/// and a cheap one (2 cascades of 1024², local maps of 512², hard).
pub const SHADOW_SETTINGS: [Option<ShadowSettings>; 4] = [
    None,
    Some(ShadowSettings::DEFAULT),
    Some(ShadowSettings {
        filter: ShadowFilter::Pcf16,
        ..ShadowSettings::DEFAULT
    }),
    Some(ShadowSettings {
        cascades: 2,
        map_size: 1024,
        local_map_size: 512,
        filter: ShadowFilter::Hard,
    }),
];

/// The name of the ray-traced shadows' row (after the maps' settings, on devices with
/// ray queries).
pub const RAY_TRACED: &str = "ray-traced";

/// n·l below which the shadow verdict is not compared: the terminator band of the
/// built-in scenes' UV spheres, sin of their facet angle (2π/64 ≈ 0.098; see
/// [`shadow_mismatch`]).
pub const TERMINATOR_COS: f64 = 0.1;

/// One scene and shadow setting.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowRow {
    /// The scene's label.
    pub scene: String,
    /// The setting (`None`: no shadow maps).
    pub settings: Option<ShadowSettings>,
    /// Ray-traced shadows (`ray-traced-shadows`, on devices with ray queries) instead of
    /// maps (`settings` is then `None`).
    pub traced: bool,
    /// Whole frame's GPU time, static camera (the maps rendered once, then kept).
    pub static_total: Spread,
    /// Whole frame's GPU time, the camera moving every frame (the maps rendered again).
    pub moving_total: Spread,
    /// The shadow pass, camera moving: the maps', or the traced shadows' rays
    /// ([`Spread::NONE`] without shadows).
    pub maps: Spread,
    /// Pixels the maps leave lit though exactly shadowed from the scene's first light (a
    /// frame without shadows lights every pixel).
    pub lit_should_be_shadowed: usize,
    /// Pixels the maps shadow though exactly lit.
    pub shadowed_should_be_lit: usize,
    /// The mean and the largest absolute radiance error (W·sr⁻¹·m⁻², green channel) at
    /// the misclassified pixels (shadow edges, and whole shadows without shadows).
    pub edge_error: (f64, f64),
    /// Pixels whose verdict was compared.
    pub compared: usize,
    /// The frame's mean relative error against the reference with exact visibility.
    pub mean_relative: f64,
    /// Its largest relative error.
    pub max_relative: f64,
}

impl ShadowRow {
    /// The setting's name: `off`, or filter, cascades, map size and the local lights'
    /// map size (`hard-4x2048-1024`).
    pub fn setting_name(&self) -> String {
        if self.traced {
            RAY_TRACED.into()
        } else {
            setting_name(self.settings)
        }
    }
}

/// `off`, or filter-cascadesxsize-localsize (`hard-4x2048-1024`).
pub fn setting_name(settings: Option<ShadowSettings>) -> String {
    match settings {
        None => "off".into(),
        Some(s) => format!(
            "{}-{}x{}-{}",
            s.filter.name(),
            s.cascades,
            s.map_size,
            s.local_map_size
        ),
    }
}

/// Measures every setting of `desc.shadows` on `gpu` (a scene with lights),
/// leaving the renderer's shading options at the default.
pub(super) fn measure_scene(
    renderer: &mut Renderer,
    gpu: &GpuScene,
    label: &str,
    desc: &ReportDesc,
    threads: usize,
    mut progress: impl FnMut(&str),
) -> Result<Vec<ShadowRow>, Error> {
    let (width, height) = (desc.width, desc.height);
    let inputs = FrameInputs::of_scene(gpu, 1.0);
    let mut reference = ReferenceShading::new(gpu.scene(), &inputs, width, height)
        .with_exact_visibility(
            Arc::new(SceneBvh::shadow_casters(gpu.scene())),
            inputs.lights,
        );
    if let Some(environment) = &gpu.scene().environment {
        reference = reference.with_environment(environment.clone(), ENVIRONMENT_SAMPLING);
    }
    let both = Readback::ALL;
    // The moving camera: the scene's own and one moved a tenth of its distance to the
    // target sideways, alternately (every frame places new cascades).
    let mut moved = inputs.camera;
    let forward = moved.target - moved.position;
    let sideways = forward.cross(moved.up).normalize_or_zero() * forward.length() * 0.1;
    moved.position += sideways;
    moved.target += sideways;
    let mut rows = Vec::new();
    // The maps' settings, then the ray-traced shadows where the device has ray queries.
    let traced = combustion_renderer::optional_pass("ray-traced-shadows")
        .filter(|_| renderer.device().ray_queries() && !desc.shadows.is_empty());
    let measured = desc
        .shadows
        .iter()
        .map(|&settings| (settings, None))
        .chain(traced.map(|pass| (None, Some(pass))));
    for (settings, traced) in measured {
        let name = traced.map_or_else(|| setting_name(settings), |_| RAY_TRACED.into());
        progress(&format!("{label} shadows {name}"));
        let shading = ShadingOptions {
            shadows: settings,
            optional_passes: traced.map_or(combustion_renderer::OptionalPasses::NONE, |pass| {
                combustion_renderer::OptionalPasses::NONE.with(pass, true)
            }),
            ..ShadingOptions::DEFAULT
        };
        renderer.set_shading(shading, &[gpu])?;
        let frame = renderer.render_with(gpu, &inputs, width, height, both)?;
        let errors = error_map(&frame, &reference, threads);
        let (counts, wrong) = if settings.is_some() || traced.is_some() {
            renderer.set_shading(
                ShadingOptions {
                    debug_view: DebugView::ShadowFactor,
                    ..shading
                },
                &[gpu],
            )?;
            let view = renderer.render_with(gpu, &inputs, width, height, both)?;
            renderer.set_shading(shading, &[gpu])?;
            shadow_mismatch(&view, |i| view.ldr[i][0] >= 128, &reference, TERMINATOR_COS)
        } else {
            shadow_mismatch(&frame, |_| true, &reference, TERMINATOR_COS)
        };
        let still = time_frames(renderer, gpu, width, height, desc.frames)?;
        renderer.take_completed_timings();
        for i in 0..desc.frames {
            let frame_inputs = FrameInputs {
                camera: if i % 2 == 0 { moved } else { inputs.camera },
                ..inputs
            };
            renderer.submit_offscreen_with(gpu, &frame_inputs, width, height)?;
        }
        renderer.finish_offscreen()?;
        let moving = renderer.take_completed_timings();
        rows.push(ShadowRow {
            scene: label.to_owned(),
            settings,
            static_total: Spread::of(still.iter().map(|t| t.total_ms).collect()),
            moving_total: Spread::of(moving.iter().map(|t| t.total_ms).collect()),
            maps: PassSpreads::of(&moving).get(if traced.is_some() {
                "ray-traced shadows"
            } else {
                PassTimings::SHADOW_MAPS
            }),
            traced: traced.is_some(),
            lit_should_be_shadowed: counts.lit_should_be_shadowed,
            shadowed_should_be_lit: counts.shadowed_should_be_lit,
            edge_error: edge_error(&frame, &errors, &wrong),
            compared: counts.compared,
            mean_relative: errors.mean_relative,
            max_relative: errors.max_relative,
        });
    }
    renderer.set_shading(ShadingOptions::DEFAULT, &[gpu])?;
    Ok(rows)
}

/// The mean and largest absolute radiance error (green) of `frame` against the
/// reference radiance of `errors` over the pixels marked in `wrong` ((0, 0) if none).
fn edge_error(
    frame: &combustion_renderer::Frame,
    errors: &combustion_renderer::reference::ErrorMap,
    wrong: &[bool],
) -> (f64, f64) {
    let values: Vec<f64> = wrong
        .iter()
        .enumerate()
        .filter(|(_, &w)| w)
        .filter_map(|(i, _)| {
            let reference = errors.reference_radiance.get(i)?;
            Some((f64::from(frame.hdr[i][1]) - f64::from(reference[1])).abs())
        })
        .collect();
    if values.is_empty() {
        return (0.0, 0.0);
    }
    (
        values.iter().sum::<f64>() / values.len() as f64,
        values.iter().fold(0.0, |a: f64, &b| a.max(b)),
    )
}

impl ShadowRow {
    /// Pixels misclassified either way.
    pub fn misclassified(&self) -> usize {
        self.lit_should_be_shadowed + self.shadowed_should_be_lit
    }
}

/// One point per shadow setting, over the scenes measured: its mean static frame time
/// and its mean share of misclassified pixels (the error shadows add or remove).
pub fn points(rows: &[ShadowRow]) -> Vec<SpeedErrorPoint> {
    let mut names: Vec<String> = Vec::new();
    for row in rows {
        if !names.contains(&row.setting_name()) {
            names.push(row.setting_name());
        }
    }
    names
        .into_iter()
        .map(|name| {
            let of: Vec<&ShadowRow> = rows.iter().filter(|r| r.setting_name() == name).collect();
            let n = of.len() as f64;
            SpeedErrorPoint {
                ms: of.iter().map(|r| r.static_total.median).sum::<f64>() / n,
                error: of
                    .iter()
                    .map(|r| r.misclassified() as f64 / r.compared.max(1) as f64)
                    .sum::<f64>()
                    / n,
                label: name,
            }
        })
        .collect()
}

/// The shadow settings' speed against error, with their Pareto front
/// (`shadows-speed-vs-error.png`).
pub fn plot(rows: &[ShadowRow], device: &str, desc: &ReportDesc) -> Result<Png, Error> {
    Ok(plot_speed_vs_error(
        "Shadows: speed against error",
        &format!(
            "{device}, {}×{}, scenes with lights; red: Pareto front",
            desc.width, desc.height
        ),
        "frame time, GPU ms (median, static camera)",
        "share of pixels misclassified against exact visibility",
        &points(rows),
        1000,
        620,
    )?)
}

/// `shadows.csv`: one row per scene and setting.
pub fn csv(rows: &[ShadowRow]) -> String {
    let mut table = combustion_report_csv::Table::new(&[
        "scene",
        "shadows",
        "static_total_ms",
        "moving_total_ms",
        "shadow_maps_ms",
        "lit_should_be_shadowed",
        "shadowed_should_be_lit",
        "pixels_compared",
        "misclassified_fraction",
        "edge_mean_abs_error",
        "edge_max_abs_error",
        "mean_relative_error_exact_visibility",
        "max_relative_error_exact_visibility",
    ]);
    for r in rows {
        table.row([
            r.scene.clone(),
            r.setting_name().to_string(),
            format!("{:.3}", r.static_total.median),
            format!("{:.3}", r.moving_total.median),
            (
                // Empty where no shadow pass ran (the ray-traced row: its rays' pass).
                if r.maps.median.is_finite() {
                    format!("{:.3}", r.maps.median)
                } else {
                    String::new()
                }
            )
            .to_string(),
            r.lit_should_be_shadowed.to_string(),
            r.shadowed_should_be_lit.to_string(),
            r.compared.to_string(),
            format!("{:.5}", r.misclassified() as f64 / r.compared.max(1) as f64),
            format!("{:.3e}", r.edge_error.0),
            format!("{:.3e}", r.edge_error.1),
            format!("{:.3e}", r.mean_relative),
            format!("{:.3e}", r.max_relative),
        ]);
    }
    table.finish()
}

/// The report's shadow section (empty without rows).
pub fn markdown(rows: &[ShadowRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "## Shadows (scenes with lights)\n\nEach shadow setting (filter-cascades×map size-local lights' map size) against exact visibility: the f64 reference with every light's term multiplied by its visibility, ray cast against the scene's triangles (`combustion_reference`). *Misclassified*: pixels whose verdict on the scene's first light (the shadow-factor view below ½, or lit everywhere without shadows) differs from exact visibility, where the light reaches and n·l > 0.1 (the spheres' terminator band left out). Lit/shadowed: pixels left lit that are exactly shadowed, and shadowed that are exactly lit. Edge error: the absolute radiance error (W/sr/m², green) at those pixels, mean and max. Frame times: static camera (the maps are kept) and a camera moving every frame (the cascades rendered again each frame; spot and point lights' maps do not depend on the camera and stay kept, so their scenes show no map pass there); medians. *ray-traced*: hard shadows by ray queries (`--ray-traced-shadows on`, devices with ray queries), its pass in the maps' column.\n\n| scene | shadows | frame ms, static | frame ms, moving | shadow maps ms | misclassified | lit / shadowed | edge error mean / max | mean rel. error (exact visibility) |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "| {} | {} | {:.2} | {:.2} | {} | {:.3} % of {} | {} / {} | {:.2e} / {:.2e} | {:.2e} |",
            md_cell(&r.scene),
            r.setting_name(),
            r.static_total.median,
            r.moving_total.median,
            if r.maps.median.is_finite() {
                format!("{:.2}", r.maps.median)
            } else {
                "—".into()
            },
            100.0 * r.misclassified() as f64 / r.compared.max(1) as f64,
            r.compared,
            r.lit_should_be_shadowed,
            r.shadowed_should_be_lit,
            r.edge_error.0,
            r.edge_error.1,
            r.mean_relative,
        );
    }
    let points = points(rows);
    let front = pareto_front(&points);
    out += "\nPer setting over the scenes (mean static frame time, mean share misclassified; `shadows-speed-vs-error.png`):\n\n| shadows | frame ms | misclassified | Pareto front |\n|---|---|---|---|\n";
    for (i, p) in points.iter().enumerate() {
        let _ = writeln!(
            out,
            "| {} | {:.2} | {:.3} % | {} |",
            p.label,
            p.ms,
            100.0 * p.error,
            if front.contains(&i) { "yes" } else { "" }
        );
    }
    out + "\n"
}
