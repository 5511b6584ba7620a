//! Why rendering failed: [`RenderError`], and what is wrong with a host's target image
//! ([`TargetImageProblem`]).

use combustion_scene::SceneError;
use combustion_vk::{vk, VkError};

use crate::options::MAX_FRAMES_IN_FLIGHT;
use crate::scene_edit::EditError;
#[cfg(doc)]
use crate::{FrameEnvironment, GpuScene, OutputEncoding, Renderer, RendererSettings};

/// Why rendering failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A Vulkan call failed: out of device or host memory, a lost device, a shader that does
    /// not compile, or a pipeline that cannot be built.
    #[error(transparent)]
    Vulkan(#[from] VkError),
    /// The scene, or a frame's camera or lights, failed validation.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A frame or overlay image size with a side of 0 or larger than the device's
    /// maximum 2D image dimension.
    #[error("image size {width}x{height} is not allowed: each side must be between 1 and {max} on this device")]
    InvalidSize {
        /// The width asked for, in pixels.
        width: u32,
        /// The height asked for, in pixels.
        height: u32,
        /// The device's largest side (`maxImageDimension2D`).
        max: u32,
    },
    /// A supersampling factor outside 1 to [`crate::MAX_SUPERSAMPLE`].
    #[error("supersampling {0}x{0} is not supported; use 1 to {max} samples per side", max = crate::MAX_SUPERSAMPLE)]
    InvalidSupersample(u32),
    /// [`crate::ShadowSettings`] outside their ranges (the message names the field).
    #[error("shadow settings refused: {0}")]
    InvalidShadowSettings(String),
    /// A frame's pose does not fit its scene (counts, or values not finite); the
    /// message names what.
    #[error("invalid pose: {0}")]
    InvalidPose(String),
    /// An exposure (in the settings or a frame's inputs) that is not finite and positive.
    #[error("exposure {0} must be a positive finite number")]
    InvalidExposure(f32),
    /// A physical camera's or auto exposure's setting out of its range (the message
    /// names it).
    #[error("{0}")]
    InvalidExposureSettings(String),
    /// A bloom intensity that is not a number from 0 to 1.
    #[error("bloom intensity {} must be a number from 0 to 1", combustion_optics::readable(*.0))]
    InvalidBloomIntensity(f32),
    /// A frame meters its exposure before [`Renderer::prepare_auto_exposure`] was called.
    #[error("auto exposure was not prepared; call Renderer::prepare_auto_exposure before recording frames that meter their exposure")]
    AutoExposureNotPrepared,
    /// A background colour whose radiance is not finite, negative or above
    /// [`combustion_scene::MAX_RADIANCE`].
    #[error("background colour {0:?} must be finite radiances between 0 and 1e30")]
    InvalidBackground([f32; 3]),
    /// Something of the scene exceeds a device or format limit (an image larger than the
    /// device's maximum 2D image size, a mesh of 2³² indices or more); the message names
    /// it.
    #[error("scene too large: {0}")]
    TooLarge(String),
    /// [`crate::ShadingOptions::environment_samples`] is not one of
    /// [`crate::ENVIRONMENT_SAMPLE_COUNTS`].
    #[error("{0} environment samples per pixel are not supported; use 0 (the split sum) or a power of two from 1 to 1024")]
    InvalidEnvironmentSamples(u32),
    /// [`crate::ShadingOptions::path_depth`] is outside [`crate::PATH_DEPTHS`].
    #[error("a path depth of {0} is not supported; use 1 to 64")]
    InvalidPathDepth(u32),
    /// [`RendererSettings::frames_in_flight`] is outside 1 to [`MAX_FRAMES_IN_FLIGHT`].
    #[error("{0} frames in flight are not supported; use 1 to {max}", max = MAX_FRAMES_IN_FLIGHT)]
    InvalidFramesInFlight(usize),
    /// A frame slot at or past [`RendererSettings::frames_in_flight`].
    #[error(
        "frame slot {slot} is out of range: the renderer has {frames_in_flight} frames in flight"
    )]
    InvalidFrameSlot {
        /// The slot asked for.
        slot: usize,
        /// The renderer's frames in flight.
        frames_in_flight: usize,
    },
    /// The frame last recorded in the slot has not completed on the GPU (its
    /// end-of-frame marker is unwritten): the host must wait for that frame's fence, or
    /// call [`Renderer::frames_completed`] if it was never submitted.
    #[error("frame slot {slot} is still in flight: the GPU has not completed the frame last recorded with it; wait for that frame's fence before recording the slot again (or call Renderer::frames_completed if it was never submitted)")]
    FrameSlotInFlight {
        /// The slot.
        slot: usize,
    },
    /// A target format the output pass cannot write ([`OutputEncoding::of`] gives `None`).
    #[error("output format {0:?} is not supported; use an RGBA16F/RGBA32F (linear), RGBA8/BGRA8 UNORM or _SRGB (display) format")]
    UnsupportedOutputFormat(vk::Format),
    /// A supported target format whose output pass was not built: call
    /// [`Renderer::prepare_output`] first.
    #[error("output format {0:?} was not prepared; call Renderer::prepare_output before recording frames into it")]
    OutputNotPrepared(vk::Format),
    /// A frame asks for anti-aliasing whose output pipeline was not built for its
    /// target's format.
    #[error("{} anti-aliasing into {format:?} was not prepared; call Renderer::prepare_anti_aliasing before recording such frames", anti_aliasing.name())]
    AntiAliasingNotPrepared {
        /// The target's format.
        format: vk::Format,
        /// What the frame asked for.
        anti_aliasing: crate::AntiAliasing,
    },
    /// The pipelines the frame needs with the current shading options were not built:
    /// pass the scene to [`Renderer::set_shading`] when changing them, or call
    /// [`Renderer::prepare`] for it after.
    #[error("the scene's pipelines for the current shading options were not built; pass the scene to Renderer::set_shading, or call Renderer::prepare for it")]
    VariantNotPrepared,
    /// The [`GpuScene`] was uploaded by another renderer.
    #[error("the scene was uploaded by another renderer; upload it with this renderer")]
    SceneOfAnotherRenderer,
    /// The frame's [`FrameEnvironment`] was baked for other materials (another scene, or
    /// before an edit changed a material's optics) or by another renderer.
    #[error("the frame's environment was baked for other materials (another scene, or before an edit changed a material's optics) or by another renderer; bake it again for this scene with Renderer::bake_environment")]
    EnvironmentOfAnotherScene,
    /// A scene edit was refused; the scene is unchanged.
    #[error("scene edit refused: {0}")]
    Edit(#[from] EditError),
    /// A target's `after` layout is `UNDEFINED` or `PREINITIALIZED`, which an image cannot be
    /// left in; the field names the target (`colour` or `depth`).
    #[error("the {0} target's `after` layout must be a layout an image can be left in, not UNDEFINED or PREINITIALIZED")]
    InvalidAfterLayout(&'static str),
    /// The overlay cannot be drawn: an overlay image whose texel count is not
    /// `width · height` or larger than the device reads from one buffer, or an unusable font.
    #[error("overlay: {0}")]
    Overlay(String),
    /// The device cannot bake or sample environment lighting (it cannot write the cubes'
    /// format from compute shaders or filter it linearly); the message names the device.
    #[error("this device cannot render environment lighting: {0}")]
    EnvironmentUnsupported(String),
    /// A host's target image a frame cannot use.
    #[error("the {target} target image {problem}")]
    InvalidTargetImage {
        /// Which target: `colour` or `depth`.
        target: &'static str,
        /// What is wrong with it.
        problem: TargetImageProblem,
    },
    /// The host's depth image is not `D32_SFLOAT` or not of the colour target's extent.
    #[error("the host's depth image is {got:?} of {got_width}x{got_height}; it must be D32_SFLOAT of the target's size {width}x{height}")]
    InvalidDepthTarget {
        /// The depth image's format.
        got: vk::Format,
        /// The depth image's width.
        got_width: u32,
        /// The depth image's height.
        got_height: u32,
        /// The colour target's width.
        width: u32,
        /// The colour target's height.
        height: u32,
    },
}

/// What is wrong with an image a host gave as a frame's target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TargetImageProblem {
    /// The image lacks the usage flags the frame needs (`COLOR_ATTACHMENT` for the colour
    /// target, `TRANSFER_DST` for the depth target).
    #[error("was not created with {0:?} usage")]
    MissingUsage(vk::ImageUsageFlags),
    /// Not a 2D image of depth 1.
    #[error("is a {0:?} image, not a 2D one")]
    NotTwoDimensional(vk::ImageType),
    /// More than one sample per pixel.
    #[error("has {0:?} samples per pixel; frames are rendered with one")]
    Multisampled(vk::SampleCountFlags),
    /// Created with no mip level or no array layer.
    #[error("has no mip level or no array layer")]
    Empty,
    /// The `after` state's layout needs a usage the image was not created with (e.g.
    /// `SHADER_READ_ONLY_OPTIMAL` needs `SAMPLED` or `INPUT_ATTACHMENT`).
    #[error("cannot be left in {layout:?}: that layout needs {needs:?} usage (one of them), which it was not created with")]
    AfterLayoutNeedsUsage {
        /// The `after` layout asked for.
        layout: vk::ImageLayout,
        /// The usages one of which that layout needs.
        needs: vk::ImageUsageFlags,
    },
}
