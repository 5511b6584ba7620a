#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! The raw-JSON extensions: `COMBUSTION_materials_optics` (the project's, see
//! `docs/gltf.md`) and `KHR_materials_anisotropy` (which the `gltf` crate does not parse).

use serde_json::{Map, Value};

use crate::{ComplexIor, DiffuseModel};

/// The conductor a material's `COMBUSTION_materials_optics` asks for.
#[derive(Debug, PartialEq)]
pub(crate) enum ConductorSpec {
    /// η + ik given (named metal, per-channel values or a spectral table). With
    /// `from_base_color`, the material is still flagged as a base-colour conductor.
    Given {
        ior: ComplexIor,
        from_base_color: bool,
    },
    /// Derive η + ik from the base colour (glTF's behaviour, stated explicitly).
    FromBaseColor,
}

#[derive(Debug, Default, PartialEq)]
pub(crate) struct MaterialOptics {
    pub conductor: Option<ConductorSpec>,
    pub outside_ior: Option<f32>,
    pub polarisation_weight: Option<f32>,
    pub diffuse_model: Option<DiffuseModel>,
}

pub(crate) const DIFFUSE_MODEL_NAMES: [(&str, DiffuseModel); 3] = [
    ("lambert", DiffuseModel::Lambert),
    ("oren-nayar-qualitative", DiffuseModel::OrenNayarQualitative),
    ("oren-nayar-full", DiffuseModel::OrenNayarFull),
];

pub(crate) fn diffuse_model_name(model: DiffuseModel) -> &'static str {
    DIFFUSE_MODEL_NAMES
        .iter()
        .find(|(_, m)| *m == model)
        .map_or("lambert", |(name, _)| name)
}

fn object<'a>(value: &'a Value, what: &str) -> Result<&'a Map<String, Value>, String> {
    value
        .as_object()
        .ok_or_else(|| format!("{what} must be a JSON object"))
}

fn number(value: &Value, what: &str) -> Result<f32, String> {
    let x = value
        .as_f64()
        .ok_or_else(|| format!("{what} must be a number, found {}", short(value)))?;
    let x = x as f32;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!(
            "{what} must be a finite number, found {}",
            short(value)
        ))
    }
}

fn triple(value: &Value, what: &str) -> Result<[f32; 3], String> {
    let Some([r, g, b]) = value.as_array().map(|a| a.as_slice()) else {
        return Err(format!(
            "{what} must be an array of 3 numbers (R, G, B), found {}",
            short(value)
        ));
    };
    Ok([number(r, what)?, number(g, what)?, number(b, what)?])
}

fn short(value: &Value) -> String {
    let mut text = value.to_string();
    if text.len() > 60 {
        // The last character boundary at or before 60 (0 is one).
        let end = (0..=60)
            .rev()
            .find(|&i| text.is_char_boundary(i))
            .unwrap_or(0);
        text.truncate(end);
        text.push('…');
    }
    text
}

fn unknown_keys(map: &Map<String, Value>, known: &[&str], what: &str, warnings: &mut Vec<String>) {
    for key in map.keys() {
        if !known.contains(&key.as_str()) {
            warnings.push(format!("{what}: unknown property `{key}` ignored"));
        }
    }
}

/// The scene-level object (`extensions.COMBUSTION_materials_optics` of the glTF root or
/// of a scene): the outside medium's IOR.
pub(crate) fn parse_scene_level(
    value: &Value,
    warnings: &mut Vec<String>,
) -> Result<Option<f32>, String> {
    let map = object(value, "COMBUSTION_materials_optics")?;
    unknown_keys(
        map,
        &["outsideIor"],
        "COMBUSTION_materials_optics",
        warnings,
    );
    map.get("outsideIor")
        .map(|v| positive(v, "outsideIor"))
        .transpose()
}

fn positive(value: &Value, what: &str) -> Result<f32, String> {
    let x = number(value, what)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!(
            "{what} must be positive, found {}",
            crate::message_number(x)
        ))
    }
}

/// A material's object. `read_spectrum` reads a CSV file named relative to the scene.
pub(crate) fn parse_material(
    value: &Value,
    metal_colour: combustion_spectra::MetalColour,
    read_spectrum: &mut dyn FnMut(&str) -> Result<String, String>,
    warnings: &mut Vec<String>,
) -> Result<MaterialOptics, String> {
    let map = object(value, "COMBUSTION_materials_optics")?;
    unknown_keys(
        map,
        &[
            "conductor",
            "outsideIor",
            "polarisationWeight",
            "diffuseModel",
        ],
        "COMBUSTION_materials_optics",
        warnings,
    );
    let mut optics = MaterialOptics::default();
    if let Some(v) = map.get("outsideIor") {
        optics.outside_ior = Some(positive(v, "outsideIor")?);
    }
    if let Some(v) = map.get("polarisationWeight") {
        let w = number(v, "polarisationWeight")?;
        if !(0.0..=1.0).contains(&w) {
            return Err(format!(
                "polarisationWeight must lie in [0, 1], found {}",
                crate::message_number(w)
            ));
        }
        optics.polarisation_weight = Some(w);
    }
    if let Some(v) = map.get("diffuseModel") {
        let name = v
            .as_str()
            .ok_or_else(|| format!("diffuseModel must be a string, found {}", short(v)))?;
        let model = DIFFUSE_MODEL_NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name.trim()))
            .map(|(_, m)| *m)
            .ok_or_else(|| {
                format!(
                    "unknown diffuseModel `{name}` (known: {})",
                    DIFFUSE_MODEL_NAMES.map(|(n, _)| n).join(", ")
                )
            })?;
        optics.diffuse_model = Some(model);
    }
    if let Some(v) = map.get("conductor") {
        optics.conductor = Some(parse_conductor(v, metal_colour, read_spectrum, warnings)?);
    }
    Ok(optics)
}

fn parse_conductor(
    value: &Value,
    metal_colour: combustion_spectra::MetalColour,
    read_spectrum: &mut dyn FnMut(&str) -> Result<String, String>,
    warnings: &mut Vec<String>,
) -> Result<ConductorSpec, String> {
    let map = object(value, "conductor")?;
    unknown_keys(
        map,
        &["metal", "eta", "k", "spectrum", "colour", "fromBaseColor"],
        "COMBUSTION_materials_optics.conductor",
        warnings,
    );
    let from_base_color = match map.get("fromBaseColor") {
        None => false,
        Some(Value::Bool(b)) => *b,
        Some(v) => {
            return Err(format!(
                "conductor.fromBaseColor must be true or false, found {}",
                short(v)
            ))
        }
    };
    let forms = ["metal", "spectrum", "eta"]
        .iter()
        .filter(|k| map.contains_key(**k))
        .count()
        .saturating_add(usize::from(
            map.contains_key("k") && !map.contains_key("eta"),
        ));
    if forms > 1 {
        return Err("conductor must give exactly one of `metal`, `spectrum` or `eta` + `k`".into());
    }
    // How a spectrum becomes RGB constants: the material's `colour`, else the import's.
    let colour = match map.get("colour") {
        None => metal_colour,
        Some(v) => {
            let name = v.as_str().unwrap_or_default();
            combustion_spectra::MetalColour::ALL
                .into_iter()
                .find(|c| c.name() == name)
                .ok_or_else(|| {
                    format!(
                        "conductor.colour must be \"bands\" or \"colorimetric\", found {}",
                        short(v)
                    )
                })?
        }
    };
    if map.contains_key("colour") && !(map.contains_key("metal") || map.contains_key("spectrum")) {
        return Err(
            "conductor.colour applies to a `metal` or a `spectrum`, not to given constants".into(),
        );
    }
    let reduce = |spectrum: &combustion_spectra::Spectrum, what: &str| {
        let c = colour
            .constants(spectrum)
            .map_err(|e| format!("{what}: {e}"))?;
        let ior = ComplexIor {
            eta: c.eta.map(|x| x as f32),
            k: c.k.map(|x| x as f32),
        };
        // The renderer holds η and k in 32-bit floats: a band's mean that leaves their
        // range (n = 1e-300 rounds to 0) is said here, with the bands' means.
        let means = |v: [f64; 3]| format!("({:.3e}, {:.3e}, {:.3e})", v[0], v[1], v[2]);
        if !ior.eta.iter().all(|&x| x > 0.0 && x.is_finite()) {
            return Err(format!(
                "{what}: its bands' η {} are not positive 32-bit numbers (the smallest is {:e})",
                means(c.eta),
                f32::MIN_POSITIVE
            ));
        }
        if !ior.k.iter().all(|&x| x.is_finite()) {
            return Err(format!(
                "{what}: its bands' k {} exceed 32-bit numbers (the largest is {:e})",
                means(c.k),
                f32::MAX
            ));
        }
        Ok(ior)
    };
    let ior = if let Some(v) = map.get("metal") {
        let name = v
            .as_str()
            .ok_or_else(|| format!("conductor.metal must be a string, found {}", short(v)))?;
        let metal = combustion_spectra::BuiltinMetal::from_name(name).ok_or_else(|| {
            format!(
                "unknown metal `{name}` (built-in: {})",
                combustion_spectra::BuiltinMetal::ALL
                    .map(|m| m.name())
                    .join(", ")
            )
        })?;
        let c = metal.constants(colour);
        Some(ComplexIor {
            eta: c.eta.map(|x| x as f32),
            k: c.k.map(|x| x as f32),
        })
    } else if let Some(v) = map.get("spectrum") {
        let path = v.as_str().ok_or_else(|| {
            format!(
                "conductor.spectrum must be a path string, found {}",
                short(v)
            )
        })?;
        let text = read_spectrum(path)?;
        let spectrum = combustion_spectra::Spectrum::from_csv(&text)
            .map_err(|e| format!("spectral table `{path}`: {e}"))?;
        Some(reduce(&spectrum, &format!("spectral table `{path}`"))?)
    } else if map.contains_key("eta") || map.contains_key("k") {
        let eta = triple(
            map.get("eta").ok_or("conductor.k needs conductor.eta")?,
            "conductor.eta",
        )?;
        let k = triple(
            map.get("k").ok_or("conductor.eta needs conductor.k")?,
            "conductor.k",
        )?;
        if !eta.iter().all(|&x| x > 0.0) {
            return Err(format!(
                "conductor.eta must be positive, found {}",
                crate::message_numbers(&eta)
            ));
        }
        if !k.iter().all(|&x| x >= 0.0) {
            return Err(format!(
                "conductor.k must not be negative, found {}",
                crate::message_numbers(&k)
            ));
        }
        Some(ComplexIor { eta, k })
    } else {
        None
    };
    match (ior, from_base_color) {
        (Some(ior), from_base_color) => Ok(ConductorSpec::Given {
            ior,
            from_base_color,
        }),
        (None, true) => Ok(ConductorSpec::FromBaseColor),
        (None, false) => {
            Err("conductor needs `metal`, `spectrum`, `eta` + `k`, or `fromBaseColor: true`".into())
        }
    }
}

/// A textureInfo as the importer reads it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TextureInfo {
    pub index: usize,
    pub tex_coord: u32,
    /// Its `extensions.KHR_texture_transform` object, unparsed.
    pub transform: Option<Value>,
}

/// Parses a KHR_texture_transform object: the transform (offset, rotation, scale, each
/// finite, defaults 0, 0, 1) and the texCoord it overrides the textureInfo's with.
pub(crate) fn parse_texture_transform(
    value: &Value,
) -> Result<(crate::material::UvTransform, Option<u32>), String> {
    let map = object(value, "KHR_texture_transform")?;
    let pair = |key: &str, default: [f32; 2]| -> Result<[f32; 2], String> {
        match map.get(key) {
            None => Ok(default),
            Some(v) => match v.as_array().map(Vec::as_slice) {
                Some([a, b]) => Ok([number(a, key)?, number(b, key)?]),
                _ => Err(format!(
                    "{key} must be an array of 2 numbers, found {}",
                    short(v)
                )),
            },
        }
    };
    let transform = crate::material::UvTransform {
        offset: pair("offset", [0.0, 0.0])?,
        rotation: map
            .get("rotation")
            .map_or(Ok(0.0), |v| number(v, "rotation"))?,
        scale: pair("scale", [1.0, 1.0])?,
    };
    let tex_coord = match map.get("texCoord") {
        None => None,
        Some(v) => Some(
            v.as_u64()
                .and_then(|t| u32::try_from(t).ok())
                .ok_or_else(|| {
                    format!(
                        "texCoord must be a non-negative integer, found {}",
                        short(v)
                    )
                })?,
        ),
    };
    Ok((transform, tex_coord))
}

/// KHR_materials_ior's `ior` (1.5 when absent): at least 1, or exactly 0, the
/// specular-glossiness compatibility mode whose Fresnel term is 1 everywhere: an
/// infinite IOR, here the largest the optics clamp to (`KHR_IOR_ZERO_MEANS`, ETA_MAX =
/// 1e4: R ≥ 0.9996 but within 0.01° of grazing). Judged on the JSON number as written
/// (f64), then held to what f32 stores.
pub(crate) fn parse_ior(value: &Value) -> Result<f32, String> {
    let map = object(value, "KHR_materials_ior")?;
    let Some(v) = map.get("ior") else {
        return Ok(1.5);
    };
    let ior = v
        .as_f64()
        .ok_or_else(|| format!("ior must be a number, found {}", short(v)))?;
    if ior == 0.0 {
        Ok(super::material::KHR_IOR_ZERO_MEANS)
    } else if ior >= 1.0 && ior <= f64::from(f32::MAX) {
        Ok(ior as f32)
    } else if ior >= 1.0 {
        Err(format!(
            "ior {} is larger than a 32-bit float holds (at most 3.4e38)",
            crate::error::readable(ior)
        ))
    } else {
        Err(format!(
            "ior must be at least 1, or exactly 0 (the specular-glossiness mode), found {}",
            crate::error::readable(ior)
        ))
    }
}

/// KHR_materials_transmission as read: the factor (in [0, 1]; 0 when absent) and its
/// texture.
#[derive(Debug, Default)]
pub(crate) struct Transmission {
    pub factor: f32,
    pub texture: Option<TextureInfo>,
}

pub(crate) fn parse_transmission(value: &Value) -> Result<Transmission, String> {
    let map = object(value, "KHR_materials_transmission")?;
    let mut out = Transmission::default();
    if let Some(v) = map.get("transmissionFactor") {
        out.factor = number(v, "transmissionFactor")?;
        if !(0.0..=1.0).contains(&out.factor) {
            return Err(format!(
                "transmissionFactor must lie in [0, 1], found {}",
                out.factor
            ));
        }
    }
    out.texture = texture_info(map, "transmissionTexture")?;
    Ok(out)
}

/// KHR_materials_volume as read: `None` for a thickness of 0 (glTF: thin-walled), and
/// the thickness texture.
pub(crate) fn parse_volume(
    value: &Value,
) -> Result<(Option<crate::Volume>, Option<TextureInfo>), String> {
    let map = object(value, "KHR_materials_volume")?;
    let thickness = match map.get("thicknessFactor") {
        None => 0.0,
        Some(v) => number(v, "thicknessFactor")?,
    };
    if thickness < 0.0 {
        return Err(format!(
            "thicknessFactor must be at least 0, found {}",
            crate::message_number(thickness)
        ));
    }
    let attenuation_distance = match map.get("attenuationDistance") {
        None => f32::INFINITY,
        Some(v) => {
            let d = number(v, "attenuationDistance")?;
            if d <= 0.0 {
                return Err(format!(
                    "attenuationDistance must be above 0, found {}",
                    crate::error::readable(d)
                ));
            }
            d
        }
    };
    let attenuation_color = match map.get("attenuationColor") {
        None => [1.0; 3],
        Some(v) => {
            let c = triple(v, "attenuationColor")?;
            if !c.iter().all(|x| (0.0..=1.0).contains(x)) {
                return Err(format!(
                    "attenuationColor must lie in [0, 1], found {}",
                    crate::message_numbers(&c)
                ));
            }
            c
        }
    };
    let volume = (thickness > 0.0).then_some(crate::Volume {
        thickness,
        attenuation_distance,
        attenuation_color,
    });
    Ok((volume, texture_info(map, "thicknessTexture")?))
}

/// KHR_materials_clearcoat as read: the factors (in [0, 1]; 0 when absent), the
/// textures and the normal texture's scale (1 when absent).
#[derive(Debug)]
pub(crate) struct Clearcoat {
    pub factor: f32,
    pub roughness: f32,
    pub texture: Option<TextureInfo>,
    pub roughness_texture: Option<TextureInfo>,
    pub normal_texture: Option<TextureInfo>,
    pub normal_scale: f32,
}

pub(crate) fn parse_clearcoat(value: &Value) -> Result<Clearcoat, String> {
    let map = object(value, "KHR_materials_clearcoat")?;
    let unit = |key: &str| -> Result<f32, String> {
        let Some(v) = map.get(key) else {
            return Ok(0.0);
        };
        let x = number(v, key)?;
        if (0.0..=1.0).contains(&x) {
            Ok(x)
        } else {
            Err(format!(
                "{key} must lie in [0, 1], found {}",
                crate::message_number(x)
            ))
        }
    };
    let normal_texture = texture_info(map, "clearcoatNormalTexture")?;
    let normal_scale = match map
        .get("clearcoatNormalTexture")
        .and_then(|t| t.get("scale"))
    {
        None => 1.0,
        Some(v) => number(v, "clearcoatNormalTexture.scale")?,
    };
    Ok(Clearcoat {
        factor: unit("clearcoatFactor")?,
        roughness: unit("clearcoatRoughnessFactor")?,
        texture: texture_info(map, "clearcoatTexture")?,
        roughness_texture: texture_info(map, "clearcoatRoughnessTexture")?,
        normal_texture,
        normal_scale,
    })
}

/// KHR_materials_sheen as read: the colour (black when absent: no sheen), the roughness
/// (0 when absent) and their textures.
#[derive(Debug)]
pub(crate) struct Sheen {
    pub color: [f32; 3],
    pub roughness: f32,
    pub color_texture: Option<TextureInfo>,
    pub roughness_texture: Option<TextureInfo>,
}

pub(crate) fn parse_sheen(value: &Value) -> Result<Sheen, String> {
    let map = object(value, "KHR_materials_sheen")?;
    let color = match map.get("sheenColorFactor") {
        None => [0.0; 3],
        Some(v) => {
            let c = triple(v, "sheenColorFactor")?;
            if !c.iter().all(|x| (0.0..=1.0).contains(x)) {
                return Err(format!(
                    "sheenColorFactor must lie in [0, 1], found {}",
                    crate::message_numbers(&c)
                ));
            }
            c
        }
    };
    let roughness = match map.get("sheenRoughnessFactor") {
        None => 0.0,
        Some(v) => {
            let r = number(v, "sheenRoughnessFactor")?;
            if !(0.0..=1.0).contains(&r) {
                return Err(format!(
                    "sheenRoughnessFactor must lie in [0, 1], found {}",
                    crate::message_number(r)
                ));
            }
            r
        }
    };
    Ok(Sheen {
        color,
        roughness,
        color_texture: texture_info(map, "sheenColorTexture")?,
        roughness_texture: texture_info(map, "sheenRoughnessTexture")?,
    })
}

/// KHR_materials_iridescence as read: the film (its defaults where a value is absent)
/// and its two textures.
#[derive(Debug)]
pub(crate) struct IridescenceRead {
    pub film: crate::Iridescence,
    pub texture: Option<TextureInfo>,
    pub thickness_texture: Option<TextureInfo>,
}

pub(crate) fn parse_iridescence(value: &Value) -> Result<IridescenceRead, String> {
    let map = object(value, "KHR_materials_iridescence")?;
    let defaults = crate::Iridescence::default();
    let read = |key: &str, default: f32, ok: &dyn Fn(f32) -> bool, rule: &str| {
        let Some(v) = map.get(key) else {
            return Ok(default);
        };
        let x = number(v, key)?;
        if ok(x) {
            Ok(x)
        } else {
            Err(format!(
                "{key} must {rule}, found {}",
                crate::error::readable(f64::from(x))
            ))
        }
    };
    let thickness = |x: f32| (0.0..=crate::IRIDESCENCE_THICKNESS_MAX_NM).contains(&x);
    let thickness_rule = format!("lie in [0, {}] nm", crate::IRIDESCENCE_THICKNESS_MAX_NM);
    Ok(IridescenceRead {
        film: crate::Iridescence {
            factor: read(
                "iridescenceFactor",
                defaults.factor,
                &|x| (0.0..=1.0).contains(&x),
                "lie in [0, 1]",
            )?,
            ior: read(
                "iridescenceIor",
                defaults.ior,
                &|x| x >= 1.0,
                "be at least 1",
            )?,
            thickness_min_nm: read(
                "iridescenceThicknessMinimum",
                defaults.thickness_min_nm,
                &thickness,
                &thickness_rule,
            )?,
            thickness_max_nm: read(
                "iridescenceThicknessMaximum",
                defaults.thickness_max_nm,
                &thickness,
                &thickness_rule,
            )?,
        },
        texture: texture_info(map, "iridescenceTexture")?,
        thickness_texture: texture_info(map, "iridescenceThicknessTexture")?,
    })
}

#[derive(Debug, Default, PartialEq)]
pub(crate) struct Anisotropy {
    pub strength: f32,
    pub rotation: f32,
    pub texture: Option<TextureInfo>,
}

pub(crate) fn parse_anisotropy(value: &Value) -> Result<Anisotropy, String> {
    let map = object(value, "KHR_materials_anisotropy")?;
    let mut out = Anisotropy::default();
    if let Some(v) = map.get("anisotropyStrength") {
        out.strength = number(v, "anisotropyStrength")?;
        if !(0.0..=1.0).contains(&out.strength) {
            return Err(format!(
                "anisotropyStrength must lie in [0, 1], found {}",
                out.strength
            ));
        }
    }
    if let Some(v) = map.get("anisotropyRotation") {
        out.rotation = number(v, "anisotropyRotation")?;
    }
    out.texture = texture_info(map, "anisotropyTexture")?;
    Ok(out)
}

/// The textureInfo `map[what]` of an extension read from JSON (`None` when absent).
pub(crate) fn texture_info(
    map: &Map<String, Value>,
    what: &str,
) -> Result<Option<TextureInfo>, String> {
    let Some(v) = map.get(what) else {
        return Ok(None);
    };
    let info = object(v, what)?;
    let index = info
        .get("index")
        .and_then(Value::as_u64)
        .ok_or_else(|| format!("{what} needs a non-negative integer `index`"))?;
    let tex_coord = match info.get("texCoord") {
        None => 0,
        Some(v) => v
            .as_u64()
            .and_then(|t| u32::try_from(t).ok())
            .ok_or_else(|| format!("{what}.texCoord must be a non-negative integer"))?,
    };
    Ok(Some(TextureInfo {
        index: usize::try_from(index).unwrap_or(usize::MAX),
        tex_coord,
        transform: info
            .get("extensions")
            .and_then(|e| e.get("KHR_texture_transform"))
            .cloned(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn parse(value: Value) -> Result<MaterialOptics, String> {
        parse_material(
            &value,
            combustion_spectra::MetalColour::Bands,
            &mut |_| Err("no files here".into()),
            &mut Vec::new(),
        )
    }

    /// `conductor.colour` chooses how a named metal or a spectrum becomes RGB constants
    /// (the import's choice otherwise); it is refused with given constants or a value
    /// that names no method.
    #[test]
    fn a_conductor_chooses_its_metal_colour() {
        use combustion_spectra::{BuiltinMetal, MetalColour};
        let ior_of = |value: Value, default: MetalColour| {
            let optics = parse_material(
                &value,
                default,
                &mut |_| Err("no files here".into()),
                &mut Vec::new(),
            )
            .unwrap();
            match optics.conductor {
                Some(ConductorSpec::Given { ior, .. }) => ior,
                _ => panic!("no constants"),
            }
        };
        let expected = |colour: MetalColour| {
            let c = colour.constants(BuiltinMetal::Gold.spectrum()).unwrap();
            (c.eta.map(|x| x as f32), c.k.map(|x| x as f32))
        };
        let colorimetric = json!({"conductor": {"metal": "Au", "colour": "colorimetric"}});
        let bands = json!({"conductor": {"metal": "Au", "colour": "bands"}});
        let plain = json!({"conductor": {"metal": "Au"}});
        for (value, default, colour) in [
            (
                colorimetric.clone(),
                MetalColour::Bands,
                MetalColour::Colorimetric,
            ),
            (bands, MetalColour::Colorimetric, MetalColour::Bands),
            (
                plain.clone(),
                MetalColour::Colorimetric,
                MetalColour::Colorimetric,
            ),
            (plain, MetalColour::Bands, MetalColour::Bands),
        ] {
            let ior = ior_of(value, default);
            assert_eq!((ior.eta, ior.k), expected(colour));
        }
        let refused = [
            (
                json!({"conductor": {"eta": [1, 1, 1], "k": [2, 2, 2], "colour": "bands"}}),
                "applies to a `metal` or a `spectrum`",
            ),
            (
                json!({"conductor": {"metal": "Au", "colour": "spectral"}}),
                "conductor.colour must be \"bands\" or \"colorimetric\"",
            ),
        ];
        for (value, message) in refused {
            let e = parse(value).unwrap_err();
            assert!(e.contains(message), "{e}");
        }
    }

    #[test]
    fn named_metal_and_explicit_constants() {
        let gold = parse(json!({"conductor": {"metal": "Au"}})).unwrap();
        let Some(ConductorSpec::Given {
            ior,
            from_base_color: false,
        }) = gold.conductor
        else {
            panic!("{gold:?}")
        };
        assert!(ior.k[0] > 2.0 && ior.eta[0] < 0.5, "{ior:?}");
        let explicit = parse(json!({"conductor": {"eta": [1, 2, 3], "k": [0, 1, 2]}, "diffuseModel": "oren-nayar-full", "polarisationWeight": 0.25, "outsideIor": 1.33})).unwrap();
        assert_eq!(explicit.diffuse_model, Some(DiffuseModel::OrenNayarFull));
        assert_eq!(explicit.outside_ior, Some(1.33));
        assert_eq!(explicit.polarisation_weight, Some(0.25));
    }

    #[test]
    fn bad_values_are_named() {
        for (value, needle) in [
            (
                json!({"conductor": {"metal": "unobtainium"}}),
                "unknown metal",
            ),
            (
                json!({"conductor": {"eta": [1, 2], "k": [0, 0, 0]}}),
                "3 numbers",
            ),
            (
                json!({"conductor": {"eta": [1, 2, 3]}}),
                "needs conductor.k",
            ),
            (
                json!({"conductor": {"metal": "gold", "eta": [1, 1, 1], "k": [1, 1, 1]}}),
                "exactly one",
            ),
            (json!({"conductor": {"spectrum": "x.csv"}}), "no files here"),
            (json!({"diffuseModel": "phong"}), "unknown diffuseModel"),
            (json!({"polarisationWeight": 2}), "[0, 1]"),
            (json!({"outsideIor": -1}), "positive"),
            (json!([1]), "JSON object"),
        ] {
            let err = parse(value).unwrap_err();
            assert!(err.contains(needle), "{err}");
        }
    }
}
