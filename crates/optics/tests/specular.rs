//! The dielectric's specular strength and colour (KHR_materials_specular,
//! `combustion_optics::specular`, applied by `brdf_view_layered`): the extension's
//! identities, in f64.

use crate::common::*;
use combustion_optics::brdf::{brdf_evaluate_view, brdf_view, brdf_view_layered, BrdfInputs};
use combustion_optics::fresnel::{fresnel_dielectric, fresnel_schlick};
use combustion_optics::specular::DielectricSpecular;
use combustion_optics::thin_film::ThinFilm;
use combustion_optics::Vec3;

fn material(rng: &mut Lcg) -> BrdfInputs<f64> {
    BrdfInputs {
        metalness: [0.0, 0.0, 0.4][rng.range(0.0, 3.0) as usize % 3],
        outside_eta: [1.0, 1.333][rng.range(0.0, 2.0) as usize % 2],
        dielectric_eta: rng.range(1.05, 2.4),
        polarisation_weight: [0.5, 0.0, 1.0][rng.range(0.0, 3.0) as usize % 3],
        base_color: [
            rng.range(0.0, 1.0),
            rng.range(0.0, 1.0),
            rng.range(0.0, 1.0),
        ],
        ..white_lambert(rng.range(0.01, 1.0))
    }
}

fn random_direction(rng: &mut Lcg) -> Vec3<f64> {
    dir(rng.range(0.0, 1.55), rng.range(0.0, std::f64::consts::TAU))
}

fn f(
    m: &BrdfInputs<f64>,
    specular: &DielectricSpecular<f64>,
    v: Vec3<f64>,
    l: Vec3<f64>,
) -> [f64; 3] {
    brdf_evaluate_view(
        m,
        &brdf_view_layered(m, None, Some(specular), Z, X, Y, v),
        l,
    )
}

/// Factor 1 and colour 1 is the material without the extension, bit for bit (it is not
/// present), with or without a thin film.
#[test]
fn factor_one_and_colour_one_is_the_plain_material_bit_for_bit() {
    let mut rng = Lcg(11);
    let neutral = DielectricSpecular::neutral();
    assert!(!neutral.is_present());
    for _ in 0..2000 {
        let m = material(&mut rng);
        let (v, l) = (random_direction(&mut rng), random_direction(&mut rng));
        let plain = brdf_evaluate_view(&m, &brdf_view(&m, Z, X, Y, v), l);
        assert_eq!(f(&m, &neutral, v, l), plain);
        let film = ThinFilm {
            weight: 0.7,
            eta: 1.8,
            thickness_nm: 400.0,
        };
        let filmed = combustion_optics::brdf_evaluate_with_film(&m, Some(&film), Z, X, Y, v, l);
        let layered = brdf_evaluate_view(
            &m,
            &brdf_view_layered(&m, Some(&film), Some(&neutral), Z, X, Y, v),
            l,
        );
        assert_eq!(layered, filmed);
    }
}

/// The mapping itself, forced at factor 1 and colour 1, returns the dielectric's
/// reflectance to rounding, and 1 − it as the transmittance: the neutral values are the
/// extension's identity, not only a short cut.
#[test]
fn the_mapping_at_factor_one_and_colour_one_is_the_identity() {
    let neutral = DielectricSpecular::neutral();
    for outside in [1.0, 1.333] {
        for eta in [1.1, 1.5, 2.4] {
            let f0 = fresnel_dielectric(1.0, outside, eta).weighted(0.5);
            for i in 0..=100 {
                let c = f64::from(i) / 100.0;
                for w in [0.0, 0.5, 1.0] {
                    let r = fresnel_dielectric(c, outside, eta).weighted(w);
                    for got in neutral.reflectance(r, f0) {
                        assert!((got - r).abs() <= 4.0 * f64::EPSILON, "{c} {eta} {w}");
                    }
                    let t = neutral.transmittance(r, f0);
                    assert!((t - (1.0 - r)).abs() <= 4.0 * f64::EPSILON);
                }
            }
        }
    }
}

/// Factor 0 removes the dielectric's specular lobe and lets all light reach the diffuse
/// lobe: f is exactly (1 − metal) f_diffuse + metal f_conductor, whatever the colour.
#[test]
fn factor_zero_removes_the_specular_lobe() {
    let mut rng = Lcg(12);
    for _ in 0..2000 {
        let m = material(&mut rng);
        let (v, l) = (random_direction(&mut rng), random_direction(&mut rng));
        let none = DielectricSpecular {
            factor: 0.0,
            color: [rng.range(0.0, 3.0), rng.range(0.0, 3.0), 1.0],
        };
        let got = f(&m, &none, v, l);
        // The same material behind no interface: a dielectric matched to the outside
        // medium has R = 0 and T = 1 at every angle, so its BRDF is the diffuse lobe and
        // the conductor's alone.
        let matched = BrdfInputs {
            dielectric_eta: m.outside_eta,
            ..m
        };
        let want = brdf_evaluate_view(&matched, &brdf_view(&matched, Z, X, Y, v), l);
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() <= 1e-12 * want[c].abs() + 1e-300,
                "{got:?} {want:?}"
            );
        }
    }
}

/// With Schlick's curve as the dielectric's reflectance, the mapping is the extension's
/// formula itself: factor (F₀′ + (1 − F₀′)(1 − cos θ)⁵), F₀′ = min(F₀ colour, 1).
#[test]
fn on_schlicks_curve_the_mapping_is_the_extensions_formula() {
    let s = DielectricSpecular {
        factor: 0.6,
        color: [0.2, 1.0, 40.0],
    };
    let f0 = 0.04;
    for i in 0..=50 {
        let c = f64::from(i) / 50.0;
        let got = s.reflectance(fresnel_schlick(c, f0), f0);
        for (ch, &colour) in s.color.iter().enumerate() {
            let f0_prime = (f0 * colour).min(1.0);
            let want = 0.6 * (f0_prime + (1.0 - f0_prime) * (1.0 - c).powi(5));
            assert!(
                (got[ch] - want).abs() <= 1e-15,
                "{c} {ch}: {} {want}",
                got[ch]
            );
        }
    }
}

/// f(v, l) = f(l, v) with a specular strength and colour: the reflectance depends on
/// v·h, the diffuse weight is a product of one factor per direction.
#[test]
fn a_specular_brdf_is_reciprocal() {
    let mut rng = Lcg(13);
    for _ in 0..2000 {
        let m = material(&mut rng);
        let s = DielectricSpecular {
            factor: rng.range(0.0, 1.0),
            color: [
                rng.range(0.0, 2.0),
                rng.range(0.0, 2.0),
                rng.range(0.0, 30.0),
            ],
        };
        let (v, l) = (random_direction(&mut rng), random_direction(&mut rng));
        let (a, b) = (f(&m, &s, v, l), f(&m, &s, l, v));
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-12 * a[c].abs().max(1e-300) + 1e-300,
                "{a:?} {b:?}"
            );
        }
    }
}

/// ∫ f cos ≤ 1 per channel over a white Lambertian dielectric whatever the strength and
/// colour (a colour that saturates F₀′ at 1 included): the diffuse lobe receives
/// 1 − max F′ of each crossing.
#[test]
fn a_specular_dielectric_over_white_conserves_energy() {
    let mut worst = (0.0_f64, String::new());
    for outside in [1.0, 1.333] {
        for alpha in [0.05, 0.3, 0.8] {
            for (factor, color) in [
                (1.0, [2.0, 1.0, 0.0]),
                (0.5, [1.0, 1.0, 1.0]),
                (1.0, [100.0, 100.0, 100.0]),
                (0.3, [25.0, 0.5, 3.0]),
            ] {
                let s = DielectricSpecular { factor, color };
                for deg in [0.0, 45.0, 75.0, 85.0] {
                    let v = dir(f64::to_radians(deg), 0.3);
                    let m = BrdfInputs {
                        outside_eta: outside,
                        ..white_lambert(alpha)
                    };
                    let mut spec_only = m;
                    spec_only.base_color = [0.0; 3];
                    let (spec, diffuse) = albedo_parts(
                        alpha,
                        v,
                        |v, l| f(&spec_only, &s, v, l),
                        |v, l| f(&m, &s, v, l),
                    );
                    for c in 0..3 {
                        let total = spec[c] + diffuse[c];
                        let case =
                            format!("ηi {outside} α {alpha} {factor} {color:?} θv {deg} ch {c}");
                        if total > worst.0 {
                            worst = (total, case.clone());
                        }
                        assert!(total <= 1.0 + 1e-6, "{case}: {total}");
                    }
                }
            }
        }
    }
    println!(
        "a_specular_dielectric_over_white_conserves_energy: largest albedo {:.6} at {}",
        worst.0, worst.1
    );
}
