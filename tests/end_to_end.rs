//! The G-buffer checked end to end, from the scene alone: for built-in scenes, each
//! pixel's primary ray is cast in f64 against the scene's triangles through the
//! camera's own description (`combustion_reference::primary`, which shares no code with
//! the renderer), and what the GPU rasterised there — which material, how far, which
//! normal — is compared with what the ray hits. The parity tests start from the
//! G-buffer; this checks the G-buffer itself: camera, rasterisation, depth, the object
//! table's transforms and normal matrices, the normal encoding.
//!
//! Bounds, stated before they were measured and derived from the formats:
//! - coverage and material: a pixel may disagree only at an object's silhouette (within
//!   one pixel of a pixel whose ray hits another object or nothing): which object a
//!   pixel whose centre lies within rounding of an edge shows is the rasteriser's call;
//! - depth: the view distance the 32-bit float depth stands for, against the ray's:
//!   the depth d = far/(far − near)·(1 − near/z) has a rounding step of at most 2⁻²⁴
//!   near 1, which is z²/near · (far − near)/far · 2⁻²⁴ of view distance; eight such
//!   steps for the f32 plane equation and matrices, plus 1e-5 z for the f32 camera;
//! - normal: the 16-bit octahedral encoding is within 5e-5 rad of the normal it
//!   stores; 1e-4 rad allowed for it and the f32 interpolation, away from silhouettes
//!   (a pixel next to another object or the background). At a silhouette the triangle
//!   is seen edge-on and the f32 perspective interpolation of its normals is
//!   ill-conditioned: two rim pixels of hard-cases measured 1.22e-4 rad when this was
//!   written (the only ones above 1e-4), and are not held to the bound.

mod common;

use combustion::reference::primary::primary_hits;
use combustion::reference::SceneBvh;
use combustion::renderer::gbuffer::octahedral_decode;
use combustion::renderer::Readback;
use combustion::scene::builtin_scene;
use glam::DVec3;

const W: u32 = 160;
const H: u32 = 120;

#[test]
fn the_gbuffer_is_what_the_cameras_rays_hit() {
    for name in [
        "spheres",
        "hard-cases",
        "grid-sun",
        "spot-box",
        "point-among",
    ] {
        let scene = builtin_scene(name).unwrap();
        let frame = common::render(
            &scene,
            W,
            H,
            common::exact_f32(),
            Readback {
                images: false,
                gbuffer: true,
            },
        );
        let g = frame.gbuffer.as_ref().unwrap();
        let bvh = SceneBvh::new(&scene);
        let hits = primary_hits(&scene, &bvh, W, H, 2);
        let (near, far) = (f64::from(scene.camera.near), f64::from(scene.camera.far));
        // Which material each ray sees (None: nothing).
        let seen: Vec<Option<usize>> = hits
            .iter()
            .map(|h| h.map(|h| scene.objects[h.object].material))
            .collect();
        let at_silhouette = |x: u32, y: u32| {
            let own = seen[(y * W + x) as usize];
            (y.saturating_sub(1)..(y + 2).min(H)).any(|yy| {
                (x.saturating_sub(1)..(x + 2).min(W)).any(|xx| seen[(yy * W + xx) as usize] != own)
            })
        };
        let (mut compared, mut silhouette, mut away) = (0, 0, Vec::new());
        let (mut worst_depth, mut worst_normal, mut worst_rim) = (0.0f64, 0.0f64, 0.0f64);
        let (mut depth_failures, mut normal_failures) = (Vec::new(), Vec::new());
        for y in 0..H {
            for x in 0..W {
                let i = (y * W + x) as usize;
                let texel = &g.texels[i];
                let gpu = (texel.depth < 1.0).then_some(usize::from(texel.material_direction[0]));
                if gpu != seen[i] {
                    silhouette += 1;
                    if !at_silhouette(x, y) {
                        away.push((x, y, gpu, seen[i]));
                    }
                    continue;
                }
                let Some(hit) = hits[i] else {
                    continue; // background both
                };
                compared += 1;
                // The view distance the stored depth stands for.
                let d = f64::from(texel.depth);
                let z = near * far / (far - d * (far - near));
                let step =
                    hit.view_depth * hit.view_depth / near * (far - near) / far * 2f64.powi(-24);
                let allowed = 8.0 * step + 1e-5 * hit.view_depth;
                let depth_error = (z - hit.view_depth).abs();
                worst_depth = worst_depth.max(depth_error / allowed);
                if depth_error > allowed {
                    depth_failures.push((x, y, z, hit.view_depth));
                }
                let unorm = |v: u16| f64::from(v) / 65535.0;
                let [nx, ny, ..] = texel.normal_roughness_anisotropy;
                let n = DVec3::from(octahedral_decode([unorm(nx), unorm(ny)]));
                let angle = n.angle_between(DVec3::from(hit.normal));
                if at_silhouette(x, y) {
                    worst_rim = worst_rim.max(angle);
                    continue;
                }
                worst_normal = worst_normal.max(angle);
                if angle > 1e-4 {
                    normal_failures.push((x, y, angle));
                }
            }
        }
        eprintln!(
            "{name} {W}x{H}: {compared} pixels compared, {silhouette} at silhouettes; depth error at most {worst_depth:.3} of its bound, normal error at most {worst_normal:.2e} rad ({worst_rim:.2e} at silhouettes)"
        );
        assert!(compared > 1000, "{name}: {compared} pixels compared");
        assert!(
            away.is_empty(),
            "{name}: {} pixels disagree away from any silhouette, e.g. {:?}",
            away.len(),
            &away[..away.len().min(6)]
        );
        assert!(
            depth_failures.is_empty(),
            "{name}: {} depths beyond the bound, e.g. {:?}",
            depth_failures.len(),
            &depth_failures[..depth_failures.len().min(6)]
        );
        assert!(
            normal_failures.is_empty(),
            "{name}: {} normals beyond 1e-4 rad, e.g. {:?}",
            normal_failures.len(),
            &normal_failures[..normal_failures.len().min(6)]
        );
    }
}
