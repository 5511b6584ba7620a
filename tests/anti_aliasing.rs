//! Anti-aliasing (issue 23, item 4): FXAA in the output pass and exact supersampling of
//! still frames, each measured against a 4×4-supersampled frame of the same scene (mean
//! FLIP of the display images, as the speed-against-error report measures them).

use crate::common;

use combustion::renderer::{AntiAliasing, FrameInputs, Readback, RenderError, ToneMapping};
use combustion::report::flip_against_radiance;
use combustion::scene::builtin_scene;

const IMAGES: Readback = Readback::IMAGES;

/// On the sphere grid at 480×360 (silhouettes, highlights): the pixels FXAA changes are
/// nearer the 4×4-supersampled frame than the plain frame's, its mean FLIP no worse;
/// 2×2 supersampling is nearer than the plain frame, 3×3 nearer than 2×2; FXAA leaves every pixel whose 3×3 neighbourhood
/// is one colour as it was; one sample a pixel is the plain frame (its radiance bit for
/// bit, its display codes within one step of the GPU's); factors 0 and 5 are refused.
#[test]
fn anti_aliasing_against_the_supersampled_frame() {
    let scene = builtin_scene("spheres").unwrap();
    let mut headless = common::lavapipe(common::exact_f32());
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).unwrap();
        let inputs = FrameInputs::of_scene(&gpu, 1.0);
        let (w, h) = (480, 360);
        let reference = renderer
            .render_supersampled(&gpu, &inputs, w, h, 4)
            .unwrap();
        let radiance: Vec<[f32; 3]> = reference.hdr.iter().map(|p| [p[0], p[1], p[2]]).collect();
        let flip = |frame: &combustion::renderer::Frame| {
            flip_against_radiance(frame, &radiance, 1.0, ToneMapping::Exponential)
        };
        let plain = renderer.render_with(&gpu, &inputs, w, h, IMAGES).unwrap();
        let fxaa_inputs = FrameInputs {
            anti_aliasing: AntiAliasing::Fxaa,
            ..inputs
        };
        let fxaa = renderer
            .render_with(&gpu, &fxaa_inputs, w, h, IMAGES)
            .unwrap();
        let ss2 = renderer
            .render_supersampled(&gpu, &inputs, w, h, 2)
            .unwrap();
        let ss3 = renderer
            .render_supersampled(&gpu, &inputs, w, h, 3)
            .unwrap();
        let (f_plain, f_fxaa, f_ss2, f_ss3) = (flip(&plain), flip(&fxaa), flip(&ss2), flip(&ss3));
        eprintln!(
            "mean FLIP against 4x4 supersampling: none {f_plain:.5}, fxaa {f_fxaa:.5}, 2x2 {f_ss2:.5}, 3x3 {f_ss3:.5}"
        );
        assert!(f_fxaa < f_plain, "FXAA {f_fxaa} against none {f_plain}");
        assert!(
            f_ss2 < f_plain && f_ss3 < f_ss2,
            "{f_ss2} {f_ss3} against {f_plain}"
        );

        // FXAA touches only where the plain image has contrast.
        let (wi, hi) = (w as i64, h as i64);
        let at =
            |x: i64, y: i64| plain.ldr[(y.clamp(0, hi - 1) * wi + x.clamp(0, wi - 1)) as usize];
        let mut uniform = 0;
        for y in 0..hi {
            for x in 0..wi {
                let centre = at(x, y);
                let flat = (-1..=1).all(|dy| (-1..=1).all(|dx| at(x + dx, y + dy) == centre));
                if flat {
                    uniform += 1;
                    assert_eq!(fxaa.ldr[(y * wi + x) as usize], centre, "({x}, {y})");
                }
            }
        }
        assert!(uniform > 1000, "{uniform} uniform pixels");
        let changed = plain
            .ldr
            .iter()
            .zip(&fxaa.ldr)
            .filter(|(a, b)| a != b)
            .count();
        assert!(changed > 50, "FXAA changed {changed} pixels");

        // One sample a pixel is the plain frame.
        let one = renderer
            .render_supersampled(&gpu, &inputs, w, h, 1)
            .unwrap();
        assert_eq!(one.hdr, plain.hdr);
        for (a, b) in one.ldr.iter().zip(&plain.ldr) {
            for c in 0..3 {
                assert!(a[c].abs_diff(b[c]) <= 1, "{a:?} {b:?}");
            }
        }
        for factor in [0, 5] {
            assert!(matches!(
                renderer.render_supersampled(&gpu, &inputs, w, h, factor),
                Err(RenderError::InvalidSupersample(f)) if f == factor
            ));
        }
    }
    common::finish(headless);
}

/// Frames with and without FXAA (its own output pipeline; without, the output folded into
/// the lighting pass) and frames at a supersampled size (targets of another size, the
/// others retired after the 16-frame delay), in runs
/// of 24 frames, three frames in flight, under validation with synchronisation
/// validation: no message, targets retired, and an FXAA frame at the end the same, bit
/// for bit, as one at the start.
#[test]
fn frames_alternate_anti_aliasing_and_supersampled_sizes_past_the_retire_delay() {
    let scene = common::with_coarse_grid_spheres(builtin_scene("spheres").unwrap());
    let settings = combustion::renderer::RendererSettings {
        frames_in_flight: 3,
        ..common::exact_f32()
    };
    let mut headless = common::lavapipe(settings);
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).unwrap();
        let plain = FrameInputs::of_scene(&gpu, 1.0);
        let fxaa = FrameInputs {
            anti_aliasing: AntiAliasing::Fxaa,
            ..plain
        };
        let (w, h) = (64, 48);
        let first = renderer.render_with(&gpu, &fxaa, w, h, IMAGES).unwrap();
        for round in 0..2 {
            for (inputs, size) in [(&plain, (w, h)), (&fxaa, (w, h)), (&plain, (3 * w, 3 * h))] {
                for _ in 0..24 {
                    renderer
                        .submit_offscreen_with(&gpu, inputs, size.0, size.1)
                        .unwrap();
                }
            }
            renderer.finish_offscreen().unwrap();
            let stats = renderer.stats();
            assert!(
                stats.targets_retired > round,
                "targets of the size not drawn were retired: {stats:?}"
            );
            // The plain frames (read back by nothing) have the output folded into the
            // lighting pass; the FXAA frames run the output pass: both kinds alternate.
            let timings = renderer.take_completed_timings();
            let folded = timings
                .iter()
                .filter(|t| t.ms(combustion::renderer::PassTimings::OUTPUT).is_none())
                .count();
            assert!(
                folded >= 48 && timings.len() - folded >= 24,
                "{folded} folded of {}",
                timings.len()
            );
        }
        let last = renderer.render_with(&gpu, &fxaa, w, h, IMAGES).unwrap();
        assert_eq!(first.ldr, last.ldr);
    }
    common::finish(headless);
}
