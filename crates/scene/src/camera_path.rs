//! Scripted camera paths (`view --camera-path FILE`): keyframes of (time, eye, target),
//! linearly interpolated.

use std::path::Path;

use glam::Vec3;

use crate::Camera;

/// The largest camera path file read: 16 MiB.
pub const MAX_CAMERA_PATH_BYTES: u64 = 16 << 20;

/// A scripted camera: keyframes of (time, eye, target), linearly interpolated.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraPath {
    keys: Vec<(f32, Vec3, Vec3)>,
}

impl CameraPath {
    /// Reads a path file (a regular file of at most [`MAX_CAMERA_PATH_BYTES`], UTF-8):
    /// one keyframe per line, `time_s eye_x eye_y eye_z target_x target_y target_z`; `#`
    /// starts a comment; times strictly increasing. Errors name the file and line.
    pub fn read(path: &Path) -> Result<Self, String> {
        let text = crate::read_text(path, MAX_CAMERA_PATH_BYTES, "a camera path")
            .map_err(|e| format!("{}: cannot read the camera path: {e}", path.display()))?;
        Self::parse(&text).map_err(|e| format!("{}:{e}", path.display()))
    }

    /// Parses a path's text; errors start with the line number. Consecutive keyframes
    /// must be near enough that their differences are finite (an eye at −3e38 then
    /// +3e38 would put every camera between them at infinity).
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut keys: Vec<(f32, Vec3, Vec3)> = Vec::new();
        for (number, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let values: Vec<f32> = line
                .split_whitespace()
                .map(|v| v.parse::<f32>().ok().filter(|x| x.is_finite()))
                .collect::<Option<_>>()
                .ok_or_else(|| format!("{}: not a list of finite numbers", number + 1))?;
            let [t, ex, ey, ez, tx, ty, tz] = values[..] else {
                return Err(format!(
                    "{}: {} numbers; a keyframe is `time eye_x eye_y eye_z target_x target_y target_z`",
                    number + 1,
                    values.len()
                ));
            };
            let (eye, target) = (Vec3::new(ex, ey, ez), Vec3::new(tx, ty, tz));
            if eye == target || !(target - eye).is_finite() {
                return Err(format!(
                    "{}: the eye is at the target, or too far from it",
                    number + 1
                ));
            }
            if let Some(&(last, last_eye, last_target)) = keys.last() {
                if t <= last {
                    return Err(format!("{}: times must increase", number + 1));
                }
                if !((t - last).is_finite()
                    && (eye - last_eye).is_finite()
                    && (target - last_target).is_finite())
                {
                    return Err(format!(
                        "{}: too far from the keyframe before it (the differences of times and positions must be finite)",
                        number + 1
                    ));
                }
            }
            keys.push((t, eye, target));
        }
        if keys.is_empty() {
            return Err("1: no keyframes".into());
        }
        Ok(Self { keys })
    }

    /// The keyframes' times, increasing.
    pub fn times(&self) -> impl Iterator<Item = f32> + '_ {
        self.keys.iter().map(|&(t, _, _)| t)
    }

    /// The camera at `time` (held at the first and last keyframes outside them), with
    /// `base`'s up, field of view and planes.
    pub fn at(&self, time: f32, base: &Camera) -> Camera {
        let i = self.keys.partition_point(|&(t, _, _)| t <= time);
        let (eye, target) = match (i, self.keys.get(i)) {
            (0, _) => (self.keys[0].1, self.keys[0].2),
            (_, None) => {
                let last = self.keys[self.keys.len() - 1];
                (last.1, last.2)
            }
            (_, Some(&(t1, e1, g1))) => {
                let (t0, e0, g0) = self.keys[i - 1];
                // In [0, 1): time lies in [t0, t1), whose width is finite.
                let s = ((time - t0) / (t1 - t0)).clamp(0.0, 1.0);
                // a + (b − a)·s: exactly a where a key repeats (a camera that holds still
                // is the same camera every frame).
                (e0 + (e1 - e0) * s, g0 + (g1 - g0) * s)
            }
        };
        Camera {
            position: eye,
            target,
            ..*base
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The camera a path takes its up, field of view and planes from.
    fn start() -> Camera {
        Camera::framing(None)
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        a.abs_diff_eq(b, 1e-4)
    }

    #[test]
    fn camera_paths_interpolate_and_hold_their_ends() {
        let path =
            CameraPath::parse("# t eye target\n0 0 0 5 0 0 0\n2 4 0 5 4 0 0  # a keyframe\n\n")
                .unwrap();
        let base = start();
        assert!(close(
            path.at(-1.0, &base).position,
            Vec3::new(0.0, 0.0, 5.0)
        ));
        assert!(close(
            path.at(1.0, &base).position,
            Vec3::new(2.0, 0.0, 5.0)
        ));
        assert!(close(path.at(1.0, &base).target, Vec3::new(2.0, 0.0, 0.0)));
        assert!(close(
            path.at(9.0, &base).position,
            Vec3::new(4.0, 0.0, 5.0)
        ));
        assert_eq!(path.at(1.0, &base).vertical_fov, base.vertical_fov);
        assert_eq!(path.times().collect::<Vec<_>>(), [0.0, 2.0]);
    }

    #[test]
    fn bad_camera_paths_name_the_line() {
        for (text, expected) in [
            ("", "1: no keyframes"),
            ("0 0 0 5 0 0 0\n0 1 0 5 0 0 0", "2: times must increase"),
            ("0 0 0 5 0 0", "1: 6 numbers"),
            ("0 0 0 x 0 0 0", "1: not a list of finite numbers"),
            ("0 1 1 1 1 1 1", "1: the eye is at the target"),
            ("0 0 0 inf 0 0 0", "1: not a list of finite numbers"),
            // Finite numbers whose differences are not: every camera between these
            // keyframes would be at infinity (or NaN).
            (
                "0 -3e38 0 0 3e38 0 0",
                "1: the eye is at the target, or too far from it",
            ),
            (
                "0 -3e38 0 0 -3e38 1 0\n1 3e38 0 0 3e38 1 0",
                "2: too far from the keyframe before it",
            ),
            (
                "-3e38 0 0 5 0 0 0\n3e38 0 0 6 0 0 0",
                "2: too far from the keyframe before it",
            ),
        ] {
            let error = CameraPath::parse(text).unwrap_err();
            assert!(error.starts_with(expected), "{text:?}: {error}");
        }
    }

    /// Keyframes as far apart as a path may have them: every camera is finite.
    #[test]
    fn distant_keyframes_give_finite_cameras() {
        let path = CameraPath::parse("-1e38 -1e38 0 0 -1e38 1 0\n1e38 1e38 0 0 1e38 1 0").unwrap();
        for time in [-f32::MAX, -1e38, 0.0, 5e37, 1e38, f32::MAX] {
            let camera = path.at(time, &start());
            assert!(
                camera.position.is_finite() && camera.target.is_finite(),
                "{time}: {camera:?}"
            );
        }
    }
}
