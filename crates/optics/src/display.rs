//! How radiance becomes a display value: the output pass's exponential tone curve and
//! the sRGB encoding, in f64 (CPU mirrors of tonemap.glsl and srgb.glsl; the renderer's
//! `color` module re-exports them).

/// CPU mirror of `tonemap_exponential` (tonemap.glsl): the display value before sRGB
/// encoding, 1 − e^(−x) (0 for x ≤ 0).
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
