//! Colour encodings shared by the passes, the reference and the tests: the sRGB
//! transfer functions, the output pass's tone curve, and the half floats an RGBA16F
//! image is read back as (CPU mirrors of `srgb.glsl` and `tonemap.glsl`).

/// CPU mirror of `tonemap_exponential` (tonemap.glsl), and the sRGB encoding (IEC
/// 61966-2-1) the tonemap pass applies (`srgb_encode`): in the optics crate, where the
/// image comparison (combustion-diff) finds them without the renderer.
pub use combustion_optics::display::{linear_to_srgb, tonemap_exponential};

/// CPU mirror of `tonemap_pbr_neutral` (tonemap.glsl): Khronos PBR Neutral (the Khronos
/// 3D Commerce group's tone mapper, 2024), per pixel: colours below 0.76 pass unchanged
/// but for a small offset near black; brighter ones are compressed towards 1 and
/// desaturated.
pub fn tonemap_pbr_neutral(rgb: [f64; 3]) -> [f64; 3] {
    const START_COMPRESSION: f64 = 0.8 - 0.04;
    const DESATURATION: f64 = 0.15;
    let rgb = rgb.map(|c| c.max(0.0));
    let x = rgb[0].min(rgb[1]).min(rgb[2]);
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let color = rgb.map(|c| c - offset);
    let peak = color[0].max(color[1]).max(color[2]);
    if peak < START_COMPRESSION {
        return color;
    }
    let d = 1.0 - START_COMPRESSION;
    let new_peak = 1.0 - d * d / (peak + d - START_COMPRESSION);
    let color = color.map(|c| c * new_peak / peak);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    color.map(|c| c + (new_peak - c) * g)
}

/// CPU mirror of `tonemap_aces` (tonemap.glsl): K. Narkowicz's fit of the ACES filmic
/// curve ("ACES Filmic Tone Mapping Curve", 2016), x(2.51x + 0.03) / (x(2.43x + 0.59) +
/// 0.14) of 0.6 x, clamped to [0, 1], per channel.
pub fn tonemap_aces(x: f64) -> f64 {
    let x = 0.6 * x.max(0.0);
    (x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// The inset matrix of AgX (rows: output channels), from B. Wrensch's minimal AgX
/// (2024; the transform of T. Sobotka's AgX).
const AGX_INSET: [[f64; 3]; 3] = [
    [0.842479062253094, 0.0784335999999992, 0.0792237451477643],
    [0.0423282422610123, 0.878468636469772, 0.0791661274605434],
    [0.0423756549057051, 0.0784336, 0.879142973793104],
];
/// Its outset matrix (rows: output channels).
const AGX_OUTSET: [[f64; 3]; 3] = [
    [1.19687900512017, -0.0980208811401368, -0.0990297440797205],
    [-0.0528968517574562, 1.15190312990417, -0.0989611768448433],
    [-0.0529716355144438, -0.0980434501171241, 1.15107367264116],
];
/// The log2 range AgX maps to [0, 1] before its contrast curve.
const AGX_MIN_EV: f64 = -12.47393;
const AGX_MAX_EV: f64 = 4.026069;

/// CPU mirror of `tonemap_agx` (tonemap.glsl): AgX (T. Sobotka), as B. Wrensch's minimal
/// form computes it — the inset matrix, log2 encoding over [−12.47, 4.03] stops, the
/// 6th-order fit of AgX's default contrast curve, the outset matrix — and then decoded
/// from its 2.2-power display encoding to the linear display value the output pass
/// encodes to sRGB.
pub fn tonemap_agx(rgb: [f64; 3]) -> [f64; 3] {
    let times = |m: &[[f64; 3]; 3], v: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
    };
    let inset = times(&AGX_INSET, rgb.map(|c| c.max(1e-10)));
    let curved = inset.map(|c| {
        let x = (c.max(1e-10).log2().clamp(AGX_MIN_EV, AGX_MAX_EV) - AGX_MIN_EV)
            / (AGX_MAX_EV - AGX_MIN_EV);
        let (x2, x4) = (x * x, x * x * x * x);
        15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
            - 0.00232
    });
    times(&AGX_OUTSET, curved).map(|c| c.max(0.0).powf(2.2).min(1.0))
}

/// The sRGB decoding (IEC 61966-2-1), as the lighting pass's table applies it.
pub fn srgb_to_linear(encoded: f64) -> f64 {
    combustion_scene::srgb_decode(encoded)
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
            let back = linear_to_srgb(srgb_to_linear(e));
            assert!((back - e).abs() < 1e-12, "{i}");
        }
    }
}
