//! What a host gives [`crate::Renderer::record`]: the image to render into (and
//! optionally its depth image), with the synchronisation contract of each, and the
//! frame's own camera, exposure and lights.

use combustion_scene::{Camera, Light};
use combustion_vk::{vk, ImageState};

use crate::{GpuScene, OverlayPanel};

/// The format of the renderer's own display image ([`crate::Renderer::render`]), whose
/// output pass is prepared at construction.
pub const DISPLAY_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// How the output pass writes a target format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputEncoding {
    /// Float formats (RGBA16F, RGBA32F): linear radiance × exposure, no tone curve, for
    /// the host's own post-processing.
    Linear,
    /// UNORM formats (RGBA8, BGRA8): tone curve, then the exact sRGB encoding in the
    /// shader (the bytes are sRGB-encoded).
    ShaderSrgb,
    /// _SRGB formats (RGBA8, BGRA8): tone curve; the driver encodes on write (on
    /// lavapipe its conversion is ≈ 0.4 % off the exact formula).
    HardwareSrgb,
}

impl OutputEncoding {
    /// The encoding for a target format, or `None` if the format is not supported.
    pub fn of(format: vk::Format) -> Option<Self> {
        use vk::Format as F;
        match format {
            F::R16G16B16A16_SFLOAT | F::R32G32B32A32_SFLOAT => Some(Self::Linear),
            F::R8G8B8A8_UNORM | F::B8G8R8A8_UNORM => Some(Self::ShaderSrgb),
            F::R8G8B8A8_SRGB | F::B8G8R8A8_SRGB => Some(Self::HardwareSrgb),
            _ => None,
        }
    }

    pub(crate) fn defines(self) -> Vec<(&'static str, Option<&'static str>)> {
        match self {
            Self::Linear => vec![("OUTPUT_LINEAR", None)],
            Self::ShaderSrgb => vec![],
            Self::HardwareSrgb => vec![("OUTPUT_HARDWARE_SRGB", None)],
        }
    }
}

/// The colour image a frame is rendered into: a 2D image (one mip level, one layer) with
/// `COLOR_ATTACHMENT` usage, of a format [`OutputEncoding::of`] accepts and prepared with
/// [`crate::Renderer::prepare_output`].
///
/// Synchronisation contract: the frame's first barrier on this image waits for
/// `before.stage`/`before.access` (the host's last use, recorded earlier in the same
/// queue's submission order) and moves it from `before.layout`; every pixel is then
/// overwritten by the output pass; the frame's last barrier makes the writes available
/// to `after.stage`/`after.access` and leaves the image in `after.layout`.
#[derive(Clone, Copy, Debug)]
pub struct ColorTarget {
    pub image: vk::Image,
    /// A 2D colour view of mip level 0, layer 0.
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    /// Where the host left the image. `ImageState::UNDEFINED` is right for an image
    /// whose contents the host does not need (they are overwritten anyway).
    pub before: ImageState,
    /// Where the host wants it: the layout and the stages/accesses of its next use
    /// (e.g. sampled in a fragment shader, or `PRESENT_SRC_KHR` with no access).
    pub after: ImageState,
}

/// A host's depth image that receives the frame's depth (the G-buffer's, copied), so
/// that the host can draw its own geometry afterwards, depth-tested against the scene.
/// `D32_SFLOAT`, of the colour target's extent, with `TRANSFER_DST` usage; depth 1 is the
/// far plane (nothing drawn), as the projection of [`Camera`] gives.
///
/// Synchronisation contract as for [`ColorTarget`]: waited for from `before`, written by
/// a copy, released to `after`.
#[derive(Clone, Copy, Debug)]
pub struct DepthTarget {
    pub image: vk::Image,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub before: ImageState,
    pub after: ImageState,
}

/// Where a frame goes.
#[derive(Clone, Copy, Debug)]
pub struct FrameTarget {
    pub color: ColorTarget,
    pub depth: Option<DepthTarget>,
}

/// What changes from frame to frame without touching the uploaded scene: the camera,
/// the exposure, the lights, and the text drawn over the frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameInputs<'a> {
    pub camera: Camera,
    /// Multiplies radiance before the tone curve (and in linear outputs).
    pub exposure: f32,
    /// This frame's lights (any number; validated like a scene's).
    pub lights: &'a [Light],
    /// Text panels drawn over the frame by the output pass (none: nothing drawn).
    pub overlay: &'a [OverlayPanel<'a>],
}

impl<'a> FrameInputs<'a> {
    /// The scene's own camera and lights, with `exposure`.
    pub fn of_scene(scene: &'a GpuScene, exposure: f32) -> Self {
        Self {
            camera: scene.scene.camera,
            exposure,
            lights: &scene.scene.lights,
            overlay: &[],
        }
    }
}
