//! Built-in procedural scenes, so rendering needs no downloaded assets.

use glam::{Mat4, Vec3};

use crate::{Camera, ComplexIor, DiffuseModel, Light, Material, Mesh, Object, Scene, SceneError};

/// Names accepted by [`builtin_scene`] (also as `builtin:NAME` on the command line).
pub const BUILTIN_SCENES: &[&str] = &["spheres", "hard-cases"];

/// Builds the built-in scene `name`.
pub fn builtin_scene(name: &str) -> Result<Scene, SceneError> {
    match name {
        "spheres" => Ok(spheres()),
        "hard-cases" => Ok(hard_cases()),
        _ => Err(SceneError::UnknownBuiltin {
            name: name.to_owned(),
            known: BUILTIN_SCENES.join(", "),
        }),
    }
}

/// Perceptual roughness of each column of the sphere grid, left to right.
pub const SPHERE_GRID_ROUGHNESS: [f32; 6] = [0.1, 0.25, 0.4, 0.55, 0.75, 1.0];

fn metal(metal: combustion_spectra::BuiltinMetal) -> ComplexIor {
    let constants = combustion_spectra::rgb_optical_constants(metal.spectrum())
        .expect("built-in metal tables cover the RGB bands (checked by the spectra crate's tests)");
    ComplexIor {
        eta: constants.eta.map(|x| x as f32),
        k: constants.k.map(|x| x as f32),
    }
}

/// The sphere grid: roughness varies along columns, material along rows (top to bottom:
/// red plastic, gold, a half-metallic copper blend, anisotropic aluminium).
fn spheres() -> Scene {
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
            conductor: metal(BuiltinMetal::Gold),
            ..Material::default()
        },
        Material {
            name: "half-metallic copper over white".into(),
            base_color: [0.8, 0.8, 0.8],
            metalness: 0.5,
            conductor: metal(BuiltinMetal::Copper),
            ..Material::default()
        },
        Material {
            name: "anisotropic aluminium".into(),
            metalness: 1.0,
            anisotropy_strength: 0.8,
            conductor: metal(BuiltinMetal::Aluminium),
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
            });
        }
    }
    Scene {
        name: "spheres".into(),
        meshes: vec![Mesh::uv_sphere("sphere", 0.42, 64, 32)],
        materials,
        objects,
        lights: vec![
            Light::Point {
                position: Vec3::new(-4.0, 4.0, 6.0),
                intensity: [60.0; 3],
            },
            Light::Point {
                position: Vec3::new(5.0, -2.0, 5.0),
                intensity: [12.0, 13.0, 15.0],
            },
            Light::Directional {
                direction: Vec3::new(-0.3, -1.0, -0.4),
                irradiance: [0.6, 0.58, 0.55],
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
    }
}

/// Numerically hard geometry and materials for the stability and parity tests: a floor
/// seen and lit at grazing angles, roughness 0 and 1, anisotropy at its ends, η = 1,
/// η just above 1, η < 1 (silver), very large k, an air bubble under water (TIR), both
/// Oren–Nayar models, a light at the camera, lights behind surfaces, and a light exactly
/// opposite the viewer behind a sphere.
fn hard_cases() -> Scene {
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
                conductor: metal(BuiltinMetal::Aluminium),
                ..Material::default()
            },
        ),
        sphere(
            "anisotropy 1, roughness 0.05",
            Material {
                metalness: 1.0,
                roughness: 0.05,
                anisotropy_strength: 1.0,
                conductor: metal(BuiltinMetal::Silver),
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
                conductor: metal(BuiltinMetal::Silver),
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
            },
            Light::Point {
                position: opposite,
                intensity: [20.0; 3],
            },
            // Behind every sphere.
            Light::Point {
                position: Vec3::new(0.0, 0.3, -3.0),
                intensity: [15.0; 3],
            },
            // Grazing on the floor: n·l = 0.001.
            Light::Directional {
                direction: Vec3::new(1.0, -0.001, 0.0),
                irradiance: [2.0; 3],
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
    }
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
    fn diffuse_model_discriminants_are_stable() {
        // The material table stores these numbers; the shaders compare against them.
        assert_eq!(DiffuseModel::Lambert as u32, 0);
        assert_eq!(DiffuseModel::OrenNayarQualitative as u32, 1);
        assert_eq!(DiffuseModel::OrenNayarFull as u32, 2);
    }
}
