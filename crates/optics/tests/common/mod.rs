//! Quadrature and input generators shared by the integration tests (f64 only).
#![allow(dead_code)] // each test binary uses a different subset

use combustion_optics::{brdf_evaluate, BrdfInputs, ShadingFrame, Vec3, ALPHA_MIN};
use std::f64::consts::PI;

/// The shading frame's axes as world vectors: tangent, bitangent, normal.
pub const X: Vec3<f64> = Vec3 {
    x: 1.0,
    y: 0.0,
    z: 0.0,
};
/// See [`X`].
pub const Y: Vec3<f64> = Vec3 {
    x: 0.0,
    y: 1.0,
    z: 0.0,
};
/// See [`X`].
pub const Z: Vec3<f64> = Vec3 {
    x: 0.0,
    y: 0.0,
    z: 1.0,
};

/// A white Lambertian dielectric of index 1.5 in air, GGX of width `alpha`, unpolarised
/// (gold-like conductor constants, unused while metalness is 0).
pub fn white_lambert(alpha: f64) -> BrdfInputs<f64> {
    BrdfInputs {
        base_color: [1.0, 1.0, 1.0],
        metalness: 0.0,
        alpha_x: alpha,
        alpha_y: alpha,
        conductor_eta: [0.18, 0.42, 1.37],
        conductor_k: [3.42, 2.35, 1.77],
        dielectric_eta: 1.5,
        outside_eta: 1.0,
        polarisation_weight: 0.5,
        diffuse_model: combustion_optics::DiffuseModel::Lambert,
        oren_nayar_sigma: 0.0,
    }
}

/// Gauss–Legendre nodes and weights on [a, b] (Newton on P_n, Golub–Welsch-free).
pub fn gauss_legendre(n: usize, a: f64, b: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    let half = 0.5 * (b - a);
    let mid = 0.5 * (b + a);
    for i in 0..n {
        // Tricomi's initial guess, then Newton.
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((mid + half * x, half * w));
    }
    out
}

/// Gauss–Legendre after the change of variable x = a + (b − a)(3t² − 2t³): nodes cluster
/// at both ends, and an integrand that behaves like √(distance) at an end (a Fresnel
/// critical angle, a cut) becomes smooth in t. The nodes on [0, 1] are computed once.
pub struct Clustered(Vec<(f64, f64)>);

impl Clustered {
    pub fn new(n: usize) -> Self {
        Self(
            gauss_legendre(n, 0.0, 1.0)
                .into_iter()
                .map(|(t, w)| (t * t * (3.0 - 2.0 * t), w * 6.0 * t * (1.0 - t)))
                .collect(),
        )
    }
    pub fn on(&self, a: f64, b: f64) -> Vec<(f64, f64)> {
        self.0
            .iter()
            .map(|&(x, w)| (a + (b - a) * x, w * (b - a)))
            .collect()
    }
}

/// Sorted break points in [0, 2π) and the pieces between them (wrapping around).
fn pieces(breaks: &[f64], min_pieces: usize) -> Vec<(f64, f64)> {
    let mut b: Vec<f64> = breaks.iter().map(|x| x.rem_euclid(2.0 * PI)).collect();
    for k in 0..min_pieces {
        b.push(2.0 * PI * k as f64 / min_pieces as f64);
    }
    b.sort_by(f64::total_cmp);
    b.dedup_by(|x, y| (*x - *y).abs() < 1e-12);
    (0..b.len())
        .map(|i| {
            let end = if i + 1 < b.len() {
                b[i + 1]
            } else {
                b[0] + 2.0 * PI
            };
            (b[i], end)
        })
        .collect()
}

/// ∫ g(m) dω over the upper hemisphere, in stretched slope space:
/// m ∝ (−p, −q, 1), p = sx ρ cosψ, q = sy ρ sinψ, ρ = tan u, u ∈ [0, u_max(ψ)].
/// dω = cos³θ dp dq = m.z³ sx sy ρ sec²u du dψ. Gauss–Legendre in u (n_u nodes) and in
/// ψ (n_psi nodes on each of ≥ 4 pieces, split also at `psi_breaks`, where u_max or g
/// may have kinks). `u_max(ψ)` ≤ π/2 lets the caller cut the domain exactly where the
/// integrand has a kink. Vector-valued so one evaluation serves several channels.
pub fn integrate_slope_space_n<const N: usize>(
    sx: f64,
    sy: f64,
    n_u: usize,
    n_psi: usize,
    psi_breaks: &[f64],
    u_max: impl Fn(f64) -> f64,
    g: impl Fn(Vec3<f64>) -> [f64; N],
) -> [f64; N] {
    let mut total = [0.0; N];
    let (rule_psi, rule_u) = (Clustered::new(n_psi), Clustered::new(n_u));
    for (a, b) in pieces(psi_breaks, 4) {
        for (psi, wpsi) in rule_psi.on(a, b) {
            let um = u_max(psi);
            if um <= 0.0 {
                continue;
            }
            let (cp, sp) = (psi.cos(), psi.sin());
            for (u, wu) in rule_u.on(0.0, um) {
                let rho = u.tan();
                let sec2 = 1.0 + rho * rho;
                let m = Vec3::new(-sx * rho * cp, -sy * rho * sp, 1.0).normalize();
                let jac = m.z.powi(3) * sx * sy * rho * sec2;
                let v = g(m);
                for k in 0..N {
                    total[k] += wpsi * wu * jac * v[k];
                }
            }
        }
    }
    total
}

/// Scalar [`integrate_slope_space_n`].
pub fn integrate_slope_space(
    sx: f64,
    sy: f64,
    n_u: usize,
    n_psi: usize,
    psi_breaks: &[f64],
    u_max: impl Fn(f64) -> f64,
    g: impl Fn(Vec3<f64>) -> f64,
) -> f64 {
    integrate_slope_space_n(sx, sy, n_u, n_psi, psi_breaks, u_max, |m| [g(m)])[0]
}

/// ∫ g(l) dω over the upper hemisphere in (θ, φ), clustered Gauss–Legendre in both,
/// with φ split into ≥ 4 pieces, also at `phi_breaks`, and θ split at `theta_breaks`
/// (where g may have kinks).
pub fn integrate_hemisphere_n<const N: usize>(
    n_theta: usize,
    n_phi: usize,
    phi_breaks: &[f64],
    theta_breaks: &[f64],
    g: impl Fn(Vec3<f64>) -> [f64; N],
) -> [f64; N] {
    let mut total = [0.0; N];
    let mut tb: Vec<f64> = theta_breaks
        .iter()
        .copied()
        .filter(|&t| t > 0.0 && t < PI / 2.0)
        .collect();
    tb.push(0.0);
    tb.push(PI / 2.0);
    tb.sort_by(f64::total_cmp);
    let rule_theta = Clustered::new(n_theta);
    let rule_phi = Clustered::new(n_phi);
    let thetas: Vec<(f64, f64)> = tb
        .windows(2)
        .flat_map(|w| rule_theta.on(w[0], w[1]))
        .collect();
    for (a, b) in pieces(phi_breaks, 4) {
        for (phi, wphi) in rule_phi.on(a, b) {
            for &(theta, wt) in &thetas {
                let v = g(dir(theta, phi));
                for k in 0..N {
                    total[k] += wphi * wt * theta.sin() * v[k];
                }
            }
        }
    }
    total
}

/// Scalar [`integrate_hemisphere_n`].
pub fn integrate_hemisphere(
    n_theta: usize,
    n_phi: usize,
    phi_breaks: &[f64],
    g: impl Fn(Vec3<f64>) -> f64,
) -> f64 {
    integrate_hemisphere_n(n_theta, n_phi, phi_breaks, &[], |l| [g(l)])[0]
}

/// The azimuths ψ where κ(ψ) = v.x sx cosψ + v.y sy sinψ changes sign (kinks of
/// [`u_max_front_facing`]).
pub fn kappa_zeros(v: Vec3<f64>, sx: f64, sy: f64) -> [f64; 2] {
    let psi0 = (v.y * sy).atan2(v.x * sx);
    [psi0 + PI / 2.0, psi0 - PI / 2.0]
}

/// [`kappa_zeros`] plus breaks clustered around them: for a grazing v,
/// [`u_max_reflection`] sweeps from ≈ 0 to ≈ π/2 within ≈ v.z rad of each zero, so
/// breaks at v.z × {1, 3, 10, 30} (those below 0.5 rad) resolve the sweep.
pub fn kappa_zeros_clustered(v: Vec3<f64>, sx: f64, sy: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for z in kappa_zeros(v, sx, sy) {
        out.push(z);
        for k in [1.0, 3.0, 10.0, 30.0] {
            let d = k * v.z.max(1e-3);
            if d < 0.5 {
                out.push(z - d);
                out.push(z + d);
            }
        }
    }
    out
}

/// Unit vector at polar angle θ from +z and azimuth φ.
pub fn dir(theta: f64, phi: f64) -> Vec3<f64> {
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// Mirror reflection of v about unit h: 2(v·h)h − v.
pub fn reflect(v: Vec3<f64>, h: Vec3<f64>) -> Vec3<f64> {
    h * (2.0 * v.dot(h)) - v
}

/// u_max(ψ) in slope space (scales sx, sy) such that the reflection of v about the
/// slope-space normal stays above the horizon: l.z > 0 ⇔ ρ < v.z/(κ + √(κ² + v.z² s²)),
/// κ = v.x sx cosψ + v.y sy sinψ, s² = sx² cos²ψ + sy² sin²ψ.
pub fn u_max_reflection(v: Vec3<f64>, sx: f64, sy: f64) -> impl Fn(f64) -> f64 {
    move |psi: f64| {
        let (c, s) = (psi.cos(), psi.sin());
        let kappa = v.x * sx * c + v.y * sy * s;
        let s2 = (sx * c).powi(2) + (sy * s).powi(2);
        let root = (kappa * kappa + v.z * v.z * s2).sqrt();
        // the two arrangements of the positive root, each free of cancellation
        let rho = if kappa >= 0.0 {
            v.z / (kappa + root)
        } else {
            (root - kappa) / (v.z * s2)
        };
        rho.atan()
    }
}

/// u_max(ψ) such that v·m > 0: ρ < v.z/κ when κ > 0, else the whole range.
pub fn u_max_front_facing(v: Vec3<f64>, sx: f64, sy: f64) -> impl Fn(f64) -> f64 {
    move |psi: f64| {
        let kappa = v.x * sx * psi.cos() + v.y * sy * psi.sin();
        if kappa > 0.0 {
            (v.z / kappa).atan()
        } else {
            PI / 2.0
        }
    }
}

/// A deterministic 64-bit LCG with a 53-bit uniform in [0, 1), for sweeps that must be
/// the same on every run (the measured bounds are stated from them).
pub struct Lcg(pub u64);

impl Lcg {
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next_f64()
    }
    /// A direction with polar angle drawn so grazing angles are well represented:
    /// cosθ = 10^(−6·x³) for half the draws, uniform in [0,1] for the other half.
    pub fn direction_upper(&mut self) -> Vec3<f64> {
        let c = if self.next_f64() < 0.5 {
            10f64.powf(-6.0 * self.next_f64().powi(3))
        } else {
            self.next_f64()
        };
        let s = ((1.0 - c) * (1.0 + c)).sqrt();
        let phi = self.range(0.0, 2.0 * PI);
        Vec3::new(s * phi.cos(), s * phi.sin(), c)
    }
}

/// ∫ g(l, h) (n·l) dω_l over the upper hemisphere of l, parametrised by the half vector h
/// in spherical coordinates centred on v: h = cosθ' v + sinθ' (cosφ' e₁ + sinφ' e₂), e₁
/// the unit direction from v towards n, l = 2(v·h)h − v, dω_l = 4 cosθ' sinθ' dθ' dφ'.
///
/// In these coordinates v·h = cosθ' (so a Fresnel kink at v·h = c_k is the line
/// θ' = acos c_k, passed in `theta_breaks`), the horizon cut l.z > 0 is exactly
/// cosφ' > −v.z cos2θ'/(sinθ_v sin2θ') (so θ' ≤ π/4 + θ_v/2, with a break at
/// π/4 − θ_v/2), and a microfacet lobe of width α sits at θ' = θ_v, φ' = 0, where
/// breaks at ±α, ±3α, ±10α resolve it.
pub fn integrate_reflection_n<const N: usize>(
    v: Vec3<f64>,
    lobe_alpha: f64,
    n_t: usize,
    n_p: usize,
    theta_breaks: &[f64],
    g: impl Fn(Vec3<f64>, Vec3<f64>) -> [f64; N],
) -> [f64; N] {
    let n = Vec3::new(0.0, 0.0, 1.0);
    let sin_v = (v.x * v.x + v.y * v.y).sqrt();
    let theta_v = sin_v.atan2(v.z);
    let e1 = if sin_v > 1e-12 {
        (n - v * v.z).normalize()
    } else {
        Vec3::new(1.0, 0.0, 0.0)
    };
    let e2 = v.cross(e1);
    let top = PI / 4.0 + theta_v / 2.0;
    let mut tb: Vec<f64> = vec![0.0, top, PI / 4.0 - theta_v / 2.0, theta_v];
    for k in [1.0, 3.0, 10.0] {
        tb.push(theta_v - k * lobe_alpha);
        tb.push(theta_v + k * lobe_alpha);
    }
    tb.extend_from_slice(theta_breaks);
    tb.retain(|&t| (0.0..=top).contains(&t));
    tb.sort_by(f64::total_cmp);
    tb.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let mut total = [0.0; N];
    let (rule_t, rule_p) = (Clustered::new(n_t), Clustered::new(n_p));
    for w in tb.windows(2) {
        for (tp, wt) in rule_t.on(w[0], w[1]) {
            let (ct, st) = (tp.cos(), tp.sin());
            // φ' range from the horizon cut
            let phi_max = if sin_v > 1e-12 && st > 0.0 {
                let x = -v.z * (2.0 * ct * ct - 1.0) / (sin_v * 2.0 * st * ct);
                if x >= 1.0 {
                    continue;
                }
                x.max(-1.0).acos()
            } else {
                PI
            };
            let mut pb: Vec<f64> = vec![-phi_max, 0.0, phi_max];
            let width = lobe_alpha / sin_v.max(lobe_alpha);
            for k in [1.0, 3.0, 10.0] {
                pb.push(k * width);
                pb.push(-k * width);
            }
            pb.retain(|&p| p >= -phi_max && p <= phi_max);
            pb.sort_by(f64::total_cmp);
            pb.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
            for pw in pb.windows(2) {
                for (pp, wp) in rule_p.on(pw[0], pw[1]) {
                    let h = v * ct + (e1 * pp.cos() + e2 * pp.sin()) * st;
                    let l = h * (2.0 * ct) - v;
                    if l.z <= 0.0 {
                        continue;
                    }
                    let val = g(l, h);
                    let jac = 4.0 * ct * st * l.z;
                    for k in 0..N {
                        total[k] += wt * wp * jac * val[k];
                    }
                }
            }
        }
    }
    total
}

// ---- f32 error model shared by f32_accuracy.rs and hard_cases.rs ----

/// f32::EPSILON as f64.
pub const EPS: f64 = f32::EPSILON as f64;

/// Condition number of the Fresnel terms with respect to the rounding of cos²θ:
/// 1 + η_i² cos²θ / |η_t² − k² − η_i² sin²θ + 2iη_t k|. Near a dielectric's critical
/// angle R and T depend on √(η_t² − η_i² sin²θ), whose argument is a difference of
/// the inputs' squares: rounding cos²θ (≈ ε) moves it by ≈ ε η_i² cos²θ, so no f32
/// arrangement can do better than ≈ ε × this number there (a backward-stable error).
/// Away from the critical angle it is ≤ 2; for conductors it stays small (k > 0 keeps
/// the modulus away from 0).
pub fn fresnel_condition(c: f64, ei: f64, et: f64, k: f64) -> f64 {
    let u = (et - ei) * (et + ei) - k * k + ei * ei * c * c;
    let w = (u * u + (2.0 * et * k).powi(2)).sqrt();
    if w == 0.0 {
        return 1.0; // index-matched: R ≡ 0 exactly
    }
    1.0 + ei * ei * c * c / w
}

/// The condition numbers the BRDF's f32 error scales with, from the f64 geometry:
/// * κ_D = 1/(α_min cos θ_h): h = (v̂ + l̂)/|v̂ + l̂| inherits the ≈ ε absolute rounding of
///   the normalised v̂, l̂ amplified by 1/|v̂ + l̂| = 1/(2 cos θ_h) (large when v and l are
///   nearly opposite, the neighbourhood of V = −L), and D's relative sensitivity to an
///   angular error δ is up to 2δ/α; α_min = min(α_x, α_y);
/// * κ_F = the largest `fresnel_condition` among the Fresnel terms evaluated (v·h for
///   both lobes, n·v and n·l for the diffuse weight): large only near a critical angle;
/// * κ_F,world, for world-space inputs only, where each cosine is computed in f32 with an
///   absolute rounding of ≈ ε, i.e. ε/cos relative: the largest Fresnel condition
///   divided by the cosine it is evaluated at. It is ≥ 1/min(n·v, n·l), which also
///   covers the BRDF's first-power dependence on n·v, n·l at grazing (Fresnel
///   transmittance, V, Oren–Nayar).
///
/// Returns (κ_D, κ_F, κ_F,world, min(n·v, n·l)).
pub fn brdf_condition(
    m: &BrdfInputs<f64>,
    n: Vec3<f64>,
    t: Vec3<f64>,
    b: Vec3<f64>,
    v: Vec3<f64>,
    l: Vec3<f64>,
) -> (f64, f64, f64, f64) {
    let frame = ShadingFrame::new(n, t, b);
    let v = frame.to_local(v.normalize());
    let l = frame.to_local(l.normalize());
    let cos_h = (v + l).length() / 2.0;
    let alpha = m.alpha_x.min(m.alpha_y).max(ALPHA_MIN);
    let kappa_d = 1.0 / (alpha * cos_h);
    let (ei, ed) = (m.outside_eta, m.dielectric_eta);
    let mut kappa_f: f64 = 1.0;
    let mut kappa_f_world: f64 = 1.0;
    for c in [cos_h, v.z, l.z] {
        let k = fresnel_condition(c, ei, ed, 0.0);
        kappa_f = kappa_f.max(k);
        kappa_f_world = kappa_f_world.max(k / c);
    }
    for c in 0..3 {
        let k = fresnel_condition(cos_h, ei, m.conductor_eta[c], m.conductor_k[c]);
        kappa_f = kappa_f.max(k);
        kappa_f_world = kappa_f_world.max(k / cos_h);
    }
    (kappa_d, kappa_f, kappa_f_world, v.z.min(l.z))
}

/// Bound for the assembled BRDF with inputs in the shading frame (n = z, t = x, b = y
/// exactly): (16 + κ_D + κ_F) ε, see `brdf_condition`. Measured (printed): ≈ 8 ε where
/// well conditioned (κ_D ≤ 10, κ_F ≤ 2), ≈ 0.7 ε κ_D where κ_D dominates, ≈ 0.2 ε κ_F
/// where κ_F does. At α = ALPHA_MIN and cos θ_h = 1 the κ_D term is 1000 ε ≈ 1.2e-4.
pub fn local_bound(kappa_d: f64, kappa_f: f64) -> f64 {
    (16.0 + kappa_d + kappa_f) * EPS
}

/// Bound for the assembled BRDF from world-space inputs (random, non-unit,
/// non-orthogonal normals and tangents): (24 + 1.5 κ_D + 1.5 κ_F,world) ε, see
/// `brdf_condition`. Measured worst error / bound
/// and the coefficient of κ_F,world where it dominates printed; the bound is 1.5× the
/// shading-frame one because the measured worst ratio to that is 0.8.
pub fn world_bound(kappa_d: f64, kappa_f_world: f64) -> f64 {
    1.5 * local_bound(kappa_d, kappa_f_world)
}

/// Exact widening.
pub fn f(x: f32) -> f64 {
    x as f64
}

/// Nearest f32 vector.
pub fn v32(v: Vec3<f64>) -> Vec3<f32> {
    v.convert()
}

/// Exact widening.
pub fn v64(v: Vec3<f32>) -> Vec3<f64> {
    v.convert()
}

/// Relative error of the f32 BRDF per channel, with the scale of the R_p-zero case: for
/// w > ½ the error is measured relative to max(f_w, f_½), since R_w = (1−w)R_s + w R_p
/// has no relative accuracy at Brewster's angle when w → 1 (see `fresnel_err`).
pub fn brdf_err(
    m: &BrdfInputs<f32>,
    n: Vec3<f32>,
    t: Vec3<f32>,
    b: Vec3<f32>,
    v: Vec3<f32>,
    l: Vec3<f32>,
) -> f64 {
    let m64 = m.convert::<f64>();
    let a = brdf_evaluate(m, n, t, b, v, l);
    let e = brdf_evaluate(&m64, v64(n), v64(t), v64(b), v64(v), v64(l));
    let mut half = m64;
    half.polarisation_weight = m64.polarisation_weight.min(0.5);
    let e_half = brdf_evaluate(&half, v64(n), v64(t), v64(b), v64(v), v64(l));
    let mut worst: f64 = 0.0;
    for c in 0..3 {
        assert!(a[c].is_finite() && a[c] >= 0.0, "{a:?}");
        let scale = e[c].max(e_half[c]);
        if scale == 0.0 {
            assert_eq!(a[c], 0.0);
            continue;
        }
        worst = worst.max((f(a[c]) - e[c]).abs() / scale);
    }
    worst
}

/// The directional albedo ∫ f cos dl of a BRDF seen from `v`, per channel, split into its
/// specular part — `specular(v, l)`, the BRDF with a black base, integrated over the GGX
/// lobe of roughness `alpha` in slope space — and its diffuse part — `all(v, l)` less
/// the specular, over the hemisphere. (specular, diffuse).
pub fn albedo_parts(
    alpha: f64,
    v: Vec3<f64>,
    specular: impl Fn(Vec3<f64>, Vec3<f64>) -> [f64; 3],
    all: impl Fn(Vec3<f64>, Vec3<f64>) -> [f64; 3],
) -> ([f64; 3], [f64; 3]) {
    let spec = integrate_slope_space_n(
        alpha,
        alpha,
        96,
        32,
        &kappa_zeros_clustered(v, alpha, alpha),
        u_max_reflection(v, alpha, alpha),
        |h| {
            let l = reflect(v, h);
            if l.z <= 0.0 {
                return [0.0; 3];
            }
            specular(v, l).map(|x| x * l.z * 4.0 * v.dot(h))
        },
    );
    let diffuse: [f64; 3] = integrate_hemisphere_n(48, 24, &[], &[], |l| {
        let (whole, spec) = (all(v, l), specular(v, l));
        std::array::from_fn(|c| (whole[c] - spec[c]) * l.z)
    });
    (spec, diffuse)
}
