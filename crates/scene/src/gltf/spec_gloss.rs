#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! KHR_materials_pbrSpecularGlossiness (archived by Khronos, still in circulation),
//! converted to the metallic-roughness model at import: per texel where the material has
//! textures, so the renderer shades one model.
//!
//! The conversion is the one Khronos published with the extension's retirement (the glTF
//! repository's "convert between workflows" example, also Babylon.js's): with the
//! dielectric F₀ = 0.04 of metallic-roughness glTF and the perceived brightness
//! B(c) = √(0.299 r² + 0.587 g² + 0.114 b²),
//!
//! - the metalness m solves 0.04 m² + (B(d) (1 − s_max)/0.96 + B(s) − 0.08) m + 0.04 −
//!   B(s) = 0 (0 where B(s) ≤ 0.04), d the diffuse and s the specular colour,
//!   s_max = max(s);
//! - the base colour blends d (1 − s_max)/(0.96 (1 − m)) and (s − 0.04 (1 − m))/m by m²,
//!   clamped to [0, 1];
//! - the roughness is 1 − glossiness; the alpha is the diffuse's.
//!
//! A pure dielectric (s = 0.04) keeps its diffuse colour as base colour, metalness 0; a
//! pure metal (d = 0) gets its specular colour, metalness 1; in between the result is
//! the published fit, not an exact inverse (within 0.002 of the metalness and 0.001 of
//! the base colour of the half-metals tried; this module's tests).

use serde_json::{Map, Value};

use super::optics_ext::TextureInfo;

/// The extension as read: factors (glTF's defaults when absent) and textures.
#[derive(Debug)]
pub(crate) struct SpecGloss {
    /// `diffuseFactor`: linear RGBA, each in [0, 1].
    pub diffuse_factor: [f32; 4],
    /// `diffuseTexture`: sRGB RGB, linear alpha.
    pub diffuse_texture: Option<TextureInfo>,
    /// `specularFactor`: linear RGB, each in [0, 1].
    pub specular_factor: [f32; 3],
    /// `glossinessFactor` ∈ [0, 1].
    pub glossiness_factor: f32,
    /// `specularGlossinessTexture`: sRGB specular RGB, linear glossiness A.
    pub specular_glossiness_texture: Option<TextureInfo>,
}

/// Reads the extension's object; a factor that is not numbers in [0, 1] is an error.
pub(crate) fn parse_spec_gloss(
    value: &Value,
    texture_info: impl Fn(&Map<String, Value>, &str) -> Result<Option<TextureInfo>, String>,
) -> Result<SpecGloss, String> {
    let map = value
        .as_object()
        .ok_or("KHR_materials_pbrSpecularGlossiness must be a JSON object")?;
    let numbers = |key: &str, default: &[f32]| -> Result<Vec<f32>, String> {
        let Some(v) = map.get(key) else {
            return Ok(default.to_vec());
        };
        let list: Vec<f32> = match v {
            Value::Array(items) if items.len() == default.len() => items
                .iter()
                .map(|x| x.as_f64().map(|x| x as f32))
                .collect::<Option<_>>()
                .ok_or_else(|| format!("{key} must be {} numbers", default.len()))?,
            Value::Number(n) if default.len() == 1 => vec![n.as_f64().unwrap_or(f64::NAN) as f32],
            _ => {
                return Err(if default.len() == 1 {
                    format!("{key} must be a number")
                } else {
                    format!("{key} must be an array of {} numbers", default.len())
                })
            }
        };
        if list.iter().all(|x| (0.0..=1.0).contains(x)) {
            Ok(list)
        } else {
            Err(format!(
                "{key} must lie in [0, 1], found {}",
                crate::message_numbers(&list)
            ))
        }
    };
    // `numbers` gives as many as the default has (else an error).
    let [diffuse_r, diffuse_g, diffuse_b, diffuse_a] = numbers("diffuseFactor", &[1.0; 4])?[..]
    else {
        return Err("diffuseFactor must be 4 numbers".into());
    };
    let [specular_r, specular_g, specular_b] = numbers("specularFactor", &[1.0; 3])?[..] else {
        return Err("specularFactor must be 3 numbers".into());
    };
    let [glossiness] = numbers("glossinessFactor", &[1.0])?[..] else {
        return Err("glossinessFactor must be a number".into());
    };
    Ok(SpecGloss {
        diffuse_factor: [diffuse_r, diffuse_g, diffuse_b, diffuse_a],
        diffuse_texture: texture_info(map, "diffuseTexture")?,
        specular_factor: [specular_r, specular_g, specular_b],
        glossiness_factor: glossiness,
        specular_glossiness_texture: texture_info(map, "specularGlossinessTexture")?,
    })
}

/// The dielectric F₀ of the metallic-roughness model (IOR 1.5 in air).
const DIELECTRIC_SPECULAR: f64 = 0.04;

fn perceived_brightness([r, g, b]: [f64; 3]) -> f64 {
    (0.299 * r * r + 0.587 * g * g + 0.114 * b * b).sqrt()
}

/// The metallic-roughness material of one texel (or of the factors) of a
/// specular-glossiness one: (base colour, metalness, roughness) from the linear diffuse
/// and specular colours and the glossiness (module documentation).
pub fn metal_rough_from_spec_gloss(
    diffuse: [f64; 3],
    specular: [f64; 3],
    glossiness: f64,
) -> ([f64; 3], f64, f64) {
    let one_minus_specular = 1.0 - specular.iter().copied().fold(0.0, f64::max);
    let (d, s) = (
        perceived_brightness(diffuse),
        perceived_brightness(specular),
    );
    // At or below the dielectric's F₀ (to rounding: a specular factor of exactly 0.04
    // has a brightness a few ulps either side of it) the texel is a dielectric.
    let metalness = if s <= DIELECTRIC_SPECULAR * (1.0 + 1e-12) {
        0.0
    } else {
        let a = DIELECTRIC_SPECULAR;
        let b = d * one_minus_specular / (1.0 - a) + s - 2.0 * a;
        let c = a - s;
        let discriminant = (b * b - 4.0 * a * c).max(0.0);
        ((-b + discriminant.sqrt()) / (2.0 * a)).clamp(0.0, 1.0)
    };
    let epsilon = 1e-6;
    let channel = |diffuse: f64, specular: f64| {
        let from_diffuse = diffuse * one_minus_specular
            / (1.0 - DIELECTRIC_SPECULAR)
            / (1.0 - metalness).max(epsilon);
        let from_specular =
            (specular - DIELECTRIC_SPECULAR * (1.0 - metalness)) / metalness.max(epsilon);
        let t = metalness * metalness;
        (from_diffuse + (from_specular - from_diffuse) * t).clamp(0.0, 1.0)
    };
    let ([dr, dg, db], [sr, sg, sb]) = (diffuse, specular);
    let base = [channel(dr, sr), channel(dg, sg), channel(db, sb)];
    (base, metalness, (1.0 - glossiness).clamp(0.0, 1.0))
}

#[cfg(test)]
#[allow(clippy::indexing_slicing)] // the tests' own arrays, indexed by their own ranges
mod tests {
    use super::*;

    /// The specular-glossiness colours that shade as a metallic-roughness material:
    /// the same F₀ = mix(0.04, base, m) (glTF 2.0, appendix B) and the same diffuse
    /// albedo, base (1 − 0.04)(1 − m) there and diffuse (1 − max F₀) here.
    fn spec_gloss_of(base: [f64; 3], metalness: f64) -> ([f64; 3], [f64; 3]) {
        let specular = base.map(|b| DIELECTRIC_SPECULAR + (b - DIELECTRIC_SPECULAR) * metalness);
        let one_minus = 1.0 - specular.iter().copied().fold(0.0, f64::max);
        (
            base.map(|b| b * (1.0 - DIELECTRIC_SPECULAR) * (1.0 - metalness) / one_minus),
            specular,
        )
    }

    /// Pure dielectrics and pure metals come back as they were; glossiness is
    /// 1 − roughness.
    #[test]
    fn dielectrics_and_metals_come_back() {
        for base in [
            [0.8, 0.2, 0.1],
            [0.05, 0.5, 0.9],
            [1.0, 1.0, 1.0],
            [0.02; 3],
            [0.0; 3],
        ] {
            let (diffuse, specular) = spec_gloss_of(base, 0.0);
            let (back, metalness, roughness) = metal_rough_from_spec_gloss(diffuse, specular, 0.7);
            assert_eq!(metalness, 0.0);
            assert!((roughness - 0.3).abs() < 1e-12);
            for c in 0..3 {
                assert!((back[c] - base[c]).abs() < 1e-12, "{base:?} → {back:?}");
            }
        }
        for base in [[0.95, 0.64, 0.54], [0.91, 0.92, 0.92], [0.3, 0.3, 0.3]] {
            let (diffuse, specular) = spec_gloss_of(base, 1.0);
            let (back, metalness, _) = metal_rough_from_spec_gloss(diffuse, specular, 1.0);
            assert!((metalness - 1.0).abs() < 1e-9, "{base:?}: {metalness}");
            for c in 0..3 {
                assert!((back[c] - base[c]).abs() < 1e-6, "{base:?} → {back:?}");
            }
        }
    }

    /// Between the two the published fit is not an exact inverse: measured here, the
    /// metalness of a half-metal comes back within 0.002 and its base colour within
    /// 0.001 (held to 0.01).
    #[test]
    fn half_metals_come_back_near_where_they_were() {
        let mut worst = (0.0f64, 0.0f64);
        for base in [[0.95, 0.64, 0.54], [0.8, 0.8, 0.8], [0.5, 0.3, 0.2]] {
            for metalness in [0.25, 0.5, 0.75] {
                let (diffuse, specular) = spec_gloss_of(base, metalness);
                let (back, m, _) = metal_rough_from_spec_gloss(diffuse, specular, 1.0);
                worst.0 = worst.0.max((m - metalness).abs());
                for c in 0..3 {
                    worst.1 = worst.1.max((back[c] - base[c]).abs());
                }
            }
        }
        println!(
            "half metals: metalness within {:.3}, base colour within {:.3}",
            worst.0, worst.1
        );
        assert!(worst.0 < 0.01 && worst.1 < 0.01, "{worst:?}");
    }
}
