//! Sheen, the back-scattering of fibres over the material (KHR_materials_sheen), and its
//! CPU reference.
//!
//! GLSL mirror: `shaders/include/brdf.glsl` (`d_charlie`, `lambda_sheen`,
//! `visibility_sheen`, `sheen_albedo_scaling`). Same names, inputs in the same order.
//!
//! The lobe is Estevez & Kulla's (2017, "Production Friendly Microfacet Sheen BRDF"):
//! f_sheen = c · D_Charlie(h) · V_sheen(v, l), c the sheen colour, with
//!
//! - D_Charlie(h) = (2 + 1/α) sin^(1/α)θ_h / (2π), α = r² of the sheen's perceptual
//!   roughness: normalised, ∫ D cos θ_h dω = 1 (`tests/sheen.rs`);
//! - V_sheen = 1/((1 + Λ(v) + Λ(l)) 4 n·v n·l), the height-correlated form with their
//!   fitted Λ: Λ(μ) = e^{L(μ)} for μ < ½ and e^{2 L(½) − L(1 − μ)} above, L(x) = a/(1 +
//!   b x^c) + d x + e, the five coefficients blended between their fits at α = 0 and 1
//!   by (1 − α)² (the glTF extension's choice).
//!
//! The layer over the base is the extension's albedo scaling: f = f_sheen + s f_base,
//! s = min(1 − max(c) E(n·v), 1 − max(c) E(n·l)), E(μ) = ∫ D V (n·l) dl the lobe's
//! directional albedo for white sheen: symmetric in v and l (reciprocal), and what the
//! sheen reflects in its brightest channel is taken from the base on both ways.
//! E is read from a table ([`sheen_albedo_table`], 32² cell-centred entries over (μ, r),
//! integrated in f64, looked up bilinearly: [`sheen_albedo_lookup`]) on the GPU and in
//! the f64 references alike; the table's error against the integral at any point is
//! measured in `tests/sheen.rs`.
//!
//! Found by that integral: the lobe as the extension defines it (the Charlie
//! distribution with the fitted Λ) reflects more than it receives within about a degree
//! of grazing when the sheen is smooth: E = 2.1 at r = 0.1 and 1.19 at r = 0.2 (both at
//! μ ≈ 0.003), E ≤ 0.94 for r ≥ 0.3 everywhere (the fit of Λ is poor where α is small
//! and the visibility's 1/(n·v n·l) is large). The lobe is kept as defined; the table
//! caps E at 1, so the base's scaling never goes below 0.

use crate::real::Real;
use crate::vec3::{ShadingFrame, Vec3};

/// The sheen's inputs: its colour (linear RGB, the sheen colour factor × texture) and
/// its α = r² (the sheen roughness factor × texture, squared).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheenInputs<T> {
    /// Linear RGB in [0, 1]; black: no sheen.
    pub color: [T; 3],
    /// α of the Charlie distribution, clamped to [`SHEEN_ALPHA_MIN`, 1].
    pub alpha: T,
}

/// The smallest sheen α (the distribution's exponent 1/α stays finite).
pub const SHEEN_ALPHA_MIN: f64 = 1e-3;

fn clamp_sheen_alpha<T: Real>(alpha: T) -> T {
    alpha.clamp_to(T::from_f64(SHEEN_ALPHA_MIN), T::ONE)
}

/// The Charlie distribution of sheen normals (Estevez & Kulla 2017, eq. 2) for a unit
/// microfacet normal `m` in the local frame: (2 + 1/α) sin^(1/α)θ / (2π); 0 below the
/// horizon.
pub fn d_charlie<T: Real>(m: Vec3<T>, alpha: T) -> T {
    if !m.z.is_positive() {
        return T::ZERO;
    }
    let alpha = clamp_sheen_alpha(alpha);
    let inv = T::ONE / alpha;
    let sin2 = (m.x * m.x + m.y * m.y).min(T::ONE);
    if !sin2.is_positive() {
        return T::ZERO; // sin^(1/α) θ at θ = 0
    }
    (T::from_f64(2.0) + inv) * (T::HALF * inv * sin2.ln()).exp() / (T::from_f64(2.0) * T::PI)
}

/// Estevez & Kulla's fitted L(x) for the sheen's Λ, its coefficients blended between
/// their α = 0 and α = 1 fits by (1 − α)².
fn lambda_sheen_fit<T: Real>(x: T, alpha: T) -> T {
    let t = (T::ONE - alpha) * (T::ONE - alpha);
    let mix = |at_one: f64, at_zero: f64| {
        T::from_f64(at_one) + (T::from_f64(at_zero) - T::from_f64(at_one)) * t
    };
    let a = mix(21.5473, 25.3245);
    let b = mix(3.82987, 3.32435);
    let c = mix(0.19823, 0.16801);
    let d = mix(-1.97760, -1.27393);
    let e = mix(-4.32054, -4.85967);
    // x^c, with 0^c = 0
    let power = if x.is_positive() {
        (c * x.ln()).exp()
    } else {
        T::ZERO
    };
    a / (T::ONE + b * power) + d * x + e
}

/// The sheen's Smith Λ at cos θ = `cos` (Estevez & Kulla 2017, section 3: their fit,
/// mirrored about ½ for the upper half).
pub fn lambda_sheen<T: Real>(cos: T, alpha: T) -> T {
    let alpha = clamp_sheen_alpha(alpha);
    let cos = cos.abs().min(T::ONE);
    if cos < T::HALF {
        lambda_sheen_fit(cos, alpha).exp()
    } else {
        (T::from_f64(2.0) * lambda_sheen_fit(T::HALF, alpha)
            - lambda_sheen_fit(T::ONE - cos, alpha))
        .exp()
    }
}

/// V = 1/((1 + Λ(v) + Λ(l)) 4 n·v n·l) for directions in the local frame (cosines raised
/// to [`crate::COS_MIN`]); 0 unless both are above the horizon.
pub fn visibility_sheen<T: Real>(v: Vec3<T>, l: Vec3<T>, alpha: T) -> T {
    if !(v.z.is_positive() && l.z.is_positive()) {
        return T::ZERO;
    }
    let cos_min = T::from_f64(crate::COS_MIN);
    let (cv, cl) = (v.z.max(cos_min), l.z.max(cos_min));
    T::ONE
        / ((T::ONE + lambda_sheen(cv, alpha) + lambda_sheen(cl, alpha))
            * T::from_f64(4.0)
            * cv
            * cl)
}

/// The white sheen lobe D V for v and l in the local frame (not multiplied by a cosine).
pub fn sheen_lobe<T: Real>(v: Vec3<T>, l: Vec3<T>, alpha: T) -> T {
    if !(v.z.is_positive() && l.z.is_positive()) {
        return T::ZERO;
    }
    let h = (v + l).normalize();
    d_charlie(h, alpha) * visibility_sheen(v, l, alpha)
}

/// E(μ, α) = ∫ D V (n·l) dl, the white sheen lobe's directional albedo at cos θ_v = `mu`,
/// by a Gauss–Legendre rule of `n` nodes in cos θ_l and 2n in φ_l (the lobe is smooth:
/// no kink above the horizon). f64: the table's source.
pub fn sheen_directional_albedo(mu: f64, alpha: f64, n: usize) -> f64 {
    let mu = mu.clamp(1e-6, 1.0);
    let v = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
    let nodes = gauss_legendre(n);
    let phis = gauss_legendre(2 * n);
    let mut sum = 0.0;
    for &(x, wx) in &nodes {
        let cos = 0.5 * (x + 1.0); // cos θ_l ∈ (0, 1), dcos = ½ dx
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        for &(y, wy) in &phis {
            let phi = std::f64::consts::PI * y; // φ ∈ (−π, π), dφ = π dy
            let l = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
            sum += wx * 0.5 * wy * std::f64::consts::PI * sheen_lobe(v, l, alpha) * cos;
        }
    }
    sum
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on the Legendre recurrence).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                derivative = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / derivative;
                x -= step;
                if step.abs() < 1e-15 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * derivative * derivative))
        })
        .collect()
}

/// Entries per axis of the sheen albedo table.
pub const SHEEN_TABLE_SIZE: usize = 32;

/// E(μ, r) over [`SHEEN_TABLE_SIZE`]² cell-centred entries, μ along a row, the sheen's
/// perceptual roughness r (α = r²) down the rows, each integrated in f64
/// ([`sheen_directional_albedo`], 48 × 96 nodes) and capped at 1 (module
/// documentation: the lobe gains energy at grazing for smooth sheen, and the base's
/// scaling stays ≥ 0); computed once per process, on first use.
pub fn sheen_albedo_table() -> &'static [f64] {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let at = |i: usize| (i as f64 + 0.5) / SHEEN_TABLE_SIZE as f64;
        (0..SHEEN_TABLE_SIZE)
            .flat_map(|j| {
                (0..SHEEN_TABLE_SIZE).map(move |i| {
                    let r = at(j);
                    sheen_directional_albedo(at(i), r * r, 48).min(1.0)
                })
            })
            .collect()
    })
}

/// M(μ_v, r) = ∫ max(E(μ_v), E(μ_l)) (n·l)/π dl over [`SHEEN_TABLE_SIZE`]² entries
/// laid out as [`sheen_albedo_table`]'s, E from that table (256 midpoints in μ_l): the
/// base's albedo scaling min(1 − c E(n·v), 1 − c E(n·l)) = 1 − c max(E(n·v), E(n·l))
/// averaged over cosine-weighted light is 1 − c M, exactly for a Lambertian base. What
/// the environment's split sum scales the base's term by.
pub fn sheen_scaling_table() -> &'static [f64] {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let albedo = sheen_albedo_table();
        let at = |i: usize| (i as f64 + 0.5) / SHEEN_TABLE_SIZE as f64;
        const STEPS: usize = 256;
        (0..SHEEN_TABLE_SIZE)
            .flat_map(|j| {
                (0..SHEEN_TABLE_SIZE).map(move |i| {
                    let r = at(j);
                    let e_v = sheen_albedo_lookup(albedo, at(i), r);
                    (0..STEPS)
                        .map(|k| {
                            let mu = (k as f64 + 0.5) / STEPS as f64;
                            e_v.max(sheen_albedo_lookup(albedo, mu, r)) * 2.0 * mu / STEPS as f64
                        })
                        .sum::<f64>()
                })
            })
            .collect()
    })
}

/// E at (μ, r) from `table` ([`sheen_albedo_table`], possibly rounded to f32):
/// bilinear, cell-centred, clamped at the edges (GLSL: `bilinear_cells`).
pub fn sheen_albedo_lookup<T: Real>(table: &[T], mu: T, r: T) -> T {
    let size = SHEEN_TABLE_SIZE;
    let top = T::from_f64((size - 1) as f64);
    let coordinate = |c: T| (c * T::from_f64(size as f64) - T::HALF).clamp_to(T::ZERO, top);
    let (x, y) = (coordinate(mu), coordinate(r));
    let (x0, y0) = (x.to_f64().floor() as usize, y.to_f64().floor() as usize);
    let (x1, y1) = ((x0 + 1).min(size - 1), (y0 + 1).min(size - 1));
    let (fx, fy) = (x - T::from_f64(x0 as f64), y - T::from_f64(y0 as f64));
    let at = |i: usize, j: usize| table[j * size + i];
    let row0 = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * fx;
    let row1 = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * fx;
    row0 + (row1 - row0) * fy
}

/// The extension's albedo scaling of the base under sheen of colour `color`:
/// min(1 − max(c) E(n·v), 1 − max(c) E(n·l)) with E's two values given.
pub fn sheen_albedo_scaling<T: Real>(color: [T; 3], albedo_v: T, albedo_l: T) -> T {
    let c = color[0].max(color[1]).max(color[2]).saturate();
    (T::ONE - c * albedo_v).min(T::ONE - c * albedo_l)
}

/// The sheen's f(v, l) per channel (c D V, not multiplied by a cosine) at a surface of
/// normal `n` (world space), directions `v`, `l` (world space).
pub fn sheen_evaluate<T: Real>(s: &SheenInputs<T>, n: Vec3<T>, v: Vec3<T>, l: Vec3<T>) -> [T; 3] {
    let frame = ShadingFrame::from_normal(n);
    let (v, l) = (frame.to_local(v.normalize()), frame.to_local(l.normalize()));
    let lobe = sheen_lobe(v, l, s.alpha);
    s.color.map(|c| c.saturate() * lobe)
}
