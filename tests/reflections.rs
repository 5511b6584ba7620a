//! Ray-traced reflections (`--ray-traced-reflections on`, passes/ray_traced_reflections.rs)
//! measured against light that bounces: the real-time frame's mirror-like surfaces
//! against the f64 path tracer (`combustion_reference::path`, which shares nothing with
//! the renderer but the scene), with and without the option; and a lone object, whose
//! rays meet nothing, unchanged by it. They fail, not skip, without ray queries.

use combustion::renderer::{optional_pass, OptionalPasses};
use combustion::scene::{builtin_scene, ComplexIor, Material, Scene};
use combustion_reference::shading::SceneShading;
use combustion_reference::SceneBvh;

use crate::common;

/// builtin:resting with its sphere a polished silver mirror (perceptual roughness 0.05):
/// it shows the box, the floor and the studio.
fn mirror_resting() -> Scene {
    let mut scene = builtin_scene("resting").unwrap();
    let silver = combustion_spectra::BuiltinMetal::Silver
        .constants(combustion_spectra::MetalColour::default());
    scene.materials[1] = Material {
        name: "polished silver".into(),
        metalness: 1.0,
        roughness: 0.05,
        conductor: ComplexIor {
            eta: silver.eta.map(|x| x as f32),
            k: silver.k.map(|x| x as f32),
        },
        ..Material::default()
    };
    scene.validate().unwrap();
    scene
}

/// The mean relative error of `frame`'s radiance (luminance) against the f64 path
/// tracer's over the pixels of `object` (interior pixels: the four neighbours on it too).
fn error_on_object(
    frame: &[[f32; 4]],
    (width, height): (u32, u32),
    object: usize,
    reference: &[Option<combustion_optics::environment::Estimate>],
    shading: &SceneShading<'_>,
) -> (f64, usize) {
    let on = |x: i64, y: i64| {
        x >= 0
            && y >= 0
            && x < i64::from(width)
            && y < i64::from(height)
            && shading
                .surface(x as u32, y as u32)
                .is_some_and(|s| s.hit.object == object)
    };
    let (mut error, mut weight, mut count) = (0.0, 0.0, 0usize);
    for y in 0..height {
        for x in 0..width {
            let (xi, yi) = (i64::from(x), i64::from(y));
            if !(on(xi, yi) && on(xi + 1, yi) && on(xi - 1, yi) && on(xi, yi + 1) && on(xi, yi - 1))
            {
                continue;
            }
            let i = (y * width + x) as usize;
            let Some(r) = &reference[i] else { continue };
            let l = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
            let f = frame[i];
            let ours = l([f64::from(f[0]), f64::from(f[1]), f64::from(f[2])]);
            let theirs = l(r.mean);
            error += (ours - theirs).abs();
            weight += theirs;
            count += 1;
        }
    }
    (error / weight, count)
}

/// The mirror sphere's pixels against light that bounces (the f64 path tracer, 512
/// paths a pixel at 64×36): the split sum shows the studio where the sphere reflects the
/// box and the floor.
#[test]
fn a_mirror_shows_its_neighbours_as_light_that_bounces_does() {
    let scene = mirror_resting();
    let size = (64, 36);
    let frames = common::radiance_without_and_with(&scene, size, "ray-traced-reflections");
    let reference = common::f64_path_traced(&scene, size, 512);
    // The reference's surfaces, to choose the pixels compared.
    let bvh = SceneBvh::new(&scene);
    let shading = SceneShading::new(&scene, &bvh, &scene.lights, size.0, size.1);
    let (off, count) = error_on_object(&frames[0], size, 1, &reference, &shading);
    let (on, _) = error_on_object(&frames[1], size, 1, &reference, &shading);
    println!(
        "mirror sphere, {count} pixels: mean relative error {off:.4} split sum, {on:.4} traced"
    );
    assert!(count > 50, "{count} pixels of the sphere");
    assert!(on < 0.5 * off, "traced {on} against the split sum's {off}");
}

/// A lone mirror sphere under the studio: every reflection ray leaves the scene and takes
/// the prefiltered radiance the frame shows without the option — the same bytes, on a
/// device that traces them (the pass runs).
#[test]
fn a_lone_object_reflects_what_it_did_without_the_option() {
    let mut scene = mirror_resting();
    scene.objects.retain(|o| o.material == 1);
    scene.validate().unwrap();
    let (w, h) = (96, 54);
    let pass = optional_pass("ray-traced-reflections").expect("the renderer declares it");
    let [off, on] = [false, true].map(|traced| {
        let mut settings = common::exact_f32();
        settings.shading.optional_passes = OptionalPasses::NONE.with(pass, traced);
        common::render_images(&scene, w, h, settings)
    });
    assert!(
        on.timings.names().contains(&"ray-traced reflections"),
        "the pass ran: {:?}",
        on.timings.names()
    );
    let lit = off.hdr.iter().filter(|p| p[0] > 0.0).count();
    assert!(lit > 200, "{lit} pixels of the sphere");
    assert_eq!(common::hdr_pixels_differing(&off, &on), 0);
}
