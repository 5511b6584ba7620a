//! `combustion render`: a scene to PNG / EXR, optionally within an accuracy budget.

use std::path::PathBuf;

use combustion::renderer::{
    Frame, FrameInputs, Readback, Renderer, RendererSettings, ShadingOptions,
};
use combustion::{check_validation, output, Error, Headless, HeadlessDesc};

use super::write_stdout;
use super::*;

/// The images of a frame, read back (no G-buffer).
const IMAGES: Readback = Readback::IMAGES;

/// Frames `--accumulate-until` averages at least (for a spread to measure) and at most.
const ACCUMULATED_FRAMES: (u32, u32) = (4, 1024);

/// When [`accumulate`] stops.
#[derive(Clone, Copy)]
pub(crate) enum Until {
    /// When the mean's relative standard error is at most this ([`ACCUMULATED_FRAMES`]
    /// bound the count).
    Error(f64),
    /// After this many frames (`--samples`).
    Frames(u32),
}

/// Frames of `inputs` with environment seeds 0, 1, 2, … averaged until `until`: for
/// [`Until::Error`], until the mean's relative standard error — per pixel the largest
/// channel's √(s²/k) over its mean (at least the reference's radiance floor), averaged
/// over the pixels brighter than the floor — is at most the target. The mean frame (its
/// display image made from the mean radiance as the output pass makes it), the frames
/// taken and the error reached.
pub(crate) fn accumulate(
    renderer: &mut Renderer,
    scene: &combustion::renderer::GpuScene,
    inputs: &FrameInputs<'_>,
    (width, height): (u32, u32),
    until: Until,
) -> Result<(Frame, u32, f64), Error> {
    let floor = combustion::renderer::reference::RADIANCE_FLOOR;
    let mut averaged = combustion::frame_mean::FrameMean::new((width * height) as usize);
    let mut last = None;
    let mut achieved = f64::INFINITY;
    let (most, target) = match until {
        Until::Error(target) => (ACCUMULATED_FRAMES.1, target),
        Until::Frames(frames) => (frames, 0.0),
    };
    while averaged.frames() < most {
        let seeded = FrameInputs {
            environment_seed: averaged.frames(),
            ..*inputs
        };
        let frame = renderer.render_with(scene, &seeded, width, height, IMAGES)?;
        averaged.add(&frame.hdr);
        last = Some(frame);
        let measured = averaged.frames() >= ACCUMULATED_FRAMES.0 || averaged.frames() == most;
        if measured && averaged.frames() > 1 {
            let (sum, lit) = averaged
                .mean()
                .iter()
                .zip(&averaged.standard_errors())
                .fold((0.0, 0usize), |(sum, lit), (m, s)| {
                    if m.iter().all(|&v| v <= floor) {
                        return (sum, lit);
                    }
                    let error = (0..3).map(|c| s[c] / m[c].max(floor)).fold(0.0, f64::max);
                    (sum + error, lit + 1)
                });
            achieved = if lit == 0 { 0.0 } else { sum / lit as f64 };
            if matches!(until, Until::Error(_)) && achieved <= target {
                break;
            }
        }
    }
    let mut frame = last.expect("at least one frame");
    // A metered frame's exposure is its last frame's (each metered alone).
    let exposure = renderer.exposure_shown(inputs);
    for ((out, display), m) in frame
        .hdr
        .iter_mut()
        .zip(&mut frame.ldr)
        .zip(averaged.mean())
    {
        *out = [m[0] as f32, m[1] as f32, m[2] as f32, out[3]];
        let exposed = m.map(|v| v * f64::from(exposure));
        let [r, g, b] = inputs.tone_mapping.display_codes(exposed);
        *display = [r, g, b, display[3]];
    }
    Ok((frame, averaged.frames(), achieved))
}

/// `e`, said in the options the user gave where it is the supersampled frame's size (a
/// size they never asked for: `--supersample N` renders N times as wide and high).
pub(crate) fn supersampled_size_error(
    e: combustion::renderer::RenderError,
    factor: u32,
    (width, height): (u32, u32),
) -> Error {
    match e {
        combustion::renderer::RenderError::InvalidSize { max, .. } => Error::Usage(format!(
            "--supersample {factor} with --width {width} --height {height}: the frame is rendered {factor} times as wide and high, {}×{} pixels, past this device's {max} per side; give a smaller size or factor",
            u64::from(width) * u64::from(factor),
            u64::from(height) * u64::from(factor),
        )),
        other => other.into(),
    }
}

/// Whether `passes` run the optional pass named `name`.
pub(crate) fn pass_asked(passes: &combustion::renderer::OptionalPasses, name: &str) -> bool {
    combustion::renderer::optional_pass(name).is_some_and(|pass| passes.contains(pass))
}

/// Whether `o` asks for ray-traced occlusion, and for path tracing.
fn traced_and_path_traced(o: &RenderArgs) -> (bool, bool) {
    let passes = &o.shading.optional.passes;
    (
        pass_asked(passes, "ray-traced-occlusion"),
        pass_asked(passes, "path-trace"),
    )
}

/// What `o` averages over frames (`--samples`, `--accumulate-until`), refused where
/// nothing it renders has noise to average.
pub(crate) fn frames_averaged(o: &RenderArgs) -> Result<Option<Until>, Error> {
    let (traced, path_traced) = traced_and_path_traced(o);
    if o.samples.is_some() && !path_traced {
        return Err(Error::Usage(
            "--samples needs --path-trace on (the paths a pixel averages; --environment-samples N sets the environment's)".into(),
        ));
    }
    if o.accumulate_until.is_some() && o.shading.environment_samples == 0 && !traced && !path_traced
    {
        return Err(Error::Usage(
            "--accumulate-until needs --environment-samples N, --environment-occlusion ray-traced or --path-trace on (the split sum has no noise to average)".into(),
        ));
    }
    Ok(match (o.accumulate_until, o.samples) {
        (Some(target), _) => Some(Until::Error(target)),
        (None, Some(samples)) => Some(Until::Frames(
            samples / combustion::renderer::PATHS_PER_FRAME,
        )),
        (None, None) => None,
    })
}

pub(crate) fn render(o: &RenderArgs) -> Result<(), Error> {
    // Fail on an unwritable destination before spending time on the render.
    // A name whose extension says another format would get bytes it does not say.
    if let Some(png) = &o.output {
        output::check_extension(png, "-o", "PNG", &["png"])?;
    }
    if let Some(exr) = &o.hdr {
        output::check_extension(exr, "--hdr", "OpenEXR", &["exr"])?;
    }
    if o.accumulate_until.is_some() && o.supersample > 1 {
        return Err(Error::Usage(
            "--accumulate-until and --supersample cannot be combined yet: choose one".into(),
        ));
    }
    if let Some(smoothing) = o.picture.smoothing_asked().filter(|_| o.supersample > 1) {
        return Err(Error::Usage(format!(
            "--supersample {n} and --anti-aliasing {}: supersampling is the exact anti-aliasing of a still image; give one",
            smoothing.name(),
            n = o.supersample
        )));
    }
    let until = frames_averaged(o)?;
    let auto_exposure = o.frame.auto_exposure()?;
    let bloom_intensity = o
        .frame
        .bloom_intensity(pass_asked(&o.shading.optional.passes, "bloom"))?;
    let (traced, path_traced) = traced_and_path_traced(o);
    let default_output = (o.output.is_none() && o.hdr.is_none()).then(|| PathBuf::from("out.png"));
    let png_path = o.output.clone().or(default_output);
    let targets = png_path
        .iter()
        .chain(o.hdr.iter())
        .map(|path| output::check_writable(path))
        .collect::<Result<Vec<_>, _>>()?;
    // No output may be written over what the run reads.
    let scene_source = o.scene.source();
    let mut inputs: Vec<(&'static str, &std::path::Path)> = Vec::new();
    if let combustion::SceneSource::File(scene) = &scene_source {
        inputs.push(("scene file", scene));
    }
    if let Some(EnvironmentChoice::File(image)) = &o.shading.environment {
        inputs.push(("environment image", image));
    }
    for given in png_path.iter().chain(o.hdr.iter()) {
        output::check_not_an_input(given, &inputs)?;
    }
    if let [png, exr] = &targets[..] {
        if output::same_file(png, exr) {
            return Err(Error::Usage(format!(
                "-o and --hdr name the same file ({}): give each its own",
                png.display()
            )));
        }
    }
    let (device, mut settings) = device_and_settings(
        &o.device,
        &o.frame,
        RendererSettings::default().frames_in_flight,
    )?;
    preflight(&device, &o.frame)?;
    let source = o.scene.source();
    let scene = lit_as_asked(&source, o.camera.camera, &o.shading)?;
    let pose = o.animation.pose(&scene)?;
    if scene.objects.is_empty() {
        log::warn!(
            "{}: the scene has nothing to draw (no objects); the image shows the background alone",
            source.label()
        );
    }
    warn_about_view(&scene, &source.label(), o.frame.width, o.frame.height);
    // An accuracy budget: the fastest variant set within it, measured on this scene at
    // this size (5 frames each).
    if let Some(budget) = o.max_error {
        let choice = combustion::report::choose(
            &source,
            budget,
            o.frame.width,
            o.frame.height,
            5,
            device.clone(),
        )?;
        if choice.nothing_compared() {
            // Nothing lit in view: the budget cannot choose; the options as given stand.
            log::warn!(
                "--max-error {budget:e}: no pixel of this scene was compared with the reference (nothing lit in view); rendering with the default variant set"
            );
            settings.shading = o.shading.options(settings.shading);
        } else {
            let Some(set) = choice.chosen else {
                let best = choice
                    .candidates
                    .iter()
                    .min_by(|a, b| a.mean_relative.total_cmp(&b.mean_relative));
                return Err(Error::Usage(format!(
                    "--max-error {budget:e}: no variant set is within it on this scene (the most accurate, {}, has mean relative error {:.2e})",
                    best.map_or("none".into(), |r| r.set.name()),
                    best.map_or(f64::NAN, |r| r.mean_relative)
                )));
            };
            // The set's choices, and every shading option the sets do not vary as asked.
            settings.shading = ShadingOptions {
                energy_compensation: o.shading.energy_compensation,
                shadows: o.shading.shadows(),
                environment_samples: o.shading.environment_samples,
                optional_passes: o.shading.optional.passes,
                ..set.shading
            };
            settings.hdr_format = set.hdr;
            outln!("variant set {} (--max-error {budget:e}; `combustion info SCENE --max-error {budget:e}` says why)", set.name());
        }
    } else {
        settings.shading = o.shading.options(settings.shading);
    }
    let started = std::time::Instant::now();
    let mut headless = Headless::new(&HeadlessDesc { device, settings })?;
    let (frame, stats) = {
        let renderer = headless.renderer();
        if path_traced && !renderer.device().ray_queries() {
            // A raster frame is not what was asked for: say so rather than write one.
            return Err(Error::Unsupported(format!(
                "--path-trace on needs a device with ray queries (VK_KHR_ray_query; lavapipe from Mesa 24.1): {} has none",
                renderer.device().info().name
            )));
        }
        // The scene itself goes to the renderer (the run holds it once); read back from
        // there below.
        let gpu_scene = renderer.upload_owned(scene)?;
        let scene = gpu_scene.scene();
        let inputs = combustion::renderer::FrameInputs {
            background: o.picture.background_for(scene),
            tone_mapping: o.picture.tone_mapping_for(&source),
            anti_aliasing: o.picture.anti_aliasing_for(o.supersample),
            pose: pose.as_ref(),
            auto_exposure,
            bloom_intensity,
            ..combustion::renderer::FrameInputs::of_scene(&gpu_scene, settings.exposure)
        };
        let size = (o.frame.width, o.frame.height);
        let frame = match until {
            None if o.supersample > 1 => renderer
                .render_supersampled(&gpu_scene, &inputs, size.0, size.1, o.supersample)
                .map_err(|e| supersampled_size_error(e, o.supersample, size))?,
            None => {
                // Temporal anti-aliasing: a still frame is the last of one period of the
                // jitter from its camera (the history's first frames run unread).
                if pass_asked(&o.shading.optional.passes, "temporal-anti-aliasing") {
                    for _ in 1..combustion::renderer::TEMPORAL_JITTER_PERIOD {
                        renderer.render_with(
                            &gpu_scene,
                            &inputs,
                            size.0,
                            size.1,
                            combustion::renderer::Readback::default(),
                        )?;
                    }
                }
                renderer.render_with(&gpu_scene, &inputs, size.0, size.1, IMAGES)?
            }
            Some(Until::Frames(frames)) => {
                let (frame, frames, achieved) =
                    accumulate(renderer, &gpu_scene, &inputs, size, Until::Frames(frames))?;
                outln!(
                    "path traced {} paths per pixel ({frames} {} of {}): relative standard error {}",
                    frames * combustion::renderer::PATHS_PER_FRAME,
                    if frames == 1 { "frame" } else { "frames" },
                    combustion::renderer::PATHS_PER_FRAME,
                    if frames > 1 {
                        format!("{achieved:.2e}")
                    } else {
                        "not measured (one frame)".to_owned()
                    }
                );
                frame
            }
            Some(Until::Error(target)) => {
                let (frame, frames, achieved) =
                    accumulate(renderer, &gpu_scene, &inputs, size, Until::Error(target))?;
                let per_frame = match (o.shading.environment_samples, traced) {
                    _ if path_traced => {
                        format!("{} paths per pixel", combustion::renderer::PATHS_PER_FRAME)
                    }
                    (0, _) => "ray-traced occlusion".to_owned(),
                    (n, false) => format!("{n} environment samples per pixel"),
                    (n, true) => {
                        format!("{n} environment samples per pixel and ray-traced occlusion")
                    }
                };
                outln!(
                    "accumulated {frames} frames of {per_frame}: relative standard error {achieved:.2e} (asked {target:e})"
                );
                if achieved > target {
                    log::warn!(
                        "--accumulate-until {target:e}: not reached in {frames} frames, the most it averages (relative standard error {achieved:.2e}); the image is their mean{}",
                        if path_traced {
                            ""
                        } else {
                            " (more --environment-samples reach a smaller error)"
                        }
                    );
                }
                frame
            }
        };
        if let (Some(_), Some(metered)) = (auto_exposure, renderer.last_metered_exposure()) {
            outln!(
                "auto exposure: EV100 {:.2} (exposure {}), metered from {} of {} pixels",
                metered.ev100,
                combustion::optics::readable(metered.exposure),
                metered.counted,
                u64::from(frame.width) * u64::from(frame.height)
            );
        }
        (frame, renderer.stats())
    };
    let start_up = started.elapsed();
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    // A frame that overflowed is refused, not written: its PNG would show the NaN
    // pixels black and its EXR carry them.
    // (In a 16-bit frame, f16's largest value counts: lavapipe clamps an overflow there
    // rather than writing infinity.)
    let count = frame.overflowed_pixels(settings.hdr_format);
    if count > 0 {
        return Err(Error::NonFiniteFrame {
            count,
            pixels: frame.hdr.len(),
        });
    }
    if let Some(path) = &png_path {
        output::write_png(path, frame.width, frame.height, &frame.ldr)?;
        outln!(
            "wrote {} ({}x{})",
            path.display(),
            frame.width,
            frame.height
        );
    }
    if let Some(path) = &o.hdr {
        output::write_exr(path, frame.width, frame.height, &frame.hdr)?;
        outln!(
            "wrote {} ({}x{}, linear float)",
            path.display(),
            frame.width,
            frame.height
        );
    }
    let t = &frame.timings;
    let passes: Vec<String> = t
        .passes
        .iter()
        .map(|p| format!("{} {:.2} ms", p.name, p.ms))
        .collect();
    outln!(
        "GPU time: {}, total {:.2} ms (one frame; `combustion bench` for medians)",
        passes.join(", "),
        t.total_ms
    );
    let bakes = match stats.environment_bakes {
        0 => String::new(),
        1 => format!(
            ", 1 environment bake ({} its cubes from the bake cache)",
            if stats.environment_cubes_from_cache == 1 {
                "with"
            } else {
                "without"
            }
        ),
        bakes => format!(
            ", {bakes} environment bakes ({} with their cubes from the bake cache)",
            stats.environment_cubes_from_cache
        ),
    };
    let structures = match stats.acceleration_structure_bytes {
        0 => String::new(),
        bytes => format!(
            ", acceleration structures of {:.1} MiB",
            bytes as f64 / (1024.0 * 1024.0)
        ),
    };
    outln!(
        "start-up: {} shaders ({} from the SPIR-V cache) in {:.0} ms, {} pipelines{bakes}{structures}; device, pipelines, scene upload and frame {:.2} s in all",
        stats.shaders_compiled,
        stats.shaders_from_cache,
        stats.shader_compile_micros as f64 / 1e3,
        stats.pipelines_built,
        start_up.as_secs_f64()
    );
    Ok(())
}
