use glam::{Mat4, Vec3};

use crate::{CameraProblem, SceneError};

/// A perspective camera in world space (right-handed, y up, metres), looking from
/// `position` towards `target`. The horizontal field of view follows from the image's
/// aspect ratio, given when projecting ([`Camera::projection`]).
///
/// Nothing is checked when a camera is built; [`Camera::validate`] (called by
/// [`crate::Scene::validate`]) says whether it gives an image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye point, world space, metres.
    pub position: Vec3,
    /// A point the camera looks at, world space, metres; only the direction from
    /// `position` matters (not the distance), and it must differ from `position`.
    pub target: Vec3,
    /// The world-space direction that appears upwards in the image (any length; it need
    /// not be orthogonal to the view direction, only not along it).
    pub up: Vec3,
    /// Vertical field of view, radians, in (0, π).
    pub vertical_fov: f32,
    /// Distance of the near clipping plane from `position` along the view direction,
    /// metres; above 0.
    pub near: f32,
    /// Distance of the far clipping plane, metres; finite and above `near`.
    pub far: f32,
}

impl Camera {
    /// The view matrix: world space to the camera's right-handed view space, where the
    /// camera sits at the origin looking along −z with +y up.
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.position, self.target, self.up)
    }

    /// Projection to Vulkan clip space: depth in [0, 1], y pointing down in framebuffer
    /// coordinates (the y flip is folded in here, once). `aspect` is the image's width
    /// over its height.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let mut p = Mat4::perspective_rh(self.vertical_fov, aspect, self.near, self.far);
        p.y_axis.y = -p.y_axis.y;
        p
    }

    /// [`Camera::projection`] × [`Camera::view`]: world space to Vulkan clip space.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// Checks that the camera gives an image: finite vectors, distinct position and
    /// target, an up vector off the view direction, a field of view in (0, π) and
    /// 0 < near < far < ∞; the first problem found is a [`SceneError::InvalidCamera`].
    pub fn validate(&self) -> Result<(), SceneError> {
        let forward = self.target - self.position;
        // (NaN compares false: a NaN length or cross product counts as zero.)
        let zero = |x: f32| x.is_nan() || x <= 0.0;
        let problem =
            if !(self.position.is_finite() && self.target.is_finite() && self.up.is_finite()) {
                Some(CameraProblem::NotFinite)
            } else if zero(forward.length_squared()) {
                Some(CameraProblem::NoViewDirection)
            } else if zero(forward.cross(self.up).length_squared()) {
                Some(CameraProblem::UpAlongView)
            } else if !(self.vertical_fov > 0.0 && self.vertical_fov < std::f32::consts::PI) {
                Some(CameraProblem::FieldOfView(self.vertical_fov))
            } else if !(self.near > 0.0 && self.far > self.near && self.far.is_finite()) {
                Some(CameraProblem::ClipPlanes {
                    near: self.near,
                    far: self.far,
                })
            } else {
                None
            };
        match problem {
            Some(problem) => Err(SceneError::InvalidCamera(problem)),
            None => Ok(()),
        }
    }
}
