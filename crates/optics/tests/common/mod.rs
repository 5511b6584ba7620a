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

/// ∫ g(m) dω over the upper hemisphere, in stretched slope space:
/// m ∝ (−p, −q, 1), p = sx ρ cosψ, q = sy ρ sinψ, ρ = tan u, u ∈ [0, u_max(ψ)].
/// dω = cos³θ dp dq = m.z³ sx sy ρ sec²u du dψ. Gauss–Legendre in u (n_u nodes) and in
/// ψ on `psi_pieces` equal pieces (n_psi nodes each). `u_max(ψ)` ≤ π/2 lets the caller cut
/// the domain exactly where the integrand has a kink.
pub fn integrate_slope_space(
    sx: f64,
    sy: f64,
    n_u: usize,
    n_psi: usize,
    psi_pieces: usize,
    u_max: impl Fn(f64) -> f64,
    g: impl Fn(Vec3<f64>) -> f64,
) -> f64 {
    let mut total = 0.0;
    let piece = 2.0 * PI / psi_pieces as f64;
    for k in 0..psi_pieces {
        for (psi, wpsi) in gauss_legendre(n_psi, k as f64 * piece, (k + 1) as f64 * piece) {
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
                total += wpsi * wu * jac * g(m);
            }
        }
    }
    total
}

/// ∫ g(l) dω over the upper hemisphere in (θ, φ), Gauss–Legendre in both, with φ split
/// into pieces at the given break angles (where g may have kinks).
pub fn integrate_hemisphere(
    n_theta: usize,
    n_phi: usize,
    phi_breaks: &[f64],
    g: impl Fn(Vec3<f64>) -> f64,
) -> f64 {
    let mut breaks: Vec<f64> = phi_breaks
        .iter()
        .map(|b| b.rem_euclid(2.0 * PI))
        .collect();
    breaks.sort_by(f64::total_cmp);
    if breaks.is_empty() {
        breaks.push(0.0);
    }
    let mut total = 0.0;
    let thetas = gauss_legendre(n_theta, 0.0, PI / 2.0);
    for i in 0..breaks.len() {
        let a = breaks[i];
        let b = if i + 1 < breaks.len() {
            breaks[i + 1]
        } else {
            breaks[0] + 2.0 * PI
        };
        for (phi, wphi) in gauss_legendre(n_phi, a, b) {
            for &(theta, wt) in &thetas {
                let l = dir(theta, phi);
                total += wphi * wt * theta.sin() * g(l);
            }
        }
    }
    total
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
