//! What a host gives [`crate::Renderer::record`]: the image to render into (and
//! optionally its depth image), with the synchronisation contract of each, and the
//! frame's own camera, exposure and lights.

use combustion_scene::{Camera, Light};
use combustion_vk::{vk, ImageState};

use crate::error::RenderError;
use crate::error::TargetImageProblem;
use crate::overlay::OverlayPanel;
use crate::scene_upload::GpuScene;

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

/// The colour image a frame is rendered into: a 2D image (one sample; the frame writes
/// mip level 0, layer 0) with `COLOR_ATTACHMENT` usage, of a format
/// [`OutputEncoding::of`] accepts and prepared with [`crate::Renderer::prepare_output`].
/// The frame covers the whole image.
///
/// `format`, `extent` and `usage` are the image's as it was created: take them from the
/// create info it was created with ([`ColorTarget::from_create_info`],
/// [`ColorTarget::from_swapchain`]) rather than typing them again. Vulkan cannot be
/// asked an image's size, so that these are the image's, and that `view` is a 2D view
/// of its mip level 0 and layer 0, remain the host's promise; everything else is
/// checked ([`crate::Renderer::record`]).
///
/// Synchronisation contract: the frame's first barrier on this image waits for
/// `before.stage`/`before.access` (the host's last use, recorded earlier in the same
/// queue's submission order) and moves it from `before.layout`; every pixel is then
/// overwritten by the output pass; the frame's last barrier makes the writes available
/// to `after.stage`/`after.access` and leaves the image in `after.layout`.
#[derive(Clone, Copy, Debug)]
pub struct ColorTarget {
    /// The image (owned by the host, which keeps it alive until the frames recorded into it
    /// have completed).
    pub image: vk::Image,
    /// A 2D colour view of mip level 0, layer 0.
    pub view: vk::ImageView,
    /// The image's format.
    pub format: vk::Format,
    /// The image's extent (width and height it was created with).
    pub extent: vk::Extent2D,
    /// The image's usage flags (must include `COLOR_ATTACHMENT`).
    pub usage: vk::ImageUsageFlags,
    /// Where the host left the image. `ImageState::UNDEFINED` is right for an image
    /// whose contents the host does not need (they are overwritten anyway).
    pub before: ImageState,
    /// Where the host wants it: the layout and the stages/accesses of its next use
    /// (e.g. sampled in a fragment shader, or `PRESENT_SRC_KHR` with no access).
    pub after: ImageState,
}

impl ColorTarget {
    /// The target for `image`, created with `info`, seen through `view`. Refuses
    /// images a frame cannot be rendered into (not 2D, multisampled, without a mip level
    /// or layer: [`RenderError::InvalidTargetImage`]); the usage is checked by
    /// [`crate::Renderer::record`] (`COLOR_ATTACHMENT`).
    pub fn from_create_info(
        image: vk::Image,
        view: vk::ImageView,
        info: &vk::ImageCreateInfo<'_>,
        before: ImageState,
        after: ImageState,
    ) -> Result<Self, RenderError> {
        check_created("colour", info)?;
        Ok(Self {
            image,
            view,
            format: info.format,
            extent: extent_2d(info.extent),
            usage: info.usage,
            before,
            after,
        })
    }

    /// The target for a swapchain image of the swapchain created with `info`.
    pub fn from_swapchain(
        image: vk::Image,
        view: vk::ImageView,
        info: &vk::SwapchainCreateInfoKHR<'_>,
        before: ImageState,
        after: ImageState,
    ) -> Self {
        Self {
            image,
            view,
            format: info.image_format,
            extent: info.image_extent,
            usage: info.image_usage,
            before,
            after,
        }
    }
}

/// A host's depth image that receives the frame's depth (the G-buffer's, copied), so
/// that the host can draw its own geometry afterwards, depth-tested against the scene.
/// `D32_SFLOAT`, of the colour target's extent, with `TRANSFER_DST` usage; depth 1 is the
/// far plane (nothing drawn), as the projection of [`Camera`] gives. `format`, `extent`
/// and `usage` are the image's as created, as for [`ColorTarget`]
/// ([`DepthTarget::from_create_info`]).
///
/// Synchronisation contract as for [`ColorTarget`]: waited for from `before`, written by
/// a copy, released to `after`.
#[derive(Clone, Copy, Debug)]
pub struct DepthTarget {
    /// The image (owned by the host, which keeps it alive until the frames recorded into it
    /// have completed).
    pub image: vk::Image,
    /// The image's format (must be `D32_SFLOAT`).
    pub format: vk::Format,
    /// The image's extent (must equal the colour target's).
    pub extent: vk::Extent2D,
    /// The image's usage flags (must include `TRANSFER_DST`).
    pub usage: vk::ImageUsageFlags,
    /// Where the host left the image (`ImageState::UNDEFINED` if its contents do not matter:
    /// they are overwritten).
    pub before: ImageState,
    /// Where the host wants it: the layout and the stages/accesses of its next use (not
    /// `UNDEFINED` or `PREINITIALIZED`).
    pub after: ImageState,
}

impl DepthTarget {
    /// The depth target for `image`, created with `info` (not 2D, multisampled, or without
    /// a mip level or layer: refused with [`RenderError::InvalidTargetImage`]); the
    /// format, extent and usage are checked by [`crate::Renderer::record`].
    pub fn from_create_info(
        image: vk::Image,
        info: &vk::ImageCreateInfo<'_>,
        before: ImageState,
        after: ImageState,
    ) -> Result<Self, RenderError> {
        check_created("depth", info)?;
        Ok(Self {
            image,
            format: info.format,
            extent: extent_2d(info.extent),
            usage: info.usage,
            before,
            after,
        })
    }
}

fn extent_2d(extent: vk::Extent3D) -> vk::Extent2D {
    vk::Extent2D {
        width: extent.width,
        height: extent.height,
    }
}

/// Refuses create infos of images a frame cannot use as its `target`.
fn check_created(target: &'static str, info: &vk::ImageCreateInfo<'_>) -> Result<(), RenderError> {
    let problem = if info.image_type != vk::ImageType::TYPE_2D || info.extent.depth != 1 {
        Some(TargetImageProblem::NotTwoDimensional(info.image_type))
    } else if info.samples != vk::SampleCountFlags::TYPE_1 {
        Some(TargetImageProblem::Multisampled(info.samples))
    } else if info.mip_levels == 0 || info.array_layers == 0 {
        Some(TargetImageProblem::Empty)
    } else {
        None
    };
    match problem {
        Some(problem) => Err(RenderError::InvalidTargetImage { target, problem }),
        None => Ok(()),
    }
}

/// Where a frame goes.
#[derive(Clone, Copy, Debug)]
pub struct FrameTarget {
    /// The colour image the frame's output pass writes.
    pub color: ColorTarget,
    /// A host depth image to receive the frame's depth (`None`: no depth copy).
    pub depth: Option<DepthTarget>,
}

/// What changes from frame to frame without touching the uploaded scene: the camera,
/// the exposure, the lights, and the text drawn over the frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameInputs<'a> {
    /// The tone curve of display outputs (UNORM and _SRGB targets; linear targets get
    /// radiance × exposure).
    pub tone_mapping: ToneMapping,
    /// What the frame shows where no surface is (the tone curve and exposure apply to it
    /// as to any radiance).
    pub background: Background,
    /// The camera the frame is seen from (validated by [`crate::Renderer::record`]).
    pub camera: Camera,
    /// Multiplies radiance before the tone curve (and in linear outputs), unless
    /// `auto_exposure` meters the frame's own (a physical camera's:
    /// [`crate::PhysicalCamera::exposure`]).
    pub exposure: f32,
    /// Exposure metered from the frame's HDR image, in place of `exposure` (None: the
    /// exposure given). Frames that meter need [`crate::Renderer::prepare_auto_exposure`]
    /// first.
    pub auto_exposure: Option<crate::AutoExposure>,
    /// The fraction of the frame's radiance bloom spreads into its glow (0 to 1), in
    /// frames whose shading runs bloom (`--bloom on`); 0.05 in
    /// [`FrameInputs::of_scene`].
    pub bloom_intensity: f32,
    /// This frame's lights (any number; validated like a scene's).
    pub lights: &'a [Light],
    /// Text panels drawn over the frame by the output pass (none: nothing drawn).
    pub overlay: &'a [OverlayPanel<'a>],
    /// The environment lighting this frame in place of the scene's own (None: the
    /// scene's, if it has one), baked for the scene's materials by
    /// [`crate::Renderer::bake_environment`].
    pub environment: Option<&'a crate::environment::FrameEnvironment>,
    /// Where the scene's objects are this frame (each object's transform and morph
    /// weights, each skin's joint matrices: [`combustion_scene::Scene::pose_objects`]
    /// makes them from an animation's pose), or `None` for the scene as uploaded.
    /// Checked against the scene by [`crate::Renderer::record`].
    pub pose: Option<&'a combustion_scene::ObjectPoses>,
    /// Which sample set the sampled environment takes this frame
    /// ([`crate::ShadingOptions::environment_samples`]; 0 the first, and the only one
    /// a frame of the split sum reads nothing of): frames of different seeds are
    /// independent estimates, whose mean is the integral with that many times the
    /// samples (a still render accumulates them; a host may vary it per frame).
    pub environment_seed: u32,
    /// Anti-aliasing of display outputs by the output pass (linear targets get none:
    /// a host's own post-processing takes their radiance). For still renders,
    /// [`crate::Renderer::render_supersampled`] resolves N×N samples per pixel exactly.
    pub anti_aliasing: AntiAliasing,
}

impl<'a> FrameInputs<'a> {
    /// The scene's own camera and lights, with `exposure`.
    pub fn of_scene(scene: &'a GpuScene, exposure: f32) -> Self {
        Self {
            camera: scene.scene().camera,
            exposure,
            lights: &scene.scene().lights,
            overlay: &[],
            environment: None,
            background: Background::None,
            tone_mapping: ToneMapping::Exponential,
            pose: None,
            environment_seed: 0,
            anti_aliasing: AntiAliasing::None,
            auto_exposure: None,
            bloom_intensity: DEFAULT_BLOOM_INTENSITY,
        }
    }
}

/// The fraction of a frame's radiance bloom spreads by default (the viewer's; headless
/// renders run no bloom unless asked).
pub const DEFAULT_BLOOM_INTENSITY: f32 = 0.05;

/// How the output pass smooths the edges of a frame (per frame,
/// [`FrameInputs::anti_aliasing`]); its error against a 4×4-supersampled frame and its
/// cost are in the speed-against-error report.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum AntiAliasing {
    /// Each pixel shows its centre's radiance.
    #[default]
    None = 0,
    /// FXAA (Lottes 2009, the structure of its 3.11 quality preset; `shaders/include/
    /// fxaa.glsl`): where the display luma's local contrast is high, the pixel is
    /// resampled across the edge found, by how far it lies from the edge's nearer end.
    /// Interpolates radiance, then applies the tone curve.
    Fxaa = 1,
}

impl AntiAliasing {
    /// Every method, in discriminant order.
    pub const ALL: [AntiAliasing; 2] = [Self::None, Self::Fxaa];

    /// The command line's name: `none`, `fxaa`.
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Fxaa => "fxaa",
        }
    }
}

/// The tone curve that maps exposed radiance to display values (per frame,
/// [`FrameInputs::tone_mapping`]), each mirrored on the CPU for the tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum ToneMapping {
    /// 1 − e^(−x) per channel ([`crate::tonemap_exponential`]): linear near black,
    /// never clips, invertible (x = −ln(1 − y)); Combustion's own.
    #[default]
    Exponential = 0,
    /// Khronos PBR Neutral ([`crate::tonemap_pbr_neutral`]): base colours under light of
    /// 1 show as themselves (up to 0.76), brighter ones compressed and desaturated; what
    /// glTF viewers (glTF-Sample-Viewer, model-viewer) show by default.
    PbrNeutral = 1,
    /// K. Narkowicz's ACES filmic fit ([`crate::tonemap_aces`]): contrast and a toe,
    /// clips at high radiance.
    Aces = 2,
    /// AgX ([`crate::tonemap_agx`]): 16.5 stops of range, bright colours desaturated
    /// towards white.
    Agx = 3,
}

impl ToneMapping {
    /// Every curve, in discriminant order.
    pub const ALL: [ToneMapping; 4] = [Self::Exponential, Self::PbrNeutral, Self::Aces, Self::Agx];

    /// The command line's name: `exponential`, `pbr-neutral`, `aces`, `agx`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Exponential => "exponential",
            Self::PbrNeutral => "pbr-neutral",
            Self::Aces => "aces",
            Self::Agx => "agx",
        }
    }

    /// The 8-bit sRGB codes the output pass writes for exposed radiance `rgb` (the CPU
    /// mirror: [`ToneMapping::display`], the exact sRGB encoding, rounded).
    pub fn display_codes(self, rgb: [f64; 3]) -> [u8; 3] {
        self.display(rgb)
            .map(|d| (crate::linear_to_srgb(d).clamp(0.0, 1.0) * 255.0).round() as u8)
    }

    /// The display value (before sRGB encoding) of exposed radiance `rgb`, in f64: the
    /// CPU mirror of the output pass.
    pub fn display(self, rgb: [f64; 3]) -> [f64; 3] {
        match self {
            Self::Exponential => rgb.map(crate::tonemap_exponential),
            Self::PbrNeutral => crate::tonemap_pbr_neutral(rgb),
            Self::Aces => rgb.map(crate::tonemap_aces),
            Self::Agx => crate::tonemap_agx(rgb),
        }
    }
}

/// What a frame shows behind the scene, where no surface is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Background {
    /// Nothing: zero radiance (black).
    #[default]
    None,
    /// A uniform radiance, W·sr⁻¹·m⁻² per linear RGB channel (finite, 0 to
    /// [`combustion_scene::MAX_RADIANCE`]).
    Color([f32; 3]),
    /// The environment that lights the frame (its own or the scene's), as the camera
    /// would see it: its radiance cube's finest level (128² per face) along each pixel's
    /// ray. Black in a frame without an environment.
    Environment,
}

impl Background {
    /// `asked`, else the environment where `scene` has one, else none: what a viewer
    /// shows by default (the command line's `render` and `view`).
    pub fn asked_or_default(asked: Option<Background>, scene: &combustion_scene::Scene) -> Self {
        asked.unwrap_or(if scene.environment.is_some() {
            Background::Environment
        } else {
            Background::None
        })
    }

    /// Checks a colour's radiance: finite, at least 0 and at most
    /// [`combustion_scene::MAX_RADIANCE`].
    pub fn validate(&self) -> Result<(), RenderError> {
        if let Background::Color(rgb) = self {
            if !rgb
                .iter()
                .all(|c| c.is_finite() && (0.0..=combustion_scene::MAX_RADIANCE).contains(c))
            {
                return Err(RenderError::InvalidBackground(*rgb));
            }
        }
        Ok(())
    }
}
