//! Placeholder images: what a descriptor set binds where a real image is absent, left
//! once in the layout shaders sample in.

use std::sync::Arc;

use combustion_vk::{vk, Device, Image, ImageDesc, OneShot};

use crate::error::RenderError;

/// Leaves `images` (new, never written) in the layout fragment shaders sample in, once,
/// waiting for the transition: placeholders a set binds where a real image is absent
/// (every binding of a set is written, since a driver may read a bound set's descriptors
/// whether the pipeline uses them or not). Never called inside a frame.
pub(crate) fn make_sampled_placeholders(
    device: &Arc<Device>,
    images: &[&Image],
) -> Result<(), RenderError> {
    let mut commands = OneShot::new(device)?;
    let cmd = commands.begin()?;
    let barriers: Vec<_> = images
        .iter()
        .map(|image| {
            combustion_vk::image_barrier(
                image.raw(),
                image.subresource_range(),
                combustion_vk::ImageState::UNDEFINED,
                combustion_vk::ImageState::FRAGMENT_SAMPLED,
            )
        })
        .collect();
    // SAFETY: recording state; the images live until the wait below.
    unsafe {
        device.raw().cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&barriers),
        )
    };
    commands.submit_and_wait()?;
    Ok(())
}

/// A 1×1 image of `format` standing in for an absent G-buffer target in the lighting
/// set (e.g. the emissive + occlusion target of variants without it).
pub(crate) fn absent_target_placeholder(
    device: &Arc<Device>,
    format: vk::Format,
) -> Result<Image, RenderError> {
    let image = Image::new(
        device,
        &ImageDesc::new(
            "absent target placeholder",
            format,
            1,
            1,
            vk::ImageUsageFlags::SAMPLED,
        ),
    )?;
    make_sampled_placeholders(device, &[&image])?;
    Ok(image)
}
