//! CPU scene model of Combustion: meshes, materials, lights and a camera. No Vulkan here.
//!
//! Conventions (one place for each):
//! - Right-handed world space, y up; lengths in metres.
//! - Colours are linear RGB.
//! - `Material::roughness` is *perceptual* roughness r ∈ [0, 1]; the GGX α = r² is applied
//!   by the shading code (`alpha_from_perceptual_roughness`), never here.
//! - Point lights carry a radiant intensity I (W/sr per RGB channel): irradiance at
//!   distance d is I/d². Directional lights carry the irradiance E (W/m²) they give a
//!   surface facing them.
//! - Angles are radians.
//! - Transforms are glam `Mat4`s (column-major, points transformed as `m * p`), from an
//!   object's own space to world space.
//! - Texture coordinates follow glTF: u right, v down, (0, 0) the image's top-left corner.
//!
//! A [`Scene`]'s fields are public and nothing is checked as they are set:
//! [`Scene::validate`] checks references and value ranges as a whole (the renderer calls
//! it before uploading), and each part has its own `validate`. Failures are typed
//! errors ([`SceneError`], [`gltf::ImportError`], [`gltf::SaveError`]), not panics.

#![warn(missing_docs)]

mod alpha_coverage;
mod builtin;
mod camera;
mod camera_path;
mod environment;
mod error;
pub mod gltf;
mod material;
mod mesh;
pub mod motion;
mod view_check;

pub use alpha_coverage::{alpha_mip_scales, ALPHA_MIP_LEVELS};
pub use builtin::{builtin_scene, builtin_scene_with, BUILTIN_SCENES, SPHERE_GRID_ROUGHNESS};
pub use camera::{Camera, FRAMING_AZIMUTH, FRAMING_ELEVATION, FRAMING_FOV};
pub use camera_path::{CameraPath, MAX_CAMERA_PATH_BYTES};
pub use environment::{
    decode_exr_rgb, equirect_coordinates, studio_radiance, Environment, EnvironmentFormat,
    EnvironmentImage, MAX_ENVIRONMENT_FILE_BYTES, MAX_ENVIRONMENT_TEXELS, STUDIO_BOXES,
    STUDIO_GROUND, STUDIO_SKY,
};
pub use error::{CameraProblem, LightProblem, SceneError};
/// The rule for every file Combustion reads (glTF files and their buffers and images,
/// environment images, and the command line's tables, reports and camera paths): a
/// regular file within a size limit, both checked before it is read.
pub use gltf::{png_error_message, read_regular_file, read_text};
pub use material::{
    conductor_from_reflectivity, srgb_decode, srgb_encode, AlphaMode, ColorSpace, ComplexIor,
    DiffuseModel, Filter, Image, Iridescence, Material, Sampler, Texture, TextureRef, TextureSlot,
    UvTransform, Volume, WrapMode, CLEARCOAT_IOR, IRIDESCENCE_THICKNESS_MAX_NM, TEXTURE_SLOTS,
};
pub use mesh::{Mesh, Topology, Vertex};
pub use motion::{Motion, ObjectPoses, Pose};
pub use view_check::{ViewWarning, MIN_PRECISION_STEPS};

use glam::{Mat4, Vec3};

/// A light source. [`validate_lights`] (called by [`Scene::validate`]) checks each
/// variant's values as its fields state.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Radiant intensity `intensity` (W/sr per channel) from `position`. With a `range`
    /// (KHR_lights_punctual), the inverse-square law is windowed smoothly to 0 at that
    /// distance ([`range_window`]); without one it holds at every distance.
    Point {
        /// World-space position, metres; finite.
        position: Vec3,
        /// Radiant intensity I per linear RGB channel, W/sr; between 0 and
        /// [`MAX_RADIANCE`].
        intensity: [f32; 3],
        /// Distance (metres) at which the light's effect ends, finite and above 0;
        /// `None`: unlimited.
        range: Option<f32>,
        /// Whether the light casts shadows (when the renderer draws them).
        casts_shadows: bool,
        /// The radius (metres) of the sphere the light is, for the softness of its
        /// shadows; 0: a point (hard shadows). Finite, ≥ 0 and at most
        /// [`MAX_LIGHT_RADIUS`]. Shading treats the light as a point either way.
        radius: f32,
    },
    /// Parallel light travelling along `direction`, giving irradiance `irradiance`
    /// (W/m² per channel) on a surface facing it.
    Directional {
        /// World-space direction the light travels along (from the light towards the
        /// scene); any non-zero length, finite.
        direction: Vec3,
        /// Irradiance E per linear RGB channel on a surface facing the light, W/m²;
        /// between 0 and [`MAX_RADIANCE`].
        irradiance: [f32; 3],
        /// Whether the light casts shadows (when the renderer draws them).
        casts_shadows: bool,
        /// The angular diameter (radians) of the disc the light comes from (the Sun's:
        /// about 0.0093), for the softness of its shadows; 0: parallel light (hard
        /// shadows). Finite, ≥ 0 and at most [`MAX_ANGULAR_DIAMETER`]. Shading treats
        /// the light as parallel either way.
        angular_diameter: f32,
    },
    /// A point light limited to a cone around `direction` (the direction light travels
    /// along the axis), with full intensity inside `inner_cone` and none outside
    /// `outer_cone` (half-angles, radians), falling off between as KHR_lights_punctual
    /// specifies.
    Spot {
        /// World-space position, metres; finite.
        position: Vec3,
        /// World-space direction of the cone's axis, the way light travels; any
        /// non-zero length, finite.
        direction: Vec3,
        /// Radiant intensity I on the axis per linear RGB channel, W/sr; between 0 and
        /// [`MAX_RADIANCE`].
        intensity: [f32; 3],
        /// Half-angle (radians) inside which the intensity is full; 0 ≤ inner < outer.
        inner_cone: f32,
        /// Half-angle (radians) outside which there is no light; at most π/2.
        outer_cone: f32,
        /// As for [`Light::Point`].
        range: Option<f32>,
        /// As for [`Light::Point`].
        casts_shadows: bool,
        /// As for [`Light::Point`].
        radius: f32,
    },
}

/// The largest [`Light::Point`] or [`Light::Spot`] radius accepted, metres.
pub const MAX_LIGHT_RADIUS: f32 = 1.0e3;

/// The largest radiance (W·sr⁻¹·m⁻²), light intensity (W/sr) or irradiance (W/m²) a
/// scene may give, per channel. The shading multiplies these by BRDF values up to
/// ~10¹¹ (a lobe of α = 10⁻³ seen at grazing) and an environment's bake sums about 10³
/// samples of them, so 10³⁰ keeps every product within f32's 3.4·10³⁸ with room to
/// spare; what can still overflow (a light of 10³⁰ W/sr a micrometre from a surface,
/// or any radiance above 65504 in a 16-bit HDR frame) is caught after the render.
pub const MAX_RADIANCE: f32 = 1.0e30;
/// The largest [`Light::Directional`] angular diameter accepted, radians (30°: a sky
/// patch, far beyond any sun).
pub const MAX_ANGULAR_DIAMETER: f32 = std::f32::consts::FRAC_PI_6;

/// A number as messages write it: its shortest form, in scientific notation past 10⁷ or
/// below 10⁻⁴ (`3.4e38`, not 39 digits).
pub fn message_number<T>(x: T) -> String
where
    T: Copy + Into<f64> + std::fmt::Display + std::fmt::LowerExp,
{
    let a = x.into().abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e7).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// Numbers as messages write them, in parentheses: `(1, 0.5, 3.4e38)` (not a Rust
/// array's debug form).
pub fn message_numbers<T>(values: &[T]) -> String
where
    T: Copy + Into<f64> + std::fmt::Display + std::fmt::LowerExp,
{
    let written: Vec<String> = values.iter().map(|&x| message_number(x)).collect();
    format!("({})", written.join(", "))
}

/// The window a light's `range` puts on the inverse-square law at distance `d`:
/// (max(0, 1 − (d/range)⁴))² (Karis 2013; the KHR_lights_punctual recommendation
/// squared, so the falloff reaches 0 with zero slope). It removes 0.8 % of the
/// irradiance at d = range/4, 12.1 % at range/2, 53.3 % at 3/4 of the range, all of
/// it beyond. Lights without range are not windowed.
pub fn range_window(d: f64, range: f64) -> f64 {
    let x = d / range;
    range_window_of_squared(x * x)
}

/// [`range_window`] from x² = (d/range)² (the form the lighting pass evaluates, from
/// d² and 1/range²).
pub fn range_window_of_squared(x2: f64) -> f64 {
    let w = (1.0 - x2 * x2).max(0.0);
    w * w
}

impl Light {
    /// Whether the light casts shadows.
    pub fn casts_shadows(&self) -> bool {
        match *self {
            Light::Point { casts_shadows, .. }
            | Light::Spot { casts_shadows, .. }
            | Light::Directional { casts_shadows, .. } => casts_shadows,
        }
    }

    /// The light's range (point and spot lights that have one).
    pub fn range(&self) -> Option<f32> {
        match self {
            Light::Point { range, .. } | Light::Spot { range, .. } => *range,
            Light::Directional { .. } => None,
        }
    }
}

/// One placed mesh: an instance of [`Scene::meshes`]`[mesh]` drawn with
/// [`Scene::materials`]`[material]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// Object space to world space (column-major, glam convention: a point p is placed
    /// at `transform * p`). Finite, and not singular ([`transform_is_degenerate`]) unless
    /// the object hangs from a node (an animation may grow a node scaled to 0 at rest;
    /// the object is not drawn while its transform is singular). A
    /// mirroring transform (negative determinant) turns the mesh's triangles to face
    /// inwards, which back-face culling then removes: give such an object a
    /// winding-reversed mesh (as the glTF importer does) or a double-sided material.
    pub transform: Mat4,
    /// Whether the object casts shadows (it is lit, and receives them, either way).
    pub casts_shadows: bool,
    /// The node of [`Scene::motion`] it hangs from, if any: a pose moves it
    /// ([`Scene::pose_objects`]), and the node's skin and weights deform its mesh.
    /// `transform` is its place at rest.
    pub node: Option<NodeLink>,
}

/// How an object hangs from a node: its transform is the node's world transform times
/// `offset` (an instance's place within the node, glTF's EXT_mesh_gpu_instancing;
/// the identity otherwise). A skinned object's joints place it instead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeLink {
    /// Index into [`Motion::nodes`].
    pub node: usize,
    /// The object's transform relative to the node.
    pub offset: Mat4,
}

impl Object {
    /// Mesh `mesh` drawn with material `material`, placed by `transform`, casting shadows.
    pub fn casting_shadows(mesh: usize, material: usize, transform: Mat4) -> Self {
        Self {
            mesh,
            material,
            transform,
            casts_shadows: true,
            node: None,
        }
    }
}

/// Everything one frame shows: meshes and materials, objects placing them, lights, a
/// camera, the surrounding medium and an optional environment.
///
/// Fields are public and nothing is checked as they are set; [`Scene::validate`] checks
/// the whole (the renderer calls it before uploading).
#[derive(Clone, Debug)]
pub struct Scene {
    /// A name for the user (the built-in scene's name, the glTF scene's or file's).
    pub name: String,
    /// Meshes, each in its own object space; objects refer to them by index.
    pub meshes: Vec<Mesh>,
    /// Materials; objects refer to them by index. At most 65535 (the G-buffer's 16-bit
    /// material index).
    pub materials: Vec<Material>,
    /// The placed meshes, drawn in this order.
    pub objects: Vec<Object>,
    /// The scene's lights (a frame may bring its own as well).
    pub lights: Vec<Light>,
    /// The camera the scene is seen from by default.
    pub camera: Camera,
    /// Index of refraction of the medium the scene sits in (air ≈ 1.0, water ≈ 1.33);
    /// a material may override it.
    pub outside_ior: f32,
    /// Light from every direction besides `lights` (image-based lighting), or none.
    pub environment: Option<Environment>,
    /// The node hierarchy objects may hang from, skins and animations (empty for a
    /// still scene).
    pub motion: Motion,
}

/// Smallest |[`normalised_axes_determinant`]| of a transform that places a mesh: below it
/// the transform has collapsed an axis (a scale of 0, before or after any rotation) and
/// the normal matrix, its inverse transpose, would not fit f32 (its entries grow as
/// 1/determinant). A very flat object (a scale of 1e-7 on one axis) stays well above.
pub const MIN_AXES_DETERMINANT: f32 = 1e-30;

/// The determinant of `transform`'s linear part divided by its largest component
/// cubed: its sign is the transform's handedness, and its magnitude does not depend on
/// the transform's own scale (a scale of 1e-4 gives what a scale of 1 gives; the plain
/// determinant, 1e-12, says nothing about singularity), nor, beyond a factor of at most
/// 3√3, on the order in which a rotation and a flattening are applied. NaN when the
/// linear part is zero or not finite.
pub fn normalised_axes_determinant(transform: &glam::Mat4) -> f32 {
    let linear = glam::Mat3::from_mat4(*transform);
    let largest = [linear.x_axis, linear.y_axis, linear.z_axis]
        .iter()
        .map(|axis| axis.abs().max_element())
        .fold(0.0f32, f32::max);
    if !(largest > 0.0 && largest.is_finite()) {
        return f32::NAN;
    }
    (linear * (1.0 / largest)).determinant()
}

/// The eight corners of the axis-aligned box (`lo`, `hi`).
pub fn box_corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The world-space box around a mesh whose own box is `local` ([`Mesh::bounds`]),
/// placed by `transform`: its eight corners transformed (so a rotated box grows).
pub fn placed_bounds(local: Option<(Vec3, Vec3)>, transform: &Mat4) -> Option<(Vec3, Vec3)> {
    let (lo, hi) = local?;
    box_corners(lo, hi)
        .iter()
        .map(|corner| transform.transform_point3(*corner))
        .map(|p| (p, p))
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
}

/// Whether `transform` cannot place a mesh: not finite, or its axes (scale-relative,
/// [`normalised_axes_determinant`]) are within [`MIN_AXES_DETERMINANT`] of coplanar.
pub fn transform_is_degenerate(transform: &glam::Mat4) -> bool {
    !(transform.is_finite() && normalised_axes_determinant(transform).abs() >= MIN_AXES_DETERMINANT)
}

fn finite3(v: [f32; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

impl Scene {
    /// The world-space axis-aligned box around every object, as its (min, max) corners
    /// in metres: each mesh's own box, its corners transformed by the object's transform
    /// (so a rotated object's box may be larger than it is tight). `None` for a scene
    /// without objects (or whose meshes have no vertices). Objects naming a mesh that
    /// does not exist (which [`Scene::validate`] refuses) are left out, not a panic.
    pub fn world_bounds(&self) -> Option<(glam::Vec3, glam::Vec3)> {
        gltf::import::world_bounds(&self.meshes, &self.objects)
    }

    /// The box [`Camera::framing`] frames the scene by: the scene as drawn at rest
    /// where a mesh deforms (skins by their rest joints, morphs at their default
    /// weights), grown by the first animation's motion of its rigid objects; else every
    /// object's box so grown.
    pub fn framing_bounds(&self) -> Option<(glam::Vec3, glam::Vec3)> {
        gltf::import::framing_bounds(self)
    }

    /// Each object's world-space box, as [`Scene::world_bounds`] makes them (in the
    /// objects' order; `None` for an object whose mesh is missing or empty).
    pub fn object_bounds(&self) -> Vec<Option<(glam::Vec3, glam::Vec3)>> {
        gltf::import::object_bounds(&self.meshes, &self.objects)
    }

    /// Object `i`'s link to a node: the node exists, its offset is finite, its skin's
    /// joints cover the mesh's influences (a mesh with influences needs a skinned node),
    /// and it has one weight per morph target of the mesh.
    fn validate_link(&self, i: usize, link: &NodeLink) -> Result<(), SceneError> {
        let invalid = |what: String| Err(SceneError::Invalid(format!("object {i}: {what}")));
        let Some(node) = self.motion.nodes.get(link.node) else {
            return invalid(format!("its node {} does not exist", link.node));
        };
        if transform_is_degenerate(&link.offset) {
            return invalid("its offset from its node is not finite or singular".into());
        }
        let mesh = &self.meshes[self.objects[i].mesh];
        let joints = node
            .skin
            .and_then(|s| self.motion.skins.get(s))
            .map(|s| s.joints.len());
        match (&mesh.skin, joints) {
            (Some(weights), Some(joints)) => {
                if let Some(j) = weights.joints.iter().find(|&&j| j as usize >= joints) {
                    return invalid(format!(
                        "its mesh names joint {j} but its node's skin has {joints}"
                    ));
                }
            }
            (Some(_), None) => {
                return invalid("its mesh has joint influences but its node has no skin".into())
            }
            _ => {}
        }
        if !mesh.morph_targets.is_empty() && node.weights.len() != mesh.morph_targets.len() {
            return invalid(format!(
                "its mesh has {} morph targets but its node {} weights",
                mesh.morph_targets.len(),
                node.weights.len()
            ));
        }
        Ok(())
    }

    /// Each object's transform and morph weights and each skin's joint matrices in
    /// `pose` (of [`Scene::motion`]): an object hanging from a node is placed by the
    /// node's world transform times its offset and takes the node's weights, a skinned
    /// one by the identity (its joints place its vertices in world space); the others
    /// keep their transform and have no weights.
    pub fn pose_objects(&self, pose: &Pose) -> ObjectPoses {
        let world = self.motion.world_transforms(pose);
        let (transforms, weights) = self
            .objects
            .iter()
            .map(|object| match object.node {
                Some(link) => {
                    let weights = if self.meshes[object.mesh].morph_targets.is_empty() {
                        Vec::new()
                    } else {
                        pose.weights[link.node].clone()
                    };
                    let skinned = self.meshes[object.mesh].skin.is_some()
                        && self.motion.nodes[link.node].skin.is_some();
                    let transform = if skinned {
                        Mat4::IDENTITY
                    } else {
                        world[link.node] * link.offset
                    };
                    (transform, weights)
                }
                None => (object.transform, Vec::new()),
            })
            .unzip();
        ObjectPoses {
            transforms,
            weights,
            joints: self.motion.joint_matrices(&world),
        }
    }

    /// [`Scene::pose_objects`] of animation `animation` at `time` seconds
    /// ([`Motion::sample`]); `None` if there is no such animation.
    pub fn pose_at(&self, animation: usize, time: f32) -> Option<ObjectPoses> {
        Some(self.pose_objects(&self.motion.sample(animation, time)?))
    }

    /// The scene as a frame draws it, still: in `poses` if given, else at rest when its
    /// objects hang from nodes (rest joints and weights deform its meshes), else itself.
    /// What an f64 reference shades to compare with the frame.
    pub fn as_drawn(&self, poses: Option<&ObjectPoses>) -> std::borrow::Cow<'_, Scene> {
        match poses {
            Some(poses) => std::borrow::Cow::Owned(self.posed(poses)),
            None if self.objects.iter().any(|o| o.node.is_some()) => {
                std::borrow::Cow::Owned(self.posed(&self.pose_objects(&self.motion.rest_pose())))
            }
            None => std::borrow::Cow::Borrowed(self),
        }
    }

    /// The scene as a still one in `poses`: every object where `poses` puts it, and each
    /// object whose mesh it deforms (morph targets, a skin) given a mesh of its own,
    /// its vertices morphed and skinned as [`motion::pose_vertex`] does (in world space
    /// for a skinned one, whose transform becomes the identity). Objects no longer hang
    /// from nodes; the hierarchy, skins and animations are kept.
    pub fn posed(&self, poses: &ObjectPoses) -> Scene {
        let mut posed = self.clone();
        for (i, object) in posed.objects.iter_mut().enumerate() {
            let mesh = &self.meshes[object.mesh];
            let joints = self.object_joints(i, poses);
            let weights = &poses.weights[i];
            object.transform = poses.transforms[i];
            object.node = None;
            if joints.is_none() && (mesh.morph_targets.is_empty() || weights.is_empty()) {
                continue;
            }
            // Morphed in its own space, which its transform places; skinned into world
            // space (its transform in `poses` is the identity).
            let vertices = (0..mesh.vertices.len())
                .map(|v| motion::pose_vertex(mesh, v, weights, joints, &Mat4::IDENTITY))
                .collect();
            object.mesh = posed.meshes.len();
            posed.meshes.push(Mesh {
                name: format!("{} (posed)", mesh.name),
                vertices,
                indices: mesh.indices.clone(),
                topology: mesh.topology,
                ..Mesh::default()
            });
        }
        posed
    }

    /// The skin joint matrices placing object `object` in `poses`, if its node has a
    /// skin and its mesh joint influences.
    pub fn object_joints<'a>(&self, object: usize, poses: &'a ObjectPoses) -> Option<&'a [Mat4]> {
        let object = &self.objects[object];
        self.meshes[object.mesh].skin.as_ref()?;
        let skin = self.motion.nodes[object.node?.node].skin?;
        poses.joints.get(skin).map(Vec::as_slice)
    }

    /// The outside-medium IOR that applies to `material`.
    pub fn outside_ior_of(&self, material: &Material) -> f32 {
        material.outside_ior.unwrap_or(self.outside_ior)
    }

    /// Checks every reference and value range; the renderer calls this before uploading:
    /// the outside IOR is finite and positive; there are at most 65535 materials; every
    /// mesh ([`Mesh::validate`]), material ([`Material::validate`]) and the environment
    /// ([`Environment::validate`]) are valid; every object refers to an existing mesh and
    /// material and has a finite, non-singular transform; every light
    /// ([`validate_lights`]) and the camera ([`Camera::validate`]) are valid. Returns the
    /// first problem found.
    pub fn validate(&self) -> Result<(), SceneError> {
        let invalid = |what: String| Err(SceneError::Invalid(what));
        if !(self.outside_ior.is_finite() && self.outside_ior > 0.0) {
            return invalid(format!(
                "outside IOR {} must be a positive number",
                self.outside_ior
            ));
        }
        if u16::try_from(self.materials.len()).is_err() {
            return invalid(format!(
                "{} materials; at most {} fit the G-buffer's 16-bit material index",
                self.materials.len(),
                u16::MAX
            ));
        }
        for (i, mesh) in self.meshes.iter().enumerate() {
            mesh.validate()
                .map_err(|e| SceneError::Invalid(format!("mesh {i} ({}): {e}", mesh.name)))?;
        }
        for material in &self.materials {
            material.validate()?;
        }
        if let Some(environment) = &self.environment {
            environment.validate()?;
        }
        for (i, object) in self.objects.iter().enumerate() {
            if object.mesh >= self.meshes.len() {
                return invalid(format!(
                    "object {i} uses mesh {} of {}",
                    object.mesh,
                    self.meshes.len()
                ));
            }
            if object.material >= self.materials.len() {
                return invalid(format!(
                    "object {i} uses material {} of {}",
                    object.material,
                    self.materials.len()
                ));
            }
            // Singular only where a pose may make it regular.
            if !object.transform.is_finite()
                || (object.node.is_none() && transform_is_degenerate(&object.transform))
            {
                return invalid(format!("object {i} has a non-finite or singular transform"));
            }
            if let Some(link) = &object.node {
                self.validate_link(i, link)?;
            }
        }
        self.motion.validate().map_err(SceneError::Invalid)?;
        validate_lights(&self.lights)?;
        self.camera.validate()
    }
}

fn valid_range(range: Option<f32>) -> bool {
    range.is_none_or(|r| r.is_finite() && r > 0.0)
}

/// Checks every light's values (the scene's, or a frame's own lights): the first
/// problem found, by light index.
pub fn validate_lights(lights: &[Light]) -> Result<(), SceneError> {
    for (index, light) in lights.iter().enumerate() {
        if let Some(problem) = light_problem(light) {
            return Err(SceneError::InvalidLight { index, problem });
        }
    }
    Ok(())
}

fn light_problem(light: &Light) -> Option<LightProblem> {
    let power = |p: [f32; 3]| {
        (!(finite3(p) && p.iter().all(|&x| (0.0..=MAX_RADIANCE).contains(&x))))
            .then_some(LightProblem::Power(p))
    };
    let position = |p: glam::Vec3| (!p.is_finite()).then_some(LightProblem::Position);
    let direction = |d: glam::Vec3| {
        (!(d.is_finite() && d.length_squared() > 0.0)).then_some(LightProblem::Direction)
    };
    let range = |r: Option<f32>| match r {
        Some(r) if !valid_range(Some(r)) => Some(LightProblem::Range(r)),
        _ => None,
    };
    let radius = |r: f32| {
        (!(r.is_finite() && (0.0..=MAX_LIGHT_RADIUS).contains(&r)))
            .then_some(LightProblem::Radius(r))
    };
    match *light {
        Light::Point {
            position: p,
            intensity,
            range: r,
            radius: size,
            ..
        } => position(p)
            .or(power(intensity))
            .or(range(r))
            .or(radius(size)),
        Light::Directional {
            direction: d,
            irradiance,
            angular_diameter,
            ..
        } => direction(d)
            .or(power(irradiance))
            .or((!(angular_diameter.is_finite()
                && (0.0..=MAX_ANGULAR_DIAMETER).contains(&angular_diameter)))
            .then_some(LightProblem::AngularDiameter(angular_diameter))),
        Light::Spot {
            position: p,
            direction: d,
            intensity,
            inner_cone,
            outer_cone,
            range: r,
            radius: size,
            ..
        } => {
            let cone = (!(inner_cone >= 0.0
                && inner_cone < outer_cone
                && outer_cone <= std::f32::consts::FRAC_PI_2))
                .then_some(LightProblem::Cone {
                    inner: inner_cone,
                    outer: outer_cone,
                });
            position(p)
                .or(direction(d))
                .or(power(intensity))
                .or(cone)
                .or(range(r))
                .or(radius(size))
        }
    }
}

/// Every distinct image and texture of a scene, for upload: images deduplicated by
/// identity (`Arc`), textures by (image, sampler).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TextureTable {
    /// The distinct images, in the order materials first use them.
    pub images: Vec<std::sync::Arc<Image>>,
    /// The distinct (image, sampler) pairs, in the order materials first use them.
    pub textures: Vec<TextureTableEntry>,
    /// Per material (scene order), per slot in [`TextureSlot::ALL`] order: the index into
    /// `textures`, if the material uses that slot.
    pub material_textures: Vec<[Option<usize>; TEXTURE_SLOTS]>,
}

/// One texture of a [`TextureTable`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureTableEntry {
    /// Index into [`TextureTable::images`].
    pub image: usize,
    /// How the image is sampled.
    pub sampler: Sampler,
}

/// What a scene exercises, for `combustion info` and for choosing tests. Material counts
/// cover every material of the scene, used or not.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneFeatures {
    /// Materials with a conductor part (metalness > 0 or a metallic-roughness texture)
    /// whose η + ik is given (measured, named or explicit).
    pub conductors: usize,
    /// Materials with a conductor part derived from the base colour (glTF metals).
    pub conductors_from_base_color: usize,
    /// Materials with anisotropy (strength > 0 or an anisotropy texture).
    pub anisotropic: usize,
    /// The scene's outside-medium IOR, or any material's override, differs from 1.
    pub outside_ior_not_one: bool,
    /// Distinct diffuse models, in [`DiffuseModel`] order.
    pub diffuse_models: Vec<DiffuseModel>,
    /// Per texture slot (in [`TextureSlot::ALL`] order): how many materials use it.
    pub textures: [usize; TEXTURE_SLOTS],
    /// Distinct images.
    pub images: usize,
    /// Materials that emit light (emissive factor · strength > 0).
    pub emissive: usize,
    /// Materials with a non-default KHR_materials_specular factor, colour or texture.
    pub specular: usize,
    /// Materials rendered double-sided.
    pub double_sided: usize,
    /// Cut-out materials ([`AlphaMode::Mask`]).
    pub masked: usize,
    /// Blended materials ([`AlphaMode::Blend`]).
    pub blended: usize,
    /// Transmissive materials (KHR_materials_transmission), and of those, the ones with
    /// a volume (KHR_materials_volume).
    pub transmissive: usize,
    /// Transmissive materials with a volume.
    pub volumes: usize,
    /// Materials with a clear coat (KHR_materials_clearcoat).
    pub coated: usize,
    /// Materials with a sheen (KHR_materials_sheen).
    pub sheen: usize,
    /// Materials with a thin film (KHR_materials_iridescence).
    pub iridescent: usize,
    /// Unlit materials (KHR_materials_unlit).
    pub unlit: usize,
    /// [`Light::Point`]s among the scene's lights.
    pub point_lights: usize,
    /// [`Light::Spot`]s among the scene's lights.
    pub spot_lights: usize,
    /// [`Light::Directional`]s among the scene's lights.
    pub directional_lights: usize,
}

impl SceneFeatures {
    /// How many materials use texture slot `slot`.
    pub fn texture_count(&self, slot: TextureSlot) -> usize {
        let i = TextureSlot::ALL
            .iter()
            .position(|&s| s == slot)
            .unwrap_or(0);
        self.textures[i]
    }
}

impl std::fmt::Display for SceneFeatures {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "conductors (given η+ik): {}", self.conductors)?;
        writeln!(
            f,
            "conductors from base colour: {}",
            self.conductors_from_base_color
        )?;
        writeln!(f, "anisotropic materials: {}", self.anisotropic)?;
        writeln!(
            f,
            "outside IOR ≠ 1: {}",
            if self.outside_ior_not_one {
                "yes"
            } else {
                "no"
            }
        )?;
        let models: Vec<&str> = self
            .diffuse_models
            .iter()
            .map(|m| match m {
                DiffuseModel::Lambert => "lambert",
                DiffuseModel::OrenNayarQualitative => "oren-nayar-qualitative",
                DiffuseModel::OrenNayarFull => "oren-nayar-full",
            })
            .collect();
        writeln!(
            f,
            "diffuse models: {}",
            if models.is_empty() {
                "none".into()
            } else {
                models.join(", ")
            }
        )?;
        let textures: Vec<String> = TextureSlot::ALL
            .iter()
            .zip(self.textures)
            .filter(|(_, n)| *n > 0)
            .map(|(slot, n)| format!("{} {n}", slot.name()))
            .collect();
        writeln!(
            f,
            "textured materials: {} ({} images)",
            if textures.is_empty() {
                "none".into()
            } else {
                textures.join(", ")
            },
            self.images
        )?;
        writeln!(f, "emissive materials: {}", self.emissive)?;
        writeln!(f, "KHR_materials_specular materials: {}", self.specular)?;
        writeln!(f, "double-sided materials: {}", self.double_sided)?;
        writeln!(f, "cut-out (alpha mask) materials: {}", self.masked)?;
        writeln!(f, "blended (alpha blend) materials: {}", self.blended)?;
        writeln!(
            f,
            "transmissive materials: {} ({} with a volume)",
            self.transmissive, self.volumes
        )?;
        writeln!(f, "clear-coated materials: {}", self.coated)?;
        writeln!(f, "materials with sheen: {}", self.sheen)?;
        writeln!(f, "iridescent (thin-film) materials: {}", self.iridescent)?;
        writeln!(f, "unlit materials: {}", self.unlit)?;
        write!(
            f,
            "lights: {} point, {} spot, {} directional",
            self.point_lights, self.spot_lights, self.directional_lights
        )
    }
}

impl Scene {
    /// What this scene exercises (see [`SceneFeatures`]).
    pub fn features(&self) -> SceneFeatures {
        let mut features = SceneFeatures {
            outside_ior_not_one: self.outside_ior != 1.0,
            images: self.texture_table().images.len(),
            ..SceneFeatures::default()
        };
        for m in &self.materials {
            if m.metalness > 0.0 || m.metallic_roughness_texture.is_some() {
                if m.conductor_from_base_color {
                    features.conductors_from_base_color += 1;
                } else {
                    features.conductors += 1;
                }
            }
            if m.anisotropy_strength > 0.0 || m.anisotropy_texture.is_some() {
                features.anisotropic += 1;
            }
            if m.outside_ior.is_some_and(|ior| ior != 1.0) {
                features.outside_ior_not_one = true;
            }
            if !features.diffuse_models.contains(&m.diffuse_model) {
                features.diffuse_models.push(m.diffuse_model);
            }
            for (i, (_, texture)) in m.texture_slots().iter().enumerate() {
                if texture.is_some() {
                    features.textures[i] += 1;
                }
            }
            if m.emissive_strength > 0.0 && m.emissive_factor.iter().any(|&x| x > 0.0) {
                features.emissive += 1;
            }
            if m.has_specular() {
                features.specular += 1;
            }
            if m.double_sided {
                features.double_sided += 1;
            }
            if m.is_masked() {
                features.masked += 1;
            }
            if m.is_blended() {
                features.blended += 1;
            }
            if m.is_transmissive() {
                features.transmissive += 1;
                features.volumes += usize::from(m.volume.is_some());
            }
            features.coated += usize::from(m.is_coated());
            features.sheen += usize::from(m.has_sheen());
            features.iridescent += usize::from(m.is_iridescent());
            if m.unlit {
                features.unlit += 1;
            }
        }
        features.diffuse_models.sort_by_key(|&m| m as u32);
        for light in &self.lights {
            match light {
                Light::Point { .. } => features.point_lights += 1,
                Light::Spot { .. } => features.spot_lights += 1,
                Light::Directional { .. } => features.directional_lights += 1,
            }
        }
        features
    }

    /// The scene's distinct images and textures and which material uses which.
    pub fn texture_table(&self) -> TextureTable {
        let mut table = TextureTable::default();
        for m in &self.materials {
            let mut slots = [None; TEXTURE_SLOTS];
            for (i, (_, texture)) in m.texture_slots().iter().enumerate() {
                let Some(texture) = texture else { continue };
                let image = &texture.texture.image;
                let image = match table
                    .images
                    .iter()
                    .position(|known| std::sync::Arc::ptr_eq(known, image))
                {
                    Some(index) => index,
                    None => {
                        table.images.push(image.clone());
                        table.images.len() - 1
                    }
                };
                let entry = TextureTableEntry {
                    image,
                    sampler: texture.texture.sampler,
                };
                slots[i] = Some(match table.textures.iter().position(|&t| t == entry) {
                    Some(index) => index,
                    None => {
                        table.textures.push(entry);
                        table.textures.len() - 1
                    }
                });
            }
            table.material_textures.push(slots);
        }
        table
    }
}

#[cfg(test)]
mod message_number_tests {
    use super::{message_number, message_numbers};

    #[test]
    fn numbers_in_messages_are_short() {
        assert_eq!(message_number(3.4e38f32), "3.4e38");
        assert_eq!(message_number(1e-20f32), "1e-20");
        assert_eq!(message_number(0.5f32), "0.5");
        assert_eq!(message_number(-2.0f32), "-2");
        assert_eq!(message_number(0.0f32), "0");
        assert_eq!(message_number(f32::NAN), "NaN");
        assert_eq!(message_numbers(&[1.0f32, 0.25, -3e38]), "(1, 0.25, -3e38)");
        assert_eq!(message_number(0.1f32), "0.1");
        assert_eq!(message_number(1e300f64), "1e300");
    }
}

#[cfg(test)]
mod range_tests {
    use super::*;

    #[test]
    fn the_range_window_removes_the_stated_energy_and_ends_at_the_range() {
        let lost = |x: f64| 1.0 - range_window(x, 1.0);
        assert!((lost(0.25) - 0.0078).abs() < 1e-4, "{}", lost(0.25));
        assert!((lost(0.5) - 0.1211).abs() < 1e-4, "{}", lost(0.5));
        assert!((lost(0.75) - 0.5327).abs() < 1e-4, "{}", lost(0.75));
        assert_eq!(range_window(0.0, 3.0), 1.0);
        assert_eq!(range_window(3.0, 3.0), 0.0);
        assert_eq!(range_window(10.0, 3.0), 0.0);
        // Zero slope at the range: the window's derivative vanishes there.
        let h = 1e-6;
        assert!(range_window(1.0 - h, 1.0) < 1e-10);
    }

    #[test]
    fn lights_with_a_bad_range_are_invalid() {
        let light = |range| Light::Point {
            position: Vec3::ZERO,
            intensity: [1.0; 3],
            range,
            casts_shadows: true,
            radius: 0.0,
        };
        assert!(validate_lights(&[light(Some(2.0)), light(None)]).is_ok());
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(validate_lights(&[light(Some(bad))]).is_err(), "{bad}");
        }
    }
}

#[cfg(test)]
mod transform_tests {
    use super::*;
    use glam::{Mat4, Quat, Vec3, Vec4};

    #[test]
    fn singularity_is_relative_to_the_transforms_own_scale() {
        let turn = Mat4::from_quat(Quat::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.7));
        let at_one = normalised_axes_determinant(&turn);
        assert!(at_one >= 1.0, "{at_one}");
        for s in [1e-12_f32, 1e-4, 1.0, 1e4, 1e12] {
            let m = turn * Mat4::from_scale(Vec3::splat(s));
            let d = normalised_axes_determinant(&m);
            assert!((d - at_one).abs() < 1e-5 * at_one, "{s}: {d} vs {at_one}");
            assert!(!transform_is_degenerate(&m), "{s}");
            // a mirror keeps its handedness, whatever the scale
            let mirrored = m * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
            let dm = normalised_axes_determinant(&mirrored);
            assert!((dm + d).abs() < 1e-5 * at_one, "{s}: {dm}");
        }
        // a flattened (but not collapsed) object is kept, flattened before or after a
        // rotation, with the same measure up to the rotation's largest component
        let thin = Mat4::from_scale(Vec3::new(1.0, 1.0, 1e-7));
        for m in [thin, turn * thin, thin * turn] {
            assert!(!transform_is_degenerate(&m), "{m:?}");
            let d = normalised_axes_determinant(&m);
            assert!((1e-7..=6e-7).contains(&d), "{d}");
        }
        // a scale of 0 on an axis, before or after a rotation
        let flat = Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0));
        assert!(transform_is_degenerate(&flat));
        assert!(transform_is_degenerate(&(turn * flat)));
        assert!(transform_is_degenerate(&(flat * turn)));
        // axes that are not zero but exactly coplanar
        let coplanar = Mat4::from_cols(
            Vec4::new(1.0, 0.0, 0.0, 0.0),
            Vec4::new(0.0, 1.0, 0.0, 0.0),
            Vec4::new(1.0, 1.0, 0.0, 0.0),
            Vec4::W,
        );
        assert!(transform_is_degenerate(&coplanar));
        assert!(transform_is_degenerate(&Mat4::from_scale(Vec3::splat(
            f32::NAN
        ))));
        assert!(transform_is_degenerate(&Mat4::from_scale(Vec3::splat(
            f32::INFINITY
        ))));
    }
}

#[cfg(test)]
mod bounds_tests {
    use super::*;

    /// A host may ask an unvalidated scene for its bounds: an object naming a mesh that
    /// does not exist is left out rather than a panic.
    #[test]
    fn world_bounds_of_an_invalid_scene_do_not_panic() {
        let mut scene = builtin_scene("spheres").unwrap();
        let before = scene.world_bounds();
        assert!(before.is_some());
        scene.objects.push(Object {
            mesh: scene.meshes.len() + 5,
            material: 0,
            transform: Mat4::IDENTITY,
            casts_shadows: true,
            node: None,
        });
        assert_eq!(scene.world_bounds(), before);
        scene.objects.truncate(0);
        scene.objects.push(Object {
            mesh: 99,
            material: 0,
            transform: Mat4::IDENTITY,
            casts_shadows: true,
            node: None,
        });
        assert_eq!(scene.world_bounds(), None);
        assert!(scene.validate().is_err());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A host's material with an alpha outside [0, 1] or a cutoff that is negative or
    /// not finite is refused, naming the material and the rule.
    #[test]
    fn alpha_and_cutoff_are_checked() {
        let mut scene = builtin_scene("spheres").unwrap();
        scene.materials[0].alpha_mode = AlphaMode::Mask { cutoff: 0.0 };
        assert!(scene.validate().is_ok());
        for (alpha, cutoff, rule) in [
            (1.5, 0.5, "alpha must lie in [0, 1]"),
            (f32::NAN, 0.5, "alpha must lie in [0, 1]"),
            (0.5, -0.1, "alpha cutoff must be finite and non-negative"),
            (
                0.5,
                f32::INFINITY,
                "alpha cutoff must be finite and non-negative",
            ),
        ] {
            scene.materials[0].alpha = alpha;
            scene.materials[0].alpha_mode = AlphaMode::Mask { cutoff };
            let error = scene.validate().unwrap_err().to_string();
            assert!(
                error.contains(rule) && error.contains(&scene.materials[0].name),
                "{error}"
            );
        }
    }

    /// Issue 28, defect 3: a light's power above [`MAX_RADIANCE`] (3e38 W/sr, finite in
    /// f32, made pixels infinite) is refused with the bound named; the bound itself is
    /// taken.
    #[test]
    fn light_power_is_bounded() {
        let point = |intensity: f32| Light::Point {
            position: glam::Vec3::ZERO,
            intensity: [intensity, 1.0, 1.0],
            range: None,
            casts_shadows: false,
            radius: 0.0,
        };
        let error = validate_lights(&[point(1.0), point(3e38)]).unwrap_err();
        assert!(
            matches!(error, SceneError::InvalidLight { index: 1, .. }),
            "{error:?}"
        );
        let message = error.to_string();
        assert!(
            message.contains("3e38 1 1 is not between 0 and 1e30"),
            "{message}"
        );
        assert!(validate_lights(&[point(MAX_RADIANCE)]).is_ok());
    }
}
