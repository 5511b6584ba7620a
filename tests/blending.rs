//! Blended objects (glTF alphaMode BLEND) and the forward pass that draws them, on
//! lavapipe with validation: the pass runs only for scenes that have them; they cast
//! no shadow; the G-buffer reference (the viewer's error view) leaves out what they
//! cover and agrees everywhere else. Their shading and compositing are checked against
//! the f64 scene reference in tests/end_to_end.rs (assets/scenes/blend).

use crate::common;

use combustion::renderer::{PassTimings, RendererSettings, ShadingOptions, ShadowSettings};

const W: u32 = 160;
const H: u32 = 120;

/// A scene without a blended object has no forward pipeline and its frames run no
/// forward pass (what it costs them: nothing); the blend scene's frames run it between
/// the lighting and the output.
#[test]
fn only_scenes_with_blended_objects_run_the_forward_pass() {
    for (name, blended) in [("cutout", false), ("blend", true)] {
        let frame = common::render_images(&common::authored_scene(name), W, H, common::exact_f32());
        let mut expected = vec![PassTimings::GBUFFER, PassTimings::LIGHTING];
        if blended {
            expected.push(PassTimings::FORWARD);
        }
        expected.push(PassTimings::OUTPUT);
        assert_eq!(frame.timings.names(), expected, "{name}");
    }
}

/// Blended objects cast no shadow (the shadow maps hold depth, not coverage; the f64
/// reference's shadow rays pass them too): with shadows on, the blend scene renders bit
/// for bit the same whether its blended objects are marked as casting shadows or not.
/// Its frames read the shadow maps in the forward pass too (the SHADOWS variant of
/// forward.frag, under validation).
#[test]
fn blended_objects_cast_no_shadow() {
    let settings = RendererSettings {
        shading: ShadingOptions {
            shadows: Some(ShadowSettings::DEFAULT),
            ..ShadingOptions::DEFAULT
        },
        ..common::exact_f32()
    };
    let scene = common::authored_scene("blend");
    let mut not_casting = scene.clone();
    for object in &mut not_casting.objects {
        if scene.materials[object.material].is_blended() {
            object.casts_shadows = false;
        }
    }
    assert_ne!(scene.objects, not_casting.objects);
    let casting = common::render_images(&scene, W, H, settings);
    let plain = common::render_images(&not_casting, W, H, settings);
    assert!(casting.timings.ms(PassTimings::SHADOW_MAPS).is_some());
    let differ = casting
        .hdr
        .iter()
        .zip(&plain.hdr)
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differ, 0, "{differ} pixels differ");
}

/// The G-buffer reference (`combustion_renderer::reference`, the viewer's error view)
/// sees the opaque surfaces only: pixels a blended object may cover (its box projected)
/// are counted and left out, background ones included, and every other pixel agrees
/// with it as the parity tests' scenes do (their bound: 1e-3 relative, tests/parity.rs).
#[test]
fn the_error_view_leaves_out_what_blended_objects_cover() {
    let scene = common::authored_scene("blend");
    let (_, map) = common::render_with_error_map(&scene, W, H, common::exact_f32(), 2);
    eprintln!(
        "blend {W}x{H}: {} compared, {} under blended objects, max {:.3e} at {:?}, mean {:.3e}",
        map.lit_pixels, map.blended_pixels, map.max_relative, map.worst_pixel, map.mean_relative
    );
    assert!(map.blended_pixels > 2000, "{}", map.blended_pixels);
    assert!(map.lit_pixels > 5000, "{}", map.lit_pixels);
    assert_eq!(map.background_not_black, 0);
    assert_eq!(map.non_finite, 0);
    assert!(map.max_relative < 1e-3, "max {:.3e}", map.max_relative);
}

/// The viewer's error view compares the pixels of blended and glass surfaces, which
/// the G-buffer reference leaves out, with the scene reference instead (rays cast
/// through the scene in f64, blended surfaces composited): on the blend scene it
/// reports as many of them, with the same errors, as `combustion::end_to_end` finds
/// for the same frame.
#[test]
fn the_viewer_error_view_compares_blended_pixels_with_the_scene_reference() {
    use combustion::end_to_end::{precision_of, SceneReference};
    let scene = common::authored_scene("blend");
    let mut headless = common::lavapipe(common::exact_f32());
    let renderer = headless.renderer();
    let gpu = renderer.upload(&scene).unwrap();
    let inputs = common::frame_inputs(&scene, &scene.lights);
    let summary =
        combustion::viewer::inspect::measure_error(renderer, &gpu, &inputs, (W, H)).unwrap();
    let (pixels, mean, max) = summary.forward.expect("blended pixels compared");
    eprintln!("{pixels} blended pixels: mean {mean:.2e}, max {max:.2e}");
    assert!(pixels > 2000, "{pixels}");
    let frame = common::render(
        &scene,
        W,
        H,
        common::exact_f32(),
        combustion::renderer::Readback::ALL,
    );
    let bvh = combustion::reference::SceneBvh::new(&scene);
    let precision = precision_of(combustion::renderer::GBufferStorage::DEFAULT);
    let reference = SceneReference::new(&scene, &bvh, &scene.lights, (W, H), precision, 2);
    let compared = reference.compare(&frame);
    let under_blended: Vec<f64> = compared
        .pixels
        .iter()
        .filter(|p| !reference.blended(p.x, p.y).is_empty())
        .map(|p| p.total)
        .collect();
    assert_eq!(pixels, under_blended.len());
    let expected_max = under_blended.iter().copied().fold(0.0, f64::max);
    assert!(
        (max - expected_max).abs() <= 1e-12 * expected_max,
        "{max:e} against {expected_max:e}"
    );
}
