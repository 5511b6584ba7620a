/// Why a scene can't be built or used. Its message (`Display`) names what is wrong, for
/// the user.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// [`crate::builtin_scene`] was asked for a name it does not know.
    #[error("unknown built-in scene `{name}`; built-in scenes: {known}")]
    UnknownBuiltin {
        /// The name asked for.
        name: String,
        /// The known names ([`crate::BUILTIN_SCENES`]), comma-separated.
        known: String,
    },
    /// A value or reference of the scene is out of range ([`crate::Scene::validate`]):
    /// the message names the mesh, material, object or value and the rule it breaks.
    #[error("invalid scene: {0}")]
    Invalid(String),
    /// An environment image could not be read, or its size or values are out of range
    /// ([`crate::EnvironmentImage::load`], [`crate::EnvironmentImage::validate`]).
    #[error("environment image {path}: {reason}")]
    EnvironmentImage {
        /// The file (or the image's name, for an image built in memory).
        path: String,
        /// What is wrong.
        reason: String,
    },
    /// The camera gives no image ([`crate::Camera::validate`]).
    #[error("invalid camera: {0}")]
    InvalidCamera(CameraProblem),
    /// A light's values are out of range ([`crate::validate_lights`]).
    #[error("invalid light {index}: {problem}")]
    InvalidLight {
        /// Index of the light in the list checked.
        index: usize,
        /// What is wrong with it.
        problem: LightProblem,
    },
}

/// What is wrong with a camera ([`crate::Camera::validate`]).
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum CameraProblem {
    /// `position`, `target` or `up` has a NaN or infinite component.
    #[error("its position, target or up vector is not finite")]
    NotFinite,
    /// `position` and `target` are the same point: there is no view direction.
    #[error("its position and target coincide")]
    NoViewDirection,
    /// `up` is zero or parallel to the view direction: the image's roll is undefined.
    #[error("its up vector is zero or along the view direction")]
    UpAlongView,
    /// The vertical field of view (radians, the value given) is not in (0, π).
    #[error("its vertical field of view {} rad is not in (0, π)", readable(*.0))]
    FieldOfView(f32),
    /// The clipping planes are not 0 < near < far < ∞.
    #[error("its near and far planes {} and {} are not 0 < near < far < ∞", readable(*.near), readable(*.far))]
    ClipPlanes {
        /// The near plane's distance given.
        near: f32,
        /// The far plane's distance given.
        far: f32,
    },
}

/// What is wrong with a light ([`crate::validate_lights`]).
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum LightProblem {
    /// A point or spot light's position has a NaN or infinite component.
    #[error("its position is not finite")]
    Position,
    /// A directional or spot light's direction is zero or not finite.
    #[error("its direction is zero or not finite")]
    Direction,
    /// The intensity (point, spot) or irradiance (directional) given, per channel, is
    /// negative, not finite, or above [`crate::MAX_RADIANCE`].
    #[error("its power (intensity or irradiance) {} {} {} is not between 0 and {max:e}", readable(.0[0]), readable(.0[1]), readable(.0[2]), max = crate::MAX_RADIANCE)]
    Power([f32; 3]),
    /// The range given is not finite and above 0.
    #[error("its range {} is not finite and above 0", readable(*.0))]
    Range(f32),
    /// A point or spot light's radius (metres) is not finite, or outside
    /// 0 ..= [`crate::MAX_LIGHT_RADIUS`].
    #[error("its radius {} m is not finite and between 0 and {max}", readable(*.0), max = crate::MAX_LIGHT_RADIUS)]
    Radius(f32),
    /// A directional light's angular diameter (radians) is not finite, or outside
    /// 0 ..= [`crate::MAX_ANGULAR_DIAMETER`].
    #[error("its angular diameter {} rad is not finite and between 0 and {max}", readable(*.0), max = crate::MAX_ANGULAR_DIAMETER)]
    AngularDiameter(f32),
    /// A spot light's cone half-angles (radians) are not 0 ≤ inner < outer ≤ π/2.
    #[error("its cone angles {} and {} rad are not 0 <= inner < outer <= π/2", readable(*.inner), readable(*.outer))]
    Cone {
        /// The inner half-angle given.
        inner: f32,
        /// The outer half-angle given.
        outer: f32,
    },
}

/// Numbers in messages: six significant digits at most, exponent form for very large or
/// small magnitudes (never 39 digits), the same in every crate.
pub(crate) use combustion_optics::{readable, shortened};
