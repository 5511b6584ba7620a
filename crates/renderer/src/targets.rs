//! The renderer's own images at one size: the G-buffer and the HDR (lit) image. Kept
//! per (size, variant) so that viewports of different sizes rendered in alternation do
//! not rebuild anything per frame; a size unused for a while is retired.

use std::sync::Arc;

use combustion_vk::{vk, Device, Image, ImageDesc};

use crate::error::RenderError;
use crate::gbuffer::{GBufferTargets, DEPTH_FORMAT};
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
    /// Whether there are the far sides of transmissive volumes (depth and normals).
    pub back_faces: bool,
    /// Whether the G-buffer has the clear coat's target.
    pub clearcoat: bool,
    /// Whether the G-buffer has the sheen's target.
    pub sheen: bool,
    /// Whether the G-buffer has the thin film's target.
    pub film: bool,
    /// Whether the G-buffer has the specular target.
    pub specular: bool,
}

impl TargetKey {
    /// The targets a frame of `extent` in `variant` draws into.
    pub fn of(extent: vk::Extent2D, variant: crate::variant::ShaderVariant) -> Self {
        Self {
            width: extent.width,
            height: extent.height,
            emissive_occlusion: variant.has_emissive_occlusion_target(),
            behind: variant.transmission,
            back_faces: variant.volume,
            clearcoat: variant.clearcoat,
            sheen: variant.sheen,
            film: variant.iridescence,
            specular: variant.specular,
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
    /// The far sides of the transmissive objects with a volume, in variants with one
    /// (the back faces pass draws them; forward.frag's refracted rays leave there).
    pub back_faces: Option<BackFaceTargets>,
}

/// The nearest back face of the transmissive volumes at each pixel: where a ray
/// refracted into such an object leaves it.
pub(crate) struct BackFaceTargets {
    /// Its depth ([`DEPTH_FORMAT`], 1 where there is none).
    pub depth: Image,
    /// Its world-space normal, as the mesh gives it (facing out of the object), in rgb.
    pub normal: Image,
}

/// The format of [`BackFaceTargets::normal`].
pub(crate) const BACK_FACE_NORMAL_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

impl BackFaceTargets {
    fn new(device: &Arc<Device>, width: u32, height: u32) -> Result<Self, RenderError> {
        let image = |name, format, usage: vk::ImageUsageFlags| {
            Image::new(
                device,
                &ImageDesc::new(
                    name,
                    format,
                    width,
                    height,
                    usage | vk::ImageUsageFlags::SAMPLED,
                ),
            )
        };
        Ok(Self {
            depth: image(
                "transmissive volumes' back face depth",
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            )?,
            normal: image(
                "transmissive volumes' back face normal",
                BACK_FACE_NORMAL_FORMAT,
                vk::ImageUsageFlags::COLOR_ATTACHMENT,
            )?,
        })
    }
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
                [key.clearcoat, key.sheen, key.film, key.specular],
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
            back_faces: if key.back_faces {
                Some(BackFaceTargets::new(device, key.width, key.height)?)
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
        if let Some(back_faces) = &self.back_faces {
            all.push((&back_faces.depth).into());
            all.push((&back_faces.normal).into());
        }
        all
    }
}
