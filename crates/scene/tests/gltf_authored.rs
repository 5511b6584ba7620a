//! The scenes in `assets/scenes/` are made here, from code, with the writer
//! (`COMBUSTION_BLESS=1 cargo test -p combustion-scene --test integration gltf_authored::`
//! rewrites them); the tests check that the files on disk import to exactly these scenes, and
//! that every built-in scene survives a save → import round trip unchanged.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use combustion_scene::gltf::{import, save_gltf, CameraSource, ImportOptions};
use combustion_scene::{
    builtin_scene, AlphaMode, Camera, ColorSpace, ComplexIor, DiffuseModel, Filter, Image, Light,
    Material, Mesh, Object, Sampler, Scene, Texture, TextureRef, TextureSlot, UvTransform,
    WrapMode, BUILTIN_SCENES,
};
use glam::{Mat4, Quat, Vec3};

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes")
}

/// With `COMBUSTION_BLESS=1`, (re)writes `assets/scenes/` once per test run.
fn bless() {
    static WRITE: std::sync::Once = std::sync::Once::new();
    if std::env::var_os("COMBUSTION_BLESS").is_some_and(|v| v == "1") {
        WRITE.call_once(|| write_authored(&assets()));
    }
}

/// A fresh, empty temporary folder.
fn temp_dir(name: &str) -> PathBuf {
    super::support::temp_dir("gltf", name)
}

fn assert_same_scene(expected: &Scene, actual: &Scene) {
    assert_eq!(expected.name, actual.name);
    assert_eq!(expected.meshes.len(), actual.meshes.len(), "mesh count");
    for (a, b) in expected.meshes.iter().zip(&actual.meshes) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.indices, b.indices, "{}", a.name);
        assert_eq!(a.vertices, b.vertices, "{}", a.name);
    }
    assert_eq!(
        expected.materials.len(),
        actual.materials.len(),
        "material count"
    );
    for (a, b) in expected.materials.iter().zip(&actual.materials) {
        assert_eq!(a, b, "material `{}`", a.name);
    }
    // The objects as placed; an imported one hangs from the node written for it, whose
    // world transform at rest (times the object's offset) places it there.
    let unlinked = |objects: &[combustion_scene::Object]| {
        objects
            .iter()
            .map(|o| combustion_scene::Object {
                node: None,
                ..o.clone()
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(unlinked(&expected.objects), unlinked(&actual.objects));
    let rest = actual.pose_objects(&actual.motion.rest_pose());
    for (object, transform) in actual.objects.iter().zip(&rest.transforms) {
        assert!(
            object.node.is_some(),
            "an imported object hangs from no node"
        );
        assert_eq!(object.transform, *transform);
    }
    assert_eq!(expected.lights, actual.lights);
    assert_eq!(expected.camera, actual.camera);
    assert_eq!(expected.outside_ior, actual.outside_ior);
}

fn image(name: &str, color_space: ColorSpace, f: impl Fn(u32, u32) -> [u8; 4]) -> Arc<Image> {
    let (width, height) = (16, 16);
    let mut pixels = Vec::with_capacity(16 * 16 * 4);
    for y in 0..height {
        for x in 0..width {
            pixels.extend_from_slice(&f(x, y));
        }
    }
    Arc::new(Image {
        name: name.into(),
        width,
        height,
        color_space,
        pixels,
    })
}

fn texture(image: &Arc<Image>, sampler: Sampler) -> Option<TextureRef> {
    Some(TextureRef {
        texture: Texture {
            image: image.clone(),
            sampler,
        },
        tex_coord: 0,
        transform: UvTransform::IDENTITY,
    })
}

/// Every texture slot, the sampler variants, all three light kinds, a placed camera.
fn textured_scene() -> Scene {
    let checker = image("checker", ColorSpace::Srgb, |x, y| {
        if (x / 4 + y / 4) % 2 == 0 {
            [230, 200, 150, 255]
        } else {
            [40, 60, 90, 255]
        }
    });
    let metal_rough = image("metal-rough", ColorSpace::Linear, |x, y| {
        [0, (x * 16) as u8, if y < 8 { 255 } else { 0 }, 255]
    });
    let bumps = image("bumps", ColorSpace::Linear, |x, _| {
        let slope = (x as f32 / 16.0 * std::f32::consts::TAU).sin() * 0.5;
        let n = Vec3::new(slope, 0.0, 1.0).normalize();
        [
            ((n.x * 0.5 + 0.5) * 255.0).round() as u8,
            ((n.y * 0.5 + 0.5) * 255.0).round() as u8,
            ((n.z * 0.5 + 0.5) * 255.0).round() as u8,
            255,
        ]
    });
    let occlusion = image("occlusion", ColorSpace::Linear, |x, y| {
        let d = (x as i32 - 8).pow(2) + (y as i32 - 8).pow(2);
        let v = (255 - d * 2).clamp(0, 255) as u8;
        [v, v, v, 255]
    });
    let glow = image("glow", ColorSpace::Srgb, |x, y| {
        if x == y || x + y == 15 {
            [255, 120, 20, 255]
        } else {
            [0, 0, 0, 255]
        }
    });
    let swirl = image("anisotropy-swirl", ColorSpace::Linear, |x, y| {
        let angle = (y as f32 - 7.5).atan2(x as f32 - 7.5) + std::f32::consts::FRAC_PI_2;
        [
            ((angle.cos() * 0.5 + 0.5) * 255.0).round() as u8,
            ((angle.sin() * 0.5 + 0.5) * 255.0).round() as u8,
            255,
            255,
        ]
    });
    let specular = image("specular", ColorSpace::Linear, |x, _| {
        [255, 255, 255, (x * 17) as u8]
    });
    let specular_color = image("specular-colour", ColorSpace::Srgb, |_, y| {
        [255, (y * 17) as u8, 128, 255]
    });

    let nearest_clamp = Sampler {
        mag_filter: Filter::Nearest,
        min_filter: Filter::Nearest,
        mipmap_filter: None,
        wrap_u: WrapMode::ClampToEdge,
        wrap_v: WrapMode::ClampToEdge,
    };
    let mirrored = Sampler {
        mag_filter: Filter::Linear,
        min_filter: Filter::Nearest,
        mipmap_filter: Some(Filter::Nearest),
        wrap_u: WrapMode::MirroredRepeat,
        wrap_v: WrapMode::Repeat,
    };
    let trilinear = Sampler::default();
    let floor = Material {
        name: "textured floor".into(),
        base_color: [0.9, 0.9, 0.9],
        roughness: 0.7,
        base_color_texture: texture(&checker, nearest_clamp),
        occlusion_texture: texture(&occlusion, trilinear),
        occlusion_strength: 0.8,
        normal_texture: texture(&bumps, mirrored),
        normal_scale: 0.75,
        ..Material::default()
    };
    let metal = Material {
        name: "textured brushed metal".into(),
        base_color: [0.95, 0.64, 0.54],
        metalness: 1.0,
        roughness: 0.35,
        conductor: combustion_scene::conductor_from_reflectivity([0.95, 0.64, 0.54]),
        conductor_from_base_color: true,
        metallic_roughness_texture: texture(&metal_rough, trilinear),
        anisotropy_strength: 0.6,
        anisotropy_rotation: 0.3,
        anisotropy_texture: texture(&swirl, trilinear),
        ..Material::default()
    };
    let glowing = Material {
        name: "glowing specular plastic".into(),
        base_color: [0.1, 0.2, 0.5],
        roughness: 0.3,
        dielectric_ior: 1.45,
        emissive_factor: [1.0, 0.5, 0.25],
        emissive_strength: 4.0,
        emissive_texture: texture(&glow, trilinear),
        specular_factor: 0.8,
        specular_color_factor: [1.0, 0.9, 0.8],
        specular_texture: texture(&specular, trilinear),
        specular_color_texture: texture(&specular_color, trilinear),
        double_sided: true,
        ..Material::default()
    };
    Scene {
        name: "textured".into(),
        meshes: vec![
            Mesh::plane("floor", 4.0),
            Mesh::uv_sphere("sphere", 0.5, 24, 12),
        ],
        materials: vec![floor, metal, glowing],
        objects: vec![
            Object {
                mesh: 0,
                material: 0,
                transform: Mat4::IDENTITY,
                casts_shadows: true,
                node: None,
            },
            Object {
                mesh: 1,
                material: 1,
                transform: Mat4::from_translation(Vec3::new(-0.7, 0.5, 0.0)),
                casts_shadows: true,
                node: None,
            },
            Object {
                mesh: 1,
                material: 2,
                transform: Mat4::from_scale_rotation_translation(
                    Vec3::splat(0.8),
                    Quat::from_rotation_y(0.5),
                    Vec3::new(0.7, 0.4, 0.2),
                ),
                casts_shadows: true,
                node: None,
            },
        ],
        lights: vec![
            Light::Point {
                position: Vec3::new(-2.0, 3.0, 2.0),
                intensity: [30.0, 28.0, 25.0],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
            Light::Spot {
                position: Vec3::new(2.0, 3.0, 1.0),
                direction: Vec3::new(-0.5, -1.0, -0.3),
                intensity: [40.0, 40.0, 50.0],
                inner_cone: 0.2,
                outer_cone: 0.5,
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
            Light::Directional {
                direction: Vec3::new(0.2, -1.0, -0.5),
                irradiance: [0.5, 0.5, 0.6],
                casts_shadows: true,
                angular_diameter: 0.0,
            },
        ],
        camera: Camera {
            position: Vec3::new(0.0, 1.6, 3.5),
            target: Vec3::new(0.0, 0.3, 0.0),
            up: Vec3::Y,
            vertical_fov: 45f32.to_radians(),
            near: 0.1,
            far: 50.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// Where a panel (`Mesh::plane`, facing +y) of side `size` stands upright facing +z (the
/// camera; v down), turned by `turn` about y, centred at `at`.
fn upright(size: f32, turn: f32, at: Vec3) -> Mat4 {
    Mat4::from_scale_rotation_translation(
        Vec3::splat(size),
        Quat::from_rotation_y(turn) * Quat::from_rotation_x(std::f32::consts::FRAC_PI_2),
        at,
    )
}

/// Cut-outs (alphaMode MASK): a double-sided lattice panel (a 16×16 alpha texture of
/// 2×2-texel holes, linear filtering) and a gradient panel whose alpha rises across u,
/// scaled by a base colour alpha of 0.8, cut at 0.3 (present from u ≈ 0.38 on); a
/// panel whose factor alone (0.4) is below its cutoff (0.5), so it is nowhere; a
/// blended material would be drawn opaque, so none is here; a vertex-coloured panel
/// (COLOR_0 RGBA: its colours multiply the base colour, its alpha is cut at 0.5). A sun
/// from behind the panels and a point light in front that both cast the holes' shadows
/// onto the floor.
fn cutout_scene() -> Scene {
    let lattice = image("lattice", ColorSpace::Srgb, |x, y| {
        let hole = x % 4 >= 2 && y % 4 >= 2;
        [70, 150, 60, if hole { 0 } else { 255 }]
    });
    let gradient = image("gradient", ColorSpace::Srgb, |x, _| {
        [230, 120, 40, (x * 17) as u8]
    });
    let floor = Material {
        name: "floor".into(),
        base_color: [0.7, 0.7, 0.68],
        roughness: 0.8,
        ..Material::default()
    };
    let lattice = Material {
        name: "lattice".into(),
        base_color: [1.0, 1.0, 1.0],
        roughness: 0.6,
        base_color_texture: texture(&lattice, Sampler::default()),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        double_sided: true,
        ..Material::default()
    };
    let gradient = Material {
        name: "gradient".into(),
        base_color: [1.0, 1.0, 1.0],
        alpha: 0.8,
        roughness: 0.4,
        // Clamped: a repeating bilinear filter would blend the last column's alpha into
        // the first at u = 0.
        base_color_texture: texture(
            &gradient,
            Sampler {
                wrap_u: WrapMode::ClampToEdge,
                wrap_v: WrapMode::ClampToEdge,
                ..Sampler::default()
            },
        ),
        alpha_mode: AlphaMode::Mask { cutoff: 0.3 },
        double_sided: true,
        ..Material::default()
    };
    let absent = Material {
        name: "below its cutoff".into(),
        base_color: [0.9, 0.1, 0.1],
        alpha: 0.4,
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    };
    let object = Object::casting_shadows;
    // Vertex colours (COLOR_0): red, green, blue and white corners, the two far ones
    // with an alpha of 0.2, cut at 0.5: the panel is cut along the alpha's ramp.
    let mut coloured = Mesh::plane("coloured panel", 1.0);
    for (v, color) in coloured.vertices.iter_mut().zip([
        [1.0, 0.2, 0.2, 1.0],
        [0.2, 1.0, 0.2, 1.0],
        [0.2, 0.2, 1.0, 0.2],
        [1.0, 1.0, 1.0, 0.2],
    ]) {
        v.color = color;
    }
    let vertex_coloured = Material {
        name: "vertex coloured".into(),
        base_color: [0.9, 0.9, 0.9],
        roughness: 0.5,
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        double_sided: true,
        ..Material::default()
    };
    Scene {
        name: "cutout".into(),
        meshes: vec![
            Mesh::plane("floor", 6.0),
            Mesh::plane("panel", 1.0),
            coloured,
        ],
        materials: vec![floor, lattice, gradient, absent, vertex_coloured],
        objects: vec![
            object(0, 0, Mat4::IDENTITY),
            object(1, 1, upright(1.6, 0.0, Vec3::new(-0.6, 0.9, 0.0))),
            object(1, 2, upright(1.0, -0.35, Vec3::new(0.9, 0.6, -0.3))),
            object(1, 3, upright(0.8, 0.0, Vec3::new(0.2, 0.5, 0.6))),
            object(2, 4, upright(0.8, 0.7, Vec3::new(0.8, 0.41, 1.4))),
        ],
        lights: vec![
            Light::Directional {
                direction: Vec3::new(0.35, -0.75, 0.55),
                irradiance: [2.5, 2.4, 2.2],
                casts_shadows: true,
                angular_diameter: 0.0,
            },
            Light::Point {
                position: Vec3::new(1.8, 2.2, 2.0),
                intensity: [6.0, 6.0, 7.0],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
        ],
        camera: Camera {
            position: Vec3::new(0.0, 2.2, 3.6),
            target: Vec3::new(0.0, 0.4, -0.5),
            up: Vec3::Y,
            vertical_fov: 45f32.to_radians(),
            near: 0.1,
            far: 50.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// Blending (alphaMode BLEND): a row of panels of alpha 0.25 (a red Lambert
/// dielectric), 0.5 (a smooth green one), 0.75 (a rough blue conductor) and a
/// vertex-coloured one whose alpha falls from 1 to 0.2 across it, in front of an opaque
/// sphere, a back wall and a checkered floor; above them two panels that overlap on
/// screen (a yellow one in front of a double-sided cyan one), blended in their depth
/// order. A sun and a point light, both casting shadows (the sphere's; blended surfaces
/// cast none).
fn blend_scene() -> Scene {
    let checker = image("checker", ColorSpace::Srgb, |x, y| {
        if (x / 4 + y / 4) % 2 == 0 {
            [200, 200, 190, 255]
        } else {
            [60, 60, 70, 255]
        }
    });
    let opaque = |name: &str, base_color: [f32; 3], roughness: f32| Material {
        name: name.into(),
        base_color,
        roughness,
        ..Material::default()
    };
    let blended = |name: &str, base_color: [f32; 3], alpha: f32, roughness: f32| Material {
        name: name.into(),
        base_color,
        alpha,
        roughness,
        alpha_mode: AlphaMode::Blend,
        ..Material::default()
    };
    let floor = Material {
        base_color_texture: texture(&checker, Sampler::default()),
        ..opaque("checkered floor", [1.0; 3], 0.8)
    };
    let conductor = Material {
        metalness: 1.0,
        conductor: ComplexIor {
            eta: [1.2, 1.0, 0.6],
            k: [2.5, 2.7, 3.2],
        },
        ..blended("blue conductor, alpha 0.75", [0.3, 0.4, 0.9], 0.75, 0.6)
    };
    let cyan = Material {
        double_sided: true,
        ..blended("cyan, alpha 0.6", [0.1, 0.8, 0.8], 0.6, 0.5)
    };
    let object = Object::casting_shadows;
    let upright = |size: f32, at: Vec3| upright(size, 0.0, at);
    // Vertex colours (COLOR_0): warm corners, alpha 1 on the left edge and 0.2 on the
    // right.
    let mut ramp = Mesh::plane("alpha ramp panel", 1.0);
    for v in &mut ramp.vertices {
        let alpha = if v.position[0] < 0.0 { 1.0 } else { 0.2 };
        v.color = [1.0, 0.6 + 0.4 * v.position[2].abs(), 0.3, alpha];
    }
    Scene {
        name: "blend".into(),
        meshes: vec![
            Mesh::plane("floor", 6.0),
            Mesh::plane("panel", 1.0),
            ramp,
            Mesh::uv_sphere("sphere", 0.45, 32, 16),
        ],
        materials: vec![
            floor,
            opaque("back wall", [0.55, 0.55, 0.6], 0.7),
            opaque("sphere", [0.8, 0.35, 0.1], 0.35),
            blended("red Lambert, alpha 0.25", [0.9, 0.1, 0.1], 0.25, 1.0),
            blended("smooth green, alpha 0.5", [0.1, 0.8, 0.2], 0.5, 0.15),
            conductor,
            blended("vertex-coloured ramp", [1.0; 3], 1.0, 0.5),
            blended("yellow, alpha 0.5", [0.9, 0.8, 0.1], 0.5, 0.4),
            cyan,
        ],
        objects: vec![
            object(0, 0, Mat4::IDENTITY),
            object(1, 1, upright(6.0, Vec3::new(0.0, 3.0, -1.8))),
            object(3, 2, Mat4::from_translation(Vec3::new(0.2, 0.45, -0.9))),
            object(1, 3, upright(0.9, Vec3::new(-1.65, 0.6, 0.3))),
            object(1, 4, upright(0.9, Vec3::new(-0.55, 0.6, 0.3))),
            object(1, 5, upright(0.9, Vec3::new(0.55, 0.6, 0.3))),
            object(2, 6, upright(0.9, Vec3::new(1.65, 0.6, 0.3))),
            object(1, 7, upright(0.8, Vec3::new(-0.3, 1.65, 0.9))),
            object(1, 8, upright(0.8, Vec3::new(0.25, 1.85, -0.2))),
        ],
        lights: vec![
            Light::Directional {
                direction: Vec3::new(-0.3, -0.8, -0.5),
                irradiance: [2.5, 2.4, 2.2],
                casts_shadows: true,
                angular_diameter: 0.0,
            },
            Light::Point {
                position: Vec3::new(1.6, 2.4, 2.2),
                intensity: [5.0, 5.0, 6.0],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
        ],
        camera: Camera {
            position: Vec3::new(0.0, 1.5, 4.4),
            target: Vec3::new(0.0, 0.9, 0.0),
            up: Vec3::Y,
            vertical_fov: 45f32.to_radians(),
            near: 0.1,
            far: 50.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// What glTF cannot say, through `COMBUSTION_materials_optics`: spheres under water
/// (scene outside IOR 1.33), a named metal, a spectral table, explicit η + ik, a
/// base-colour conductor, an air bubble (material outside IOR), all three diffuse
/// models and polarisation weights. Before saving, [`optics_postprocess`] rewrites the
/// conductors into the extension's other forms, removes TANGENT from the normal-mapped
/// sphere (so MikkTSpace must make them) and NORMAL from the floor (flat normals).
fn optics_scene() -> Scene {
    let sphere = |name: &str, m: Material| Material {
        name: name.into(),
        ..m
    };
    let materials = vec![
        sphere(
            "gold (named metal)",
            Material {
                metalness: 1.0,
                roughness: 0.3,
                ..Material::default()
            },
        ),
        sphere(
            "copper (spectral table)",
            Material {
                metalness: 1.0,
                roughness: 0.4,
                polarisation_weight: 0.0,
                ..Material::default()
            },
        ),
        sphere(
            "explicit eta + ik",
            Material {
                metalness: 1.0,
                roughness: 0.2,
                conductor: ComplexIor {
                    eta: [0.2, 0.9, 1.1],
                    k: [3.0, 2.5, 2.0],
                },
                polarisation_weight: 1.0,
                ..Material::default()
            },
        ),
        sphere(
            "base-colour metal",
            Material {
                base_color: [0.9, 0.9, 0.3],
                metalness: 1.0,
                roughness: 0.25,
                ..Material::default()
            },
        ),
        sphere(
            "air bubble, Oren-Nayar full",
            Material {
                base_color: [0.7, 0.7, 0.7],
                roughness: 0.9,
                dielectric_ior: 1.0,
                outside_ior: Some(1.0),
                diffuse_model: DiffuseModel::OrenNayarFull,
                ..Material::default()
            },
        ),
        sphere(
            "normal-mapped Oren-Nayar qualitative",
            Material {
                base_color: [0.6, 0.3, 0.2],
                roughness: 0.8,
                diffuse_model: DiffuseModel::OrenNayarQualitative,
                normal_texture: texture(
                    &image("ripples", ColorSpace::Linear, |x, y| {
                        let s = ((x + y) as f32 * 0.8).sin();
                        [(128.0 + s * 60.0) as u8, 128, 255, 255]
                    }),
                    Sampler::default(),
                ),
                ..Material::default()
            },
        ),
        Material {
            name: "sand floor".into(),
            base_color: [0.76, 0.7, 0.5],
            roughness: 1.0,
            ..Material::default()
        },
    ];
    let mut objects = Vec::new();
    for i in 0..6 {
        objects.push(Object {
            mesh: if i == 5 { 1 } else { 0 },
            material: i,
            transform: Mat4::from_translation(Vec3::new(i as f32 * 1.1 - 2.75, 0.5, 0.0)),
            casts_shadows: true,
            node: None,
        });
    }
    objects.push(Object {
        mesh: 2,
        material: 6,
        transform: Mat4::IDENTITY,
        casts_shadows: true,
        node: None,
    });
    Scene {
        name: "optics".into(),
        meshes: vec![
            Mesh::uv_sphere("sphere", 0.5, 32, 16),
            Mesh::uv_sphere("normal-mapped sphere", 0.5, 32, 16),
            Mesh::plane("floor", 10.0),
        ],
        materials,
        objects,
        lights: vec![Light::Directional {
            direction: Vec3::new(0.3, -1.0, -0.6),
            irradiance: [3.0; 3],
            casts_shadows: true,
            angular_diameter: 0.0,
        }],
        camera: Camera {
            position: Vec3::new(0.0, 2.0, 6.0),
            target: Vec3::new(0.0, 0.5, 0.0),
            up: Vec3::Y,
            vertical_fov: 40f32.to_radians(),
            near: 0.1,
            far: 100.0,
        },
        outside_ior: 1.33,
        environment: None,
        motion: Default::default(),
    }
}

/// Rewrites the writer's output for `optics_scene` into the extension's other forms.
fn optics_postprocess(gltf: &Path) {
    let mut root: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(gltf).unwrap()).unwrap();
    let set_conductor =
        |root: &mut serde_json::Value, material: usize, conductor: serde_json::Value| {
            root["materials"][material]["extensions"]["COMBUSTION_materials_optics"]["conductor"] =
                conductor;
        };
    set_conductor(&mut root, 0, serde_json::json!({ "metal": "gold" }));
    set_conductor(
        &mut root,
        1,
        serde_json::json!({ "spectrum": "copper.csv" }),
    );
    set_conductor(&mut root, 3, serde_json::json!({ "fromBaseColor": true }));
    // The scene's outside IOR on the scene rather than the root.
    let optics = root["extensions"]
        .as_object_mut()
        .unwrap()
        .remove("COMBUSTION_materials_optics")
        .unwrap();
    root["scenes"][0]["extensions"] = serde_json::json!({ "COMBUSTION_materials_optics": optics });
    // The normal-mapped sphere: no TANGENT (MikkTSpace). The floor: no NORMAL, no TANGENT
    // (flat normals, reference tangents).
    for mesh in root["meshes"].as_array_mut().unwrap() {
        let name = mesh["name"].as_str().unwrap().to_owned();
        let attributes = mesh["primitives"][0]["attributes"].as_object_mut().unwrap();
        if name == "normal-mapped sphere" {
            attributes.remove("TANGENT");
        }
        if name == "floor" {
            attributes.remove("TANGENT");
            attributes.remove("NORMAL");
        }
    }
    std::fs::write(gltf, serde_json::to_string_pretty(&root).unwrap() + "\n").unwrap();
    let copper = combustion_spectra::BuiltinMetal::Copper.csv();
    std::fs::write(gltf.with_file_name("copper.csv"), copper).unwrap();
}

fn write_authored(dir: &Path) {
    std::fs::create_dir_all(dir.join("textured")).unwrap();
    std::fs::create_dir_all(dir.join("optics")).unwrap();
    std::fs::create_dir_all(dir.join("cutout")).unwrap();
    std::fs::create_dir_all(dir.join("blend")).unwrap();
    std::fs::create_dir_all(dir.join("glass")).unwrap();
    // The built-in glass scene, kept as a file too: the transmission and volume
    // extensions' reader and writer, and the scene the tests of glass load.
    save_gltf(
        &builtin_scene("glass").unwrap(),
        &dir.join("glass/glass.gltf"),
    )
    .unwrap();
    save_gltf(&blend_scene(), &dir.join("blend/blend.gltf")).unwrap();
    save_gltf(&textured_scene(), &dir.join("textured/textured.gltf")).unwrap();
    save_gltf(&cutout_scene(), &dir.join("cutout/cutout.gltf")).unwrap();
    let optics = dir.join("optics/optics.gltf");
    save_gltf(&optics_scene(), &optics).unwrap();
    optics_postprocess(&optics);
}

#[test]
fn authored_scenes_are_current() {
    bless();
    let (scene, report) = import(
        &assets().join("textured/textured.gltf"),
        &ImportOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e} (regenerate with COMBUSTION_BLESS=1)"));
    assert_same_scene(&textured_scene(), &scene);
    assert!(report.warnings.is_empty(), "{report}");
    assert_eq!(report.camera, CameraSource::Gltf { index: 0, node: 6 });
    let features = scene.features();
    // Every slot of an opaque material (transmission's two:
    // `transmission_and_volumes_round_trip`; the clear coat's three:
    // `clearcoats_round_trip`; the sheen's two: `sheen_round_trips`; the thin film's two:
    // `iridescence_round_trips`).
    let opaque_slots = TextureSlot::ALL.into_iter().filter(|s| {
        !matches!(
            s,
            TextureSlot::Transmission
                | TextureSlot::Thickness
                | TextureSlot::Clearcoat
                | TextureSlot::ClearcoatRoughness
                | TextureSlot::ClearcoatNormal
                | TextureSlot::SheenColor
                | TextureSlot::SheenRoughness
                | TextureSlot::Iridescence
                | TextureSlot::IridescenceThickness
        )
    });
    for slot in opaque_slots {
        assert!(
            features.texture_count(slot) > 0,
            "{slot:?} unused: {features}"
        );
    }
    assert_eq!(
        (
            features.point_lights,
            features.spot_lights,
            features.directional_lights
        ),
        (1, 1, 1)
    );
    assert_eq!(
        (
            features.emissive,
            features.anisotropic,
            features.conductors_from_base_color
        ),
        (1, 1, 1)
    );
}

/// Imports `assets/scenes/NAME/NAME.gltf` and checks that it is `expected`, read without
/// a warning; the scene read.
fn assert_authored_is_current(name: &str, expected: &Scene) -> Scene {
    bless();
    let (scene, report) = import(
        &assets().join(format!("{name}/{name}.gltf")),
        &ImportOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e} (regenerate with COMBUSTION_BLESS=1)"));
    assert_same_scene(expected, &scene);
    assert!(report.warnings.is_empty(), "{report}");
    scene
}

#[test]
fn the_cutout_scene_is_current() {
    let scene = assert_authored_is_current("cutout", &cutout_scene());
    assert_eq!(scene.features().masked, 4);
    assert!(scene.meshes[2].has_colors());
}

#[test]
fn the_blend_scene_is_current() {
    let scene = assert_authored_is_current("blend", &blend_scene());
    assert_eq!(scene.features().blended, 6);
    assert!(scene.meshes[2].has_colors());
}

#[test]
fn the_glass_scene_is_current() {
    let scene = assert_authored_is_current("glass", &builtin_scene("glass").unwrap());
    let features = scene.features();
    assert_eq!((features.transmissive, features.volumes), (6, 2));
}

#[test]
fn authored_optics_scene_uses_the_extension() {
    bless();
    let (scene, report) = import(
        &assets().join("optics/optics.gltf"),
        &ImportOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e} (regenerate with COMBUSTION_BLESS=1)"));
    let expected = optics_scene();
    assert_eq!(scene.outside_ior, 1.33);
    let constants = |metal: combustion_spectra::BuiltinMetal| {
        let c = combustion_spectra::rgb_optical_constants(metal.spectrum()).unwrap();
        ComplexIor {
            eta: c.eta.map(|x| x as f32),
            k: c.k.map(|x| x as f32),
        }
    };
    assert_eq!(
        scene.materials[0].conductor,
        constants(combustion_spectra::BuiltinMetal::Gold)
    );
    assert_eq!(
        scene.materials[1].conductor,
        constants(combustion_spectra::BuiltinMetal::Copper)
    );
    assert_eq!(
        scene.materials[2].conductor,
        expected.materials[2].conductor
    );
    assert!(scene.materials[3].conductor_from_base_color);
    assert_eq!(
        scene.materials[3].conductor,
        combustion_scene::conductor_from_reflectivity([0.9, 0.9, 0.3])
    );
    assert_eq!(scene.materials[4].outside_ior, Some(1.0));
    assert_eq!(scene.materials[1].polarisation_weight, 0.0);
    assert_eq!(scene.materials[2].polarisation_weight, 1.0);
    let features = scene.features();
    assert_eq!(features.diffuse_models.len(), 3);
    assert!(features.outside_ior_not_one);
    assert_eq!(
        (features.conductors, features.conductors_from_base_color),
        (3, 1)
    );
    // MikkTSpace for the normal-mapped sphere, flat normals for the floor.
    assert_eq!(
        (report.generated_tangents, report.generated_normals),
        (1, 1),
        "{report}"
    );
    let floor = scene.meshes.iter().find(|m| m.name == "floor").unwrap();
    assert!(floor.vertices.iter().all(|v| v.normal == [0.0, 1.0, 0.0]));
    let mapped = scene
        .meshes
        .iter()
        .find(|m| m.name == "normal-mapped sphere")
        .unwrap();
    for v in &mapped.vertices {
        let n = Vec3::from(v.normal);
        let t = Vec3::from_slice(&v.tangent[..3]);
        assert!(
            (t.length() - 1.0).abs() < 1e-3 && n.dot(t).abs() < 1e-2,
            "{v:?}"
        );
    }
    // The rest is as written.
    for (a, b) in expected.materials.iter().zip(&scene.materials) {
        assert_eq!(
            (a.diffuse_model, a.roughness, a.outside_ior),
            (b.diffuse_model, b.roughness, b.outside_ior)
        );
    }
}

#[test]
fn assets_stay_small() {
    let mut total = 0;
    let mut stack = vec![assets()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(dir).unwrap() {
            let entry = entry.unwrap();
            if entry.file_type().unwrap().is_dir() {
                stack.push(entry.path());
            } else {
                total += entry.metadata().unwrap().len();
            }
        }
    }
    assert!(total < 1 << 20, "assets/scenes holds {total} bytes");
}

#[test]
fn builtin_scenes_round_trip_exactly() {
    for name in BUILTIN_SCENES {
        let scene = builtin_scene(name).unwrap();
        let dir = temp_dir(name);
        let path = dir.join(format!("{name}.gltf"));
        save_gltf(&scene, &path).unwrap();
        let (loaded, report) = import(&path, &ImportOptions::default()).unwrap();
        assert_same_scene(&scene, &loaded);
        assert!(report.warnings.is_empty(), "{report}");
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// KHR_lights_punctual `range` is read and written; a range that is not a finite
/// number above 0 is refused with the light named.
#[test]
fn light_ranges_round_trip_and_bad_ranges_are_refused() {
    let mut scene = builtin_scene("spheres").unwrap();
    for (i, light) in scene.lights.iter_mut().enumerate() {
        if let Light::Point { range, .. } = light {
            *range = Some(4.0 + i as f32);
        }
    }
    scene.lights.push(Light::Spot {
        position: Vec3::new(0.0, 3.0, 2.0),
        direction: Vec3::new(0.0, -1.0, -0.5),
        intensity: [10.0; 3],
        inner_cone: 0.3,
        outer_cone: 0.6,
        range: Some(7.5),
        casts_shadows: true,
        radius: 0.0,
    });
    let dir = temp_dir("ranges");
    let path = dir.join("ranges.gltf");
    save_gltf(&scene, &path).unwrap();
    let (loaded, _) = import(&path, &ImportOptions::default()).unwrap();
    assert_same_scene(&scene, &loaded);
    assert!(loaded
        .lights
        .iter()
        .any(|l| matches!(l, Light::Spot { range: Some(r), .. } if *r == 7.5)));
    let mut json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    json["extensions"]["KHR_lights_punctual"]["lights"][0]["range"] = (-1.0).into();
    std::fs::write(&path, json.to_string()).unwrap();
    let error = import(&path, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("light 0") && error.contains("range -1"),
        "{error}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn textured_scene_round_trips_through_a_temporary_folder() {
    let scene = textured_scene();
    let dir = temp_dir("textured");
    let path = dir.join("t.gltf");
    save_gltf(&scene, &path).unwrap();
    let (loaded, _) = import(&path, &ImportOptions::default()).unwrap();
    assert_same_scene(&scene, &loaded);
    // One image shared by two slots stays one file.
    let table = loaded.texture_table();
    assert_eq!(table.images.len(), 8);
    let _ = std::fs::remove_dir_all(dir);
}

/// `scene` saved as glTF in a temporary folder and imported again: the same scene, no
/// warning. Returns what was imported and the glTF JSON written.
fn round_trip(scene: &Scene, name: &str) -> (Scene, serde_json::Value) {
    let dir = temp_dir(name);
    let path = dir.join(format!("{name}.gltf"));
    save_gltf(scene, &path).unwrap();
    let (loaded, report) = import(&path, &ImportOptions::default()).unwrap();
    assert_same_scene(scene, &loaded);
    assert!(report.warnings.is_empty(), "{report}");
    let json = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let _ = std::fs::remove_dir_all(dir);
    (loaded, json)
}

/// KHR_materials_transmission and KHR_materials_volume survive a save and an import:
/// a thin-walled transmissive material, one with a volume that absorbs, and one whose
/// volume absorbs nothing (no attenuation distance: infinite, which JSON cannot write).
#[test]
fn transmission_and_volumes_round_trip() {
    let mut scene = builtin_scene("spheres").unwrap();
    scene.materials[0].transmission = 1.0;
    scene.materials[1].transmission = 0.75;
    scene.materials[1].volume = Some(combustion_scene::Volume {
        thickness: 0.4,
        attenuation_distance: 0.5,
        attenuation_color: [0.8, 0.6, 0.2],
    });
    scene.materials[2].transmission = 0.5;
    scene.materials[2].volume = Some(combustion_scene::Volume {
        thickness: 2.0,
        attenuation_distance: f32::INFINITY,
        attenuation_color: [1.0; 3],
    });
    // Their textures: one linear image in both slots (R: transmission, G: thickness).
    let shades = image("transmission and thickness", ColorSpace::Linear, |x, y| {
        [(x * 16) as u8, (y * 16) as u8, 0, 255]
    });
    scene.materials[2].transmission_texture = texture(&shades, Sampler::default());
    scene.materials[2].thickness_texture = texture(&shades, Sampler::default());
    let (loaded, _) = round_trip(&scene, "transmission");
    let features = loaded.features();
    for slot in [TextureSlot::Transmission, TextureSlot::Thickness] {
        assert_eq!(features.texture_count(slot), 1, "{slot:?}");
    }
}

/// KHR_materials_clearcoat survives a save and an import: factors, the three textures
/// (one linear image in the weight and roughness slots, a normal map) and the normal
/// map's scale; a material without a coat is written without the extension.
#[test]
fn clearcoats_round_trip() {
    let mut scene = builtin_scene("clearcoat").unwrap();
    let shades = image("coat weight and roughness", ColorSpace::Linear, |x, y| {
        [(x * 16) as u8, (y * 16) as u8, 0, 255]
    });
    let bumps = image("coat normals", ColorSpace::Linear, |x, y| {
        [128 + (x * 4) as u8, 128 - (y * 4) as u8, 250, 255]
    });
    let coated = scene.materials.iter().position(|m| m.is_coated()).unwrap();
    let material = &mut scene.materials[coated];
    material.clearcoat_texture = texture(&shades, Sampler::default());
    material.clearcoat_roughness_texture = texture(&shades, Sampler::default());
    material.clearcoat_normal_texture = texture(&bumps, Sampler::default());
    material.clearcoat_normal_scale = 0.5;
    let (loaded, root) = round_trip(&scene, "clearcoat");
    let features = loaded.features();
    assert_eq!(features.coated, scene.features().coated);
    assert!(features.coated > 0 && features.coated < loaded.materials.len());
    for slot in [
        TextureSlot::Clearcoat,
        TextureSlot::ClearcoatRoughness,
        TextureSlot::ClearcoatNormal,
    ] {
        assert_eq!(features.texture_count(slot), 1, "{slot:?}");
    }
    let written = root["materials"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["extensions"].get("KHR_materials_clearcoat").is_some())
        .count();
    assert_eq!(written, features.coated);
}

/// KHR_materials_sheen survives a save and an import: colour, roughness and both
/// textures; a material without sheen is written without the extension.
#[test]
fn sheen_round_trips() {
    let mut scene = builtin_scene("sheen").unwrap();
    let colours = image("sheen colour", ColorSpace::Srgb, |x, y| {
        [(x * 16) as u8, (y * 16) as u8, 200, 255]
    });
    let roughness = image("sheen roughness", ColorSpace::Linear, |x, _| {
        [0, 0, 0, (x * 16) as u8]
    });
    let with = scene.materials.iter().position(|m| m.has_sheen()).unwrap();
    scene.materials[with].sheen_color_texture = texture(&colours, Sampler::default());
    scene.materials[with].sheen_roughness_texture = texture(&roughness, Sampler::default());
    let (loaded, _) = round_trip(&scene, "sheen");
    let features = loaded.features();
    assert!(features.sheen > 0 && features.sheen < loaded.materials.len());
    for slot in [TextureSlot::SheenColor, TextureSlot::SheenRoughness] {
        assert_eq!(features.texture_count(slot), 1, "{slot:?}");
    }
}

/// KHR_materials_iridescence survives a save and an import: factor, IOR, thickness
/// range and both textures; a material without a film is written without the extension.
#[test]
fn iridescence_round_trips() {
    let mut scene = builtin_scene("iridescence").unwrap();
    let weights = image("iridescence", ColorSpace::Linear, |x, _| {
        [(x * 16) as u8, 0, 0, 255]
    });
    let thickness = image("iridescence thickness", ColorSpace::Linear, |_, y| {
        [0, (y * 16) as u8, 0, 255]
    });
    let with = scene
        .materials
        .iter()
        .position(|m| m.is_iridescent())
        .unwrap();
    scene.materials[with].iridescence_texture = texture(&weights, Sampler::default());
    scene.materials[with].iridescence_thickness_texture = texture(&thickness, Sampler::default());
    let (loaded, _) = round_trip(&scene, "iridescence");
    let features = loaded.features();
    assert!(features.iridescent > 0 && features.iridescent < loaded.materials.len());
    for slot in [TextureSlot::Iridescence, TextureSlot::IridescenceThickness] {
        assert_eq!(features.texture_count(slot), 1, "{slot:?}");
    }
    let films: Vec<_> = loaded.materials.iter().map(|m| m.iridescence).collect();
    let expected: Vec<_> = scene.materials.iter().map(|m| m.iridescence).collect();
    assert_eq!(films, expected);
}

/// KHR_texture_transform and TEXCOORD_1 survive a save and an import: a slot on set 1
/// with an offset, rotation and scale, a mesh whose second set differs from its first.
#[test]
fn texture_transforms_and_the_second_set_round_trip() {
    let mut scene = textured_scene();
    let material = &mut scene.materials[0];
    let base = material.base_color_texture.as_mut().unwrap();
    base.tex_coord = 1;
    base.transform = UvTransform {
        offset: [0.25, -0.5],
        rotation: 0.3,
        scale: [2.0, 0.5],
    };
    let emissive_or_normal = material
        .normal_texture
        .as_mut()
        .or(material.emissive_texture.as_mut());
    emissive_or_normal.unwrap().transform.offset = [0.125, 0.0];
    let mesh = scene.objects[0].mesh;
    for v in &mut scene.meshes[mesh].vertices {
        v.uv1 = [v.uv[1], 1.0 - v.uv[0]];
    }
    let dir = temp_dir("texture-transform");
    let path = dir.join("transformed.gltf");
    save_gltf(&scene, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("KHR_texture_transform") && text.contains("TEXCOORD_1"));
    let (imported, report) = import(&path, &ImportOptions::default()).unwrap();
    assert!(report.warnings.is_empty(), "{report}");
    assert_same_scene(&scene, &imported);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn saving_an_invalid_scene_names_the_problem() {
    let mut scene = textured_scene();
    scene.materials[0].roughness = 2.0;
    let dir = temp_dir("invalid");
    let err = save_gltf(&scene, &dir.join("x.gltf"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("x.gltf") && err.contains("roughness"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

/// A scene with morph targets is refused in one line (its targets, skins and animations
/// cannot be written yet), nothing written; its still copy in a pose saves.
#[test]
fn saving_a_morphing_scene_is_refused_and_its_still_copy_saves() {
    let mut scene = builtin_scene("spheres").unwrap();
    let vertices = scene.meshes[0].vertices.len();
    scene.meshes[0].morph_targets = vec![combustion_scene::motion::MorphTarget {
        positions: vec![[0.0, 0.1, 0.0]; vertices],
        ..Default::default()
    }];
    scene.motion.nodes.push(combustion_scene::motion::Node {
        name: None,
        parent: None,
        local: combustion_scene::motion::LocalTransform::Matrix(scene.objects[0].transform),
        skin: None,
        weights: vec![1.0],
    });
    scene.objects[0].node = Some(combustion_scene::NodeLink {
        node: 0,
        offset: glam::Mat4::IDENTITY,
    });
    let users: Vec<usize> = (0..scene.objects.len())
        .filter(|&i| scene.objects[i].mesh == 0)
        .collect();
    // Every object of the mesh hangs from the node (weights for its target).
    for &i in &users[1..] {
        scene.objects[i].node = scene.objects[0].node;
        scene.objects[i].transform = scene.objects[0].transform;
    }
    scene.validate().unwrap();
    let dir = temp_dir("morphing");
    let error = save_gltf(&scene, &dir.join("m.gltf"))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("skins, morph targets and animations cannot be written")
            && !error.contains('\n'),
        "{error}"
    );
    assert!(!dir.join("m.gltf").exists());
    let still = scene.posed(&scene.pose_objects(&scene.motion.rest_pose()));
    save_gltf(&still, &dir.join("still.gltf")).unwrap();
    let _ = std::fs::remove_dir_all(dir);
}

/// `COMBUSTION_shadows`: whether each light casts shadows and its size (a point or
/// spot light's radius, a directional light's angular diameter) survive a save → import
/// round trip, and so does an object's (a node's) flag; the extension is written only
/// where a light or an object differs from the defaults
/// (casting, no size), and named in `extensionsUsed` then. Bad values get a one-line
/// error naming the light and the field.
#[test]
fn shadow_flags_and_light_sizes_round_trip_and_bad_values_are_refused() {
    let mut scene = builtin_scene("grid-sun").unwrap();
    let dir = temp_dir("light-shadows");
    let path = dir.join("plain.gltf");
    save_gltf(&scene, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        !text.contains("COMBUSTION_shadows"),
        "defaults are not written"
    );

    if let Light::Directional {
        angular_diameter, ..
    } = &mut scene.lights[0]
    {
        *angular_diameter = 0.0093;
    }
    scene.lights.push(Light::Point {
        position: Vec3::new(1.0, 2.0, 0.5),
        intensity: [5.0; 3],
        range: None,
        casts_shadows: false,
        radius: 0.0,
    });
    // An object that casts none (a node's flag).
    scene.objects[3].casts_shadows = false;
    scene.lights.push(Light::Spot {
        position: Vec3::new(0.0, 3.0, 2.0),
        direction: Vec3::new(0.0, -1.0, -0.5),
        intensity: [10.0; 3],
        inner_cone: 0.3,
        outer_cone: 0.6,
        range: None,
        casts_shadows: true,
        radius: 0.25,
    });
    let path = dir.join("shadows.gltf");
    save_gltf(&scene, &path).unwrap();
    let (loaded, _) = import(&path, &ImportOptions::default()).unwrap();
    assert_same_scene(&scene, &loaded);
    assert_eq!(loaded.lights, scene.lights);
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    assert!(json["extensionsUsed"]
        .as_array()
        .unwrap()
        .iter()
        .any(|e| e == "COMBUSTION_shadows"));

    for (light, field, value, expected) in [
        (
            2,
            "radius",
            serde_json::json!(-1.0),
            "radius must be a number from 0 to",
        ),
        (
            2,
            "radius",
            serde_json::json!("big"),
            "radius must be a number from 0 to",
        ),
        (
            0,
            "angularDiameter",
            serde_json::json!(2.0),
            "angularDiameter must be a number from 0 to",
        ),
        (
            2,
            "angularDiameter",
            serde_json::json!(0.01),
            "is for directional lights",
        ),
        (
            0,
            "radius",
            serde_json::json!(0.01),
            "is for point and spot lights",
        ),
        (
            1,
            "castsShadows",
            serde_json::json!(1),
            "castsShadows must be true or false",
        ),
        (
            1,
            "softness",
            serde_json::json!(1),
            "has no field `softness`",
        ),
    ] {
        let mut bad = json.clone();
        bad["extensions"]["KHR_lights_punctual"]["lights"][light]["extensions"]
            ["COMBUSTION_shadows"][field] = value;
        let bad_path = dir.join("bad.gltf");
        std::fs::write(&bad_path, bad.to_string()).unwrap();
        let error = match import(&bad_path, &ImportOptions::default()) {
            Ok(_) => panic!(
                "{field} = {} was accepted",
                bad["extensions"]["KHR_lights_punctual"]["lights"][light]
            ),
            Err(e) => e.to_string(),
        };
        assert!(
            error.contains(&format!("light {light}")) && error.contains(expected),
            "{field} = {}: {error}",
            bad["extensions"]["KHR_lights_punctual"]["lights"][light]["extensions"]
        );
        assert_eq!(error.lines().count(), 1, "{error}");
    }
    // A node's flag that is not a boolean, or an unknown field on a node.
    let node = json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n.get("extensions").is_some())
        .unwrap();
    for (value, expected) in [
        (
            serde_json::json!({ "castsShadows": "no" }),
            "castsShadows must be true or false",
        ),
        (
            serde_json::json!({ "radius": 1.0 }),
            "has no field `radius`",
        ),
    ] {
        let mut bad = json.clone();
        bad["nodes"][node]["extensions"]["COMBUSTION_shadows"] = value;
        let bad_path = dir.join("bad-node.gltf");
        std::fs::write(&bad_path, bad.to_string()).unwrap();
        let error = match import(&bad_path, &ImportOptions::default()) {
            Ok(_) => panic!("node {node}: accepted"),
            Err(e) => e.to_string(),
        };
        assert!(
            error.contains(&format!("node {node}")) && error.contains(expected),
            "{error}"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// A light's shadow size out of range is refused by the scene's validation (hosts build
/// scenes and frames' lights without the importer), naming the light.
#[test]
fn light_sizes_out_of_range_are_refused() {
    for light in [
        Light::Point {
            position: Vec3::ZERO,
            intensity: [1.0; 3],
            range: None,
            casts_shadows: true,
            radius: -0.1,
        },
        Light::Point {
            position: Vec3::ZERO,
            intensity: [1.0; 3],
            range: None,
            casts_shadows: true,
            radius: f32::NAN,
        },
        Light::Directional {
            direction: Vec3::NEG_Y,
            irradiance: [1.0; 3],
            casts_shadows: true,
            angular_diameter: 1.0,
        },
        Light::Directional {
            direction: Vec3::NEG_Y,
            irradiance: [1.0; 3],
            casts_shadows: true,
            angular_diameter: f32::INFINITY,
        },
    ] {
        let error = combustion_scene::validate_lights(std::slice::from_ref(&light))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("light 0")
                && (error.contains("radius") || error.contains("angular diameter")),
            "{light:?}: {error}"
        );
    }
}

/// Points and lines are written with their glTF mode (0 and 1) and read back with their
/// topology, indices and vertices, their unlit material kept (the importer's copy of it
/// for points and lines: unlit, the same base colour).
#[test]
fn points_and_lines_round_trip() {
    use combustion_scene::{Mesh, Object, Topology, Vertex};
    let mut scene = builtin_scene("spheres").unwrap();
    let vertex = |x: f32, y: f32| Vertex {
        position: [x, y, 0.5],
        normal: [0.0, 0.0, 1.0],
        tangent: [0.0, 1.0, 0.0, -1.0],
        color: [0.5, 0.25, 1.0, 1.0],
        ..Vertex::default()
    };
    let strokes = [
        (Topology::Lines, vec![0, 1, 1, 2]),
        (Topology::Points, vec![2, 0]),
    ];
    let material = scene.materials.len();
    scene.materials.push(combustion_scene::Material {
        base_color: [0.25, 0.5, 0.75],
        ..combustion_scene::Material::default().for_points_and_lines()
    });
    for (topology, indices) in &strokes {
        scene.objects.push(Object {
            mesh: scene.meshes.len(),
            material,
            transform: glam::Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)),
            casts_shadows: true,
            node: None,
        });
        scene.meshes.push(Mesh {
            name: format!("{topology:?}"),
            vertices: vec![vertex(0.0, 0.0), vertex(1.0, 0.0), vertex(1.0, 1.0)],
            indices: indices.clone(),
            topology: *topology,
            ..Mesh::default()
        });
    }
    scene.validate().unwrap();
    let dir = temp_dir("strokes");
    let path = dir.join("strokes.gltf");
    save_gltf(&scene, &path).unwrap();
    let (loaded, report) = import(&path, &ImportOptions::default()).unwrap();
    assert!(report.warnings.is_empty(), "{report}");
    for (topology, indices) in &strokes {
        let object = loaded
            .objects
            .iter()
            .find(|o| loaded.meshes[o.mesh].topology == *topology)
            .unwrap_or_else(|| panic!("no {topology:?} read back"));
        let mesh = &loaded.meshes[object.mesh];
        assert_eq!(&mesh.indices, indices);
        assert_eq!(
            mesh.vertices,
            [vertex(0.0, 0.0), vertex(1.0, 0.0), vertex(1.0, 1.0)]
        );
        assert_eq!(object.transform, scene.objects.last().unwrap().transform);
        let m = &loaded.materials[object.material];
        assert!(m.unlit && m.base_color == [0.25, 0.5, 0.75], "{m:?}");
    }
    let _ = std::fs::remove_dir_all(dir);
}
