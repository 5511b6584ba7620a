//! `combustion bench`: GPU pass times of a scene, or the speed-against-error report.

use std::time::Instant;

use combustion::renderer::Readback;
use combustion::{check_validation, output, Error, Headless, HeadlessDesc, SceneSource};

use super::write_stdout;
use super::*;

/// `bench --report DIR`: every variant set on the built-in scenes (or the scene named).
pub(crate) fn bench_report(o: &BenchArgs, dir: &std::path::Path) -> Result<(), Error> {
    use combustion::report::{ReportDesc, ReportSection, VariantSet};
    let sections = report_sections(o)?;
    let asked = |section: ReportSection| sections.contains(&section);
    // clap refuses --report with the options it sets itself (--fresnel, --hdr-format,
    // --specialised, --distribution, --diffuse, --extra-lights, --culling).
    // An unreadable previous report and an unwritable report folder are refused before
    // minutes of measuring.
    let previous = o
        .against
        .as_deref()
        .map(combustion::report::PreviousRun::read)
        .transpose()?;
    output::make_folder(dir)?;
    combustion::report::check_report_folder(dir)?;
    let (device, _) = device_and_settings(&o.device, &o.frame, o.frames_in_flight)?;
    preflight(&device, &o.frame)?;
    let scenes = if let Some(scene) = o.scene.given() {
        vec![scene.clone()]
    } else {
        combustion::scene::BUILTIN_SCENES
            .iter()
            .map(|name| SceneSource::Builtin((*name).to_owned()))
            .collect()
    };
    // By default, the authored textured glTF scene too, lit by the studio environment
    // (its textured metal, occlusion and emission against the environment oracle): from
    // the working folder when it is the source tree, else from the tree this was built
    // from; left out, with a warning, where neither is.
    let studio_scenes = if o.scene.given().is_some() {
        Vec::new()
    } else {
        let textured = std::path::Path::new("assets/scenes/textured/textured.gltf");
        let built_from = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(textured);
        if textured.is_file() {
            vec![SceneSource::File(textured.to_owned())]
        } else if built_from.is_file() {
            vec![SceneSource::File(built_from)]
        } else {
            log::warn!(
                "assets/scenes/textured/textured.gltf not found: the report has no textured glTF scene"
            );
            Vec::new()
        }
    };
    let desc = ReportDesc {
        scenes,
        studio_scenes,
        sets: if asked(ReportSection::Variants) {
            VariantSet::all()
        } else {
            Vec::new()
        },
        width: o.frame.width,
        height: o.frame.height,
        frames: o.frames,
        device,
        floors: asked(ReportSection::Floors),
        shadows: if asked(ReportSection::Shadows) {
            combustion::report::shadows::SHADOW_SETTINGS.to_vec()
        } else {
            Vec::new()
        },
        storages: if asked(ReportSection::Storage) {
            combustion::report::storage::all_storages()
        } else {
            Vec::new()
        },
        anti_aliasing: asked(ReportSection::AntiAliasing),
        environment_sampling: asked(ReportSection::EnvironmentSampling),
        occlusion: asked(ReportSection::Occlusion),
        path_traced_frames: if asked(ReportSection::LightTransport) {
            o.path_traced_frames.unwrap_or(0)
        } else {
            0
        },
        // Frame time against size and light count: on the scene named, else on the
        // performance scene.
        scaling: asked(ReportSection::Scaling).then(|| {
            o.scene
                .given()
                .cloned()
                .unwrap_or_else(|| SceneSource::Builtin("grid-7x7".to_owned()))
        }),
    };
    let started = Instant::now();
    let terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let measured = combustion::report::measure(&desc, |done, total, what| {
        let width = 30;
        let filled = done * width / total.max(1);
        let bar = format!(
            "[{}{}] {done}/{total} {what:<48.48}",
            "#".repeat(filled),
            ".".repeat(width - filled)
        );
        // A bar redrawn in place on a terminal; one line per step in a log.
        if terminal {
            eprint!("\r{bar}");
            if done == total {
                eprintln!();
            }
        } else {
            eprintln!("{}", bar.trim_end());
        }
    })?;
    let reproduction = previous.map(|p| p.compare(&measured.rows));
    let written = combustion::report::write(dir, &measured, &desc, reproduction.as_ref())?;
    let measured_sections: Vec<&str> = sections.iter().map(|s| s.name()).collect();
    outln!(
        "wrote {} ({}): {} scene(s); {} in {:.0} s",
        dir.display(),
        written.join(", "),
        desc.scenes.len() + desc.studio_scenes.len(),
        measured_sections.join(", "),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The report's sections `--report-sections` and `--path-traced-frames` ask for, checked
/// before the device starts: light transport needs its frame count, the floors and
/// `--against` the variant sets they are read against.
fn report_sections(o: &BenchArgs) -> Result<Vec<combustion::report::ReportSection>, Error> {
    use combustion::report::ReportSection;
    let mut sections: Vec<ReportSection> = if o.report_sections.is_empty() {
        ReportSection::ALL
            .into_iter()
            .filter(|s| *s != ReportSection::LightTransport || o.path_traced_frames.is_some())
            .collect()
    } else {
        o.report_sections.clone()
    };
    sections.sort_by_key(|s| ReportSection::ALL.iter().position(|a| a == s));
    sections.dedup();
    let asked = |section: ReportSection| sections.contains(&section);
    let usage = |why: &str| Err(Error::Usage(why.to_owned()));
    match (asked(ReportSection::LightTransport), o.path_traced_frames) {
        (true, None) => {
            return usage("--report-sections light-transport needs --path-traced-frames N (the path-traced frames averaged)")
        }
        (false, Some(_)) => {
            return usage("--path-traced-frames measures the light-transport section, which --report-sections leaves out")
        }
        _ => {}
    }
    if asked(ReportSection::Floors) && !asked(ReportSection::Variants) {
        return usage("--report-sections floors needs variants too (each floor is read against the default variant set's passes)");
    }
    if o.against.is_some() && !asked(ReportSection::Variants) {
        return usage(
            "--against compares the variant sets' rows, which --report-sections leaves out",
        );
    }
    Ok(sections)
}

pub(crate) fn bench(o: &BenchArgs) -> Result<(), Error> {
    let auto_exposure = o.frame.auto_exposure()?;
    let bloom_intensity = o.frame.bloom_intensity(super::render::pass_asked(
        &o.shading.optional.passes,
        "bloom",
    ))?;
    if let Some(dir) = &o.report {
        return bench_report(o, dir);
    }
    let (device, mut settings) = device_and_settings(&o.device, &o.frame, o.frames_in_flight)?;
    preflight(&device, &o.frame)?;
    let scene = combustion::with_localised_lights(
        &lit_as_asked(&o.scene.source(), CameraChoice::Scene, &o.shading)?,
        o.extra_lights,
    );
    settings.shading = o.shading.options(settings.shading);
    settings.shading.specialised = o.specialised;
    settings.fold_output = o.fold_output;
    let mut headless = Headless::new(&HeadlessDesc { device, settings })?;
    let device_name = {
        let renderer = headless.renderer();
        renderer.device().info().name.clone()
    };
    let renderer = headless.renderer();
    let frames_in_flight = renderer.settings().frames_in_flight;
    let settings_exposure = renderer.settings().exposure;
    renderer.set_light_culling(o.culling);
    let gpu_scene = renderer.upload(&scene)?;
    let features = renderer.lighting_features(&gpu_scene);
    let still = combustion::renderer::FrameInputs {
        anti_aliasing: o.anti_aliasing,
        auto_exposure,
        bloom_intensity,
        ..combustion::renderer::FrameInputs::of_scene(&gpu_scene, settings_exposure)
    };
    // One warm-up frame (first-touch allocations, driver caches) is not counted.
    renderer.render_with(
        &gpu_scene,
        &still,
        o.frame.width,
        o.frame.height,
        Readback::default(),
    )?;
    renderer.take_completed_timings();
    // Frames in flight: each submission waits only for the frame that used its slot,
    // so CPU recording overlaps GPU work; the wall clock is taken between submissions.
    let mut wall_ms = Vec::with_capacity(o.frames as usize);
    // A playing animation: each frame's pose sampled and placed on the CPU (in the wall
    // time), morphed and skinned on the GPU (the deform pass).
    let playing = (o.animation.animation.is_some() || o.animation.time.is_some())
        .then(|| combustion::animation::choose_animation(&scene, o.animation.animation.as_deref()))
        .transpose()?;
    let start = Instant::now();
    let mut last = start;
    for i in 0..o.frames {
        match playing {
            Some(animation) => {
                let duration = scene.motion.animations[animation].duration();
                let mut time = o.animation.time.unwrap_or(0.0) + i as f32 / 30.0;
                if duration > 0.0 {
                    time %= duration;
                }
                let pose = combustion::animation::sampled_pose(&scene, animation, time)?;
                let inputs = combustion::renderer::FrameInputs {
                    pose: Some(&pose),
                    ..still
                };
                renderer.submit_offscreen_with(
                    &gpu_scene,
                    &inputs,
                    o.frame.width,
                    o.frame.height,
                )?;
            }
            None => {
                renderer.submit_offscreen_with(&gpu_scene, &still, o.frame.width, o.frame.height)?
            }
        }
        let now = Instant::now();
        wall_ms.push((now - last).as_secs_f64() * 1e3);
        last = now;
    }
    renderer.finish_offscreen()?;
    let elapsed = start.elapsed().as_secs_f64();
    let timings = renderer.take_completed_timings();
    drop(gpu_scene);
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    // Each pass the frames ran, by name in the order they ran, then the frame's total.
    let passes = combustion::report::PassSpreads::of(&timings);
    let total = combustion::report::Spread::of(timings.iter().map(|t| t.total_ms).collect());
    outln!(
        "scene {} at {}x{} on {device_name}, n={} frames ({} timed), {frames_in_flight} in flight (GPU timestamps, ms):",
        o.scene.source().label(),
        o.frame.width,
        o.frame.height,
        o.frames,
        timings.len()
    );
    outln!(
        "lighting pipeline: {}",
        if features == combustion::renderer::LightingFeatures::ALL {
            "general (every feature)".to_owned()
        } else {
            format!("specialised to {}", features.names())
        }
    );
    let ranged = scene.lights.iter().filter(|l| l.range().is_some()).count();
    let culling = o.culling.name();
    let max_culled = combustion::renderer::MAX_CULLED_LIGHTS;
    if o.culling != combustion::renderer::LightCulling::Never && scene.lights.len() > max_culled {
        log::warn!(
            "{} lights: more than the {max_culled} a frame can cull into tile lists, so --culling {culling} does not cull; every pixel loops over every light",
            scene.lights.len(),
        );
    }
    outln!(
        "lights: {} ({ranged} with a range); light culling: {culling} ({})",
        scene.lights.len(),
        if o.culling.culls(&scene.lights) {
            "culled into tile lists"
        } else {
            "every pixel loops over every light"
        }
    );
    if let Some(animation) = playing {
        let a = &scene.motion.animations[animation];
        outln!(
            "animation {animation}{} playing ({:.2} s long, 1/30 s per frame)",
            a.name
                .as_deref()
                .map_or(String::new(), |n| format!(" `{n}`")),
            a.duration()
        );
    }
    let ran_output = timings
        .iter()
        .any(|t| t.ms(combustion::renderer::PassTimings::OUTPUT).is_some());
    if !timings.is_empty() && !ran_output {
        outln!("output: folded into the lighting pass (--fold-output off times the two apart)");
    }
    outln!("{:<10} {:>9} {:>9} {:>9}", "pass", "median", "p10", "p90");
    let wall = combustion::report::Spread::of(wall_ms);
    let mut rows: Vec<(&str, combustion::report::Spread)> = Vec::new();
    if !timings.is_empty() {
        rows.extend(passes.0.iter().copied());
        rows.push(("total", total));
    }
    rows.push(("wall", wall));
    for (name, spread) in rows {
        outln!(
            "{:<10} {:>9.2} {:>9.2} {:>9.2}",
            name,
            spread.median,
            spread.p10,
            spread.p90
        );
    }
    outln!(
        "wall clock: {:.2} ms per frame ({:.1} frames/s) over {} frames; GPU total median {:.2} ms",
        elapsed * 1e3 / f64::from(o.frames),
        f64::from(o.frames) / elapsed,
        o.frames,
        total.median
    );
    Ok(())
}
