//! Shader variants: the `#define`s a scene's pipelines are built with, from the scene's
//! features ([`LightingFeatures`], [`ShaderVariant`]) and the renderer's shading options
//! (`ShadingOptions::variant`).

use combustion_scene::{DiffuseModel, Scene};

#[cfg(doc)]
use crate::environment;
use crate::options::{
    DebugView, Distribution, FresnelModel, Masking, MeasurementFloor, OptionalPasses,
    ShadingOptions,
};

/// The parts of the material model a lighting pipeline contains (unlit materials
/// included). A scene's pipeline holds only what its materials use ([`LightingFeatures::of`]): each part left out is
/// a `NO_*` (or `OUTSIDE_ETA_ONE`) `#define` that removes its code from the shader, so
/// no pixel pays for a branch the scene cannot take. [`LightingFeatures::ALL`] is the
/// general pipeline (debug views, and the comparison
/// [`ShadingOptions::specialised`] turns on); both give the same radiance up to f32 rounding (tests/specialisation.rs).
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
    /// Unlit materials (KHR_materials_unlit): their pixels show their base colour.
    pub unlit: bool,
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
        unlit: true,
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
            unlit: f.unlit > 0,
        }
    }

    /// The parts present, by name (`anisotropy, conductors, …`; `none` without any), for
    /// messages and reports.
    pub fn names(&self) -> String {
        let parts: Vec<&str> = [
            (self.anisotropy, "anisotropy"),
            (self.conductors, "conductors"),
            (self.conductor_table, "conductor table"),
            (self.dielectrics, "dielectrics"),
            (self.outside_medium, "outside medium"),
            (self.lambert, "Lambert"),
            (self.oren_nayar_qualitative, "Oren-Nayar qualitative"),
            (self.oren_nayar_full, "Oren-Nayar full"),
            (self.unlit, "unlit"),
        ]
        .into_iter()
        .filter(|(present, _)| *present)
        .map(|(_, name)| name)
        .collect();
        if parts.is_empty() {
            "none".to_owned()
        } else {
            parts.join(", ")
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
            (self.unlit, "NO_UNLIT"),
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

/// The shader features a scene needs. Each distinct variant gets its own G-buffer and
/// lighting pipelines (compile-time `#define`s), so a scene does not pay for features it
/// lacks; variants are built at upload (or edit) and kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ShaderVariant {
    /// An emissive target in the G-buffer, added to the lit radiance.
    pub emissive: bool,
    /// Some material has a texture (any slot): the passes that rasterise surfaces (the
    /// G-buffer and forward passes) sample them where a material's slot is set; scenes
    /// without any compile the reads out (on lavapipe the G-buffer pass of
    /// builtin:grid-7x7 takes 24.7 ms without them against 26.7 with them compiled in,
    /// docs/performance.md).
    pub textures: bool,
    /// Some texture slot samples the second coordinate set or through a
    /// KHR_texture_transform: the G-buffer shader reads `Vertex::uv1` and maps each
    /// slot's coordinates (else it samples every slot at `Vertex::uv` as it is).
    pub texture_transforms: bool,
    /// Some material is a cut-out (`AlphaMode::Mask`): the G-buffer pass (and the shadow
    /// casters') gets a second pipeline, built with `ALPHA_MASK`, that tests alpha and
    /// discards, for those materials' objects only; the other objects keep the pipeline
    /// without a discard (early depth testing intact).
    pub alpha_mask: bool,
    /// Some drawn object's material is blended (`AlphaMode::Blend`): the frame gets the
    /// forward pass (forward.frag) for those objects, after the deferred lighting; a
    /// scene without one has no forward pipeline and the pass does not run.
    pub blend: bool,
    /// Some drawn object's material is transmissive (KHR_materials_transmission): those
    /// objects are drawn by the forward pass (TRANSMISSION variant), which reads a copy
    /// of the lit image behind them, made by the behind pass with its mip chain.
    pub transmission: bool,
    /// Some drawn transmissive object has a volume (KHR_materials_volume): the back
    /// faces pass draws those objects' far sides (depth and normals), and forward.frag's
    /// VOLUME variant follows each refracted ray through the object to where it leaves
    /// and on to the opaque surface it meets (marching the depths); thin-walled glass
    /// needs neither.
    pub volume: bool,
    /// Some drawn object's material has a clear coat (KHR_materials_clearcoat): the
    /// G-buffer gets the coat's target (its normal, roughness and weight) and the passes
    /// that shade add the coat's lobe and its attenuation of the base
    /// (`combustion_optics::coat`); scenes without a coat carry neither.
    pub clearcoat: bool,
    /// Some drawn object's material has a sheen (KHR_materials_sheen): the G-buffer gets
    /// the sheen's target (its colour and roughness) and the passes that shade add the
    /// sheen's lobe and its albedo scaling of the base (`combustion_optics::sheen`, the
    /// albedo table bound); scenes without one carry neither.
    pub sheen: bool,
    /// Some drawn object's material has a thin film (KHR_materials_iridescence): the
    /// G-buffer gets the film's target (its weight and thickness) and the passes that
    /// shade mix the film's Fresnel reflectance into every lobe's
    /// (`combustion_optics::thin_film`); scenes without one carry neither.
    pub iridescence: bool,
    /// Some drawn object's material sets the dielectric's specular strength or colour
    /// (KHR_materials_specular): the G-buffer gets the specular target (its colour and
    /// factor) and the passes that shade rescale the dielectric's Fresnel terms
    /// (`combustion_optics::specular`); scenes without one carry neither.
    pub specular: bool,
    /// Some drawn mesh has vertex colours (glTF COLOR_0): the G-buffer pipelines read the
    /// colour stream and multiply it into the base colour and alpha (objects whose mesh
    /// has none use white).
    pub vertex_colors: bool,
    /// Some drawn mesh is a line list ([`combustion_scene::Topology::Lines`]): the
    /// G-buffer pass gets a pipeline that draws line lists (its surfaces' shaders), in a
    /// round after the surfaces; no other pass draws them.
    pub lines: bool,
    /// Some drawn mesh is a point list ([`combustion_scene::Topology::Points`]): the
    /// G-buffer pass gets a pipeline that draws point lists, its vertex shader built
    /// with `POINTS` (a point size of 1 pixel).
    pub points: bool,
    /// The Fresnel term ([`FresnelModel`]; a shading option, not a scene feature).
    pub fresnel: FresnelModel,
    /// The lighting pass can show a G-buffer channel or a BRDF term instead of radiance
    /// ([`DebugView`]; a shading option).
    pub debug_views: bool,
    /// The parts of the material model the lighting pipeline contains.
    pub features: LightingFeatures,
    /// A measurement floor instead of the real pass
    /// ([`ShadingOptions::measurement_floor`]).
    pub floor: Option<MeasurementFloor>,
    /// The masking–shadowing term ([`ShadingOptions::masking`]).
    pub masking: Masking,
    /// The normal distribution ([`ShadingOptions::distribution`]).
    pub distribution: Distribution,
    /// Environment lighting ([`combustion_scene::Scene::environment`]): the lighting pass
    /// adds the split-sum term of [`environment`].
    pub environment: bool,
    /// glTF occlusion textures attenuate the environment term (scenes with an
    /// environment and a material with an occlusion texture): the G-buffer stores the
    /// occlusion in the emissive target's alpha.
    pub occlusion: bool,
    /// Multiple-scattering energy compensation of the specular lobes
    /// ([`ShadingOptions::energy_compensation`]; a shading option).
    pub energy_compensation: bool,
    /// Shadows ([`ShadingOptions::shadows`]; a shading option): the lighting pass
    /// samples the shadow maps with this many cascades, this filter, for these kinds of
    /// light.
    pub shadows: Option<crate::shadows::ShadowShader>,
    /// The kinds of shadow the scene's lights cast (a scene feature, read when shadows
    /// are on; cleared otherwise, so that it splits no pipeline).
    pub shadow_kinds: crate::shadows::ShadowKinds,
    /// Samples per pixel of the environment's sampled integral
    /// ([`ShadingOptions::environment_samples`]; 0: the split sum, and 0 in scenes
    /// without an environment, so that it splits no pipeline).
    pub environment_samples: u32,
    /// The optional passes the frames run ([`ShadingOptions::optional_passes`]; each
    /// pass's define in every pipeline of the variant).
    pub optional_passes: OptionalPasses,
}

/// A shader feature a variant switches on: its `#define`, declared once, and whether a
/// variant has it. The variant's define list (`ShaderVariant::defines`) and the
/// descriptor bindings a feature enables (`bindings.rs`: `.only_with(FEATURE.define)`)
/// both name it through these constants, so a feature's define cannot be misspelt in
/// one place and right in the other (`bindings::tests` checks every `only_with`).
pub(crate) struct Feature {
    /// The `#define` the shaders test.
    pub(crate) define: &'static str,
    /// Whether `variant` has the feature.
    pub(crate) of: fn(&ShaderVariant) -> bool,
}

/// Emitted radiance (the emissive target's rgb).
pub(crate) const EMISSIVE: Feature = Feature {
    define: "EMISSIVE",
    of: |v| v.emissive,
};
/// GlTF occlusion textures (the emissive target's a).
pub(crate) const OCCLUSION: Feature = Feature {
    define: "OCCLUSION",
    of: |v| v.occlusion,
};
/// The G-buffer's emissive + occlusion target.
pub(crate) const EMISSIVE_OCCLUSION_TARGET: Feature = Feature {
    define: "EMISSIVE_OCCLUSION_TARGET",
    of: |v| v.has_emissive_occlusion_target(),
};
/// Multiple-scattering energy compensation (its table bound).
pub(crate) const ENERGY_COMPENSATION: Feature = Feature {
    define: "ENERGY_COMPENSATION",
    of: |v| v.energy_compensation,
};
/// Material textures sampled by the passes that rasterise surfaces.
pub(crate) const TEXTURES: Feature = Feature {
    define: "TEXTURES",
    of: |v| v.textures,
};
/// KHR_texture_transform (per-slot coordinates mapped per vertex).
pub(crate) const TEXTURE_TRANSFORMS: Feature = Feature {
    define: "TEXTURE_TRANSFORMS",
    of: |v| v.texture_transforms,
};
/// GlTF COLOR_0 multiplied into base colour and alpha.
pub(crate) const VERTEX_COLORS: Feature = Feature {
    define: "VERTEX_COLORS",
    of: |v| v.vertex_colors,
};
/// KHR_materials_transmission (the forward pass reads what lies behind).
pub(crate) const TRANSMISSION: Feature = Feature {
    define: "TRANSMISSION",
    of: |v| v.transmission,
};
/// KHR_materials_volume (the far sides of glass volumes).
pub(crate) const VOLUME: Feature = Feature {
    define: "VOLUME",
    of: |v| v.volume,
};
/// KHR_materials_clearcoat (its G-buffer target and lobe).
pub(crate) const CLEARCOAT: Feature = Feature {
    define: "CLEARCOAT",
    of: |v| v.clearcoat,
};
/// KHR_materials_sheen (its G-buffer target, lobe and tables).
pub(crate) const SHEEN: Feature = Feature {
    define: "SHEEN",
    of: |v| v.sheen,
};
/// KHR_materials_iridescence (its G-buffer target, the film's Fresnel).
pub(crate) const IRIDESCENCE: Feature = Feature {
    define: "IRIDESCENCE",
    of: |v| v.iridescence,
};
/// KHR_materials_specular (its G-buffer target, the rescaled Fresnel).
pub(crate) const SPECULAR: Feature = Feature {
    define: "SPECULAR",
    of: |v| v.specular,
};
/// The environment's split sum or sampled light (its cubes and tables bound).
pub(crate) const ENVIRONMENT: Feature = Feature {
    define: "ENVIRONMENT",
    of: |v| v.environment,
};
/// Shadow maps (their arrays, sampler and cascade table bound).
pub(crate) const SHADOWS: Feature = Feature {
    define: "SHADOWS",
    of: |v| v.shadows.is_some(),
};

/// The boolean features, in the order their defines are listed.
pub(crate) const FEATURES: [&Feature; 13] = [
    &EMISSIVE,
    &OCCLUSION,
    &EMISSIVE_OCCLUSION_TARGET,
    &ENERGY_COMPENSATION,
    &TEXTURES,
    &TEXTURE_TRANSFORMS,
    &VERTEX_COLORS,
    &TRANSMISSION,
    &VOLUME,
    &CLEARCOAT,
    &SHEEN,
    &IRIDESCENCE,
    &SPECULAR,
];

impl ShaderVariant {
    /// Whether the G-buffer has its fourth target: emitted radiance (rgb, EMISSIVE) and
    /// occlusion (a, OCCLUSION).
    pub(crate) fn has_emissive_occlusion_target(&self) -> bool {
        self.emissive || self.occlusion
    }

    /// The `#define`s of this variant.
    pub(crate) fn defines(&self) -> Vec<(&'static str, Option<&'static str>)> {
        let mut defines: Vec<(&'static str, Option<&'static str>)> = FEATURES
            .iter()
            .filter(|f| (f.of)(self))
            .map(|f| (f.define, None))
            .collect();
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
        if (ENVIRONMENT.of)(self) {
            defines.push((ENVIRONMENT.define, None));
            if let Some(count) = environment_samples_define(self.environment_samples) {
                defines.push(("ENVIRONMENT_SAMPLES", Some(count)));
            }
        }
        if let Some(shadows) = self.shadows {
            shadows.defines(&mut defines);
        }
        defines.extend(self.optional_passes.iter().map(|p| (p.define, None)));
        match self.floor {
            None => {}
            Some(MeasurementFloor::Geometry) => defines.push(("FLOOR_GEOMETRY", None)),
            Some(MeasurementFloor::LightingFetch) => defines.push(("FLOOR_FETCH", None)),
            Some(MeasurementFloor::LightingPlainGgx) => defines.push(("FLOOR_PLAIN_GGX", None)),
        }
        defines
    }
}

/// The `ENVIRONMENT_SAMPLES` value of a sample count of [`ENVIRONMENT_SAMPLE_COUNTS`]
/// (`None` for 0, the split sum).
///
/// [`ENVIRONMENT_SAMPLE_COUNTS`]: crate::ENVIRONMENT_SAMPLE_COUNTS
fn environment_samples_define(count: u32) -> Option<&'static str> {
    const NAMES: [&str; 12] = [
        "0", "1", "2", "4", "8", "16", "32", "64", "128", "256", "512", "1024",
    ];
    let i = crate::ENVIRONMENT_SAMPLE_COUNTS
        .iter()
        .position(|&c| c == count)?;
    (count > 0).then_some(NAMES[i])
}

impl ShaderVariant {
    /// The part of the variant the G-buffer shaders read (the emissive target, texture
    /// transforms, cut-outs, vertex colours, points and lines, the clear coat's, the
    /// sheen's, the thin film's and the specular targets and the geometry floor); every other feature
    /// is the lighting pass's.
    pub(crate) fn gbuffer_part(self) -> ShaderVariant {
        ShaderVariant {
            emissive: self.emissive,
            occlusion: self.occlusion,
            textures: self.textures,
            texture_transforms: self.texture_transforms,
            alpha_mask: self.alpha_mask,
            vertex_colors: self.vertex_colors,
            lines: self.lines,
            points: self.points,
            clearcoat: self.clearcoat,
            sheen: self.sheen,
            iridescence: self.iridescence,
            specular: self.specular,
            floor: self.floor.filter(|f| *f == MeasurementFloor::Geometry),
            ..ShaderVariant::default()
        }
    }
}

impl ShadingOptions {
    /// The scene's variant with these options applied.
    pub(crate) fn variant(&self, scene_variant: ShaderVariant) -> ShaderVariant {
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
            fresnel: self.fresnel,
            debug_views,
            features,
            floor: if debug_views {
                None
            } else {
                self.measurement_floor
            },
            masking: self.masking,
            distribution: if debug_views {
                Distribution::Ggx
            } else {
                self.distribution
            },
            energy_compensation: self.energy_compensation && !debug_views,
            shadows: self
                .shadows
                .filter(|_| self.measurement_floor.is_none() || debug_views)
                .map(|s| s.shader(scene_variant.shadow_kinds)),
            shadow_kinds: Default::default(),
            environment_samples: if scene_variant.environment && !debug_views {
                self.environment_samples
            } else {
                0
            },
            optional_passes: self.optional_passes,
            ..scene_variant
        }
    }
}
