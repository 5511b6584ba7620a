//! Cut-outs (glTF alphaMode MASK) at a distance, on lavapipe with validation: where an
//! alpha ramp is cut stays where the cutoff says on every mip level (as Khronos'
//! AlphaBlendModeTest shows), and how much of a fence of thin bars is left as its mip
//! levels average the bars' alpha (measured: docs/gltf.md, "Alpha modes"). The
//! cut-outs' shapes up close, their shadows and their shading are checked against the
//! f64 reference in tests/end_to_end.rs and tests/shadows.rs (assets/scenes/cutout).

mod common;

use std::sync::Arc;

use combustion::reference::primary::primary_hits;
use combustion::reference::SceneBvh;
use combustion::renderer::Readback;
use combustion::scene::{
    AlphaMode, Camera, ColorSpace, Image, Light, Material, Mesh, Object, Sampler, Scene, Texture,
    TextureRef, UvTransform,
};
use glam::{Mat4, Quat, Vec3};

const W: u32 = 160;
const H: u32 = 120;
/// The textures' side, texels.
const SIDE: u32 = 64;
/// The fence: bars `BAR` texels wide every `PERIOD`, so its true coverage is
/// `BAR / PERIOD`.
const BAR: u32 = 3;
const PERIOD: u32 = 8;

/// A `SIDE`² sRGB image of grey with alpha `alpha(x, y)`.
fn alpha_image(name: &str, alpha: impl Fn(u32, u32) -> u8) -> Arc<Image> {
    let pixels = (0..SIDE)
        .flat_map(|y| (0..SIDE).map(move |x| (x, y)))
        .flat_map(|(x, y)| [200, 200, 200, alpha(x, y)])
        .collect();
    Arc::new(Image {
        name: name.into(),
        width: SIDE,
        height: SIDE,
        color_space: ColorSpace::Srgb,
        pixels,
    })
}

/// Unit panels side by side facing the camera, one per cutoff, each textured with
/// `image`, seen `distance` metres away (45° vertical field of view), lit by a sun.
fn panels_scene(image: &Arc<Image>, cutoffs: &[f32], distance: f32) -> Scene {
    let materials: Vec<Material> = cutoffs
        .iter()
        .map(|&cutoff| Material {
            name: format!("cut at {cutoff}"),
            base_color_texture: Some(TextureRef {
                texture: Texture {
                    image: image.clone(),
                    sampler: Sampler::default(),
                },
                tex_coord: 0,
                transform: UvTransform::IDENTITY,
            }),
            alpha_mode: AlphaMode::Mask { cutoff },
            double_sided: true,
            ..Material::default()
        })
        .collect();
    let spread = cutoffs.len() as f32 - 1.0;
    Scene {
        name: "panels".into(),
        meshes: vec![Mesh::plane("panel", 1.0)],
        objects: (0..cutoffs.len())
            .map(|i| Object {
                mesh: 0,
                material: i,
                transform: Mat4::from_rotation_translation(
                    Quat::from_rotation_x(std::f32::consts::FRAC_PI_2),
                    Vec3::new(1.25 * (i as f32 - spread / 2.0), 0.0, 0.0),
                ),
                casts_shadows: true,
            })
            .collect(),
        materials,
        lights: vec![Light::Directional {
            direction: Vec3::new(0.0, -0.5, -1.0).normalize(),
            irradiance: [3.0; 3],
            casts_shadows: false,
            angular_diameter: 0.0,
        }],
        camera: Camera {
            position: Vec3::new(0.0, 0.0, distance),
            target: Vec3::ZERO,
            up: Vec3::Y,
            vertical_fov: 45f32.to_radians(),
            near: 0.05,
            far: 500.0,
        },
        outside_ior: 1.0,
        environment: None,
    }
}

/// What each panel of `scene` shows when rendered: per object, its pixels (where its
/// bare triangles are hit, no alpha test), the share of them the renderer drew, and the
/// share the reference's rays (alpha at the hit on level 0) see.
fn drawn_shares(headless: &mut combustion::Headless, scene: &Scene) -> Vec<(usize, f64, f64)> {
    let frame = {
        let renderer = headless.renderer();
        let gpu_scene = renderer.upload(scene).expect("upload");
        renderer
            .render(
                &gpu_scene,
                W,
                H,
                Readback {
                    images: false,
                    gbuffer: true,
                },
            )
            .expect("render")
    };
    let g = frame.gbuffer.as_ref().unwrap();
    let exact = SceneBvh::new(scene);
    let solid = SceneBvh::from_triangles(exact.triangles().to_vec());
    let panel = primary_hits(scene, &solid, W, H, 2);
    let seen = primary_hits(scene, &exact, W, H, 2);
    let mut shares = vec![(0usize, 0usize, 0usize); scene.objects.len()];
    for (i, hit) in panel.iter().enumerate() {
        let texel = &g.texels[i];
        let drawn = (texel.depth < 1.0).then_some(usize::from(texel.material_direction[0]));
        let Some(hit) = hit else {
            assert_eq!(drawn, None, "pixel {i} drawn outside every panel");
            continue;
        };
        let share = &mut shares[hit.object];
        share.0 += 1;
        share.1 += usize::from(drawn == Some(scene.objects[hit.object].material));
        share.2 += usize::from(seen[i].is_some_and(|s| s.object == hit.object));
    }
    shares
        .into_iter()
        .map(|(n, drawn, seen)| (n, drawn as f64 / n as f64, seen as f64 / n as f64))
        .collect()
}

/// An alpha ramp (0 at the top row to 1 at the bottom, the way Khronos'
/// AlphaBlendModeTest marks its cutoffs) cut at 0.25, 0.5 and 0.75 keeps 0.75, 0.5 and
/// 0.25 of each panel's height, within a pixel row and 1 % (the ramp's 8-bit steps),
/// whether the panel spans 64 pixels (the texture at its resolution) or 8 (level of
/// detail 3): a linear ramp averages to itself on every mip level, so the cut stays
/// where the cutoff says. (A renderer that raised alpha on coarse levels to keep thin
/// cut-outs would move it: × 1.75 at level 3 keeps 0.71 of the panel cut at 0.5.)
///
/// A fence of 3-texel bars every 8 texels is measured the same way and printed: up
/// close it covers its true 3/8; from level 3 on every texel of its mip level averages
/// 0.375, below the cutoff of 0.5, and it vanishes (docs/gltf.md, "Alpha modes").
#[test]
fn cutoffs_stay_where_the_alpha_says_on_every_mip_level() {
    let tan_half = (22.5f64).to_radians().tan();
    let distance_for = |pixels_across: f64| f64::from(H) / (2.0 * pixels_across * tan_half);
    let ramp = alpha_image("ramp", |_, y| {
        ((f64::from(y) + 0.5) / f64::from(SIDE) * 255.0).round() as u8
    });
    let cutoffs = [0.25f32, 0.5, 0.75];
    let fence = alpha_image("fence", |x, _| if x % PERIOD < BAR { 255 } else { 0 });
    let mut headless = common::lavapipe(common::exact_f32());
    let mut table = Vec::new();
    for pixels_across in [64.0, 32.0, 16.0, 8.0, 4.0] {
        let lod = (f64::from(SIDE) / pixels_across).log2();
        let distance = distance_for(pixels_across) as f32;
        // Three panels side by side need the frame's width: at 64 px they do not fit
        // in 160, so the ramp is held from 32 px down.
        if pixels_across <= 32.0 {
            let shares = drawn_shares(&mut headless, &panels_scene(&ramp, &cutoffs, distance));
            for (&cutoff, &(n, drawn, seen)) in cutoffs.iter().zip(&shares) {
                let expected = 1.0 - f64::from(cutoff);
                let allowed = 1.0 / pixels_across + 0.01;
                eprintln!("ramp cut at {cutoff}, {pixels_across} px (λ ≈ {lod:.0}): {n} pixels, drawn {drawn:.3}, the reference's rays {seen:.3}, expected {expected}");
                assert!(
                    (drawn - expected).abs() <= allowed,
                    "cut at {cutoff}, {pixels_across} px: drawn {drawn:.3} of the panel, expected {expected} ± {allowed:.3}"
                );
            }
        }
        let shares = drawn_shares(&mut headless, &panels_scene(&fence, &[0.5], distance));
        let (n, drawn, seen) = shares[0];
        table.push((pixels_across, lod, n, drawn, seen));
    }
    common::finish(headless);
    let true_share = f64::from(BAR) / f64::from(PERIOD);
    eprintln!("fence: panel px | λ | pixels | drawn | the reference's rays (true {true_share})");
    for (across, lod, n, drawn, seen) in &table {
        eprintln!("{across} | {lod:.0} | {n} | {drawn:.3} | {seen:.3}");
    }
    let (_, _, _, close, _) = table[0];
    assert!(
        (close - true_share).abs() < 0.02,
        "the fence at its texture's resolution: drawn {close:.3}, true {true_share}"
    );
}
