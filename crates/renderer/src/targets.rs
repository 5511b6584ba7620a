//! The frame's images, from one pool: each pass asks for the images it creates by name
//! and description (`passes::FramePass::images`: the G-buffer's targets, the HDR image,
//! what lies behind glass, the far sides of glass volumes), the pool makes each at the
//! frame's size the first time a frame needs it and keeps it while frames of that size
//! use it (viewports of different sizes rendered in alternation rebuild nothing), and
//! gives up an image no frame has used for a while, for the renderer to retire. A frame
//! sees its images by name ([`FrameImages`]).

use std::collections::HashMap;
use std::sync::Arc;

use combustion_vk::{vk, Device, Image, ImageDesc};

use crate::error::RenderError;

/// An image a pass creates for the frame: its name (how passes find it, and its debug
/// name), format, usage, and whether it has a full mip chain; its size is the frame's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct ImageRequest {
    pub name: &'static str,
    pub format: vk::Format,
    pub usage: vk::ImageUsageFlags,
    pub full_mips: bool,
}

impl ImageRequest {
    /// `name`, one mip level.
    pub const fn new(name: &'static str, format: vk::Format, usage: vk::ImageUsageFlags) -> Self {
        Self {
            name,
            format,
            usage,
            full_mips: false,
        }
    }

    /// The same with every mip level down to 1×1.
    pub const fn with_full_mips(self) -> Self {
        Self {
            full_mips: true,
            ..self
        }
    }
}

/// An image of the pool: what was asked for, at which size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct PoolKey {
    request: ImageRequest,
    width: u32,
    height: u32,
}

/// Every image the frames have asked for, with the number of the frame that used it
/// last.
#[derive(Default)]
pub(crate) struct ImagePool {
    images: HashMap<PoolKey, (Image, u64)>,
}

impl ImagePool {
    /// Makes sure each of `requests` exists at `extent` and marks it used by `frame`;
    /// whether any had to be made.
    pub fn ensure(
        &mut self,
        device: &Arc<Device>,
        requests: &[ImageRequest],
        extent: vk::Extent2D,
        frame: u64,
    ) -> Result<bool, RenderError> {
        let mut made = false;
        for &request in requests {
            let key = PoolKey {
                request,
                width: extent.width,
                height: extent.height,
            };
            if let Some((_, last_used)) = self.images.get_mut(&key) {
                *last_used = frame;
                continue;
            }
            let mut desc = ImageDesc::new(
                request.name,
                request.format,
                extent.width,
                extent.height,
                request.usage,
            );
            if request.full_mips {
                desc = desc.full_mips();
            }
            self.images.insert(key, (Image::new(device, &desc)?, frame));
            made = true;
        }
        Ok(made)
    }

    /// The images of `requests` at `extent` (made by [`ImagePool::ensure`]), by name.
    pub fn frame_images(&self, requests: &[ImageRequest], extent: vk::Extent2D) -> FrameImages<'_> {
        FrameImages {
            images: requests
                .iter()
                .map(|&request| {
                    let key = PoolKey {
                        request,
                        width: extent.width,
                        height: extent.height,
                    };
                    let (image, _) = self.images.get(&key).expect("made for the frame");
                    (request.name, image)
                })
                .collect(),
        }
    }

    /// The images no frame has used since frame `frame − kept`, taken out of the pool
    /// for the caller to retire.
    pub fn take_unused(&mut self, frame: u64, kept: u64) -> Vec<Image> {
        let stale: Vec<PoolKey> = self
            .images
            .iter()
            .filter(|(_, (_, last_used))| last_used + kept < frame)
            .map(|(key, _)| *key)
            .collect();
        stale
            .into_iter()
            .filter_map(|key| self.images.remove(&key).map(|(image, _)| image))
            .collect()
    }
}

/// The images of one frame, by the names their passes asked for them with.
pub(crate) struct FrameImages<'a> {
    images: Vec<(&'static str, &'a Image)>,
}

impl<'a> FrameImages<'a> {
    /// The image named `name`, which a pass of the frame asked for (checked).
    pub fn get(&self, name: &str) -> &'a Image {
        self.find(name)
            .unwrap_or_else(|| panic!("no pass of the frame asked for the image {name}"))
    }

    /// The image named `name`, if a pass of the frame asked for it.
    pub fn find(&self, name: &str) -> Option<&'a Image> {
        self.images
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, image)| *image)
    }
}
