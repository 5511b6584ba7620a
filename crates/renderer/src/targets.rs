//! The renderer's own images at one size: the G-buffer and the HDR (lit) image. Kept
//! per (size, variant) so that viewports of different sizes rendered in alternation do
//! not rebuild anything per frame; a size unused for a while is retired.

use std::sync::Arc;

use combustion_vk::{vk, Device, Image, ImageDesc, OneShot};

use crate::gbuffer::GBufferTargets;
use crate::graph::TrackedImage;
use crate::{HdrFormat, RenderError};

/// Identifies one set of targets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct TargetKey {
    pub width: u32,
    pub height: u32,
    /// Whether the G-buffer has the emissive + occlusion target.
    pub emissive_occlusion: bool,
}

/// The images of one frame size.
pub(crate) struct FrameTargets {
    pub gbuffer: GBufferTargets,
    pub hdr: Image,
}

impl FrameTargets {
    pub fn new(
        device: &Arc<Device>,
        key: TargetKey,
        hdr_format: HdrFormat,
    ) -> Result<Self, RenderError> {
        Ok(Self {
            gbuffer: GBufferTargets::new(
                device,
                key.width,
                key.height,
                key.emissive_occlusion,
                hdr_format.vk(),
            )?,
            hdr: Image::new(
                device,
                &ImageDesc::new(
                    "hdr radiance",
                    hdr_format.vk(),
                    key.width,
                    key.height,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::SAMPLED
                        | vk::ImageUsageFlags::TRANSFER_SRC,
                ),
            )?,
        })
    }

    /// Every image, for forgetting their tracked states when the targets are retired.
    pub fn images(&self) -> Vec<TrackedImage> {
        let mut all: Vec<TrackedImage> = self
            .gbuffer
            .attachments()
            .into_iter()
            .map(TrackedImage::from)
            .collect();
        all.push((&self.gbuffer.depth).into());
        all.push((&self.hdr).into());
        all
    }
}

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
