/// Why a scene can't be built or used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("unknown built-in scene `{name}`; built-in scenes: {known}")]
    UnknownBuiltin { name: String, known: String },
    #[error("invalid scene: {0}")]
    Invalid(String),
    #[error("environment image {path}: {reason}")]
    EnvironmentImage { path: String, reason: String },
    #[error("invalid camera: {0}")]
    InvalidCamera(CameraProblem),
    #[error("invalid light {index}: {problem}")]
    InvalidLight { index: usize, problem: LightProblem },
}

/// What is wrong with a camera ([`crate::Camera::validate`]).
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum CameraProblem {
    #[error("its position, target or up vector is not finite")]
    NotFinite,
    #[error("its position and target coincide")]
    NoViewDirection,
    #[error("its up vector is zero or along the view direction")]
    UpAlongView,
    #[error("its vertical field of view {0} rad is not in (0, π)")]
    FieldOfView(f32),
    #[error("its near and far planes {near} and {far} are not 0 < near < far < ∞")]
    ClipPlanes { near: f32, far: f32 },
}

/// What is wrong with a light ([`crate::validate_lights`]).
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum LightProblem {
    #[error("its position is not finite")]
    Position,
    #[error("its direction is zero or not finite")]
    Direction,
    #[error("its power (intensity or irradiance) {0:?} is not finite and non-negative")]
    Power([f32; 3]),
    #[error("its range {0} is not finite and above 0")]
    Range(f32),
    #[error("its cone angles {inner} and {outer} rad are not 0 <= inner < outer <= π/2")]
    Cone { inner: f32, outer: f32 },
}
