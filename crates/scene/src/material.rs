use crate::SceneError;

/// Which diffuse BRDF the dielectric part of a material uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u32)]
pub enum DiffuseModel {
    /// ρ/π.
    #[default]
    Lambert = 0,
    /// Oren–Nayar 1994, qualitative model.
    OrenNayarQualitative = 1,
    /// Oren–Nayar 1994, full model with interreflection.
    OrenNayarFull = 2,
}

/// A complex index of refraction η + ik per RGB channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComplexIor {
    pub eta: [f32; 3],
    pub k: [f32; 3],
}

/// A surface material: the per-pixel factors the G-buffer stores (base colour,
/// metalness, roughness, anisotropy) and the optical constants the lighting pass reads
/// from the material table.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Linear RGB albedo of the dielectric part.
    pub base_color: [f32; 3],
    /// 0 = dielectric, 1 = conductor; in between blends the two linearly.
    pub metalness: f32,
    /// Perceptual roughness r ∈ [0, 1] (α = r²).
    pub roughness: f32,
    /// Anisotropy strength ∈ [0, 1] (KHR_materials_anisotropy).
    pub anisotropy_strength: f32,
    /// Rotation of the anisotropy direction from the mesh tangent towards the bitangent, radians.
    pub anisotropy_rotation: f32,
    /// Real IOR of the dielectric part.
    pub dielectric_ior: f32,
    /// Complex IOR of the conductor part.
    pub conductor: ComplexIor,
    /// Overrides the scene's outside-medium IOR for this material.
    pub outside_ior: Option<f32>,
    /// Polarisation weight: 0 = s (perpendicular), 1 = p (parallel), 0.5 = unpolarised.
    pub polarisation_weight: f32,
    pub diffuse_model: DiffuseModel,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".into(),
            base_color: [0.8, 0.8, 0.8],
            metalness: 0.0,
            roughness: 0.5,
            anisotropy_strength: 0.0,
            anisotropy_rotation: 0.0,
            dielectric_ior: 1.5,
            // A conductor part that is never used while metalness is 0.
            conductor: ComplexIor {
                eta: [1.0; 3],
                k: [0.0; 3],
            },
            outside_ior: None,
            polarisation_weight: 0.5,
            diffuse_model: DiffuseModel::Lambert,
        }
    }
}

impl Material {
    pub fn validate(&self) -> Result<(), SceneError> {
        let unit = |x: f32| (0.0..=1.0).contains(&x);
        let positive = |x: f32| x.is_finite() && x > 0.0;
        let problem = if !self.base_color.iter().all(|&c| unit(c)) {
            Some("base colour must lie in [0, 1]")
        } else if !unit(self.metalness) {
            Some("metalness must lie in [0, 1]")
        } else if !unit(self.roughness) {
            Some("roughness must lie in [0, 1]")
        } else if !unit(self.anisotropy_strength) {
            Some("anisotropy strength must lie in [0, 1]")
        } else if !self.anisotropy_rotation.is_finite() {
            Some("anisotropy rotation must be finite")
        } else if !positive(self.dielectric_ior) {
            Some("dielectric IOR must be positive")
        } else if !self.conductor.eta.iter().all(|&x| positive(x)) {
            Some("conductor η must be positive")
        } else if !self.conductor.k.iter().all(|&x| x.is_finite() && x >= 0.0) {
            Some("conductor k must be non-negative")
        } else if !self.outside_ior.is_none_or(positive) {
            Some("outside IOR must be positive")
        } else if !unit(self.polarisation_weight) {
            Some("polarisation weight must lie in [0, 1]")
        } else {
            None
        };
        match problem {
            Some(p) => Err(SceneError::Invalid(format!(
                "material `{}`: {p}",
                self.name
            ))),
            None => Ok(()),
        }
    }
}
