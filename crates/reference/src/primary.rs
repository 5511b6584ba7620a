//! What the camera sees, from the scene alone: the primary ray through each pixel's
//! centre, cast in f64 against the scene's triangles, and the surface it hits — its
//! object, world position and interpolated shading normal. The first half of an
//! end-to-end reference: it checks the renderer's camera, rasterisation, depth and
//! normals (its G-buffer) without reading anything the renderer computed.
//!
//! The camera's rays follow [`Camera`]'s documented meaning (an eye at `position`
//! looking at `target`, `up` upwards in the image, `vertical_fov` across the image's
//! height, pixels square), computed here in f64, not through its matrices. Hits nearer
//! than the near plane or beyond the far plane (along the view direction) are not
//! seen, as the rasteriser clips them.

use combustion_scene::{Camera, Scene};
use glam::{DMat3, DVec3};

use crate::{Ray, SceneBvh};

/// The surface a pixel's primary ray hits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimaryHit {
    /// The hit object's index in [`Scene::objects`].
    pub object: usize,
    /// The hit triangle within the object's mesh.
    pub triangle: usize,
    /// The hit's barycentric coordinates (b1, b2) on the triangle (see [`crate::Hit`]),
    /// the weights a vertex attribute is interpolated with.
    pub barycentrics: [f64; 2],
    /// The hit point, world space, metres.
    pub position: [f64; 3],
    /// The unit shading normal there: the mesh's vertex normals interpolated with the
    /// hit's barycentrics and carried to world space by the inverse transpose of the
    /// object's transform (f64), not flipped towards the eye.
    pub normal: [f64; 3],
    /// The triangle's unit geometric normal (front by the scene's winding rule).
    pub geometric_normal: [f64; 3],
    /// The hit's distance from the eye along the view direction, metres.
    pub view_depth: f64,
}

/// The ray from the eye through the point (`x`, `y`) of a `width` × `height` image
/// (pixel units from the top-left corner, y down; a pixel's centre is at + 0.5) of
/// `camera`. Its direction has unit length along the view direction, so the ray's t is
/// the distance along it.
pub fn camera_ray(camera: &Camera, width: u32, height: u32, x: f64, y: f64) -> Ray {
    let eye = camera.position.as_dvec3();
    let forward = (camera.target.as_dvec3() - eye).normalize();
    let right = forward.cross(camera.up.as_dvec3()).normalize();
    let up = right.cross(forward);
    let half_height = (f64::from(camera.vertical_fov) * 0.5).tan();
    let half_width = half_height * f64::from(width) / f64::from(height);
    let ndc_x = 2.0 * x / f64::from(width) - 1.0;
    let ndc_y = 1.0 - 2.0 * y / f64::from(height);
    let direction = forward + right * (ndc_x * half_width) + up * (ndc_y * half_height);
    Ray::new(eye.to_array(), direction.to_array())
}

/// What the primary ray through pixel (`x`, `y`)'s centre hits in `scene` (whose
/// triangles `bvh` holds: [`SceneBvh::new`]), between the camera's near and far planes;
/// `None` where it hits nothing there. The back face of a triangle whose material is
/// not double-sided is not seen (the ray goes on past it), as glTF allows a renderer
/// to cull it and Combustion's rasteriser does. Blended surfaces (alphaMode BLEND) are
/// passed through: this is the opaque surface behind them ([`primary_layers`] gives
/// them too).
pub fn primary_hit(
    scene: &Scene,
    bvh: &SceneBvh,
    width: u32,
    height: u32,
    x: u32,
    y: u32,
) -> Option<PrimaryHit> {
    primary_layers(scene, bvh, width, height, x, y).opaque
}

/// Everything the primary ray through a pixel's centre meets: the blended surfaces
/// (alphaMode BLEND) and transmissive ones (KHR_materials_transmission) in front of the
/// first opaque one, nearest first, and that one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PrimaryLayers {
    /// The blended surfaces the ray passes through before `opaque` (or before the far
    /// plane), nearest first; each front face, or either face of a double-sided
    /// material.
    pub blended: Vec<PrimaryHit>,
    /// The first opaque surface ([`primary_hit`]'s answer), `None` if there is none.
    pub opaque: Option<PrimaryHit>,
}

/// [`primary_hit`], with the blended surfaces in front of it.
pub fn primary_layers(
    scene: &Scene,
    bvh: &SceneBvh,
    width: u32,
    height: u32,
    x: u32,
    y: u32,
) -> PrimaryLayers {
    let camera = &scene.camera;
    let ray = camera_ray(
        camera,
        width,
        height,
        f64::from(x) + 0.5,
        f64::from(y) + 0.5,
    );
    let (mut t_min, far) = (f64::from(camera.near), f64::from(camera.far));
    let mut layers = PrimaryLayers::default();
    while let Some((hit, material)) = next_seen(scene, bvh, &ray, &mut t_min, far) {
        let seen = seen_surface(scene, &ray, &hit);
        // Blended and transmissive surfaces: the renderer draws them over the opaque
        // one (its forward pass), which is what its G-buffer holds.
        if material.is_see_through() {
            layers.blended.extend(seen);
            continue;
        }
        layers.opaque = seen;
        break;
    }
    layers
}

/// The next surface `ray` meets with `*t_min < t < far`, and its material: back faces
/// of single-sided materials are passed (glTF lets a renderer cull them, and the
/// rasteriser does). `*t_min` moves past the hit, so a further call finds the one
/// after; `None` when there is none (or an object or material that does not exist).
pub(crate) fn next_seen<'s>(
    scene: &'s Scene,
    bvh: &SceneBvh,
    ray: &Ray,
    t_min: &mut f64,
    far: f64,
) -> Option<(crate::Hit, &'s combustion_scene::Material)> {
    loop {
        let hit = bvh.closest_hit(ray, *t_min, far)?;
        // The hit interval is open: a further cast starts just past this triangle.
        *t_min = hit.t;
        let material = scene
            .materials
            .get(scene.objects.get(hit.object)?.material)?;
        let back = DVec3::from(hit.normal).dot(DVec3::from(ray.direction)) > 0.0;
        if !back || material.double_sided {
            return Some((hit, material));
        }
    }
}

/// The surface `hit` (on `ray`) shows: its interpolated shading normal and position
/// (`view_depth`: the hit's t, a distance for a camera ray or any unit direction).
pub(crate) fn seen_surface(scene: &Scene, ray: &Ray, hit: &crate::Hit) -> Option<PrimaryHit> {
    let object = scene.objects.get(hit.object)?;
    let mesh = scene.meshes.get(object.mesh)?;
    let corner = |k: usize| -> Option<DVec3> {
        let index = *mesh.indices.get(3 * hit.triangle + k)? as usize;
        Some(DVec3::from(mesh.vertices.get(index)?.normal.map(f64::from)))
    };
    let [b1, b2] = hit.barycentrics;
    let local = corner(0)? * (1.0 - b1 - b2) + corner(1)? * b1 + corner(2)? * b2;
    let normal_matrix = DMat3::from_mat4(object.transform.as_dmat4())
        .inverse()
        .transpose();
    let normal = (normal_matrix * local).normalize_or_zero();
    Some(PrimaryHit {
        object: hit.object,
        triangle: hit.triangle,
        barycentrics: hit.barycentrics,
        position: ray.at(hit.t),
        normal: normal.to_array(),
        geometric_normal: hit.normal,
        view_depth: hit.t,
    })
}

/// [`primary_hit`] for every pixel of a `width` × `height` image, row-major from the
/// top-left, on up to `threads` threads.
pub fn primary_hits(
    scene: &Scene,
    bvh: &SceneBvh,
    width: u32,
    height: u32,
    threads: usize,
) -> Vec<Option<PrimaryHit>> {
    per_pixel(width, height, threads, |x, y| {
        primary_hit(scene, bvh, width, height, x, y)
    })
}

/// `f(x, y)` for every pixel of a `width` × `height` image, row-major from the
/// top-left, rows split between up to `threads` threads.
pub fn per_pixel<T: Send>(
    width: u32,
    height: u32,
    threads: usize,
    f: impl Fn(u32, u32) -> T + Sync,
) -> Vec<T> {
    let rows: Vec<u32> = (0..height).collect();
    let per_thread = rows.len().div_ceil(threads.max(1)).max(1);
    let f = &f;
    std::thread::scope(|scope| {
        let handles: Vec<_> = rows
            .chunks(per_thread)
            .map(|chunk| {
                scope.spawn(move || {
                    chunk
                        .iter()
                        .flat_map(|&y| (0..width).map(move |x| f(x, y)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a per-pixel thread panicked"))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// The ray through the image's centre runs along the view direction, and the rays
    /// through the image's top and bottom edges' centres are half the vertical field
    /// of view from it, up and down.
    #[test]
    fn camera_rays_span_the_field_of_view() {
        let camera = Camera {
            position: Vec3::new(1.0, 2.0, 3.0),
            target: Vec3::new(1.0, 2.0, -5.0),
            up: Vec3::Y,
            vertical_fov: 0.8,
            near: 0.1,
            far: 100.0,
        };
        let centre = camera_ray(&camera, 200, 100, 100.0, 50.0);
        assert!((DVec3::from(centre.direction) - DVec3::NEG_Z).length() < 1e-12);
        let top = DVec3::from(camera_ray(&camera, 200, 100, 100.0, 0.0).direction).normalize();
        let bottom = DVec3::from(camera_ray(&camera, 200, 100, 100.0, 100.0).direction).normalize();
        assert!((top.angle_between(DVec3::NEG_Z) - 0.4).abs() < 1e-6 && top.y > 0.0);
        assert!((bottom.angle_between(DVec3::NEG_Z) - 0.4).abs() < 1e-6 && bottom.y < 0.0);
        let right = DVec3::from(camera_ray(&camera, 200, 100, 200.0, 50.0).direction);
        assert!(right.x > 0.0, "image right is the camera's right");
    }
}
