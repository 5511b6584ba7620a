//! Exposure on lavapipe with validation: the auto exposure's metering against a CPU
//! mirror of its definition on the frame's own HDR image, the output exposed by what it
//! metered, its scale invariance (a scene 1e5 times brighter metered 1e5 times lower),
//! its adaptation speed, and frames that hold nothing to meter. The physical camera's
//! relations are tested in the renderer crate (exposure.rs); the command line's options
//! in tests/cli.rs.

use crate::common;

use combustion::renderer::{
    ev100_of_exposure, exposure_of_ev100, metered_ev100, AutoExposure, Frame, FrameInputs,
    MeteredExposure, Readback, RendererSettings, HISTOGRAM_BINS, METERED_LOG2_LUMINANCE,
};
use combustion::scene::{builtin_scene, Light, Scene};

const IMAGES: Readback = Readback::IMAGES;

/// The metering's definition in f64 on `hdr` (crate::exposure's docs): luminance
/// Y = 0.2126 R + 0.7152 G + 0.0722 B; pixels above 0 counted in 256 bins of log2 Y,
/// darker ones than the span in the first, brighter in the last; the mean of the bin centres of the ranks within the
/// window (a straddling bin in part); EV100 = mean + log2(100 / 12.5) − compensation.
/// The histogram and the EV100.
fn metered_on_cpu(hdr: &[[f32; 4]], auto: &AutoExposure) -> (Vec<u32>, f64) {
    let [low, high] = METERED_LOG2_LUMINANCE.map(f64::from);
    let mut histogram = vec![0u32; HISTOGRAM_BINS];
    for p in hdr {
        let y = 0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2]);
        if y > 0.0 {
            let t = ((y.log2() - low) / (high - low)).clamp(0.0, 1.0);
            histogram[((t * 256.0) as usize).min(255)] += 1;
        }
    }
    let total: f64 = histogram.iter().map(|&n| f64::from(n)).sum();
    let (from, to) = (
        f64::from(auto.window[0]) * total,
        f64::from(auto.window[1]) * total,
    );
    let width = (high - low) / 256.0;
    let (mut below, mut weight, mut sum) = (0.0, 0.0, 0.0);
    for (b, &n) in histogram.iter().enumerate() {
        let n = f64::from(n);
        let inside = ((below + n).min(to) - below.max(from)).max(0.0);
        sum += inside * (low + (b as f64 + 0.5) * width);
        weight += inside;
        below += n;
    }
    let ev100 = sum / weight + (100.0f64 / 12.5).log2() - f64::from(auto.compensation);
    (histogram, ev100)
}

/// A still frame of `scene` (its camera and lights) with `auto`, its HDR image and
/// display read back, and what it metered.
fn metered_frame(
    scene: &Scene,
    (width, height): (u32, u32),
    auto: AutoExposure,
) -> (Frame, MeteredExposure) {
    let mut headless = common::lavapipe(common::exact_f32());
    let result = {
        let renderer = headless.renderer();
        let gpu = renderer.upload(scene).unwrap();
        let inputs = FrameInputs {
            auto_exposure: Some(auto),
            ..FrameInputs::of_scene(&gpu, 1.0)
        };
        let frame = renderer
            .render_with(&gpu, &inputs, width, height, IMAGES)
            .unwrap();
        let metered = renderer.last_metered_exposure().cloned().unwrap();
        (frame, metered)
    };
    common::finish(headless);
    result
}

/// `scene` with every light's power × `factor`.
fn brighter(mut scene: Scene, factor: f32) -> Scene {
    for light in &mut scene.lights {
        match light {
            Light::Point { intensity, .. } | Light::Spot { intensity, .. } => {
                *intensity = intensity.map(|i| i * factor);
            }
            Light::Directional { irradiance, .. } => *irradiance = irradiance.map(|e| e * factor),
        }
    }
    scene
}

/// The sphere grid metered by the GPU is the CPU's metering of the same HDR image: the
/// histogram pixel for pixel (up to pixels whose luminance lies within f32's rounding
/// of a bin's edge), the EV100 within 1e-3; the display image is the HDR image × the
/// metered exposure through the tone curve (so the output pass applied it). The auto
/// exposure lands within the stated 1.5 EV of the grid's hand-set exposure (1, the
/// built-in scenes' default: measured 1.18 EV brighter at 160×90).
#[test]
fn the_metering_is_its_definition_and_the_output_applies_it() {
    let scene = builtin_scene("grid-7x7").unwrap();
    let auto = AutoExposure::default();
    let (frame, metered) = metered_frame(&scene, (160, 90), auto);
    let (histogram, ev100) = metered_on_cpu(&frame.hdr, &auto);
    let moved: u32 = histogram
        .iter()
        .zip(&metered.histogram)
        .map(|(&a, &b)| a.abs_diff(b))
        .sum();
    let counted: u32 = histogram.iter().sum();
    eprintln!(
        "GPU EV100 {:.5} (target {:.5}), CPU {ev100:.5}; {} pixels counted (CPU {counted}), {moved} bin differences; exposure {} against 1 by hand ({:+.2} EV)",
        metered.ev100,
        metered.target_ev100,
        metered.counted,
        metered.exposure,
        metered.exposure.log2()
    );
    assert!(counted > 1000, "{counted}");
    assert_eq!(metered.counted, counted);
    assert!(moved <= 4, "{moved} pixels in other bins");
    assert!((f64::from(metered.ev100) - ev100).abs() < 1e-3);
    assert_eq!(
        metered.ev100, metered.target_ev100,
        "a still frame takes its target"
    );
    assert!((ev100_of_exposure(metered.exposure) - metered.ev100).abs() < 1e-4);
    // The display: every pixel the tone curve of radiance × the metered exposure.
    let curve = combustion::renderer::ToneMapping::Exponential;
    let mut worst = 0.0f64;
    for (hdr, ldr) in frame.hdr.iter().zip(&frame.ldr) {
        let exposed = [0, 1, 2].map(|c| f64::from(hdr[c]) * f64::from(metered.exposure));
        let display = curve.display(exposed);
        for c in 0..3 {
            let expected = combustion::renderer::linear_to_srgb(display[c].clamp(0.0, 1.0)) * 255.0;
            worst = worst.max((f64::from(ldr[c]) - expected).abs());
        }
    }
    assert!(
        worst <= 0.51,
        "{worst} codes from the metered exposure's display"
    );
    assert!(
        metered.exposure.log2().abs() <= 1.5,
        "{} EV from the hand-set exposure",
        metered.exposure.log2()
    );
}

/// Light is metered, not counted: the grid under lights 1e5 times stronger (and a
/// self-lit model of emissive strength 1e5 against strength 1) is exposed 1e5 times
/// less, within one bin of the histogram (0.156 EV); so the hand-set exposure of such a
/// scene (1e-5 of the plain one's, --ev -16.6) is met as closely as the plain one's:
/// within the stated 3 EV (measured: the lit grid +1.18 EV, the self-lit grid −2.13
/// EV, which a meter takes for a mid grey), where an exposure left at 1 is 16.6 EV off.
#[test]
fn a_scene_1e5_times_brighter_is_exposed_1e5_times_less() {
    let plain = builtin_scene("grid-7x7").unwrap();
    let auto = AutoExposure::default();
    let bin = (METERED_LOG2_LUMINANCE[1] - METERED_LOG2_LUMINANCE[0]) / HISTOGRAM_BINS as f32;
    let emissive = |strength: f32| {
        let mut scene = plain.clone();
        scene.lights.clear();
        for material in &mut scene.materials {
            material.emissive_factor = material.base_color;
            material.emissive_strength = strength;
        }
        scene
    };
    for (what, dim, bright) in [
        ("lit", plain.clone(), brighter(plain.clone(), 1e5)),
        ("emissive", emissive(1.0), emissive(1e5)),
    ] {
        let (_, a) = metered_frame(&dim, (160, 90), auto);
        let (_, b) = metered_frame(&bright, (160, 90), auto);
        let stops = b.ev100 - a.ev100;
        eprintln!(
            "{what}: EV100 {:.3} → {:.3}: {stops:.3} stops (log2 1e5 = {:.3}); exposure {:.3e} against {:.3e} by hand ({:+.2} EV)",
            a.ev100,
            b.ev100,
            1e5f32.log2(),
            b.exposure,
            1e-5,
            (b.exposure / 1e-5).log2()
        );
        assert!((stops - 1e5f32.log2()).abs() <= bin, "{what}: {stops}");
        assert!(
            (b.exposure / 1e-5).log2().abs() <= 3.0,
            "{what}: {} EV from the hand-set exposure",
            (b.exposure / 1e-5).log2()
        );
    }
}

/// Adaptation: after a frame metered at once, a scene 1e5 times brighter 0.1 s later
/// moves the exposure by the fall speed × 0.1 s exactly (EV100 up by 0.3 at 3 EV/s),
/// and back towards the dim scene by the rise speed (1 EV/s: 0.1 EV); frames enough
/// reach the target and stay.
#[test]
fn the_exposure_follows_at_its_stated_speeds() {
    let dim = builtin_scene("grid-7x7").unwrap();
    let bright = brighter(dim.clone(), 1e5);
    let mut headless = common::lavapipe(common::exact_f32());
    {
        let renderer = headless.renderer();
        let dim_gpu = renderer.upload(&dim).unwrap();
        let bright_gpu = renderer.upload(&bright).unwrap();
        let mut frame = |gpu: &combustion::renderer::GpuScene, elapsed: Option<f32>| {
            let inputs = FrameInputs {
                auto_exposure: Some(AutoExposure {
                    elapsed_seconds: elapsed,
                    ..AutoExposure::default()
                }),
                ..FrameInputs::of_scene(gpu, 1.0)
            };
            renderer
                .render_with(gpu, &inputs, 64, 36, Readback::default())
                .unwrap();
            renderer.last_metered_exposure().cloned().unwrap()
        };
        let start = frame(&dim_gpu, None);
        let step = frame(&bright_gpu, Some(0.1));
        eprintln!(
            "EV100 {:.4} → {:.4} (target {:.4})",
            start.ev100, step.ev100, step.target_ev100
        );
        assert!((step.ev100 - start.ev100 - 0.3).abs() < 1e-4, "{step:?}");
        let back = frame(&dim_gpu, Some(0.1));
        assert!((step.ev100 - back.ev100 - 0.1).abs() < 1e-4, "{back:?}");
        // 16.6 EV at 3 EV/s: 5.6 s; 60 frames of 0.1 s reach it and hold it.
        let mut last = back;
        for _ in 0..60 {
            last = frame(&bright_gpu, Some(0.1));
        }
        assert_eq!(last.ev100, last.target_ev100);
        assert!((last.exposure - exposure_of_ev100(last.ev100)).abs() <= 1e-6 * last.exposure);
    }
    common::finish(headless);
}

/// Nothing to meter: a frame of black (no light, no background) counts no pixel and
/// takes the frame's own exposure; the brightest frame the inputs allow (a background of
/// 1e30 in an f16 target: lavapipe stores f16's largest value, 65504, in every pixel
/// where no sphere is;
/// a driver that stored infinity would have it counted in the last bin by the shader's
/// clamp, but validated inputs cannot make an infinite pixel here) counts each of them
/// in one bin and meters its centre. Neither exposure is NaN.
#[test]
fn no_frame_drives_the_exposure_to_nan() {
    let mut dark = builtin_scene("grid-7x7").unwrap();
    dark.lights.clear();
    let (_, black) = metered_frame(&dark, (32, 18), AutoExposure::default());
    assert_eq!(black.counted, 0);
    assert!((black.exposure - 1.0).abs() < 1e-6, "{black:?}");
    assert!(
        (black.ev100 - ev100_of_exposure(1.0)).abs() < 1e-5,
        "{black:?}"
    );
    let mut headless = common::lavapipe(RendererSettings {
        hdr_format: combustion::renderer::HdrFormat::Rgba16Float,
        ..common::exact_f32()
    });
    let (glare, frame) = {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&dark).unwrap();
        let inputs = FrameInputs {
            background: combustion::renderer::Background::Color([1e30; 3]),
            auto_exposure: Some(AutoExposure::default()),
            ..FrameInputs::of_scene(&gpu, 1.0)
        };
        let frame = renderer.render_with(&gpu, &inputs, 32, 18, IMAGES).unwrap();
        (renderer.last_metered_exposure().cloned().unwrap(), frame)
    };
    common::finish(headless);
    // The background's pixels (the unlit spheres are black, not counted).
    let stored = frame.hdr[0][0];
    let lit = frame.hdr.iter().filter(|p| p[0] > 0.0).count() as u32;
    eprintln!(
        "stored {stored} in {lit} pixels; EV100 {}, exposure {}",
        glare.ev100, glare.exposure
    );
    assert!(lit > 100, "{lit}");
    assert!(
        frame.hdr.iter().all(|p| p[0] == stored || p[0] == 0.0),
        "one value in every lit pixel"
    );
    assert_eq!(glare.counted, lit);
    let [low, high] = METERED_LOG2_LUMINANCE;
    let width = (high - low) / HISTOGRAM_BINS as f32;
    let bin = (((stored.log2() - low) / width) as usize).min(HISTOGRAM_BINS - 1);
    assert_eq!(glare.histogram[bin], lit);
    assert!(glare.exposure.is_finite() && glare.exposure > 0.0);
    let centre = low + (bin as f32 + 0.5) * width;
    assert!((glare.ev100 - metered_ev100(centre.exp2())).abs() < 1e-3);
}
