//! The text overlay (`FrameInputs::overlay`): drawn by the output pass over the frame,
//! on lavapipe with validation. Every pixel of a frame with panels is checked against
//! the same frame without them, composited on the CPU from the laid-out quads and the
//! font atlas (`OverlayFont::composite_unorm8`, src·α + dst·(1 − α) in f64): the GPU's
//! result may differ by one 8-bit step (its blend is rounded once more to 8 bits).
//! Pixels under no quad must be byte-identical.

use crate::common;

use combustion::renderer::{
    Corner, Frame, FrameInputs, OverlayImage, OverlayPanel, Readback, Renderer, RendererSettings,
};
use combustion::scene::builtin_scene;

const W: u32 = 320;
const H: u32 = 200;

#[test]
fn overlay_panels_blend_exactly_over_the_frame() {
    let mut headless = common::lavapipe(RendererSettings::default());
    let renderer = headless.renderer();
    let gpu = renderer.upload(&builtin_scene("spheres").unwrap()).unwrap();
    let panels = [
        OverlayPanel {
            text: "spheres 320×200\nGPU 72.8 ms · 13.7 fps",
            corner: Corner::TopLeft,
        },
        OverlayPanel {
            text: "H\thelp\nV\tdebug view (G-buffer, BRDF terms)",
            corner: Corner::TopRight,
        },
        OverlayPanel {
            text: "ημ≤ unknown: ☃",
            corner: Corner::BottomRight,
        },
    ];
    let readback = Readback::IMAGES;
    let plain = renderer.render(&gpu, W, H, readback).unwrap();
    let inputs = FrameInputs {
        overlay: &panels,
        environment: None,
        ..FrameInputs::of_scene(&gpu, renderer.settings().exposure)
    };
    let with_text = renderer.render_with(&gpu, &inputs, W, H, readback).unwrap();
    let (covered, bright) = check_overlay(&plain, &with_text, renderer, &panels, None);
    // The panels cover part of the frame and the text puts bright pixels on dark panels.
    assert!(
        covered > 2000 && covered < (W * H / 2) as usize,
        "{covered}"
    );
    assert!(bright > 300, "{bright} text pixels");

    // An overlay image (a gradient smaller than the frame) under the same panels.
    let image = OverlayImage {
        width: 200,
        height: 120,
        rgba: (0..200 * 120)
            .map(|i| [(i % 200) as u8, (i / 200 * 2) as u8, 77, 255])
            .collect(),
    };
    renderer.set_overlay_image(Some(&image)).unwrap();
    let with_image = renderer.render_with(&gpu, &inputs, W, H, readback).unwrap();
    let (covered, _) = check_overlay(&plain, &with_image, renderer, &panels, Some(&image));
    assert!(covered >= 200 * 120, "{covered}");
    // Taken away again: the frame is as before.
    renderer.set_overlay_image(None).unwrap();
    let again = renderer.render_with(&gpu, &inputs, W, H, readback).unwrap();
    assert_eq!(again.ldr, with_text.ldr);
    let wrong = OverlayImage {
        width: 3,
        height: 3,
        rgba: vec![[0; 4]; 8],
    };
    let error = renderer.set_overlay_image(Some(&wrong)).unwrap_err();
    assert!(error.to_string().contains("needs 9 texels"), "{error}");
    drop(gpu);
    common::finish(headless);
}

/// Checks every pixel of `with` against `plain` composited on the CPU with the quads of
/// `panels` (and `image`); the pixels under some quad, and those of them left bright.
fn check_overlay(
    plain: &Frame,
    with: &Frame,
    renderer: &Renderer,
    panels: &[OverlayPanel<'_>],
    image: Option<&OverlayImage>,
) -> (usize, usize) {
    let font = renderer.overlay_font();
    let quads = font.layout(panels, [W, H], image.map(|i| [i.width, i.height]));
    // The layout itself: one background per panel, inside the target; every glyph
    // inside a background.
    let backgrounds: Vec<_> = quads.iter().filter(|q| q.atlas[2] == 1.0).collect();
    assert_eq!(backgrounds.len(), panels.len());
    for b in &backgrounds {
        assert!(b.rect[0] >= 0.0 && b.rect[1] >= 0.0, "{b:?}");
        assert!(b.rect[2] <= W as f32 && b.rect[3] <= H as f32, "{b:?}");
    }
    for g in quads.iter().filter(|q| q.atlas[2] == 0.0) {
        assert!(
            backgrounds.iter().any(|b| b.rect[0] <= g.rect[0]
                && b.rect[1] <= g.rect[1]
                && g.rect[2] <= b.rect[2]
                && g.rect[3] <= b.rect[3]),
            "glyph {g:?} outside every panel"
        );
    }
    let (mut covered, mut bright, mut worst) = (0usize, 0usize, 0.0f64);
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            let (below, got) = (plain.ldr[i], with.ldr[i]);
            let under_quad = quads.iter().any(|q| {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                px >= q.rect[0] && px < q.rect[2] && py >= q.rect[1] && py < q.rect[3]
            });
            if !under_quad {
                assert_eq!(got, below, "pixel ({x}, {y}) is under no quad");
                continue;
            }
            covered += 1;
            let expected = font.composite_unorm8(&quads, image, x, y, below);
            for c in 0..3 {
                let e = (f64::from(got[c]) - expected[c] * 255.0).abs();
                worst = worst.max(e);
                assert!(
                    e <= 1.0,
                    "pixel ({x}, {y}) channel {c}: GPU {} CPU {:.2}",
                    got[c],
                    expected[c] * 255.0
                );
            }
            if got[..3].iter().any(|&v| v > 200) {
                bright += 1;
            }
        }
    }
    eprintln!("{covered} pixels under quads, {bright} bright, worst {worst:.2} codes");
    (covered, bright)
}
