//! The viewer's camera: orbit around a target, pan, zoom, fly, frame the scene, reset;
//! and scripted camera paths. Pure geometry, no window: every motion takes the elapsed
//! time or the mouse travel, so a run is the same at any frame rate.

use combustion_scene::Camera;
use glam::Vec3;

/// Radians of orbit (or look) per pixel of mouse travel.
const RADIANS_PER_PIXEL: f32 = 0.005;
/// Zoom: the distance shrinks by this factor per wheel step.
const ZOOM_PER_STEP: f32 = 0.9;
/// Flying speed, in distances-to-target per second.
const FLY_SPEED: f32 = 1.0;
/// The pitch stays this far from straight up or down.
const PITCH_LIMIT: f32 = 1.55;
/// Longest step time integrated at once (a stalled frame does not throw the camera).
const MAX_STEP_SECONDS: f32 = 0.1;

/// A camera that orbits `target` at `distance`, from `yaw` (about world up) and `pitch`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point orbited and looked at (world space).
    pub target: Vec3,
    /// Distance from the target to the eye (world units, > 0).
    pub distance: f32,
    /// Angle about the up direction, radians.
    pub yaw: f32,
    /// Elevation above the plane normal to the up direction, radians (kept within ±1.55).
    pub pitch: f32,
    up: Vec3,
    vertical_fov: f32,
    near: f32,
    far: f32,
    /// Where `reset` returns to.
    home: Camera,
}

impl OrbitCamera {
    /// The orbit that reproduces `camera` (its up direction is kept as "world up").
    pub fn new(camera: &Camera) -> Self {
        let up = camera.up.try_normalize().unwrap_or(Vec3::Y);
        let offset = camera.position - camera.target;
        let distance = offset.length().max(1e-6);
        let (x, y, z) = basis(up);
        let d = offset / distance;
        Self {
            target: camera.target,
            distance,
            yaw: d.dot(x).atan2(d.dot(z)),
            pitch: d
                .dot(y)
                .clamp(-1.0, 1.0)
                .asin()
                .clamp(-PITCH_LIMIT, PITCH_LIMIT),
            up,
            vertical_fov: camera.vertical_fov,
            near: camera.near,
            far: camera.far,
            home: *camera,
        }
    }

    /// The unit vector from the target to the eye.
    fn direction(&self) -> Vec3 {
        let (x, y, z) = basis(self.up);
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        (x * sy + z * cy) * cp + y * sp
    }

    /// The camera of the orbit (near and far planes scaled with the distance, so the depth
    /// precision of the start is kept).
    pub fn camera(&self) -> Camera {
        // Near and far follow the distance, keeping the depth precision of the start.
        let scale = self.distance / (self.home.position - self.home.target).length().max(1e-6);
        Camera {
            position: self.target + self.direction() * self.distance,
            target: self.target,
            up: self.up,
            vertical_fov: self.vertical_fov,
            near: self.near * scale,
            far: self.far * scale,
        }
    }

    /// Orbits by mouse travel `dx`, `dy` (pixels): right turns the scene right.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * RADIANS_PER_PIXEL;
        self.pitch = (self.pitch + dy * RADIANS_PER_PIXEL).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// Turns the view about the eye (the target moves): mouse-look while flying.
    pub fn look(&mut self, dx: f32, dy: f32) {
        let eye = self.target + self.direction() * self.distance;
        self.orbit(dx, dy);
        self.target = eye - self.direction() * self.distance;
    }

    /// Moves the target in the view plane by mouse travel (pixels), so that the point
    /// under the cursor follows it: a viewport `height` pixels high spans the field of
    /// view at the target's distance.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        let camera = self.camera();
        let forward = (camera.target - camera.position).normalize_or_zero();
        let right = forward.cross(self.up).normalize_or_zero();
        let up = right.cross(forward);
        let metres_per_pixel =
            2.0 * self.distance * (self.vertical_fov / 2.0).tan() / height.max(1.0);
        self.target += (-right * dx + up * dy) * metres_per_pixel;
    }

    /// Zooms by wheel steps (positive: closer).
    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * ZOOM_PER_STEP.powf(steps)).max(1e-6);
    }

    /// Flies for `seconds` along `motion` in the camera's frame (x right, y up, z
    /// forward; each −1, 0 or 1), at a speed proportional to the distance to the target.
    pub fn fly(&mut self, motion: Vec3, seconds: f32) {
        let camera = self.camera();
        let forward = (camera.target - camera.position).normalize_or_zero();
        let right = forward.cross(self.up).normalize_or_zero();
        let step = seconds.clamp(0.0, MAX_STEP_SECONDS) * FLY_SPEED * self.distance;
        self.target += (right * motion.x + self.up * motion.y + forward * motion.z) * step;
    }

    /// Looks at the middle of `bounds` from far enough for all of it to fit a view of
    /// `aspect` (width / height): the narrower of the two fields of view decides.
    pub fn frame(&mut self, bounds: (Vec3, Vec3), aspect: f32) {
        let (lo, hi) = bounds;
        let radius = ((hi - lo).length() / 2.0).max(1e-3);
        let half_vertical = self.vertical_fov / 2.0;
        let half_horizontal = (half_vertical.tan() * aspect.max(1e-3)).atan();
        self.target = (lo + hi) / 2.0;
        self.distance = radius / half_vertical.min(half_horizontal).sin() * 1.05;
    }

    /// Back to the camera the orbit started from.
    pub fn reset(&mut self) {
        *self = Self::new(&self.home);
    }
}

/// A right-handed basis with `y` = up.
fn basis(up: Vec3) -> (Vec3, Vec3, Vec3) {
    let y = up;
    let helper = if y.z.abs() < 0.9 { Vec3::Z } else { Vec3::X };
    let x = helper.cross(y).normalize();
    let z = x.cross(y);
    (x, y, z)
}

/// Scripted camera paths are the scene crate's ([`combustion_scene::CameraPath`]).
pub use combustion_scene::CameraPath;

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> Camera {
        Camera {
            position: Vec3::new(1.0, 2.0, 6.0),
            target: Vec3::new(0.5, 0.0, 0.0),
            up: Vec3::Y,
            vertical_fov: 0.8,
            near: 0.1,
            far: 100.0,
        }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-4
    }

    #[test]
    fn the_orbit_reproduces_the_camera_it_starts_from() {
        let camera = OrbitCamera::new(&start()).camera();
        assert!(close(camera.position, start().position), "{camera:?}");
        assert!(close(camera.target, start().target));
    }

    #[test]
    fn orbiting_keeps_the_distance_and_reset_returns_home() {
        let mut orbit = OrbitCamera::new(&start());
        orbit.orbit(120.0, -40.0);
        let camera = orbit.camera();
        let d0 = (start().position - start().target).length();
        assert!(((camera.position - camera.target).length() - d0).abs() < 1e-4);
        assert!(!close(camera.position, start().position));
        orbit.reset();
        assert!(close(orbit.camera().position, start().position));
    }

    #[test]
    fn pitch_stops_short_of_the_poles() {
        let mut orbit = OrbitCamera::new(&start());
        orbit.orbit(0.0, 1e6);
        assert!(orbit.pitch <= PITCH_LIMIT);
        let c = orbit.camera();
        assert!((c.position - c.target).normalize().dot(Vec3::Y) < 1.0);
    }

    #[test]
    fn flying_is_frame_rate_independent() {
        let mut one = OrbitCamera::new(&start());
        let mut many = one;
        let forward = Vec3::new(0.0, 0.0, 1.0);
        one.fly(forward, 0.1);
        for _ in 0..10 {
            many.fly(forward, 0.01);
        }
        assert!(close(one.camera().position, many.camera().position));
        // Moved toward the target by 0.1 s × one distance per second.
        let d0 = (start().position - start().target).length();
        let moved = (one.camera().position - start().position).length();
        assert!((moved - 0.1 * d0).abs() < 1e-4, "{moved}");
    }

    #[test]
    fn looking_turns_about_the_eye() {
        let mut orbit = OrbitCamera::new(&start());
        orbit.look(50.0, 10.0);
        let c = orbit.camera();
        assert!(close(c.position, start().position));
        assert!(!close(c.target, start().target));
    }

    #[test]
    fn panning_follows_the_cursor_at_the_target() {
        let mut orbit = OrbitCamera::new(&start());
        let height = 500.0;
        orbit.pan(0.0, height, height);
        // A full viewport height of travel moves the target by the view's height there.
        let d = (start().position - start().target).length();
        let moved = (orbit.target - start().target).length();
        assert!((moved - 2.0 * d * (0.4f32).tan()).abs() < 1e-3, "{moved}");
    }

    #[test]
    fn framing_fits_the_bounds_and_zoom_scales_the_distance() {
        let mut orbit = OrbitCamera::new(&start());
        orbit.frame((Vec3::splat(-2.0), Vec3::splat(2.0)), 1.5);
        assert!(close(orbit.target, Vec3::ZERO));
        let radius = 12f32.sqrt();
        assert!(orbit.distance * (0.4f32).sin() >= radius);
        // A tall window: the horizontal field of view is the narrower one.
        let mut tall = orbit;
        tall.frame((Vec3::splat(-2.0), Vec3::splat(2.0)), 0.5);
        let half_horizontal = ((0.4f32).tan() * 0.5).atan();
        assert!(tall.distance * half_horizontal.sin() >= radius);
        assert!(tall.distance > orbit.distance);
        let before = orbit.distance;
        orbit.zoom(2.0);
        assert!((orbit.distance - before * 0.81).abs() < 1e-4);
    }
}
