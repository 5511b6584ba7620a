#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! glTF materials, textures, samplers and images → [`Material`], [`TextureRef`].

use std::sync::Arc;

use gltf::json;
use gltf::json::validation::Checked;

use super::image::{decode, DecodeError, Decoded, Header};
use super::import::{ImageSource, Importer};
use super::optics_ext::{self, parse_texture_transform, ConductorSpec, TextureInfo};
use super::source::{read_resolved, resolve_uri};
use super::spec_gloss::{metal_rough_from_spec_gloss, parse_spec_gloss, SpecGloss};
use super::{ImportProblem, OPTICS_EXTENSION};
use crate::{
    conductor_from_reflectivity, srgb_decode, srgb_encode, AlphaMode, ColorSpace, Filter, Image,
    Material, Sampler, Texture, TextureRef, TextureSlot, UvTransform, WrapMode,
};

/// glTF's default material (base colour 1, metallic 1, roughness 1), used by primitives
/// without one.
pub(crate) fn default_material() -> Material {
    let base_color = [1.0; 3];
    Material {
        name: "glTF default material".into(),
        base_color,
        metalness: 1.0,
        roughness: 1.0,
        conductor: conductor_from_reflectivity(base_color),
        conductor_from_base_color: true,
        ..Material::default()
    }
}

pub(crate) fn convert_sampler(sampler: Option<&json::texture::Sampler>) -> Sampler {
    use json::texture::{MagFilter, MinFilter, WrappingMode};
    let Some(s) = sampler else {
        return Sampler::default();
    };
    let mag_filter = match s.mag_filter {
        Some(Checked::Valid(MagFilter::Nearest)) => Filter::Nearest,
        _ => Filter::Linear,
    };
    let (min_filter, mipmap_filter) = match s.min_filter {
        Some(Checked::Valid(MinFilter::Nearest)) => (Filter::Nearest, None),
        Some(Checked::Valid(MinFilter::Linear)) => (Filter::Linear, None),
        Some(Checked::Valid(MinFilter::NearestMipmapNearest)) => {
            (Filter::Nearest, Some(Filter::Nearest))
        }
        Some(Checked::Valid(MinFilter::LinearMipmapNearest)) => {
            (Filter::Linear, Some(Filter::Nearest))
        }
        Some(Checked::Valid(MinFilter::NearestMipmapLinear)) => {
            (Filter::Nearest, Some(Filter::Linear))
        }
        _ => (Filter::Linear, Some(Filter::Linear)),
    };
    let wrap = |w: &Checked<WrappingMode>| match w {
        Checked::Valid(WrappingMode::ClampToEdge) => WrapMode::ClampToEdge,
        Checked::Valid(WrappingMode::MirroredRepeat) => WrapMode::MirroredRepeat,
        _ => WrapMode::Repeat,
    };
    Sampler {
        mag_filter,
        min_filter,
        mipmap_filter,
        wrap_u: wrap(&s.wrap_s),
        wrap_v: wrap(&s.wrap_t),
    }
}

impl Importer<'_> {
    fn material_error(&self, index: usize, message: String) -> ImportProblem {
        ImportProblem::Material {
            index,
            name: self.root.materials.get(index).and_then(|m| m.name.clone()),
            message,
        }
    }

    /// A factor glTF bounds to [0, 1]: NaN is an error, out of range is clamped.
    fn unit_factor(&mut self, index: usize, what: &str, x: f32) -> Result<f32, ImportProblem> {
        if !x.is_finite() {
            return Err(self.material_error(index, format!("{what} is not finite ({x})")));
        }
        if !(0.0..=1.0).contains(&x) {
            let clamped = x.clamp(0.0, 1.0);
            self.warn(format!(
                "material {index}: {what} {} is outside [0, 1]; clamped to {clamped}",
                crate::error::readable(x)
            ));
            return Ok(clamped);
        }
        Ok(x)
    }

    pub(crate) fn material(&mut self, index: usize) -> Result<Material, ImportProblem> {
        let root = self.root;
        let m = root
            .materials
            .get(index)
            .ok_or_else(|| self.material_error(index, "does not exist".into()))?;
        let pbr = &m.pbr_metallic_roughness;
        let [r, g, b, a] = pbr.base_color_factor.0;
        let base_color = [
            self.unit_factor(index, "base colour factor", r)?,
            self.unit_factor(index, "base colour factor", g)?,
            self.unit_factor(index, "base colour factor", b)?,
        ];
        let alpha = self.unit_factor(index, "base colour alpha", a)?;
        // glTF: alphaCutoff applies in MASK mode only (0.5 when absent), with a minimum of
        // 0; in OPAQUE mode alpha is ignored.
        let alpha_mode = match m.alpha_mode {
            Checked::Valid(json::material::AlphaMode::Mask) => {
                let cutoff = m.alpha_cutoff.map_or(0.5, |c| c.0);
                if !(cutoff.is_finite() && cutoff >= 0.0) {
                    return Err(self.material_error(
                        index,
                        format!(
                            "alphaCutoff {} is not a finite number ≥ 0",
                            crate::error::readable(cutoff)
                        ),
                    ));
                }
                if cutoff > 1.0 {
                    self.warn(format!(
                        "material {index}: alphaCutoff {} is above 1: no alpha reaches it, \
                         so the material is invisible",
                        crate::error::readable(cutoff)
                    ));
                }
                AlphaMode::Mask { cutoff }
            }
            Checked::Valid(json::material::AlphaMode::Blend) => AlphaMode::Blend,
            _ => AlphaMode::Opaque,
        };
        let metalness = self.unit_factor(index, "metallic factor", pbr.metallic_factor.0)?;
        let roughness = self.unit_factor(index, "roughness factor", pbr.roughness_factor.0)?;
        let mut material = Material {
            name: m
                .name
                .clone()
                .unwrap_or_else(|| format!("material {index}")),
            base_color,
            alpha,
            alpha_mode,
            metalness,
            roughness,
            double_sided: m.double_sided,
            ..Material::default()
        };
        material.base_color_texture = self.texture_info(
            index,
            TextureSlot::BaseColor,
            pbr.base_color_texture.as_ref().map(info_of),
        )?;
        material.metallic_roughness_texture = self.texture_info(
            index,
            TextureSlot::MetallicRoughness,
            pbr.metallic_roughness_texture.as_ref().map(info_of),
        )?;
        if let Some(normal) = &m.normal_texture {
            if !normal.scale.is_finite() {
                return Err(self.material_error(
                    index,
                    format!("normalTexture.scale is not finite ({})", normal.scale),
                ));
            }
            material.normal_scale = normal.scale;
            material.normal_texture = self.texture_info(
                index,
                TextureSlot::Normal,
                Some(TextureInfo {
                    index: normal.index.value(),
                    tex_coord: normal.tex_coord,
                    transform: extension_transform(normal.extensions.as_ref().map(|e| &e.others)),
                }),
            )?;
        }
        if let Some(occlusion) = &m.occlusion_texture {
            material.occlusion_strength =
                self.unit_factor(index, "occlusionTexture.strength", occlusion.strength.0)?;
            material.occlusion_texture = self.texture_info(
                index,
                TextureSlot::Occlusion,
                Some(TextureInfo {
                    index: occlusion.index.value(),
                    tex_coord: occlusion.tex_coord,
                    transform: extension_transform(
                        occlusion.extensions.as_ref().map(|e| &e.others),
                    ),
                }),
            )?;
        }
        // Kept as given even above 1 (glTF bounds it to [0, 1]; Combustion does not).
        let emissive = m.emissive_factor.0;
        if !emissive.iter().all(|x| x.is_finite() && *x >= 0.0) {
            return Err(self.material_error(
                index,
                format!(
                    "emissiveFactor must be non-negative numbers, found {}",
                    crate::message_numbers(&emissive)
                ),
            ));
        }
        material.emissive_factor = emissive;
        material.emissive_texture = self.texture_info(
            index,
            TextureSlot::Emissive,
            m.emissive_texture.as_ref().map(info_of),
        )?;

        let mut optics = optics_ext::MaterialOptics::default();
        if let Some(ext) = &m.extensions {
            if let Some(value) = ext.others.get("KHR_materials_pbrSpecularGlossiness") {
                let spec_gloss =
                    parse_spec_gloss(value, optics_ext::texture_info).map_err(|e| {
                        self.material_error(
                            index,
                            format!("KHR_materials_pbrSpecularGlossiness: {e}"),
                        )
                    })?;
                self.convert_spec_gloss(index, &mut material, spec_gloss)?;
            }
            if let Some(value) = ext.others.get("KHR_materials_ior") {
                // Read from the JSON number itself (f64), not after rounding to f32: 1e-46
                // is not the specification's 0, and 1e300 is not "inf".
                material.dielectric_ior = optics_ext::parse_ior(value)
                    .map_err(|e| self.material_error(index, format!("KHR_materials_ior: {e}")))?;
            }
            if let Some(strength) = &ext.emissive_strength {
                let s = strength.emissive_strength.0;
                if !(s.is_finite() && s >= 0.0) {
                    return Err(self.material_error(
                        index,
                        format!("KHR_materials_emissive_strength: emissiveStrength must be a non-negative number, found {}", crate::message_number(s)),
                    ));
                }
                material.emissive_strength = s;
            }
            if let Some(specular) = &ext.specular {
                material.specular_factor =
                    self.unit_factor(index, "specularFactor", specular.specular_factor.0)?;
                let color = specular.specular_color_factor.0;
                if !color.iter().all(|x| x.is_finite() && *x >= 0.0) {
                    return Err(self.material_error(
                        index,
                        format!(
                            "KHR_materials_specular: specularColorFactor must be non-negative numbers, found {}",
                            crate::message_numbers(&color)
                        ),
                    ));
                }
                material.specular_color_factor = color;
                material.specular_texture = self.texture_info(
                    index,
                    TextureSlot::Specular,
                    specular.specular_texture.as_ref().map(info_of),
                )?;
                material.specular_color_texture = self.texture_info(
                    index,
                    TextureSlot::SpecularColor,
                    specular.specular_color_texture.as_ref().map(info_of),
                )?;
            }
            if let Some(value) = ext.others.get("KHR_materials_unlit") {
                if !value.is_object() {
                    return Err(self.material_error(
                        index,
                        "KHR_materials_unlit must be an object".to_owned(),
                    ));
                }
                material.unlit = true;
            }
            if let Some(value) = ext.others.get("KHR_materials_transmission") {
                let transmission = optics_ext::parse_transmission(value).map_err(|e| {
                    self.material_error(index, format!("KHR_materials_transmission: {e}"))
                })?;
                material.transmission = transmission.factor;
                material.transmission_texture =
                    self.texture_info(index, TextureSlot::Transmission, transmission.texture)?;
            }
            if let Some(value) = ext.others.get("KHR_materials_volume") {
                let (volume, texture) = optics_ext::parse_volume(value).map_err(|e| {
                    self.material_error(index, format!("KHR_materials_volume: {e}"))
                })?;
                material.volume = volume;
                // A thin-walled material has no thickness to scale.
                let texture = texture.filter(|_| volume.is_some());
                material.thickness_texture =
                    self.texture_info(index, TextureSlot::Thickness, texture)?;
            }
            if let Some(value) = ext.others.get("KHR_materials_clearcoat") {
                let coat = optics_ext::parse_clearcoat(value).map_err(|e| {
                    self.material_error(index, format!("KHR_materials_clearcoat: {e}"))
                })?;
                material.clearcoat = coat.factor;
                material.clearcoat_roughness = coat.roughness;
                material.clearcoat_normal_scale = coat.normal_scale;
                // Without a coat its textures are not read.
                if coat.factor > 0.0 {
                    material.clearcoat_texture =
                        self.texture_info(index, TextureSlot::Clearcoat, coat.texture)?;
                    material.clearcoat_roughness_texture = self.texture_info(
                        index,
                        TextureSlot::ClearcoatRoughness,
                        coat.roughness_texture,
                    )?;
                    material.clearcoat_normal_texture = self.texture_info(
                        index,
                        TextureSlot::ClearcoatNormal,
                        coat.normal_texture,
                    )?;
                }
            }
            if let Some(value) = ext.others.get("KHR_materials_sheen") {
                let sheen = optics_ext::parse_sheen(value)
                    .map_err(|e| self.material_error(index, format!("KHR_materials_sheen: {e}")))?;
                material.sheen_color = sheen.color;
                material.sheen_roughness = sheen.roughness;
                // A black sheen is none (the colour texture multiplies the factor).
                if material.has_sheen() {
                    material.sheen_color_texture =
                        self.texture_info(index, TextureSlot::SheenColor, sheen.color_texture)?;
                    material.sheen_roughness_texture = self.texture_info(
                        index,
                        TextureSlot::SheenRoughness,
                        sheen.roughness_texture,
                    )?;
                }
            }
            if let Some(value) = ext.others.get("KHR_materials_iridescence") {
                let read = optics_ext::parse_iridescence(value).map_err(|e| {
                    self.material_error(index, format!("KHR_materials_iridescence: {e}"))
                })?;
                // A factor of 0 is no film (the texture multiplies the factor).
                if read.film.factor > 0.0 {
                    material.iridescence = Some(read.film);
                    material.iridescence_texture =
                        self.texture_info(index, TextureSlot::Iridescence, read.texture)?;
                    material.iridescence_thickness_texture = self.texture_info(
                        index,
                        TextureSlot::IridescenceThickness,
                        read.thickness_texture,
                    )?;
                }
            }
            if let Some(value) = ext.others.get("KHR_materials_anisotropy") {
                let anisotropy = optics_ext::parse_anisotropy(value).map_err(|e| {
                    self.material_error(index, format!("KHR_materials_anisotropy: {e}"))
                })?;
                material.anisotropy_strength = anisotropy.strength;
                material.anisotropy_rotation = anisotropy.rotation;
                material.anisotropy_texture =
                    self.texture_info(index, TextureSlot::Anisotropy, anisotropy.texture)?;
            }
            if let Some(value) = ext.others.get(OPTICS_EXTENSION) {
                let base = self.base;
                let allow = self.options.allow_external_uris;
                let limit = self.options.max_file_bytes;
                let mut read_spectrum = |path: &str| -> Result<String, String> {
                    let resolved = resolve_uri(path, base, allow).map_err(|e| e.to_string())?;
                    let (_, bytes) =
                        read_resolved(path, resolved, limit).map_err(|e| e.to_string())?;
                    String::from_utf8(bytes)
                        .map_err(|_| format!("spectral table `{path}` is not UTF-8 text"))
                };
                let mut warnings = Vec::new();
                let colour = self.options.metal_colour;
                optics =
                    optics_ext::parse_material(value, colour, &mut read_spectrum, &mut warnings)
                        .map_err(|e| {
                            self.material_error(index, format!("{OPTICS_EXTENSION}: {e}"))
                        })?;
                for w in warnings {
                    self.warn(format!("material {index}: {w}"));
                }
            }
        }
        if let Some(ior) = optics.outside_ior {
            material.outside_ior = Some(ior);
        }
        if let Some(w) = optics.polarisation_weight {
            material.polarisation_weight = w;
        }
        if let Some(model) = optics.diffuse_model {
            material.diffuse_model = model;
        }
        match optics.conductor {
            Some(ConductorSpec::Given {
                ior,
                from_base_color,
            }) => {
                material.conductor = ior;
                material.conductor_from_base_color = from_base_color;
            }
            Some(ConductorSpec::FromBaseColor) => {
                material.conductor = conductor_from_reflectivity(material.base_color);
                material.conductor_from_base_color = true;
            }
            None => {
                // glTF's metals: reflectivity = base colour.
                if material.metalness > 0.0 || material.metallic_roughness_texture.is_some() {
                    material.conductor = conductor_from_reflectivity(material.base_color);
                    material.conductor_from_base_color = true;
                }
            }
        }
        Ok(material)
    }

    fn texture_info(
        &mut self,
        material: usize,
        slot: TextureSlot,
        info: Option<TextureInfo>,
    ) -> Result<Option<TextureRef>, ImportProblem> {
        let Some(info) = info else {
            return Ok(None);
        };
        let texture_index = info.index;
        let (transform, tex_coord) = match &info.transform {
            None => (UvTransform::IDENTITY, info.tex_coord),
            Some(value) => {
                let (transform, tex_coord) = parse_texture_transform(value).map_err(|e| {
                    self.material_error(
                        material,
                        format!("{} texture: KHR_texture_transform: {e}", slot.name()),
                    )
                })?;
                (transform, tex_coord.unwrap_or(info.tex_coord))
            }
        };
        if tex_coord > 1 {
            self.warn(format!(
                "material {material}: the {} texture uses texture-coordinate set {tex_coord}; sets 0 and 1 are supported, so the texture is ignored",
                slot.name()
            ));
            return Ok(None);
        }
        // The tangent frame follows TEXCOORD_0 as it is: a tangent-space texture read on
        // another set, rotated or mirrored is sampled right but turned wrong.
        let turns = transform.rotation != 0.0 || transform.scale.iter().any(|&s| s < 0.0);
        if matches!(
            slot,
            TextureSlot::Normal | TextureSlot::ClearcoatNormal | TextureSlot::Anisotropy
        ) && (tex_coord != 0 || turns)
        {
            self.warn(format!(
                "material {material}: the {} texture is read on set {tex_coord} with rotation {} and scale {}; its tangent frame follows TEXCOORD_0 untransformed, so its directions are turned",
                slot.name(),
                crate::message_number(transform.rotation),
                crate::message_numbers(&transform.scale)
            ));
        }
        let root = self.root;
        let texture = root.textures.get(texture_index).ok_or_else(|| {
            self.material_error(
                material,
                format!(
                    "{} texture {texture_index} does not exist ({} textures)",
                    slot.name(),
                    root.textures.len()
                ),
            )
        })?;
        let sampler = match texture.sampler {
            None => None,
            Some(s) => Some(root.samplers.get(s.value()).ok_or_else(|| {
                self.material_error(
                    material,
                    format!(
                        "texture {texture_index}: sampler {} does not exist",
                        s.value()
                    ),
                )
            })?),
        };
        // EXT_texture_webp: its image in place of the fallback `source` (which a file
        // requiring the extension may leave out).
        let webp = texture
            .extensions
            .as_ref()
            .and_then(|e| e.others.get("EXT_texture_webp"));
        let source = match webp {
            Some(ext) => ext
                .get("source")
                .and_then(serde_json::Value::as_u64)
                .and_then(|i| usize::try_from(i).ok())
                .ok_or_else(|| {
                    self.material_error(
                        material,
                        format!(
                            "texture {texture_index}: EXT_texture_webp needs a non-negative integer `source`"
                        ),
                    )
                })?,
            None if texture.source.value() == u32::MAX as usize => {
                return Err(self.material_error(
                    material,
                    format!("texture {texture_index} has no image (`source`)"),
                ))
            }
            None => texture.source.value(),
        };
        let image = self.image(source, slot.color_space())?;
        Ok(Some(TextureRef {
            texture: Texture {
                image,
                sampler: convert_sampler(sampler),
            },
            tex_coord,
            transform,
        }))
    }

    fn image(
        &mut self,
        index: usize,
        color_space: ColorSpace,
    ) -> Result<Arc<Image>, ImportProblem> {
        let root = self.root;
        let json_image = root.images.get(index).ok_or_else(|| ImportProblem::Image {
            index,
            name: None,
            message: format!("does not exist ({} images)", root.images.len()),
        })?;
        let name = json_image.name.clone();
        let err = |message: String| ImportProblem::Image {
            index,
            name: name.clone(),
            message,
        };
        let source = match (&json_image.uri, json_image.buffer_view) {
            (Some(uri), _) => ImageSource::Uri(uri.clone()),
            (None, Some(view)) => ImageSource::BufferView(view.value()),
            (None, None) => return Err(err("has neither a URI nor a buffer view".into())),
        };
        if let Some(image) = self.images.get(&(source.clone(), color_space)) {
            return Ok(image.clone());
        }
        // Each image is held once per colour space it is used in: the first use takes the
        // decoded pixels themselves, another colour space a copy of them; each counts
        // against the budget, and nothing else is kept (no decode cache beside them).
        let used_before = self
            .images
            .iter()
            .find(|((s, _), _)| *s == source)
            .map(|(_, image)| image.clone());
        let decoded = match used_before {
            Some(image) => {
                // Charged before the copy is made.
                self.charge_pixel_count(
                    u64::from(image.width).saturating_mul(u64::from(image.height)),
                )
                .map_err(err)?;
                Decoded {
                    width: image.width,
                    height: image.height,
                    rgba: image.pixels.clone(),
                }
            }
            None => {
                let declared = json_image.mime_type.as_ref().map(|m| m.0.clone());
                let (mime, bytes): (Option<String>, Vec<u8>) = match &source {
                    ImageSource::Uri(uri) => {
                        let resolved =
                            resolve_uri(uri, self.base, self.options.allow_external_uris)?;
                        read_resolved(uri, resolved, self.options.max_file_bytes)?
                    }
                    ImageSource::BufferView(view) => {
                        let (data, range, _) = self.buffers.view(*view).map_err(err)?;
                        let bytes = data.get(range).ok_or_else(|| {
                            err("its buffer view is past its buffer's end".into())
                        })?;
                        (None, bytes.to_vec())
                    }
                };
                let mime = declared.or(mime);
                let (held, budget) = (self.decoded_pixels, self.options.max_decoded_pixels);
                let admit = |header: &Header| admit_decode(header, held, budget);
                let decoded = decode(
                    &bytes,
                    mime.as_deref(),
                    self.options.max_image_dimension,
                    admit,
                )
                .map_err(|e| match e {
                    DecodeError::TooLarge { width, height } => ImportProblem::ImageTooLarge {
                        index,
                        name: name.clone(),
                        width,
                        height,
                        limit: self.options.max_image_dimension,
                    },
                    DecodeError::Other(message) => err(message),
                })?;
                self.charge_pixels(&decoded).map_err(err)?;
                decoded
            }
        };
        let display_name = name.clone().unwrap_or_else(|| match &json_image.uri {
            Some(uri) if !uri.starts_with("data:") => uri.clone(),
            _ => format!("image {index}"),
        });
        let image = Arc::new(Image {
            name: display_name,
            width: decoded.width,
            height: decoded.height,
            color_space,
            pixels: decoded.rgba,
        });
        self.images.insert((source, color_space), image.clone());
        Ok(image)
    }
}

impl Importer<'_> {
    /// A KHR_materials_pbrSpecularGlossiness material's base colour, alpha, metalness and
    /// roughness (`spec_gloss`'s conversion) in place of its metallic-roughness ones: from
    /// the factors alone, or texel by texel into a base colour image (sRGB, the diffuse's
    /// alpha) and a metallic-roughness image (G roughness, B metalness) at the larger of
    /// the two textures' sizes (each sampled at the nearest texel), the factors folded
    /// in. Both textures must be read at the same coordinates (set and transform).
    fn convert_spec_gloss(
        &mut self,
        index: usize,
        material: &mut Material,
        spec_gloss: SpecGloss,
    ) -> Result<(), ImportProblem> {
        let SpecGloss {
            diffuse_factor,
            diffuse_texture,
            specular_factor,
            glossiness_factor,
            specular_glossiness_texture,
        } = spec_gloss;
        let diffuse = self.texture_info(index, TextureSlot::BaseColor, diffuse_texture)?;
        // sRGB specular colour, linear glossiness in alpha: a colour image's encoding.
        let specular = self.texture_info(
            index,
            TextureSlot::SpecularColor,
            specular_glossiness_texture,
        )?;
        let f = |x: f32| f64::from(x);
        let [df0, df1, df2, diffuse_alpha] = diffuse_factor.map(f);
        let [sf0, sf1, sf2] = specular_factor.map(f);
        let convert = |[d0, d1, d2, _]: [f64; 4], [s0, s1, s2, gloss]: [f64; 4]| {
            metal_rough_from_spec_gloss(
                [df0 * d0, df1 * d1, df2 * d2],
                [sf0 * s0, sf1 * s1, sf2 * s2],
                f(glossiness_factor) * gloss,
            )
        };
        let (Some(reference), other) = (match (&diffuse, &specular) {
            (Some(d), s) => (Some(d), s.as_ref()),
            (None, s) => (s.as_ref(), None),
        }) else {
            let (base, metalness, roughness) = convert([1.0; 4], [1.0; 4]);
            material.base_color = base.map(|c| c as f32);
            material.alpha = diffuse_alpha as f32;
            material.metalness = metalness as f32;
            material.roughness = roughness as f32;
            material.base_color_texture = None;
            material.metallic_roughness_texture = None;
            return Ok(());
        };
        if other.is_some_and(|o| {
            o.tex_coord != reference.tex_coord || o.transform != reference.transform
        }) {
            return Err(self.material_error(
                index,
                "KHR_materials_pbrSpecularGlossiness: its diffuseTexture and specularGlossinessTexture are read at different texture coordinates, so they cannot be converted to metallic-roughness texel by texel".into(),
            ));
        }
        let images = [&diffuse, &specular].map(|t| t.as_ref().map(|t| t.texture.image.clone()));
        let width = images.iter().flatten().map(|i| i.width).max().unwrap_or(1);
        let height = images.iter().flatten().map(|i| i.height).max().unwrap_or(1);
        self.charge_pixel_count(
            u64::from(width)
                .saturating_mul(u64::from(height))
                .saturating_mul(2),
        )
        .map_err(|e| self.material_error(index, e))?;
        // The texel of `image` nearest texel (x, y) of the output's grid, as values: RGB
        // decoded from sRGB, alpha linear; white where there is no image.
        let texel = |image: &Option<Arc<Image>>, x: u32, y: u32| -> [f64; 4] {
            let Some(image) = image else {
                return [1.0; 4];
            };
            // x < width and the image at most `width` wide: each product fits in u64 (both
            // sides under 2³²), its quotient under the image's width; likewise y.
            let nearest = |x: u32, side: u32, of: u32| {
                u64::from(x)
                    .saturating_mul(u64::from(side))
                    .checked_div(u64::from(of))
                    .unwrap_or(0)
            };
            let (ix, iy) = (
                nearest(x, image.width, width),
                nearest(y, image.height, height),
            );
            let at = iy
                .saturating_mul(u64::from(image.width))
                .saturating_add(ix)
                .saturating_mul(4);
            let code = |c: u8| f64::from(c) / 255.0;
            // An image's pixels hold width × height RGBA texels (Image's rule); a texel
            // past them would read as white, never panic.
            let Some(&[r, g, b, a]) = usize::try_from(at)
                .ok()
                .and_then(|at| image.pixels.get(at..at.saturating_add(4)))
                .and_then(|p| <&[u8; 4]>::try_from(p).ok())
            else {
                return [1.0; 4];
            };
            [
                srgb_decode(code(r)),
                srgb_decode(code(g)),
                srgb_decode(code(b)),
                code(a),
            ]
        };
        let bytes = (width as usize)
            .saturating_mul(height as usize)
            .saturating_mul(4);
        let mut base_pixels = Vec::with_capacity(bytes);
        let mut metal_rough_pixels = Vec::with_capacity(bytes);
        let byte = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
        for y in 0..height {
            for x in 0..width {
                let [diffuse_image, specular_image] = &images;
                let (d, s) = (texel(diffuse_image, x, y), texel(specular_image, x, y));
                let (base, metalness, roughness) = convert(d, s);
                base_pixels.extend(base.map(|c| byte(srgb_encode(c))));
                let [_, _, _, alpha] = d;
                base_pixels.push(byte(diffuse_alpha * alpha));
                metal_rough_pixels.extend([0, byte(roughness), byte(metalness), 255]);
            }
        }
        let name = |what: &str| {
            format!(
                "{} ({what} converted from specular-glossiness)",
                reference.texture.image.name
            )
        };
        let texture = |image: Image| TextureRef {
            texture: Texture {
                image: Arc::new(image),
                sampler: reference.texture.sampler,
            },
            tex_coord: reference.tex_coord,
            transform: reference.transform,
        };
        material.base_color_texture = Some(texture(Image {
            name: name("base colour"),
            width,
            height,
            color_space: ColorSpace::Srgb,
            pixels: base_pixels,
        }));
        material.metallic_roughness_texture = Some(texture(Image {
            name: name("metallic-roughness"),
            width,
            height,
            color_space: ColorSpace::Linear,
            pixels: metal_rough_pixels,
        }));
        material.base_color = [1.0; 3];
        material.alpha = 1.0;
        material.metalness = 1.0;
        material.roughness = 1.0;
        Ok(())
    }
}

/// The dielectric IOR KHR_materials_ior's `ior: 0` stands for (its Fresnel term is 1 at
/// every angle: an infinite IOR; this is the optics crate's `ETA_MAX`).
pub const KHR_IOR_ZERO_MEANS: f32 = 1.0e4;

impl Importer<'_> {
    /// Counts `decoded`'s pixels against `ImportOptions::max_decoded_pixels`.
    fn charge_pixels(&mut self, decoded: &Decoded) -> Result<(), String> {
        self.charge_pixel_count(u64::from(decoded.width).saturating_mul(u64::from(decoded.height)))
    }

    /// Counts `pixels` more decoded pixels against `ImportOptions::max_decoded_pixels`.
    fn charge_pixel_count(&mut self, pixels: u64) -> Result<(), String> {
        self.decoded_pixels = self.decoded_pixels.saturating_add(pixels);
        if self.decoded_pixels > self.options.max_decoded_pixels {
            return Err(format!(
                "it brings the scene's image pixels (each image once per colour space it is used in) to {}, over the budget of {} for one scene",
                self.decoded_pixels, self.options.max_decoded_pixels
            ));
        }
        Ok(())
    }
}

/// Whether an image whose decoder holds `header.peak_bytes` at once may be decoded
/// while the scene's images hold `held` pixels of `budget`: the decoder's peak counts as
/// pixels of 4 bytes, so the images kept and a decode under way never pass the budget
/// together; after decoding, only the pixels kept stay charged.
fn admit_decode(header: &Header, held: u64, budget: u64) -> Result<(), DecodeError> {
    let at_once = header.peak_bytes.div_ceil(4);
    let total = held.saturating_add(at_once);
    if total <= budget {
        return Ok(());
    }
    let pixels = u64::from(header.width).saturating_mul(u64::from(header.height));
    Err(DecodeError::Other(format!(
        "decoding it ({}×{}{}) takes the room of {at_once} pixels at once, which brings the scene's image pixels (each image once per colour space it is used in) to {total}, over the budget of {budget} for one scene",
        header.width,
        header.height,
        if at_once > pixels {
            format!(", its decoder's work beside its {pixels} pixels")
        } else {
            String::new()
        }
    )))
}

/// The importer's view of a core textureInfo.
fn info_of(t: &json::texture::Info) -> TextureInfo {
    TextureInfo {
        index: t.index.value(),
        tex_coord: t.tex_coord,
        transform: extension_transform(t.extensions.as_ref().map(|e| &e.others)),
    }
}

/// The KHR_texture_transform object among a textureInfo's extensions.
fn extension_transform(
    extensions: Option<&serde_json::Map<String, serde_json::Value>>,
) -> Option<serde_json::Value> {
    extensions
        .and_then(|e| e.get("KHR_texture_transform"))
        .cloned()
}
