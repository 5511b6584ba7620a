//! Why a valid scene may still render as an empty picture: no object inside the camera's
//! view, or objects so far from the origin that f32 positions cannot resolve them.
//! [`Scene::view_warnings`] finds both before anything is rendered; the command line
//! prints them as warnings.

use glam::{DVec4, Vec3};

use crate::{box_corners, Scene};

/// Positions are single precision on the GPU: an object spanning fewer than this many
/// representable steps (f32 spacing at its distance from the origin or the camera's,
/// whichever is further) cannot keep its shape: its vertices collapse onto a few points.
pub const MIN_PRECISION_STEPS: f32 = 256.0;

/// A reason a frame of a scene may show nothing, or not what the scene holds.
#[derive(Clone, Debug, PartialEq)]
pub enum ViewWarning {
    /// No object's box reaches into the camera's view (behind it, beside it, beyond its
    /// far plane, or a field of view too narrow to hold any of them).
    NothingInView {
        /// The objects the scene has.
        objects: usize,
    },
    /// An object spans fewer than [`MIN_PRECISION_STEPS`] steps of f32 at its distance.
    BeyondPrecision {
        /// The object's index.
        object: usize,
        /// Its size (the box's diagonal), metres.
        size: f32,
        /// Its distance from the origin, or the camera's, the larger, metres.
        distance: f32,
        /// The spacing of f32 values there, metres.
        spacing: f32,
    },
    /// The camera's field of view spans, at the nearest object in view, fewer than
    /// [`MIN_PRECISION_STEPS`] steps of f32 positions there: the frame cannot resolve it
    /// (its triangles' clip coordinates grow past what the rasteriser keeps).
    NarrowerThanPrecision {
        /// The vertical field of view, radians.
        fov: f32,
        /// How much of the scene it spans at that object's depth, metres.
        span: f32,
        /// The object's depth along the view, metres.
        distance: f32,
        /// The spacing of f32 positions there, metres.
        spacing: f32,
    },
}

impl std::fmt::Display for ViewWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let short = |x: f32| format!("{x:.3e}");
        match self {
            Self::NothingInView { objects } => write!(
                f,
                "none of the scene's {objects} objects is in the camera's view; the image shows the background alone"
            ),
            Self::BeyondPrecision {
                object,
                size,
                distance,
                spacing,
            } => write!(
                f,
                "object {object} is {} m across but {} m from the origin or the camera, where 32-bit positions are {} m apart; it cannot be drawn faithfully (move the scene or the camera nearer the origin)",
                short(*size),
                short(*distance),
                short(*spacing)
            ),
            Self::NarrowerThanPrecision {
                fov,
                span,
                distance,
                spacing,
            } => write!(
                f,
                "the camera's field of view of {} rad spans {} m at the nearest object in view ({} m away), where 32-bit positions are {} m apart; the frame cannot resolve it (widen the field of view)",
                short(*fov),
                short(*span),
                short(*distance),
                short(*spacing)
            ),
        }
    }
}

impl Scene {
    /// What may make a frame of this scene, seen by its camera in an image of width over
    /// height `aspect`, show nothing or not what the scene holds (see [`ViewWarning`]):
    /// at most one [`ViewWarning::NothingInView`] (a scene without objects gives none:
    /// it has nothing to show), then each object beyond precision. The objects are taken
    /// at rest; the test is conservative (a box partly in view counts as in view).
    pub fn view_warnings(&self, aspect: f32) -> Vec<ViewWarning> {
        let mut warnings = Vec::new();
        let bounds = self.object_bounds();
        let boxes: Vec<&(Vec3, Vec3)> = bounds.iter().flatten().collect();
        // Clip space in f64: a field of view of 1e-20 scales by 2e20, a far box by more.
        let clip = self.camera.view_projection(aspect).as_dmat4();
        let in_view = |(lo, hi): &&(Vec3, Vec3)| {
            let corners: Vec<DVec4> = box_corners(*lo, *hi)
                .iter()
                .map(|c| clip * c.as_dvec3().extend(1.0))
                .collect();
            // Outside when every corner is beyond one plane of the view volume.
            let planes: [fn(&DVec4) -> bool; 6] = [
                |c| c.x < -c.w,
                |c| c.x > c.w,
                |c| c.y < -c.w,
                |c| c.y > c.w,
                |c| c.z < 0.0,
                |c| c.z > c.w,
            ];
            !planes.iter().any(|beyond| corners.iter().all(beyond))
        };
        if !boxes.is_empty() && !boxes.iter().any(in_view) {
            warnings.push(ViewWarning::NothingInView {
                objects: self.objects.len(),
            });
        }
        let seen = boxes.iter().filter(|b| in_view(b)).copied();
        if let Some(narrow) = self.narrower_than_precision(seen) {
            warnings.push(narrow);
        }
        let camera_distance = self.camera.position.abs().max_element();
        for (object, bounds) in bounds.iter().enumerate() {
            let Some((lo, hi)) = *bounds else { continue };
            let size = (hi - lo).length();
            let distance = lo.abs().max(hi.abs()).max_element().max(camera_distance);
            let spacing = distance * f32::EPSILON;
            if size < MIN_PRECISION_STEPS * spacing {
                warnings.push(ViewWarning::BeyondPrecision {
                    object,
                    size,
                    distance,
                    spacing,
                });
            }
        }
        warnings
    }

    /// [`ViewWarning::NarrowerThanPrecision`] for the nearest of the boxes in view (by
    /// its nearest corner's depth, at least the near plane's), if the view is that narrow
    /// there.
    fn narrower_than_precision<'a>(
        &self,
        in_view: impl Iterator<Item = &'a (Vec3, Vec3)>,
    ) -> Option<ViewWarning> {
        let camera = &self.camera;
        let along = (camera.target - camera.position).normalize_or_zero();
        let (distance, reach) = in_view
            .map(|(lo, hi)| {
                let corners = box_corners(*lo, *hi);
                let depth = corners
                    .iter()
                    .map(|c| (*c - camera.position).dot(along))
                    .fold(f32::INFINITY, f32::min)
                    .max(camera.near);
                let reach = corners
                    .iter()
                    .map(|c| c.abs().max_element())
                    .fold(0.0, f32::max);
                (depth, reach)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))?;
        let fov = camera.vertical_fov;
        let span = 2.0 * distance * (0.5 * fov).tan();
        let spacing = reach.max(camera.position.abs().max_element()) * f32::EPSILON;
        (span < MIN_PRECISION_STEPS * spacing).then_some(ViewWarning::NarrowerThanPrecision {
            fov,
            span,
            distance,
            spacing,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{builtin_scene, Camera};

    fn spheres() -> Scene {
        builtin_scene("spheres").expect("a built-in scene")
    }

    #[test]
    fn a_framed_scene_has_no_view_warning() {
        assert_eq!(spheres().view_warnings(16.0 / 9.0), []);
    }

    #[test]
    fn a_camera_looking_away_or_through_a_pinhole_sees_nothing() {
        let mut away = spheres();
        away.camera.target = away.camera.position + (away.camera.position - away.camera.target);
        // Aimed 1.5 bounding-sphere radii beside the scene's centre: the scene fills the
        // side of a 45° view, and is out of a view of 1e-20 radians.
        let scene = spheres();
        let (lo, hi) = scene.world_bounds().expect("objects");
        let framed = Camera::framing(Some((lo, hi)));
        let right = (framed.target - framed.position)
            .cross(framed.up)
            .normalize();
        let beside = Camera {
            target: framed.target + right * 1.5 * (hi - lo).length() / 2.0,
            ..framed
        };
        let mut wide = spheres();
        wide.camera = beside;
        assert_eq!(wide.view_warnings(1.0), []);
        let mut pinhole = spheres();
        pinhole.camera = Camera {
            vertical_fov: 1e-20,
            ..beside
        };
        for scene in [away, pinhole] {
            let objects = scene.objects.len();
            assert_eq!(
                scene.view_warnings(1.0),
                [ViewWarning::NothingInView { objects }]
            );
        }
    }

    /// A camera aimed at the scene through a field of view of 1e-20 rad (glTF allows
    /// any yfov above 0) sees objects it cannot resolve: said, where 45° says nothing.
    #[test]
    fn a_field_of_view_narrower_than_precision_is_said() {
        let mut scene = spheres();
        scene.camera = Camera::framing(scene.world_bounds());
        assert_eq!(scene.view_warnings(1.0), []);
        for (fov, narrow) in [(1e-20f32, true), (1e-9, true), (1e-3, false)] {
            scene.camera.vertical_fov = fov;
            let warnings = scene.view_warnings(1.0);
            let said = warnings
                .iter()
                .any(|w| matches!(w, ViewWarning::NarrowerThanPrecision { .. }));
            assert_eq!(said, narrow, "{fov}: {warnings:?}");
            if narrow {
                let message = warnings[0].to_string();
                assert!(
                    message.contains("field of view of") && message.contains("widen"),
                    "{message}"
                );
            }
        }
    }

    #[test]
    fn an_object_a_hundred_million_metres_out_is_beyond_precision() {
        let mut scene = spheres();
        let far = glam::Mat4::from_translation(Vec3::new(1e8, 0.0, 0.0));
        scene.objects[0].transform = far * scene.objects[0].transform;
        scene.camera = Camera::framing(scene.world_bounds());
        let warnings = scene.view_warnings(1.0);
        assert!(
            warnings.iter().any(|w| matches!(
                w,
                ViewWarning::BeyondPrecision { object: 0, spacing, .. } if *spacing > 8.0
            )),
            "{warnings:?}"
        );
        // Every object, once the camera frames the far one from 1e8 m out.
        assert_eq!(warnings.len(), scene.objects.len(), "{warnings:?}");
        let message = warnings[0].to_string();
        assert!(
            message.contains("where 32-bit positions are 1."),
            "{message}"
        );
    }
}
