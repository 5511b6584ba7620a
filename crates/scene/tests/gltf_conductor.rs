//! The base-colour → η + ik mapping for glTF metals (docs/gltf.md, "Metals"), checked
//! against the optics crate's full Fresnel equations.

use combustion_optics::fresnel::{fresnel_conductor, fresnel_schlick};
use combustion_scene::conductor_from_reflectivity;

fn reflectance(cos: f64, eta: f32, k: f32) -> f64 {
    fresnel_conductor(cos, 1.0, f64::from(eta), f64::from(k)).weighted(0.5)
}

#[test]
fn normal_incidence_reflectance_is_the_base_colour() {
    for r in [0.0f32, 0.02, 0.04, 0.1, 0.3, 0.5, 0.7, 0.9, 0.95, 0.99] {
        let c = conductor_from_reflectivity([r; 3]);
        assert!(c.eta[0] > 0.0 && c.k[0] >= 0.0, "{r}: {c:?}");
        let f0 = reflectance(1.0, c.eta[0], c.k[0]);
        assert!((f0 - f64::from(r)).abs() < 1e-5, "r {r}: F0 {f0} ({c:?})");
    }
}

#[test]
fn the_fresnel_curve_follows_schlick() {
    for r in [0.04f32, 0.2, 0.5, 0.8, 0.95] {
        let c = conductor_from_reflectivity([r; 3]);
        let mut worst: f64 = 0.0;
        for i in 0..=100 {
            let cos = f64::from(i) / 100.0;
            let exact = reflectance(cos, c.eta[0], c.k[0]);
            let schlick = fresnel_schlick(cos, f64::from(r));
            worst = worst.max((exact - schlick).abs());
        }
        assert!(worst < 0.06, "r {r}: max |F − Schlick| = {worst}");
    }
}

#[test]
fn channels_are_independent_and_metal_like() {
    // A gold-like base colour: the more a channel reflects, the smaller its η (as in
    // measured gold, η ≈ 0.18, 0.42, 1.37), and the weakly reflecting blue has the least k.
    let c = conductor_from_reflectivity([0.95, 0.75, 0.33]);
    assert!(c.eta[0] < c.eta[1] && c.eta[1] < c.eta[2], "{c:?}");
    assert!(c.k[2] < c.k[0] && c.k[2] < c.k[1], "{c:?}");
    // Out-of-range and NaN inputs stay usable.
    let c = conductor_from_reflectivity([1.0, f32::NAN, -1.0]);
    assert!(c.eta.iter().all(|x| x.is_finite() && *x > 0.0), "{c:?}");
    assert!(c.k.iter().all(|x| x.is_finite() && *x >= 0.0), "{c:?}");
}
