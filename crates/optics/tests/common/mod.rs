//! Quadrature and input generators shared by the integration tests (f64 only).
#![allow(dead_code)] // each test binary uses a different subset

use combustion_optics::Vec3;
use std::f64::consts::PI;

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
    for (a, b) in pieces(psi_breaks, 4) {
        for (psi, wpsi) in gauss_legendre(n_psi, a, b) {
            let um = u_max(psi);
            if um <= 0.0 {
                continue;
            }
            let (cp, sp) = (psi.cos(), psi.sin());
            for (u, wu) in gauss_legendre(n_u, 0.0, um) {
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

/// ∫ g(l) dω over the upper hemisphere in (θ, φ), Gauss–Legendre in both, with φ split
/// into ≥ 4 pieces, also at the given break angles (where g may have kinks).
pub fn integrate_hemisphere_n<const N: usize>(
    n_theta: usize,
    n_phi: usize,
    phi_breaks: &[f64],
    g: impl Fn(Vec3<f64>) -> [f64; N],
) -> [f64; N] {
    let mut total = [0.0; N];
    let thetas = gauss_legendre(n_theta, 0.0, PI / 2.0);
    for (a, b) in pieces(phi_breaks, 4) {
        for (phi, wphi) in gauss_legendre(n_phi, a, b) {
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
    integrate_hemisphere_n(n_theta, n_phi, phi_breaks, |l| [g(l)])[0]
}

/// The azimuths ψ where κ(ψ) = v.x sx cosψ + v.y sy sinψ changes sign (kinks of
/// [`u_max_front_facing`]).
pub fn kappa_zeros(v: Vec3<f64>, sx: f64, sy: f64) -> [f64; 2] {
    let psi0 = (v.y * sy).atan2(v.x * sx);
    [psi0 + PI / 2.0, psi0 - PI / 2.0]
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
