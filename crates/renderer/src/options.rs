//! The renderer's settings and shading options: what [`Renderer::new`] is given
//! ([`RendererSettings`]), how the lighting pass shades ([`ShadingOptions`]: the
//! comparison variants [`FresnelModel`], [`Masking`], [`Distribution`],
//! [`MeasurementFloor`], its debug views, …) and what a frame reads back. Plain values:
//! the renderer switches options with [`Renderer::set_shading`].

use combustion_scene::DiffuseModel;

use crate::error::RenderError;
use crate::shadows::ShadowSettings;
use combustion_vk::vk;

#[cfg(doc)]
use crate::{FrameInputs, GpuScene, LightingFeatures, Renderer};

/// How the lighting pass shades: every option that selects the pipelines a frame uses.
/// Given at construction ([`RendererSettings::shading`]) and switched between frames,
/// all at once, with [`Renderer::set_shading`], which builds the pipelines the new
/// options need for the scenes it is given before it switches (on error nothing
/// changes). [`ShadingOptions::default`] is the exact model the f64 reference
/// evaluates, with the specialised pipelines; every other value of a field is a
/// comparison variant, a debug view or a measurement floor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShadingOptions {
    /// The Fresnel term: the full equations (default), or Schlick's or Hoffman's F82
    /// comparison variant.
    pub fresnel: FresnelModel,
    /// The masking–shadowing term: Smith's height-correlated G₂ (default), or the
    /// separable or approximate comparison variant.
    pub masking: Masking,
    /// The microfacet normal distribution: GGX (default), or Beckmann for comparison.
    pub distribution: Distribution,
    /// One diffuse model for every material's dielectric part (a comparison variant: the
    /// f64 reference keeps each material's own model), or `None` for each material's own
    /// (default).
    pub diffuse_override: Option<DiffuseModel>,
    /// Lighting pipelines specialised to each scene's features ([`LightingFeatures::of`];
    /// default `true`), or the general pipeline for every scene (to compare the two; they
    /// agree to f32 rounding).
    pub specialised: bool,
    /// A G-buffer channel or a BRDF term shown instead of radiance (render it at exposure
    /// 1); [`DebugView::None`], radiance, by default. A debug view takes the general
    /// pipeline with GGX and no measurement floor or energy compensation, whatever the
    /// other fields say.
    pub debug_view: DebugView,
    /// Multiple-scattering energy compensation (off by default): every specular lobe, of
    /// lights and of the environment, is scaled by 1 + F₀ (1 − E)/E (Turquin 2019), E the
    /// white lobe's directional albedo at the pixel's n·v and roughness
    /// ([`crate::environment::white_specular_albedo_table`]) and F₀ the exact Fresnel
    /// reflectance at normal incidence (per channel, with the outside medium), so a white
    /// rough conductor keeps the energy single scattering loses. The f64 reference stays
    /// single-scattering: the difference is this option's measured deviation from it.
    /// The table is built when the option is first turned on (not in a frame).
    pub energy_compensation: bool,
    /// A [`MeasurementFloor`] rendered instead of the real pass, to time a frame against
    /// what it would cost without shading (`None`, the real passes, by default).
    pub measurement_floor: Option<MeasurementFloor>,
    /// Shadows of the frames' lights that cast them (cascades for up to
    /// [`MAX_SHADOWED_LIGHTS`](crate::MAX_SHADOWED_LIGHTS) directional lights, a map per
    /// spot light, a cube per point light; docs/shadows.md), rendered when they change and
    /// sampled by the lighting pass; `None` (the default): no light is blocked, no shadow
    /// pass runs and the lighting pipeline has no shadow code.
    pub shadows: Option<ShadowSettings>,
    /// How the lighting pass integrates environment lighting: `0` (the default), the
    /// split sum (prefiltered cube × full-Fresnel albedo tables: no noise, an
    /// approximation); otherwise that many samples per pixel of each of two strategies
    /// (GGX visible normals and the cosine), combined by the balance heuristic, of the
    /// radiance cube's finest level: an unbiased estimate of the rendering equation's
    /// environment term (no occlusion by the scene, as the f64 reference), noisy at few
    /// samples. One of [`ENVIRONMENT_SAMPLE_COUNTS`]. Blended and transmissive surfaces
    /// (the forward pass) keep the split sum.
    pub environment_samples: u32,
    /// The optional passes frames run (none by default; [`crate::optional_passes`] lists
    /// them): each adds its pass and what the passes that read its output do with it.
    pub optional_passes: OptionalPasses,
    /// The most surfaces a path lights in path-traced frames (`--path-trace on`): 1 is
    /// direct light alone; [`PATH_DEPTHS`] (16 by default; Russian roulette ends most
    /// paths sooner).
    pub path_depth: u32,
}

/// The depths [`ShadingOptions::path_depth`] takes.
pub const PATH_DEPTHS: std::ops::RangeInclusive<u32> = 1..=64;

/// A pass the frame runs only when asked: declared once, in its pass's file, with its
/// name (how [`crate::optional_pass`] finds it, and the command line's `--NAME on|off`
/// unless it is one way of a [`PassChoice`]), its `#define` (set in every pipeline of
/// frames that run it, so that the passes reading its output read it) and a line of
/// help. [`crate::optional_passes`] lists them.
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct OptionalPass {
    /// Its name: lower case words joined by `-` (`ambient-occlusion`).
    pub name: &'static str,
    /// The `#define` of the pipelines of frames that run it.
    pub define: &'static str,
    /// What it does, in a line (the command line's help).
    pub help: &'static str,
    /// It traces rays (acceleration structures, ray queries): on a device without ray
    /// queries the renderer leaves it out of the options it is given, with a warning.
    pub needs_ray_queries: bool,
    /// The choice it is one way of, and its value there (`None`: a switch of its own).
    pub choice: Option<(&'static PassChoice, &'static str)>,
    /// It works on the environment's light, and what it finds without one (`nothing to
    /// block`): frames of a scene without an environment do not run it, which the
    /// command line says (`None`: it works without one).
    pub needs_environment: Option<&'static str>,
}

impl OptionalPass {
    /// How the command line asks for it: `--CHOICE VALUE`, or `--NAME on`.
    pub fn asked_as(&self) -> String {
        match self.choice {
            Some((choice, value)) => format!("--{} {value}", choice.name),
            None => format!("--{} on", self.name),
        }
    }
}

/// One job that several optional passes do different ways, chosen by one option
/// (`--NAME none|VALUE…` on the command line: none, or one pass's value).
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct PassChoice {
    /// Its name: lower case words joined by `-` (`environment-occlusion`).
    pub name: &'static str,
    /// What it chooses, in a line (the command line's help, before each way's).
    pub help: &'static str,
}

/// How the scene blocks the environment's light: the screen-space pass (`gtao`) or the
/// traced one (`ray-traced`); docs/occlusion.md.
pub static ENVIRONMENT_OCCLUSION: PassChoice = PassChoice {
    name: "environment-occlusion",
    help:
        "How the scene blocks the environment's light (with glTF occlusion textures: their minimum)",
};

/// The optional passes a frame runs: a set of [`OptionalPass`]es (empty by default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct OptionalPasses {
    /// The passes, by name, then empty entries (so that equal sets are equal values).
    on: [Option<&'static OptionalPass>; OptionalPasses::CAPACITY],
}

impl OptionalPasses {
    /// How many a set holds: every optional pass the renderer declares (a test checks).
    pub const CAPACITY: usize = 8;

    /// No optional pass.
    pub const NONE: OptionalPasses = OptionalPasses {
        on: [None; Self::CAPACITY],
    };

    /// This set with `pass` in it (or out of it, with `on` false).
    pub fn with(mut self, pass: &'static OptionalPass, on: bool) -> Self {
        let mut passes: Vec<&'static OptionalPass> =
            self.iter().filter(|p| p.name != pass.name).collect();
        if on {
            passes.push(pass);
        }
        passes.sort_by_key(|p| p.name);
        self.on = [None; Self::CAPACITY];
        for (slot, pass) in self.on.iter_mut().zip(passes) {
            *slot = Some(pass);
        }
        self
    }

    /// This set without the passes that need ray queries.
    pub fn without_ray_queries(self) -> Self {
        self.iter()
            .filter(|p| p.needs_ray_queries)
            .fold(self, |set, pass| set.with(pass, false))
    }

    /// Whether `pass` is in the set.
    pub fn contains(&self, pass: &OptionalPass) -> bool {
        self.iter().any(|p| p.name == pass.name)
    }

    /// The passes in the set, by name.
    pub fn iter(&self) -> impl Iterator<Item = &'static OptionalPass> + '_ {
        self.on.iter().flatten().copied()
    }
}

/// The sample counts [`ShadingOptions::environment_samples`] takes (each its own
/// pipeline): 0 (the split sum) and powers of two to 1024.
pub const ENVIRONMENT_SAMPLE_COUNTS: [u32; 12] = [0, 1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024];

impl ShadingOptions {
    /// Refuses an [`ShadingOptions::environment_samples`] outside
    /// [`ENVIRONMENT_SAMPLE_COUNTS`].
    pub(crate) fn validate_environment_samples(&self) -> Result<(), crate::RenderError> {
        if ENVIRONMENT_SAMPLE_COUNTS.contains(&self.environment_samples) {
            Ok(())
        } else {
            Err(crate::RenderError::InvalidEnvironmentSamples(
                self.environment_samples,
            ))
        }
    }

    /// Refuses a [`ShadingOptions::path_depth`] outside [`PATH_DEPTHS`].
    pub(crate) fn validate_path_depth(&self) -> Result<(), crate::RenderError> {
        if PATH_DEPTHS.contains(&self.path_depth) {
            Ok(())
        } else {
            Err(crate::RenderError::InvalidPathDepth(self.path_depth))
        }
    }

    /// The defaults: the exact model, each material's own diffuse model, specialised
    /// pipelines, radiance, no energy compensation, the real passes.
    pub const DEFAULT: ShadingOptions = ShadingOptions {
        fresnel: FresnelModel::Full,
        masking: Masking::HeightCorrelated,
        distribution: Distribution::Ggx,
        diffuse_override: None,
        specialised: true,
        debug_view: DebugView::None,
        energy_compensation: false,
        measurement_floor: None,
        shadows: None,
        environment_samples: 0,
        optional_passes: OptionalPasses::NONE,
        path_depth: 16,
    };
}

impl Default for ShadingOptions {
    fn default() -> Self {
        Self::DEFAULT
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

/// What the lighting pass shows instead of radiance (`debug_views.glsl` reads the same
/// numbering, as `DEBUG_VIEW_*` generated from it). With a debug view, render at exposure 1: the view's values are written so
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
    /// The lit fraction of the first light as its shadow map gives it (1: lit, 0:
    /// shadowed; 1 everywhere without shadows), as a grey code.
    ShadowFactor = 14,
    /// The shadow cascade the first light's lookup uses, a colour each (grey: beyond
    /// the shadow distance, or no shadows).
    ShadowCascade = 15,
}

impl DebugView {
    /// Every view, in key order.
    pub const ALL: [DebugView; 16] = [
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
        DebugView::ShadowFactor,
        DebugView::ShadowCascade,
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
            Self::ShadowFactor => "shadow factor",
            Self::ShadowCascade => "shadow cascade",
        }
    }
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
    pub(crate) fn bytes_per_pixel(self) -> u64 {
        match self {
            Self::Rgba16Float => 8,
            Self::Rgba32Float => 16,
        }
    }
}

/// Storage of the G-buffer's base colour and metalness (colour attachment 0).
///
/// One of the G-buffer's precision choices, measured end to end (the frame against the
/// scene's f64 reference) and for cost in the speed-against-error report's "G-buffer
/// storage" section; docs/gbuffer.md states the figures and why the default is 16-bit
/// sRGB (at 1280×720 on lavapipe, over the environment-free built-in scenes: the frame's
/// mean error 7.7e-5 against 4.6e-3 with 8 bits, for 3.2 ms, 4 %, more frame time).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BaseColorStorage {
    /// `R8G8B8A8_UNORM`: base colour through the sRGB curve, 8 bits (the shaders encode
    /// and decode exactly); metalness linear, 8 bits. 4 bytes. The cheaper choice: a
    /// base colour of 0.8 is stored 1.12·10⁻³ low.
    Srgb8,
    /// `R16G16B16A16_UNORM`: base colour through the sRGB curve, 16 bits; metalness
    /// linear, 16 bits. 8 bytes.
    #[default]
    Srgb16,
    /// `R16G16B16A16_SFLOAT`: base colour linear in f16 (11 significant bits, a relative
    /// step of 2⁻¹¹ at every level); metalness f16. 8 bytes.
    LinearHalf,
}

impl BaseColorStorage {
    /// Every storage, the default first.
    pub const ALL: [BaseColorStorage; 3] = [Self::Srgb16, Self::Srgb8, Self::LinearHalf];

    /// The Vulkan format of the target.
    pub fn vk(self) -> vk::Format {
        match self {
            Self::Srgb8 => vk::Format::R8G8B8A8_UNORM,
            Self::Srgb16 => vk::Format::R16G16B16A16_UNORM,
            Self::LinearHalf => vk::Format::R16G16B16A16_SFLOAT,
        }
    }

    /// Bytes per pixel of the target.
    pub fn bytes_per_pixel(self) -> u32 {
        match self {
            Self::Srgb8 => 4,
            Self::Srgb16 | Self::LinearHalf => 8,
        }
    }

    /// Short name (command line, report).
    pub fn name(self) -> &'static str {
        match self {
            Self::Srgb8 => "srgb8",
            Self::Srgb16 => "srgb16",
            Self::LinearHalf => "f16",
        }
    }
}

/// Storage of the G-buffer's octahedral normal, perceptual roughness and anisotropy
/// strength (colour attachment 1), all unorm. See [`BaseColorStorage`] for where the
/// choice is measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SurfaceStorage {
    /// `R16G16B16A16_UNORM`: 16 bits each (normal to 6.3·10⁻⁵ rad). 8 bytes.
    #[default]
    Unorm16,
    /// `R8G8B8A8_UNORM`: 8 bits each (normal to ≈ 1.6·10⁻² rad; α steps of up to 0.8 %
    /// of 2r/255). 4 bytes.
    Unorm8,
}

impl SurfaceStorage {
    /// Every storage, the default first.
    pub const ALL: [SurfaceStorage; 2] = [Self::Unorm16, Self::Unorm8];

    /// The Vulkan format of the target.
    pub fn vk(self) -> vk::Format {
        match self {
            Self::Unorm16 => vk::Format::R16G16B16A16_UNORM,
            Self::Unorm8 => vk::Format::R8G8B8A8_UNORM,
        }
    }

    /// Bytes per pixel of the target.
    pub fn bytes_per_pixel(self) -> u32 {
        match self {
            Self::Unorm16 => 8,
            Self::Unorm8 => 4,
        }
    }

    /// Bits per channel.
    pub fn bits(self) -> u32 {
        match self {
            Self::Unorm16 => 16,
            Self::Unorm8 => 8,
        }
    }

    /// Short name (command line, report).
    pub fn name(self) -> &'static str {
        match self {
            Self::Unorm16 => "unorm16",
            Self::Unorm8 => "unorm8",
        }
    }
}

/// The G-buffer's storage choices (its other targets, the material index with the
/// anisotropy direction and the depth, have one form). Fixed for a renderer's life, as
/// the HDR format is: the G-buffer and lighting pipelines and the targets are made for it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct GBufferStorage {
    /// Base colour and metalness.
    pub base_color: BaseColorStorage,
    /// Normal, roughness and anisotropy strength.
    pub surface: SurfaceStorage,
}

impl GBufferStorage {
    /// 16-bit sRGB base colour and metalness, 16-bit normal, roughness and anisotropy:
    /// the default, chosen by the measurement in docs/gbuffer.md.
    pub const DEFAULT: GBufferStorage = GBufferStorage {
        base_color: BaseColorStorage::Srgb16,
        surface: SurfaceStorage::Unorm16,
    };

    /// Bytes per pixel of the whole G-buffer, depth included (the emissive + occlusion
    /// target of scenes that need it not counted).
    pub fn bytes_per_pixel(self) -> u32 {
        self.base_color.bytes_per_pixel() + self.surface.bytes_per_pixel() + 4 + 4
    }

    /// Short name: `srgb16+unorm16` for the default.
    pub fn name(self) -> String {
        format!("{}+{}", self.base_color.name(), self.surface.name())
    }

    /// The `#define`s of the G-buffer and lighting shaders for this storage (none for
    /// 8-bit sRGB with a 16-bit surface).
    pub(crate) fn defines(self) -> Vec<(&'static str, Option<&'static str>)> {
        let mut defines = match self.base_color {
            BaseColorStorage::Srgb8 => Vec::new(),
            BaseColorStorage::Srgb16 => vec![("BASE_COLOR_SRGB16", None)],
            BaseColorStorage::LinearHalf => vec![("BASE_COLOR_LINEAR", None)],
        };
        if self.surface == SurfaceStorage::Unorm8 {
            defines.push(("SURFACE_UNORM8", None));
        }
        defines
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

impl Readback {
    /// The HDR radiance and the display image: what a picture or its radiance needs.
    pub const IMAGES: Readback = Readback {
        images: true,
        gbuffer: false,
    };

    /// The images and the G-buffer: what a comparison with a reference reads.
    pub const ALL: Readback = Readback {
        images: true,
        gbuffer: true,
    };
}

/// The most frames in flight a renderer keeps.
pub const MAX_FRAMES_IN_FLIGHT: usize = 3;

/// How many frames a renderer keeps targets no frame used by default
/// ([`RendererSettings::targets_kept_for_frames`]).
pub const TARGETS_KEPT_FOR_FRAMES: u32 = 16;

/// Settings of the renderer. The HDR format, the G-buffer's storage, the frames in
/// flight and how long unused targets are kept are fixed for the renderer's life (the
/// G-buffer and lighting pipelines, the frame targets and their placeholders are made
/// for the formats); the shading options change with [`Renderer::set_shading`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RendererSettings {
    /// The HDR (lit) image's format.
    pub hdr_format: HdrFormat,
    /// The G-buffer's storage of base colour, metalness, normal and roughness.
    pub gbuffer: GBufferStorage,
    /// Multiplies radiance before the tone curve, in [`Renderer::render`] (frames
    /// recorded with [`Renderer::record`] bring their own, in [`FrameInputs`]).
    pub exposure: f32,
    /// The shading options the renderer starts with (its pipelines for scenes without
    /// special features are built at construction); switched later with
    /// [`Renderer::set_shading`].
    pub shading: ShadingOptions,
    /// Frames the CPU may record ahead of the GPU (1 to [`MAX_FRAMES_IN_FLIGHT`]):
    /// each has its own descriptor sets, light buffer and timestamp queries.
    pub frames_in_flight: usize,
    /// Frames an image of the frames (a G-buffer target, the HDR image and the rest, per
    /// size and kind) is kept after the last frame that used it, then retired (freed once
    /// the frames in flight that used it complete): a host alternating viewports or
    /// variants keeps what it draws again; fewer frames free memory sooner. Default
    /// [`TARGETS_KEPT_FOR_FRAMES`]. Any count is safe; 0 retires each frame's targets
    /// after it, so every frame builds its own.
    pub targets_kept_for_frames: u32,
    /// Whether a frame in which nothing reads the radiance between the lighting and the
    /// output pass (no forward-drawn objects, temporal anti-aliasing, bloom, auto
    /// exposure or FXAA, and no copy of the HDR image read back) has the lighting pass
    /// write the target itself — the output pass's exposure, tone curve and encoding
    /// done per pixel there, and its full-screen pass saved (docs/performance.md). Its
    /// pixels are the two passes' bit for bit with an f32 HDR format (an f16 one's
    /// rounding is skipped). Default on; off keeps every frame's two passes apart (the
    /// report measures them so, pass by pass).
    pub fold_output: bool,
    /// Whether path-traced frames (`--path-trace on`) are averaged on the GPU while
    /// nothing changes: each joins the mean of the frames before it since the camera,
    /// lights, pose, scene, size, shading, background or seed last changed, its paths
    /// drawn from the next seed, so a still view converges (the viewer's). Default off:
    /// each frame is its own [`FrameInputs::environment_seed`]'s estimate alone (a
    /// still render averages them itself). [`Renderer::accumulated_paths`] says how
    /// many paths a pixel the last frame holds.
    pub accumulate_paths: bool,
}

impl Default for RendererSettings {
    fn default() -> Self {
        Self {
            hdr_format: HdrFormat::default(),
            gbuffer: GBufferStorage::DEFAULT,
            exposure: 1.0,
            shading: ShadingOptions::DEFAULT,
            frames_in_flight: 2,
            targets_kept_for_frames: TARGETS_KEPT_FOR_FRAMES,
            fold_output: true,
            accumulate_paths: false,
        }
    }
}

impl RendererSettings {
    /// Checks every field; the shadow maps' size against `device`'s limit.
    pub(crate) fn validate(&self, device: &combustion_vk::Device) -> Result<(), RenderError> {
        if let Some(shadows) = &self.shading.shadows {
            shadows.validate(device.limits().max_image_dimension2_d)?;
        }
        self.shading.validate_environment_samples()?;
        self.shading.validate_path_depth()?;
        if !(self.exposure.is_finite() && self.exposure > 0.0) {
            return Err(RenderError::InvalidExposure(self.exposure));
        }
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&self.frames_in_flight) {
            return Err(RenderError::InvalidFramesInFlight(self.frames_in_flight));
        }
        Ok(())
    }
}
