//! Tiled light culling (`LightCulling`): a culled frame is the unculled frame, bit for
//! bit — the tile lists keep index order and leave out only lights whose range window is
//! exactly 0 over the whole tile — for lights without range (every list holds every
//! light) and for many localised lights with ranges (most lists short). The
//! "lights per tile" debug view shows that the lists really are shorter, and never
//! shorter than the lights without range.

use crate::common;

use combustion::renderer::{
    DebugView, FrameInputs, HdrFormat, LightCulling, Readback, RendererSettings, ShadingOptions,
};
use combustion::scene::{builtin_scene, Light, Scene};
use glam::Vec3;

const W: u32 = 200;
const H: u32 = 136;

/// The sphere grid with `n` small point lights of range 1.2 scattered through it
/// (deterministic), besides its own lights (without range).
fn many_lights(n: usize) -> Scene {
    let mut scene = builtin_scene("spheres").unwrap();
    let mut state = 0x2545_f491_u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        f32::from(u16::try_from(state >> 16).unwrap()) / 65535.0
    };
    for _ in 0..n {
        let position = Vec3::new(next() * 8.0 - 4.0, next() * 5.0 - 2.5, next() * 2.0 - 0.5);
        let colour = [next() * 3.0, next() * 3.0, next() * 3.0];
        scene.lights.push(Light::Point {
            position,
            intensity: colour,
            range: Some(1.2),
            casts_shadows: true,
            radius: 0.0,
        });
    }
    scene
}

fn render_all(scene: &Scene, culling: &[LightCulling], view: DebugView) -> Vec<Vec<[f32; 4]>> {
    let mut headless = common::lavapipe(RendererSettings {
        hdr_format: HdrFormat::Rgba32Float,
        ..RendererSettings::default()
    });
    let renderer = headless.renderer();
    renderer
        .set_shading(
            ShadingOptions {
                debug_view: view,
                ..ShadingOptions::default()
            },
            &[],
        )
        .unwrap();
    let gpu = renderer.upload(scene).unwrap();
    let inputs = FrameInputs::of_scene(&gpu, 1.0);
    let frames = culling
        .iter()
        .map(|&c| {
            renderer.set_light_culling(c);
            renderer
                .render_with(&gpu, &inputs, W, H, Readback::IMAGES)
                .unwrap()
                .hdr
        })
        .collect();
    drop(gpu);
    common::finish(headless);
    frames
}

#[test]
fn culling_changes_no_pixel() {
    let modes = [
        LightCulling::Never,
        LightCulling::Always,
        LightCulling::Auto,
    ];
    // Lights without range: every tile lists every light.
    let plain = render_all(&builtin_scene("spheres").unwrap(), &modes, DebugView::None);
    assert_eq!(plain[0], plain[1], "culling lights without range");
    assert_eq!(plain[0], plain[2]);
    // 96 localised lights with ranges, and the grid's own three.
    let frames = render_all(&many_lights(96), &modes, DebugView::None);
    let lit = frames[0].iter().filter(|p| p[..3] != [0.0; 3]).count();
    assert!(lit > (W * H / 8) as usize, "{lit} lit pixels");
    for (mode, frame) in modes.iter().zip(&frames).skip(1) {
        let differing = frame.iter().zip(&frames[0]).filter(|(a, b)| a != b).count();
        assert_eq!(
            differing, 0,
            "{mode:?}: {differing} pixels differ from the unculled frame"
        );
    }
    // A near plane 5·10⁵ times closer than the scene: the depth → position reconstruction
    // loses digits (w cancels), which the culling pass's error bound covers. (The
    // earlier, size-relative padding passed this case too: no frame here was seen to
    // break it; the bound is the reason it holds in general.)
    let mut near = many_lights(96);
    near.camera.near = 1e-5;
    let frames = render_all(&near, &modes[..2], DebugView::None);
    let lit = frames[0].iter().filter(|p| p[..3] != [0.0; 3]).count();
    assert!(lit > (W * H / 8) as usize, "{lit} lit pixels");
    let differing = frames[1]
        .iter()
        .zip(&frames[0])
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differing, 0, "near plane 1e-5: {differing} pixels differ");
}

#[test]
fn tiles_list_fewer_lights_but_never_fewer_than_the_unranged() {
    let scene = many_lights(96);
    let total = scene.lights.len() as f64;
    let unranged = scene.lights.iter().filter(|l| l.range().is_none()).count() as f64;
    let frames = render_all(
        &scene,
        &[LightCulling::Never, LightCulling::Always],
        DebugView::LightsPerTile,
    );
    // The view writes count / total as a display code c: radiance −ln(1 − decode(c))
    // (debug_views.glsl); the tone curve and the sRGB encoding give c back.
    let fraction = |radiance: f32| {
        let y = 1.0 - (-f64::from(radiance)).exp();
        combustion::renderer::linear_to_srgb(y)
    };
    let shown = |frame: &Vec<[f32; 4]>| -> Vec<f64> {
        frame
            .iter()
            .filter(|p| p[0] > 0.0)
            .map(|p| fraction(p[0]) * total)
            .collect()
    };
    let never = shown(&frames[0]);
    assert!(
        never.iter().all(|&n| (n - total).abs() < 0.5),
        "unculled: every light"
    );
    let always = shown(&frames[1]);
    let fewest = always.iter().copied().fold(f64::INFINITY, f64::min);
    let mean = always.iter().sum::<f64>() / always.len() as f64;
    eprintln!(
        "{total} lights ({unranged} without range): per tile fewest {fewest:.1}, mean {mean:.1}"
    );
    assert!(
        fewest >= unranged - 0.5,
        "a tile left out a light without range"
    );
    assert!(
        mean < total / 2.0,
        "culling left most lights in: mean {mean:.1} of {total}"
    );
}
