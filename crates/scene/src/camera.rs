use glam::{Mat4, Vec3};

use crate::SceneError;

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view, radians.
    pub vertical_fov: f32,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.position, self.target, self.up)
    }

    /// Projection to Vulkan clip space: depth in [0, 1], y pointing down in framebuffer
    /// coordinates (the y flip is folded in here, once).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let mut p = Mat4::perspective_rh(self.vertical_fov, aspect, self.near, self.far);
        p.y_axis.y = -p.y_axis.y;
        p
    }

    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    pub fn validate(&self) -> Result<(), SceneError> {
        let forward = self.target - self.position;
        let ok = self.position.is_finite()
            && self.target.is_finite()
            && self.up.is_finite()
            && forward.length_squared() > 0.0
            && forward.cross(self.up).length_squared() > 0.0
            && self.vertical_fov > 0.0
            && self.vertical_fov < std::f32::consts::PI
            && self.near > 0.0
            && self.far > self.near
            && self.far.is_finite();
        if ok {
            Ok(())
        } else {
            Err(SceneError::Invalid(format!(
                "camera needs distinct position and target, an up vector not along the view, a field of view in (0, π) and 0 < near < far: {self:?}"
            )))
        }
    }
}
