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
    /// Whether there is the image of what lies behind transmissive objects.
    pub behind: bool,
}

impl TargetKey {
    /// The targets a frame of `extent` in `variant` draws into.
    pub fn of(extent: vk::Extent2D, variant: crate::variant::ShaderVariant) -> Self {
        Self {
            width: extent.width,
            height: extent.height,
            emissive_occlusion: variant.has_emissive_occlusion_target(),
            behind: variant.transmission,
        }
    }
}

/// The images of one frame size.
pub(crate) struct FrameTargets {
    pub gbuffer: GBufferTargets,
    pub hdr: Image,
    /// What lies behind the transmissive objects: the lit HDR image before the forward
    /// pass, with every mip level (rough transmission reads coarser levels), in variants
    /// with transmission (the behind pass makes it).
    pub behind: Option<Image>,
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
            behind: if key.behind {
                Some(Image::new(
                    device,
                    &ImageDesc::new(
                        "hdr radiance behind transmissive objects",
                        hdr_format.vk(),
                        key.width,
                        key.height,
                        vk::ImageUsageFlags::SAMPLED
                            | vk::ImageUsageFlags::TRANSFER_SRC
                            | vk::ImageUsageFlags::TRANSFER_DST,
                    )
                    .full_mips(),
                )?)
            } else {
                None
            },
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
        all.extend(self.behind.as_ref().map(TrackedImage::from));
        all
    }
}
