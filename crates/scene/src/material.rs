use std::sync::Arc;

use crate::SceneError;

/// Which diffuse BRDF the dielectric part of a material uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum DiffuseModel {
    /// ρ/π.
    #[default]
    Lambert = 0,
    /// Oren–Nayar 1994, qualitative model.
    OrenNayarQualitative = 1,
    /// Oren–Nayar 1994, full model with interreflection.
    OrenNayarFull = 2,
}

impl DiffuseModel {
    /// The command line's name: `lambert`, `oren-nayar-qualitative`, `oren-nayar-full`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Lambert => "lambert",
            Self::OrenNayarQualitative => "oren-nayar-qualitative",
            Self::OrenNayarFull => "oren-nayar-full",
        }
    }

    /// Every model, in discriminant order.
    pub const ALL: [DiffuseModel; 3] = [
        Self::Lambert,
        Self::OrenNayarQualitative,
        Self::OrenNayarFull,
    ];
}

/// How a material's alpha (the base colour factor's alpha × the base colour texture's
/// alpha) is used (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface is opaque everywhere.
    #[default]
    Opaque,
    /// Cut-out: the surface exists where alpha ≥ `cutoff` and is absent (not drawn, casts
    /// no shadow) elsewhere (glTF `alphaCutoff`, 0.5 by default; finite and ≥ 0).
    Mask {
        /// The alpha below which the surface is absent.
        cutoff: f32,
    },
    /// Blended over what is behind ("over", straight alpha). Not rendered yet: such
    /// materials are drawn opaque (the importer warns).
    Blend,
}

impl AlphaMode {
    /// The cut-out threshold of a [`AlphaMode::Mask`] material.
    pub fn cutoff(self) -> Option<f32> {
        match self {
            AlphaMode::Mask { cutoff } => Some(cutoff),
            _ => None,
        }
    }
}

/// A complex index of refraction η + ik per RGB channel: the material's own constants
/// (as tabulated, against vacuum); the surrounding medium's IOR
/// ([`crate::Scene::outside_ior`], [`Material::outside_ior`]) is given separately.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComplexIor {
    /// Real part η per linear RGB channel; finite and above 0.
    pub eta: [f32; 3],
    /// Extinction coefficient k per channel; finite and ≥ 0 (0 for a dielectric).
    pub k: [f32; 3],
}

/// A surface material: the per-pixel factors the G-buffer stores (base colour,
/// metalness, roughness, anisotropy) and the optical constants the lighting pass reads
/// from the material table.
///
/// Factors multiply the matching texture, if any (glTF's rule). Nothing is checked when a
/// material is built; [`Material::validate`] checks the ranges stated on each field.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// A name for messages and tools (not necessarily unique).
    pub name: String,
    /// Linear RGB albedo of the dielectric part.
    pub base_color: [f32; 3],
    /// The base colour factor's alpha ∈ [0, 1], multiplied by the base colour texture's
    /// alpha; read only under [`AlphaMode::Mask`] (and `Blend`).
    pub alpha: f32,
    /// How alpha is used (glTF `alphaMode`).
    pub alpha_mode: AlphaMode,
    /// KHR_materials_unlit: the surface is not lit; it shows its base colour (factor ×
    /// texture × vertex colour) as emitted radiance, W·sr⁻¹·m⁻² per linear channel, and
    /// every other property but alpha is ignored.
    pub unlit: bool,
    /// 0 = dielectric, 1 = conductor; in between blends the two linearly.
    pub metalness: f32,
    /// Perceptual roughness r ∈ [0, 1] (α = r²).
    pub roughness: f32,
    /// Anisotropy strength ∈ [0, 1] (KHR_materials_anisotropy).
    pub anisotropy_strength: f32,
    /// Rotation of the anisotropy direction from the mesh tangent towards the bitangent, radians.
    pub anisotropy_rotation: f32,
    /// Real IOR of the dielectric part.
    pub dielectric_ior: f32,
    /// Complex IOR of the conductor part.
    pub conductor: ComplexIor,
    /// Overrides the scene's outside-medium IOR for this material.
    pub outside_ior: Option<f32>,
    /// Polarisation weight: 0 = s (perpendicular), 1 = p (parallel), 0.5 = unpolarised.
    pub polarisation_weight: f32,
    /// The diffuse BRDF of the dielectric part.
    pub diffuse_model: DiffuseModel,
    /// The conductor part was not measured but derived from the base colour (glTF metals):
    /// `conductor` then holds η, k computed from the base colour *factor* (see
    /// `docs/gltf.md`, "Metals"), and a renderer may instead derive them per pixel from the
    /// textured base colour with the same mapping ([`conductor_from_reflectivity`]).
    pub conductor_from_base_color: bool,
    /// Render both faces (glTF `doubleSided`); false: back faces may be culled.
    pub double_sided: bool,
    /// Base colour (RGB, sRGB-encoded) multiplied into `base_color`.
    pub base_color_texture: Option<TextureRef>,
    /// glTF metallic-roughness texture (linear): B = metalness, G = perceptual roughness,
    /// multiplied into `metalness` and `roughness`.
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Tangent-space normal map (linear, glTF convention: +X right, +Y up).
    pub normal_texture: Option<TextureRef>,
    /// Scale of the normal map's X and Y (glTF `normalTexture.scale`).
    pub normal_scale: f32,
    /// Ambient occlusion (linear, R channel).
    pub occlusion_texture: Option<TextureRef>,
    /// 1 + strength · (occlusion − 1) (glTF `occlusionTexture.strength`), in [0, 1].
    pub occlusion_strength: f32,
    /// Emitted radiance factor (linear RGB); the radiance is
    /// `emissive_factor · emissive_strength · texture`, in W/(sr·m²) per channel.
    pub emissive_factor: [f32; 3],
    /// KHR_materials_emissive_strength (≥ 0).
    pub emissive_strength: f32,
    /// Emission colour (RGB, sRGB-encoded).
    pub emissive_texture: Option<TextureRef>,
    /// KHR_materials_anisotropy texture (linear): RG = direction in tangent space mapped
    /// to [0, 1], B = strength multiplier.
    pub anisotropy_texture: Option<TextureRef>,
    /// KHR_materials_specular `specularFactor` ∈ [0, 1] (1 = unchanged).
    pub specular_factor: f32,
    /// KHR_materials_specular `specularColorFactor` (linear RGB, ≥ 0; may exceed 1).
    pub specular_color_factor: [f32; 3],
    /// KHR_materials_specular strength texture (linear, A channel).
    pub specular_texture: Option<TextureRef>,
    /// KHR_materials_specular colour texture (RGB, sRGB-encoded).
    pub specular_color_texture: Option<TextureRef>,
    /// KHR_materials_transmission `transmissionFactor` ∈ [0, 1]: the share of the light
    /// the dielectric part lets through its surface (what the Fresnel equations
    /// transmit) that passes on through the object, refracted and tinted by the base
    /// colour, instead of scattering diffusely. 0: opaque.
    pub transmission: f32,
    /// KHR_materials_volume: the medium a transmissive surface encloses; `None`:
    /// thin-walled (a shell with no thickness: no refraction offset).
    pub volume: Option<Volume>,
    /// KHR_materials_transmission `transmissionTexture` (linear, R), multiplied into
    /// `transmission`.
    pub transmission_texture: Option<TextureRef>,
    /// KHR_materials_volume `thicknessTexture` (linear, G), multiplied into the volume's
    /// thickness.
    pub thickness_texture: Option<TextureRef>,
    /// KHR_materials_clearcoat `clearcoatFactor` ∈ [0, 1]: the weight of a clear
    /// dielectric coat over the material, of index [`CLEARCOAT_IOR`] with its own
    /// roughness and normal (`combustion_optics::coat`); 0: no coat.
    pub clearcoat: f32,
    /// KHR_materials_clearcoat `clearcoatRoughnessFactor` ∈ [0, 1]: the coat's perceptual
    /// roughness (α = r²).
    pub clearcoat_roughness: f32,
    /// KHR_materials_clearcoat `clearcoatTexture` (linear, R), multiplied into
    /// `clearcoat`.
    pub clearcoat_texture: Option<TextureRef>,
    /// KHR_materials_clearcoat `clearcoatRoughnessTexture` (linear, G), multiplied into
    /// `clearcoat_roughness`.
    pub clearcoat_roughness_texture: Option<TextureRef>,
    /// KHR_materials_clearcoat `clearcoatNormalTexture`: the coat's own tangent-space
    /// normal map (linear, glTF convention); without it the coat follows the geometry's
    /// normal (not the base's normal map).
    pub clearcoat_normal_texture: Option<TextureRef>,
    /// Scale of the coat's normal map's X and Y (`clearcoatNormalTexture.scale`).
    pub clearcoat_normal_scale: f32,
    /// KHR_materials_sheen `sheenColorFactor` (linear RGB in [0, 1]): the colour of the
    /// sheen of fibres over the material (`combustion_optics::sheen`); black: no sheen.
    pub sheen_color: [f32; 3],
    /// KHR_materials_sheen `sheenRoughnessFactor` ∈ [0, 1]: the sheen's perceptual
    /// roughness (α = r²).
    pub sheen_roughness: f32,
    /// KHR_materials_sheen `sheenColorTexture` (RGB, sRGB-encoded), multiplied into
    /// `sheen_color`.
    pub sheen_color_texture: Option<TextureRef>,
    /// KHR_materials_sheen `sheenRoughnessTexture` (linear, A), multiplied into
    /// `sheen_roughness`.
    pub sheen_roughness_texture: Option<TextureRef>,
    /// KHR_materials_iridescence: a thin dielectric film over the material
    /// ([`Iridescence`]); `None`: no film.
    pub iridescence: Option<Iridescence>,
    /// KHR_materials_iridescence `iridescenceTexture` (linear, R), multiplied into
    /// [`Iridescence::factor`].
    pub iridescence_texture: Option<TextureRef>,
    /// KHR_materials_iridescence `iridescenceThicknessTexture` (linear, G): the film's
    /// thickness from [`Iridescence::thickness_min_nm`] (0) to
    /// [`Iridescence::thickness_max_nm`] (1); without it the thickness is the maximum.
    pub iridescence_thickness_texture: Option<TextureRef>,
}

/// KHR_materials_iridescence: a thin dielectric film over a material's base, whose
/// interference colours its Fresnel reflectance (`combustion_optics::thin_film`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iridescence {
    /// `iridescenceFactor` ∈ [0, 1]: how much of the Fresnel reflectance is the film's.
    pub factor: f32,
    /// `iridescenceIor`: the film's real IOR (finite, ≥ 1; 1.3 by default).
    pub ior: f32,
    /// `iridescenceThicknessMinimum`, nm (finite, ≥ 0; 100 by default).
    pub thickness_min_nm: f32,
    /// `iridescenceThicknessMaximum`, nm (finite, ≥ 0; 400 by default). It may be below
    /// the minimum: the texture then maps the other way.
    pub thickness_max_nm: f32,
}

impl Default for Iridescence {
    fn default() -> Self {
        Self {
            factor: 0.0,
            ior: 1.3,
            thickness_min_nm: 100.0,
            thickness_max_nm: 400.0,
        }
    }
}

/// The thickest film accepted, nm: the thickest the optics evaluate
/// (`combustion_optics::thin_film::FILM_THICKNESS_MAX_NM`; a film thicker than a few µm
/// shows no interference).
pub const IRIDESCENCE_THICKNESS_MAX_NM: f32 =
    combustion_optics::thin_film::FILM_THICKNESS_MAX_NM as f32;

/// The index of refraction of a clear coat (KHR_materials_clearcoat fixes it at 1.5).
pub const CLEARCOAT_IOR: f32 = 1.5;

/// KHR_materials_volume: the homogeneous medium inside a transmissive object, whose
/// index is the material's `dielectric_ior`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Volume {
    /// The medium's thickness under the surface (glTF `thicknessFactor`, > 0), in the
    /// mesh's own units: scaled by the object's transform, it is the path a refracted
    /// ray is taken to travel inside when only the surface is known.
    pub thickness: f32,
    /// The distance (world units, metres) light travels in the medium before white
    /// light has become `attenuation_color` (Beer–Lambert); infinite: no absorption.
    pub attenuation_distance: f32,
    /// The colour white light has after `attenuation_distance`, linear RGB in [0, 1].
    pub attenuation_color: [f32; 3],
}

impl Volume {
    /// The absorption coefficient σ = −ln(attenuation colour) / attenuation distance per
    /// channel (1/m): the transmittance over a path of length d is e^(−σ d). Infinite for
    /// a channel of colour 0, 0 without absorption.
    pub fn absorption(&self) -> [f64; 3] {
        let distance = f64::from(self.attenuation_distance);
        self.attenuation_color.map(|c| {
            let c = f64::from(c);
            if c >= 1.0 || distance.is_infinite() {
                0.0
            } else {
                -c.ln() / distance
            }
        })
    }
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".into(),
            base_color: [0.8, 0.8, 0.8],
            alpha: 1.0,
            alpha_mode: AlphaMode::Opaque,
            unlit: false,
            metalness: 0.0,
            roughness: 0.5,
            anisotropy_strength: 0.0,
            anisotropy_rotation: 0.0,
            dielectric_ior: 1.5,
            // A conductor part that is never used while metalness is 0.
            conductor: ComplexIor {
                eta: [1.0; 3],
                k: [0.0; 3],
            },
            outside_ior: None,
            polarisation_weight: 0.5,
            diffuse_model: DiffuseModel::Lambert,
            conductor_from_base_color: false,
            double_sided: false,
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            emissive_factor: [0.0; 3],
            emissive_strength: 1.0,
            emissive_texture: None,
            anisotropy_texture: None,
            specular_factor: 1.0,
            specular_color_factor: [1.0; 3],
            specular_texture: None,
            specular_color_texture: None,
            transmission: 0.0,
            volume: None,
            transmission_texture: None,
            thickness_texture: None,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            clearcoat_texture: None,
            clearcoat_roughness_texture: None,
            clearcoat_normal_texture: None,
            clearcoat_normal_scale: 1.0,
            sheen_color: [0.0; 3],
            sheen_roughness: 0.0,
            sheen_color_texture: None,
            sheen_roughness_texture: None,
            iridescence: None,
            iridescence_texture: None,
            iridescence_thickness_texture: None,
        }
    }
}

impl Material {
    /// Checks every factor's range as its field states (base colour, alpha, metalness,
    /// roughness, anisotropy strength, polarisation weight, occlusion strength,
    /// specular factor, transmission, clearcoat and its roughness, the sheen's colour and
    /// roughness, the iridescence factor in [0, 1]; the iridescence IOR finite and ≥ 1, its
    /// thicknesses in [0, [`IRIDESCENCE_THICKNESS_MAX_NM`]]; a volume's thickness finite and
    /// positive, its attenuation distance positive or infinite and its attenuation
    /// colour in [0, 1]; IORs finite and positive; k, the emissive factor and
    /// strength and the specular colour finite and ≥ 0; the anisotropy rotation and
    /// normal scales finite) and every texture: an image whose size matches its pixels, in the colour
    /// space the slot needs ([`TextureSlot::color_space`]), coordinate set 0 or 1, and
    /// a finite [`UvTransform`]. The first problem is a [`SceneError::Invalid`] naming
    /// the material.
    pub fn validate(&self) -> Result<(), SceneError> {
        let unit = |x: f32| (0.0..=1.0).contains(&x);
        let positive = |x: f32| x.is_finite() && x > 0.0;
        let problem = if !self.base_color.iter().all(|&c| unit(c)) {
            Some("base colour must lie in [0, 1]")
        } else if !unit(self.alpha) {
            Some("alpha must lie in [0, 1]")
        } else if !self
            .alpha_mode
            .cutoff()
            .is_none_or(|c| c.is_finite() && c >= 0.0)
        {
            Some("alpha cutoff must be finite and non-negative")
        } else if !unit(self.metalness) {
            Some("metalness must lie in [0, 1]")
        } else if !unit(self.roughness) {
            Some("roughness must lie in [0, 1]")
        } else if !unit(self.anisotropy_strength) {
            Some("anisotropy strength must lie in [0, 1]")
        } else if !self.anisotropy_rotation.is_finite() {
            Some("anisotropy rotation must be finite")
        } else if !positive(self.dielectric_ior) {
            Some("dielectric IOR must be positive")
        } else if !self.conductor.eta.iter().all(|&x| positive(x)) {
            Some("conductor η must be positive")
        } else if !self.conductor.k.iter().all(|&x| x.is_finite() && x >= 0.0) {
            Some("conductor k must be non-negative")
        } else if !self.outside_ior.is_none_or(positive) {
            Some("outside IOR must be positive")
        } else if !unit(self.polarisation_weight) {
            Some("polarisation weight must lie in [0, 1]")
        } else if !self.normal_scale.is_finite() {
            Some("normal scale must be finite")
        } else if !unit(self.occlusion_strength) {
            Some("occlusion strength must lie in [0, 1]")
        } else if !self
            .emissive_factor
            .iter()
            .all(|&x| x.is_finite() && x >= 0.0)
        {
            Some("emissive factor must be finite and non-negative")
        } else if !(self.emissive_strength.is_finite() && self.emissive_strength >= 0.0) {
            Some("emissive strength must be finite and non-negative")
        } else if !unit(self.specular_factor) {
            Some("specular factor must lie in [0, 1]")
        } else if !self
            .specular_color_factor
            .iter()
            .all(|&x| x.is_finite() && x >= 0.0)
        {
            Some("specular colour factor must be finite and non-negative")
        } else if !unit(self.clearcoat) {
            Some("clearcoat must lie in [0, 1]")
        } else if !unit(self.clearcoat_roughness) {
            Some("clearcoat roughness must lie in [0, 1]")
        } else if !self.sheen_color.iter().all(|&c| unit(c)) {
            Some("sheen colour must lie in [0, 1]")
        } else if !unit(self.sheen_roughness) {
            Some("sheen roughness must lie in [0, 1]")
        } else if !self.iridescence.is_none_or(|i| unit(i.factor)) {
            Some("iridescence factor must lie in [0, 1]")
        } else if !self
            .iridescence
            .is_none_or(|i| i.ior.is_finite() && i.ior >= 1.0)
        {
            Some("iridescence IOR must be finite and at least 1")
        } else if !self.iridescence.is_none_or(|i| {
            [i.thickness_min_nm, i.thickness_max_nm]
                .iter()
                .all(|&d| (0.0..=IRIDESCENCE_THICKNESS_MAX_NM).contains(&d))
        }) {
            Some("iridescence thicknesses must lie in [0, 100000] nm")
        } else if !self.clearcoat_normal_scale.is_finite() {
            Some("clearcoat normal scale must be finite")
        } else if !unit(self.transmission) {
            Some("transmission must lie in [0, 1]")
        } else if !self.volume.is_none_or(|v| positive(v.thickness)) {
            Some("volume thickness must be finite and positive")
        } else if !self
            .volume
            .is_none_or(|v| v.attenuation_distance > 0.0 && !v.attenuation_distance.is_nan())
        {
            Some("volume attenuation distance must be positive (or infinite)")
        } else if !self
            .volume
            .is_none_or(|v| v.attenuation_color.iter().all(|&c| unit(c)))
        {
            Some("volume attenuation colour must lie in [0, 1]")
        } else {
            None
        };
        if let Some(p) = problem {
            return Err(SceneError::Invalid(format!(
                "material `{}`: {p}",
                self.name
            )));
        }
        for (slot, texture) in self.texture_slots() {
            if let Some(texture) = texture {
                texture.validate(slot).map_err(|e| {
                    SceneError::Invalid(format!(
                        "material `{}`: {} texture: {e}",
                        self.name,
                        slot.name()
                    ))
                })?;
            }
        }
        Ok(())
    }

    /// Every texture slot with its texture, in a fixed order.
    pub fn texture_slots(&self) -> [(TextureSlot, Option<&TextureRef>); TEXTURE_SLOTS] {
        [
            (TextureSlot::BaseColor, self.base_color_texture.as_ref()),
            (
                TextureSlot::MetallicRoughness,
                self.metallic_roughness_texture.as_ref(),
            ),
            (TextureSlot::Normal, self.normal_texture.as_ref()),
            (TextureSlot::Occlusion, self.occlusion_texture.as_ref()),
            (TextureSlot::Emissive, self.emissive_texture.as_ref()),
            (TextureSlot::Anisotropy, self.anisotropy_texture.as_ref()),
            (TextureSlot::Specular, self.specular_texture.as_ref()),
            (
                TextureSlot::SpecularColor,
                self.specular_color_texture.as_ref(),
            ),
            (
                TextureSlot::Transmission,
                self.transmission_texture.as_ref(),
            ),
            (TextureSlot::Thickness, self.thickness_texture.as_ref()),
            (TextureSlot::Clearcoat, self.clearcoat_texture.as_ref()),
            (
                TextureSlot::ClearcoatRoughness,
                self.clearcoat_roughness_texture.as_ref(),
            ),
            (
                TextureSlot::ClearcoatNormal,
                self.clearcoat_normal_texture.as_ref(),
            ),
            (TextureSlot::SheenColor, self.sheen_color_texture.as_ref()),
            (
                TextureSlot::SheenRoughness,
                self.sheen_roughness_texture.as_ref(),
            ),
            (TextureSlot::Iridescence, self.iridescence_texture.as_ref()),
            (
                TextureSlot::IridescenceThickness,
                self.iridescence_thickness_texture.as_ref(),
            ),
        ]
    }

    /// Whether the material has a thin film (KHR_materials_iridescence with a factor
    /// above 0).
    pub fn is_iridescent(&self) -> bool {
        self.film().is_some()
    }

    /// The thin film that is there: [`Material::iridescence`] with a factor above 0.
    pub fn film(&self) -> Option<Iridescence> {
        self.iridescence.filter(|i| i.factor > 0.0)
    }

    /// Whether the material changes its dielectric's specular reflection
    /// (KHR_materials_specular): a factor or colour other than 1, or a texture for
    /// either.
    pub fn has_specular(&self) -> bool {
        self.specular_factor != 1.0
            || self.specular_color_factor != [1.0; 3]
            || self.specular_texture.is_some()
            || self.specular_color_texture.is_some()
    }

    /// Whether the material has a sheen (KHR_materials_sheen with a colour other than
    /// black).
    pub fn has_sheen(&self) -> bool {
        self.sheen_color.iter().any(|&c| c > 0.0)
    }

    /// Whether the material has a clear coat (KHR_materials_clearcoat with a factor
    /// above 0).
    pub fn is_coated(&self) -> bool {
        self.clearcoat > 0.0
    }

    /// This material as glTF's points and lines are drawn ([`crate::Topology`]): unlit,
    /// since a point or a line has no surface to light, showing its base colour (factor
    /// × texture × the vertex colour); opaque (alpha is not used) and nothing else of the
    /// material kept. Named `NAME (points and lines)`.
    pub fn for_points_and_lines(&self) -> Material {
        Material {
            name: format!("{} (points and lines)", self.name),
            base_color: self.base_color,
            base_color_texture: self.base_color_texture.clone(),
            unlit: true,
            double_sided: true,
            ..Material::default()
        }
    }

    /// Whether the material is a cut-out ([`AlphaMode::Mask`]): drawn by the pipelines
    /// that test alpha.
    pub fn is_masked(&self) -> bool {
        matches!(self.alpha_mode, AlphaMode::Mask { .. })
    }

    /// Whether the material is blended ([`AlphaMode::Blend`]): its objects are drawn by
    /// the forward pass over what is behind them, not into the G-buffer.
    pub fn is_blended(&self) -> bool {
        matches!(self.alpha_mode, AlphaMode::Blend)
    }

    /// Whether light passes through the material (KHR_materials_transmission with a
    /// factor above 0).
    pub fn is_transmissive(&self) -> bool {
        self.transmission > 0.0
    }

    /// Whether what is behind the material shows through it: blended or transmissive.
    /// The renderer draws such surfaces over the opaque scene (its forward pass), not
    /// into the G-buffer, and they cast no shadow.
    pub fn is_see_through(&self) -> bool {
        self.is_blended() || self.is_transmissive()
    }

    /// Whether the material needs a tangent frame that follows the texture coordinates
    /// (a normal map, the coat's normal map or anisotropy).
    pub fn needs_uv_tangents(&self) -> bool {
        self.normal_texture.is_some()
            || self.clearcoat_normal_texture.is_some()
            || self.anisotropy_strength > 0.0
            || self.anisotropy_texture.is_some()
    }
}

/// How the 8-bit values of an image encode numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// RGB use the sRGB transfer curve (colours: base colour, emissive, specular colour);
    /// alpha is linear. Upload as `R8G8B8A8_SRGB`.
    Srgb,
    /// Plain unorm data (normals, metallic-roughness, occlusion, anisotropy, specular).
    Linear,
}

impl ColorSpace {
    /// Its name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Srgb => "sRGB-encoded colour",
            Self::Linear => "linear data",
        }
    }
}

/// A decoded image: RGBA, 8 bits per channel, rows top to bottom (the first row is at
/// v = 0), no padding. `Eq`, so that comparing two `Arc<Image>`s that are one image
/// returns at once instead of comparing every texel (scene edits compare texture tables).
#[derive(Clone, PartialEq, Eq)]
pub struct Image {
    /// A name for messages (where it came from, when known).
    pub name: String,
    /// Width in pixels, at least 1.
    pub width: u32,
    /// Height in pixels, at least 1.
    pub height: u32,
    /// How its values encode numbers; must be what the texture slot using it needs.
    pub color_space: ColorSpace,
    /// `width · height · 4` bytes.
    pub pixels: Vec<u8>,
}

impl std::fmt::Debug for Image {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Image")
            .field("name", &self.name)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("color_space", &self.color_space)
            .field("pixels", &format_args!("[{} bytes]", self.pixels.len()))
            .finish()
    }
}

impl Image {
    /// Checks that the image has pixels and that `pixels` holds exactly
    /// `width · height · 4` bytes; the message names the image.
    pub fn validate(&self) -> Result<(), String> {
        let expected = u64::from(self.width) * u64::from(self.height) * 4;
        if self.width == 0 || self.height == 0 {
            Err(format!(
                "image `{}` has no pixels ({}×{})",
                self.name, self.width, self.height
            ))
        } else if self.pixels.len() as u64 != expected {
            Err(format!(
                "image `{}` is {}×{} RGBA8 ({expected} bytes) but holds {} bytes",
                self.name,
                self.width,
                self.height,
                self.pixels.len()
            ))
        } else {
            Ok(())
        }
    }
}

/// Texel filter (glTF `magFilter`/`minFilter`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Filter {
    /// The nearest texel (or mip level).
    Nearest,
    /// Linear interpolation between texels (or mip levels).
    Linear,
}

/// Texture-coordinate wrapping outside [0, 1] (glTF `wrapS`/`wrapT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WrapMode {
    /// The image tiles: only the fractional part of the coordinate counts.
    Repeat,
    /// The image tiles, every other copy mirrored.
    MirroredRepeat,
    /// Coordinates are clamped to the edge texels.
    ClampToEdge,
}

/// How a texture is sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Sampler {
    /// Filter when a texel covers more than a pixel (magnification).
    pub mag_filter: Filter,
    /// Filter within a mip level when a texel covers less than a pixel (minification).
    pub min_filter: Filter,
    /// Filter between mip levels; `None`: no mipmaps (glTF `NEAREST`/`LINEAR` min filters).
    pub mipmap_filter: Option<Filter>,
    /// Wrapping along u (glTF `wrapS`).
    pub wrap_u: WrapMode,
    /// Wrapping along v (glTF `wrapT`).
    pub wrap_v: WrapMode,
}

impl Default for Sampler {
    /// glTF's default when a texture names no sampler: repeat, trilinear.
    fn default() -> Self {
        Self {
            mag_filter: Filter::Linear,
            min_filter: Filter::Linear,
            mipmap_filter: Some(Filter::Linear),
            wrap_u: WrapMode::Repeat,
            wrap_v: WrapMode::Repeat,
        }
    }
}

/// An image and how to sample it. Images are shared (`Arc`): the same image may be used
/// by many textures and materials; [`crate::Scene::texture_table`] lists each once.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// The pixels, shared.
    pub image: Arc<Image>,
    /// How they are sampled.
    pub sampler: Sampler,
}

/// KHR_texture_transform: an affine map of a slot's texture coordinates, applied as
/// uv' = offset + R(rotation) · (scale ⊙ uv), with R turning the coordinates
/// counter-clockwise (u right, v down): u' = s_u cos θ u + s_v sin θ v + o_u,
/// v' = −s_u sin θ u + s_v cos θ v + o_v.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Added last, in texture-coordinate units (1 = the image's width or height).
    pub offset: [f32; 2],
    /// Radians, counter-clockwise in (u right, v down) coordinates.
    pub rotation: f32,
    /// Multiplies u and v first (negative values mirror).
    pub scale: [f32; 2],
}

impl UvTransform {
    /// No change: offset 0, rotation 0, scale 1.
    pub const IDENTITY: UvTransform = UvTransform {
        offset: [0.0, 0.0],
        rotation: 0.0,
        scale: [1.0, 1.0],
    };

    /// The map as two rows (a, b, c): u' = a u + b v + c, and likewise v'.
    pub fn rows(&self) -> [[f32; 3]; 2] {
        let (sin, cos) = self.rotation.sin_cos();
        let [su, sv] = self.scale;
        let [ou, ov] = self.offset;
        [[su * cos, sv * sin, ou], [-su * sin, sv * cos, ov]]
    }

    /// `uv` mapped.
    pub fn apply(&self, uv: [f32; 2]) -> [f32; 2] {
        let [r0, r1] = self.rows();
        [
            r0[0] * uv[0] + r0[1] * uv[1] + r0[2],
            r1[0] * uv[0] + r1[1] * uv[1] + r1[2],
        ]
    }

    /// Whether this is exactly [`UvTransform::IDENTITY`].
    pub fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }
}

impl Default for UvTransform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// A material's use of a texture.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureRef {
    /// The image and sampler.
    pub texture: Texture,
    /// Texture-coordinate set: 0 (`Vertex::uv`, glTF TEXCOORD_0) or 1 (`Vertex::uv1`).
    pub tex_coord: u32,
    /// KHR_texture_transform (identity when the file gives none).
    pub transform: UvTransform,
}

impl TextureRef {
    /// Whether sampling it needs more than `Vertex::uv` as it is: set 1 or a transform.
    pub fn maps_coordinates(&self) -> bool {
        self.tex_coord != 0 || !self.transform.is_identity()
    }

    fn validate(&self, slot: TextureSlot) -> Result<(), String> {
        self.texture.image.validate()?;
        if self.tex_coord > 1 {
            return Err(format!(
                "uses texture-coordinate set {}; sets 0 and 1 are supported",
                self.tex_coord
            ));
        }
        let t = &self.transform;
        if !(t.offset.iter().chain(&t.scale).all(|x| x.is_finite()) && t.rotation.is_finite()) {
            return Err(format!(
                "has a non-finite texture transform (offset {}, scale {}, rotation {})",
                crate::message_numbers(&t.offset),
                crate::message_numbers(&t.scale),
                crate::message_number(t.rotation)
            ));
        }
        let image = &self.texture.image;
        if image.color_space != slot.color_space() {
            return Err(format!(
                "image `{}` is {} but this slot needs {}",
                image.name,
                image.color_space.name(),
                slot.color_space().name()
            ));
        }
        Ok(())
    }
}

/// The texture slots of a [`Material`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureSlot {
    /// [`Material::base_color_texture`] (sRGB).
    BaseColor,
    /// [`Material::metallic_roughness_texture`] (linear).
    MetallicRoughness,
    /// [`Material::normal_texture`] (linear).
    Normal,
    /// [`Material::occlusion_texture`] (linear).
    Occlusion,
    /// [`Material::emissive_texture`] (sRGB).
    Emissive,
    /// [`Material::anisotropy_texture`] (linear).
    Anisotropy,
    /// [`Material::specular_texture`] (linear).
    Specular,
    /// [`Material::specular_color_texture`] (sRGB).
    SpecularColor,
    /// [`Material::transmission_texture`] (linear, R).
    Transmission,
    /// [`Material::thickness_texture`] (linear, G).
    Thickness,
    /// [`Material::clearcoat_texture`] (linear, R).
    Clearcoat,
    /// [`Material::clearcoat_roughness_texture`] (linear, G).
    ClearcoatRoughness,
    /// [`Material::clearcoat_normal_texture`] (linear).
    ClearcoatNormal,
    /// [`Material::sheen_color_texture`] (sRGB).
    SheenColor,
    /// [`Material::sheen_roughness_texture`] (linear, A).
    SheenRoughness,
    /// [`Material::iridescence_texture`] (linear, R).
    Iridescence,
    /// [`Material::iridescence_thickness_texture`] (linear, G).
    IridescenceThickness,
}

/// How many texture slots a material has ([`TextureSlot::ALL`]).
pub const TEXTURE_SLOTS: usize = 17;

impl TextureSlot {
    /// Every slot, in the order [`Material::texture_slots`] gives them (the order of the
    /// per-slot arrays of [`crate::TextureTable`] and [`crate::SceneFeatures`]).
    pub const ALL: [TextureSlot; TEXTURE_SLOTS] = [
        TextureSlot::BaseColor,
        TextureSlot::MetallicRoughness,
        TextureSlot::Normal,
        TextureSlot::Occlusion,
        TextureSlot::Emissive,
        TextureSlot::Anisotropy,
        TextureSlot::Specular,
        TextureSlot::SpecularColor,
        TextureSlot::Transmission,
        TextureSlot::Thickness,
        TextureSlot::Clearcoat,
        TextureSlot::ClearcoatRoughness,
        TextureSlot::ClearcoatNormal,
        TextureSlot::SheenColor,
        TextureSlot::SheenRoughness,
        TextureSlot::Iridescence,
        TextureSlot::IridescenceThickness,
    ];

    /// A short lower-case name for messages: `base colour`, `metallic-roughness`, ...
    pub const fn name(self) -> &'static str {
        match self {
            TextureSlot::BaseColor => "base colour",
            TextureSlot::MetallicRoughness => "metallic-roughness",
            TextureSlot::Normal => "normal",
            TextureSlot::Occlusion => "occlusion",
            TextureSlot::Emissive => "emissive",
            TextureSlot::Anisotropy => "anisotropy",
            TextureSlot::Specular => "specular",
            TextureSlot::SpecularColor => "specular colour",
            TextureSlot::Transmission => "transmission",
            TextureSlot::Thickness => "thickness",
            TextureSlot::Clearcoat => "clearcoat",
            TextureSlot::ClearcoatRoughness => "clearcoat roughness",
            TextureSlot::ClearcoatNormal => "clearcoat normal",
            TextureSlot::SheenColor => "sheen colour",
            TextureSlot::SheenRoughness => "sheen roughness",
            TextureSlot::Iridescence => "iridescence",
            TextureSlot::IridescenceThickness => "iridescence thickness",
        }
    }

    /// The colour space glTF prescribes for the slot.
    pub const fn color_space(self) -> ColorSpace {
        match self {
            TextureSlot::BaseColor
            | TextureSlot::Emissive
            | TextureSlot::SpecularColor
            | TextureSlot::SheenColor => ColorSpace::Srgb,
            _ => ColorSpace::Linear,
        }
    }
}

/// The exact sRGB decoding of an encoded value in [0, 1] (IEC 61966-2-1).
pub fn srgb_decode(encoded: f64) -> f64 {
    if encoded <= 0.04045 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// The exact sRGB encoding of a linear value (clamped to [0, 1]; IEC 61966-2-1), the
/// inverse of [`srgb_decode`].
pub fn srgb_encode(linear: f64) -> f64 {
    let c = linear.clamp(0.0, 1.0);
    if c <= 0.0031308 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Complex IOR of a metal given only its reflectivity at normal incidence `r` (per
/// channel, e.g. a glTF base colour), after Gulbrandsen 2014, "Artist Friendly Metallic
/// Fresnel" (JCGT 3(4)): η(r, g) = g·(1−r)/(1+r) + (1−g)·(1+√r)/(1−√r),
/// k = √((r·(η+1)² − (η−1)²)/(1−r)). The edge tint g, which glTF does not give, is
/// chosen per channel so that the unpolarised Fresnel reflectance of η + ik in air is
/// the least-squares fit (weighted by cos θ) to Schlick's curve r + (1−r)(1−cos θ)⁵, the
/// Fresnel term glTF's metallic-roughness model uses. r is clamped to [0, 0.999].
/// Normal-incidence reflectance of the result equals r by construction.
///
/// The fit is a minimisation per channel (about 20 evaluations of its misfit), and the f64
/// reference calls this per shading point of every metal whose optical constants come
/// from its base colour, mostly with the same few colours: each thread remembers the
/// results for up to 16 384 inputs it was given (a pure
/// function of the input's bits, so a remembered result is the one computed again).
pub fn conductor_from_reflectivity(r: [f32; 3]) -> ComplexIor {
    thread_local! {
        static REMEMBERED: std::cell::RefCell<std::collections::HashMap<[u32; 3], ComplexIor>> =
            std::cell::RefCell::default();
    }
    let key = r.map(f32::to_bits);
    if let Some(known) = REMEMBERED.with_borrow(|known| known.get(&key).copied()) {
        return known;
    }
    let ior = fit_conductor_to_reflectivity(r);
    REMEMBERED.with_borrow_mut(|known| {
        if known.len() >= REMEMBERED_REFLECTIVITIES {
            known.clear();
        }
        known.insert(key, ior);
    });
    ior
}

/// How many inputs of [`conductor_from_reflectivity`] each thread remembers (then it
/// forgets them all and starts again): 16 384 entries of 36 bytes.
const REMEMBERED_REFLECTIVITIES: usize = 16_384;

fn fit_conductor_to_reflectivity(r: [f32; 3]) -> ComplexIor {
    let mut eta = [1.0f32; 3];
    let mut k = [0.0f32; 3];
    for c in 0..3 {
        let r = f64::from(r[c]);
        let r = if r.is_finite() {
            r.clamp(0.0, 0.999)
        } else {
            0.0
        };
        let g = gulbrandsen::best_edge_tint(r);
        let (n, kk) = gulbrandsen::eta_k(r, g);
        eta[c] = n as f32;
        k[c] = kk as f32;
    }
    ComplexIor { eta, k }
}

mod gulbrandsen {
    /// η, k for reflectivity r ∈ [0, 0.999] and edge tint g ∈ [0, 1].
    pub fn eta_k(r: f64, g: f64) -> (f64, f64) {
        let sr = r.sqrt();
        let n_min = (1.0 - r) / (1.0 + r);
        let n_max = (1.0 + sr) / (1.0 - sr);
        let n = g * n_min + (1.0 - g) * n_max;
        let k2 = (r * (n + 1.0) * (n + 1.0) - (n - 1.0) * (n - 1.0)) / (1.0 - r);
        (n, k2.max(0.0).sqrt())
    }

    /// Unpolarised reflectance of η + ik seen from air at cos θ (the full Fresnel
    /// equations for a conductor).
    pub fn fresnel(cos: f64, n: f64, k: f64) -> f64 {
        let cos2 = cos * cos;
        let sin2 = 1.0 - cos2;
        let a = n * n - k * k - sin2;
        let b = (a * a + 4.0 * n * n * k * k).sqrt();
        let a2b2 = b; // a² + b² of the usual notation
        let a_ = ((a2b2 + a) / 2.0).max(0.0).sqrt();
        let t1 = a2b2 + cos2;
        let t2 = 2.0 * a_ * cos;
        let rs = (t1 - t2) / (t1 + t2);
        let t3 = cos2 * a2b2 + sin2 * sin2;
        let t4 = t2 * sin2;
        let rp = rs * (t3 - t4) / (t3 + t4);
        0.5 * (rs + rp)
    }

    fn misfit(r: f64, g: f64) -> f64 {
        let (n, k) = eta_k(r, g);
        const N: usize = 64;
        (0..N)
            .map(|i| {
                let cos = (i as f64 + 0.5) / N as f64;
                let schlick = r + (1.0 - r) * (1.0 - cos).powi(5);
                let d = fresnel(cos, n, k) - schlick;
                d * d * cos
            })
            .sum()
    }

    /// The edge tint minimising [`misfit`]: a coarse scan brackets the minimum (the
    /// misfit has one minimum over g ∈ [0, 1] for every r, checked on a dense grid by
    /// the test below), then Brent's method (parabolic steps, golden-section where a
    /// parabola is not trusted) narrows it to 1e-9 in g — about as far as the misfit's
    /// values can tell neighbouring tints apart (it is flat to second order there).
    /// About 20 evaluations of the misfit where a scan and a golden-section search took
    /// 113: the f64 reference evaluates this per shading point of a textured metal.
    pub fn best_edge_tint(r: f64) -> f64 {
        if r <= 0.0 {
            return 1.0;
        }
        let steps = 8;
        let (best, best_misfit) = (0..=steps)
            .map(|i| (i, misfit(r, f64::from(i) / f64::from(steps))))
            .fold((0, f64::INFINITY), |best, next| {
                if next.1 < best.1 {
                    next
                } else {
                    best
                }
            });
        let step = 1.0 / f64::from(steps);
        let lo = (f64::from(best) * step - step).max(0.0);
        let hi = (f64::from(best) * step + step).min(1.0);
        let g = brent_minimum(|g| misfit(r, g), lo, hi, 1e-9);
        // A minimum at an end of [0, 1] is the scan's own point: Brent stops within its
        // tolerance of it.
        if misfit(r, g) < best_misfit {
            g
        } else {
            f64::from(best) * step
        }
    }

    /// The minimum of `f` on [lo, hi] (one minimum there) to within about `tolerance`,
    /// by Brent's method (R. P. Brent, "Algorithms for Minimization without Derivatives",
    /// 1973, ch. 5): a parabola through the three best points where it steps inside the
    /// bracket and less than half the step before last, otherwise a golden-section step.
    pub(super) fn brent_minimum(f: impl Fn(f64) -> f64, lo: f64, hi: f64, tolerance: f64) -> f64 {
        // (3 − √5)/2: the golden section's smaller part.
        const GOLDEN: f64 = 0.381_966_011_250_105_1;
        let (mut lo, mut hi) = (lo, hi);
        // x: the best point so far; w: the second best; v: the previous w.
        let mut x = lo + GOLDEN * (hi - lo);
        let (mut w, mut v) = (x, x);
        let mut fx = f(x);
        let (mut fw, mut fv) = (fx, fx);
        // step: the last step; step_before: the one before it.
        let (mut step, mut step_before) = (0.0f64, 0.0f64);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            let tol1 = tolerance + 1e-12 * x.abs();
            let tol2 = 2.0 * tol1;
            if (x - mid).abs() <= tol2 - 0.5 * (hi - lo) {
                break;
            }
            let mut parabolic = None;
            if step_before.abs() > tol1 {
                let r = (x - w) * (fx - fv);
                let q = (x - v) * (fx - fw);
                let mut p = (x - v) * q - (x - w) * r;
                let mut q = 2.0 * (q - r);
                if q > 0.0 {
                    p = -p;
                }
                q = q.abs();
                if p.abs() < (0.5 * q * step_before).abs() && p > q * (lo - x) && p < q * (hi - x) {
                    parabolic = Some(p / q);
                }
            }
            match parabolic {
                Some(d) => {
                    step_before = step;
                    step = d;
                    let u = x + step;
                    if u - lo < tol2 || hi - u < tol2 {
                        step = tol1.copysign(mid - x);
                    }
                }
                None => {
                    step_before = if x >= mid { lo - x } else { hi - x };
                    step = GOLDEN * step_before;
                }
            }
            let u = if step.abs() >= tol1 {
                x + step
            } else {
                x + tol1.copysign(step)
            };
            let fu = f(u);
            if fu <= fx {
                if u >= x {
                    lo = x;
                } else {
                    hi = x;
                }
                (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
            } else {
                if u < x {
                    lo = u;
                } else {
                    hi = u;
                }
                if fu <= fw || w == x {
                    (v, fv, w, fw) = (w, fw, u, fu);
                } else if fu <= fv || v == x || v == w {
                    (v, fv) = (u, fu);
                }
            }
        }
        x
    }

    #[cfg(test)]
    mod tests {
        use super::{best_edge_tint, brent_minimum, misfit};

        /// Over r ∈ (0, 0.999] the misfit has one minimum in g (what the coarse scan's
        /// bracket relies on), and the tint found is that minimum: no tint on a 401-point
        /// grid, nor 1e-6 either side of it, fits Schlick's curve better.
        #[test]
        fn the_edge_tint_is_the_misfits_one_minimum() {
            for j in 1..=100 {
                let r = 0.999 * f64::from(j) / 100.0;
                let grid: Vec<f64> = (0..=400).map(|i| misfit(r, f64::from(i) / 400.0)).collect();
                let interior = (1..400)
                    .filter(|&i| grid[i] < grid[i - 1] && grid[i] <= grid[i + 1])
                    .count();
                let at_ends = usize::from(grid[0] < grid[1]) + usize::from(grid[400] < grid[399]);
                assert_eq!(interior + at_ends, 1, "r {r}: more than one minimum");
                let g = best_edge_tint(r);
                let found = misfit(r, g);
                let smallest = grid.iter().copied().fold(f64::INFINITY, f64::min);
                assert!(
                    found <= smallest,
                    "r {r}: g {g} misfit {found} > grid {smallest}"
                );
                for nearby in [g - 1e-6, g + 1e-6] {
                    if (0.0..=1.0).contains(&nearby) {
                        assert!(found <= misfit(r, nearby), "r {r}: g {g} vs {nearby}");
                    }
                }
            }
        }

        /// Brent's method on functions whose minimum is known: inside, and at either end.
        #[test]
        fn brent_finds_known_minima() {
            let inside = brent_minimum(|x| (x - 0.3).powi(2) + 1.0, 0.0, 1.0, 1e-9);
            assert!((inside - 0.3).abs() < 1e-6, "{inside}");
            let at_hi = brent_minimum(|x| -x, 0.0, 1.0, 1e-9);
            assert!(at_hi > 1.0 - 1e-8 && at_hi <= 1.0, "{at_hi}");
            let at_lo = brent_minimum(|x| x.exp(), 0.25, 0.5, 1e-9);
            assert!((0.25..0.25 + 1e-8).contains(&at_lo), "{at_lo}");
            let quartic = brent_minimum(|x| (x - 0.7).powi(4), 0.0, 1.0, 1e-9);
            assert!((quartic - 0.7).abs() < 1e-3, "{quartic}");
        }
    }
}

#[cfg(test)]
mod conductor_from_reflectivity_tests {
    use super::{
        conductor_from_reflectivity, fit_conductor_to_reflectivity, REMEMBERED_REFLECTIVITIES,
    };

    /// A remembered fit is the fit computed again, bit for bit: for inputs met once,
    /// met again, and met again after more than the thread remembers came between.
    #[test]
    fn a_remembered_fit_is_the_fit() {
        let input = |i: usize| {
            let t = i as f32 / (REMEMBERED_REFLECTIVITIES + 100) as f32;
            [t, 1.0 - t, 0.5 * t + 0.25]
        };
        let bits = |ior: super::ComplexIor| (ior.eta.map(f32::to_bits), ior.k.map(f32::to_bits));
        for round in 0..2 {
            for i in (0..REMEMBERED_REFLECTIVITIES + 100)
                .step_by(97)
                .chain([3, 3, 5])
            {
                let r = input(i);
                assert_eq!(
                    bits(conductor_from_reflectivity(r)),
                    bits(fit_conductor_to_reflectivity(r)),
                    "round {round}, input {r:?}"
                );
            }
        }
        // More distinct inputs than it remembers: it starts again, and still agrees.
        for i in 0..REMEMBERED_REFLECTIVITIES + 10 {
            let r = [i as f32 / 1e5, 0.5, 0.9];
            let _ = conductor_from_reflectivity(r);
        }
        let r = [0.02, 0.5, 0.9];
        assert_eq!(
            bits(conductor_from_reflectivity(r)),
            bits(fit_conductor_to_reflectivity(r))
        );
    }
}

#[cfg(test)]
mod uv_transform_tests {
    use super::UvTransform;

    /// The KHR_texture_transform specification's example: offset (0, 1), rotation 90°,
    /// scale ½ "utilizes only the lower left quadrant of the source image, rotated
    /// clockwise 90°": the unit square's corners land on u ∈ [0, ½], v ∈ [½, 1].
    #[test]
    fn the_specifications_example_maps_onto_the_lower_left_quadrant() {
        let t = UvTransform {
            offset: [0.0, 1.0],
            rotation: std::f32::consts::FRAC_PI_2,
            scale: [0.5, 0.5],
        };
        let close =
            |a: [f32; 2], b: [f32; 2]| (a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6;
        // (u, v) → (½ v, 1 − ½ u)
        for (uv, expected) in [
            ([0.0, 0.0], [0.0, 1.0]),
            ([1.0, 0.0], [0.0, 0.5]),
            ([0.0, 1.0], [0.5, 1.0]),
            ([1.0, 1.0], [0.5, 0.5]),
        ] {
            assert!(close(t.apply(uv), expected), "{uv:?} → {:?}", t.apply(uv));
        }
        assert!(UvTransform::IDENTITY.is_identity());
        assert_eq!(UvTransform::IDENTITY.apply([0.3, 0.7]), [0.3, 0.7]);
        // The inverted-T example: offset (0, 1), scale (1, −1) gives a bottom-left origin.
        let flip = UvTransform {
            offset: [0.0, 1.0],
            rotation: 0.0,
            scale: [1.0, -1.0],
        };
        assert_eq!(flip.apply([0.25, 0.0]), [0.25, 1.0]);
    }
}
