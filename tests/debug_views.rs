//! The lighting pass's debug views (`ShadingOptions::debug_view`): every view renders on
//! lavapipe with validation and gives finite values, and the G-buffer views show exactly
//! what the G-buffer holds — checked pixel by pixel against the G-buffer read back from
//! the same frame (within one 8-bit step: the view goes through the f32 tone curve and
//! sRGB encoding and is rounded to 8 bits once more).

use crate::common;

use combustion::renderer::gbuffer::{anisotropy_direction_decode, octahedral_decode, GBufferTexel};
use combustion::renderer::{DebugView, Frame, Readback, RendererSettings, ShadingOptions};
use combustion::scene::builtin_scene;

const W: u32 = 192;
const H: u32 = 128;

fn render_views(scene_name: &str) -> Vec<(DebugView, Frame)> {
    let mut headless = common::lavapipe(RendererSettings::default());
    let renderer = headless.renderer();
    let gpu = renderer
        .upload(&builtin_scene(scene_name).unwrap())
        .unwrap();
    let mut frames = Vec::new();
    for view in DebugView::ALL {
        renderer
            .set_shading(
                ShadingOptions {
                    debug_view: view,
                    ..ShadingOptions::default()
                },
                &[&gpu],
            )
            .unwrap();
        let frame = renderer.render(&gpu, W, H, Readback::ALL).unwrap();
        frames.push((view, frame));
    }
    drop(gpu);
    common::finish(headless);
    frames
}

/// The largest difference, in 8-bit steps, between the view's display bytes and
/// `expected(texel)` over every pixel where something was drawn.
fn worst_step(frame: &Frame, expected: impl Fn(&GBufferTexel) -> [f64; 3]) -> u32 {
    let g = frame.gbuffer.as_ref().unwrap();
    let mut worst = 0;
    for (texel, shown) in g.texels.iter().zip(&frame.ldr) {
        if texel.depth >= 1.0 {
            continue;
        }
        let e = expected(texel);
        for c in 0..3 {
            let code = (e[c].clamp(0.0, 1.0) * 255.0).round() as i32;
            worst = worst.max((i32::from(shown[c]) - code).unsigned_abs());
        }
    }
    worst
}

#[test]
fn gbuffer_views_show_what_the_gbuffer_holds() {
    let frames = render_views("spheres");
    for (view, frame) in &frames {
        assert!(
            frame.hdr.iter().flatten().all(|x| x.is_finite()),
            "{view:?}: a value is not finite"
        );
        let worst = match view {
            DebugView::Roughness => worst_step(frame, |t| [t.normal_roughness_anisotropy[2]; 3]),
            DebugView::AnisotropyStrength => {
                worst_step(frame, |t| [t.normal_roughness_anisotropy[3]; 3])
            }
            DebugView::Metalness => worst_step(frame, |t| [t.base_color_metalness[3]; 3]),
            DebugView::BaseColor => worst_step(frame, |t| {
                let b = t.base_color_metalness;
                [b[0], b[1], b[2]]
            }),
            DebugView::Normal => worst_step(frame, |t| {
                let n = t.normal_roughness_anisotropy;
                octahedral_decode([n[0], n[1]]).map(|c| c * 0.5 + 0.5)
            }),
            DebugView::AnisotropyDirection => worst_step(frame, |t| {
                let n = t.normal_roughness_anisotropy;
                let normal = octahedral_decode([n[0], n[1]]);
                anisotropy_direction_decode(normal, t.material_direction[1]).map(|c| c * 0.5 + 0.5)
            }),
            DebugView::MaterialIndex => worst_step(frame, |t| {
                // debug_index_colour: a multiplicative hash of the index.
                let h = u32::from(t.material_direction[0]).wrapping_mul(2654435761);
                [8, 16, 24].map(|shift| f64::from((h >> shift) & 255) / 255.0)
            }),
            // Radiance, distance, and the BRDF terms: the next test.
            _ => 0,
        };
        assert!(worst <= 1, "{view:?}: {worst} steps from the G-buffer");
    }
    // The grid has several roughness values and both metals and dielectrics: the views
    // are not uniform.
    for view in [
        DebugView::Roughness,
        DebugView::Metalness,
        DebugView::MaterialIndex,
    ] {
        let frame = &frames.iter().find(|(v, _)| *v == view).unwrap().1;
        let mut distinct: Vec<[u8; 4]> = frame.ldr.clone();
        distinct.sort();
        distinct.dedup();
        assert!(
            distinct.len() > 2,
            "{view:?} shows {} values",
            distinct.len()
        );
    }
}

/// The views that must be non-zero on lit surfaces are, and the BRDF-term views stay in their
/// ranges: G2, F and the diffuse albedo in [0, 1] (their display bytes are codes of
/// values that cannot exceed 1), D finite and non-negative. (Their values are not
/// compared with the f64 BRDF here: that is the error view's work, not done yet.)
#[test]
fn brdf_term_views_stay_in_range_on_the_hard_cases() {
    for (view, frame) in render_views("hard-cases") {
        let hdr_ok = frame
            .hdr
            .iter()
            .all(|p| p[..3].iter().all(|x| x.is_finite() && *x >= 0.0));
        assert!(hdr_ok, "{view:?}: a negative or non-finite value");
        if matches!(
            view,
            DebugView::Normal
                | DebugView::Depth
                | DebugView::Distribution
                | DebugView::Smith
                | DebugView::Fresnel
                | DebugView::Diffuse
        ) {
            // These show something wherever the hard cases have a surface lit by the
            // first light (a view of zeros, e.g. with that light wrongly taken as
            // missing, would not).
            let shown = frame.ldr.iter().filter(|p| p[..3] != [0, 0, 0]).count();
            assert!(
                shown > frame.ldr.len() / 20,
                "{view:?}: only {shown} pixels are not black"
            );
        }
        if matches!(
            view,
            DebugView::Smith | DebugView::Fresnel | DebugView::Diffuse
        ) {
            // Codes of values ≤ 1 are written as −ln(1 − y) with y ≤ 0.999: ≤ 6.91.
            let max = frame
                .hdr
                .iter()
                .flat_map(|p| p[..3].to_vec())
                .fold(0f32, f32::max);
            assert!(max <= 6.91, "{view:?}: {max}");
        }
    }
}
