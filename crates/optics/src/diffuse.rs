//! Diffuse BRDFs: Lambert, and Oren–Nayar (qualitative and full 1994 models).
//!
//! Every function returns the BRDF value f (per unit solid angle, *not* multiplied by
//! n·l) for view `v` and light `l` given **in the shading frame** (z = normal), and 0
//! when v.z ≤ 0 or l.z ≤ 0. σ is the standard deviation of the facet slope angle in
//! radians (clamped to ≥ 0). Cosines that are divided by are raised to
//! [`COS_MIN`] first, so results stay finite at grazing angles.
//!
//! The notes' α and β in Oren–Nayar are max(θ_i, θ_r) and min(θ_i, θ_r), not roughness
//! (seed-notes 5); the code calls them `theta_max` and `theta_min`.
//!
//! GLSL mirror: `shaders/include/diffuse.glsl` (there ρ is a `vec3`, one value per
//! channel; the geometry is computed once).

use crate::real::Real;
use crate::vec3::Vec3;
use crate::COS_MIN;

/// The A-constant of the rendering notes' Oren–Nayar formula: A = 1 − 0.5 σ²/(σ² + 0.57).
pub const OREN_NAYAR_A_CONSTANT_NOTES: f64 = 0.57;
/// The A-constant of Oren & Nayar's (1994) qualitative model and of their full model's
/// C1: A = 1 − 0.5 σ²/(σ² + 0.33).
pub const OREN_NAYAR_A_CONSTANT_PAPER: f64 = 0.33;
/// The A-constant [`crate::brdf::DiffuseModel::OrenNayarQualitative`] uses: the paper's
/// 0.33 (seed-notes 5).
///
/// Measured against the full model with interreflection (cosine-weighted RMS over the
/// hemisphere of (f_qualitative − f_full)/(ρ/π); `tests/identities.rs`,
/// `oren_nayar_a_constant_choice`):
///
/// | ρ   | σ = 0.1 | 0.3 | 0.5 | 0.7 |
/// |-----|---------|-----|-----|-----|
/// | 0.2 | 0.013 / 0.016 | 0.062 / 0.084 | 0.090 / 0.125 | 0.103 / 0.140 |
/// | 0.5 | 0.011 / 0.013 | 0.056 / 0.068 | 0.082 / 0.100 | 0.094 / 0.110 |
/// | 0.8 | 0.011 / 0.011 | 0.057 / 0.056 | 0.087 / 0.081 | 0.101 / 0.090 |
///
/// (A = 0.33 / A = 0.57.) 0.33 is closer for every σ at ρ ≤ 0.5, the range of most
/// real diffuse albedos; the notes' 0.57 only wins at high albedo and roughness, where
/// the ρ²-weighted interreflection is large enough for a raised A to imitate it.
pub const OREN_NAYAR_A_CONSTANT_BRDF: f64 = OREN_NAYAR_A_CONSTANT_PAPER;

/// Oren–Nayar σ (radians) from the stored perceptual roughness r ∈ [0, 1]:
/// σ = α/√2 with α = r² (the GGX α before the [`ALPHA_MIN`](crate::ALPHA_MIN) floor).
///
/// Why: a microfacet distribution of width α has a per-axis slope standard deviation of
/// α/√2 (exact for Beckmann, whose slopes are Gaussian with variance α²/2 per axis; GGX
/// has the same width parameter near the peak). Oren–Nayar's σ is the standard deviation
/// of the facet slope *angle* of V-cavities seen in cross-section, i.e. per axis; for
/// small slopes angle ≈ slope, so σ = α/√2 makes the diffuse and specular lobes describe
/// the same surface. r = 1 gives σ = 0.707 rad (40.5°), r = 0 gives σ = 0 (Lambert).
/// r is clamped to [0, 1] (NaN → 0).
#[inline]
pub fn oren_nayar_sigma_from_roughness<T: Real>(r: T) -> T {
    let r = r.saturate();
    r * r * T::FRAC_1_SQRT_2
}

/// Lambert's diffuse BRDF f = ρ/π (Lambert 1760, "Photometria").
///
/// Seed-notes 1: the notes' f = N·L is the cosine factor of the rendering equation, not
/// the BRDF; reflected radiance from irradiance E is (ρ/π) E (N·L). ρ is the albedo.
#[inline]
pub fn diffuse_lambert<T: Real>(rho: T) -> T {
    rho * T::FRAC_1_PI
}

/// σ limited to [0, π/2] (NaN → 0).
#[inline]
fn clamp_sigma<T: Real>(sigma: T) -> T {
    sigma.clamp_to(T::ZERO, T::HALF * T::PI)
}

/// Local cosines, sines and the azimuthal products the Oren–Nayar models share.
struct OrenNayarGeometry<T> {
    /// cosθ_i, cosθ_r, raised to COS_MIN
    ci: T,
    cr: T,
    /// sinθ_i = |n × l|, sinθ_r = |n × v|
    si: T,
    sr: T,
    /// sinθ_i sinθ_r cos(φ_r − φ_i) = v.x l.x + v.y l.y (no cancellation in the frame)
    sin_sin_cos_phi: T,
}

#[inline]
fn geometry<T: Real>(v: Vec3<T>, l: Vec3<T>) -> Option<OrenNayarGeometry<T>> {
    if !(v.z.is_positive() && l.z.is_positive()) {
        return None;
    }
    let cmin = T::from_f64(COS_MIN);
    Some(OrenNayarGeometry {
        ci: l.z.max(cmin),
        cr: v.z.max(cmin),
        si: (l.x * l.x + l.y * l.y).sqrt(),
        sr: (v.x * v.x + v.y * v.y).sqrt(),
        sin_sin_cos_phi: v.x * l.x + v.y * l.y,
    })
}

/// Oren–Nayar *qualitative* model (Oren & Nayar 1994, "Generalization of Lambert's
/// Reflectance Model", §4.4): f = ρ/π (A + B max(0, cos(φ_r − φ_i)) sin α tan β),
/// A = 1 − 0.5 σ²/(σ² + a_constant), B = 0.45 σ²/(σ² + 0.09).
///
/// `a_constant` is [`OREN_NAYAR_A_CONSTANT_PAPER`] (0.33) or the notes'
/// [`OREN_NAYAR_A_CONSTANT_NOTES`] (0.57). Evaluated without angles:
/// cos(φ_r − φ_i) sin α tan β = (v.x l.x + v.y l.y)/max(cosθ_i, cosθ_r), since the
/// smaller angle has the larger cosine. This is what the notes call "the full form"
/// (seed-notes 5); the paper's full model is [`diffuse_oren_nayar_full`].
#[inline]
pub fn diffuse_oren_nayar_qualitative<T: Real>(
    rho: T,
    sigma: T,
    a_constant: T,
    v: Vec3<T>,
    l: Vec3<T>,
) -> T {
    let Some(g) = geometry(v, l) else {
        return T::ZERO;
    };
    let s2 = clamp_sigma(sigma).sq();
    let a = if s2 > T::ZERO {
        T::ONE - T::HALF * s2 / (s2 + a_constant.max(T::ZERO))
    } else {
        T::ONE
    };
    let b = T::from_f64(0.45) * s2 / (s2 + T::from_f64(0.09));
    let x = g.sin_sin_cos_phi.max(T::ZERO) / g.ci.max(g.cr);
    rho * T::FRAC_1_PI * (a + b * x)
}

/// Oren–Nayar *full* model (Oren & Nayar 1994, "Generalization of Lambert's Reflectance
/// Model", eqs. for L_r¹ and L_r² with C1, C2, C3): f = (L₁ + L₂)/π with
///
/// * L₁ = ρ (C1 + cosφ C2 tan β + (1 − |cosφ|) C3 tan((α + β)/2)),
/// * C1 = 1 − 0.5 σ²/(σ² + 0.33),
///   C2 = 0.45 σ²/(σ² + 0.09) · (sin α if cosφ ≥ 0, else sin α − (2β/π)³),
///   C3 = 0.125 σ²/(σ² + 0.09) (4αβ/π²)²,
/// * L₂ = 0.17 ρ² σ²/(σ² + 0.13) (1 − cosφ (2β/π)²) (interreflection),
///
/// α = max(θ_i, θ_r), β = min(θ_i, θ_r), φ = φ_r − φ_i. Arrangement (f32, grazing):
/// θ = atan2(sinθ, cosθ) with sinθ from the frame (not acos, which loses accuracy near
/// 0) and 1 − 2β/π from atan2(cos β, sin β) (accurate near π/2);
/// tan((α + β)/2) = (sinθ_i + sinθ_r)/(cosθ_i + cosθ_r) (sum of positives);
/// cosφ and 1 − |cosφ| = sin²φ/(1 + |cosφ|) from the normalised tangent-plane
/// projections; C2's sin α − (2β/π)³ and L₂'s 1 − cosφ(2β/π)² as sums of non-negative
/// terms (both would otherwise cancel near grazing, where C2 is multiplied by
/// tan β ≈ 1/cos β). ρ enters squared in L₂, so this is evaluated per channel.
///
/// The paper's L₁ dips below zero for σ ≳ 0.6 rad at near-grazing forward scattering
/// (cosφ = −1, θ_i, θ_r ≳ 87°), where C2's (2β/π)³ correction over-subtracts; L₁ is
/// clamped at 0 so f ≥ 0 (a BRDF cannot be negative; tested).
pub fn diffuse_oren_nayar_full<T: Real>(rho: T, sigma: T, v: Vec3<T>, l: Vec3<T>) -> T {
    let Some(g) = geometry(v, l) else {
        return T::ZERO;
    };
    let s2 = clamp_sigma(sigma).sq();
    let theta_i = g.si.atan2(g.ci);
    let theta_r = g.sr.atan2(g.cr);
    let theta_max = theta_i.max(theta_r);
    let theta_min = theta_i.min(theta_r);
    // (sin, cos) of α = max(θ_i, θ_r) and of β = min(θ_i, θ_r)
    let (s_max_angle, c_max_angle, s_min_angle, c_min_angle) = if theta_i < theta_r {
        (g.sr, g.cr, g.si, g.ci)
    } else {
        (g.si, g.ci, g.sr, g.cr)
    };
    let tan_beta = s_min_angle / c_min_angle;

    // cosφ and 1 − |cosφ| from the unit projections onto the tangent plane
    let (cos_phi, one_minus_abs_cos_phi) = if g.si > T::ZERO && g.sr > T::ZERO {
        let vx = v.x / g.sr;
        let vy = v.y / g.sr;
        let lx = l.x / g.si;
        let ly = l.y / g.si;
        let cos_phi = (vx * lx + vy * ly).clamp_to(-T::ONE, T::ONE);
        let sin_phi = vx * ly - vy * lx;
        (cos_phi, sin_phi * sin_phi / (T::ONE + cos_phi.abs()))
    } else {
        // one direction is the normal: φ is undefined, and every φ term is multiplied
        // by β = 0 (tan β, β², β³), except the interreflection (2β/π)² also = 0
        (T::ZERO, T::ONE)
    };

    let tmp = s2 / (s2 + T::from_f64(0.09));
    let c1 = T::ONE - T::HALF * s2 / (s2 + T::from_f64(0.33));
    let two_beta_over_pi = T::TWO * theta_min * T::FRAC_1_PI;
    // x = 1 − 2β/π from the complementary angle, accurate as β → π/2
    let x = T::TWO * T::FRAC_1_PI * c_min_angle.atan2(s_min_angle);
    let c2 = if cos_phi >= T::ZERO {
        T::from_f64(0.45) * tmp * s_max_angle
    } else {
        // sin α − (2β/π)³ = (1 − (1 − x)³) − (1 − sin α)
        //                 = x (3 − 3x + x²) − cos²α/(1 + sin α):
        // near grazing both are small and the naive difference cancels, while it is
        // multiplied by tan β ≈ 1/cos β; the first term dominates (β ≤ α), so this is
        // free of cancellation.
        let three = T::from_f64(3.0);
        let one_minus_sin_alpha = c_max_angle * c_max_angle / (T::ONE + s_max_angle);
        T::from_f64(0.45) * tmp * (x * (three - three * x + x * x) - one_minus_sin_alpha)
    };
    let four_ab_over_pi2 = T::from_f64(4.0) * theta_max * theta_min * T::FRAC_1_PI * T::FRAC_1_PI;
    let c3 = T::from_f64(0.125) * tmp * four_ab_over_pi2.sq();
    let tan_half_sum = (g.si + g.sr) / (g.ci + g.cr);
    let l1 = rho
        * (c1 + cos_phi * c2 * tan_beta + one_minus_abs_cos_phi * c3 * tan_half_sum).max(T::ZERO);
    let c4 = T::from_f64(0.17) * s2 / (s2 + T::from_f64(0.13));
    // 1 − cosφ (2β/π)²; for cosφ > 0 as (1 − cosφ) + cosφ (1 − (2β/π)²), both ≥ 0,
    // with 1 − cosφ = 1 − |cosφ| and 1 − (2β/π)² = x (2 − x)
    let interreflection = if cos_phi > T::ZERO {
        one_minus_abs_cos_phi + cos_phi * x * (T::TWO - x)
    } else {
        T::ONE - cos_phi * two_beta_over_pi.sq()
    };
    let l2 = rho * rho * c4 * interreflection;
    (l1 + l2) * T::FRAC_1_PI
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(theta: f64, phi: f64) -> Vec3<f64> {
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    /// The paper's L₁ and L₂ written with angles (tan, cos of φ), unclamped.
    fn paper_terms(rho: f64, sigma: f64, tr: f64, pr: f64, ti: f64, pi_: f64) -> (f64, f64) {
        use std::f64::consts::PI;
        let s2 = sigma * sigma;
        let a = tr.max(ti);
        let b = tr.min(ti);
        let cphi = (pr - pi_).cos();
        let c1 = 1.0 - 0.5 * s2 / (s2 + 0.33);
        let c2 = if cphi >= 0.0 {
            0.45 * s2 / (s2 + 0.09) * a.sin()
        } else {
            0.45 * s2 / (s2 + 0.09) * (a.sin() - (2.0 * b / PI).powi(3))
        };
        let c3 = 0.125 * s2 / (s2 + 0.09) * (4.0 * a * b / (PI * PI)).powi(2);
        let l1 = rho * (c1 + cphi * c2 * b.tan() + (1.0 - cphi.abs()) * c3 * ((a + b) / 2.0).tan());
        let l2 = 0.17 * rho * rho * s2 / (s2 + 0.13) * (1.0 - cphi * (2.0 * b / PI).powi(2));
        (l1, l2)
    }

    fn full_with_angles(rho: f64, sigma: f64, tr: f64, pr: f64, ti: f64, pi_: f64) -> f64 {
        let (l1, l2) = paper_terms(rho, sigma, tr, pr, ti, pi_);
        (l1.max(0.0) + l2) / std::f64::consts::PI
    }

    #[test]
    fn full_model_matches_the_angle_form() {
        for sigma in [0.1, 0.4, 0.7] {
            for (tr, pr, ti, pi_) in [
                (0.3, 0.2, 0.9, 2.0),
                (1.2, 0.0, 0.5, 0.1),
                (0.7, 1.0, 0.7, 1.0 + std::f64::consts::PI),
                (1.4, 3.0, 0.2, 1.0),
            ] {
                let f = diffuse_oren_nayar_full(0.6, sigma, dir(tr, pr), dir(ti, pi_));
                let e = full_with_angles(0.6, sigma, tr, pr, ti, pi_);
                assert!((f - e).abs() <= 1e-13 * e, "{sigma} {tr} {ti}: {f} {e}");
            }
        }
    }

    #[test]
    fn qualitative_matches_the_angle_form() {
        use std::f64::consts::PI;
        let (sigma, rho) = (0.5, 0.8);
        let (tr, pr, ti, pi_) = (1.1, 0.3, 0.4, 0.9);
        let s2 = sigma * sigma;
        for ac in [OREN_NAYAR_A_CONSTANT_PAPER, OREN_NAYAR_A_CONSTANT_NOTES] {
            let a = 1.0 - 0.5 * s2 / (s2 + ac);
            let b = 0.45 * s2 / (s2 + 0.09);
            let e = rho / PI
                * (a + b * (pr - pi_).cos().max(0.0) * tr.max(ti).sin() * tr.min(ti).tan());
            let f = diffuse_oren_nayar_qualitative(rho, sigma, ac, dir(tr, pr), dir(ti, pi_));
            assert!((f - e).abs() <= 1e-14, "{f} {e}");
        }
    }

    #[test]
    fn normal_incidence_has_no_azimuth_terms() {
        let n = Vec3::new(0.0, 0.0, 1.0);
        let l = dir(0.8, 1.0);
        let sigma: f64 = 0.5;
        let s2 = sigma * sigma;
        let expected = (0.5 * (1.0 - 0.5 * s2 / (s2 + 0.33)) + 0.25 * 0.17 * s2 / (s2 + 0.13))
            / std::f64::consts::PI;
        let f = diffuse_oren_nayar_full(0.5, sigma, n, l);
        assert!((f - expected).abs() < 1e-15);
    }

    #[test]
    fn sigma_mapping() {
        assert_eq!(oren_nayar_sigma_from_roughness(0.0_f64), 0.0);
        assert!((oren_nayar_sigma_from_roughness(1.0_f64) - 0.5_f64.sqrt()).abs() < 1e-16);
        assert_eq!(oren_nayar_sigma_from_roughness(f64::NAN), 0.0);
        assert_eq!(
            oren_nayar_sigma_from_roughness(0.5_f64),
            0.25 * std::f64::consts::FRAC_1_SQRT_2
        );
    }

    #[test]
    fn full_model_is_clamped_where_the_paper_goes_negative() {
        // forward scattering (cosφ = −1), both directions 88° from the normal, σ = 0.7:
        // the paper's single-scattering term is negative there
        use std::f64::consts::PI;
        // and with a dark albedo the interreflection term cannot make up for it
        let (sigma, rho, theta) = (0.7, 0.005, 88.0_f64.to_radians());
        let (l1, l2) = paper_terms(rho, sigma, theta, 0.0, theta, PI);
        assert!(l1 < 0.0 && l1 + l2 < 0.0, "{l1} {l2}");
        let f = diffuse_oren_nayar_full(rho, sigma, dir(theta, 0.0), dir(theta, PI));
        assert!((f - l2 / PI).abs() <= 1e-12 * l2, "{f} vs {}", l2 / PI);
    }
}
