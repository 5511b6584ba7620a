//! What the viewer shows about its frames: the statistics and help panels of the
//! overlay, and the error view (the frame re-shaded in f64 by the optics reference, its
//! relative error shown as a heat map).

use combustion_renderer::reference::{
    error_map, heat_map_color, heat_map_color_in, ReferenceShading, HEAT_MAP_RANGE,
};
use combustion_renderer::{
    FrameInputs, FresnelModel, GpuScene, HdrFormat, OverlayImage, PassTimings, Readback, Renderer,
};
use combustion_scene::Camera;

use crate::Error;

/// What a measured error map was measured of: a change of any of these makes it stale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewKey {
    /// The camera.
    pub camera: Camera,
    /// Frame size, pixels.
    pub extent: (u32, u32),
    /// Counts scene loads and edits.
    pub scene_generation: u64,
    /// The Fresnel term.
    pub fresnel: FresnelModel,
    /// The animation shown and its time (a playing one keeps the map from settling:
    /// pause it to measure).
    pub animation: (usize, f32),
}

/// The summary of a measured error map, for the overlay.
#[derive(Clone, Copy, Debug)]
pub struct ErrorSummary {
    /// The largest per-pixel relative error.
    pub max_relative: f64,
    /// The mean per-pixel relative error.
    pub mean_relative: f64,
    /// The pixel (x, y) with the largest error, from the top-left.
    pub worst_pixel: (u32, u32),
    /// Pixels compared.
    pub compared: usize,
    /// Pixels a blended or transmissive object may cover, which the G-buffer reference
    /// leaves out (the forward pass's surfaces are not in the G-buffer).
    pub blended: usize,
    /// Of those, the ones compared with the scene reference instead
    /// ([`forward_pixel_errors`]), and their mean and largest relative error.
    pub forward: Option<(usize, f64, f64)>,
    /// CPU time of the f64 re-shading, ms.
    pub reshade_ms: f64,
}

/// The relative errors the heat map of the real-time frame against light that bounces
/// spans: 1e-3 (blue) to 1 (red) — a frame that lights each surface once misses whole
/// terms, where the one-bounce reference's map measures rounding.
pub const TRANSPORT_HEAT_MAP_RANGE: (f64, f64) = (1e-3, 1.0);

/// Paths a pixel the path-traced mean holds before the error view first compares the
/// real-time frame with it (then again each time they have doubled).
pub const TRANSPORT_FIRST_PATHS: u64 = 64;

/// The real-time frame against the path-traced mean of the same view, summed up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransportSummary {
    /// Paths a pixel the mean held.
    pub paths: u64,
    /// Pixels compared: where either frame has light.
    pub compared: usize,
    /// The mean of the per-pixel relative errors.
    pub mean_relative: f64,
    /// Their 95th percentile.
    pub p95_relative: f64,
    /// The real-time frame's total radiance over the traced one's, less 1 (below 0:
    /// darker than light that bounces).
    pub brightness: f64,
}

/// Per pixel, the real-time frame's relative error against the path-traced mean: the
/// largest channel's |realtime − traced| / max(traced, 1e-4) (the report's floor), NaN
/// (grey: not compared) where both frames are black; and the summary over the compared
/// pixels. The mean's own noise is not removed: the more paths, the less it adds.
pub fn transport_errors(
    realtime: &[[f32; 4]],
    traced: &[[f32; 4]],
    paths: u64,
) -> (Vec<f32>, TransportSummary) {
    let mut compared = Vec::new();
    let (mut total_realtime, mut total_traced) = (0.0f64, 0.0f64);
    let errors: Vec<f32> = realtime
        .iter()
        .zip(traced)
        .map(|(a, t)| {
            let lit = (0..3).any(|c| a[c] > 0.0 || t[c] > 0.0);
            if !lit {
                return f32::NAN;
            }
            let error = (0..3)
                .map(|c| {
                    let (a, t) = (f64::from(a[c]), f64::from(t[c]));
                    total_realtime += a;
                    total_traced += t;
                    (a - t).abs() / t.max(1e-4)
                })
                .fold(0.0, f64::max);
            compared.push(error);
            error as f32
        })
        .collect();
    compared.sort_by(f64::total_cmp);
    let mean_relative = compared.iter().sum::<f64>() / compared.len().max(1) as f64;
    let p95_relative = compared
        .get((compared.len().saturating_sub(1) as f64 * 0.95).round() as usize)
        .copied()
        .unwrap_or(0.0);
    let brightness = if total_traced > 0.0 {
        total_realtime / total_traced - 1.0
    } else {
        0.0
    };
    let summary = TransportSummary {
        paths,
        compared: compared.len(),
        mean_relative,
        p95_relative,
        brightness,
    };
    (errors, summary)
}

/// The heat map of [`transport_errors`]' per-pixel errors over
/// [`TRANSPORT_HEAT_MAP_RANGE`], as the overlay image.
pub fn transport_overlay(width: u32, height: u32, errors: &[f32]) -> OverlayImage {
    OverlayImage {
        width,
        height,
        rgba: errors
            .iter()
            .map(|&e| heat_map_color_in(e, TRANSPORT_HEAT_MAP_RANGE))
            .collect(),
    }
}

/// The error view while it is on.
#[derive(Clone, Copy, Debug, Default)]
pub struct ErrorView {
    /// The view measured last and its errors (`None`: not measured, or stale).
    pub measured: Option<(ViewKey, ErrorSummary)>,
    /// While not measured: the view of the last frame (measured once it stays the same
    /// for a while).
    pub pending: Option<ViewKey>,
}

/// Rays per axis of the reference's environment visibility in the error view (16²
/// stratified cosine rays at each compared pixel).
const ERROR_VIEW_RAYS_PER_AXIS: u32 = 16;

/// Renders the frame of `inputs` at `extent` again with its HDR image and G-buffer read
/// back, re-shades every pixel in f64, and shows the relative error as the renderer's
/// overlay image. The reference blocks what the renderer's options block: each light by
/// its exact visibility with shadows (maps or ray-traced), the environment by the
/// occlusion passes' visibility with one of them on (every sampled direction traced
/// with the sampled environment and ray-traced occlusion). The caller has waited for its frames in flight (this frame uses the
/// renderer's frame slots too). A diagnostic: it waits for the GPU and reads back.
pub fn measure_error(
    renderer: &mut Renderer,
    scene: &GpuScene,
    inputs: &FrameInputs<'_>,
    extent: (u32, u32),
) -> Result<ErrorSummary, Error> {
    let (width, height) = extent;
    let readback = Readback::ALL;
    let frame = renderer.render_with(scene, inputs, width, height, readback)?;
    let started = std::time::Instant::now();
    // The scene as the frame showed it: still, in the frame's pose (at rest without
    // one: its skinned and morphed meshes deformed as the frame deformed them).
    let drawn = scene.scene().as_drawn(inputs.pose);
    let shown = drawn.as_ref();
    let mut reference = ReferenceShading::new(shown, inputs, width, height);
    let options = renderer.shading();
    let on = |name| {
        combustion_renderer::optional_pass(name)
            .is_some_and(|p| options.optional_passes.contains(p))
    };
    let occluded = on("ambient-occlusion") || on("ray-traced-occlusion");
    let casters = (options.shadows.is_some() || on("ray-traced-shadows") || occluded)
        .then(|| std::sync::Arc::new(combustion_reference::SceneBvh::shadow_casters(shown)));
    if let Some(bvh) = &casters {
        if options.shadows.is_some() || on("ray-traced-shadows") {
            // Frames with shadows are measured against exact visibility: each light's
            // term times its f64 ray-cast visibility (combustion_reference).
            reference = reference.with_exact_visibility(bvh.clone(), inputs.lights);
        }
        if occluded && options.environment_samples > 0 && on("ray-traced-occlusion") {
            // The sampled environment traces each direction: so does its reference.
            reference = reference.with_traced_environment(bvh.clone(), ERROR_VIEW_RAYS_PER_AXIS);
        } else if occluded {
            // Frames whose environment the scene blocks are measured against the
            // occlusion passes' definition of its visibility.
            reference =
                reference.with_environment_visibility(bvh.clone(), ERROR_VIEW_RAYS_PER_AXIS);
        }
    }
    if let Some(environment) = &scene.scene().environment {
        // The environment's integral costs thousands of BRDF evaluations a pixel: one
        // pixel in 4×4 is compared (the rest grey), with 500 samples of each strategy.
        reference = reference.with_environment(
            environment.clone(),
            combustion_renderer::reference::EnvironmentSampling {
                iterations: 500,
                stride: 4,
            },
        );
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut map = error_map(&frame, &reference, threads);
    let mut forward = None;
    if let Some(errors) = forward_pixel_errors(renderer, scene, inputs, &frame, threads) {
        let mut kept = Vec::new();
        for (x, y, e) in errors {
            if reference.under_blended(x, y) {
                map.relative[(y * width + x) as usize] = e as f32;
                kept.push(e);
            }
        }
        let mean = kept.iter().sum::<f64>() / kept.len().max(1) as f64;
        forward = Some((kept.len(), mean, kept.iter().copied().fold(0.0, f64::max)));
    }
    let reshade_ms = started.elapsed().as_secs_f64() * 1e3;
    let image = OverlayImage {
        width,
        height,
        rgba: map.relative.iter().map(|&e| heat_map_color(e)).collect(),
    };
    renderer.set_overlay_image(Some(&image))?;
    log::info!(
        "error view: max relative error {:.3e} at {:?}, mean {:.3e}, {} pixels compared ({} of them emissive; {} under blended objects skipped), re-shaded in {reshade_ms:.0} ms",
        map.max_relative,
        map.worst_pixel,
        map.mean_relative,
        map.lit_pixels,
        map.emissive_pixels,
        map.blended_pixels
    );
    Ok(ErrorSummary {
        max_relative: map.max_relative,
        mean_relative: map.mean_relative,
        worst_pixel: map.worst_pixel,
        compared: map.lit_pixels,
        blended: map.blended_pixels,
        forward,
        reshade_ms,
    })
}

/// The relative errors, (x, y, error), of the pixels the frame shows a blended or
/// transmissive surface at, against the scene reference (`crate::end_to_end`: each
/// pixel's ray cast through the scene in f64, blended surfaces composited over what is
/// behind them, light followed through glass) with the frame's camera and lights;
/// `None` for a scene without such objects, or one whose frames that reference does not
/// model (lit by an environment, or with shadows).
pub fn forward_pixel_errors(
    renderer: &Renderer,
    scene: &GpuScene,
    inputs: &FrameInputs<'_>,
    frame: &combustion_renderer::Frame,
    threads: usize,
) -> Option<Vec<(u32, u32, f64)>> {
    let source = scene.scene();
    let forward_drawn = source.materials.iter().any(|m| m.is_see_through());
    let environment_lit = source.environment.is_some() || inputs.environment.is_some();
    if !forward_drawn || environment_lit || renderer.shading().shadows.is_some() {
        return None;
    }
    let mut seen = source.clone();
    seen.camera = inputs.camera;
    let bvh = combustion_reference::SceneBvh::new(&seen);
    let precision = crate::end_to_end::precision_of(renderer.settings().gbuffer);
    let reference = crate::end_to_end::SceneReference::new(
        &seen,
        &bvh,
        inputs.lights,
        (frame.width, frame.height),
        precision,
        threads,
    );
    let compared = reference.compare(frame);
    Some(
        compared
            .pixels
            .iter()
            .chain(&compared.transmissive)
            .filter(|p| !reference.blended(p.x, p.y).is_empty())
            .map(|p| (p.x, p.y, p.total))
            .collect(),
    )
}

/// What the error view left out, for its panel line (empty when nothing was).
fn not_compared(e: &ErrorSummary) -> String {
    let under_forward = e.blended - e.forward.map_or(0, |(n, ..)| n);
    let parts: Vec<String> = [(under_forward, "in the boxes of blended or glass objects")]
        .into_iter()
        .filter(|(count, _)| *count > 0)
        .map(|(count, what)| format!("{} {what}", thousands(count)))
        .collect();
    if parts.is_empty() {
        String::new()
    } else {
        format!(" ({} not compared)", parts.join(", "))
    }
}

/// The statistics panel's facts.
pub struct Stats<'a> {
    /// The scene's label.
    pub label: &'a str,
    /// Frame size, pixels.
    pub extent: (u32, u32),
    /// Triangles drawn.
    pub triangles: usize,
    /// Lights of the frame.
    pub lights: usize,
    /// Median wall time between presents over the last frames, ms.
    pub frame_ms: Option<f64>,
    /// GPU times of the last completed frame's passes, if known.
    pub timings: Option<PassTimings>,
    /// The debug view's name ([`crate::renderer::DebugView::name`]).
    pub view: &'a str,
    /// The Fresnel term.
    pub fresnel: FresnelModel,
    /// The viewer's material and medium overrides, described.
    pub overrides: &'a str,
    /// The exposure, as said ([`crate::viewer`]'s exposure text).
    pub exposure: String,
    /// The auto exposure's histogram as a line of text ([`histogram_line`]), when on.
    pub histogram: Option<String>,
    /// The camera shown (index from 0) and the number of cameras.
    pub camera: (usize, usize),
    /// The HDR image's format.
    pub hdr_format: HdrFormat,
    /// The error view, while it is on.
    pub error_view: Option<ErrorView>,
    /// The outside medium's index being typed, if any.
    pub typing: Option<&'a str>,
    /// The animation playing, described (none for a still scene).
    pub animation: Option<String>,
    /// Paths a pixel the frame's converging mean holds, in path-traced frames (0:
    /// none).
    pub accumulated_paths: u64,
    /// With the error view on a path-traced view: the real-time frame against the mean,
    /// once measured (`None`: not yet, or not that view).
    pub transport: Option<TransportSummary>,
}

/// Groups of three digits: 194304 → "194,304".
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

impl Stats<'_> {
    /// The panel's text, one fact group per line.
    pub fn text(&self) -> String {
        let (w, h) = self.extent;
        let mut lines = vec![format!(
            "{} · {w}×{h} · {} triangles · {} lights",
            self.label,
            thousands(self.triangles),
            self.lights
        )];
        let mut timing = match self.frame_ms {
            Some(ms) => format!("{:.1} fps · frame {ms:.1} ms", 1e3 / ms),
            None => "first frame".to_owned(),
        };
        if let Some(t) = &self.timings {
            let passes: Vec<String> = t
                .passes
                .iter()
                .map(|p| format!("{} {:.1}", p.name, p.ms))
                .collect();
            timing += &format!(" · GPU {:.1} ms: {}", t.total_ms, passes.join(", "));
        }
        lines.push(timing);
        let fresnel = self.fresnel.description();
        lines.push(format!(
            "view: {} · {fresnel} · {} · {}",
            self.view, self.overrides, self.exposure
        ));
        if let Some(histogram) = &self.histogram {
            lines.push(histogram.clone());
        }
        if self.camera.1 > 1 {
            lines.push(format!("camera {} of {}", self.camera.0 + 1, self.camera.1));
        }
        if let Some(animation) = &self.animation {
            lines.push(animation.clone());
        }
        if self.accumulated_paths > 0 {
            lines.push(format!(
                "path traced: {} paths a pixel (converging while nothing moves)",
                thousands(self.accumulated_paths as usize)
            ));
        }
        if let (Some(_), Some(t)) = (self.error_view, self.transport) {
            let (lo, hi) = TRANSPORT_HEAT_MAP_RANGE;
            lines.push(format!(
                "error view: the real-time frame against light that bounces ({} paths a pixel)",
                thousands(t.paths as usize)
            ));
            lines.push(format!(
                "mean {:.2e} · p95 {:.2e} · {} pixels · radiance {:+.1} %",
                t.mean_relative,
                t.p95_relative,
                thousands(t.compared),
                t.brightness * 100.0
            ));
            lines.push(format!(
                "heat map, log scale: blue {lo:.0e} · cyan · green · yellow · red ≥ {hi:.0e}; grey: black in both"
            ));
        } else if let Some(error_view) = self.error_view {
            let (lo, hi) = HEAT_MAP_RANGE;
            let hdr = match self.hdr_format {
                HdrFormat::Rgba16Float => "f16",
                HdrFormat::Rgba32Float => "f32",
            };
            match error_view.measured {
                Some((_, e)) => {
                    lines.push(format!(
                        "error view: relative error against the f64 reference (HDR {hdr})"
                    ));
                    lines.push(format!(
                        "max {:.2e} at ({}, {}) · mean {:.2e} · {} pixels{} · re-shaded in {:.0} ms",
                        e.max_relative,
                        e.worst_pixel.0,
                        e.worst_pixel.1,
                        e.mean_relative,
                        thousands(e.compared),
                        not_compared(&e),
                        e.reshade_ms
                    ));
                    if let Some((pixels, mean, max)) = e.forward {
                        lines.push(format!(
                            "blended and glass surfaces, against rays cast through the scene: {} pixels · mean {mean:.2e} · max {max:.2e}",
                            thousands(pixels)
                        ));
                    }
                    lines.push(format!(
                        "heat map, log scale: blue {lo:.0e} · cyan · green · yellow · red ≥ {hi:.0e}; grey: not compared"
                    ));
                }
                None => lines.push("error view: measured when the view stops changing".into()),
            }
        }
        if let Some(typed) = self.typing {
            lines.push(format!(
                "outside medium η: {typed}_   (Enter applies, Escape cancels)"
            ));
        }
        lines.push("H: help · Tab: hide".into());
        lines.join("\n")
    }
}

/// The help panel: every key, two columns.
pub fn help_text(keys: &[(&str, &str)]) -> String {
    keys.iter()
        .map(|(key, what)| format!("{key}\t{what}"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The auto exposure's histogram as one line of text: 64 columns of 4 bins each, from
/// the darkest luminance metered to the brightest, each a character of ` .:-=+*#%@` by
/// its share of the fullest column, between the log2 luminances it spans.
pub fn histogram_line(metered: &combustion_renderer::MeteredExposure) -> String {
    const LEVELS: &[u8] = b" .:-=+*#%@";
    let columns: Vec<u64> = metered
        .histogram
        .chunks(4)
        .map(|bins| bins.iter().map(|&n| u64::from(n)).sum())
        .collect();
    let fullest = columns.iter().copied().max().unwrap_or(0).max(1);
    let bars: String = columns
        .iter()
        .map(|&n| {
            let level = if n == 0 {
                0
            } else {
                1 + (n * (LEVELS.len() as u64 - 2) / fullest) as usize
            };
            char::from(LEVELS[level])
        })
        .collect();
    let [low, high] = combustion_renderer::METERED_LOG2_LUMINANCE;
    format!("log2 luminance {low} |{bars}| {high}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thousands_are_grouped() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1000), "1,000");
        assert_eq!(thousands(194_304), "194,304");
        assert_eq!(thousands(1_234_567), "1,234,567");
    }
}
