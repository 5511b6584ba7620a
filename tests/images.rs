//! Image tests: built-in scenes rendered on lavapipe and compared with goldens (FLIP),
//! and the goldens themselves checked against an independent f64 reference that ray-casts
//! the analytic spheres and shades them with the optics crate.

use crate::common;

use combustion::renderer::{Readback, RendererSettings};
use combustion::scene::{builtin_scene, Scene};

const WIDTH: u32 = 256;
const HEIGHT: u32 = 256;

/// Mean FLIP allowed between a render and its golden. Lavapipe is deterministic for a
/// given Mesa/LLVM build, so the same machine gives 0. The bound is half the mean FLIP
/// that a just-visible change produces — exposure ×1.02 on this scene measured 0.0096
/// (`measure_flip_of_a_just_visible_change`) — so such a change fails while LLVM
/// code-generation noise (a few 8-bit steps in isolated pixels) passes.
const SPHERES_MAX_MEAN_FLIP: f32 = 0.0048;

fn render_spheres(settings: RendererSettings) -> (Scene, combustion::renderer::Frame) {
    let scene = builtin_scene("spheres").unwrap();
    let frame = common::render(&scene, WIDTH, HEIGHT, settings, Readback::IMAGES);
    (scene, frame)
}

#[test]
fn spheres_match_golden() {
    let (_, frame) = render_spheres(RendererSettings::default());
    common::compare_with_golden("spheres_256", &frame, SPHERES_MAX_MEAN_FLIP);
}

/// How the FLIP threshold above was derived (run with --ignored to re-measure).
#[test]
#[ignore]
fn measure_flip_of_a_just_visible_change() {
    let (_, reference) = render_spheres(RendererSettings::default());
    let (_, brighter) = render_spheres(RendererSettings {
        exposure: 1.02,
        ..RendererSettings::default()
    });
    let rgb = |p: &[[u8; 4]]| {
        p.iter()
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect::<Vec<u8>>()
    };
    let a = nv_flip::FlipImageRgb8::with_data(WIDTH, HEIGHT, &rgb(&reference.ldr));
    let b = nv_flip::FlipImageRgb8::with_data(WIDTH, HEIGHT, &rgb(&brighter.ldr));
    let map = nv_flip::flip(a, b, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    println!(
        "mean FLIP of exposure x1.02: {}",
        nv_flip::FlipPool::from_image(&map).mean()
    );
}

/// How far the tessellated sphere's shading normal can stray from the analytic normal
/// at the same pixel: measured by intersecting every interior pixel's ray with the actual
/// 96×48 triangles (`measure_tessellation_normal_error`, run with --ignored): 2.73e-3 rad,
/// rounded up. (Estimate: the triangles lie inside the sphere by up to the sagitta
/// r(1 − cos(π/96)) = 5.4e-4 r; seen at n·v ≥ 0.3 the hit point moves by up to 3.2 times
/// that along the surface, ≈ 1.7e-3 rad, plus the interpolation error of the normals.)
const TESSELLATION_NORMAL_ERROR: f64 = 2.8e-3;

/// The committed golden agrees with the analytic f64 reference, pixel by pixel, on the
/// interior of every sphere. This is the independent check of the golden: it reads the
/// PNG on disk, not a render, and computes every expected pixel from the analytic
/// spheres with the optics crate in f64.
///
/// Pixels whose expected value changes by more than 2 levels when the normal is tilted
/// by the tessellation error (the sharpest highlights) can't be decided by an analytic
/// sphere and are counted but not compared.
#[test]
fn spheres_golden_matches_analytic_reference() {
    let scene = builtin_scene("spheres").unwrap();
    let comparison =
        common::compare_golden_with_analytic(scene, "spheres_256", TESSELLATION_NORMAL_ERROR);
    // Measured: 6.2 % of interior samples lie in highlights too sharp to decide (the
    // smooth columns); the comparison must still cover at least 90 % of them. What remains
    // between the analytic spheres and the render: the 8-bit sRGB storage of base colour
    // (≤ half a step of albedo), the 8-bit output rounding (half a level), and the
    // tessellation (≤ 2 levels by the conditioning filter): worst ≤ 3 levels. Away from
    // the few pixels where those add up, only the two roundings remain (the reference's
    // and the output's, half a level each): nearly all within one level.
    comparison.assert_bounds("spheres_256", 20_001);
}

/// Measures the tessellation's actual normal error on this golden's view (run with
/// --ignored): every interior pixel's ray is intersected with the 64×32 triangles in f64.
#[test]
#[ignore]
fn measure_tessellation_normal_error() {
    let scene = builtin_scene("spheres").unwrap();
    let error = common::measure_tessellation_normal_error(&scene, WIDTH, HEIGHT);
    println!("spheres {WIDTH}x{HEIGHT}: largest normal error {error:.3e} rad");
}

/// The golden gate sees a local regression the mean dilutes: a 20×20 patch of
/// spheres_256 made 30 levels brighter stays under the mean bound but puts hundreds of
/// pixels above the noise level, more than the gate allows.
#[test]
fn a_local_regression_fails_the_golden_gate_though_the_mean_passes() {
    let (_, mut frame) = render_spheres(RendererSettings::default());
    for y in 100..120 {
        for x in 100..120 {
            let p = &mut frame.ldr[(y * frame.width + x) as usize];
            for c in &mut p[..3] {
                *c = c.saturating_add(30);
            }
        }
    }
    let d = common::golden_difference("spheres_256", &frame);
    assert!(d.mean <= SPHERES_MAX_MEAN_FLIP, "{}", d.mean);
    assert!(
        d.above_noise > d.allowed_above_noise,
        "{} pixels",
        d.above_noise
    );
}
