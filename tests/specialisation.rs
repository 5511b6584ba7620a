//! Lighting pipelines specialised to a scene's features (`LightingFeatures`) against the
//! general pipeline: for every built-in scene, the HDR radiance of the two (f32 HDR, one
//! renderer, same frame) agree to f32 rounding — each pixel's largest channel difference
//! relative to max(|radiance|, 1e-4) is at most 1e-5 (the parity bound of the f32
//! pipeline against the f64 reference is 1e-3 relative; specialisation only removes code
//! a scene cannot reach and folds η_i = 1, so the results may differ by the rounding of
//! a re-associated expression, not by a model difference).

use crate::common;

use combustion::renderer::{
    HdrFormat, LightingFeatures, Readback, RendererSettings, ShadingOptions,
};
use combustion::scene::{builtin_scene, BUILTIN_SCENES};

const W: u32 = 160;
const H: u32 = 120;
const BOUND: f64 = 1e-5;
const RADIANCE_FLOOR: f64 = 1e-4;

#[test]
fn specialised_and_general_pipelines_agree_on_every_builtin_scene() {
    let mut headless = common::lavapipe(RendererSettings {
        hdr_format: HdrFormat::Rgba32Float,
        ..RendererSettings::default()
    });
    let renderer = headless.renderer();
    let readback = Readback::IMAGES;
    let mut specialised_somewhere = false;
    for name in BUILTIN_SCENES {
        let scene = builtin_scene(name).unwrap();
        renderer
            .set_shading(ShadingOptions::default(), &[])
            .unwrap();
        let gpu = renderer.upload(&scene).unwrap();
        let features = renderer.lighting_features(&gpu);
        assert_eq!(features, LightingFeatures::of(&scene));
        specialised_somewhere |= features != LightingFeatures::ALL;
        let specialised = renderer.render(&gpu, W, H, readback).unwrap();
        let general = ShadingOptions {
            specialised: false,
            ..ShadingOptions::default()
        };
        renderer.set_shading(general, &[&gpu]).unwrap();
        assert_eq!(renderer.lighting_features(&gpu), LightingFeatures::ALL);
        let general = renderer.render(&gpu, W, H, readback).unwrap();
        let (mut worst, mut lit, mut identical) = (0.0f64, 0usize, 0usize);
        for (s, g) in specialised.hdr.iter().zip(&general.hdr) {
            if s == g {
                identical += 1;
            }
            if g[..3] != [0.0; 3] {
                lit += 1;
            }
            for c in 0..3 {
                let (s, g) = (f64::from(s[c]), f64::from(g[c]));
                assert!(s.is_finite(), "{name}: non-finite specialised radiance");
                worst = worst.max((s - g).abs() / g.abs().max(RADIANCE_FLOOR));
            }
        }
        eprintln!(
            "{name}: {features:?}\n  {lit} lit pixels, {identical} of {} identical, largest relative difference {worst:.2e}",
            W * H
        );
        assert!(lit > 0, "{name}: nothing lit");
        assert!(
            worst <= BOUND,
            "{name}: specialised and general pipelines differ by {worst:.3e} (bound {BOUND:.0e})"
        );
        renderer.retire(gpu);
    }
    assert!(
        specialised_somewhere,
        "some built-in scene leaves a feature out"
    );
    common::finish(headless);
}

/// What a scene's materials use decides each feature.
#[test]
fn features_follow_the_materials() {
    let spheres = LightingFeatures::of(&builtin_scene("spheres").unwrap());
    assert!(spheres.anisotropy && spheres.conductors && spheres.dielectrics);
    assert!(!spheres.conductor_table && !spheres.outside_medium);
    assert!(spheres.lambert && !spheres.oren_nayar_qualitative && !spheres.oren_nayar_full);

    let diffuse = LightingFeatures::of(&builtin_scene("diffuse-models").unwrap());
    assert!(!diffuse.conductors && !diffuse.anisotropy);
    assert!(diffuse.lambert && diffuse.oren_nayar_qualitative && diffuse.oren_nayar_full);

    let underwater = LightingFeatures::of(&builtin_scene("underwater").unwrap());
    assert!(underwater.outside_medium);

    let mut all_metal = builtin_scene("gold-copper").unwrap();
    for m in &mut all_metal.materials {
        m.metalness = 1.0;
        m.metallic_roughness_texture = None;
    }
    assert!(!LightingFeatures::of(&all_metal).dielectrics);
}
