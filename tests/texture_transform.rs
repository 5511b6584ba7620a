//! KHR_texture_transform and the second texture-coordinate set, end to end on lavapipe:
//! a slot sampled through a transform (or on set 1) gives the image of the same slot
//! sampled at coordinates transformed on the CPU (`UvTransform::apply` on the vertices).
//! The map is affine, so transforming before or after the rasteriser's interpolation is
//! the same up to f32 rounding of the coordinates: at most a few pixels whose bilinear
//! weights round across an 8-bit step.

use crate::common;

use std::sync::Arc;

use combustion::scene::{
    Camera, ColorSpace, Image, Light, Material, Mesh, Object, Sampler, Scene, Texture, TextureRef,
    UvTransform,
};
use glam::{Mat4, Vec3};

const W: u32 = 160;
const H: u32 = 160;

/// A 16×16 pattern with no symmetry (so a wrong rotation or flip shows).
fn pattern() -> Arc<Image> {
    let mut pixels = Vec::with_capacity(16 * 16 * 4);
    for y in 0..16u32 {
        for x in 0..16u32 {
            pixels.extend_from_slice(&[
                (x * 16) as u8,
                (y * 16) as u8,
                if x > y { 220 } else { 30 },
                255,
            ]);
        }
    }
    Arc::new(Image {
        name: "pattern".into(),
        width: 16,
        height: 16,
        color_space: ColorSpace::Srgb,
        pixels,
    })
}

/// A plane seen from above under a directional light, its base colour from `texture`,
/// its vertices' coordinates mapped by `uv` and `uv1`.
fn scene(
    texture: TextureRef,
    uv: impl Fn([f32; 2]) -> [f32; 2],
    uv1: impl Fn([f32; 2]) -> [f32; 2],
) -> Scene {
    let mut plane = Mesh::plane("plane", 2.0);
    for v in &mut plane.vertices {
        let original = v.uv;
        v.uv = uv(original);
        v.uv1 = uv1(original);
    }
    Scene {
        name: "texture transform".into(),
        meshes: vec![plane],
        materials: vec![Material {
            base_color: [1.0, 1.0, 1.0],
            metalness: 0.0,
            roughness: 0.9,
            base_color_texture: Some(texture),
            ..Material::default()
        }],
        objects: vec![Object {
            mesh: 0,
            material: 0,
            transform: Mat4::IDENTITY,
            casts_shadows: true,
            node: None,
        }],
        lights: vec![Light::Directional {
            direction: Vec3::new(0.2, -1.0, 0.1).normalize(),
            irradiance: [2.0, 2.0, 2.0],
            casts_shadows: true,
            angular_diameter: 0.0,
        }],
        camera: Camera {
            position: Vec3::new(0.0, 2.5, 0.0),
            target: Vec3::ZERO,
            up: Vec3::new(0.0, 0.0, -1.0),
            vertical_fov: 45f32.to_radians(),
            near: 0.1,
            far: 10.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

fn render(scene: &Scene) -> combustion::renderer::Frame {
    common::render_images(scene, W, H, common::exact_f32())
}

#[test]
fn a_transformed_slot_samples_where_the_transform_says() {
    let transform = UvTransform {
        offset: [0.3, -0.2],
        rotation: 0.6,
        scale: [1.5, 0.75],
    };
    let slot = |tex_coord, transform| TextureRef {
        texture: Texture {
            image: pattern(),
            sampler: Sampler::default(),
        },
        tex_coord,
        transform,
    };
    let same = |uv: [f32; 2]| uv;
    let mapped = |uv: [f32; 2]| transform.apply(uv);
    // On the CPU: the vertices carry the mapped coordinates, the slot none.
    let cpu = render(&scene(slot(0, UvTransform::IDENTITY), mapped, same));
    // On the GPU: the slot's transform; then set 1 carrying the mapped coordinates;
    // then set 1 carrying the original ones through the transform.
    let gpu = render(&scene(slot(0, transform), same, same));
    let set1 = render(&scene(slot(1, UvTransform::IDENTITY), same, mapped));
    let set1_transformed = render(&scene(slot(1, transform), |_| [0.0; 2], same));
    // The untransformed plane, to show the transform changes the image.
    let plain = render(&scene(slot(0, UvTransform::IDENTITY), same, same));
    let allowed = (W * H) as usize / 1000;
    for (name, frame) in [
        ("transform", &gpu),
        ("set 1", &set1),
        ("set 1 through the transform", &set1_transformed),
    ] {
        let apart = common::pixels_apart(&cpu, frame);
        eprintln!("{name}: {apart} pixels apart from the CPU-mapped coordinates");
        assert!(
            apart <= allowed,
            "{name}: {apart} pixels differ by more than one step"
        );
    }
    let changed = common::pixels_apart(&cpu, &plain);
    assert!(
        changed > (W * H) as usize / 4,
        "the transform changes the image: {changed}"
    );

    // Two slots with two transforms (base colour and emission): each slot reads its own
    // row of the table. On the CPU side set 0 carries the first map, set 1 the second.
    let other = UvTransform {
        offset: [-0.1, 0.45],
        rotation: -1.1,
        scale: [0.6, 2.0],
    };
    let with_emission = |mut s: Scene, tex_coord, transform| {
        let m = &mut s.materials[0];
        m.emissive_factor = [0.3, 0.3, 0.3];
        m.emissive_texture = Some(slot(tex_coord, transform));
        s
    };
    let cpu_two = render(&with_emission(
        scene(slot(0, UvTransform::IDENTITY), mapped, |uv| other.apply(uv)),
        1,
        UvTransform::IDENTITY,
    ));
    let gpu_two = render(&with_emission(
        scene(slot(0, transform), same, same),
        0,
        other,
    ));
    let apart = common::pixels_apart(&cpu_two, &gpu_two);
    eprintln!("two slots: {apart} pixels apart");
    assert!(
        apart <= allowed,
        "two slots: {apart} pixels differ by more than one step"
    );
}
