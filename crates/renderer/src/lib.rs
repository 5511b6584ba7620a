//! The deferred renderer of Combustion.
//!
//! A frame ([`Renderer::record`] into a host's command buffer and image, or
//! [`Renderer::render`], which submits, waits and reads back):
//! 1. **G-buffer pass** ([`gbuffer`]): rasterise every object into base colour +
//!    metalness, normal + roughness + anisotropy, material index + anisotropy direction,
//!    and depth.
//! 2. **Lighting pass** (`lighting.frag`): full-screen; per pixel, decode the G-buffer,
//!    reconstruct the position from depth, evaluate the BRDF (`brdf.glsl`) for every
//!    light of the frame, write HDR radiance. The pipeline holds only the parts of the
//!    material model the scene uses ([`LightingFeatures`]).
//! 3. **Output pass** (`tonemap.frag`): into the frame's target, by its format: exposure
//!    and `1 − e^(−x)` with the exact sRGB encoding (UNORM), the same with the driver's
//!    encoding (_SRGB), or linear radiance × exposure (float formats); then the frame's
//!    overlay ([`overlay`]: an image and text panels) in the same rendering.
//! 4. Optional: the G-buffer depth copied into the host's depth image; readback of the
//!    HDR and display images (and the G-buffer, for parity tests) in [`Renderer::render`].
//!
//! Each pass declares the images it touches ([`graph`]); the barriers between passes
//! and frames are derived from those declarations in one place. Frames in flight: each
//! frame slot has its own descriptor sets, light buffer, timestamp queries and retire
//! list. GPU timestamps bracket each pass ([`Frame::timings`],
//! [`Renderer::last_completed_timings`]).

#![warn(missing_docs)]

pub mod bindings;
pub mod environment;
pub mod gbuffer;
pub mod gpu_types;
pub mod graph;
pub mod light_cull;
pub mod overlay;
pub mod reference;

mod frame;
mod fullscreen;
mod host;
mod mesh_draw;
mod offscreen;
mod pass_io;
mod passes;
mod retire;
mod scene_edit;
mod scene_upload;
mod shader_sources;
mod targets;
mod textures;

use std::collections::HashMap;
use std::sync::atomic::Ordering;
use std::sync::Arc;

use combustion_scene::{DiffuseModel, Scene, SceneError};
use combustion_vk::{vk, DescriptorSetLayout, Device, PipelineCache, ShaderCompiler, VkError};

pub use environment::FrameEnvironment;
use fullscreen::FullscreenPass;
use gbuffer::{GBufferPass, GBufferReadback};
use gpu_types::{LightingPush, TonemapPush};
pub use host::{
    ColorTarget, DepthTarget, FrameInputs, FrameTarget, OutputEncoding, TargetImageProblem,
    DISPLAY_FORMAT,
};
pub use light_cull::{LightCulling, MAX_CULLED_LIGHTS, TILE_SIZE};
pub use overlay::{Corner, OverlayImage, OverlayPanel};
pub use scene_edit::{EditError, MaterialId, MeshId, ObjectId, SceneEditor};
pub use scene_upload::{GpuScene, SceneEditReport};

/// The parts of the material model a lighting pipeline contains. A scene's pipeline
/// holds only what its materials use ([`LightingFeatures::of`]): each part left out is
/// a `NO_*` (or `OUTSIDE_ETA_ONE`) `#define` that removes its code from the shader, so
/// no pixel pays for a branch the scene cannot take. [`LightingFeatures::ALL`] is the
/// general pipeline (debug views, and the comparison [`Renderer::set_specialised`]
/// turns on); both give the same radiance up to f32 rounding (tests/specialisation.rs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LightingFeatures {
    /// Anisotropic GGX (else the isotropic D and Smith forms: α_x = α_y everywhere).
    pub anisotropy: bool,
    /// A conductor part (some material's metalness can exceed 0).
    pub conductors: bool,
    /// Conductors whose η + ik come from the base colour's codes (the table lookup).
    pub conductor_table: bool,
    /// A dielectric part (some material's metalness can be below 1): its specular
    /// lobe, Fresnel transmittance, total internal reflection and the diffuse lobe.
    pub dielectrics: bool,
    /// An outside medium other than η_i = 1 (else η_i is the constant 1).
    pub outside_medium: bool,
    /// The Lambertian diffuse model ([`DiffuseModel::Lambert`]).
    pub lambert: bool,
    /// The qualitative Oren–Nayar diffuse model ([`DiffuseModel::OrenNayarQualitative`]).
    pub oren_nayar_qualitative: bool,
    /// The full Oren–Nayar diffuse model ([`DiffuseModel::OrenNayarFull`]).
    pub oren_nayar_full: bool,
}

impl LightingFeatures {
    /// Every part: the general pipeline.
    pub const ALL: LightingFeatures = LightingFeatures {
        anisotropy: true,
        conductors: true,
        conductor_table: true,
        dielectrics: true,
        outside_medium: true,
        lambert: true,
        oren_nayar_qualitative: true,
        oren_nayar_full: true,
    };

    /// What `scene`'s materials can use (every material counts, drawn or not).
    pub fn of(scene: &Scene) -> LightingFeatures {
        let f = scene.features();
        let textured_metal =
            |m: &combustion_scene::Material| m.metallic_roughness_texture.is_some();
        LightingFeatures {
            anisotropy: f.anisotropic > 0,
            conductors: f.conductors + f.conductors_from_base_color > 0,
            conductor_table: f.conductors_from_base_color > 0,
            dielectrics: scene
                .materials
                .iter()
                .any(|m| m.metalness < 1.0 || textured_metal(m)),
            outside_medium: f.outside_ior_not_one,
            lambert: f
                .diffuse_models
                .contains(&combustion_scene::DiffuseModel::Lambert),
            oren_nayar_qualitative: f
                .diffuse_models
                .contains(&combustion_scene::DiffuseModel::OrenNayarQualitative),
            oren_nayar_full: f
                .diffuse_models
                .contains(&combustion_scene::DiffuseModel::OrenNayarFull),
        }
    }

    fn defines(&self, defines: &mut Vec<(&'static str, Option<&'static str>)>) {
        for (present, define) in [
            (self.anisotropy, "NO_ANISOTROPY"),
            (self.conductors, "NO_CONDUCTORS"),
            (self.conductor_table, "NO_CONDUCTOR_TABLE"),
            (self.dielectrics, "NO_DIELECTRICS"),
            (self.outside_medium, "OUTSIDE_ETA_ONE"),
            (self.lambert, "NO_LAMBERT"),
            (self.oren_nayar_qualitative, "NO_OREN_NAYAR_QUALITATIVE"),
            (self.oren_nayar_full, "NO_OREN_NAYAR_FULL"),
        ] {
            if !present {
                defines.push((define, None));
            }
        }
    }
}

impl Default for LightingFeatures {
    fn default() -> Self {
        Self::ALL
    }
}

/// The masking–shadowing term of the lighting pass. The default is the exact model (the
/// one the f64 reference evaluates); the others are comparison variants whose error the
/// report measures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Masking {
    /// Smith's height-correlated G₂ (Heitz 2014).
    #[default]
    HeightCorrelated,
    /// The separable G₁(v)·G₁(l).
    Separable,
    /// Hammon 2017's approximation of the height-correlated visibility.
    Approximate,
}

impl Masking {
    /// The short name the command line and the report use (`correlated`, `separable`,
    /// `approximate`).
    pub fn name(self) -> &'static str {
        match self {
            Self::HeightCorrelated => "correlated",
            Self::Separable => "separable",
            Self::Approximate => "approximate",
        }
    }
}

/// The microfacet normal distribution of the lighting pass. GGX (the reference's) by
/// default; Beckmann is a comparison variant whose error the report measures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Distribution {
    /// GGX / Trowbridge–Reitz, isotropic or anisotropic (Walter et al. 2007; Burley 2012).
    #[default]
    Ggx,
    /// Beckmann's distribution with the same α (anisotropic form), and Beckmann's own
    /// Smith Λ in Walter et al. 2007's rational form, height-correlated or separable as
    /// [`Masking`] says. Hammon's fit ([`Masking::Approximate`]) is of GGX's term: with
    /// Beckmann it evaluates the height-correlated form.
    Beckmann,
}

impl Distribution {
    /// The short name the command line and the report use (`ggx`, `beckmann`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Ggx => "ggx",
            Self::Beckmann => "beckmann",
        }
    }
}

/// Stripped-down passes to measure the real ones against (`combustion bench --report`):
/// what the same frame costs with the shading taken out. Not images to look at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeasurementFloor {
    /// The G-buffer pass with the same meshes, vertex format and targets but a fragment
    /// stage that writes constants (the geometry floor).
    Geometry,
    /// The lighting pass fetching the G-buffer and writing, nothing shaded.
    LightingFetch,
    /// The lighting pass with a plain isotropic GGX, height-correlated Smith and the
    /// full conductor Fresnel equations per light (no frame, dielectric or diffuse).
    LightingPlainGgx,
}

/// The shader features a scene needs. Each distinct variant gets its own G-buffer and
/// lighting pipelines (compile-time `#define`s), so a scene does not pay for features it
/// lacks; variants are built at upload (or edit) and kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ShaderVariant {
    /// An emissive target in the G-buffer, added to the lit radiance.
    pub emissive: bool,
    /// Some texture slot samples the second coordinate set or through a
    /// KHR_texture_transform: the G-buffer shader reads `Vertex::uv1` and maps each
    /// slot's coordinates (else it samples every slot at `Vertex::uv` as it is).
    pub texture_transforms: bool,
    /// The Fresnel term ([`FresnelModel`]; a renderer setting, not a scene feature).
    pub fresnel: FresnelModel,
    /// The lighting pass can show a G-buffer channel or a BRDF term instead of radiance
    /// ([`DebugView`]; a renderer setting).
    pub debug_views: bool,
    /// The parts of the material model the lighting pipeline contains.
    pub features: LightingFeatures,
    /// A measurement floor instead of the real pass ([`Renderer::set_measurement_floor`]).
    pub floor: Option<MeasurementFloor>,
    /// The masking–shadowing term ([`Renderer::set_masking`]).
    pub masking: Masking,
    /// The normal distribution ([`Renderer::set_distribution`]).
    pub distribution: Distribution,
    /// Environment lighting ([`combustion_scene::Scene::environment`]): the lighting pass
    /// adds the split-sum term of [`environment`].
    pub environment: bool,
    /// glTF occlusion textures attenuate the environment term (scenes with an
    /// environment and a material with an occlusion texture): the G-buffer stores the
    /// occlusion in the emissive target's alpha.
    pub occlusion: bool,
    /// Multiple-scattering energy compensation of the specular lobes
    /// ([`Renderer::set_energy_compensation`]; a renderer setting).
    pub energy_compensation: bool,
}

/// What the lighting pass shows instead of radiance (`debug_views.glsl` has the same
/// numbering). With a debug view, render at exposure 1: the view's values are written so
/// that the output pass's tone curve and sRGB encoding give them back.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DebugView {
    /// Radiance: the frame itself.
    #[default]
    None = 0,
    /// The base colour, as a colour.
    BaseColor = 1,
    /// The normal, n·½ + ½ as RGB codes.
    Normal = 2,
    /// Perceptual roughness as a grey code.
    Roughness = 3,
    /// Anisotropy strength as a grey code.
    AnisotropyStrength = 4,
    /// The anisotropy direction, t·½ + ½ as RGB codes.
    AnisotropyDirection = 5,
    /// Metalness as a grey code.
    Metalness = 6,
    /// A colour per material index.
    MaterialIndex = 7,
    /// Distance d from the eye, as the grey code d / (1 + d).
    Depth = 8,
    /// GGX's D for the first light's half vector, through the tone curve.
    Distribution = 9,
    /// The Smith masking–shadowing G2 for the first light, as a grey code.
    Smith = 10,
    /// The Fresnel reflectance per channel at the first light's half vector.
    Fresnel = 11,
    /// The diffuse lobe × π (the albedo it shows), for the first light.
    Diffuse = 12,
    /// The share of the frame's lights the pixel's tile loops over (1 where frames do
    /// not cull): light culling made visible.
    LightsPerTile = 13,
}

impl DebugView {
    /// Every view, in key order.
    pub const ALL: [DebugView; 14] = [
        DebugView::None,
        DebugView::BaseColor,
        DebugView::Normal,
        DebugView::Roughness,
        DebugView::AnisotropyStrength,
        DebugView::AnisotropyDirection,
        DebugView::Metalness,
        DebugView::MaterialIndex,
        DebugView::Depth,
        DebugView::Distribution,
        DebugView::Smith,
        DebugView::Fresnel,
        DebugView::Diffuse,
        DebugView::LightsPerTile,
    ];

    /// The next view (after the last: none).
    pub fn next(self) -> DebugView {
        let i = Self::ALL.iter().position(|&v| v == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }

    /// A short lower-case name for titles and panels (`radiance`, `base colour`, …).
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "radiance",
            Self::BaseColor => "base colour",
            Self::Normal => "normal",
            Self::Roughness => "roughness",
            Self::AnisotropyStrength => "anisotropy strength",
            Self::AnisotropyDirection => "anisotropy direction",
            Self::Metalness => "metalness",
            Self::MaterialIndex => "material index",
            Self::Depth => "distance",
            Self::Distribution => "D (GGX)",
            Self::Smith => "G2 (Smith)",
            Self::Fresnel => "Fresnel F",
            Self::Diffuse => "diffuse",
            Self::LightsPerTile => "lights per tile",
        }
    }
}

impl ShaderVariant {
    /// Whether the G-buffer has its fourth target: emitted radiance (rgb, EMISSIVE) and
    /// occlusion (a, OCCLUSION).
    pub(crate) fn has_emissive_occlusion_target(&self) -> bool {
        self.emissive || self.occlusion
    }

    /// The `#define`s of this variant.
    pub(crate) fn defines(&self) -> Vec<(&'static str, Option<&'static str>)> {
        let mut defines = Vec::new();
        if self.emissive {
            defines.push(("EMISSIVE", None));
        }
        if self.occlusion {
            defines.push(("OCCLUSION", None));
        }
        if self.has_emissive_occlusion_target() {
            defines.push(("EMISSIVE_OCCLUSION_TARGET", None));
        }
        if self.energy_compensation {
            defines.push(("ENERGY_COMPENSATION", None));
        }
        if self.texture_transforms {
            defines.push(("TEXTURE_TRANSFORMS", None));
        }
        match self.fresnel {
            FresnelModel::Full => {}
            FresnelModel::Schlick => defines.push(("FRESNEL_SCHLICK", None)),
            FresnelModel::F82 => defines.push(("FRESNEL_F82", None)),
        }
        if self.debug_views {
            defines.push(("DEBUG_VIEWS", None));
        }
        self.features.defines(&mut defines);
        match self.masking {
            Masking::HeightCorrelated => {}
            Masking::Separable => defines.push(("SMITH_SEPARABLE", None)),
            Masking::Approximate => defines.push(("SMITH_APPROXIMATE", None)),
        }
        if self.distribution == Distribution::Beckmann {
            defines.push(("D_BECKMANN", None));
        }
        if self.environment {
            defines.push(("ENVIRONMENT", None));
        }
        match self.floor {
            None => {}
            Some(MeasurementFloor::Geometry) => defines.push(("FLOOR_GEOMETRY", None)),
            Some(MeasurementFloor::LightingFetch) => defines.push(("FLOOR_FETCH", None)),
            Some(MeasurementFloor::LightingPlainGgx) => defines.push(("FLOOR_PLAIN_GGX", None)),
        }
        defines
    }
}

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
    /// An exposure (in the settings or a frame's inputs) that is not finite and positive.
    #[error("exposure {0} must be a positive finite number")]
    InvalidExposure(f32),
    /// Something of the scene exceeds a device or format limit (an image larger than the
    /// device's maximum 2D image size, a mesh of 2³² indices or more); the message names
    /// it.
    #[error("scene too large: {0}")]
    TooLarge(String),
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
    /// The frame last recorded in the slot has not completed on the GPU (checked where
    /// the device has timestamp queries): the host must wait for that frame's fence, or
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
    /// The pipelines the frame needs with the current settings were not built: call
    /// [`Renderer::prepare`] after changing a setting.
    #[error("the scene's pipelines were not built; call Renderer::prepare after changing the renderer's settings")]
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

/// Storage of the HDR (lit) image.
///
/// Measured on lavapipe at 1280×720 (builtin:spheres, median of 30 frames): RGBA32F costs
/// ≈ 0.5 ms more in the lighting pass and ≈ 0.9 ms more in the tonemap pass than RGBA16F
/// (≈ 1.5 % of the frame), while RGBA16F's rounding (up to 2⁻¹² relative) is larger than
/// the whole shading error the parity tests measure (mean ≈ 4e-6). Hence RGBA32F by default.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HdrFormat {
    /// RGBA16F: half the bandwidth; ≈ 3 significant digits (relative step 2⁻¹¹).
    Rgba16Float,
    /// RGBA32F: the radiance as the lighting pass computed it.
    #[default]
    Rgba32Float,
}

impl HdrFormat {
    /// The Vulkan format.
    pub fn vk(self) -> vk::Format {
        match self {
            Self::Rgba16Float => vk::Format::R16G16B16A16_SFLOAT,
            Self::Rgba32Float => vk::Format::R32G32B32A32_SFLOAT,
        }
    }
    fn bytes_per_pixel(self) -> u64 {
        match self {
            Self::Rgba16Float => 8,
            Self::Rgba32Float => 16,
        }
    }
}

/// What a frame copies back to the CPU.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Readback {
    /// The HDR radiance and the tonemapped sRGB image.
    pub images: bool,
    /// The G-buffer and depth (for parity checks).
    pub gbuffer: bool,
}

/// The GPU times of one frame's passes, by name, from timestamp queries, in
/// milliseconds: whatever passes the frame ran, in the order it ran them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassTimings {
    /// Each pass the frame ran, in order.
    pub passes: Vec<PassTime>,
    /// From the frame's first command to the end of its last pass.
    pub total_ms: f64,
}

/// One pass's GPU time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PassTime {
    /// The pass's name ([`PassTimings::GBUFFER`], …).
    pub name: &'static str,
    /// Milliseconds from the end of the pass before (or the frame's start) to its end.
    pub ms: f64,
}

impl PassTimings {
    /// The G-buffer pass.
    pub const GBUFFER: &'static str = "gbuffer";
    /// The lighting pass, with the light culling that precedes it.
    pub const LIGHTING: &'static str = "lighting";
    /// The output pass (tone curve, encoding) and its overlay.
    pub const OUTPUT: &'static str = "output";
    /// The copy of the scene's depth into a host's depth image (frames given one).
    pub const DEPTH_COPY: &'static str = "depth copy";

    /// The time of the pass named `name`, if the frame ran it.
    pub fn ms(&self, name: &str) -> Option<f64> {
        self.passes.iter().find(|p| p.name == name).map(|p| p.ms)
    }

    /// The names of the passes the frame ran, in order.
    pub fn names(&self) -> Vec<&'static str> {
        self.passes.iter().map(|p| p.name).collect()
    }

    /// The time of the pass named `name`, 0 if the frame did not run it.
    pub fn ms_or_zero(&self, name: &str) -> f64 {
        self.ms(name).unwrap_or(0.0)
    }
}

/// A rendered frame.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear HDR radiance, RGBA, row-major from the top-left (empty without readback).
    pub hdr: Vec<[f32; 4]>,
    /// Tonemapped, sRGB-encoded RGBA8 (empty without readback).
    pub ldr: Vec<[u8; 4]>,
    /// The G-buffer, with [`Readback::gbuffer`] (else `None`).
    pub gbuffer: Option<GBufferReadback>,
    /// The frame's GPU pass times (zero where the device has no timestamps).
    pub timings: PassTimings,
}

/// The most frames in flight a renderer keeps.
pub const MAX_FRAMES_IN_FLIGHT: usize = 3;

/// Settings of the renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RendererSettings {
    /// The HDR (lit) image's format.
    pub hdr_format: HdrFormat,
    /// Multiplies radiance before the tone curve, in [`Renderer::render`] (frames
    /// recorded with [`Renderer::record`] bring their own, in [`FrameInputs`]).
    pub exposure: f32,
    /// The Fresnel term; changed later with [`Renderer::set_fresnel`].
    pub fresnel: FresnelModel,
    /// Frames the CPU may record ahead of the GPU (1 to [`MAX_FRAMES_IN_FLIGHT`]):
    /// each has its own descriptor sets, light buffer and timestamp queries.
    pub frames_in_flight: usize,
}

impl RendererSettings {
    fn validate(&self) -> Result<(), RenderError> {
        if !(self.exposure.is_finite() && self.exposure > 0.0) {
            return Err(RenderError::InvalidExposure(self.exposure));
        }
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&self.frames_in_flight) {
            return Err(RenderError::InvalidFramesInFlight(self.frames_in_flight));
        }
        Ok(())
    }
}

/// Which Fresnel term the lighting pass evaluates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FresnelModel {
    /// The full dielectric and conductor Fresnel equations with the outside medium's IOR,
    /// polarisation and total internal reflection (the reference; default).
    #[default]
    Full,
    /// Schlick's curve through the exact normal-incidence reflectance: cheaper, no total
    /// internal reflection. Its speed and error are measured and reported (README,
    /// "Performance and accuracy"); it exists for comparison, not as a default.
    Schlick,
    /// Hoffman's F82 model (Hoffman 2019; the form of OpenPBR): Schlick's curve less
    /// b μ (1 − μ)⁶, fitted per pixel to the exact reflectance at normal incidence and at
    /// cos θ = 1/7 (`combustion_optics::fresnel::fresnel_f82`). Cheaper per light than the
    /// full equations, closer than Schlick on metals; a comparison variant.
    F82,
}

impl FresnelModel {
    /// The short name the command line and the report use (`full`, `schlick`, `f82`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Full => "full",
            Self::Schlick => "schlick",
            Self::F82 => "f82",
        }
    }

    /// How the viewer's title and statistics panel name it.
    pub fn description(self) -> &'static str {
        match self {
            Self::Full => "full Fresnel",
            Self::Schlick => "Schlick (comparison)",
            Self::F82 => "F82 (comparison)",
        }
    }
}

impl Default for RendererSettings {
    fn default() -> Self {
        Self {
            hdr_format: HdrFormat::default(),
            exposure: 1.0,
            fresnel: FresnelModel::default(),
            frames_in_flight: 2,
        }
    }
}

/// CPU mirror of `tonemap_exponential` (tonemap.glsl): the display value before sRGB encoding.
pub fn tonemap_exponential(x: f64) -> f64 {
    1.0 - (-x.max(0.0)).exp()
}

/// The sRGB encoding (IEC 61966-2-1) the tonemap pass applies (`srgb_encode`).
pub fn linear_to_srgb(linear: f64) -> f64 {
    if linear <= 0.0031308 {
        linear * 12.92
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// Binds `pipeline` at `bind_point` with its one descriptor set (set 0) and, if any,
/// its push constants for `stages`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn bind_pass(
    raw: &combustion_vk::ash::Device,
    cmd: vk::CommandBuffer,
    bind_point: vk::PipelineBindPoint,
    pipeline: &combustion_vk::Pipeline,
    layout: &combustion_vk::PipelineLayout,
    set: vk::DescriptorSet,
    stages: vk::ShaderStageFlags,
    push: &[u8],
) {
    // SAFETY: recording state is the caller's responsibility; the set matches the layout.
    unsafe {
        raw.cmd_bind_pipeline(cmd, bind_point, pipeline.raw());
        raw.cmd_bind_descriptor_sets(cmd, bind_point, layout.raw(), 0, &[set], &[]);
        if !push.is_empty() {
            raw.cmd_push_constants(cmd, layout.raw(), stages, 0, push);
        }
    }
}

pub(crate) fn set_viewport_and_scissor(
    raw: &combustion_vk::ash::Device,
    cmd: vk::CommandBuffer,
    extent: vk::Extent2D,
) {
    // SAFETY: recording state is the caller's responsibility.
    unsafe {
        raw.cmd_set_viewport(
            cmd,
            0,
            &[vk::Viewport {
                x: 0.0,
                y: 0.0,
                width: extent.width as f32,
                height: extent.height as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            }],
        );
        raw.cmd_set_scissor(
            cmd,
            0,
            &[vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent,
            }],
        );
    }
}

/// The G-buffer and lighting pipelines of one [`ShaderVariant`]. Variants that differ
/// only in what the lighting pass reads share one G-buffer pipeline.
struct VariantPasses {
    gbuffer: Arc<GBufferPass>,
    lighting: FullscreenPass,
}

impl ShaderVariant {
    /// The part of the variant the G-buffer shader reads (the emissive target and the
    /// geometry floor); every other feature is the lighting pass's.
    fn gbuffer_part(self) -> ShaderVariant {
        ShaderVariant {
            emissive: self.emissive,
            occlusion: self.occlusion,
            texture_transforms: self.texture_transforms,
            floor: self.floor.filter(|f| *f == MeasurementFloor::Geometry),
            ..ShaderVariant::default()
        }
    }
}

/// The descriptor-set layouts of the passes, shared by every variant and frame slot.
struct SetLayouts {
    /// Set 0 of the G-buffer pass: object and material tables.
    gbuffer: DescriptorSetLayout,
    /// Set 1 of the G-buffer pass: one material's textures.
    material: DescriptorSetLayout,
    /// The lighting pass: G-buffer, depth, material table, lights, conductor table,
    /// emissive (bound in the EMISSIVE variant only).
    lighting: DescriptorSetLayout,
    /// The output pass: the HDR image.
    output: DescriptorSetLayout,
    /// The overlay: the frame's quads, the font atlas and the overlay image.
    overlay: DescriptorSetLayout,
    /// Light culling: the G-buffer depth, the frame's lights, the tile lists.
    light_cull: DescriptorSetLayout,
}

/// The passes that write a target of one format: the output pass and the overlay
/// drawn over it.
struct OutputPasses {
    output: FullscreenPass,
    overlay: overlay::OverlayPass,
}

impl SetLayouts {
    fn new(device: &Arc<Device>) -> Result<Self, RenderError> {
        Ok(Self {
            gbuffer: bindings::GBUFFER.layout(device)?,
            material: bindings::MATERIAL_TEXTURES.layout(device)?,
            lighting: bindings::LIGHTING.layout(device)?,
            output: bindings::OUTPUT.layout(device)?,
            overlay: bindings::OVERLAY.layout(device)?,
            light_cull: bindings::LIGHT_CULL.layout(device)?,
        })
    }
}

/// The deferred renderer. One per device; renders [`GpuScene`]s at any size, into its
/// own images ([`Renderer::render`]) or into a host's command buffer and image
/// ([`Renderer::record`]), with frames in flight.
///
/// Pipelines are built by [`Renderer::new`], [`Renderer::upload`],
/// [`Renderer::edit_scene`], [`Renderer::prepare`] and [`Renderer::prepare_output`],
/// never while a frame is recorded. Resources it replaces (targets of another size, an
/// edited scene's old buffers, a dropped [`GpuScene`] or [`FrameEnvironment`]) wait in
/// a retire list until the frames recorded before have completed.
///
/// Teardown: dropping it waits for its own submissions ([`Renderer::render`],
/// [`Renderer::submit_offscreen`]) and, on a device it created, for the device to be
/// idle; frames a host recorded into its own command buffers are the host's to wait
/// for before the drop (docs/integration.md, "Teardown and errors").
pub struct Renderer {
    // Field order is drop order: everything below holds the device alive.
    /// Combustion's own submissions (render, bench), created on first use.
    offscreen: Option<offscreen::Offscreen>,
    slots: Vec<frame::FrameSlot>,
    targets: HashMap<targets::TargetKey, (targets::FrameTargets, u64)>,
    variants: HashMap<ShaderVariant, VariantPasses>,
    /// G-buffer pipelines by [`ShaderVariant::gbuffer_part`].
    gbuffer_passes: HashMap<ShaderVariant, Arc<GBufferPass>>,
    /// Output passes (and overlays) by target format.
    outputs: HashMap<vk::Format, OutputPasses>,
    overlay_font: overlay::OverlayFont,
    /// The font's atlas, read by the overlay's fragment shader.
    overlay_atlas: combustion_vk::Buffer,
    /// The overlay image ([`Renderer::set_overlay_image`]) and its size; or a one-texel
    /// placeholder, bound when no image is shown.
    overlay_image: (combustion_vk::Buffer, Option<[u32; 2]>),
    /// Bound in the lighting set for scenes without an environment.
    no_environment: environment::GpuEnvironment,
    /// What this renderer's [`GpuScene`]s hand over when dropped, moved to the retire
    /// list of the frame recorded last when the next frame begins.
    retire_queue: Arc<retire::RetireQueue>,
    /// Bound in the lighting set where the frame's G-buffer has no emissive + occlusion
    /// target.
    absent_target: combustion_vk::Image,
    layouts: SetLayouts,
    pipeline_cache: PipelineCache,
    compiler: ShaderCompiler,
    states: graph::ImageStates,
    settings: RendererSettings,
    debug_view: DebugView,
    /// Lighting pipelines specialised to the scene ([`Renderer::set_specialised`]).
    specialised: bool,
    /// A measurement floor in place of the real passes.
    floor: Option<MeasurementFloor>,
    /// The masking–shadowing term ([`Renderer::set_masking`]).
    masking: Masking,
    /// The normal distribution ([`Renderer::set_distribution`]).
    distribution: Distribution,
    /// One diffuse model for every material ([`Renderer::set_diffuse_override`]).
    diffuse_override: Option<DiffuseModel>,
    /// The environment bake's pipelines, built for the first scene with an environment.
    environment_baker: Option<environment::EnvironmentBaker>,
    /// Multiple-scattering energy compensation ([`Renderer::set_energy_compensation`]).
    energy_compensation: bool,
    /// [`environment::white_specular_albedo_table`] once compensation was asked for (a
    /// 16-byte placeholder before: the binding exists in every lighting layout).
    energy_table: combustion_vk::Buffer,
    /// When frames cull their lights ([`Renderer::set_light_culling`]).
    light_culling: LightCulling,
    light_cull: light_cull::LightCullPass,
    /// Frames recorded so far.
    frame_number: u64,
    /// The slot of the frame recorded last: what is replaced now is retired to it, and
    /// freed when that slot is reused (its frame, and every earlier one, complete).
    last_slot: Option<usize>,
    last_timings: Option<PassTimings>,
    stats: RendererStats,
    /// Timings of completed frames not yet taken ([`Renderer::take_completed_timings`]).
    completed_timings: std::collections::VecDeque<PassTimings>,
    device: Arc<Device>,
}

/// Counts of what a renderer has built, for hosts and tests that check that steady
/// frames build nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RendererStats {
    /// Frames recorded.
    pub frames: u64,
    /// Sets of targets (G-buffer + HDR image) allocated.
    pub targets_built: u64,
    /// Sets of targets retired after going unused.
    pub targets_retired: u64,
    /// Graphics pipelines built.
    pub pipelines_built: u64,
    /// Display images of [`Renderer::render`] and [`Renderer::submit_offscreen`] made.
    pub display_images_built: u64,
}

/// How many completed frames' timings are kept until taken.
const COMPLETED_TIMINGS_KEPT: usize = 1024;

impl Renderer {
    /// Compiles the shaders and builds the pipelines of scenes without special
    /// features, and the output pass for [`DISPLAY_FORMAT`].
    pub fn new(device: Arc<Device>, settings: RendererSettings) -> Result<Self, RenderError> {
        Self::with_pipeline_cache(device, settings, &[])
    }

    /// As [`Renderer::new`], with a pipeline cache primed from `cache_data` (what
    /// [`Renderer::pipeline_cache_data`] returned on an earlier run; data from another
    /// driver is ignored).
    pub fn with_pipeline_cache(
        device: Arc<Device>,
        settings: RendererSettings,
        cache_data: &[u8],
    ) -> Result<Self, RenderError> {
        settings.validate()?;
        let compiler = ShaderCompiler::new(shader_sources::sources())?;
        let layouts = SetLayouts::new(&device)?;
        let overlay_font = overlay::OverlayFont::new()?;
        let overlay_atlas = frame::filled_storage_buffer(
            &device,
            "overlay font atlas",
            bytemuck::cast_slice(&overlay::atlas_words(&overlay_font)),
        )?;
        let overlay_image = (overlay_image_buffer(&device, &[[0; 4]])?, None);
        let no_environment = environment::GpuEnvironment::placeholder(&device)?;
        let absent_target = targets::absent_target_placeholder(&device, settings.hdr_format.vk())?;
        let energy_table =
            frame::filled_storage_buffer(&device, "energy table placeholder", &[0; 16])?;
        let pipeline_cache = PipelineCache::new(&device, cache_data)?;
        let light_cull = light_cull::LightCullPass::new(
            &device,
            &compiler,
            &pipeline_cache,
            &layouts.light_cull,
        )?;
        let slots = (0..settings.frames_in_flight)
            .map(|_| frame::FrameSlot::new(&device, &layouts))
            .collect::<Result<Vec<_>, _>>()?;
        let mut renderer = Self {
            offscreen: None,
            slots,
            targets: HashMap::new(),
            variants: HashMap::new(),
            gbuffer_passes: HashMap::new(),
            outputs: HashMap::new(),
            overlay_font,
            overlay_atlas,
            overlay_image,
            no_environment,
            absent_target,
            retire_queue: retire::RetireQueue::new(),
            pipeline_cache,
            layouts,
            compiler,
            states: graph::ImageStates::default(),
            settings,
            debug_view: DebugView::None,
            specialised: true,
            floor: None,
            masking: Masking::HeightCorrelated,
            distribution: Distribution::Ggx,
            diffuse_override: None,
            environment_baker: None,
            energy_compensation: false,
            energy_table,
            light_culling: LightCulling::Auto,
            light_cull,
            frame_number: 0,
            last_slot: None,
            last_timings: None,
            completed_timings: std::collections::VecDeque::new(),
            stats: RendererStats::default(),
            device,
        };
        // The plain variant is built now, so shader errors surface at construction.
        renderer.prepare_variant(renderer.variant_of(ShaderVariant::default()))?;
        renderer.prepare_output(DISPLAY_FORMAT)?;
        Ok(renderer)
    }

    /// The device the renderer was created on.
    pub fn device(&self) -> &Arc<Device> {
        &self.device
    }

    /// The settings, with the Fresnel term [`Renderer::set_fresnel`] chose last.
    pub fn settings(&self) -> RendererSettings {
        self.settings
    }

    /// The pipeline cache's contents, to save and pass to
    /// [`Renderer::with_pipeline_cache`] on the next run.
    pub fn pipeline_cache_data(&self) -> Result<Vec<u8>, RenderError> {
        Ok(self.pipeline_cache.data()?)
    }

    /// The scene's variant with the renderer's settings applied.
    fn variant_of(&self, scene_variant: ShaderVariant) -> ShaderVariant {
        let debug_views = self.debug_view != DebugView::None;
        // Debug views show every term, so they get the general pipeline (and GGX, whose
        // terms they show).
        let mut features = if self.specialised && !debug_views {
            scene_variant.features
        } else {
            LightingFeatures::ALL
        };
        if let Some(model) = self.diffuse_override {
            // The one model left is the one every material evaluates (brdf_diffuse_lobe
            // needs no test when a single model remains).
            features.lambert = model == DiffuseModel::Lambert;
            features.oren_nayar_qualitative = model == DiffuseModel::OrenNayarQualitative;
            features.oren_nayar_full = model == DiffuseModel::OrenNayarFull;
        }
        ShaderVariant {
            fresnel: self.settings.fresnel,
            debug_views,
            features,
            floor: if debug_views { None } else { self.floor },
            masking: self.masking,
            distribution: if debug_views {
                Distribution::Ggx
            } else {
                self.distribution
            },
            energy_compensation: self.energy_compensation && !debug_views,
            ..scene_variant
        }
    }

    /// Builds the pipelines of `variant` if they are not built yet.
    fn prepare_variant(&mut self, variant: ShaderVariant) -> Result<(), RenderError> {
        if self.variants.contains_key(&variant) {
            return Ok(());
        }
        let gbuffer_key = variant.gbuffer_part();
        let gbuffer = match self.gbuffer_passes.get(&gbuffer_key) {
            Some(pass) => pass.clone(),
            None => {
                let pass = Arc::new(GBufferPass::new(
                    &self.device,
                    &self.compiler,
                    &self.pipeline_cache,
                    &self.layouts.gbuffer,
                    &self.layouts.material,
                    gbuffer_key,
                    self.settings.hdr_format.vk(),
                )?);
                self.stats.pipelines_built += 1;
                self.gbuffer_passes.insert(gbuffer_key, pass.clone());
                pass
            }
        };
        let lighting = FullscreenPass::new(
            &self.device,
            &self.compiler,
            &self.pipeline_cache,
            "lighting.frag",
            &variant.defines(),
            &self.layouts.lighting,
            std::mem::size_of::<LightingPush>() as u32,
            self.settings.hdr_format.vk(),
        )?;
        self.variants
            .insert(variant, VariantPasses { gbuffer, lighting });
        self.stats.pipelines_built += 1;
        Ok(())
    }

    /// Shows `image` over the frames recorded from now on (under their text panels, at
    /// the top-left, one texel a pixel), or no image. The previous image is kept until
    /// the frames in flight that show it have completed.
    pub fn set_overlay_image(&mut self, image: Option<&OverlayImage>) -> Result<(), RenderError> {
        let next = match image {
            Some(i) => {
                self.check_size(i.width, i.height)?;
                let texels = u64::from(i.width) * u64::from(i.height);
                if i.rgba.len() as u64 != texels {
                    return Err(RenderError::Overlay(format!(
                        "an overlay image of {}x{} needs {texels} texels, not {}",
                        i.width,
                        i.height,
                        i.rgba.len()
                    )));
                }
                let range = u64::from(self.device.limits().max_storage_buffer_range);
                if texels * 4 > range {
                    return Err(RenderError::Overlay(format!(
                        "an overlay image of {}x{} takes {} bytes; this device reads at most {range} from one buffer",
                        i.width,
                        i.height,
                        texels * 4
                    )));
                }
                (
                    overlay_image_buffer(&self.device, &i.rgba)?,
                    Some([i.width, i.height]),
                )
            }
            None => (overlay_image_buffer(&self.device, &[[0; 4]])?, None),
        };
        let old = std::mem::replace(&mut self.overlay_image, next);
        self.retire(old.0);
        Ok(())
    }

    /// The overlay's font (its atlas and text layout), e.g. to check a frame's overlay.
    pub fn overlay_font(&self) -> &overlay::OverlayFont {
        &self.overlay_font
    }

    /// Builds the output pass (and the overlay over it) for targets of `format`, so that [`Renderer::record`] can
    /// render into them. [`DISPLAY_FORMAT`] is prepared by [`Renderer::new`]. Formats:
    /// see [`OutputEncoding::of`].
    pub fn prepare_output(&mut self, format: vk::Format) -> Result<(), RenderError> {
        if self.outputs.contains_key(&format) {
            return Ok(());
        }
        let encoding =
            OutputEncoding::of(format).ok_or(RenderError::UnsupportedOutputFormat(format))?;
        let output = FullscreenPass::new(
            &self.device,
            &self.compiler,
            &self.pipeline_cache,
            "tonemap.frag",
            &encoding.defines(),
            &self.layouts.output,
            std::mem::size_of::<TonemapPush>() as u32,
            format,
        )?;
        let overlay = overlay::OverlayPass::new(
            &self.device,
            &self.compiler,
            &self.pipeline_cache,
            &self.layouts.overlay,
            &encoding.defines(),
            format,
        )?;
        self.outputs
            .insert(format, OutputPasses { output, overlay });
        self.stats.pipelines_built += 2;
        Ok(())
    }

    /// Switches the Fresnel term between frames (the Schlick comparison variant, or the
    /// full equations). Pipelines are built by [`Renderer::prepare`] or the next upload
    /// or edit, never by a frame's recording.
    pub fn set_fresnel(&mut self, model: FresnelModel) {
        self.settings.fresnel = model;
    }

    /// The masking–shadowing term from the next frame on (the exact height-correlated
    /// form by default; the others are comparison variants). Pipelines as for
    /// [`Renderer::set_fresnel`].
    pub fn set_masking(&mut self, masking: Masking) {
        self.masking = masking;
    }

    /// The masking–shadowing term ([`Renderer::set_masking`]).
    pub fn masking(&self) -> Masking {
        self.masking
    }

    /// The microfacet normal distribution from the next frame on (GGX by default;
    /// Beckmann is a comparison variant). Pipelines as for [`Renderer::set_fresnel`].
    pub fn set_distribution(&mut self, distribution: Distribution) {
        self.distribution = distribution;
    }

    /// The normal distribution ([`Renderer::set_distribution`]).
    pub fn distribution(&self) -> Distribution {
        self.distribution
    }

    /// Multiple-scattering energy compensation from the next frame on (off by default):
    /// every specular lobe, of lights and of the environment, is scaled by
    /// 1 + F₀ (1 − E)/E (Turquin 2019), E the white lobe's directional albedo at the
    /// pixel's n·v and roughness ([`environment::white_specular_albedo_table`]) and F₀
    /// the exact Fresnel reflectance at normal incidence (per channel, with the outside
    /// medium), so a white rough conductor keeps the energy single scattering loses.
    /// The f64 reference stays single-scattering: the difference is this option's
    /// measured deviation from it. The table is built on first use (not in a frame).
    pub fn set_energy_compensation(&mut self, on: bool) -> Result<(), RenderError> {
        if on && self.energy_table.size() <= 16 {
            let table = frame::filled_storage_buffer(
                &self.device,
                "white specular albedo table",
                bytemuck::cast_slice(&environment::white_specular_albedo_table()),
            )?;
            let placeholder = std::mem::replace(&mut self.energy_table, table);
            self.retire(placeholder);
        }
        self.energy_compensation = on;
        Ok(())
    }

    /// Whether energy compensation is on ([`Renderer::set_energy_compensation`]).
    pub fn energy_compensation(&self) -> bool {
        self.energy_compensation
    }

    /// One diffuse model for every material's dielectric part from the next frame on
    /// (a comparison variant: the f64 reference keeps each material's own model), or
    /// `None` for each material's own (the default). Pipelines as for
    /// [`Renderer::set_fresnel`].
    pub fn set_diffuse_override(&mut self, model: Option<DiffuseModel>) {
        self.diffuse_override = model;
    }

    /// The diffuse model every material is shaded with, if any
    /// ([`Renderer::set_diffuse_override`]).
    pub fn diffuse_override(&self) -> Option<DiffuseModel> {
        self.diffuse_override
    }

    /// Renders a [`MeasurementFloor`] instead of the real pass (or the real passes
    /// again), to time a frame against what it would cost without shading. Pipelines
    /// as for [`Renderer::set_fresnel`].
    pub fn set_measurement_floor(&mut self, floor: Option<MeasurementFloor>) {
        self.floor = floor;
    }

    /// When frames cull their lights (tiled light lists, [`LightCulling`]); from the next
    /// frame on. Culling never changes a pixel: it leaves out only lights whose range
    /// window is exactly 0 over a whole tile.
    pub fn set_light_culling(&mut self, culling: LightCulling) {
        self.light_culling = culling;
    }

    /// When frames cull their lights ([`Renderer::set_light_culling`]).
    pub fn light_culling(&self) -> LightCulling {
        self.light_culling
    }

    /// Lighting pipelines specialised to each scene's features ([`LightingFeatures::of`];
    /// the default), or the general pipeline for every scene (to compare the two).
    /// Pipelines as for [`Renderer::set_fresnel`].
    pub fn set_specialised(&mut self, specialised: bool) {
        self.specialised = specialised;
    }

    /// Whether lighting pipelines are specialised to each scene
    /// ([`Renderer::set_specialised`]).
    pub fn specialised(&self) -> bool {
        self.specialised
    }

    /// The lighting features of the pipeline `scene`'s frames use now.
    pub fn lighting_features(&self, scene: &GpuScene) -> LightingFeatures {
        self.variant_of(scene.variant).features
    }

    /// Shows a G-buffer channel or a BRDF term instead of radiance from the next frame
    /// on (render it at exposure 1). Pipelines as for [`Renderer::set_fresnel`].
    pub fn set_debug_view(&mut self, view: DebugView) {
        self.debug_view = view;
    }

    /// What the lighting pass shows ([`Renderer::set_debug_view`]).
    pub fn debug_view(&self) -> DebugView {
        self.debug_view
    }

    /// Builds the pipelines `scene` needs with the current settings, if they are not
    /// built yet (after [`Renderer::set_fresnel`]).
    /// Frames lit by a [`FrameEnvironment`] baked for the scene get theirs too.
    pub fn prepare(&mut self, scene: &GpuScene) -> Result<(), RenderError> {
        self.prepare_variant(self.variant_of(scene.variant))?;
        if scene.frame_environments.load(Ordering::Relaxed) {
            self.prepare_variant(self.variant_of(scene.lit_variant))?;
        }
        Ok(())
    }

    /// Validates and uploads a scene, and builds the pipelines it needs (never inside a
    /// frame's recording). A scene with an environment has it baked here, waiting for
    /// the GPU.
    ///
    /// # Errors
    /// [`RenderError::Scene`] if the scene fails validation; [`RenderError::TooLarge`]
    /// for an image beyond the device's 2D limit or a mesh of 2³² indices or more;
    /// [`RenderError::EnvironmentUnsupported`] for an environment the device cannot
    /// bake; [`RenderError::Vulkan`] if a pipeline, buffer or image cannot be made.
    pub fn upload(&mut self, scene: &Scene) -> Result<GpuScene, RenderError> {
        scene.validate()?;
        self.prepare_variant(self.variant_of(scene_upload::scene_variant(scene)))?;
        let environment = self.bake_scene_environment(scene)?;
        GpuScene::new(
            &self.device,
            scene,
            &self.layouts.material,
            environment,
            self.retire_queue.clone(),
        )
    }

    /// Bakes `environment` for `scene`'s materials, to light its frames in place of its
    /// own through [`FrameInputs::environment`] (a per-frame or per-view environment
    /// changed without a scene edit), and builds the pipelines such frames use (with
    /// the current settings; [`Renderer::prepare`] keeps them built after a settings
    /// change, and so do edits). Waits for the GPU (0.4–1.6 s on lavapipe): an upload
    /// step, never inside a frame. On error nothing changes.
    ///
    /// # Errors
    /// [`RenderError::SceneOfAnotherRenderer`] for a scene another renderer uploaded;
    /// [`RenderError::Scene`] for an invalid environment; otherwise as
    /// [`Renderer::upload`]'s bake.
    pub fn bake_environment(
        &mut self,
        scene: &GpuScene,
        environment: &combustion_scene::Environment,
    ) -> Result<FrameEnvironment, RenderError> {
        if !scene.belongs_to(&self.retire_queue) {
            return Err(RenderError::SceneOfAnotherRenderer);
        }
        environment.validate()?;
        self.prepare_variant(self.variant_of(scene.lit_variant))?;
        let baked = self.bake(environment, scene.scene())?;
        scene.frame_environments.store(true, Ordering::Relaxed);
        Ok(FrameEnvironment::new(
            baked,
            scene.bake_materials.clone(),
            self.retire_queue.clone(),
        ))
    }

    /// The scene's environment baked for its materials (None without one).
    fn bake_scene_environment(
        &mut self,
        scene: &Scene,
    ) -> Result<Option<environment::GpuEnvironment>, RenderError> {
        match &scene.environment {
            Some(source) => self.bake(source, scene).map(Some),
            None => Ok(None),
        }
    }

    /// `source` baked for `scene`'s materials.
    fn bake(
        &mut self,
        source: &combustion_scene::Environment,
        scene: &Scene,
    ) -> Result<environment::GpuEnvironment, RenderError> {
        if self.environment_baker.is_none() {
            self.environment_baker = Some(environment::EnvironmentBaker::new(
                &self.device,
                &self.compiler,
                &self.pipeline_cache,
            )?);
        }
        let baker = self.environment_baker.as_ref().expect("built above");
        let baked = baker.bake(&self.device, source, scene)?;
        log::info!(
            "environment {} baked in {:.1} ms",
            source.name(),
            baked.bake_ms
        );
        Ok(baked)
    }

    /// Edits an uploaded scene between frames without uploading it again: `edit` changes
    /// a copy of its CPU scene by index (add, remove or change objects, materials,
    /// lights, meshes, textures); only what changed is uploaded (see
    /// [`SceneEditReport`]), the replaced parts are retired until the frames in flight
    /// that read them have completed, and a shader feature the edit needs is built now,
    /// ahead of the next frame. On error (an invalid edit) the scene is unchanged.
    /// [`Renderer::try_edit_scene`] edits by stable handle.
    pub fn edit_scene(
        &mut self,
        scene: &mut GpuScene,
        edit: impl FnOnce(&mut Scene),
    ) -> Result<SceneEditReport, RenderError> {
        self.try_edit_scene(scene, |editor| {
            edit(editor.scene_mut());
            Ok(())
        })
        .map(|((), report)| report)
    }

    /// As [`Renderer::edit_scene`], with the edit made through a [`SceneEditor`]: items
    /// added and removed by handle ([`ObjectId`], [`MaterialId`], [`MeshId`]: stable
    /// across edits; [`GpuScene::object_ids`] and its siblings give those of the items
    /// uploaded), and changes by index through [`SceneEditor::scene_mut`]. `edit` may
    /// refuse ([`EditError`]): the scene is then unchanged. Returns what `edit` returned
    /// (the handles it made, say) and what was rebuilt.
    pub fn try_edit_scene<T>(
        &mut self,
        scene: &mut GpuScene,
        edit: impl FnOnce(&mut SceneEditor) -> Result<T, EditError>,
    ) -> Result<(T, SceneEditReport), RenderError> {
        if !scene.belongs_to(&self.retire_queue) {
            return Err(RenderError::SceneOfAnotherRenderer);
        }
        let mut editor = SceneEditor::new(scene.scene().clone(), scene.ids.clone());
        let value = edit(&mut editor)?;
        let (next, ids) = editor.finish();
        next.validate()?;
        // The pipelines first: if they cannot be built, the scene stays as it was.
        let before = self.stats.pipelines_built;
        self.prepare_variant(self.variant_of(scene_upload::scene_variant(&next)))?;
        if scene.frame_environments.load(Ordering::Relaxed) {
            self.prepare_variant(self.variant_of(scene_upload::lit_scene_variant(&next)))?;
        }
        let pipelines_built = self.stats.pipelines_built - before;
        // The environment's tables follow the materials: bake again when the edit
        // changes what the bake reads — the environment or the material table (optics
        // and the outside medium, not names, textures, lights, objects or the camera) —
        // before anything of the scene is replaced, so a failed bake leaves it as it was.
        let old = scene.scene();
        let environment = if !same_environment(&next.environment, &old.environment)
            || bytemuck::cast_slice::<_, u8>(&gpu_types::material_table(&next, &[]))
                != bytemuck::cast_slice::<_, u8>(&gpu_types::material_table(old, &[]))
        {
            Some(self.bake_scene_environment(&next)?)
        } else {
            None
        };
        let (report, retired) =
            scene.edited(&self.device, next, ids, &self.layouts.material, environment)?;
        for part in retired {
            self.retire_boxed(part);
        }
        Ok((
            value,
            SceneEditReport {
                pipelines_built,
                ..report
            },
        ))
    }

    /// Keeps `resource` (a buffer, image or anything holding them) alive until the
    /// frames recorded so far have completed, then drops it. A [`GpuScene`] needs no
    /// call: dropping it retires its resources this way.
    pub fn retire(&mut self, resource: impl std::any::Any + Send) {
        self.retire_boxed(Box::new(resource));
    }

    fn retire_boxed(&mut self, resource: retire::Retired) {
        match self.last_slot {
            Some(slot) => self.slots[slot].retire(resource),
            // No frame was ever recorded: nothing can be using it.
            None => drop(resource),
        }
    }

    /// The GPU times of the most recent frame known to have completed (read when its
    /// frame slot is reused; at once for [`Renderer::render`]).
    pub fn last_completed_timings(&self) -> Option<PassTimings> {
        self.last_timings.clone()
    }

    /// What this renderer has built so far.
    pub fn stats(&self) -> RendererStats {
        RendererStats {
            frames: self.frame_number,
            ..self.stats
        }
    }

    /// The GPU times of every completed frame since the last call (oldest first; at
    /// most the last 1024 are kept).
    pub fn take_completed_timings(&mut self) -> Vec<PassTimings> {
        self.completed_timings.drain(..).collect()
    }

    /// The host has waited for every frame it recorded (e.g. at exit or before a pause):
    /// collects the timings of every slot's last frame, so that
    /// [`Renderer::take_completed_timings`] has them all.
    /// Every slot is free afterwards, even one whose last frame's timestamps are still
    /// unwritten (the host's word: its timings are then lost).
    pub fn frames_completed(&mut self) -> Result<(), RenderError> {
        let count = self.slots.len();
        let first = self.last_slot.map_or(0, |last| (last + 1) % count);
        for i in 0..count {
            let slot = (first + i) % count;
            if self.collect_timings(slot)? == frame::SlotFrame::Pending {
                // The host's word: it completed (or never ran). Its timings are lost.
                self.slots[slot].stamped.clear();
            }
        }
        Ok(())
    }

    /// Reads the timestamps of `slot`'s last frame if the GPU has written them all
    /// (never waits); [`frame::SlotFrame::Pending`] while any is not.
    pub(crate) fn collect_timings(&mut self, slot: usize) -> Result<frame::SlotFrame, RenderError> {
        let s = &mut self.slots[slot];
        let Some(t) = s.timestamps.as_ref().filter(|_| !s.stamped.is_empty()) else {
            return Ok(frame::SlotFrame::Completed);
        };
        // The start, each pass's end, and the frame's end.
        let written = s.stamped.len() as u32 + 2;
        let Some(ms) = t.read_first_ms_if_available(written)? else {
            return Ok(frame::SlotFrame::Pending);
        };
        let timings = PassTimings::from_stamps(&std::mem::take(&mut s.stamped), &ms);
        self.last_timings = Some(timings.clone());
        if self.completed_timings.len() == COMPLETED_TIMINGS_KEPT {
            self.completed_timings.pop_front();
        }
        self.completed_timings.push_back(timings);
        Ok(frame::SlotFrame::Completed)
    }

    fn check_size(&self, width: u32, height: u32) -> Result<(), RenderError> {
        let max = self.device.max_image_dimension_2d();
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::InvalidSize { width, height, max });
        }
        Ok(())
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        // Combustion's own submissions are waited for (bounded) by the frame ring's Drop;
        // frames recorded into a host's command buffers are the host's to wait for
        // (docs/integration.md). Only an owned device is waited idle as well.
        drop(self.offscreen.take());
        if self.device.is_owned() {
            if let Err(e) = self.device.wait_idle() {
                log::error!("waiting for the device before teardown: {e}");
            }
        }
        // Every frame is complete now: what scenes dropped is freed, and scenes dropped
        // from here on free their resources at once.
        drop(self.retire_queue.close());
    }
}

/// A host-visible buffer holding RGBA8 texels, as the overlay reads them.
fn overlay_image_buffer(
    device: &Arc<Device>,
    rgba: &[[u8; 4]],
) -> Result<combustion_vk::Buffer, RenderError> {
    Ok(frame::filled_storage_buffer(
        device,
        "overlay image",
        bytemuck::cast_slice(rgba),
    )?)
}

/// IEEE 754 binary16 → binary32 (exact).
pub fn f16_to_f32(bits: u16) -> f32 {
    let sign = if bits & 0x8000 != 0 { -1.0f32 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let mantissa = f32::from(bits & 0x3ff);
    match exponent {
        0 => sign * mantissa * 2f32.powi(-24),
        31 if mantissa == 0.0 => sign * f32::INFINITY,
        31 => f32::NAN,
        e => sign * (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

/// Whether two scenes' environments are the same, an image shared through its `Arc` at
/// once (comparing 2²⁶ texels on every edit would cost more than the edit).
fn same_environment(
    a: &Option<combustion_scene::Environment>,
    b: &Option<combustion_scene::Environment>,
) -> bool {
    use combustion_scene::Environment::Image;
    match (a, b) {
        (Some(Image(a)), Some(Image(b))) => std::sync::Arc::ptr_eq(a, b) || a == b,
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f16_decoding_matches_known_values() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
        assert!(f16_to_f32(0x7c00).is_infinite());
        assert!(f16_to_f32(0x7e00).is_nan());
    }

    #[test]
    fn srgb_round_trip() {
        for i in 0..=255 {
            let e = f64::from(i) / 255.0;
            let back = linear_to_srgb(gbuffer::srgb_to_linear(e));
            assert!((back - e).abs() < 1e-12, "{i}");
        }
    }
}
