//! The renderer's own images at one size: the G-buffer and the HDR (lit) image. Kept
//! per (size, variant) so that viewports of different sizes rendered in alternation do
//! not rebuild anything per frame; a size unused for a while is retired.

use std::sync::Arc;

use combustion_vk::{vk, Device, Image, ImageDesc};

use crate::error::RenderError;
use crate::gbuffer::GBufferTargets;
use crate::graph::TrackedImage;
use crate::options::{GBufferStorage, HdrFormat};

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
        storage: GBufferStorage,
    ) -> Result<Self, RenderError> {
        Ok(Self {
            gbuffer: GBufferTargets::new(
                device,
                key.width,
                key.height,
                storage,
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
