//! Microfacet distributions (D), Smith masking–shadowing (Λ, G₁, G₂), the Cook–Torrance
//! geometric term, and the roughness conventions.
//!
//! Every direction is a unit vector **in the shading frame** ([`crate::ShadingFrame`]):
//! z is the normal, x the tangent, y the bitangent. So n·m = m.z and
//! sin²θ = |n × m|² = m.x² + m.y², formed without cancellation (seed-notes, hard cases:
//! "1 − (n·h)² cancellation in f32"). Every α argument is clamped to
//! [[`ALPHA_MIN`], 1]; every cosine that is divided by is raised to [`COS_MIN`] first.
//! Results are finite for any finite vectors (unit length expected; other lengths give
//! finite but unphysical values) and any α, NaN included. Vectors with NaN or infinite
//! components give unspecified results: [`crate::brdf_evaluate`] normalises and
//! sanitises its inputs before calling these.
//!
//! GLSL mirror: `shaders/include/microfacet.glsl` (same names, same arrangements).

use crate::real::Real;
use crate::vec3::Vec3;
use crate::{ALPHA_MIN, COS_MIN};

/// α limited to [[`ALPHA_MIN`], 1] (NaN → `ALPHA_MIN`).
#[inline]
pub fn clamp_alpha<T: Real>(alpha: T) -> T {
    alpha.clamp_to(T::from_f64(ALPHA_MIN), T::ONE)
}

/// GGX α from the stored *perceptual* roughness r ∈ [0, 1]: α = max(r², [`ALPHA_MIN`]).
///
/// This is the one place the crate squares roughness (seed-notes, "Conventions:
/// Roughness"; the glTF 2.0 metallic-roughness convention). r is clamped to [0, 1]
/// (NaN → 0).
#[inline]
pub fn alpha_from_perceptual_roughness<T: Real>(r: T) -> T {
    let r = r.saturate();
    (r * r).max(T::from_f64(ALPHA_MIN))
}

/// (α_t, α_b) from an isotropic α and an anisotropy strength s ∈ [0, 1]:
/// α_t = mix(α, 1, s²) = α + (1 − α) s², α_b = α (KHR_materials_anisotropy, Khronos 2023).
///
/// α_t goes along the tangent (x), α_b along the bitangent (y). α is clamped to
/// [[`ALPHA_MIN`], 1] and s to [0, 1], so ALPHA_MIN ≤ α_b ≤ α_t ≤ 1.
#[inline]
pub fn anisotropic_alphas<T: Real>(alpha: T, strength: T) -> (T, T) {
    let a = clamp_alpha(alpha);
    let s = strength.saturate();
    (a + (T::ONE - a) * s * s, a)
}

/// GGX / Trowbridge–Reitz normal distribution D(m), isotropic (Walter et al. 2007,
/// "Microfacet Models for Refraction through Rough Surfaces", eq. 33).
///
/// The notes' simplified form α²/(π((n·m)²(α² − 1) + 1)²) is 0/0 at n·m = 1 when α → 0
/// and forms 1 − (n·m)² implicitly; here the denominator is written with
/// sin²θ = m.x² + m.y² as D = 1/(π α² (sin²θ/α² + cos²θ)²), which has neither problem.
/// Returns 0 for m.z ≤ 0 (χ⁺(n·m)).
#[inline]
pub fn d_ggx<T: Real>(m: Vec3<T>, alpha: T) -> T {
    let c = m.z;
    if !c.is_positive() {
        return T::ZERO;
    }
    let a2 = clamp_alpha(alpha).sq();
    let s2 = m.x * m.x + m.y * m.y;
    let t = s2 / a2 + c * c;
    T::ONE / (T::PI * a2 * t * t)
}

/// GGX normal distribution, anisotropic (Burley 2012, "Physically-Based Shading at
/// Disney", appendix B.2): D = 1/(π α_x α_y ((x·m/α_x)² + (y·m/α_y)² + (n·m)²)²).
/// Returns 0 for m.z ≤ 0.
#[inline]
pub fn d_ggx_anisotropic<T: Real>(m: Vec3<T>, alpha_x: T, alpha_y: T) -> T {
    let c = m.z;
    if !c.is_positive() {
        return T::ZERO;
    }
    let ax = clamp_alpha(alpha_x);
    let ay = clamp_alpha(alpha_y);
    let t = (m.x / ax).sq() + (m.y / ay).sq() + c * c;
    T::ONE / (T::PI * ax * ay * t * t)
}

/// Beckmann normal distribution, normalised so ∫D(m)(n·m)dω = 1 (Beckmann &
/// Spizzichino 1963; Walter et al. 2007, eq. 25):
/// D = exp(−tan²θ/α²)/(π α² cos⁴θ), with tan²θ = (m.x² + m.y²)/m.z².
///
/// This is the normalised D the rendering notes print; their "simplified" form was lost
/// (seed-notes 3). Returns 0 for m.z ≤ 0 and when the exponential underflows (so the
/// 0/0 of exp(−∞)/0 at grazing cannot occur).
#[inline]
pub fn d_beckmann<T: Real>(m: Vec3<T>, alpha: T) -> T {
    let c = m.z;
    if !c.is_positive() {
        return T::ZERO;
    }
    let a2 = clamp_alpha(alpha).sq();
    let c2 = c * c;
    let s2 = m.x * m.x + m.y * m.y;
    let e = (-(s2 / a2) / c2).exp();
    if !e.is_positive() {
        return T::ZERO;
    }
    e / (T::PI * a2 * c2 * c2)
}

/// Beckmann normal distribution, anisotropic (Walter et al. 2007, eq. 25 with the
/// elliptical slope variance of Heitz 2014, §5.3):
/// D = exp(−((m.x/α_x)² + (m.y/α_y)²)/m.z²)/(π α_x α_y m.z⁴). A comparison variant of
/// the lighting pass (`D_BECKMANN`), not part of the reference model. 0 for m.z ≤ 0 and
/// when the exponential underflows.
#[inline]
pub fn d_beckmann_anisotropic<T: Real>(m: Vec3<T>, alpha_x: T, alpha_y: T) -> T {
    let c = m.z;
    if !c.is_positive() {
        return T::ZERO;
    }
    let ax = clamp_alpha(alpha_x);
    let ay = clamp_alpha(alpha_y);
    let c2 = c * c;
    let e = (-((m.x / ax).sq() + (m.y / ay).sq()) / c2).exp();
    if !e.is_positive() {
        return T::ZERO;
    }
    e / (T::PI * ax * ay * c2 * c2)
}

/// Smith Λ for Beckmann, anisotropic, in Walter et al. 2007's rational form (eq. 27):
/// with a = cosθ/√((α_x v.x)² + (α_y v.y)²) (= 1/(α tanθ)),
/// Λ = (1 − 1.259a + 0.396a²)/(3.535a + 2.181a²) for a < 1.6, else 0; so 1/(1 + Λ) is
/// Walter's G₁ fit, within 0.4 % of the exact erf form (tested below). `T::MAX` for
/// v.z ≤ 0. A comparison variant's term (`D_BECKMANN`), like [`d_beckmann_anisotropic`].
#[inline]
pub fn lambda_beckmann_anisotropic<T: Real>(v: Vec3<T>, alpha_x: T, alpha_y: T) -> T {
    let c = v.z;
    if !c.is_positive() {
        return T::MAX;
    }
    let a2s2 = alpha2_sin2(v, clamp_alpha(alpha_x), clamp_alpha(alpha_y));
    // a ≥ 1.6 ⇔ c² ≥ 2.56 α² sin²θ (no division, no square root for the common case)
    if c * c >= T::from_f64(2.56) * a2s2 {
        return T::ZERO;
    }
    let a = c / a2s2.sqrt();
    (T::ONE - T::from_f64(1.259) * a + T::from_f64(0.396) * a * a)
        / (T::from_f64(3.535) * a + T::from_f64(2.181) * a * a)
}

/// α²·sin²θ·(direction-weighted) for Λ: (α_x v.x)² + (α_y v.y)², which is
/// α² tan²θ · cos²θ of the anisotropic Smith Λ (Heitz 2014, §5.3).
#[inline]
fn alpha2_sin2<T: Real>(v: Vec3<T>, ax: T, ay: T) -> T {
    (ax * v.x).sq() + (ay * v.y).sq()
}

/// Smith Λ for GGX from c = n·v > 0 and a2s2 = α² sin²θ (anisotropic: see
/// [`alpha2_sin2`]).
///
/// Λ = (−1 + √(1 + α² tan²θ))/2 forms tan²θ = sin²θ/cos²θ, which overflows as c → 0
/// (seed-notes 4), and cancels in −1 + √(1 + x) for small x. Multiplying through:
/// Λ = (S − c)/(2c) with S = √(c² + α² sin²θ), and S − c = α² sin²θ/(S + c), so
/// Λ = α² sin²θ / (2c (S + c)): no tangent, no cancellation.
#[inline]
fn lambda_from_cos<T: Real>(c: T, a2s2: T) -> T {
    if !c.is_positive() {
        return T::MAX;
    }
    if !a2s2.is_positive() {
        return T::ZERO;
    }
    let s = (c * c + a2s2).sqrt();
    (a2s2 / (T::TWO * c * (s + c))).min(T::MAX)
}

/// Smith G₁ for GGX from c = n·v > 0: 1/(1 + Λ) = 2c/(c + √(c² + α² sin²θ)).
#[inline]
fn g1_from_cos<T: Real>(c: T, a2s2: T) -> T {
    if !c.is_positive() {
        return T::ZERO;
    }
    let s = (c * c + a2s2).sqrt();
    T::TWO * c / (c + s)
}

/// Smith Λ(v) for GGX, isotropic (Heitz 2014, "Understanding the Masking-Shadowing
/// Function in Microfacet-Based BRDFs", §5.3), in the tangent-free form
/// Λ = α² sin²θ / (2 cosθ (√(cos²θ + α² sin²θ) + cosθ)).
///
/// For v.z ≤ 0 (the limit Λ → +∞) returns `T::MAX`, so 1/(1 + Λ) ≤ 1/MAX without an Inf.
#[inline]
pub fn lambda_ggx<T: Real>(v: Vec3<T>, alpha: T) -> T {
    let a = clamp_alpha(alpha);
    lambda_from_cos(v.z, a * a * (v.x * v.x + v.y * v.y))
}

/// Smith Λ(v) for GGX, anisotropic (Heitz 2014, §5.3): α² sin²θ is replaced by
/// (α_x v.x)² + (α_y v.y)². `T::MAX` for v.z ≤ 0.
#[inline]
pub fn lambda_ggx_anisotropic<T: Real>(v: Vec3<T>, alpha_x: T, alpha_y: T) -> T {
    lambda_from_cos(
        v.z,
        alpha2_sin2(v, clamp_alpha(alpha_x), clamp_alpha(alpha_y)),
    )
}

/// Smith G₁(v, m) for GGX, isotropic (Walter et al. 2007, eq. 34):
/// χ⁺((v·m)/(v·n)) · 2/(1 + √(1 + α² tan²θ_v)), evaluated as 2c/(c + √(c² + α² sin²θ)).
///
/// The χ⁺ argument is (v·m)/(v·n) (seed-notes 4; the notes print it inverted); only its
/// sign matters, so it is tested as v·m > 0 and v.z > 0 without dividing.
#[inline]
pub fn g1_smith_ggx<T: Real>(v: Vec3<T>, m: Vec3<T>, alpha: T) -> T {
    if !v.dot(m).is_positive() {
        return T::ZERO;
    }
    let a = clamp_alpha(alpha);
    g1_from_cos(v.z, a * a * (v.x * v.x + v.y * v.y))
}

/// Smith G₁(v, m) for GGX, anisotropic (Heitz 2014, §5.3): 1/(1 + Λ_aniso(v)) · χ⁺.
#[inline]
pub fn g1_smith_ggx_anisotropic<T: Real>(v: Vec3<T>, m: Vec3<T>, alpha_x: T, alpha_y: T) -> T {
    if !v.dot(m).is_positive() {
        return T::ZERO;
    }
    g1_from_cos(
        v.z,
        alpha2_sin2(v, clamp_alpha(alpha_x), clamp_alpha(alpha_y)),
    )
}

/// Separable Smith G₂ = G₁(v, m) G₁(l, m), isotropic (Heitz 2014, §6.1).
#[inline]
pub fn g2_smith_ggx_separable<T: Real>(v: Vec3<T>, l: Vec3<T>, m: Vec3<T>, alpha: T) -> T {
    g1_smith_ggx(v, m, alpha) * g1_smith_ggx(l, m, alpha)
}

/// Separable Smith G₂ = G₁(v, m) G₁(l, m), anisotropic (Heitz 2014, §6.1).
#[inline]
pub fn g2_smith_ggx_separable_anisotropic<T: Real>(
    v: Vec3<T>,
    l: Vec3<T>,
    m: Vec3<T>,
    alpha_x: T,
    alpha_y: T,
) -> T {
    g1_smith_ggx_anisotropic(v, m, alpha_x, alpha_y)
        * g1_smith_ggx_anisotropic(l, m, alpha_x, alpha_y)
}

/// Height-correlated G₂ from the cosines and α² sin²θ of v and l (both cosines > 0):
/// 1/(1 + Λ(v) + Λ(l)) = 2 c_v c_l / (c_l S_v + c_v S_l), S = √(c² + α² sin²θ).
/// All terms positive: no cancellation, no division by a cosine.
#[inline]
fn g2_height_correlated_from_cos<T: Real>(cv: T, a2s2v: T, cl: T, a2s2l: T) -> T {
    let sv = (cv * cv + a2s2v).sqrt();
    let sl = (cl * cl + a2s2l).sqrt();
    T::TWO * cv * cl / (cl * sv + cv * sl)
}

/// Height-correlated Smith G₂ = χ⁺ · 1/(1 + Λ(v) + Λ(l)), isotropic (Heitz 2014, §6.2).
#[inline]
pub fn g2_smith_ggx_height_correlated<T: Real>(v: Vec3<T>, l: Vec3<T>, m: Vec3<T>, alpha: T) -> T {
    let a = clamp_alpha(alpha);
    g2_smith_ggx_height_correlated_anisotropic(v, l, m, a, a)
}

/// Height-correlated Smith G₂, anisotropic (Heitz 2014, §6.2).
#[inline]
pub fn g2_smith_ggx_height_correlated_anisotropic<T: Real>(
    v: Vec3<T>,
    l: Vec3<T>,
    m: Vec3<T>,
    alpha_x: T,
    alpha_y: T,
) -> T {
    if !(v.z.is_positive() && l.z.is_positive() && v.dot(m).is_positive() && l.dot(m).is_positive())
    {
        return T::ZERO;
    }
    let ax = clamp_alpha(alpha_x);
    let ay = clamp_alpha(alpha_y);
    g2_height_correlated_from_cos(v.z, alpha2_sin2(v, ax, ay), l.z, alpha2_sin2(l, ax, ay))
}

/// The visibility term V = G₂/(4 (n·v)(n·l)) of the height-correlated anisotropic Smith
/// G₂ (Heitz 2014, §6.2), simplified to V = 1/(2 (c_l S_v + c_v S_l)) with
/// S = √(c² + (α_x x)² + (α_y y)²).
///
/// The half vector's χ⁺ conditions hold automatically for the reflection half vector
/// (v·h = l·h = |v + l|/2 > 0), so they are not re-tested. Returns 0 when v.z ≤ 0 or
/// l.z ≤ 0; cosines in (0, [`COS_MIN`]) are raised to `COS_MIN`, which bounds V by
/// about 1/(4 α COS_MIN) at double grazing instead of overflowing.
#[inline]
pub fn visibility_smith_ggx_height_correlated_anisotropic<T: Real>(
    v: Vec3<T>,
    l: Vec3<T>,
    alpha_x: T,
    alpha_y: T,
) -> T {
    if !(v.z.is_positive() && l.z.is_positive()) {
        return T::ZERO;
    }
    let ax = clamp_alpha(alpha_x);
    let ay = clamp_alpha(alpha_y);
    let (cv, sv) = smith_ggx_visibility_half(v, ax, ay);
    let (cl, sl) = smith_ggx_visibility_half(l, ax, ay);
    T::HALF / (cl * sv + cv * sl)
}

/// One direction's half of the height-correlated visibility: (c, S) with
/// c = max(w·n, COS_MIN) and S = √(c² + αx² wx² + αy² wy²), so that
/// V = ½ / (c_l S_v + c_v S_l). Lets a renderer compute the view's half once per pixel.
/// α must already be clamped (`clamp_alpha`).
#[inline]
pub fn smith_ggx_visibility_half<T: Real>(w: Vec3<T>, ax: T, ay: T) -> (T, T) {
    let c = w.z.max(T::from_f64(COS_MIN));
    (c, (c * c + alpha2_sin2(w, ax, ay)).sqrt())
}

/// Cook–Torrance geometric attenuation (Cook & Torrance 1981, "A Reflectance Model for
/// Computer Graphics"): G = min{1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h)}.
///
/// `h` is the (unit) half vector; l·h = v·h for it, so v·h is the denominator of both.
/// Returns 0 if any of n·v, n·l, n·h, v·h is ≤ 0.
#[inline]
pub fn g_cook_torrance_1981<T: Real>(v: Vec3<T>, l: Vec3<T>, h: Vec3<T>) -> T {
    let vh = v.dot(h);
    if !(v.z.is_positive() && l.z.is_positive() && h.z.is_positive() && vh.is_positive()) {
        return T::ZERO;
    }
    (T::TWO * h.z * v.z.min(l.z) / vh).min(T::ONE)
}

/// The microfacet specular BRDF D F G / (4 (n·v)(n·l)) (Walter et al. 2007, eq. 20).
///
/// Seed-notes 2: Cook & Torrance (1981) divided by π(n·v)(n·l) because their D was not
/// normalised; with a D normalised so ∫D(m)(n·m)dω = 1 (every D of this module) the
/// denominator must be 4(n·v)(n·l), else the lobe carries 4/π too much energy
/// (tested in `tests/identities.rs`). Cosines ≤ 0 give 0; cosines in (0, COS_MIN) are
/// raised to [`COS_MIN`].
#[inline]
pub fn specular_microfacet<T: Real>(d: T, f: T, g: T, cos_v: T, cos_l: T) -> T {
    if !(cos_v.is_positive() && cos_l.is_positive()) {
        return T::ZERO;
    }
    let cmin = T::from_f64(COS_MIN);
    d * f * g / (T::from_f64(4.0) * cos_v.max(cmin) * cos_l.max(cmin))
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

    #[test]
    fn roughness_mapping_and_floor() {
        assert_eq!(alpha_from_perceptual_roughness(0.5_f64), 0.25);
        assert_eq!(alpha_from_perceptual_roughness(1.0_f64), 1.0);
        assert_eq!(alpha_from_perceptual_roughness(0.0_f64), ALPHA_MIN);
        assert_eq!(alpha_from_perceptual_roughness(-3.0_f64), ALPHA_MIN);
        assert_eq!(alpha_from_perceptual_roughness(f64::NAN), ALPHA_MIN);
        assert_eq!(alpha_from_perceptual_roughness(7.0_f32), 1.0);
    }

    #[test]
    fn anisotropic_alphas_follow_the_khr_mapping() {
        assert_eq!(anisotropic_alphas(0.25_f64, 0.0), (0.25, 0.25));
        assert_eq!(anisotropic_alphas(0.25_f64, 1.0), (1.0, 0.25));
        assert_eq!(
            anisotropic_alphas(0.25_f64, 0.5),
            (0.25 + 0.75 * 0.25, 0.25)
        );
        assert_eq!(anisotropic_alphas(0.0_f64, 2.0), (1.0, ALPHA_MIN));
    }

    #[test]
    fn ggx_matches_the_notes_forms_where_they_are_well_conditioned() {
        for alpha in [0.05, 0.3, 1.0] {
            for theta in [0.0_f64, 0.2, 0.7, 1.2, 1.5] {
                let m = dir(theta, 0.4);
                let c = theta.cos();
                let a2 = alpha * alpha;
                // notes, simplified form
                let simple = a2 / (std::f64::consts::PI * (c * c * (a2 - 1.0) + 1.0).powi(2));
                // notes, tan form
                let t2 = theta.tan().powi(2);
                let tanform = a2 / (std::f64::consts::PI * c.powi(4) * (a2 + t2).powi(2));
                let d = d_ggx(m, alpha);
                assert!((d - simple).abs() <= 1e-12 * simple, "{alpha} {theta}");
                assert!((d - tanform).abs() <= 1e-12 * tanform, "{alpha} {theta}");
                // the anisotropic form with α_x = α_y is the isotropic one
                let da = d_ggx_anisotropic(m, alpha, alpha);
                assert!((d - da).abs() <= 1e-14 * d);
            }
        }
    }

    #[test]
    fn anisotropic_ggx_matches_burleys_form() {
        let (ax, ay) = (0.1, 0.6);
        for (theta, phi) in [(0.3, 0.0), (0.5, 1.0), (1.0, 2.5), (1.4, 4.0)] {
            let m: Vec3<f64> = dir(theta, phi);
            let expected = 1.0
                / (std::f64::consts::PI
                    * ax
                    * ay
                    * ((m.x / ax).powi(2) + (m.y / ay).powi(2) + m.z * m.z).powi(2));
            let d = d_ggx_anisotropic(m, ax, ay);
            assert!((d - expected).abs() <= 1e-13 * expected);
        }
    }

    #[test]
    fn lambda_and_g1_match_the_tangent_forms() {
        for alpha in [0.01, 0.2, 1.0] {
            for theta in [0.1_f64, 0.8, 1.3, 1.55] {
                let v = dir(theta, 1.0);
                let t2 = theta.tan().powi(2);
                let lam = (-1.0 + (1.0 + alpha * alpha * t2).sqrt()) / 2.0;
                let l = lambda_ggx(v, alpha);
                // the textbook form cancels for small α tanθ; compare with a bound that
                // covers its own error (≈ ε/(α² tan²θ) relative)
                let tol = 1e-12 * lam + 1e-15 / (alpha * alpha * t2);
                assert!((l - lam).abs() <= tol, "{alpha} {theta}: {l} vs {lam}");
                let g1 = 2.0 / (1.0 + (1.0 + alpha * alpha * t2).sqrt());
                let m = Vec3::new(0.0, 0.0, 1.0);
                assert!((g1_smith_ggx(v, m, alpha) - g1).abs() <= 1e-13);
                assert!((g1_smith_ggx(v, m, alpha) - 1.0 / (1.0 + l)).abs() <= 1e-13);
            }
        }
    }

    /// erf by its Maclaurin series (accurate to ~1e-13 for the |x| ≤ 3 used here).
    fn erf(x: f64) -> f64 {
        let mut term = x;
        let mut sum = x;
        for n in 1..200 {
            term *= -x * x / n as f64;
            sum += term / (2 * n + 1) as f64;
        }
        sum * 2.0 / std::f64::consts::PI.sqrt()
    }

    #[test]
    fn beckmann_anisotropic_is_normalised_and_walters_lambda_is_close() {
        // ∫ D(m) (n·m) dω = 1, by a midpoint rule over the hemisphere
        for (ax, ay) in [(0.3, 0.3), (0.5, 0.1), (0.2, 0.8)] {
            let (nt, np) = (2000, 400);
            let mut sum = 0.0;
            for i in 0..nt {
                let theta = (i as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
                for j in 0..np {
                    let phi = (j as f64 + 0.5) / np as f64 * 2.0 * std::f64::consts::PI;
                    let m = dir(theta, phi);
                    sum += d_beckmann_anisotropic(m, ax, ay) * m.z * theta.sin();
                }
            }
            let integral =
                sum * std::f64::consts::FRAC_PI_2 / nt as f64 * 2.0 * std::f64::consts::PI
                    / np as f64;
            assert!((integral - 1.0).abs() < 2e-3, "{ax} {ay}: {integral}");
            // isotropic case equals d_beckmann
            let m = dir(0.4, 1.1);
            assert!(
                (d_beckmann_anisotropic(m, ax, ax) - d_beckmann(m, ax)).abs()
                    <= 1e-12 * d_beckmann(m, ax)
            );
        }
        // Walter's G₁ fit against the exact Λ = (erf(a) − 1)/2 + exp(−a²)/(2a√π)
        let mut worst: f64 = 0.0;
        for alpha in [0.05, 0.3, 1.0] {
            for k in 1..400 {
                let theta = k as f64 / 400.0 * std::f64::consts::FRAC_PI_2;
                let v = dir(theta, 0.7);
                let a = 1.0 / (alpha * theta.tan());
                if a > 3.0 {
                    continue; // exact Λ < 1e-5 there; the series would lose precision
                }
                let exact =
                    (erf(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * std::f64::consts::PI.sqrt());
                let g1 = 1.0 / (1.0 + lambda_beckmann_anisotropic(v, alpha, alpha));
                let g1_exact = 1.0 / (1.0 + exact);
                worst = worst.max((g1 - g1_exact).abs() / g1_exact);
            }
        }
        assert!(worst < 4e-3, "{worst}");
        assert_eq!(
            lambda_beckmann_anisotropic(Vec3::new(1.0, 0.0, 0.0), 0.3, 0.3),
            f64::MAX
        );
    }

    #[test]
    fn height_correlated_g2_is_one_over_one_plus_lambdas() {
        let (ax, ay) = (0.3, 0.08);
        let v = dir(0.9, 0.3);
        let l = dir(0.4, 2.0);
        let h = (v + l).normalize();
        let lv = lambda_ggx_anisotropic(v, ax, ay);
        let ll = lambda_ggx_anisotropic(l, ax, ay);
        let g2 = g2_smith_ggx_height_correlated_anisotropic(v, l, h, ax, ay);
        assert!((g2 - 1.0 / (1.0 + lv + ll)).abs() < 1e-15);
        let vis = visibility_smith_ggx_height_correlated_anisotropic(v, l, ax, ay);
        assert!((vis - g2 / (4.0 * v.z * l.z)).abs() < 1e-14 * vis);
        // separable ≤ height-correlated (Heitz 2014: correlation only adds visibility)
        let g2s = g2_smith_ggx_separable_anisotropic(v, l, h, ax, ay);
        assert!(g2s <= g2 && g2s > 0.0);
    }

    #[test]
    fn back_facing_and_grazing_are_zero_not_nan() {
        let n = Vec3::new(0.0_f32, 0.0, 1.0);
        let grazing = Vec3::new(1.0_f32, 0.0, 0.0);
        let below = Vec3::new(0.6_f32, 0.0, -0.8);
        assert_eq!(g1_smith_ggx(grazing, n, 0.5), 0.0);
        assert_eq!(g1_smith_ggx(below, n, 0.5), 0.0);
        assert_eq!(lambda_ggx(grazing, 0.5), f32::MAX);
        assert!(1.0 / (1.0 + lambda_ggx(grazing, 0.5)) <= 1.0 / f32::MAX);
        assert_eq!(d_ggx(grazing, 0.5), 0.0);
        assert_eq!(d_beckmann(grazing, 0.5), 0.0);
        assert_eq!(d_beckmann(Vec3::new(1.0, 0.0, 1e-30), 0.5), 0.0);
        assert_eq!(
            visibility_smith_ggx_height_correlated_anisotropic(grazing, n, 0.5, 0.5),
            0.0
        );
        let vis = visibility_smith_ggx_height_correlated_anisotropic(
            Vec3::new(1.0, 0.0, 1e-40),
            Vec3::new(-1.0, 0.0, 1e-42),
            0.0,
            0.0,
        );
        assert!(vis.is_finite() && vis > 0.0);
    }

    #[test]
    fn alpha_zero_gives_the_alpha_min_lobe() {
        let n = Vec3::new(0.0_f32, 0.0, 1.0);
        let d0 = d_ggx(n, 0.0);
        assert!(d0.is_finite());
        assert_eq!(d0, d_ggx(n, ALPHA_MIN as f32));
        assert_eq!(d_ggx(n, f32::NAN), d0);
        assert!(d_beckmann(n, 0.0_f32).is_finite());
        let d_aniso = d_ggx_anisotropic(n, 0.0_f32, -1.0);
        assert_eq!(d_aniso, d0);
    }

    #[test]
    fn cook_torrance_g() {
        let n = Vec3::new(0.0, 0.0, 1.0_f64);
        assert_eq!(g_cook_torrance_1981(n, n, n), 1.0);
        let v = dir(1.4, 0.0);
        let l = dir(1.4, std::f64::consts::PI);
        let h = (v + l).normalize();
        let expected = 2.0 * h.z * v.z / v.dot(h);
        assert!((g_cook_torrance_1981(v, l, h) - expected.min(1.0)).abs() < 1e-15);
        let back = Vec3::new(0.0, 0.0, -1.0);
        assert_eq!(g_cook_torrance_1981(back, n, n), 0.0);
    }
}
