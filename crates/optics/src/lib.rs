//! Reference optics for Combustion (docs: written after measurement).

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod brdf;
pub mod diffuse;
pub mod fresnel;
pub mod microfacet;
pub mod real;
pub mod vec3;

pub use brdf::{brdf_evaluate, BrdfInputs, DiffuseModel, UnknownDiffuseModel};
pub use real::Real;
pub use vec3::{ShadingFrame, Vec3};

/// Smallest GGX/Beckmann α.
pub const ALPHA_MIN: f64 = 1.0e-3;
/// Smallest cosine divided by.
pub const COS_MIN: f64 = 1.0e-6;
/// Smallest IOR.
pub const ETA_MIN: f64 = 1.0e-4;
/// Largest IOR and k.
pub const ETA_MAX: f64 = 1.0e4;
