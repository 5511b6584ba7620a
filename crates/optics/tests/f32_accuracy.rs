//! The f32 path against the f64 reference, on the same inputs.
//!
//! Every input is drawn as an f32 and widened exactly to f64, so the difference measures
//! the f32 arithmetic of the arrangement alone, not input rounding. Each bound is stated
//! from the worst error measured by the deterministic sweep in the same test (printed with
//! `--nocapture`), rounded up to a round number 1.4–3.5× above the measurement, with the
//! reason for its size; the proptests then check random inputs against the same bound.
//! Where the problem itself is ill-conditioned (near a critical angle, a narrow lobe,
//! nearly opposite v and l, a cosine computed from world-space vectors) the bound is a
//! multiple of ε times the condition number, computed from the f64 geometry.
//! ε below is f32::EPSILON = 1.19e-7.

use crate::common;

use crate::common::{
    brdf_condition, brdf_err, f, fresnel_condition, local_bound, v32, v64, world_bound, Lcg, EPS,
};
use combustion_optics::brdf::{BrdfInputs, DiffuseModel};
use combustion_optics::diffuse::{diffuse_oren_nayar_full, diffuse_oren_nayar_qualitative};
use combustion_optics::fresnel::{
    fresnel_conductor, fresnel_dielectric, fresnel_dielectric_transmittance, Polarised,
};
use combustion_optics::microfacet::{
    d_beckmann, d_ggx, d_ggx_anisotropic, g1_smith_ggx, lambda_ggx_anisotropic,
    visibility_smith_ggx_height_correlated_anisotropic,
};
use combustion_optics::{Vec3, ALPHA_MIN};
use proptest::prelude::*;

/// The interfaces of the seed-notes hard-case list: (η_i, η_t, k).
const INTERFACES: [(f32, f32, f32); 14] = [
    (1.0, 1.5, 0.0),     // glass in air
    (1.33, 1.5, 0.0),    // glass in water
    (1.0, 1.0001, 0.0),  // η just above 1
    (1.0, 1.0, 0.0),     // η = 1: no reflection
    (1.5, 1.0, 0.0),     // glass → air from inside: TIR
    (1.33, 1.0, 0.0),    // air bubble under water: TIR
    (1.0001, 1.0, 0.0),  // TIR with a critical angle near grazing
    (1.0, 0.18, 3.42),   // gold, red: η < 1
    (1.0, 0.05, 4.2),    // silver: η ≪ 1
    (1.0, 1.2, 7.0),     // aluminium-like
    (1.0, 2.0, 100.0),   // k large
    (1.33, 0.18, 3.42),  // gold under water
    (1.0, 1.0001, 1e-3), // nearly index-matched absorber
    (1.0, 2.4, 0.0),     // diamond
];

fn cosines() -> Vec<f32> {
    let mut c: Vec<f32> = (0..=400).map(|i| i as f32 / 400.0).collect();
    for e in 1..=12 {
        c.push(10f32.powi(-e));
        c.push(1.0 - 10f32.powi(-e.min(7)));
    }
    c
}

/// |ΔR| relative to R_s (f64) for both polarisations; R_p is measured against R_s
/// because it has a zero at Brewster's angle, where no relative accuracy is possible
/// (the zero's position is itself rounded). For any weight w ≤ ½, R_w ≥ R_s/2, so
/// the bound doubles as a relative bound on unpolarised reflectance.
fn fresnel_err(r32: Polarised<f32>, r64: Polarised<f64>) -> f64 {
    if r64.s == 0.0 {
        return if r32.s == 0.0 && r32.p == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
    }
    ((f(r32.s) - r64.s).abs() / r64.s).max((f(r32.p) - r64.p).abs() / r64.s)
}

/// Bound of `fresnel_err` / `fresnel_condition` for the conductor and dielectric
/// reflectances and transmittances: 16 ε ≈ 1.9e-6. Measured worst printed (≈ 6 ε):
/// apart from that conditioning, every sum in the arrangements is of same-sign terms.
const FRESNEL_BOUND: f64 = 16.0 * EPS;

#[test]
fn fresnel_f32_matches_f64() {
    let mut worst_c: f64 = 0.0;
    let mut worst_d: f64 = 0.0;
    let mut worst_t: f64 = 0.0;
    for &(ei, et, k) in &INTERFACES {
        for &c in &cosines() {
            let cond = fresnel_condition(f(c), f(ei), f(et), f(k));
            let e = fresnel_err(
                fresnel_conductor(c, ei, et, k),
                fresnel_conductor(f(c), f(ei), f(et), f(k)),
            ) / cond;
            worst_c = worst_c.max(e);
            assert!(e <= FRESNEL_BOUND, "conductor {ei} {et} {k} c={c}: {e:e}");
            if k == 0.0 {
                let e = fresnel_err(
                    fresnel_dielectric(c, ei, et),
                    fresnel_dielectric(f(c), f(ei), f(et)),
                ) / cond;
                worst_d = worst_d.max(e);
                assert!(e <= FRESNEL_BOUND, "dielectric {ei} {et} c={c}: {e:e}");
                // T = 1 − R, relative per polarisation (no zero inside the range)
                let t32 = fresnel_dielectric_transmittance(c, ei, et);
                let t64 = fresnel_dielectric_transmittance(f(c), f(ei), f(et));
                for (a, b) in [(t32.s, t64.s), (t32.p, t64.p)] {
                    let e = if b == 0.0 { f(a) } else { (f(a) - b).abs() / b } / cond;
                    worst_t = worst_t.max(e);
                    assert!(e <= FRESNEL_BOUND, "transmittance {ei} {et} c={c}: {e:e}");
                }
            }
        }
    }
    println!(
        "fresnel f32 vs f64, error / condition: conductor {:.1} ε, dielectric {:.1} ε, \
         transmittance {:.1} ε",
        worst_c / EPS,
        worst_d / EPS,
        worst_t / EPS
    );
}

/// Seed-notes 10, demonstrated: the notes' printed form (t₁ − t₂)/(t₁ + t₂) in f32 is off
/// by a factor of order ten for η = 1.0001 in air, and by ~1e-5 relative for glass in
/// water, where the crate's arrangement stays within `FRESNEL_BOUND`.
#[test]
fn notes_form_cancels_in_f32_and_ours_does_not() {
    fn notes_rs(c: f32, ei: f32, et: f32, k: f32) -> f32 {
        let s2 = 1.0 - c * c;
        let x = et * et - k * k - ei * ei * s2;
        let root = (x * x + 4.0 * et * et * k * k).sqrt();
        let a2 = (root + x) / (2.0 * ei * ei);
        let b2 = (root - x) / (2.0 * ei * ei);
        let a = a2.sqrt();
        let t1 = a2 + b2 + c * c;
        let t2 = 2.0 * a * c;
        (t1 - t2) / (t1 + t2)
    }
    let mut worst_notes_near_1: f64 = 0.0;
    let mut worst_notes_water: f64 = 0.0;
    let (near_1, water, glass) = (1.0001_f32, 1.33_f32, 1.5_f32);
    for &c in &cosines()[1..] {
        let r64 = fresnel_conductor(f(c), 1.0, f(near_1), 0.0).s;
        let e = (f(notes_rs(c, 1.0, near_1, 0.0)) - r64).abs() / r64;
        worst_notes_near_1 = worst_notes_near_1.max(e);
        let ours = (f(fresnel_conductor(c, 1.0, near_1, 0.0).s) - r64).abs() / r64;
        assert!(ours <= FRESNEL_BOUND, "c={c}: {ours:e}");
        let r64 = fresnel_conductor(f(c), f(water), f(glass), 0.0).s;
        let e = (f(notes_rs(c, water, glass, 0.0)) - r64).abs() / r64;
        worst_notes_water = worst_notes_water.max(e);
        let ours = (f(fresnel_conductor(c, water, glass, 0.0).s) - r64).abs() / r64;
        assert!(ours <= FRESNEL_BOUND, "c={c}: {ours:e}");
    }
    println!(
        "notes' form in f32: η=1.0001 worst relative error {worst_notes_near_1:.2e}, \
         glass in water {worst_notes_water:.2e}"
    );
    assert!(worst_notes_near_1 > 1.0, "{worst_notes_near_1}");
    assert!(worst_notes_water > 1e-5, "{worst_notes_water}");
}

/// Bound for D (GGX isotropic and anisotropic, Beckmann) at the same f32 unit vector
/// m: 16 ε. Measured ≈ 5 ε (printed): D is a product/quotient of positive terms once
/// sin²θ = m.x² + m.y² replaces 1 − (n·m)²; Beckmann adds exp's error, ≈ |x| ε for
/// x = tan²θ/α², so it is held to the same bound only where x ≤ 4 (D ≥ e⁻⁴ D(0)).
const D_BOUND: f64 = 16.0 * EPS;

#[test]
fn distributions_f32_match_f64_near_the_peak() {
    let mut rng = Lcg(3);
    let mut worst: f64 = 0.0;
    let mut worst_naive: f64 = 0.0;
    for _ in 0..20000 {
        let alpha = (ALPHA_MIN * 10f64.powf(rng.range(0.0, 3.0))) as f32;
        let ay = (ALPHA_MIN * 10f64.powf(rng.range(0.0, 3.0))) as f32;
        // within a few α of the normal, where 1 − (n·m)² would cancel
        let theta = rng.range(0.0, 3.0) * f(alpha).min(0.5);
        let phi = rng.range(0.0, 6.3);
        let m = v32(common::dir(theta, phi));
        let mm = v64(m);
        let pairs = [
            (d_ggx(m, alpha), d_ggx(mm, f(alpha))),
            (
                d_ggx_anisotropic(m, alpha, ay),
                d_ggx_anisotropic(mm, f(alpha), f(ay)),
            ),
        ];
        for (a, b) in pairs {
            let e = (f(a) - b).abs() / b;
            worst = worst.max(e);
            assert!(e <= D_BOUND, "α={alpha} θ={theta}: {a} vs {b}");
        }
        if mm.x * mm.x + mm.y * mm.y <= 4.0 * f(alpha).powi(2) * mm.z * mm.z {
            let (a, b) = (d_beckmann(m, alpha), d_beckmann(mm, f(alpha)));
            let e = (f(a) - b).abs() / b;
            worst = worst.max(e);
            assert!(e <= D_BOUND, "Beckmann α={alpha} θ={theta}: {a} vs {b}");
        }
        // the notes' simplified form with (n·m)² in f32
        let c = m.z;
        let a2 = alpha * alpha;
        let naive = a2 / (std::f32::consts::PI * (c * c * (a2 - 1.0) + 1.0).powi(2));
        let b = d_ggx(mm, f(alpha));
        worst_naive = worst_naive.max((f(naive) - b).abs() / b);
    }
    println!(
        "D f32 vs f64 near the peak: {:.1} ε; the notes' form in f32: {:.2e}",
        worst / EPS,
        worst_naive
    );
    // the simplified form loses sin²θ ≈ α² next to 1 when α ≲ 1e-3..1e-2
    assert!(worst_naive > 1e-2, "{worst_naive}");
}

/// Bound for Λ, G₁ and the height-correlated visibility: 8 ε. Measured ≈ 2.3 ε
/// (printed), down to cosθ = 1e-6: no tangent is formed and every sum is of positive
/// terms.
const G_BOUND: f64 = 8.0 * EPS;

#[test]
fn masking_f32_matches_f64_at_grazing() {
    let mut rng = Lcg(5);
    let mut worst: f64 = 0.0;
    for _ in 0..20000 {
        let ax = (ALPHA_MIN * 10f64.powf(rng.range(0.0, 3.0))) as f32;
        let ay = (ALPHA_MIN * 10f64.powf(rng.range(0.0, 3.0))) as f32;
        let v = v32(rng.direction_upper());
        let l = v32(rng.direction_upper());
        let n = Vec3::new(0.0_f32, 0.0, 1.0);
        let (vv, ll) = (v64(v), v64(l));
        let pairs = [
            (
                lambda_ggx_anisotropic(v, ax, ay),
                lambda_ggx_anisotropic(vv, f(ax), f(ay)),
            ),
            (g1_smith_ggx(v, n, ax), g1_smith_ggx(vv, v64(n), f(ax))),
            (
                visibility_smith_ggx_height_correlated_anisotropic(v, l, ax, ay),
                visibility_smith_ggx_height_correlated_anisotropic(vv, ll, f(ax), f(ay)),
            ),
        ];
        for (a, b) in pairs {
            if b == 0.0 {
                assert_eq!(a, 0.0);
                continue;
            }
            let e = (f(a) - b).abs() / b;
            worst = worst.max(e);
            assert!(e <= G_BOUND, "α=({ax},{ay}) v={v:?} l={l:?}: {a} vs {b}");
        }
    }
    println!("Λ, G₁, V f32 vs f64: {:.1} ε", worst / EPS);
}

/// Bound for the Oren–Nayar models: 16 ε (measured ≈ 4.4 ε, printed), relative to the
/// magnitude of the terms, i.e. the value with l mirrored to cosφ ≥ 0, where every term
/// is non-negative: the full model's single-scattering sum has a genuine zero for
/// σ ≳ 0.6 at grazing forward scattering (where it is clamped), and no relative accuracy
/// is possible at a zero of a sum. atan2 and the polynomial terms in β add a few ε each.
const ON_BOUND: f64 = 16.0 * EPS;

#[test]
fn oren_nayar_f32_matches_f64() {
    let mut rng = Lcg(9);
    let mut worst: f64 = 0.0;
    for _ in 0..20000 {
        let v = v32(rng.direction_upper());
        let l = v32(rng.direction_upper());
        let sigma = rng.range(0.0, 0.8) as f32;
        let rho = rng.range(0.01, 1.0) as f32;
        let pairs = [
            (
                diffuse_oren_nayar_qualitative(rho, sigma, 0.33, v, l),
                diffuse_oren_nayar_qualitative(f(rho), f(sigma), f(0.33_f32), v64(v), v64(l)),
            ),
            (
                diffuse_oren_nayar_full(rho, sigma, v, l),
                diffuse_oren_nayar_full(f(rho), f(sigma), v64(v), v64(l)),
            ),
        ];
        let mirrored = Vec3::new(-l.x, -l.y, l.z);
        let l_pos = if v.x * l.x + v.y * l.y >= 0.0 {
            l
        } else {
            mirrored
        };
        let scale = diffuse_oren_nayar_full(f(rho), f(sigma), v64(v), v64(l_pos));
        for (a, b) in pairs {
            let e = (f(a) - b).abs() / b.max(scale);
            worst = worst.max(e);
            assert!(e <= ON_BOUND, "σ={sigma} v={v:?} l={l:?}: {a} vs {b}");
        }
    }
    println!("Oren–Nayar f32 vs f64: {:.1} ε", worst / EPS);
}

fn random_material(rng: &mut Lcg) -> BrdfInputs<f32> {
    let r = |rng: &mut Lcg, a: f64, b: f64| rng.range(a, b) as f32;
    let ei = [1.0, 1.33, 1.5, 1.0001][(rng.next_f64() * 4.0) as usize % 4];
    let ed = [1.5, 1.0, 1.0001, 2.4, 1.33, 1.2][(rng.next_f64() * 6.0) as usize % 6];
    BrdfInputs {
        base_color: [r(rng, 0.0, 1.0), r(rng, 0.0, 1.0), r(rng, 0.0, 1.0)],
        metalness: [0.0, 1.0, r(rng, 0.0, 1.0)][(rng.next_f64() * 3.0) as usize % 3],
        alpha_x: (ALPHA_MIN * 10f64.powf(rng.range(0.0, 3.0))) as f32,
        alpha_y: (ALPHA_MIN * 10f64.powf(rng.range(0.0, 3.0))) as f32,
        conductor_eta: [r(rng, 0.05, 3.0), r(rng, 0.05, 3.0), r(rng, 0.05, 3.0)],
        conductor_k: [r(rng, 0.0, 8.0), r(rng, 0.0, 8.0), r(rng, 0.0, 8.0)],
        dielectric_eta: ed,
        outside_eta: ei,
        polarisation_weight: [0.0, 0.5, 1.0, r(rng, 0.0, 1.0)][(rng.next_f64() * 4.0) as usize % 4],
        diffuse_model: [
            DiffuseModel::Lambert,
            DiffuseModel::OrenNayarQualitative,
            DiffuseModel::OrenNayarFull,
        ][(rng.next_f64() * 3.0) as usize % 3],
        oren_nayar_sigma: r(rng, 0.0, 0.8),
    }
}

#[test]
fn brdf_f32_matches_f64_in_the_shading_frame() {
    let mut rng = Lcg(17);
    let (n, t, b) = (
        Vec3::new(0.0_f32, 0.0, 1.0),
        Vec3::new(1.0_f32, 0.0, 0.0),
        Vec3::new(0.0_f32, 1.0, 0.0),
    );
    let mut worst_ratio: f64 = 0.0;
    let (mut worst_well, mut worst_kd, mut worst_kf): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for _ in 0..20000 {
        let m = random_material(&mut rng);
        let v = v32(rng.direction_upper());
        let l = v32(rng.direction_upper());
        let e = brdf_err(&m, n, t, b, v, l);
        let (kd, kf, _, _) = brdf_condition(&m.convert(), v64(n), v64(t), v64(b), v64(v), v64(l));
        let bound = local_bound(kd, kf);
        worst_ratio = worst_ratio.max(e / bound);
        if kd <= 10.0 && kf <= 2.0 {
            worst_well = worst_well.max(e / EPS);
        }
        if kd > 100.0 && kf <= 2.0 {
            worst_kd = worst_kd.max(e / (EPS * kd));
        }
        if kf > 100.0 && kd < 10.0 {
            worst_kf = worst_kf.max(e / (EPS * kf));
        }
        assert!(e <= bound, "{m:?} v={v:?} l={l:?}: {e:e} > {bound:e}");
    }
    println!(
        "  well conditioned (κ_D ≤ 10, κ_F ≤ 2): {worst_well:.1} ε; \
              κ_D > 100: {worst_kd:.2} ε κ_D; κ_F > 100: {worst_kf:.2} ε κ_F"
    );
    println!("BRDF f32 vs f64 (shading frame): worst error / bound = {worst_ratio:.2}");
}

fn world_case(rng: &mut Lcg) -> [Vec3<f32>; 5] {
    let n = Vec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    );
    let n = (if n.length() < 0.1 {
        Vec3::new(0.0, 0.0, 1.0)
    } else {
        n
    }) * rng.range(0.3, 3.0);
    let frame = combustion_optics::ShadingFrame::from_normal(n);
    let t = frame.t * rng.range(0.5, 2.0) + frame.n * rng.range(-0.5, 0.5);
    let b = frame.b * rng.range(-2.0, 2.0);
    let v = frame.to_world(rng.direction_upper()) * rng.range(0.5, 2.0);
    let l = frame.to_world(rng.direction_upper()) * rng.range(0.5, 2.0);
    [v32(n), v32(t), v32(b), v32(v), v32(l)]
}

fn world_bound_for(m: &BrdfInputs<f32>, g: &[Vec3<f32>; 5]) -> Option<f64> {
    let [n, t, b, v, l] = g.map(v64);
    let (kd, _, kfw, cmin) = brdf_condition(&m.convert(), n, t, b, v, l);
    // a cosine this close to 0 may round to ≤ 0 in f32, where f = 0
    (cmin > 1e-5).then(|| world_bound(kd, kfw))
}

#[test]
fn brdf_f32_matches_f64_in_world_space() {
    let mut rng = Lcg(23);
    let mut worst_ratio: f64 = 0.0;
    let mut worst_cos: f64 = 0.0;
    for _ in 0..20000 {
        let m = random_material(&mut rng);
        let g = world_case(&mut rng);
        let Some(bound) = world_bound_for(&m, &g) else {
            continue;
        };
        let [n, t, b, v, l] = g;
        let e = brdf_err(&m, n, t, b, v, l);
        worst_ratio = worst_ratio.max(e / bound);
        let (kd, _, kfw, _) = brdf_condition(&m.convert(), v64(n), v64(t), v64(b), v64(v), v64(l));
        if kfw > 10.0 * kd && kfw > 100.0 {
            worst_cos = worst_cos.max(e / (EPS * kfw));
        }
        assert!(
            e <= bound,
            "{m:?} n={n:?} v={v:?} l={l:?}: {e:e} > {bound:e}"
        );
    }
    println!("  where κ_F,world dominates (> 100): {worst_cos:.2} ε κ_F,world");
    println!("BRDF f32 vs f64 (world space): worst error / bound = {worst_ratio:.2}");
}

/// f32 values from `lo` to `hi` (both included) on a grid of 2²⁴ steps: proptest's own f32
/// range sampler can trip a debug assertion on some seeds (proptest-rs issues #343, #479
/// and their kin), which made this test fail at random.
fn uniform(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    (0u32..=1 << 24).prop_map(move |i| {
        let t = i as f32 / (1u32 << 24) as f32;
        (lo + (hi - lo) * t).clamp(lo, hi)
    })
}

/// The proptests' seed: fixed, so every run tries the same cases.
const PROPTEST_SEED: u64 = 0x0c0b_u64 << 32 | 0x2026;

proptest! {
    // A fixed seed (the same cases every run, so a failure reproduces) and failures
    // saved beside the crate (proptest-regressions/, replayed first on the next run).
    #![proptest_config(ProptestConfig {
        cases: 512,
        rng_seed: proptest::test_runner::RngSeed::Fixed(PROPTEST_SEED),
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::SourceParallel("proptest-regressions"),
        )),
        ..ProptestConfig::default()
    })]

    /// Random interfaces and angles, including the seed-notes extremes.
    #[test]
    fn prop_fresnel_f32(
        c in prop_oneof![uniform(0.0, 1.0), uniform(0.0, 1e-3), uniform(1.0 - 1e-3, 1.0)],
        ei in prop_oneof![Just(1.0_f32), uniform(1.0, 2.5)],
        et in prop_oneof![Just(1.0_f32), uniform(0.02, 3.0), uniform(0.999, 1.001)],
        k in prop_oneof![Just(0.0_f32), uniform(0.0, 10.0), uniform(10.0, 200.0)],
    ) {
        let cond = fresnel_condition(f(c), f(ei), f(et), f(k));
        let e = fresnel_err(
            fresnel_conductor(c, ei, et, k),
            fresnel_conductor(f(c), f(ei), f(et), f(k)),
        );
        prop_assert!(e <= FRESNEL_BOUND * cond, "{e:e} cond {cond}");
        let cond = fresnel_condition(f(c), f(ei), f(et), 0.0);
        let e = fresnel_err(fresnel_dielectric(c, ei, et), fresnel_dielectric(f(c), f(ei), f(et)));
        prop_assert!(e <= FRESNEL_BOUND * cond, "{e:e} cond {cond}");
    }

    /// Random materials and world-space geometry.
    #[test]
    fn prop_brdf_f32(seed in any::<u64>()) {
        let mut rng = Lcg(seed);
        let m = random_material(&mut rng);
        let g = world_case(&mut rng);
        let bound = world_bound_for(&m, &g);
        prop_assume!(bound.is_some());
        let [n, t, b, v, l] = g;
        let e = brdf_err(&m, n, t, b, v, l);
        prop_assert!(e <= bound.unwrap(), "{e:e}");
    }
}
