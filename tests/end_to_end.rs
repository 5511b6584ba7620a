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
use combustion::reference::shading::{GBufferPrecision, SceneShading};
use combustion::reference::SceneBvh;
use combustion::renderer::gbuffer::octahedral_decode;
use combustion::renderer::reference::RADIANCE_FLOOR;
use combustion::renderer::Readback;
use combustion::scene::{builtin_scene, Light, Scene, BUILTIN_SCENES};
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

/// Relative error of `a` against `b`: the largest over the channels of
/// |a − b| / max(|b|, `RADIANCE_FLOOR`).
fn relative(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3)
        .map(|c| (a[c] - b[c]).abs() / b[c].abs().max(RADIANCE_FLOOR))
        .fold(0.0, f64::max)
}

/// The f32 shading bound the parity tests hold the lighting pass to (relative, from the
/// G-buffer values it reads).
const SHADING_F32: f64 = 1e-3;

/// How far the renderer may place a surface point from the ray's, relative to its view
/// distance (the f32 camera term of the depth bound above).
const POSITION_RELATIVE: f64 = 1e-5;

/// How far the renderer's shading normal may turn from the interpolated f64 one away
/// from silhouettes, radians (the normal bound above).
const NORMAL_ANGLE: f64 = 1e-4;

/// Mean, 99th percentile and maximum of `errors`.
fn summary(mut errors: Vec<f64>) -> (f64, f64, f64) {
    errors.sort_by(f64::total_cmp);
    let n = errors.len().max(1);
    let mean = errors.iter().sum::<f64>() / n as f64;
    let at = |q: usize| errors.get((n - 1) * q / 100).copied().unwrap_or(0.0);
    (mean, at(99), at(100))
}

/// A frame compared with the f64 reference shaded from its scene alone.
struct SceneComparison {
    compared: usize,
    /// Pixels showing another material than the ray sees, away from any silhouette.
    away: Vec<(u32, u32)>,
    /// Per compared pixel: the GPU's relative error against the exact reference.
    total: Vec<f64>,
    /// Per compared pixel: the G-buffer storage's share (the reference shaded from the
    /// stored inputs, against the exact one).
    storage: Vec<f64>,
    /// Per compared pixel: the GPU against the reference shaded from the stored inputs.
    rest: Vec<f64>,
    /// Pixels whose `rest` exceeds their bound: (x, y, error, bound).
    beyond: Vec<(u32, u32, f64, f64)>,
}

/// Renders `scene` with `frame_lights` on lavapipe at `width`×`height` and compares each
/// pixel with `SceneShading` of the scene and its own lights.
///
/// Each pixel's bound, for the GPU against the reference shaded from the inputs as the
/// G-buffer stores them (`GBufferPrecision::COMBUSTION`): [`SHADING_F32`] plus how much the
/// reference's radiance changes when the normal turns by [`NORMAL_ANGLE`] (four ways) or
/// the point moves by [`POSITION_RELATIVE`] of its view distance (six ways) — the
/// G-buffer test's own bounds, carried through the shading by the reference itself (a
/// highlight's peak or a spot cone's edge is steep, a Lambert floor is not). Pixels at a
/// silhouette are counted, not compared.
fn compare_with_scene(
    scene: &Scene,
    frame_lights: &[Light],
    width: u32,
    height: u32,
) -> SceneComparison {
    let frame = common::render_with_lights(scene, frame_lights, width, height);
    let g = frame.gbuffer.as_ref().unwrap();
    let bvh = SceneBvh::new(scene);
    let shading = SceneShading::new(scene, &bvh, &scene.lights, width, height);
    let surfaces = shading.surfaces(2);
    let seen: Vec<Option<usize>> = surfaces
        .iter()
        .map(|s| s.map(|s| scene.objects[s.hit.object].material))
        .collect();
    let at_silhouette = |x: u32, y: u32| {
        let own = seen[(y * width + x) as usize];
        (y.saturating_sub(1)..(y + 2).min(height)).any(|yy| {
            (x.saturating_sub(1)..(x + 2).min(width))
                .any(|xx| seen[(yy * width + xx) as usize] != own)
        })
    };
    let mut out = SceneComparison {
        compared: 0,
        away: Vec::new(),
        total: Vec::new(),
        storage: Vec::new(),
        rest: Vec::new(),
        beyond: Vec::new(),
    };
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            let texel = &g.texels[i];
            let gpu_material =
                (texel.depth < 1.0).then_some(usize::from(texel.material_direction[0]));
            if gpu_material != seen[i] {
                if !at_silhouette(x, y) {
                    out.away.push((x, y));
                }
                continue;
            }
            let Some(surface) = surfaces[i] else {
                continue; // background both
            };
            if at_silhouette(x, y) {
                continue;
            }
            let material = &scene.materials[scene.objects[surface.hit.object].material];
            let exact = shading.radiance(&surface);
            let stored =
                GBufferPrecision::COMBUSTION.store(&surface, material.conductor_from_base_color);
            let as_stored = shading.radiance(&stored);
            let gpu = [0, 1, 2].map(|c| f64::from(frame.hdr[i][c]));
            let mut sensitivity = 0.0f64;
            for axis in [stored.t, -stored.t, stored.b, -stored.b] {
                let mut turned = stored;
                turned.n = (stored.n + axis * NORMAL_ANGLE.tan()).normalize();
                turned.t = stored.t.reject_from_normalized(turned.n).normalize();
                turned.b = turned.n.cross(turned.t);
                sensitivity = sensitivity.max(relative(shading.radiance(&turned), as_stored));
            }
            let step = POSITION_RELATIVE * stored.hit.view_depth;
            for axis in [
                DVec3::X,
                DVec3::NEG_X,
                DVec3::Y,
                DVec3::NEG_Y,
                DVec3::Z,
                DVec3::NEG_Z,
            ] {
                let mut moved = stored;
                moved.hit.position = (DVec3::from(stored.hit.position) + axis * step).to_array();
                sensitivity = sensitivity.max(relative(shading.radiance(&moved), as_stored));
            }
            let bound = SHADING_F32 + sensitivity;
            let rest = relative(gpu, as_stored);
            out.compared += 1;
            out.total.push(relative(gpu, exact));
            out.storage.push(relative(as_stored, exact));
            out.rest.push(rest);
            if rest > bound {
                out.beyond.push((x, y, rest, bound));
            }
        }
    }
    out
}

/// Every built-in scene without an environment (spot, point and directional lights, with
/// and without ranges; conductors measured and derived from the base colour; every
/// diffuse model; water as the outside medium), shaded by the f64 reference from the
/// scene alone (`combustion_reference::shading`: its own materials, lights, vertex
/// interpolation and BRDF evaluation from the optics crate) and compared per pixel with
/// the GPU's HDR radiance. Environment-lit scenes are compared by tests/environment.rs.
#[test]
fn the_frame_is_what_the_scene_shows() {
    for &name in BUILTIN_SCENES {
        let scene = builtin_scene(name).unwrap();
        if scene.environment.is_some() {
            continue;
        }
        let c = compare_with_scene(&scene, &scene.lights, W, H);
        let (total, storage, rest) = (summary(c.total), summary(c.storage), summary(c.rest));
        eprintln!(
            "{name} {W}x{H}: {} pixels compared; error mean {:.1e}, p99 {:.1e}, max {:.1e}; \
             of it the G-buffer's storage mean {:.1e}, max {:.1e}; the rest mean {:.1e}, max {:.1e}",
            c.compared, total.0, total.1, total.2, storage.0, storage.2, rest.0, rest.2
        );
        assert!(c.compared > 1000, "{name}: {} pixels compared", c.compared);
        assert!(
            c.away.is_empty(),
            "{name}: {} pixels show another material away from any silhouette, e.g. {:?}",
            c.away.len(),
            &c.away[..c.away.len().min(6)]
        );
        assert!(
            c.beyond.is_empty(),
            "{name}: {} pixels beyond their bound (x, y, error, bound), e.g. {:?}",
            c.beyond.len(),
            &c.beyond[..c.beyond.len().min(6)]
        );
    }
}

/// The comparison sees a light 1 % too bright: the same frame rendered with every
/// light's power × 1.01 puts most lit pixels beyond their bound.
#[test]
fn the_scene_comparison_sees_a_one_percent_light_error() {
    let scene = builtin_scene("spot-box").unwrap();
    let brighter: Vec<Light> = scene
        .lights
        .iter()
        .map(|light| {
            let mut light = light.clone();
            match &mut light {
                Light::Point { intensity, .. } | Light::Spot { intensity, .. } => {
                    *intensity = intensity.map(|i| i * 1.01)
                }
                Light::Directional { irradiance, .. } => *irradiance = irradiance.map(|e| e * 1.01),
            }
            light
        })
        .collect();
    let c = compare_with_scene(&scene, &brighter, W, H);
    let lit = c.total.iter().filter(|&&e| e > 0.0).count();
    eprintln!(
        "{} of {} lit pixels beyond their bound",
        c.beyond.len(),
        lit
    );
    assert!(c.beyond.len() * 2 > lit, "{} of {lit}", c.beyond.len());
}
