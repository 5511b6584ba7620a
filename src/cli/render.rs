//! `combustion render`: a scene to PNG / EXR, optionally within an accuracy budget.

use std::path::PathBuf;

use combustion::renderer::{RendererSettings, ShadingOptions};
use combustion::{check_validation, output, Error, Headless, HeadlessDesc};

use super::*;
use crate::write_stdout;

pub(crate) fn render(o: &RenderArgs) -> Result<(), Error> {
    // Fail on an unwritable destination before spending time on the render.
    // A name whose extension says another format would get bytes it does not say.
    if let Some(png) = &o.output {
        output::check_extension(png, "-o", "PNG", &["png"])?;
    }
    if let Some(exr) = &o.hdr {
        output::check_extension(exr, "--hdr", "OpenEXR", &["exr"])?;
    }
    let default_output = (o.output.is_none() && o.hdr.is_none()).then(|| PathBuf::from("out.png"));
    let png_path = o.output.clone().or(default_output);
    let targets = png_path
        .iter()
        .chain(o.hdr.iter())
        .map(|path| output::check_writable(path))
        .collect::<Result<Vec<_>, _>>()?;
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
            settings.shading = ShadingOptions {
                energy_compensation: o.shading.energy_compensation,
                shadows: o.shading.shadows(),
                ..set.shading
            };
            settings.hdr_format = set.hdr;
            outln!("variant set {} (--max-error {budget:e}; `combustion info SCENE --max-error {budget:e}` says why)", set.name());
        }
    } else {
        settings.shading = o.shading.options(settings.shading);
    }
    let mut headless = Headless::new(&HeadlessDesc { device, settings })?;
    let frame = {
        let renderer = headless.renderer();
        let gpu_scene = renderer.upload(&scene)?;
        let inputs = combustion::renderer::FrameInputs {
            background: o.picture.background_for(&scene),
            tone_mapping: o.picture.tone_mapping_for(&source),
            pose: pose.as_ref(),
            ..combustion::renderer::FrameInputs::of_scene(&gpu_scene, settings.exposure)
        };
        renderer.render_with(
            &gpu_scene,
            &inputs,
            o.frame.width,
            o.frame.height,
            combustion::renderer::Readback {
                images: true,
                gbuffer: false,
            },
        )?
    };
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    // A frame that overflowed is refused, not written: its PNG would show the NaN
    // pixels black and its EXR carry them.
    let count = frame.non_finite_pixels();
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
    Ok(())
}
