//! Bloom (`--bloom on`) on lavapipe with validation: it redistributes radiance and adds
//! none — the frame's total radiance per channel with bloom at any intensity is the
//! total without it, to the f32 sums' rounding (and the f16 format's where the HDR image
//! is f16) — it spreads light from bright pixels to dark ones, and intensity 0 leaves
//! every pixel as it was.

use crate::common;

use combustion::renderer::{Frame, FrameInputs, HdrFormat, Readback, RendererSettings};
use combustion::scene::builtin_scene;

const IMAGES: Readback = Readback::IMAGES;

/// Frames of `scene` (its camera and lights) at `size`: without bloom, then with bloom
/// at each of `intensities`, in an HDR image of `format`.
fn frames(scene: &str, size: (u32, u32), format: HdrFormat, intensities: &[f32]) -> Vec<Frame> {
    let scene = builtin_scene(scene).unwrap();
    let settings = RendererSettings {
        hdr_format: format,
        ..common::exact_f32()
    };
    let mut headless = common::lavapipe(settings);
    let mut out = Vec::new();
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).unwrap();
        let inputs = FrameInputs::of_scene(&gpu, 1.0);
        out.push(
            renderer
                .render_with(&gpu, &inputs, size.0, size.1, IMAGES)
                .unwrap(),
        );
        let mut shading = renderer.shading();
        let bloom = combustion::renderer::optional_pass("bloom").unwrap();
        shading.optional_passes = shading.optional_passes.with(bloom, true);
        renderer.set_shading(shading, &[&gpu]).unwrap();
        for &bloom_intensity in intensities {
            let inputs = FrameInputs {
                bloom_intensity,
                ..inputs
            };
            out.push(
                renderer
                    .render_with(&gpu, &inputs, size.0, size.1, IMAGES)
                    .unwrap(),
            );
        }
    }
    common::finish(headless);
    out
}

/// The frame's radiance summed per channel, in f64.
fn totals(frame: &Frame) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for p in &frame.hdr {
        for c in 0..3 {
            sum[c] += f64::from(p[c]);
        }
    }
    sum
}

/// The frame's total radiance is unchanged by bloom at intensities 0.05 (the default),
/// 0.5 and 1, per channel: within 1e-5 of it in f32 (the GPU's f32 sums of 12,600 pixels;
/// measured below 1e-7), and in an f16 image within 2⁻¹⁰, one unit in the last place of
/// each blended pixel (measured −3.6e-4 to −4.4e-4, all one way, as a conversion that
/// rounds towards zero gives),
/// on the sphere grid (highlights on black) and the Cornell box (a lamp in a room), at a
/// size whose halvings are odd (150×84: 75×42, 38×21, …). The bloom moved light: pixels
/// differ from the frame without it, the darkest pixels brighten.
#[test]
fn bloom_moves_radiance_and_adds_none() {
    for (scene, format, bound) in [
        ("grid-7x7", HdrFormat::Rgba32Float, 1e-5),
        ("cornell-box", HdrFormat::Rgba32Float, 1e-5),
        ("grid-7x7", HdrFormat::Rgba16Float, 2f64.powi(-10)),
    ] {
        let frames = frames(scene, (150, 84), format, &[0.05, 0.5, 1.0]);
        let plain = totals(&frames[0]);
        for (frame, intensity) in frames[1..].iter().zip([0.05f64, 0.5, 1.0]) {
            let bloomed = totals(frame);
            let worst = (0..3)
                .map(|c| ((bloomed[c] - plain[c]) / plain[c]).abs())
                .fold(0.0, f64::max);
            let moved = frames[0]
                .hdr
                .iter()
                .zip(&frame.hdr)
                .map(|(a, b)| (0..3).map(|c| f64::from((a[c] - b[c]).abs())).sum::<f64>())
                .sum::<f64>()
                / plain.iter().sum::<f64>();
            eprintln!(
                "{scene} {format:?} intensity {intensity}: totals {plain:.4?} → {bloomed:.4?}, relative {worst:.2e}; radiance moved {moved:.3} of the total"
            );
            assert!(worst <= bound, "{scene} {intensity}: {worst:e}");
            // Light changed place: at least a tenth of the intensity's share of the total
            // (measured 0.28 to 1.4 times it).
            assert!(
                moved > 0.1 * intensity,
                "{scene} {intensity}: moved {moved}"
            );
        }
        // The darkest tenth of the plain frame's pixels gain light from the glow.
        let mut order: Vec<usize> = (0..frames[0].hdr.len()).collect();
        let lum = |p: &[f32; 4]| common::luminance(*p);
        order.sort_by(|&a, &b| lum(&frames[0].hdr[a]).total_cmp(&lum(&frames[0].hdr[b])));
        let dark = &order[..order.len() / 10];
        let gain: f64 = dark
            .iter()
            .map(|&i| lum(&frames[3].hdr[i]) - lum(&frames[0].hdr[i]))
            .sum();
        assert!(gain > 0.0, "{scene}: the dark pixels gained {gain}");
    }
}

/// Bloom at intensity 0 is the frame without it, bit for bit (the composite blends the
/// glow at α = 0).
#[test]
fn bloom_at_intensity_zero_changes_nothing() {
    let frames = frames("grid-7x7", (96, 54), HdrFormat::Rgba32Float, &[0.0]);
    assert_eq!(common::hdr_pixels_differing(&frames[0], &frames[1]), 0);
    assert_eq!(common::pixels_apart(&frames[0], &frames[1]), 0);
}
