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

/// The framing camera's elevation above the horizon: 20°, a raised view, so that the
/// top of a model shows and a model lying flat is seen.
pub const FRAMING_ELEVATION: f32 = 20.0 * std::f32::consts::PI / 180.0;

/// The framing camera's azimuth: 30° about +Y from glTF's forward view (the +Z side)
/// towards +X, a three-quarter view that shows a model's front and its right side, as
/// the Khronos sample models' screenshots do.
pub const FRAMING_AZIMUTH: f32 = 30.0 * std::f32::consts::PI / 180.0;

/// The vertical field of view of [`Camera::framing`] and [`Camera::orbiting`]: 45°.
pub const FRAMING_FOV: f32 = std::f32::consts::FRAC_PI_4;

impl Camera {
    /// A three-quarter view of `bounds` (a box in world space; a 2 m box around the
    /// origin without one): from the +Z side (glTF's forward view) turned
    /// [`FRAMING_AZIMUTH`] towards +X and raised [`FRAMING_ELEVATION`] above the horizon,
    /// looking at its centre, far enough for the box's bounding sphere to fill the 45°
    /// field of view. A box flat along Y (a floor, a terrain grid: under 1 % of its
    /// largest extent high), which a low view would see almost edge-on, is seen from 45°
    /// above instead (turned as well). The importer's camera for files without one.
    pub fn framing(bounds: Option<(Vec3, Vec3)>) -> Camera {
        let size = bounds.map_or(Vec3::ONE, |(lo, hi)| hi - lo);
        let flat_along_y = size.y < 0.01 * size.max_element();
        let elevation = if flat_along_y {
            std::f32::consts::FRAC_PI_4
        } else {
            FRAMING_ELEVATION
        };
        Self::orbiting(bounds, FRAMING_AZIMUTH, elevation, 1.0)
    }

    /// A camera orbiting the centre of `bounds` (as [`Camera::framing`]) and looking at
    /// it: `azimuth` radians about +Y from the +Z side towards +X, `elevation` radians
    /// above the horizon (within ±π/2, exclusive), at `distance` times the framing
    /// distance (where the box's bounding sphere fills the 45° field of view, with 5 %
    /// to spare). Near and far planes enclose the sphere (near at least a thousandth of
    /// the distance, for a camera inside it).
    pub fn orbiting(
        bounds: Option<(Vec3, Vec3)>,
        azimuth: f32,
        elevation: f32,
        distance: f32,
    ) -> Camera {
        let (lo, hi) = bounds.unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
        let centre = (lo + hi) / 2.0;
        // Any size from a millimetre to beyond 10 km frames the same way.
        let radius = ((hi - lo).length() / 2.0).max(1e-6);
        let distance = radius / (FRAMING_FOV / 2.0).sin() * 1.05 * distance;
        let direction = Vec3::new(
            elevation.cos() * azimuth.sin(),
            elevation.sin(),
            elevation.cos() * azimuth.cos(),
        );
        Camera {
            position: centre + direction * distance,
            target: centre,
            up: Vec3::Y,
            vertical_fov: FRAMING_FOV,
            near: (distance - radius).max(distance * 1e-3),
            far: distance + radius * 2.0,
        }
    }

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

#[cfg(test)]
mod tests {
    use super::*;

    /// Framing is the orbit at the framing azimuth and elevation (45° above a flat box); an orbit's eye is at the same distance from the centre whatever its
    /// angles, on the +X side at azimuth 90°, above at positive elevations; the box's
    /// bounding sphere lies between the near and far planes; each camera validates.
    #[test]
    fn orbits_circle_the_box_at_the_framing_distance() {
        let bounds = Some((Vec3::new(-1.0, 0.0, -2.0), Vec3::new(3.0, 2.0, 0.0)));
        let centre = Vec3::new(1.0, 1.0, -1.0);
        let radius = Vec3::new(4.0, 2.0, 2.0).length() / 2.0;
        let framing = Camera::framing(bounds);
        assert_eq!(
            framing,
            Camera::orbiting(bounds, FRAMING_AZIMUTH, FRAMING_ELEVATION, 1.0)
        );
        let distance = (framing.position - centre).length();
        assert!((distance - radius / (FRAMING_FOV / 2.0).sin() * 1.05).abs() < 1e-4);
        for (azimuth, elevation) in [(90f32, 0f32), (-30.0, 60.0), (200.0, -45.0)] {
            let camera =
                Camera::orbiting(bounds, azimuth.to_radians(), elevation.to_radians(), 1.0);
            let eye = camera.position - centre;
            assert!(
                (eye.length() - distance).abs() < 1e-4,
                "{azimuth} {elevation}"
            );
            assert!((eye.y / distance - elevation.to_radians().sin()).abs() < 1e-5);
            assert_eq!(camera.target, centre);
            assert!(camera.near <= distance - radius + 1e-4 && camera.far >= distance + radius);
            camera.validate().unwrap();
        }
        let side = Camera::orbiting(bounds, 90f32.to_radians(), 0.0, 2.0).position - centre;
        assert!((side - Vec3::X * 2.0 * distance).length() < 1e-3, "{side}");
        let flat = Some((Vec3::new(-5.0, 0.0, -5.0), Vec3::new(5.0, 0.01, 5.0)));
        assert_eq!(
            Camera::framing(flat),
            Camera::orbiting(flat, FRAMING_AZIMUTH, std::f32::consts::FRAC_PI_4, 1.0)
        );
    }
}
