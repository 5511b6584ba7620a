//! Built-in procedural scenes, so rendering needs no downloaded assets.

use glam::{Mat4, Quat, Vec3};

use crate::{Camera, ComplexIor, DiffuseModel, Light, Material, Mesh, Object, Scene, SceneError};
use combustion_spectra::MetalColour;

/// Names accepted by [`builtin_scene`] (also as `builtin:NAME` on the command line).
pub const BUILTIN_SCENES: &[&str] = &[
    "spheres",
    "hard-cases",
    "gold-copper",
    "dielectrics",
    "diffuse-models",
    "underwater",
    "underwater-in-air",
    "grid-7x7",
    "spheres-studio",
    "gold-copper-underwater",
    "grid-sun",
    "spot-box",
    "point-among",
    "glass",
    "glass-underwater",
    "clearcoat",
    "clearcoat-underwater",
    "sheen",
    "iridescence",
    "specular",
    "normal-mapped",
    "resting",
    "room",
    "cornell-box",
];

/// Builds the built-in scene `name` (one of [`BUILTIN_SCENES`]), procedurally, needing no
/// files. Every built-in scene passes [`Scene::validate`].
///
/// - `spheres`: a grid of spheres, roughness ([`SPHERE_GRID_ROUGHNESS`]) along the
///   columns, material along the rows (plastic, gold, a copper blend, anisotropic
///   aluminium), lit by point lights;
/// - `hard-cases`: the renderer's edge cases (grazing angles, roughness 0 and 1, η = 1,
///   total internal reflection, lights behind surfaces, ...);
/// - `gold-copper`, `dielectrics`, `diffuse-models`: conductors, dielectrics of rising
///   IOR, and the three [`DiffuseModel`]s side by side;
/// - `underwater` and `underwater-in-air`: one set of objects in water (outside IOR 1.33)
///   and in air;
/// - `grid-7x7`: the performance grid, 49 finely tessellated spheres;
/// - `spheres-studio`, `gold-copper-underwater`: lit by [`crate::Environment::Studio`]
///   alone;
/// - `grid-sun`: the performance grid's 49 spheres standing on a floor under a low sun
///   (20° above the horizon), for shadows;
/// - `spot-box`: a closed room lit by one spot light from the ceiling, three spheres on
///   its floor; `point-among`: a point light among a ring of spheres on a floor (shadows
///   of local lights);
/// - `glass` and `glass-underwater`: a solid glass ball and a glass slab over tiles, and
///   thin-walled glass spheres from smooth to rough (KHR_materials_transmission, volume),
///   in air and under water;
/// - `clearcoat` and `clearcoat-underwater`: clear coats (KHR_materials_clearcoat) from
///   smooth to rough over a red plastic, and over gold, a half-weight coat, and the red
///   plastic uncoated beside them, in air and under water (where a 1.5 coat reflects a
///   tenth of what it does in air);
/// - `sheen`: the sheen of fibres (KHR_materials_sheen) from smooth to rough over a dark
///   red cloth, a coloured sheen over blue, sheen over gold, the cloth without sheen,
///   and a sheen under a clear coat.
/// - `iridescence`: thin films (KHR_materials_iridescence) of index 2 over a black
///   plastic, 200 to 800 nm thick; a titanium-oxide-like film over aluminium and a thin one over gold, a
///   half-weight film over blue, and the black plastic without a film.
/// - `specular`: the dielectric's specular strength and colour (KHR_materials_specular)
///   over a dark blue plastic: factor 0, ½ and 1 (the plain plastic), a yellow colour, a
///   colour of 3; a colour of 40 (F₀′ saturated at 1) on a rough plastic, factor ½ under a
///   thin film, factor 0 on a half-metal, and a yellow colour on glossy red.
/// - `normal-mapped`: spheres under a steep, high-frequency normal map (a bump field of
///   32 × 16 cells whose normals tilt up to 72°), so that shading normals face away from
///   the eye over much of each sphere and all around its rim: plastic, gold, a clear coat
///   whose own normal stays smooth, and an anisotropic metal, lit from the eye's side and
///   grazing from behind.
///
/// - `resting`: a sphere and a box resting on a floor, lit by the studio environment
///   alone: the contacts, the crevice between the box and the floor and the ground
///   beside them are where the scene blocks the environment (`--environment-occlusion gtao`,
///   `--environment-occlusion ray-traced`; docs/occlusion.md).
/// - `room`: a closed room (4 × 2.6 × 4 m, light grey Lambertian walls, floor and ceiling)
///   with a window of 1.4 × 1.1 m in one wall and a red sphere on its floor, seen from
///   inside: lit by the studio environment alone, which only the window lets in — without
///   occlusion the walls glow as if there were none (docs/occlusion.md).
///
/// - `cornell-box`: a closed box (2 m a side inside) with a red wall on the left, a green
///   one on the right and the rest white Lambertian, a white block and a gold sphere on
///   its floor, lit by a small emissive square under the ceiling and a point light
///   below it; the camera inside, by the front wall. Light that bounces: the walls tint
///   the floor and the block, the gold sphere reflects them, and the emissive square
///   lights the box only by what a path tracer finds (the real-time frame sees only
///   its glow).
///
/// An unknown name is [`SceneError::UnknownBuiltin`], which lists the known ones.
pub fn builtin_scene(name: &str) -> Result<Scene, SceneError> {
    builtin_scene_with(name, MetalColour::Bands)
}

/// As [`builtin_scene`], its metals' RGB constants derived from their measured spectra by
/// `colour` (the rendering notes' bands, or fitted to the colorimetric reflectance).
pub fn builtin_scene_with(name: &str, colour: MetalColour) -> Result<Scene, SceneError> {
    match name {
        "spheres" => Ok(spheres(colour)),
        "hard-cases" => Ok(hard_cases(colour)),
        "gold-copper" => Ok(gold_copper(colour)),
        "dielectrics" => Ok(dielectrics()),
        "diffuse-models" => Ok(diffuse_models()),
        "underwater" => Ok(underwater(colour, WATER_IOR, "underwater")),
        "underwater-in-air" => Ok(underwater(colour, 1.0, "underwater-in-air")),
        "grid-7x7" => Ok(grid_7x7(colour)),
        "grid-sun" => Ok(grid_sun(colour)),
        "spot-box" => Ok(spot_box(colour)),
        "point-among" => Ok(point_among(colour)),
        "glass" => Ok(glass(1.0, "glass")),
        "glass-underwater" => Ok(glass(WATER_IOR, "glass-underwater")),
        "clearcoat" => Ok(clearcoat(colour, 1.0, "clearcoat")),
        "clearcoat-underwater" => Ok(clearcoat(colour, WATER_IOR, "clearcoat-underwater")),
        "sheen" => Ok(sheen(colour)),
        "iridescence" => Ok(iridescence(colour)),
        "specular" => Ok(specular(colour)),
        "normal-mapped" => Ok(normal_mapped(colour)),
        "resting" => Ok(resting()),
        "room" => Ok(room()),
        "cornell-box" => Ok(cornell_box(colour)),
        "spheres-studio" => Ok(under_studio(spheres(colour), "spheres-studio")),
        "gold-copper-underwater" => Ok(under_studio(
            Scene {
                outside_ior: WATER_IOR,
                ..gold_copper(colour)
            },
            "gold-copper-underwater",
        )),
        _ => Err(SceneError::UnknownBuiltin {
            name: name.to_owned(),
            known: BUILTIN_SCENES.join(", "),
        }),
    }
}

/// `scene` lit by the studio environment alone (its lights removed): environment
/// lighting's built-in scenes (`spheres-studio`, the sphere grid; `gold-copper-underwater`,
/// gold and copper in water, η_i = 1.33).
fn under_studio(scene: Scene, name: &str) -> Scene {
    Scene {
        name: name.into(),
        lights: Vec::new(),
        environment: Some(crate::Environment::Studio),
        ..scene
    }
}

/// Perceptual roughness of each column of the sphere grid, left to right.
pub const SPHERE_GRID_ROUGHNESS: [f32; 6] = [0.1, 0.25, 0.4, 0.55, 0.75, 1.0];

fn metal(metal: combustion_spectra::BuiltinMetal, colour: MetalColour) -> ComplexIor {
    let constants = metal.constants(colour);
    ComplexIor {
        eta: constants.eta.map(|x| x as f32),
        k: constants.k.map(|x| x as f32),
    }
}

/// The performance grid: 7×7 spheres of 64×32 segments (194,432 triangles), seven
/// materials down the rows (plastic, gold, silver, copper, anisotropic aluminium, glass,
/// rough clay with Oren–Nayar), roughness 0.05–1 along the columns, four point lights.
/// The performance grid's materials: a material per row (top to bottom), roughness
/// rising along each row's 7 columns from 0.05 to 1.
fn grid_materials(colour: MetalColour) -> Vec<Material> {
    use combustion_spectra::BuiltinMetal;
    let conductor = |name: &str, which: BuiltinMetal| Material {
        name: name.into(),
        metalness: 1.0,
        conductor: metal(which, colour),
        ..Material::default()
    };
    let rows = [
        Material {
            name: "blue plastic".into(),
            base_color: [0.05, 0.2, 0.7],
            ..Material::default()
        },
        conductor("gold", BuiltinMetal::Gold),
        conductor("silver", BuiltinMetal::Silver),
        conductor("copper", BuiltinMetal::Copper),
        Material {
            anisotropy_strength: 0.7,
            ..conductor("anisotropic aluminium", BuiltinMetal::Aluminium)
        },
        Material {
            name: "glass".into(),
            base_color: [0.02, 0.02, 0.02],
            dielectric_ior: 1.5,
            ..Material::default()
        },
        Material {
            name: "clay".into(),
            base_color: [0.6, 0.35, 0.25],
            diffuse_model: DiffuseModel::OrenNayarFull,
            ..Material::default()
        },
    ];
    rows.iter()
        .flat_map(|base| {
            (0..7).map(|column| {
                let roughness = 0.05 + 0.95 * column as f32 / 6.0;
                Material {
                    name: format!("{} r={roughness:.2}", base.name),
                    roughness,
                    ..base.clone()
                }
            })
        })
        .collect()
}

fn grid_7x7(colour: MetalColour) -> Scene {
    let materials = grid_materials(colour);
    let objects = (0..materials.len())
        .map(|i| {
            let (row, column) = (i / 7, i % 7);
            Object {
                mesh: 0,
                material: i,
                transform: Mat4::from_translation(Vec3::new(
                    column as f32 - 3.0,
                    3.0 - row as f32,
                    0.0,
                )),
                casts_shadows: true,
                node: None,
            }
        })
        .collect();
    let light = |x: f32, y: f32, i: f32| Light::Point {
        position: Vec3::new(x, y, 5.0),
        intensity: [i; 3],
        range: None,
        casts_shadows: true,
        radius: 0.0,
    };
    Scene {
        name: "grid-7x7".into(),
        meshes: vec![Mesh::uv_sphere("sphere", 0.42, 64, 32)],
        materials,
        objects,
        lights: vec![
            light(-5.0, 5.0, 60.0),
            light(5.0, 4.0, 40.0),
            light(-4.0, -5.0, 25.0),
            light(5.0, -5.0, 20.0),
        ],
        camera: Camera {
            position: Vec3::new(0.0, 0.0, 12.5),
            target: Vec3::ZERO,
            up: Vec3::Y,
            vertical_fov: 40f32.to_radians(),
            near: 0.1,
            far: 100.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// The performance grid's spheres standing on a grey Lambertian floor in rows 1 m apart,
/// under a sun 20° above the horizon giving 3 W/m², seen from above and in front.
fn grid_sun(colour: MetalColour) -> Scene {
    let mut materials = grid_materials(colour);
    let spheres = materials.len();
    let radius = 0.42;
    let mut objects: Vec<Object> = (0..spheres)
        .map(|i| {
            let (row, column) = (i / 7, i % 7);
            Object {
                mesh: 0,
                material: i,
                transform: Mat4::from_translation(Vec3::new(
                    column as f32 - 3.0,
                    radius,
                    row as f32 - 3.0,
                )),
                casts_shadows: true,
                node: None,
            }
        })
        .collect();
    materials.push(Material {
        name: "floor".into(),
        base_color: [0.5, 0.5, 0.5],
        roughness: 0.8,
        ..Material::default()
    });
    objects.push(Object {
        mesh: 1,
        material: spheres,
        transform: Mat4::IDENTITY,
        casts_shadows: true,
        node: None,
    });
    let (elevation, azimuth) = (20f32.to_radians(), 35f32.to_radians());
    Scene {
        name: "grid-sun".into(),
        meshes: vec![
            Mesh::uv_sphere("sphere", radius, 64, 32),
            Mesh::plane("floor", 20.0),
        ],
        materials,
        objects,
        lights: vec![Light::Directional {
            // The way the light travels: down, and away from the sun's azimuth.
            direction: Vec3::new(
                -elevation.cos() * azimuth.cos(),
                -elevation.sin(),
                -elevation.cos() * azimuth.sin(),
            ),
            irradiance: [3.0; 3],
            casts_shadows: true,
            angular_diameter: 0.0,
        }],
        camera: Camera {
            position: Vec3::new(0.0, 7.0, 9.0),
            target: Vec3::new(0.0, 0.0, 0.5),
            up: Vec3::Y,
            vertical_fov: 40f32.to_radians(),
            near: 0.1,
            far: 100.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// Grey Lambertian walls (material 0) and three spheres (materials 1–3: plastic, gold,
/// clay) for the local-light shadow scenes.
fn shadow_scene_materials(colour: MetalColour) -> Vec<Material> {
    vec![
        Material {
            name: "wall".into(),
            base_color: [0.6, 0.6, 0.6],
            roughness: 0.9,
            ..Material::default()
        },
        Material {
            name: "red plastic".into(),
            base_color: [0.7, 0.08, 0.05],
            roughness: 0.35,
            ..Material::default()
        },
        Material {
            name: "gold".into(),
            metalness: 1.0,
            roughness: 0.3,
            conductor: metal(combustion_spectra::BuiltinMetal::Gold, colour),
            ..Material::default()
        },
        Material {
            name: "clay".into(),
            base_color: [0.6, 0.35, 0.25],
            roughness: 0.8,
            diffuse_model: DiffuseModel::OrenNayarFull,
            ..Material::default()
        },
    ]
}

/// A scene of the local-light shadow scenes: mesh 0 a UV sphere of `sphere_radius`
/// (64 × 32), mesh 1 a square of side `plane_side`, the shared materials, one light.
fn local_light_scene(
    colour: MetalColour,
    name: &str,
    sphere_radius: f32,
    plane_side: f32,
    objects: Vec<Object>,
    light: Light,
    camera: Camera,
) -> Scene {
    Scene {
        name: name.into(),
        meshes: vec![
            Mesh::uv_sphere("sphere", sphere_radius, 64, 32),
            Mesh::plane("plane", plane_side),
        ],
        materials: shadow_scene_materials(colour),
        objects,
        lights: vec![light],
        camera,
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// A room 6 m square and 3 m high (floor, ceiling and four walls facing inwards), a
/// spot light under the ceiling's centre pointing down (cone 30°–45°, 60 W/sr), and
/// three spheres of radius 0.5 on the floor, seen from a corner.
fn spot_box(colour: MetalColour) -> Scene {
    use std::f32::consts::FRAC_PI_2;
    let wall = |transform: Mat4| Object {
        mesh: 1,
        material: 0,
        transform,
        casts_shadows: true,
        node: None,
    };
    let mut objects = vec![
        wall(Mat4::IDENTITY),
        wall(
            Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0))
                * Mat4::from_rotation_x(std::f32::consts::PI),
        ),
    ];
    for turn in 0..4 {
        // A wall 3 m from the centre, facing it: 2 % wider and taller than the room, so
        // its edges pass through the neighbouring walls, the floor and the ceiling
        // instead of meeting theirs, which f32 transforms cannot make exact (an edge
        // meeting an edge leaves pixel-wide cracks the rasteriser may show through).
        let around = Mat4::from_rotation_y(turn as f32 * FRAC_PI_2);
        objects.push(wall(
            around
                * Mat4::from_translation(Vec3::new(0.0, 1.5, -3.0))
                * Mat4::from_rotation_x(FRAC_PI_2)
                * Mat4::from_scale(Vec3::new(1.02, 1.0, 0.51)),
        ));
    }
    for (i, x) in [-1.4f32, 0.2, 1.5].into_iter().enumerate() {
        objects.push(Object {
            mesh: 0,
            material: i + 1,
            transform: Mat4::from_translation(Vec3::new(x, 0.5, 0.3 * i as f32 - 0.4)),
            casts_shadows: true,
            node: None,
        });
    }
    let light = Light::Spot {
        position: Vec3::new(0.0, 2.9, 0.0),
        direction: Vec3::new(0.15, -1.0, 0.1),
        intensity: [60.0; 3],
        inner_cone: 30f32.to_radians(),
        outer_cone: 45f32.to_radians(),
        range: None,
        casts_shadows: true,
        radius: 0.0,
    };
    let camera = Camera {
        position: Vec3::new(2.6, 2.5, 2.6),
        target: Vec3::new(0.0, 0.4, 0.0),
        up: Vec3::Y,
        vertical_fov: 60f32.to_radians(),
        near: 0.05,
        far: 20.0,
    };
    local_light_scene(colour, "spot-box", 0.5, 6.0, objects, light, camera)
}

/// A point light 1.2 m above a floor, among six spheres of radius 0.4 in a ring of
/// radius 1.6 around it, seen from above and to the side (its six cube faces all cast).
fn point_among(colour: MetalColour) -> Scene {
    let mut objects = vec![Object {
        mesh: 1,
        material: 0,
        transform: Mat4::IDENTITY,
        casts_shadows: true,
        node: None,
    }];
    for i in 0..6 {
        let angle = i as f32 * std::f32::consts::TAU / 6.0 + 0.3;
        objects.push(Object {
            mesh: 0,
            material: 1 + i % 3,
            transform: Mat4::from_translation(Vec3::new(
                1.6 * angle.cos(),
                0.4 + 0.5 * (i % 2) as f32,
                1.6 * angle.sin(),
            )),
            casts_shadows: true,
            node: None,
        });
    }
    let light = Light::Point {
        position: Vec3::new(0.0, 1.2, 0.0),
        intensity: [20.0; 3],
        range: None,
        casts_shadows: true,
        radius: 0.0,
    };
    let camera = Camera {
        position: Vec3::new(0.0, 6.0, 5.5),
        target: Vec3::new(0.0, 0.0, 0.3),
        up: Vec3::Y,
        vertical_fov: 50f32.to_radians(),
        near: 0.05,
        far: 40.0,
    };
    local_light_scene(colour, "point-among", 0.4, 16.0, objects, light, camera)
}

/// The sphere grid: roughness varies along columns, material along rows (top to bottom:
/// red plastic, gold, a half-metallic copper blend, anisotropic aluminium).
fn spheres(colour: MetalColour) -> Scene {
    use combustion_spectra::BuiltinMetal;
    let rows = [
        Material {
            name: "red plastic".into(),
            base_color: [0.7, 0.06, 0.04],
            ..Material::default()
        },
        Material {
            name: "gold".into(),
            metalness: 1.0,
            conductor: metal(BuiltinMetal::Gold, colour),
            ..Material::default()
        },
        Material {
            name: "half-metallic copper over white".into(),
            base_color: [0.8, 0.8, 0.8],
            metalness: 0.5,
            conductor: metal(BuiltinMetal::Copper, colour),
            ..Material::default()
        },
        Material {
            name: "anisotropic aluminium".into(),
            metalness: 1.0,
            anisotropy_strength: 0.8,
            conductor: metal(BuiltinMetal::Aluminium, colour),
            ..Material::default()
        },
    ];
    let mut materials = Vec::new();
    let mut objects = Vec::new();
    let spacing = 1.0;
    let columns = SPHERE_GRID_ROUGHNESS.len();
    for (row, base) in rows.iter().enumerate() {
        for (column, &roughness) in SPHERE_GRID_ROUGHNESS.iter().enumerate() {
            materials.push(Material {
                name: format!("{} r={roughness}", base.name),
                roughness,
                ..base.clone()
            });
            let x = (column as f32 - (columns as f32 - 1.0) / 2.0) * spacing;
            let y = ((rows.len() as f32 - 1.0) / 2.0 - row as f32) * spacing;
            objects.push(Object {
                mesh: 0,
                material: materials.len() - 1,
                transform: Mat4::from_translation(Vec3::new(x, y, 0.0)),
                casts_shadows: true,
                node: None,
            });
        }
    }
    Scene {
        name: "spheres".into(),
        meshes: vec![Mesh::uv_sphere("sphere", 0.42, 96, 48)],
        materials,
        objects,
        lights: vec![
            Light::Point {
                position: Vec3::new(-4.0, 4.0, 6.0),
                intensity: [60.0; 3],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
            Light::Point {
                position: Vec3::new(5.0, -2.0, 5.0),
                intensity: [12.0, 13.0, 15.0],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
            Light::Directional {
                direction: Vec3::new(-0.3, -1.0, -0.4),
                irradiance: [0.6, 0.58, 0.55],
                casts_shadows: true,
                angular_diameter: 0.0,
            },
        ],
        camera: Camera {
            position: Vec3::new(0.0, 0.0, 9.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            vertical_fov: 40f32.to_radians(),
            near: 0.1,
            far: 100.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// Numerically hard geometry and materials for the stability and parity tests: a floor
/// seen and lit at grazing angles, roughness 0 and 1, anisotropy at its ends, η = 1,
/// η just above 1, η < 1 (silver), very large k, an air bubble under water (TIR), both
/// Oren–Nayar models, a light at the camera, lights behind surfaces, and a light exactly
/// opposite the viewer behind a sphere.
fn hard_cases(colour: MetalColour) -> Scene {
    use combustion_spectra::BuiltinMetal;
    let sphere = |name: &str, material: Material| Material {
        name: name.into(),
        ..material
    };
    let spheres = [
        sphere(
            "roughness 0, huge k",
            Material {
                metalness: 1.0,
                roughness: 0.0,
                conductor: ComplexIor {
                    eta: [1.5, 0.8, 0.3],
                    k: [30.0, 60.0, 100.0],
                },
                ..Material::default()
            },
        ),
        sphere(
            "eta = 1: no interface",
            Material {
                roughness: 0.0,
                dielectric_ior: 1.0,
                ..Material::default()
            },
        ),
        sphere(
            "anisotropy 1, roughness 1",
            Material {
                metalness: 1.0,
                roughness: 1.0,
                anisotropy_strength: 1.0,
                anisotropy_rotation: 0.7,
                conductor: metal(BuiltinMetal::Aluminium, colour),
                ..Material::default()
            },
        ),
        sphere(
            "anisotropy 1, roughness 0.05",
            Material {
                metalness: 1.0,
                roughness: 0.05,
                anisotropy_strength: 1.0,
                conductor: metal(BuiltinMetal::Silver, colour),
                ..Material::default()
            },
        ),
        sphere(
            "air bubble under water (TIR)",
            Material {
                roughness: 0.2,
                dielectric_ior: 1.0,
                outside_ior: Some(1.33),
                base_color: [0.2, 0.4, 0.8],
                ..Material::default()
            },
        ),
        sphere(
            "Oren-Nayar full, roughness 1",
            Material {
                roughness: 1.0,
                diffuse_model: DiffuseModel::OrenNayarFull,
                ..Material::default()
            },
        ),
        sphere(
            "Oren-Nayar qualitative, roughness 1",
            Material {
                roughness: 1.0,
                diffuse_model: DiffuseModel::OrenNayarQualitative,
                ..Material::default()
            },
        ),
        sphere(
            "silver (eta < 1), roughness 0.3, s-polarised",
            Material {
                metalness: 1.0,
                roughness: 0.3,
                polarisation_weight: 0.0,
                conductor: metal(BuiltinMetal::Silver, colour),
                ..Material::default()
            },
        ),
    ];
    let floor = Material {
        name: "floor: eta just above 1, smooth".into(),
        roughness: 0.02,
        dielectric_ior: 1.0001,
        base_color: [0.5, 0.5, 0.5],
        ..Material::default()
    };
    let camera_position = Vec3::new(0.0, -0.4, 6.0);
    let mut materials = vec![floor];
    let mut objects = vec![Object {
        mesh: 1,
        material: 0,
        transform: Mat4::from_translation(Vec3::new(0.0, -0.5, 0.0)),
        casts_shadows: true,
        node: None,
    }];
    let count = spheres.len();
    let mut centres = Vec::new();
    for (i, material) in spheres.into_iter().enumerate() {
        materials.push(material);
        let centre = Vec3::new((i as f32 - (count as f32 - 1.0) / 2.0) * 0.95, 0.1, 0.0);
        centres.push(centre);
        objects.push(Object {
            mesh: 0,
            material: i + 1,
            transform: Mat4::from_translation(centre),
            casts_shadows: true,
            node: None,
        });
    }
    // Exactly opposite the viewer, seen through the centre of the second sphere.
    let opposite = centres[1] + (centres[1] - camera_position).normalize() * 3.0;
    Scene {
        name: "hard-cases".into(),
        meshes: vec![
            Mesh::uv_sphere("sphere", 0.42, 48, 24),
            Mesh::plane("floor", 60.0),
        ],
        materials,
        objects,
        lights: vec![
            // At the camera: v = l everywhere (retro-reflection).
            Light::Point {
                position: camera_position,
                intensity: [8.0; 3],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
            Light::Point {
                position: opposite,
                intensity: [20.0; 3],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
            // Behind every sphere.
            Light::Point {
                position: Vec3::new(0.0, 0.3, -3.0),
                intensity: [15.0; 3],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
            // Grazing on the floor: n·l = 0.001.
            Light::Directional {
                direction: Vec3::new(1.0, -0.001, 0.0),
                irradiance: [2.0; 3],
                casts_shadows: true,
                angular_diameter: 0.0,
            },
        ],
        camera: Camera {
            position: camera_position,
            target: Vec3::new(0.0, 0.1, 0.0),
            up: Vec3::Y,
            vertical_fov: 45f32.to_radians(),
            near: 0.05,
            far: 100.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// Index of refraction of water (visible light, 20 °C), the outside medium of `underwater`.
/// Glass (KHR_materials_transmission, KHR_materials_volume, KHR_materials_ior): a solid
/// glass sphere (IOR 1.5, slightly green, absorbing) and an upright glass slab 4 cm thick
/// over a floor of tiles in two colours, before a wall of tiles; a row of small
/// thin-walled spheres from smooth to rough in front. Tiles are quads of two materials
/// rather than a texture, so that every ray, refracted or not, sees a pattern the f64
/// reference shades exactly. A sun and a point light. In the medium of index
/// `outside_ior` (air, water).
fn glass(outside_ior: f32, name: &str) -> Scene {
    let tile = |name: &str, base_color: [f32; 3]| Material {
        name: name.into(),
        base_color,
        roughness: 0.7,
        ..Material::default()
    };
    let glass = |name: &str, roughness: f32, volume: Option<crate::Volume>| Material {
        name: name.into(),
        base_color: [1.0; 3],
        roughness,
        dielectric_ior: 1.5,
        transmission: 1.0,
        volume,
        ..Material::default()
    };
    let absorbing = crate::Volume {
        thickness: 1.0,
        attenuation_distance: 1.5,
        attenuation_color: [0.8, 0.95, 0.85],
    };
    let clear_slab = crate::Volume {
        thickness: 0.04,
        attenuation_distance: f32::INFINITY,
        attenuation_color: [1.0; 3],
    };
    let mut objects = Vec::new();
    // The floor: 8 × 8 tiles of 0.5 m; the wall: 8 × 4, upright at z = −1.5.
    for i in 0..8 {
        for j in 0..8 {
            let at = Vec3::new(-1.75 + 0.5 * i as f32, 0.0, -1.5 + 0.5 * j as f32 + 0.25);
            objects.push(Object::casting_shadows(
                0,
                (i + j) % 2,
                Mat4::from_translation(at),
            ));
        }
    }
    for i in 0..8 {
        for j in 0..4 {
            let at = Vec3::new(-1.75 + 0.5 * i as f32, 0.25 + 0.5 * j as f32, -1.5);
            let upright = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
            objects.push(Object::casting_shadows(
                0,
                (i + j + 1) % 2,
                Mat4::from_rotation_translation(upright, at),
            ));
        }
    }
    objects.push(Object::casting_shadows(
        1,
        2,
        Mat4::from_translation(Vec3::new(-0.6, 0.5, -0.5)),
    ));
    objects.push(Object::casting_shadows(
        2,
        3,
        Mat4::from_translation(Vec3::new(0.75, 0.4, -0.4)),
    ));
    for (k, x) in [-0.9f32, -0.3, 0.3, 0.9].into_iter().enumerate() {
        objects.push(Object::casting_shadows(
            3,
            4 + k,
            Mat4::from_translation(Vec3::new(x, 0.2, 0.7)),
        ));
    }
    Scene {
        name: name.into(),
        meshes: vec![
            Mesh::plane("tile", 0.5),
            Mesh::uv_sphere("glass sphere", 0.5, 48, 24),
            Mesh::cuboid("glass slab", [0.8, 0.8, 0.04]),
            Mesh::uv_sphere("small sphere", 0.18, 32, 16),
        ],
        materials: vec![
            tile("light tile", [0.8, 0.78, 0.7]),
            tile("dark tile", [0.1, 0.12, 0.2]),
            glass("green glass", 0.02, Some(absorbing)),
            glass("clear glass slab", 0.02, Some(clear_slab)),
            glass("thin, roughness 0", 0.0, None),
            glass("thin, roughness 0.15", 0.15, None),
            glass("thin, roughness 0.3", 0.3, None),
            glass("thin, roughness 0.5", 0.5, None),
        ],
        objects,
        lights: vec![
            Light::Directional {
                direction: Vec3::new(-0.4, -0.8, -0.45),
                irradiance: [2.5, 2.4, 2.2],
                casts_shadows: true,
                angular_diameter: 0.0,
            },
            Light::Point {
                position: Vec3::new(1.5, 2.0, 1.8),
                intensity: [4.0, 4.0, 4.5],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
        ],
        camera: Camera {
            position: Vec3::new(0.0, 1.3, 3.2),
            target: Vec3::new(0.0, 0.45, -0.4),
            up: Vec3::Y,
            vertical_fov: 45f32.to_radians(),
            near: 0.1,
            far: 50.0,
        },
        outside_ior,
        environment: None,
        motion: Default::default(),
    }
}

const WATER_IOR: f32 = 1.33;

/// Centre spacing and radius of the spheres of the figure scenes below.
const FIGURE_SPACING: f32 = 1.0;
const FIGURE_RADIUS: f32 = 0.42;

/// Tessellation of the figure scenes' spheres: 48 segments × 24 rings (2 256 triangles),
/// enough for smooth shading at the sizes the figures are rendered at, a quarter of the
/// vertex work of the 64 × 32 grid spheres.
const FIGURE_SEGMENTS: u32 = 96;
const FIGURE_RINGS: u32 = 48;

/// A camera on the +z axis looking at the origin that frames a grid of `columns` × `rows`
/// figure spheres with a margin, for images of aspect `aspect` (width / height). The field
/// of view is a moderate 30°, so every sphere is seen nearly head-on.
fn grid_camera(columns: usize, rows: usize, aspect: f32) -> Camera {
    let margin = 0.12;
    let half_width = columns as f32 * FIGURE_SPACING / 2.0 + margin;
    let half_height = (rows as f32 * FIGURE_SPACING / 2.0 + margin).max(half_width / aspect);
    let fov = 30f32.to_radians();
    Camera {
        position: Vec3::new(0.0, 0.0, half_height / (fov / 2.0).tan()),
        target: Vec3::ZERO,
        up: Vec3::Y,
        vertical_fov: fov,
        near: 0.1,
        far: 100.0,
    }
}

/// Figure spheres on a grid in the z = 0 plane: `rows[r][c]` is the material of row `r`
/// (top first), column `c` (left first). One mesh, one material per sphere, in reading
/// order (material i is object i).
fn sphere_grid(
    name: &str,
    rows: Vec<Vec<Material>>,
    lights: Vec<Light>,
    camera: Camera,
    outside_ior: f32,
) -> Scene {
    let row_count = rows.len();
    let mut materials = Vec::new();
    let mut objects = Vec::new();
    for (row, row_materials) in rows.into_iter().enumerate() {
        let columns = row_materials.len();
        for (column, material) in row_materials.into_iter().enumerate() {
            let x = (column as f32 - (columns as f32 - 1.0) / 2.0) * FIGURE_SPACING;
            let y = ((row_count as f32 - 1.0) / 2.0 - row as f32) * FIGURE_SPACING;
            materials.push(material);
            objects.push(Object {
                mesh: 0,
                material: materials.len() - 1,
                transform: Mat4::from_translation(Vec3::new(x, y, 0.0)),
                casts_shadows: true,
                node: None,
            });
        }
    }
    Scene {
        name: name.into(),
        meshes: vec![Mesh::uv_sphere(
            "sphere",
            FIGURE_RADIUS,
            FIGURE_SEGMENTS,
            FIGURE_RINGS,
        )],
        materials,
        objects,
        lights,
        camera,
        outside_ior,
        environment: None,
        motion: Default::default(),
    }
}

/// A directional light coming *from* `towards_light` (any length) with irradiance `e`.
fn light_from(towards_light: Vec3, e: [f32; 3]) -> Light {
    Light::Directional {
        direction: -towards_light.normalize(),
        irradiance: e,
        casts_shadows: true,
        angular_diameter: 0.0,
    }
}

/// Perceptual roughness of the columns of `gold-copper`, left to right.
const GOLD_COPPER_ROUGHNESS: [f32; 4] = [0.15, 0.3, 0.5, 0.75];

/// The rendering notes' Figures 10 and 11: gold (top row) and copper (bottom row) at
/// roughness 0.15, 0.3, 0.5, 0.75 (left to right), made for a 2:1 image. Their colour is
/// the Fresnel reflectance of their measured η + ik alone (no diffuse part).
///
/// A point light at the camera gives v = l, hence v·h = 1 on every pixel it lights: the
/// face of each sphere shows the metal's reflectance at normal incidence, F(0°) — gold
/// pale yellow, copper salmon (linear F(0°): gold 0.97, 0.75, 0.39; copper 0.98, 0.66,
/// 0.60). Two directional lights from behind the spheres (138° and 144° from the view
/// direction) light their rims at v·h ≈ 0.36 and 0.31 (angles of incidence 69° and 72°),
/// where the blue and green reflectance have risen toward the red (gold's blue/red
/// 0.40 → 0.49): the rim highlights are whiter, the whitening toward grazing of Figures
/// 10 and 11.
fn gold_copper(colour: MetalColour) -> Scene {
    use combustion_spectra::BuiltinMetal;
    let row = |metal: BuiltinMetal| {
        GOLD_COPPER_ROUGHNESS
            .iter()
            .map(|&roughness| Material {
                name: format!("{} r={roughness}", metal.name()),
                metalness: 1.0,
                roughness,
                conductor: self::metal(metal, colour),
                ..Material::default()
            })
            .collect::<Vec<_>>()
    };
    let camera = grid_camera(4, 2, 2.0);
    sphere_grid(
        "gold-copper",
        vec![row(BuiltinMetal::Gold), row(BuiltinMetal::Copper)],
        vec![
            Light::Point {
                position: camera.position,
                intensity: [20.0; 3],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
            light_from(Vec3::new(-0.5, 0.45, -0.75), [2.5; 3]),
            light_from(Vec3::new(0.5, -0.3, -0.8), [2.5; 3]),
        ],
        camera,
        1.0,
    )
}

/// The dielectric IORs of `dielectrics`: the rendering notes' Figure 12.
const FIGURE_12_ETAS: [f32; 6] = [1.1, 1.33, 1.5, 1.8, 2.4, 3.0];

/// The rendering notes' Figure 12 as spheres: dielectrics of ηt = 1.1, 1.33, 1.5 (top row,
/// left to right), 1.8, 2.4, 3.0 (bottom row), all with the same dark blue base colour
/// and roughness 0.3, made for a 3:2 image. A point light at the camera gives v·h = 1:
/// each face shows a highlight of strength F(0°) = ((ηt − 1)/(ηt + 1))², 0.0023 for 1.1
/// up to 0.25 for 3.0, so the reflection visibly rises with ηt. A directional light from
/// behind (133° from the view) lights the rims at v·h ≈ 0.40 (67°), where every ηt
/// reflects far more than at normal incidence (Figure 12's curves rising toward 90°).
fn dielectrics() -> Scene {
    let material = |eta: f32| Material {
        name: format!("dielectric eta={eta}"),
        base_color: [0.02, 0.03, 0.06],
        roughness: 0.3,
        dielectric_ior: eta,
        ..Material::default()
    };
    let rows = FIGURE_12_ETAS
        .chunks(3)
        .map(|etas| etas.iter().map(|&eta| material(eta)).collect())
        .collect();
    let camera = grid_camera(3, 2, 1.5);
    sphere_grid(
        "dielectrics",
        rows,
        vec![
            Light::Point {
                position: camera.position,
                intensity: [30.0; 3],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            },
            light_from(Vec3::new(0.5, 0.55, -0.7), [2.0; 3]),
        ],
        camera,
        1.0,
    )
}

/// Perceptual roughness of the columns of `diffuse-models` (Oren–Nayar σ = r²/√2 =
/// 0.18, 0.40, 0.71 rad).
const DIFFUSE_MODELS_ROUGHNESS: [f32; 3] = [0.5, 0.75, 1.0];

/// The rendering notes' Figure 5: Lambert (top row), Oren–Nayar qualitative (middle) and
/// Oren–Nayar full (bottom) at roughness 0.5, 0.75, 1 (left to right), a clay-coloured
/// albedo, made for a square image. The dielectric IOR equals the outside medium's (1), so
/// there is no interface: no specular lobe and no Fresnel weighting, and the pixels show
/// the diffuse models alone, as Figure 5 does.
///
/// One directional light from the upper left, 31° from the view direction. That is where
/// Oren–Nayar's flattening shows: rough surfaces back-scatter toward a light near the
/// viewer, so across the lit face the rough spheres stay nearly uniformly bright where
/// Lambert falls off as cos θi — the flat, "full moon" look, the stronger the rougher.
/// Lit from the side or behind, the models differ far less: where light and view lie on
/// opposite sides of the normal the qualitative model's extra term is 0 and both
/// Oren–Nayar spheres take Lambert's shape (measured with the analytic reference at 70°,
/// 90° and 110°), so a side light would hide what the figure is about.
fn diffuse_models() -> Scene {
    let models = [
        ("Lambert", DiffuseModel::Lambert),
        ("Oren-Nayar qualitative", DiffuseModel::OrenNayarQualitative),
        ("Oren-Nayar full", DiffuseModel::OrenNayarFull),
    ];
    let rows = models
        .iter()
        .map(|&(label, model)| {
            DIFFUSE_MODELS_ROUGHNESS
                .iter()
                .map(|&roughness| Material {
                    name: format!("{label} r={roughness}"),
                    base_color: [0.7, 0.5, 0.38],
                    roughness,
                    dielectric_ior: 1.0,
                    diffuse_model: model,
                    ..Material::default()
                })
                .collect()
        })
        .collect();
    sphere_grid(
        "diffuse-models",
        rows,
        vec![light_from(Vec3::new(-0.45, 0.25, 0.86), [3.5; 3])],
        grid_camera(3, 3, 1.0),
        1.0,
    )
}

/// One scene definition seen from two media: `underwater` (outside IOR 1.33) and
/// `underwater-in-air` (the same objects, lights and camera in air, outside IOR 1). Made for
/// a 3:2 image. Top row: dielectrics of η = 1.1, 1.33, 1.5; bottom row: η = 1.8, an air
/// bubble (η = 1, black base colour: nothing behind its surface scatters light), and
/// silver. All have roughness 0.35, the dielectrics the same dark base colour.
///
/// Under water each interface's relative index η/1.33 is closer to 1 for η > √1.33 ≈ 1.15,
/// so the 1.5 and 1.8 spheres reflect less than in air (the silver too, by 0.3 %: its
/// k ≫ 1) and the 1.33 sphere not at all (no interface); the 1.1 sphere reflects *more* (its relative index
/// 0.83 is farther from 1 than 1.1 is). The bubble is invisible in air (η = 1: no
/// interface, nothing to scatter) but under water shows total internal reflection: past
/// the critical angle asin(1/1.33) = 48.8° F = 1. A key light from the front left (64°
/// from the view) lights every face at v·h ≈ 0.85; a light from behind on the right (134°
/// from the view, v·h ≈ 0.39, i.e. 67° > 48.8°) puts a TIR highlight on the bubble's right
/// rim, where the key light does not reach.
fn underwater(colour: MetalColour, outside_ior: f32, name: &str) -> Scene {
    use combustion_spectra::BuiltinMetal;
    let roughness = 0.35;
    let dielectric = |eta: f32| Material {
        name: format!("dielectric eta={eta}"),
        base_color: [0.02, 0.03, 0.06],
        roughness,
        dielectric_ior: eta,
        ..Material::default()
    };
    let rows = vec![
        vec![dielectric(1.1), dielectric(1.33), dielectric(1.5)],
        vec![
            dielectric(1.8),
            Material {
                name: "air bubble".into(),
                base_color: [0.0; 3],
                ..dielectric(1.0)
            },
            Material {
                name: "silver".into(),
                metalness: 1.0,
                roughness,
                conductor: metal(BuiltinMetal::Silver, colour),
                ..Material::default()
            },
        ],
    ];
    sphere_grid(
        name,
        rows,
        vec![
            light_from(Vec3::new(-0.8, 0.45, 0.45), [3.0; 3]),
            light_from(Vec3::new(0.6, 0.4, -0.7), [3.0; 3]),
        ],
        grid_camera(3, 2, 1.5),
        outside_ior,
    )
}

/// Clear coats over a red plastic (coat roughness 0.03, 0.15, 0.35, 0.7), and a smooth
/// coat over rough gold, a half-weight coat over blue plastic, the red plastic uncoated,
/// a rough coat over rough copper; `outside_ior` is the medium's.
fn clearcoat(colour: MetalColour, outside_ior: f32, name: &str) -> Scene {
    use combustion_spectra::BuiltinMetal;
    let red = Material {
        name: "red plastic".into(),
        base_color: [0.6, 0.05, 0.03],
        roughness: 0.5,
        ..Material::default()
    };
    let coated = |name: &str, base: &Material, weight: f32, roughness: f32| Material {
        name: name.into(),
        clearcoat: weight,
        clearcoat_roughness: roughness,
        ..base.clone()
    };
    let metal_base = |name: &str, which: BuiltinMetal| metal_material(name, which, colour);
    let blue = blue_plastic();
    let rows = vec![
        [0.03, 0.15, 0.35, 0.7]
            .iter()
            .map(|&r| coated(&format!("red, coat roughness {r}"), &red, 1.0, r))
            .collect(),
        vec![
            coated(
                "gold, smooth coat",
                &metal_base("gold", BuiltinMetal::Gold),
                1.0,
                0.05,
            ),
            coated("blue, half coat", &blue, 0.5, 0.05),
            red.clone(),
            coated(
                "copper, rough coat",
                &metal_base("copper", BuiltinMetal::Copper),
                1.0,
                0.4,
            ),
        ],
    ];
    sphere_grid(
        name,
        rows,
        vec![
            light_from(Vec3::new(-0.8, 0.45, 0.45), [3.0; 3]),
            light_from(Vec3::new(0.6, 0.4, -0.7), [2.0; 3]),
        ],
        grid_camera(4, 2, 1.5),
        outside_ior,
    )
}

/// Sheen (white, roughness 0.2, 0.4, 0.7, 1.0) over a dark red cloth; a cyan sheen over
/// blue, a sheen over gold, the cloth without sheen, and a sheen under a clear coat.
fn sheen(colour: MetalColour) -> Scene {
    use combustion_spectra::BuiltinMetal;
    let cloth = Material {
        name: "dark red cloth".into(),
        base_color: [0.25, 0.02, 0.03],
        roughness: 0.8,
        diffuse_model: DiffuseModel::OrenNayarFull,
        ..Material::default()
    };
    let with_sheen = |name: &str, base: &Material, color: [f32; 3], roughness: f32| Material {
        name: name.into(),
        sheen_color: color,
        sheen_roughness: roughness,
        ..base.clone()
    };
    let blue = Material {
        name: "blue cloth".into(),
        base_color: [0.02, 0.04, 0.3],
        roughness: 0.7,
        ..Material::default()
    };
    let gold = Material {
        name: "gold".into(),
        metalness: 1.0,
        roughness: 0.4,
        conductor: metal(BuiltinMetal::Gold, colour),
        ..Material::default()
    };
    let rows = vec![
        [0.2, 0.4, 0.7, 1.0]
            .iter()
            .map(|&r| with_sheen(&format!("cloth, sheen roughness {r}"), &cloth, [1.0; 3], r))
            .collect(),
        vec![
            with_sheen("blue, cyan sheen", &blue, [0.2, 0.8, 0.9], 0.5),
            with_sheen("gold, sheen", &gold, [0.6; 3], 0.3),
            cloth.clone(),
            Material {
                clearcoat: 1.0,
                clearcoat_roughness: 0.1,
                ..with_sheen("cloth, sheen, clear coat", &cloth, [0.8; 3], 0.5)
            },
        ],
    ];
    sphere_grid(
        "sheen",
        rows,
        vec![
            light_from(Vec3::new(-0.8, 0.45, 0.45), [3.0; 3]),
            // grazing from behind: where sheen shows
            light_from(Vec3::new(0.3, 0.5, -0.9), [4.0; 3]),
        ],
        grid_camera(4, 2, 1.5),
        1.0,
    )
}

/// The bump field of `normal-mapped`: a tangent-space normal map (glTF's convention, RGB
/// = n/2 + ½, linear, 256 × 128 texels) of 32 × 16 cells, n ∝ (−3 cos(2π·32u)
/// sin(2π·16v), −3 sin(2π·32u) cos(2π·16v), 1): slopes up to 3, normals up to 72° from
/// the surface's.
fn bump_normal_map() -> crate::TextureRef {
    use std::f32::consts::TAU;
    let (width, height) = (256u32, 128u32);
    let mut pixels = Vec::with_capacity((width * height * 4) as usize);
    for y in 0..height {
        for x in 0..width {
            let u = (x as f32 + 0.5) / width as f32;
            let v = (y as f32 + 0.5) / height as f32;
            let (a, b) = (TAU * 32.0 * u, TAU * 16.0 * v);
            let slope = 3.0;
            let n =
                Vec3::new(-slope * a.cos() * b.sin(), -slope * a.sin() * b.cos(), 1.0).normalize();
            for c in [n.x, n.y, n.z] {
                pixels.push(((c * 0.5 + 0.5) * 255.0).round() as u8);
            }
            pixels.push(255);
        }
    }
    crate::TextureRef {
        texture: crate::Texture {
            image: std::sync::Arc::new(crate::Image {
                name: "bump field".into(),
                width,
                height,
                color_space: crate::ColorSpace::Linear,
                pixels,
            }),
            sampler: crate::Sampler::default(),
        },
        tex_coord: 0,
        transform: crate::UvTransform::IDENTITY,
    }
}

/// The `normal-mapped` scene (see [`builtin_scene`]).
fn normal_mapped(colour: MetalColour) -> Scene {
    use combustion_spectra::BuiltinMetal;
    let bumps = bump_normal_map();
    let bumped = |material: Material| Material {
        normal_texture: Some(bumps.clone()),
        normal_scale: 1.0,
        ..material
    };
    let plastic = Material {
        name: "bumped grey plastic".into(),
        base_color: [0.5, 0.5, 0.5],
        roughness: 0.35,
        ..Material::default()
    };
    let gold = Material {
        name: "bumped gold".into(),
        metalness: 1.0,
        roughness: 0.25,
        conductor: metal(BuiltinMetal::Gold, colour),
        ..Material::default()
    };
    let coated = Material {
        name: "bumped red under a smooth clear coat".into(),
        base_color: [0.6, 0.05, 0.04],
        roughness: 0.5,
        clearcoat: 1.0,
        clearcoat_roughness: 0.05,
        ..Material::default()
    };
    let brushed = Material {
        name: "bumped anisotropic aluminium".into(),
        metalness: 1.0,
        roughness: 0.3,
        anisotropy_strength: 0.7,
        conductor: metal(BuiltinMetal::Aluminium, colour),
        ..Material::default()
    };
    sphere_grid(
        "normal-mapped",
        vec![
            vec![bumped(plastic), bumped(gold)],
            vec![bumped(coated), bumped(brushed)],
        ],
        vec![
            light_from(Vec3::new(-0.3, 0.4, 0.9), [3.0; 3]),
            // grazing from behind: the rims' away-facing normals
            light_from(Vec3::new(0.4, 0.3, -0.9), [4.0; 3]),
        ],
        grid_camera(2, 2, 1.5),
        1.0,
    )
}

/// A metal of roughness 0.45, its constants derived from its spectrum by `colour`.
fn metal_material(
    name: &str,
    which: combustion_spectra::BuiltinMetal,
    colour: MetalColour,
) -> Material {
    Material {
        name: name.into(),
        metalness: 1.0,
        roughness: 0.45,
        conductor: metal(which, colour),
        ..Material::default()
    }
}

/// Blue plastic of roughness 0.3.
/// A red plastic sphere (radius 0.5) and a blue plastic box (0.8 m a side, turned 25°
/// about the vertical) resting on a light grey Lambertian floor (12 m square), under the
/// studio environment, seen from a raised three-quarter view.
fn resting() -> Scene {
    let radius = 0.5;
    let side = 0.8;
    let placed = |mesh, material, transform| Object {
        mesh,
        material,
        transform,
        casts_shadows: true,
        node: None,
    };
    Scene {
        name: "resting".into(),
        meshes: vec![
            Mesh::plane("floor", 12.0),
            Mesh::uv_sphere("sphere", radius, 64, 32),
            Mesh::cuboid("box", [side; 3]),
        ],
        materials: vec![lambertian_grey("floor", 0.6), red_plastic(), blue_plastic()],
        objects: vec![
            placed(0, 0, Mat4::IDENTITY),
            placed(1, 1, Mat4::from_translation(Vec3::new(-0.7, radius, 0.1))),
            placed(
                2,
                2,
                Mat4::from_translation(Vec3::new(0.65, side / 2.0, -0.25))
                    * Mat4::from_rotation_y(25f32.to_radians()),
            ),
        ],
        lights: Vec::new(),
        camera: Camera {
            position: Vec3::new(0.9, 1.7, 3.4),
            target: Vec3::new(0.0, 0.35, 0.0),
            up: Vec3::Y,
            vertical_fov: 40f32.to_radians(),
            near: 0.05,
            far: 50.0,
        },
        outside_ior: 1.0,
        environment: Some(crate::Environment::Studio),
        motion: Default::default(),
    }
}

/// The room of [`builtin_scene`]'s `room`: walls, floor and ceiling as 0.1 m slabs
/// around a 4 × 2.6 × 4 m interior (its floor at y = 0, centred on the y axis), the wall
/// at z = −2 with a window of 1.4 × 1.1 m whose sill is 0.9 m up, a sphere of radius 0.4
/// on the floor; the camera inside, near the opposite wall, looking at the window.
fn room() -> Scene {
    let (width, height, depth, t) = (4.0f32, 2.6f32, 4.0f32, 0.1f32);
    let (window_width, window_height, sill) = (1.4f32, 1.1f32, 0.9f32);
    let mut meshes = Vec::new();
    let mut objects = Vec::new();
    // A slab of `size` centred at `centre`, of material 0 (the walls).
    let mut slab = |name: &str, size: [f32; 3], centre: Vec3| {
        meshes.push(Mesh::cuboid(name, size));
        objects.push(Object {
            mesh: meshes.len() - 1,
            material: 0,
            transform: Mat4::from_translation(centre),
            casts_shadows: true,
            node: None,
        });
    };
    let (outer_w, outer_d) = (width + 2.0 * t, depth + 2.0 * t);
    slab(
        "floor",
        [outer_w, t, outer_d],
        Vec3::new(0.0, -t / 2.0, 0.0),
    );
    slab(
        "ceiling",
        [outer_w, t, outer_d],
        Vec3::new(0.0, height + t / 2.0, 0.0),
    );
    slab(
        "back wall",
        [outer_w, height, t],
        Vec3::new(0.0, height / 2.0, depth / 2.0 + t / 2.0),
    );
    slab(
        "left wall",
        [t, height, depth],
        Vec3::new(-width / 2.0 - t / 2.0, height / 2.0, 0.0),
    );
    slab(
        "right wall",
        [t, height, depth],
        Vec3::new(width / 2.0 + t / 2.0, height / 2.0, 0.0),
    );
    // The window wall in four slabs around the opening.
    let z = -depth / 2.0 - t / 2.0;
    let side = (outer_w - window_width) / 2.0;
    let top = height - sill - window_height;
    slab(
        "window wall, left",
        [side, height, t],
        Vec3::new(-(window_width + side) / 2.0, height / 2.0, z),
    );
    slab(
        "window wall, right",
        [side, height, t],
        Vec3::new((window_width + side) / 2.0, height / 2.0, z),
    );
    slab(
        "below the window",
        [window_width, sill, t],
        Vec3::new(0.0, sill / 2.0, z),
    );
    slab(
        "above the window",
        [window_width, top, t],
        Vec3::new(0.0, height - top / 2.0, z),
    );
    let radius = 0.4;
    meshes.push(Mesh::uv_sphere("sphere", radius, 64, 32));
    objects.push(Object {
        mesh: meshes.len() - 1,
        material: 1,
        transform: Mat4::from_translation(Vec3::new(0.5, radius, -0.6)),
        casts_shadows: true,
        node: None,
    });
    Scene {
        name: "room".into(),
        meshes,
        materials: vec![lambertian_grey("plaster", 0.7), red_plastic()],
        objects,
        lights: Vec::new(),
        camera: Camera {
            position: Vec3::new(-0.9, 1.5, 1.7),
            target: Vec3::new(0.2, 0.9, -2.0),
            up: Vec3::Y,
            vertical_fov: 70f32.to_radians(),
            near: 0.05,
            far: 50.0,
        },
        outside_ior: 1.0,
        environment: Some(crate::Environment::Studio),
        motion: Default::default(),
    }
}

/// The box of [`builtin_scene`]'s `cornell-box`: six 0.1 m slabs around a 2 m cube of
/// air (its floor at y = 0, centred on the y axis), an emissive square of 0.5 m just
/// under the ceiling's centre, a point light 0.3 m below it, a white block (0.5 × 0.9 ×
/// 0.5 m, turned 20°) at the back left and a gold sphere (radius 0.3 m) at the right; the camera at the front wall, looking at the back one.
fn cornell_box(colour: MetalColour) -> Scene {
    let (size, t) = (2.0f32, 0.1f32);
    let white = lambertian_grey("white", 0.75);
    let red = Material {
        name: "red".into(),
        base_color: [0.63, 0.065, 0.05],
        ..lambertian_grey("red", 0.0)
    };
    let green = Material {
        name: "green".into(),
        base_color: [0.14, 0.45, 0.091],
        ..lambertian_grey("green", 0.0)
    };
    let lamp = Material {
        name: "lamp".into(),
        emissive_factor: [1.0; 3],
        emissive_strength: 12.0,
        ..lambertian_grey("lamp", 0.75)
    };
    let gold = Material {
        roughness: 0.2,
        ..metal_material("gold", combustion_spectra::BuiltinMetal::Gold, colour)
    };
    let mut meshes = Vec::new();
    let mut objects = Vec::new();
    let mut place = |mesh: Mesh, material: usize, transform: Mat4| {
        meshes.push(mesh);
        objects.push(Object {
            mesh: meshes.len() - 1,
            material,
            transform,
            casts_shadows: true,
            node: None,
        });
    };
    let outer = size + 2.0 * t;
    let half = size / 2.0;
    let slab = |name: &str, extent: [f32; 3]| Mesh::cuboid(name, extent);
    let at = |x: f32, y: f32, z: f32| Mat4::from_translation(Vec3::new(x, y, z));
    place(slab("floor", [outer, t, outer]), 0, at(0.0, -t / 2.0, 0.0));
    place(
        slab("ceiling", [outer, t, outer]),
        0,
        at(0.0, size + t / 2.0, 0.0),
    );
    place(
        slab("back wall", [size, size, t]),
        0,
        at(0.0, half, -half - t / 2.0),
    );
    place(
        slab("front wall", [size, size, t]),
        0,
        at(0.0, half, half + t / 2.0),
    );
    place(
        slab("left wall", [t, size, outer]),
        1,
        at(-half - t / 2.0, half, 0.0),
    );
    place(
        slab("right wall", [t, size, outer]),
        2,
        at(half + t / 2.0, half, 0.0),
    );
    place(slab("lamp", [0.5, 0.02, 0.5]), 3, at(0.0, size - 0.01, 0.0));
    place(
        slab("block", [0.5, 0.9, 0.5]),
        0,
        at(-0.45, 0.45, -0.55) * Mat4::from_rotation_y(20f32.to_radians()),
    );
    place(
        Mesh::uv_sphere("sphere", 0.3, 64, 32),
        4,
        at(0.45, 0.3, -0.35),
    );
    Scene {
        name: "cornell-box".into(),
        meshes,
        materials: vec![white, red, green, lamp, gold],
        objects,
        lights: vec![Light::Point {
            position: Vec3::new(0.0, size - 0.3, 0.0),
            intensity: [1.5; 3],
            range: None,
            casts_shadows: true,
            radius: 0.0,
        }],
        camera: Camera {
            position: Vec3::new(0.0, 1.0, half - 0.05),
            target: Vec3::new(0.0, 0.85, -half),
            up: Vec3::Y,
            vertical_fov: 75f32.to_radians(),
            near: 0.02,
            far: 20.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// A grey of albedo `albedo`, Lambertian alone (roughness 1, IOR 1: no specular lobe).
fn lambertian_grey(name: &str, albedo: f32) -> Material {
    Material {
        name: name.into(),
        base_color: [albedo; 3],
        roughness: 1.0,
        dielectric_ior: 1.0,
        ..Material::default()
    }
}

fn red_plastic() -> Material {
    Material {
        name: "red plastic".into(),
        base_color: [0.6, 0.05, 0.04],
        roughness: 0.35,
        ..Material::default()
    }
}

fn blue_plastic() -> Material {
    Material {
        name: "blue plastic".into(),
        base_color: [0.03, 0.08, 0.5],
        roughness: 0.3,
        ..Material::default()
    }
}

/// Thin films of index 2 (a titanium-dioxide-like coating) over black plastic, 200, 350,
/// 500 and 800 nm thick (the interference colours turn with the thickness and fade as
/// the film thickens); a 2.2 film of 300 nm over aluminium (anodised titanium's
/// colours), a 1.5 film of 150 nm over gold, a half-weight 2.0 film of 400 nm over blue
/// plastic, and the black plastic bare.
fn iridescence(colour: MetalColour) -> Scene {
    use combustion_spectra::BuiltinMetal;
    let black = Material {
        name: "black plastic".into(),
        base_color: [0.01, 0.01, 0.01],
        roughness: 0.25,
        ..Material::default()
    };
    let filmed = |name: &str, base: &Material, factor: f32, ior: f32, thickness_nm: f32| Material {
        name: name.into(),
        iridescence: Some(crate::Iridescence {
            factor,
            ior,
            thickness_min_nm: 0.0,
            thickness_max_nm: thickness_nm,
        }),
        ..base.clone()
    };
    let metal_base = |name: &str, which: BuiltinMetal| Material {
        roughness: 0.3,
        ..metal_material(name, which, colour)
    };
    let blue = blue_plastic();
    let rows = vec![
        [200.0, 350.0, 500.0, 800.0]
            .iter()
            .map(|&d| filmed(&format!("black, film {d} nm"), &black, 1.0, 2.0, d))
            .collect(),
        vec![
            filmed(
                "aluminium, film 300 nm",
                &metal_base("aluminium", BuiltinMetal::Aluminium),
                1.0,
                2.2,
                300.0,
            ),
            filmed(
                "gold, film 150 nm",
                &metal_base("gold", BuiltinMetal::Gold),
                1.0,
                1.5,
                150.0,
            ),
            filmed("blue, half film 400 nm", &blue, 0.5, 2.0, 400.0),
            black.clone(),
        ],
    ];
    sphere_grid(
        "iridescence",
        rows,
        vec![
            light_from(Vec3::new(-0.8, 0.45, 0.45), [3.0; 3]),
            light_from(Vec3::new(0.6, 0.4, -0.7), [2.0; 3]),
        ],
        grid_camera(4, 2, 1.5),
        1.0,
    )
}

/// KHR_materials_specular's strength and colour over a dark blue plastic (roughness
/// 0.3): factor 0 (no specular lobe: the diffuse alone, all light reaching it), ½ and 1
/// (the plain plastic), a yellow colour and a colour of 3 at factor 1; then a colour of
/// 40 on a rough plastic (F₀′ = min(0.04 × 40, 1) = 1: a white mirror-like lobe at every
/// angle), factor ½ under a 400 nm film of index 2, factor 0 on a half-metal (its
/// conductor half untouched), and a yellow colour on a glossy red.
fn specular(colour: MetalColour) -> Scene {
    use combustion_spectra::BuiltinMetal;
    let base = Material {
        base_color: [0.02, 0.05, 0.3],
        ..blue_plastic()
    };
    let with = |name: &str, base: &Material, factor: f32, color: [f32; 3]| Material {
        name: name.into(),
        specular_factor: factor,
        specular_color_factor: color,
        ..base.clone()
    };
    let rough = Material {
        roughness: 0.6,
        ..base.clone()
    };
    let filmed = Material {
        iridescence: Some(crate::Iridescence {
            factor: 1.0,
            ior: 2.0,
            thickness_min_nm: 0.0,
            thickness_max_nm: 400.0,
        }),
        ..base.clone()
    };
    let half_metal = Material {
        metalness: 0.5,
        roughness: 0.3,
        ..metal_material("gold", BuiltinMetal::Gold, colour)
    };
    let red = Material {
        base_color: [0.5, 0.03, 0.02],
        roughness: 0.15,
        ..base.clone()
    };
    let rows = vec![
        vec![
            with("specular 0", &base, 0.0, [1.0; 3]),
            with("specular 0.5", &base, 0.5, [1.0; 3]),
            with("specular 1", &base, 1.0, [1.0; 3]),
            with("specular yellow", &base, 1.0, [1.0, 1.0, 0.0]),
            with("specular colour 3", &base, 1.0, [3.0; 3]),
        ],
        vec![
            with("rough, specular colour 40", &rough, 1.0, [40.0; 3]),
            with("filmed, specular 0.5", &filmed, 0.5, [1.0; 3]),
            with("half gold, specular 0", &half_metal, 0.0, [1.0; 3]),
            with("red, specular yellow", &red, 1.0, [1.0, 1.0, 0.0]),
            with("red", &red, 1.0, [1.0; 3]),
        ],
    ];
    sphere_grid(
        "specular",
        rows,
        vec![
            light_from(Vec3::new(-0.8, 0.45, 0.45), [3.0; 3]),
            light_from(Vec3::new(0.6, 0.4, -0.7), [2.0; 3]),
        ],
        grid_camera(5, 2, 1.5),
        1.0,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_scenes_validate() {
        for name in BUILTIN_SCENES {
            builtin_scene(name).unwrap().validate().unwrap();
        }
    }

    #[test]
    fn unknown_builtin_names_the_known_ones() {
        let err = builtin_scene("teapot").unwrap_err().to_string();
        assert!(err.contains("teapot") && err.contains("spheres"), "{err}");
    }

    #[test]
    fn underwater_and_its_air_twin_differ_only_in_the_medium() {
        let water = builtin_scene("underwater").unwrap();
        let air = builtin_scene("underwater-in-air").unwrap();
        assert_eq!((water.outside_ior, air.outside_ior), (1.33, 1.0));
        assert_eq!(water.meshes, air.meshes);
        assert_eq!(water.materials, air.materials);
        assert_eq!(water.objects, air.objects);
        assert_eq!(water.lights, air.lights);
        assert_eq!(water.camera, air.camera);
        assert!(water.materials.iter().all(|m| m.outside_ior.is_none()));
    }

    #[test]
    fn figure_scenes_cover_every_material_model() {
        let features = |name: &str| builtin_scene(name).unwrap().features();
        assert_eq!(features("gold-copper").conductors, 8);
        assert_eq!(
            features("diffuse-models").diffuse_models,
            [
                DiffuseModel::Lambert,
                DiffuseModel::OrenNayarQualitative,
                DiffuseModel::OrenNayarFull
            ]
        );
        let etas: Vec<f32> = builtin_scene("dielectrics")
            .unwrap()
            .materials
            .iter()
            .map(|m| m.dielectric_ior)
            .collect();
        assert_eq!(etas, FIGURE_12_ETAS);
        assert!(features("underwater").outside_ior_not_one);
        assert!(!features("underwater-in-air").outside_ior_not_one);
    }

    #[test]
    fn diffuse_model_discriminants_are_stable() {
        // The material table stores these numbers; the shaders compare against them.
        assert_eq!(DiffuseModel::Lambert as u32, 0);
        assert_eq!(DiffuseModel::OrenNayarQualitative as u32, 1);
        assert_eq!(DiffuseModel::OrenNayarFull as u32, 2);
    }
}
