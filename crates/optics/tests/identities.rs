//! Identities the physics must satisfy, checked by numerical integration in f64.
//!
//! Quadrature: Gauss–Legendre in stretched slope space for lobes (see
//! `common::integrate_slope_space`), with the domain cut exactly where the integrand has a
//! kink, so the rules converge spectrally. Each tolerance below is a stated multiple of
//! the quadrature error measured on an integrand with a known value.

use crate::common::*;
use combustion_optics::brdf::{brdf_evaluate, BrdfInputs, DiffuseModel};
use combustion_optics::diffuse::{
    diffuse_lambert, diffuse_oren_nayar_full, diffuse_oren_nayar_qualitative,
    oren_nayar_sigma_from_roughness, OREN_NAYAR_A_CONSTANT_BRDF, OREN_NAYAR_A_CONSTANT_NOTES,
    OREN_NAYAR_A_CONSTANT_PAPER,
};
use combustion_optics::fresnel::{
    f0_dielectric, fresnel_conductor, fresnel_cook_torrance_1981, fresnel_dielectric,
};
use combustion_optics::microfacet::{
    d_beckmann, d_ggx, d_ggx_anisotropic, g1_smith_ggx_anisotropic, specular_microfacet,
};
use combustion_optics::Vec3;
use std::f64::consts::PI;

const ALPHAS: [f64; 7] = [0.02, 0.05, 0.1, 0.2, 0.4, 0.7, 1.0];
const ANISO: [(f64, f64); 5] = [
    (0.02, 1.0),
    (1.0, 0.02),
    (0.05, 0.3),
    (0.3, 0.1),
    (0.02, 0.08),
];

/// ∫ D(m) (n·m) dω = 1 (seed-notes 2 and 3).
#[test]
fn distributions_are_normalised() {
    let mut worst: f64 = 0.0;
    let mut check = |name: &str, value: f64| {
        worst = worst.max((value - 1.0).abs());
        // 1e-9: Gauss–Legendre with 96×(4×24) nodes on smooth integrands; the measured
        // worst error is printed (≈ 1e-12), the bound leaves room for the mismatched
        // scales, which are the harder integrands.
        assert!((value - 1.0).abs() < 1e-9, "{name}: ∫D cos = {value}");
    };
    for &a in &ALPHAS {
        // quadrature scaled to the lobe, and deliberately mismatched (×1.7, ×0.6) so the
        // change of variable is not the distribution's own inverse CDF
        for scale in [1.0, 1.7, 0.6] {
            let s = a * scale;
            let full = |_| PI / 2.0;
            let i = integrate_slope_space(s, s, 96, 24, &[], full, |m| d_ggx(m, a) * m.z);
            check(&format!("GGX α={a} scale {scale}"), i);
            let i = integrate_slope_space(s, s, 96, 24, &[], full, |m| d_beckmann(m, a) * m.z);
            check(&format!("Beckmann α={a} scale {scale}"), i);
        }
    }
    for &(ax, ay) in &ANISO {
        for scale in [1.0, 1.5] {
            let (sx, sy) = (ax * scale, ay / scale);
            let full = |_| PI / 2.0;
            let i = integrate_slope_space(sx, sy, 96, 24, &[], full, |m| {
                d_ggx_anisotropic(m, ax, ay) * m.z
            });
            check(&format!("GGX αx={ax} αy={ay} scale {scale}"), i);
        }
    }
    println!("distributions_are_normalised: worst |∫D cos − 1| = {worst:.3e}");
}

/// Weak white furnace: ∫ G₁(v, m) D(m) ⟨v·m⟩ / (v·n) dω_m = 1 (Heitz 2014, eq. 16).
#[test]
fn weak_white_furnace() {
    let mut worst: f64 = 0.0;
    let views = [0.0, 30.0, 60.0, 80.0, 89.0, 89.9];
    let mut pairs: Vec<(f64, f64)> = ALPHAS.iter().map(|&a| (a, a)).collect();
    pairs.extend_from_slice(&ANISO);
    for &(ax, ay) in &pairs {
        for &deg in &views {
            for phi in [0.3, 1.9] {
                let v = dir(f64::to_radians(deg), phi);
                let i = integrate_slope_space(
                    ax,
                    ay,
                    96,
                    32,
                    &kappa_zeros(v, ax, ay),
                    u_max_front_facing(v, ax, ay),
                    |m| {
                        g1_smith_ggx_anisotropic(v, m, ax, ay)
                            * d_ggx_anisotropic(m, ax, ay)
                            * v.dot(m).max(0.0)
                            / v.z
                    },
                );
                worst = worst.max((i - 1.0).abs());
                // the cut u_max(ψ) is exact and ψ is split where it has kinks; measured
                // worst ≈ 7e-10 (printed), bound ≈ 13×
                assert!((i - 1.0).abs() < 1e-8, "αx={ax} αy={ay} θv={deg}: {i}");
            }
        }
    }
    println!("weak_white_furnace: worst |I − 1| = {worst:.3e}");
}

/// ∫ f (n·l) dω_l over the reflection lobe, via the half vector: dω_l = 4(v·h) dω_h,
/// cut exactly at l.z = 0 (`u_max_reflection`), per channel.
fn specular_albedo_n<const N: usize>(
    v: Vec3<f64>,
    sx: f64,
    sy: f64,
    n_u: usize,
    n_psi: usize,
    f: impl Fn(Vec3<f64>, Vec3<f64>) -> [f64; N],
) -> [f64; N] {
    let breaks = kappa_zeros_clustered(v, sx, sy);
    integrate_slope_space_n(
        sx,
        sy,
        n_u,
        n_psi,
        &breaks,
        u_max_reflection(v, sx, sy),
        |h| {
            let l = reflect(v, h);
            if l.z <= 0.0 {
                return [0.0; N];
            }
            f(l, h).map(|x| x * l.z * 4.0 * v.dot(h))
        },
    )
}

fn specular_albedo(v: Vec3<f64>, sx: f64, sy: f64, f: impl Fn(Vec3<f64>, Vec3<f64>) -> f64) -> f64 {
    specular_albedo_n(v, sx, sy, 96, 32, |l, h| [f(l, h)])[0]
}

/// Seed-notes 2: with a normalised D the microfacet BRDF divides by 4(n·v)(n·l); the
/// notes' π(n·v)(n·l) would make a perfect reflector (F = G = 1) return 4/π of the light.
#[test]
fn specular_normalisation_is_four_not_pi() {
    let v = Vec3::new(0.0, 0.0, 1.0);
    for a in [0.02, 0.05, 0.1] {
        for (name, d) in [
            ("GGX", d_ggx as fn(Vec3<f64>, f64) -> f64),
            ("Beckmann", d_beckmann),
        ] {
            let e4 = specular_albedo(v, a, a, |l, h| {
                specular_microfacet(d(h, a), 1.0, 1.0, v.z, l.z)
            });
            let epi = e4 * 4.0 / PI;
            // Lost mass: microfacets tilted > 45° reflect below the horizon at normal
            // incidence; for α ≤ 0.1 that is < 1% of D (GGX tail ∝ α²).
            assert!(e4 <= 1.0 + 1e-9 && e4 > 0.99, "{name} α={a}: {e4}");
            assert!(epi > 1.26, "{name} α={a}: the π form returns {epi}");
        }
    }
}

/// Seed-notes 1: the Lambert BRDF ρ/π reflects ρ of the irradiance: ∫ ρ/π cosθ dω = ρ.
#[test]
fn lambert_albedo_is_rho() {
    for rho in [0.0, 0.3, 1.0] {
        let i = integrate_hemisphere(32, 16, &[], |l| diffuse_lambert(rho) * l.z);
        assert!((i - rho).abs() < 1e-13, "{rho}: {i}");
    }
}

fn material(model: DiffuseModel, sigma: f64, ax: f64, ay: f64) -> BrdfInputs<f64> {
    BrdfInputs {
        base_color: [1.0, 0.5, 0.0],
        metalness: 0.0,
        alpha_x: ax,
        alpha_y: ay,
        conductor_eta: [0.18, 0.42, 1.37],
        conductor_k: [3.42, 2.35, 1.77],
        dielectric_eta: 1.5,
        outside_eta: 1.0,
        polarisation_weight: 0.5,
        diffuse_model: model,
        oren_nayar_sigma: sigma,
    }
}

/// How the specular part of an albedo is integrated, and the quadrature error bound
/// that `albedo_quadrature_is_accurate` establishes for the rule.
#[derive(Debug, Clone, Copy, PartialEq)]
enum SpecRule {
    /// Half-vector slope space stretched by (α_x, α_y), cut exactly at the horizon:
    /// resolves any lobe, but the dielectric Fresnel kink at the critical angle of v·h
    /// (TIR, η_i > η_d) crosses its grid.
    Slope,
    /// Half vector in coordinates centred on v, broken at the Fresnel critical angle of
    /// v·h and around an isotropic lobe: used for isotropic TIR configurations.
    VCentred,
}

/// (n_u or n_θ', n_ψ or n_φ' per piece) of the specular rules and (n_θ, n_φ per piece) of
/// the diffuse rule, and their reference resolutions for the accuracy check.
const SLOPE_RES: (usize, usize) = (40, 10);
const VCENTRED_RES: (usize, usize) = (12, 8);
const DIFF_RES: (usize, usize) = (16, 8);
const SLOPE_REF: (usize, usize) = (96, 24);
const VCENTRED_REF: (usize, usize) = (40, 24);
const DIFF_REF: (usize, usize) = (48, 24);

/// Quadrature error bounds per rule, from the errors `albedo_quadrature_is_accurate`
/// measures (printed there) against the reference resolutions, rounded up ≈ 2×:
/// slope space (no Fresnel kink), v-centred (isotropic TIR), and the diffuse (θ, φ) rule.
/// Anisotropic lobes with a TIR kink are resolved by neither specular rule (measured
/// errors ≈ 4e-4 that do not converge fast), so the energy test leaves that combination
/// out; anisotropy and TIR are each covered on their own.
const TOL_SLOPE: f64 = 3e-7;
const TOL_VCENTRED: f64 = 5e-5;
const TOL_DIFF: f64 = 1e-8;

fn spec_rule(m: &BrdfInputs<f64>) -> SpecRule {
    let tir = m.dielectric_eta < m.outside_eta && m.metalness < 1.0;
    if tir {
        assert_eq!(m.alpha_x, m.alpha_y, "no rule for anisotropic TIR lobes");
        SpecRule::VCentred
    } else {
        SpecRule::Slope
    }
}

/// The quadrature error bound of `albedo` for this material.
fn albedo_tolerance(m: &BrdfInputs<f64>) -> f64 {
    TOL_DIFF
        + match spec_rule(m) {
            SpecRule::VCentred => TOL_VCENTRED,
            SpecRule::Slope => TOL_SLOPE,
        }
}

/// Directional albedo ∫ f(v, l) (n·l) dω_l per channel, in the identity frame: the
/// specular part (base colour 0) by a [`SpecRule`], the diffuse part (the difference) in
/// (θ, φ), split at φ_v ± 90°, φ_v, φ_v + π, θ_v (Oren–Nayar's kinks) and the critical
/// angle of n·l (where the diffuse weight vanishes). Returns (specular, diffuse).
fn albedo_parts(
    m: &BrdfInputs<f64>,
    v: Vec3<f64>,
    spec_res: (usize, usize),
    diff_res: (usize, usize),
) -> ([f64; 3], [f64; 3]) {
    (
        albedo_specular(m, v, spec_res),
        albedo_diffuse(m, v, diff_res),
    )
}

/// The specular part of [`albedo_parts`].
fn albedo_specular(m: &BrdfInputs<f64>, v: Vec3<f64>, spec_res: (usize, usize)) -> [f64; 3] {
    let z = Vec3::new(0.0, 0.0, 1.0);
    let x = Vec3::new(1.0, 0.0, 0.0);
    let y = Vec3::new(0.0, 1.0, 0.0);
    let mut spec_only = *m;
    spec_only.base_color = [0.0; 3];
    let f_spec = |l: Vec3<f64>| brdf_evaluate(&spec_only, z, x, y, v, l);
    let ratio = m.dielectric_eta / m.outside_eta;
    match spec_rule(m) {
        SpecRule::Slope => {
            specular_albedo_n(v, m.alpha_x, m.alpha_y, spec_res.0, spec_res.1, |l, _| {
                f_spec(l)
            })
        }
        SpecRule::VCentred => {
            // the Fresnel kink: v·h = cos θ_c
            let kink = (1.0 - ratio * ratio).sqrt().acos();
            integrate_reflection_n(v, m.alpha_x, spec_res.0, spec_res.1, &[kink], |l, _| {
                f_spec(l)
            })
        }
    }
}

/// The diffuse part of [`albedo_parts`].
fn albedo_diffuse(m: &BrdfInputs<f64>, v: Vec3<f64>, diff_res: (usize, usize)) -> [f64; 3] {
    let z = Vec3::new(0.0, 0.0, 1.0);
    let x = Vec3::new(1.0, 0.0, 0.0);
    let y = Vec3::new(0.0, 1.0, 0.0);
    let mut spec_only = *m;
    spec_only.base_color = [0.0; 3];
    let ratio = m.dielectric_eta / m.outside_eta;
    let phi_v = v.y.atan2(v.x);
    let breaks = [phi_v + PI / 2.0, phi_v - PI / 2.0, phi_v, phi_v + PI];
    let mut theta_breaks = vec![v.z.acos()];
    if ratio < 1.0 {
        theta_breaks.push(ratio.asin());
    }
    integrate_hemisphere_n(diff_res.0, diff_res.1, &breaks, &theta_breaks, |l| {
        let a = brdf_evaluate(m, z, x, y, v, l);
        let b = brdf_evaluate(&spec_only, z, x, y, v, l);
        [
            (a[0] - b[0]) * l.z,
            (a[1] - b[1]) * l.z,
            (a[2] - b[2]) * l.z,
        ]
    })
}

fn resolutions(m: &BrdfInputs<f64>, reference: bool) -> ((usize, usize), (usize, usize)) {
    match (spec_rule(m), reference) {
        (SpecRule::Slope, false) => (SLOPE_RES, DIFF_RES),
        (SpecRule::Slope, true) => (SLOPE_REF, DIFF_REF),
        (SpecRule::VCentred, false) => (VCENTRED_RES, DIFF_RES),
        (SpecRule::VCentred, true) => (VCENTRED_REF, DIFF_REF),
    }
}

fn albedo(m: &BrdfInputs<f64>, v: Vec3<f64>) -> [f64; 3] {
    let (sr, dr) = resolutions(m, false);
    let (s, d) = albedo_parts(m, v, sr, dr);
    [s[0] + d[0], s[1] + d[1], s[2] + d[2]]
}

/// The quadratures `albedo` uses: the diffuse rule on an integrand with a known integral
/// (an index-matched dielectric, F = 0 and T = 1, has Lambert albedo exactly ρ), and each
/// rule against itself at 2.5–4× the nodes, on the lobes the energy test integrates.
#[test]
fn albedo_quadrature_is_accurate() {
    let mut lambert = material(DiffuseModel::Lambert, 0.0, 0.1, 0.1);
    lambert.dielectric_eta = 1.0;
    lambert.base_color = [1.0, 0.5, 0.25];
    let mut worst_diff: f64 = 0.0;
    for deg in [0.0, 45.0, 80.0, 89.0] {
        let v = dir(f64::to_radians(deg), 0.7);
        let a = albedo(&lambert, v);
        for (a, rho) in a.iter().zip(lambert.base_color) {
            worst_diff = worst_diff.max((a - rho).abs());
        }
    }
    // worst error per rule
    let mut worst = [0.0_f64; 2];
    for model in [
        DiffuseModel::OrenNayarFull,
        DiffuseModel::OrenNayarQualitative,
    ] {
        for (ax, ay) in [(0.01, 0.01), (1.0, 1.0), (0.05, 0.6), (0.2, 0.2)] {
            for (eta_i, eta_d) in [(1.0, 1.5), (1.5, 1.0)] {
                if eta_i > eta_d && ax != ay {
                    continue; // see TOL_SLOPE
                }
                for deg in [0.0, 50.0, 80.0, 89.0] {
                    let mut m = material(model, 0.7, ax, ay);
                    m.outside_eta = eta_i;
                    m.dielectric_eta = eta_d;
                    let v = dir(f64::to_radians(deg), 0.4);
                    let (sr, dr) = resolutions(&m, false);
                    let (s, d) = albedo_parts(&m, v, sr, dr);
                    let (sr, dr) = resolutions(&m, true);
                    let (s_ref, d_ref) = albedo_parts(&m, v, sr, dr);
                    let slot = match spec_rule(&m) {
                        SpecRule::Slope => 0,
                        SpecRule::VCentred => 1,
                    };
                    for c in 0..3 {
                        worst[slot] = worst[slot].max((s[c] - s_ref[c]).abs());
                        worst_diff = worst_diff.max((d[c] - d_ref[c]).abs());
                    }
                }
            }
        }
    }
    println!(
        "albedo_quadrature_is_accurate: worst errors: slope {:.2e}, v-centred (TIR) {:.2e}, \
         diffuse {:.2e}",
        worst[0], worst[1], worst_diff
    );
    assert!(worst[0] < TOL_SLOPE, "{}", worst[0]);
    assert!(worst[1] < TOL_VCENTRED, "{}", worst[1]);
    assert!(worst_diff < TOL_DIFF, "{worst_diff}");
}

/// ∫ f (n·l) dω ≤ 1 for the assembled BRDF: every diffuse model at white albedo, rough
/// and smooth, isotropic and anisotropic, in air, in water, and seen from inside glass.
#[test]
fn assembled_brdf_conserves_energy() {
    let sigma_max = oren_nayar_sigma_from_roughness(1.0);
    let models = [
        (DiffuseModel::Lambert, 0.0),
        (DiffuseModel::OrenNayarQualitative, sigma_max),
        (DiffuseModel::OrenNayarQualitative, 0.35),
        (DiffuseModel::OrenNayarFull, sigma_max),
        (DiffuseModel::OrenNayarFull, 0.35),
    ];
    let mut worst = (0.0_f64, String::new());
    for (ax, ay) in [(0.01, 0.01), (0.2, 0.2), (1.0, 1.0), (0.05, 0.6)] {
        for (eta_i, eta_d) in [(1.0, 1.5), (1.33, 1.5), (1.5, 1.0), (1.0, 2.4)] {
            if eta_i > eta_d && ax != ay {
                continue; // see TOL_SLOPE
            }
            for deg in [0.0, 50.0, 80.0, 89.0] {
                let v = dir(f64::to_radians(deg), 0.4);
                // the specular part does not depend on the diffuse model: integrate once
                let mut m = material(DiffuseModel::Lambert, 0.0, ax, ay);
                m.outside_eta = eta_i;
                m.dielectric_eta = eta_d;
                m.base_color = [1.0, 1.0, 1.0];
                let (sr, _) = resolutions(&m, false);
                let spec = albedo_specular(&m, v, sr);
                for &(model, sigma) in &models {
                    m.diffuse_model = model;
                    m.oren_nayar_sigma = sigma;
                    let diff = albedo_diffuse(&m, v, DIFF_RES);
                    let a = spec[0] + diff[0];
                    let case = format!(
                        "{model:?} σ={sigma:.3} α=({ax},{ay}) ηi={eta_i} ηd={eta_d} θv={deg}"
                    );
                    if a > worst.0 {
                        worst = (a, case.clone());
                    }
                    // ≤ 1 up to the quadrature error bound of the rules used
                    assert!(a <= 1.0 + albedo_tolerance(&m), "{case}: {a}");
                }
            }
        }
    }
    // conductors (a perfect one, F = 1 everywhere, included): single-scattering GGX ≤ 1
    for (ax, ay) in [(0.01, 0.01), (0.3, 0.3), (1.0, 1.0), (0.05, 0.6)] {
        for deg in [0.0, 60.0, 89.0] {
            let mut m = material(DiffuseModel::Lambert, 0.0, ax, ay);
            m.metalness = 1.0;
            m.conductor_eta = [1e-4, 0.2, 1.5];
            m.conductor_k = [1e4, 3.0, 0.0];
            let v = dir(f64::to_radians(deg), 0.4);
            for a in albedo(&m, v) {
                assert!(
                    a <= 1.0 + albedo_tolerance(&m),
                    "conductor α=({ax},{ay}) θv={deg}: {a}"
                );
            }
        }
    }
    println!(
        "assembled_brdf_conserves_energy: largest albedo {:.6} at {}",
        worst.0, worst.1
    );
}

/// f(v, l) = f(l, v) for the assembled BRDF, including non-unit and skewed frames.
#[test]
fn assembled_brdf_is_reciprocal() {
    let mut rng = Lcg(7);
    let mut worst: f64 = 0.0;
    for i in 0..3000 {
        let model = [
            DiffuseModel::Lambert,
            DiffuseModel::OrenNayarQualitative,
            DiffuseModel::OrenNayarFull,
        ][i % 3];
        let mut m = material(
            model,
            rng.range(0.0, 0.8),
            rng.range(0.0, 1.0),
            rng.range(0.0, 1.0),
        );
        m.metalness = rng.range(0.0, 1.0);
        m.outside_eta = rng.range(1.0, 1.6);
        m.dielectric_eta = rng.range(1.0, 2.5);
        m.polarisation_weight = rng.range(0.0, 1.0);
        m.base_color = [
            rng.range(0.0, 1.0),
            rng.range(0.0, 1.0),
            rng.range(0.0, 1.0),
        ];
        let n = Vec3::new(
            rng.range(-0.3, 0.3),
            rng.range(-0.3, 0.3),
            rng.range(0.5, 2.0),
        );
        let t = Vec3::new(
            rng.range(0.5, 2.0),
            rng.range(-0.5, 0.5),
            rng.range(-0.5, 0.5),
        );
        let b = Vec3::new(0.0, 1.0, 0.0);
        let v = rng.direction_upper() * rng.range(0.5, 3.0);
        let l = rng.direction_upper() * rng.range(0.5, 3.0);
        let f = brdf_evaluate(&m, n, t, b, v, l);
        let g = brdf_evaluate(&m, n, t, b, l, v);
        for c in 0..3 {
            let rel = (f[c] - g[c]).abs() / f[c].abs().max(1e-300);
            worst = worst.max(rel);
            // Exact up to rounding: every term is written symmetrically (v + l, |v + l|,
            // c_l S_v + c_v S_l, T(l)T(v), max/min of the angles); measured worst
            // printed, the bound is 4 ε.
            assert!(rel <= 4.0 * f64::EPSILON, "{model:?}: {} vs {}", f[c], g[c]);
        }
    }
    println!("assembled_brdf_is_reciprocal: worst relative asymmetry {worst:.3e}");
}

/// Conductor Fresnel with k = 0 is the dielectric Fresnel, including under TIR.
#[test]
fn conductor_with_zero_k_is_dielectric() {
    let mut worst: f64 = 0.0;
    for (ei, et) in [
        (1.0, 1.5),
        (1.33, 1.5),
        (1.0, 1.0001),
        (1.5, 1.0),
        (1.0, 0.2),
        (2.0, 1.9999),
    ] {
        for i in 0..=2000 {
            let c = i as f64 / 2000.0;
            let a = fresnel_conductor(c, ei, et, 0.0);
            let d = fresnel_dielectric(c, ei, et);
            let es = (a.s - d.s).abs() / d.s.max(1e-300);
            let ep = (a.p - d.p).abs() / d.s.max(1e-300);
            // Both formulas are cancellation-free arrangements of the same quantity; they
            // agree to a few ε relative to R_s (R_p is compared relative to R_s because it
            // has a zero at Brewster's angle). Near the critical angle R ≈ 1 − k√u with
            // u = (η_t² − η_i² sin²θ)/η_i², so the unavoidable rounding of u (≈ ε c²)
            // moves R by ≈ ε c²/√u: the bound is 64 ε times that condition number (≥ 1).
            let u = ((et - ei) * (et + ei) + ei * ei * c * c) / (ei * ei);
            let cond = (c * c / u.abs().sqrt()).max(1.0);
            worst = worst.max(es / cond).max(ep / cond);
            assert!(
                es <= 64.0 * f64::EPSILON * cond,
                "{ei}/{et} c={c}: s {} vs {}",
                a.s,
                d.s
            );
            assert!(
                ep <= 64.0 * f64::EPSILON * cond,
                "{ei}/{et} c={c}: p {} vs {}",
                a.p,
                d.p
            );
            // past the critical angle (η_t² cos²θ_t < 0) both must give exactly 1
            if (et - ei) * (et + ei) + ei * ei * c * c < 0.0 {
                assert_eq!((d.s, d.p), (1.0, 1.0), "dielectric TIR: {ei} {et} {c}");
                assert_eq!((a.s, a.p), (1.0, 1.0), "conductor TIR: {ei} {et} {c}");
            }
        }
    }
    println!("conductor_with_zero_k_is_dielectric: worst difference / condition = {worst:.3e}");
}

/// R_s = R_p at normal incidence; F(0) = ((η_t − η_i)/(η_t + η_i))² for dielectrics.
#[test]
fn normal_incidence() {
    for (ei, et) in [
        (1.0_f64, 1.5_f64),
        (1.33, 1.5),
        (1.5, 1.0),
        (1.0, 1.0001),
        (1.0, 2.4),
        (1.0, 1.0),
    ] {
        let f0 = f0_dielectric(ei, et);
        let d = fresnel_dielectric(1.0, ei, et);
        let c = fresnel_conductor(1.0, ei, et, 0.0);
        for r in [d.s, d.p, c.s, c.p] {
            assert!(
                (r - f0).abs() <= 4.0 * f64::EPSILON * f0,
                "{ei}/{et}: {r} vs {f0}"
            );
        }
        let ct = fresnel_cook_torrance_1981(1.0, et / ei);
        assert!(
            (ct - f0).abs() <= 8.0 * f64::EPSILON * f0,
            "{ei}/{et}: {ct} vs {f0}"
        );
    }
    for (ei, et, k) in [
        (1.0_f64, 0.18_f64, 3.42_f64),
        (1.33, 1.2, 7.0),
        (1.0, 0.05, 4.2),
    ] {
        let r = fresnel_conductor(1.0, ei, et, k);
        assert!((r.s - r.p).abs() <= 4.0 * f64::EPSILON, "{r:?}");
        // and the conductor normal-incidence formula ((η−ηi)² + k²)/((η+ηi)² + k²)
        let e = ((et - ei).powi(2) + k * k) / ((et + ei).powi(2) + k * k);
        assert!((r.s - e).abs() <= 4.0 * f64::EPSILON, "{} vs {e}", r.s);
    }
}

/// Total internal reflection: exactly 1 past the critical angle; at it and just inside
/// it continuous with 1 (seed-notes 9).
#[test]
fn total_internal_reflection() {
    fn check<T: combustion_optics::Real>(ei: T, et: T) {
        // Just inside the critical angle 1 − R ≈ T_p ≈ 4 (η_i/η_t)² √(2 δc/c) for a
        // cosine δc above critical; within 4 ulps, δc/c ≤ 4ε: bound 5 (η_i/η_t)² √(8ε).
        let near_tol = 5.0 * (ei / et).to_f64().powi(2) * (8.0 * T::EPSILON.to_f64()).sqrt();
        // cos θ_c = √((η_i − η_t)(η_i + η_t))/η_i, free of the cancellation in 1 − (η_t/η_i)²
        let (ei64, et64) = (ei.to_f64(), et.to_f64());
        let c_crit = T::from_f64(((ei64 - et64) * (ei64 + et64)).sqrt() / ei64);
        // past the critical angle (smaller cosine): exactly 1, dielectric and conductor
        for i in 0..=100 {
            let c = c_crit.to_f64() * (i as f64 / 100.0) * (1.0 - 1e-6);
            let c = T::from_f64(c);
            let d = fresnel_dielectric(c, ei, et);
            let k = fresnel_conductor(c, ei, et, T::ZERO);
            for r in [d.s, d.p, k.s, k.p] {
                assert!(r == T::ONE, "c={c}: {r}");
            }
        }
        // at the rounded critical cosine and a few ulps either side: never NaN, never
        // above 1, and within `near_tol` of 1 (R − 1 ∝ √(c − c_crit) just inside)
        let mut c = c_crit;
        for _ in 0..4 {
            c = prev(c);
        }
        for _ in 0..9 {
            let d = fresnel_dielectric(c, ei, et);
            let k = fresnel_conductor(c, ei, et, T::ZERO);
            for r in [d.s, d.p, k.s, k.p] {
                assert!(
                    r <= T::ONE && (T::ONE - r).to_f64() <= near_tol,
                    "c={c}: {r}"
                );
            }
            c = next(c);
        }
        // well inside: below 1
        let inside = T::from_f64(c_crit.to_f64() + 0.1);
        assert!(fresnel_dielectric(inside, ei, et).s < T::ONE);
    }
    fn next<T: combustion_optics::Real>(x: T) -> T {
        let eps = T::EPSILON * x.abs().max(T::from_f64(1e-30));
        x + eps * T::HALF
    }
    fn prev<T: combustion_optics::Real>(x: T) -> T {
        let eps = T::EPSILON * x.abs().max(T::from_f64(1e-30));
        x - eps * T::HALF
    }
    for (ei, et) in [
        (1.5, 1.0),
        (1.33, 1.0),
        (1.5, 1.33),
        (2.4, 1.0),
        (1.0001, 1.0),
    ] {
        check::<f64>(ei, et);
        check::<f32>(ei as f32, et as f32);
    }
}

/// Oren–Nayar → Lambert as σ → 0, qualitative (both constants) and full.
#[test]
fn oren_nayar_tends_to_lambert() {
    let mut rng = Lcg(11);
    let dirs: Vec<_> = (0..400)
        .map(|_| {
            let mut d = || {
                let t = rng.range(0.0, f64::to_radians(80.0));
                dir(t, rng.range(0.0, 2.0 * PI))
            };
            (d(), d())
        })
        .collect();
    let rho = 0.8;
    let lambert = diffuse_lambert(rho);
    let dev = |sigma: f64| {
        let mut worst: f64 = 0.0;
        for &(v, l) in &dirs {
            for f in [
                diffuse_oren_nayar_qualitative(rho, sigma, OREN_NAYAR_A_CONSTANT_PAPER, v, l),
                diffuse_oren_nayar_qualitative(rho, sigma, OREN_NAYAR_A_CONSTANT_NOTES, v, l),
                diffuse_oren_nayar_full(rho, sigma, v, l),
            ] {
                worst = worst.max((f - lambert).abs() / lambert);
            }
        }
        worst
    };
    assert_eq!(dev(0.0), 0.0, "σ = 0 is exactly Lambert");
    let (d3, d4, d5) = (dev(1e-3), dev(1e-4), dev(1e-5));
    // every σ-dependent term is ∝ σ²/(σ² + const) with const ≥ 0.09 and bounded angular
    // factors (θ ≤ 80°: tan ≤ 5.7), so the deviation is ≲ 0.45·5.7·σ²/0.09 ≈ 29 σ²
    assert!(d3 <= 29.0 * 1e-6, "{d3}");
    // and it scales as σ²
    assert!(d4 < d3 / 90.0 && d5 < d4 / 90.0, "{d3} {d4} {d5}");
}

/// Seed-notes 5: measure the qualitative model's A-constant, 0.33 (paper) and 0.57
/// (notes), against the full model with interreflection, and check that the constant
/// the BRDF uses is the closer one for typical albedos.
#[test]
fn oren_nayar_a_constant_choice() {
    // cosine-weighted RMS of (f_q − f_full)/(ρ/π) over (v, l) on a product grid of the
    // hemisphere (Gauss–Legendre in θ, uniform φ_l − φ_v)
    let grid = gauss_legendre(12, 0.0, PI / 2.0);
    let rms = |rho: f64, sigma: f64, a_const: f64| {
        let (mut num, mut den) = (0.0, 0.0);
        for &(tv, wv) in &grid {
            for &(tl, wl) in &grid {
                for k in 0..24 {
                    let phi = (k as f64 + 0.5) * 2.0 * PI / 24.0;
                    let v = dir(tv, 0.0);
                    let l = dir(tl, phi);
                    let w = wv * wl * tv.sin() * tl.sin() * tv.cos() * tl.cos();
                    let q = diffuse_oren_nayar_qualitative(rho, sigma, a_const, v, l);
                    let f = diffuse_oren_nayar_full(rho, sigma, v, l);
                    num += w * ((q - f) / (rho / PI)).powi(2);
                    den += w;
                }
            }
        }
        (num / den).sqrt()
    };
    println!("Oren–Nayar qualitative vs full, cosine-weighted RMS of Δf/(ρ/π):");
    println!("   ρ     σ     A=0.33   A=0.57");
    for rho in [0.2, 0.5, 0.8] {
        for sigma in [0.1, 0.3, 0.5, 0.7] {
            let e33 = rms(rho, sigma, OREN_NAYAR_A_CONSTANT_PAPER);
            let e57 = rms(rho, sigma, OREN_NAYAR_A_CONSTANT_NOTES);
            println!("  {rho:.1}  {sigma:.1}   {e33:.4}   {e57:.4}");
            // measured (printed; also in the docs of OREN_NAYAR_A_CONSTANT_BRDF): 0.33 is
            // closer for every σ at ρ ≤ 0.5; 0.57 only wins at ρ = 0.8, σ ≥ 0.3, where
            // interreflection (∝ ρ²) is large enough for a raised A to imitate it.
            if rho <= 0.5 {
                assert!(e33 < e57, "ρ={rho} σ={sigma}: {e33} vs {e57}");
            }
            if rho >= 0.8 && sigma >= 0.3 {
                assert!(e57 < e33, "ρ={rho} σ={sigma}: {e33} vs {e57}");
            }
        }
    }
    assert_eq!(OREN_NAYAR_A_CONSTANT_BRDF, OREN_NAYAR_A_CONSTANT_PAPER);
}
