//! The output pass's tone curves (`FrameInputs::tone_mapping`) on lavapipe with
//! validation: every display pixel is its HDR radiance × exposure through the curve's CPU
//! mirror (`ToneMapping::display`) and the exact sRGB encoding, within half an 8-bit
//! code (the conversion's rounding) and the f32 curve's last bits.

use crate::common;

use combustion::renderer::{linear_to_srgb, FrameInputs, Readback, ToneMapping};
use combustion::scene::builtin_scene;

#[test]
fn every_tone_curve_is_its_mirror() {
    let scene = builtin_scene("spheres").unwrap();
    let (w, h) = (96, 64);
    let mut headless = common::lavapipe(common::exact_f32());
    for curve in ToneMapping::ALL {
        // Exposure 10 puts the lit spheres past 1, where the curves differ most.
        let exposure = 10.0f32;
        let frame = {
            let renderer = headless.renderer();
            let gpu = renderer.upload(&scene).unwrap();
            let inputs = FrameInputs {
                tone_mapping: curve,
                ..FrameInputs::of_scene(&gpu, exposure)
            };
            let readback = Readback::IMAGES;
            renderer.render_with(&gpu, &inputs, w, h, readback).unwrap()
        };
        let (mut worst, mut above_one) = (0.0f64, 0usize);
        for (hdr, ldr) in frame.hdr.iter().zip(&frame.ldr) {
            let exposed = [0, 1, 2].map(|c| f64::from(hdr[c]) * f64::from(exposure));
            above_one += usize::from(exposed.iter().any(|&x| x > 1.0));
            let display = curve.display(exposed);
            for c in 0..3 {
                let expected = linear_to_srgb(display[c].clamp(0.0, 1.0)) * 255.0;
                worst = worst.max((f64::from(ldr[c]) - expected).abs());
            }
        }
        eprintln!(
            "{}: worst {worst:.3} codes, {above_one} pixels above 1 after exposure",
            curve.name()
        );
        assert!(above_one > 100, "{above_one}");
        // Half a code is the conversion to 8 bits; 0.01 more for the f32 curve's last
        // bits against the f64 mirror (measured: 0.500 for every curve).
        assert!(worst <= 0.51, "{}: {worst} codes", curve.name());
    }
    common::finish(headless);
}

/// The curves' defining properties, in f64: the exponential curve is inverted by
/// −ln(1 − y); PBR Neutral passes a colour below its compression start through
/// unchanged but for the offset near black (0.04 above x = 0.08) and maps any radiance
/// into [0, 1]; the ACES fit clips at 1; AgX keeps greys in order within [0, 1].
#[test]
fn the_curves_keep_their_definitions() {
    use combustion::renderer::{tonemap_aces, tonemap_exponential, tonemap_pbr_neutral};
    for x in [0.0, 0.01, 0.5, 2.0, 10.0] {
        let y = tonemap_exponential(x);
        assert!((-(1.0 - y).ln() - x).abs() < 1e-12 * x.max(1.0), "{x}");
    }
    let mid = tonemap_pbr_neutral([0.5, 0.3, 0.2]);
    for (got, want) in mid.iter().zip([0.46, 0.26, 0.16]) {
        assert!((got - want).abs() < 1e-12, "{mid:?}");
    }
    for rgb in [[100.0, 1.0, 0.0], [5.0, 5.0, 5.0], [1e6, 2e6, 3e6]] {
        let out = tonemap_pbr_neutral(rgb);
        assert!(
            out.iter().all(|c| (0.0..=1.0).contains(c)),
            "{rgb:?} → {out:?}"
        );
    }
    assert_eq!(tonemap_aces(1e3), 1.0);
    assert!(tonemap_aces(0.1) < tonemap_aces(0.2));
    // AgX: greys rise monotonically from black towards white and stay in [0, 1].
    let greys: Vec<f64> = [1e-4, 1e-2, 0.18, 1.0, 10.0, 1e3]
        .map(|g| combustion::renderer::tonemap_agx([g; 3])[1])
        .to_vec();
    assert!(greys.windows(2).all(|w| w[0] < w[1]), "{greys:?}");
    assert!(greys.iter().all(|g| (0.0..=1.0).contains(g)), "{greys:?}");
}
