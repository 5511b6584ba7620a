//! `combustion view` (a window) and `combustion devices`.

use combustion::Error;

use super::write_stdout;
use super::*;

pub(crate) fn view(o: &ViewArgs) -> Result<(), Error> {
    if let Some(shot) = &o.screenshot {
        combustion::output::check_extension(shot, "--screenshot", "PNG", &["png"])?;
        // The output rule of `render -o`, before the window opens or the scene loads.
        combustion::output::check_writable(shot)?;
    }
    combustion::viewer::check_window_size(o.frame.width, o.frame.height)?;
    let auto_exposure = o.frame.auto_exposure()?;
    let mut metering = auto_exposure.unwrap_or_default();
    if let Some([rise, fall]) = o.adaptation_speed {
        if auto_exposure.is_none() {
            return Err(Error::Usage(
                "--adaptation-speed needs --auto-exposure on (it sets how fast the metered exposure follows)".into(),
            ));
        }
        metering.rise_per_second = rise;
        metering.fall_per_second = fall;
    }
    let bloom_intensity = o.frame.bloom_intensity(o.bloom)?;
    let (device, mut settings) = device_and_settings(&o.device, &o.frame, o.frames_in_flight)?;
    for (name, on) in [
        ("bloom", o.bloom),
        ("temporal-anti-aliasing", o.temporal_anti_aliasing),
        ("path-trace", o.path_trace),
    ] {
        if let Some(pass) = combustion::renderer::optional_pass(name) {
            settings.shading.optional_passes = settings.shading.optional_passes.with(pass, on);
        }
    }
    preflight(&device, &o.frame)?;
    let environment = o
        .environment
        .as_ref()
        .map(EnvironmentChoice::load)
        .transpose()?;
    let summary = combustion::viewer::run(&combustion::viewer::ViewerDesc {
        scene: o.scene.source(),
        width: o.frame.width,
        height: o.frame.height,
        frames: o.frames,
        device,
        settings,
        vsync: o.vsync,
        screenshot: o.screenshot.clone(),
        camera_path: o.camera_path.clone(),
        overlay: o.overlay,
        error_view: o.error_view,
        background: o.picture.background,
        tone_mapping: o.picture.tone_mapping,
        anti_aliasing: o.picture.anti_aliasing_for(1),
        auto_exposure: (auto_exposure.is_some(), metering),
        bloom_intensity,
        environment,
    })?;
    // A run too short to have read back a frame's timings (--frames 1) says so.
    let median = |list: &[f64]| {
        if list.is_empty() {
            "not measured".to_owned()
        } else {
            format!(
                "{:.2} ms",
                combustion::report::Spread::of(list.to_vec()).median
            )
        }
    };
    outln!(
        "viewed {} frame{} at {}x{} on {}: GPU total median {}, wall clock per frame median {} ({} in flight, on-device presentation){}",
        summary.presented,
        if summary.presented == 1 { "" } else { "s" },
        summary.width,
        summary.height,
        summary.device_name,
        median(&summary.gpu_total_ms),
        median(&summary.frame_ms),
        settings.frames_in_flight,
        summary
            .screenshots
            .iter()
            .map(|p| format!("; screenshot {}", p.display()))
            .collect::<String>()
    );
    Ok(())
}

pub(crate) fn devices() -> Result<(), Error> {
    let devices = combustion::vk::Device::enumerate()?;
    if devices.is_empty() {
        return Err(Error::Vulkan(combustion::vk::VkError::NoDevice));
    }
    for d in devices {
        outln!(
            "{}: {} ({}, Vulkan {}.{}.{}, {}){}",
            d.index,
            d.name,
            d.kind(),
            d.api_version.0,
            d.api_version.1,
            d.api_version.2,
            d.driver,
            d.unsuitable_because
                .map(|why| format!(" — unusable: {why}"))
                .unwrap_or_default()
        );
    }
    Ok(())
}
