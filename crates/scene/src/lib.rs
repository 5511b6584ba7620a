//! CPU scene model of Combustion: meshes, materials, lights and a camera. No Vulkan here.
//!
//! Conventions (one place for each):
//! - Right-handed world space, y up; lengths in metres.
//! - Colours are linear RGB.
//! - `Material::roughness` is *perceptual* roughness r ∈ [0, 1]; the GGX α = r² is applied
//!   by the shading code (`alpha_from_perceptual_roughness`), never here.
//! - Point lights carry a radiant intensity I (W/sr per RGB channel): irradiance at
//!   distance d is I/d². Directional lights carry the irradiance E (W/m²) they give a
//!   surface facing them.

mod builtin;
mod camera;
mod error;
mod material;
mod mesh;

pub use builtin::{builtin_scene, BUILTIN_SCENES, SPHERE_GRID_ROUGHNESS};
pub use camera::Camera;
pub use error::SceneError;
pub use material::{ComplexIor, DiffuseModel, Material};
pub use mesh::{Mesh, Vertex};

use glam::{Mat4, Vec3};

/// A light source.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Radiant intensity `intensity` (W/sr per channel) from `position`.
    Point { position: Vec3, intensity: [f32; 3] },
    /// Parallel light travelling along `direction`, giving irradiance `irradiance`
    /// (W/m² per channel) on a surface facing it.
    Directional {
        direction: Vec3,
        irradiance: [f32; 3],
    },
    /// A point light limited to a cone around `direction` (the direction light travels
    /// along the axis), with full intensity inside `inner_cone` and none outside
    /// `outer_cone` (half-angles, radians), falling off between as KHR_lights_punctual
    /// specifies.
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: [f32; 3],
        inner_cone: f32,
        outer_cone: f32,
    },
}

/// One placed mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    pub mesh: usize,
    pub material: usize,
    pub transform: Mat4,
}

/// Everything one frame shows.
#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub objects: Vec<Object>,
    pub lights: Vec<Light>,
    pub camera: Camera,
    /// Index of refraction of the medium the scene sits in (air ≈ 1.0, water ≈ 1.33);
    /// a material may override it.
    pub outside_ior: f32,
}

fn finite3(v: [f32; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

impl Scene {
    /// The outside-medium IOR that applies to `material`.
    pub fn outside_ior_of(&self, material: &Material) -> f32 {
        material.outside_ior.unwrap_or(self.outside_ior)
    }

    /// Checks every reference and value range; the renderer calls this before uploading.
    pub fn validate(&self) -> Result<(), SceneError> {
        let invalid = |what: String| Err(SceneError::Invalid(what));
        if !(self.outside_ior.is_finite() && self.outside_ior > 0.0) {
            return invalid(format!(
                "outside IOR {} must be a positive number",
                self.outside_ior
            ));
        }
        if u16::try_from(self.materials.len()).is_err() {
            return invalid(format!(
                "{} materials; at most {} fit the G-buffer's 16-bit material index",
                self.materials.len(),
                u16::MAX
            ));
        }
        for (i, mesh) in self.meshes.iter().enumerate() {
            mesh.validate()
                .map_err(|e| SceneError::Invalid(format!("mesh {i} ({}): {e}", mesh.name)))?;
        }
        for material in &self.materials {
            material.validate()?;
        }
        for (i, object) in self.objects.iter().enumerate() {
            if object.mesh >= self.meshes.len() {
                return invalid(format!(
                    "object {i} uses mesh {} of {}",
                    object.mesh,
                    self.meshes.len()
                ));
            }
            if object.material >= self.materials.len() {
                return invalid(format!(
                    "object {i} uses material {} of {}",
                    object.material,
                    self.materials.len()
                ));
            }
            if !object.transform.is_finite() || object.transform.determinant().abs() < 1e-12 {
                return invalid(format!("object {i} has a non-finite or singular transform"));
            }
        }
        for (i, light) in self.lights.iter().enumerate() {
            let ok = match light {
                Light::Point {
                    position,
                    intensity,
                } => {
                    position.is_finite()
                        && finite3(*intensity)
                        && intensity.iter().all(|&x| x >= 0.0)
                }
                Light::Directional {
                    direction,
                    irradiance,
                } => {
                    direction.is_finite()
                        && direction.length_squared() > 0.0
                        && finite3(*irradiance)
                        && irradiance.iter().all(|&x| x >= 0.0)
                }
                Light::Spot {
                    position,
                    direction,
                    intensity,
                    inner_cone,
                    outer_cone,
                } => {
                    position.is_finite()
                        && direction.is_finite()
                        && direction.length_squared() > 0.0
                        && finite3(*intensity)
                        && intensity.iter().all(|&x| x >= 0.0)
                        && *inner_cone >= 0.0
                        && inner_cone < outer_cone
                        && *outer_cone <= std::f32::consts::FRAC_PI_2
                }
            };
            if !ok {
                return invalid(format!(
                    "light {i} needs finite, non-negative power, a finite position or non-zero direction, and (spot) 0 <= inner cone < outer cone <= pi/2"
                ));
            }
        }
        self.camera.validate()
    }
}
