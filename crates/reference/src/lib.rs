//! f64 ground truth for Combustion, from the scene alone: every triangle of a
//! [`combustion_scene::Scene`] placed in world space in f64, in a bounding-volume
//! hierarchy ([`SceneBvh`]), with closest-hit and any-hit ray casts and exact light
//! visibility ([`visibility`]); what the camera's primary rays hit ([`primary`]); and the
//! frame shaded from the scene's own materials, textures and lights with the optics
//! crate's BRDF ([`shading`], with [`texture`]'s f64 filtering); the scene's pose
//! (animations sampled, meshes morphed and skinned) in f64 ([`pose`]).
//!
//! It is the oracle that the renderer's approximations are measured against: shadow
//! maps against exact point-to-light visibility, the rasterised G-buffer against what
//! the primary rays hit, and the rendered frame against the scene shaded in f64 (the
//! G-buffer's storage precision modelled separately, so its share of the error is
//! known). It therefore shares no code with the renderer's GPU path: it reads the CPU
//! scene model and nothing else.
//!
//! Conventions (beyond the scene's own, see [`combustion_scene`]):
//! - Every computation is in f64. A vertex's f32 position and its object's f32
//!   transform are converted to f64 exactly, then the vertex is placed in f64
//!   (`transform * p` with the transform's affine part, as the renderer does).
//! - A [`Ray`] is `origin + t · direction` for t ≥ 0; `direction` need not be unit, so
//!   t is measured in multiples of `direction` (with `direction = to − from`, t = 1 is
//!   `to`).
//! - Hit intervals are open: a hit counts when `t_min < t < t_max`.
//! - Triangles are double-sided for intersection (either face casts a shadow);
//!   [`Hit::normal`] tells the faces apart (counter-clockwise front, the scene's rule).
//! - Nothing panics, on a valid scene or an invalid one: objects naming a mesh that
//!   does not exist, triangles with an index out of range, and triangles whose world
//!   positions are not finite or span no area are left out.
//!
//! # The ray–triangle test
//!
//! Intersection uses the watertight test of Woop, Benthin and Wald ("Watertight
//! Ray/Triangle Intersection", JCGT 2013), in f64. The ray is sheared so that it runs
//! along +z; each vertex is translated and sheared on its own, identically in every
//! triangle that shares it, and the three 2D edge functions are evaluated from those
//! shared values. Two triangles sharing an edge therefore compute that edge's function
//! from the same products, with opposite signs (`a·b − c·d` against `c·d − a·b`, exact
//! negations in floating point), so a ray can never pass between them: it lands in one
//! or both (a vertex's fan likewise). Möller–Trumbore, which computes each triangle's
//! edge tests from its own edge vectors, has no such guarantee; for an oracle whose
//! answer "not blocked" must not come from a crack, watertightness is worth the few
//! extra operations.

#![warn(missing_docs)]

mod bvh;
mod cutout;
pub mod path;
pub mod pose;
pub mod primary;
pub mod shading;
pub mod texture;
pub mod transmission;
mod triangle;
pub mod visibility;

use combustion_scene::Scene;
use glam::{DMat4, DVec3};

pub use triangle::{intersect_triangle, TriangleTest};

/// A ray: the points `origin + t · direction`, t ≥ 0, in world space (metres).
///
/// `direction` need not be unit length: t counts multiples of it. A zero or non-finite
/// direction (or origin) hits nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts (t = 0), world space, metres.
    pub origin: [f64; 3],
    /// The ray's direction, any non-zero length (t is in multiples of it).
    pub direction: [f64; 3],
}

impl Ray {
    /// The ray from `origin` along `direction`.
    pub fn new(origin: [f64; 3], direction: [f64; 3]) -> Ray {
        Ray { origin, direction }
    }

    /// The ray from `from` through `to`: t = 0 at `from`, t = 1 at `to`.
    pub fn through(from: [f64; 3], to: [f64; 3]) -> Ray {
        let direction = (DVec3::from(to) - DVec3::from(from)).to_array();
        Ray {
            origin: from,
            direction,
        }
    }

    /// The point at parameter `t`: `origin + t · direction`.
    pub fn at(&self, t: f64) -> [f64; 3] {
        (DVec3::from(self.origin) + t * DVec3::from(self.direction)).to_array()
    }
}

/// Where a ray first meets the scene ([`SceneBvh::closest_hit`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The ray parameter of the hit (the point is [`Ray::at`]`(t)`).
    pub t: f64,
    /// Index of the hit object in [`Scene::objects`].
    pub object: usize,
    /// Index of the hit triangle within the object's mesh: its vertices are
    /// `mesh.indices[3 · triangle .. 3 · triangle + 3]`.
    pub triangle: usize,
    /// Barycentric coordinates (b1, b2) of the hit: the point is
    /// (1 − b1 − b2)·p0 + b1·p1 + b2·p2, with p0, p1, p2 the triangle's vertices in
    /// index order (so a vertex attribute is interpolated with the same weights).
    pub barycentrics: [f64; 2],
    /// The triangle's unit geometric normal in world space, (p1 − p0) × (p2 − p0)
    /// normalised: the side from which the world-space vertices appear
    /// counter-clockwise, the front by the scene's rule (for an object with a mirroring
    /// transform that is its mesh's back, as the renderer's culling also sees it).
    /// `normal · direction < 0` means the ray hit the front face.
    pub normal: [f64; 3],
}

/// One triangle of the scene in world space, f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldTriangle {
    /// Index of its object in [`Scene::objects`] (for triangles given to
    /// [`SceneBvh::from_triangles`]: whatever the caller set).
    pub object: usize,
    /// Index of the triangle within the object's mesh.
    pub triangle: usize,
    /// Its vertices in world space, in the mesh's index order.
    pub vertices: [[f64; 3]; 3],
}

impl WorldTriangle {
    /// Whether the triangle can be hit at all: finite vertices spanning a non-zero area
    /// (in f64). [`SceneBvh`] keeps only these.
    pub fn is_proper(&self) -> bool {
        let [p0, p1, p2] = self.vertices.map(DVec3::from);
        let n = (p1 - p0).cross(p2 - p0);
        p0.is_finite() && p1.is_finite() && p2.is_finite() && n.is_finite() && n != DVec3::ZERO
    }

    /// The unit geometric normal, (p1 − p0) × (p2 − p0) normalised (zero for a
    /// triangle that is not [proper](WorldTriangle::is_proper)).
    pub fn normal(&self) -> [f64; 3] {
        let [p0, p1, p2] = self.vertices.map(DVec3::from);
        (p1 - p0).cross(p2 - p0).normalize_or_zero().to_array()
    }
}

/// The scene's triangles in world space (f64) in a bounding-volume hierarchy, for exact
/// ray casts.
///
/// Cut-out objects (alphaMode MASK) are hit only where their alpha reaches the cutoff
/// (the texture's level 0 at the hit point; see `docs/gltf.md`, "Alpha modes"), by
/// every cast: primary rays and shadow rays alike.
///
/// Built with a binned surface-area heuristic (16 bins on each axis, leaves of at most 4
/// triangles), nodes flattened into one array; traversal is iterative with a fixed
/// stack, nearer child first. A [`Scene`] is read once: later edits to it are not seen.
#[derive(Clone, Debug)]
pub struct SceneBvh {
    /// The kept triangles, in the hierarchy's leaf order.
    triangles: Vec<WorldTriangle>,
    nodes: Vec<bvh::Node>,
    /// The scene's cut-out objects (alphaMode MASK), whose triangles are hit only where
    /// their alpha reaches the cutoff; `None` without any.
    cutouts: Option<cutout::Cutouts>,
}

impl SceneBvh {
    /// Every object's mesh placed by the object's transform, in f64. Objects naming a
    /// mesh that does not exist, triangles with an index out of range and triangles
    /// that are not [proper](WorldTriangle::is_proper) (non-finite or zero-area) are
    /// left out; nothing panics.
    pub fn new(scene: &Scene) -> SceneBvh {
        Self::of_objects(scene, |_| true)
    }

    /// As [`SceneBvh::new`], of the objects that cast shadows
    /// ([`combustion_scene::Object::casts_shadows`]) and are neither blended (alphaMode
    /// BLEND) nor transmissive (the renderer's forward-pass objects cast no shadow):
    /// what blocks light, for
    /// [`SceneBvh::light_visibility`] and its kin.
    pub fn shadow_casters(scene: &Scene) -> SceneBvh {
        Self::of_objects(scene, |object| {
            object.casts_shadows
                && !scene
                    .materials
                    .get(object.material)
                    .is_some_and(|m| m.is_see_through())
        })
    }

    fn of_objects(scene: &Scene, keep: impl Fn(&combustion_scene::Object) -> bool) -> SceneBvh {
        let cutouts = cutout::Cutouts::of(scene, &keep);
        let mut triangles = Vec::new();
        for (object_index, object) in scene.objects.iter().enumerate() {
            if !keep(object) {
                continue;
            }
            // Points and lines have no surface: no ray hits them.
            let Some(mesh) = scene
                .meshes
                .get(object.mesh)
                .filter(|m| m.topology == combustion_scene::Topology::Triangles)
            else {
                continue;
            };
            let transform: DMat4 = object.transform.as_dmat4();
            // Each vertex is placed once, so triangles sharing it share its exact f64
            // position (the watertight test's premise).
            let world: Vec<[f64; 3]> = mesh
                .vertices
                .iter()
                .map(|v| {
                    transform
                        .transform_point3(DVec3::from(v.position.map(f64::from)))
                        .to_array()
                })
                .collect();
            for (triangle_index, corners) in mesh.indices.chunks_exact(3).enumerate() {
                let vertex = |k: usize| world.get(corners[k] as usize).copied();
                let (Some(p0), Some(p1), Some(p2)) = (vertex(0), vertex(1), vertex(2)) else {
                    continue;
                };
                let triangle = WorldTriangle {
                    object: object_index,
                    triangle: triangle_index,
                    vertices: [p0, p1, p2],
                };
                if triangle.is_proper() {
                    triangles.push(triangle);
                }
            }
        }
        SceneBvh {
            cutouts,
            ..SceneBvh::from_triangles(triangles)
        }
    }

    /// A hierarchy over the given world-space triangles (a synthetic scene); those that
    /// are not [proper](WorldTriangle::is_proper) are left out. [`Hit::object`] and
    /// [`Hit::triangle`] report the triangles' own fields.
    pub fn from_triangles(mut triangles: Vec<WorldTriangle>) -> SceneBvh {
        triangles.retain(WorldTriangle::is_proper);
        let (triangles, nodes) = bvh::build(triangles);
        SceneBvh {
            triangles,
            nodes,
            cutouts: None,
        }
    }

    /// Whether `triangle`'s surface is present at barycentrics `b`: everywhere but in a
    /// cut-out's holes.
    pub(crate) fn surface_present(&self, triangle: &WorldTriangle, b: [f64; 2]) -> bool {
        self.cutouts
            .as_ref()
            .is_none_or(|cutouts| cutouts.present(triangle, b))
    }

    /// How many triangles the hierarchy holds (the scene's proper triangles, one per
    /// object that places them).
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The triangles the hierarchy holds, in its own order (for brute-force checks).
    pub fn triangles(&self) -> &[WorldTriangle] {
        &self.triangles
    }

    /// The world-space box (min, max corners) around every triangle; `None` without
    /// triangles.
    pub fn bounds(&self) -> Option<([f64; 3], [f64; 3])> {
        let mut min = DVec3::INFINITY;
        let mut max = DVec3::NEG_INFINITY;
        for vertex in self.triangles.iter().flat_map(|t| t.vertices) {
            min = min.min(DVec3::from(vertex));
            max = max.max(DVec3::from(vertex));
        }
        (!self.triangles.is_empty()).then(|| (min.to_array(), max.to_array()))
    }

    /// The nearest hit with `t_min < t < t_max`, or `None`. Where several triangles are
    /// hit at exactly the same t (a shared edge, coincident faces), the one with the
    /// smallest (object, triangle) is reported, so the answer does not depend on the
    /// hierarchy's layout.
    pub fn closest_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let (index, t, barycentrics) = bvh::closest(self, ray, t_min, t_max)?;
        let triangle = &self.triangles[index];
        Some(Hit {
            t,
            object: triangle.object,
            triangle: triangle.triangle,
            barycentrics,
            normal: triangle.normal(),
        })
    }

    /// Whether any triangle is hit with `t_min < t < t_max` (stops at the first one
    /// found: the shadow-ray query).
    pub fn any_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        bvh::any(self, ray, t_min, t_max)
    }
}
