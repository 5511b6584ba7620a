//! Things that move, in glTF's model: the node hierarchy objects hang from, skins
//! (joints and inverse bind matrices), the morph-target weights of nodes, and keyframe
//! animations of nodes' translation, rotation, scale and weights, with a player that
//! samples them at a time and blends two poses.
//!
//! The data flows one way: a [`Motion`] and an animation's time give a [`Pose`] (each
//! node's local transform and weights: [`Motion::sample`], [`Pose::blend`]); a pose gives
//! [`ObjectPoses`] (each object's transform and morph weights, each skin's joint
//! matrices: [`crate::Scene::pose_objects`]), what a renderer needs per frame. A host may
//! use the player or make its own poses and joint matrices.
//!
//! Order of deformation (glTF's): a vertex is morphed first (rest attribute plus the
//! weighted sum of the targets' displacements), then skinned: placed by the weighted sum
//! of its joints' matrices `world(joint) · inverse_bind(joint)`, which replaces the
//! object's own transform (glTF: the skinned mesh's node transform is ignored). Normals
//! are transformed by the inverse transpose of that sum, tangents by the sum itself
//! ([`pose_vertex`]).

use glam::{Mat3, Mat4, Quat, Vec3};

use crate::{Mesh, Vertex};

/// A node's transform relative to its parent (or the world, for a root).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LocalTransform {
    /// Translation · rotation · scale, the form animations change.
    Trs {
        /// Translation, metres.
        translation: Vec3,
        /// Rotation, a unit quaternion.
        rotation: Quat,
        /// Scale along the node's own axes.
        scale: Vec3,
    },
    /// A matrix (glTF: a node given by a matrix is never animated).
    Matrix(Mat4),
}

impl LocalTransform {
    /// No translation, rotation or scale.
    pub const IDENTITY: Self = Self::Trs {
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
        scale: Vec3::ONE,
    };

    /// The transform as a matrix.
    pub fn matrix(&self) -> Mat4 {
        match *self {
            Self::Trs {
                translation,
                rotation,
                scale,
            } => Mat4::from_scale_rotation_translation(scale, rotation, translation),
            Self::Matrix(m) => m,
        }
    }
}

/// One node of the hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The file's name for it, if any (animations and tools name nodes by it).
    pub name: Option<String>,
    /// Its parent, or `None` for a root.
    pub parent: Option<usize>,
    /// Its transform relative to its parent at rest.
    pub local: LocalTransform,
    /// The skin (index into [`Motion::skins`]) that places the mesh of objects attached
    /// to this node, if any.
    pub skin: Option<usize>,
    /// Its morph-target weights at rest (the node's own, else its mesh's, else zeros):
    /// one per morph target of the meshes of objects attached to it, empty without.
    pub weights: Vec<f32>,
}

/// The joints that place a skinned mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    /// The file's name for it, if any.
    pub name: Option<String>,
    /// The joints' nodes (indices into [`Motion::nodes`]); a vertex's joint `j` is
    /// `joints[j]`.
    pub joints: Vec<usize>,
    /// Per joint, the matrix from the mesh's bind space into the joint's space (glTF's
    /// inverse bind matrices; identities where the file gives none).
    pub inverse_bind: Vec<Mat4>,
}

/// The joint influences of a skinned mesh's vertices, compressed by rows: vertex `v`'s
/// influences are entries `offsets[v] .. offsets[v + 1]` of `joints` and `weights`
/// (every set of glTF's `JOINTS_n`/`WEIGHTS_n` pairs, zero weights left out).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SkinWeights {
    /// `vertices + 1` increasing offsets, the first 0.
    pub offsets: Vec<u32>,
    /// Joint indices into the skin's [`Skin::joints`].
    pub joints: Vec<u32>,
    /// Each influence's weight (positive and finite; glTF asks each vertex's to sum to 1).
    pub weights: Vec<f32>,
}

impl SkinWeights {
    /// The rows of each vertex's (joint, weight) pairs, in order, zero weights left out.
    pub fn from_influences<R: IntoIterator<Item = (u32, f32)>>(
        rows: impl IntoIterator<Item = R>,
    ) -> Self {
        let mut weights = SkinWeights {
            offsets: vec![0],
            ..SkinWeights::default()
        };
        for row in rows {
            for (joint, weight) in row.into_iter().filter(|&(_, w)| w != 0.0) {
                weights.joints.push(joint);
                weights.weights.push(weight);
            }
            weights.offsets.push(weights.joints.len() as u32);
        }
        weights
    }

    /// Checks the rows against `vertices`: `vertices + 1` offsets from 0, not
    /// decreasing, the last the length of `joints` and `weights`; weights positive and
    /// finite.
    pub fn validate(&self, vertices: usize) -> Result<(), String> {
        if self.offsets.len() != vertices + 1 || self.offsets[0] != 0 {
            return Err(format!(
                "its skin has {} influence offsets for {vertices} vertices (one more, from 0, expected)",
                self.offsets.len()
            ));
        }
        if self.offsets.windows(2).any(|w| w[0] > w[1])
            || self.offsets[vertices] as usize != self.joints.len()
            || self.joints.len() != self.weights.len()
        {
            return Err(format!(
                "its skin's influence offsets do not increase to its {} joints and {} weights",
                self.joints.len(),
                self.weights.len()
            ));
        }
        if let Some(i) = self
            .weights
            .iter()
            .position(|w| !(w.is_finite() && *w > 0.0))
        {
            return Err(format!(
                "its skin's influence {i} has weight {}, not positive and finite",
                self.weights[i]
            ));
        }
        Ok(())
    }

    /// Vertex `v`'s influences as (joint, weight) pairs.
    pub fn influences(&self, v: usize) -> impl Iterator<Item = (u32, f32)> + '_ {
        let range = self.offsets[v] as usize..self.offsets[v + 1] as usize;
        self.joints[range.clone()]
            .iter()
            .copied()
            .zip(self.weights[range].iter().copied())
    }
}

/// One morph target: per-vertex displacements of a mesh's attributes, each list empty
/// (the attribute is not displaced) or one per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    /// Position displacements, metres in the mesh's space.
    pub positions: Vec<[f32; 3]>,
    /// Normal displacements (the sum is normalised after).
    pub normals: Vec<[f32; 3]>,
    /// Tangent displacements (xyz; the sign w is not displaced).
    pub tangents: Vec<[f32; 3]>,
}

/// What a channel animates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Property {
    /// The node's translation (3 values per key).
    Translation,
    /// The node's rotation (a quaternion x, y, z, w per key).
    Rotation,
    /// The node's scale (3 values per key).
    Scale,
    /// The node's morph weights (one per target per key).
    Weights,
}

impl Property {
    /// What it animates, in words (for messages).
    pub fn name(self) -> &'static str {
        match self {
            Self::Translation => "translation",
            Self::Rotation => "rotation",
            Self::Scale => "scale",
            Self::Weights => "morph weights",
        }
    }
}

/// How a sampler fills the time between keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Interpolation {
    /// The previous key's value until the next key.
    Step,
    /// Linear interpolation; spherical (shortest arc) for rotations.
    Linear,
    /// Cubic Hermite spline with each key's in- and out-tangents (glTF's CUBICSPLINE);
    /// rotations are normalised after.
    CubicSpline,
}

/// Keyframes: times and the values at them.
#[derive(Clone, Debug, PartialEq)]
pub struct Sampler {
    /// How values between keys are made.
    pub interpolation: Interpolation,
    /// Key times in seconds, finite and strictly increasing, at least one.
    pub times: Vec<f32>,
    /// Per key, `width` values (a [`Interpolation::CubicSpline`] key has three groups:
    /// in-tangent, value, out-tangent), keys one after another.
    pub values: Vec<f32>,
}

impl Sampler {
    /// Values per key and group: the values' length over the keys (and over 3 for a
    /// cubic spline).
    pub fn width(&self) -> usize {
        let groups = match self.interpolation {
            Interpolation::CubicSpline => 3,
            _ => 1,
        };
        self.values.len() / (self.times.len() * groups).max(1)
    }

    /// Key `k`'s group `g` (cubic spline: 0 in-tangent, 1 value, 2 out-tangent; else 0).
    fn group(&self, k: usize, g: usize, width: usize) -> &[f32] {
        let groups = if self.interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        let start = (k * groups + g) * width;
        &self.values[start..start + width]
    }

    /// The value at `time` into `out` (`width` values; a rotation when `rotation`):
    /// before the first key its value, after the last key its value.
    pub fn sample(&self, time: f32, rotation: bool, out: &mut [f32]) {
        let width = out.len();
        let value = if self.interpolation == Interpolation::CubicSpline {
            1
        } else {
            0
        };
        let last = self.times.len() - 1;
        // The key interval [k, k + 1] holding `time`.
        let next = self.times.partition_point(|&t| t <= time);
        if next == 0 || next > last || !time.is_finite() {
            let k = if next == 0 || time.is_nan() { 0 } else { last };
            out.copy_from_slice(self.group(k, value, width));
            return;
        }
        let k = next - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let dt = t1 - t0;
        let s = ((time - t0) / dt).clamp(0.0, 1.0);
        match self.interpolation {
            Interpolation::Step => out.copy_from_slice(self.group(k, 0, width)),
            Interpolation::Linear if rotation => {
                let q0 = Quat::from_slice(self.group(k, 0, width));
                let q1 = Quat::from_slice(self.group(k + 1, 0, width));
                out.copy_from_slice(&slerp(q0, q1, s).to_array());
            }
            Interpolation::Linear => {
                let (a, b) = (self.group(k, 0, width), self.group(k + 1, 0, width));
                for (o, (a, b)) in out.iter_mut().zip(a.iter().zip(b)) {
                    *o = a + (b - a) * s;
                }
            }
            Interpolation::CubicSpline => {
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = s3 - 2.0 * s2 + s;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = s3 - s2;
                let v0 = self.group(k, 1, width);
                let out_tangent = self.group(k, 2, width);
                let v1 = self.group(k + 1, 1, width);
                let in_tangent = self.group(k + 1, 0, width);
                for i in 0..width {
                    out[i] = h00 * v0[i]
                        + h10 * dt * out_tangent[i]
                        + h01 * v1[i]
                        + h11 * dt * in_tangent[i];
                }
                if rotation {
                    let q = Quat::from_slice(out).normalize();
                    out.copy_from_slice(&q.to_array());
                }
            }
        }
    }
}

/// Spherical interpolation along the shorter arc (q and −q are one rotation), linear and
/// normalised where the two are within 2.6° (sin of the angle too small to divide by).
pub fn slerp(q0: Quat, q1: Quat, s: f32) -> Quat {
    let mut cos = q0.dot(q1);
    let q1 = if cos < 0.0 {
        cos = -cos;
        -q1
    } else {
        q1
    };
    if cos > 0.999 {
        return (q0 + (q1 - q0) * s).normalize();
    }
    let angle = cos.clamp(-1.0, 1.0).acos();
    let sin = angle.sin();
    let a = ((1.0 - s) * angle).sin() / sin;
    let b = (s * angle).sin() / sin;
    (q0 * a + q1 * b).normalize()
}

/// One animated property of one node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Channel {
    /// The node animated (index into [`Motion::nodes`]).
    pub node: usize,
    /// What of it.
    pub property: Property,
    /// The sampler giving its values (index into [`Animation::samplers`]).
    pub sampler: usize,
}

/// A keyframe animation: channels driven by samplers (several channels may share one).
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// The file's name for it, if any.
    pub name: Option<String>,
    /// Its samplers.
    pub samplers: Vec<Sampler>,
    /// Its channels (at most one per node and property).
    pub channels: Vec<Channel>,
}

impl Animation {
    /// The last key time of any sampler its channels use, seconds (0 without channels).
    pub fn duration(&self) -> f32 {
        self.channels
            .iter()
            .filter_map(|c| self.samplers.get(c.sampler)?.times.last().copied())
            .fold(0.0, f32::max)
    }
}

/// The hierarchy, skins and animations of a scene. Empty for a still scene made by
/// hand: objects without a node keep their own transform.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    /// Nodes, each naming its parent.
    pub nodes: Vec<Node>,
    /// Skins.
    pub skins: Vec<Skin>,
    /// Animations.
    pub animations: Vec<Animation>,
}

/// Every node's local transform and weights at one moment.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// Per node, its local transform.
    pub locals: Vec<LocalTransform>,
    /// Per node, its morph weights.
    pub weights: Vec<Vec<f32>>,
}

impl Pose {
    /// This pose blended with `other` by `weight` (0: this one, 1: `other`): translations,
    /// scales and weights linearly, rotations by [`slerp`]; a node given by a matrix
    /// in either keeps this pose's.
    pub fn blend(&self, other: &Pose, weight: f32) -> Pose {
        let locals = self
            .locals
            .iter()
            .zip(&other.locals)
            .map(|(a, b)| match (*a, *b) {
                (
                    LocalTransform::Trs {
                        translation: t0,
                        rotation: r0,
                        scale: s0,
                    },
                    LocalTransform::Trs {
                        translation: t1,
                        rotation: r1,
                        scale: s1,
                    },
                ) => LocalTransform::Trs {
                    translation: t0.lerp(t1, weight),
                    rotation: slerp(r0, r1, weight),
                    scale: s0.lerp(s1, weight),
                },
                (a, _) => a,
            })
            .collect();
        let weights = self
            .weights
            .iter()
            .zip(&other.weights)
            .map(|(a, b)| a.iter().zip(b).map(|(a, b)| a + (b - a) * weight).collect())
            .collect();
        Pose { locals, weights }
    }
}

impl Motion {
    /// Every node at rest.
    pub fn rest_pose(&self) -> Pose {
        Pose {
            locals: self.nodes.iter().map(|n| n.local).collect(),
            weights: self.nodes.iter().map(|n| n.weights.clone()).collect(),
        }
    }

    /// Animation `animation` at `time` seconds (clamped to its keys: before the first,
    /// the first key's values; after the last, the last's), the nodes it does not
    /// animate at rest. `None` if there is no such animation.
    pub fn sample(&self, animation: usize, time: f32) -> Option<Pose> {
        let mut pose = self.rest_pose();
        self.apply(animation, time, &mut pose)?;
        Some(pose)
    }

    /// Sets what animation `animation` animates in `pose` to its values at `time`.
    /// `None` if there is no such animation.
    pub fn apply(&self, animation: usize, time: f32, pose: &mut Pose) -> Option<()> {
        let animation = self.animations.get(animation)?;
        for channel in &animation.channels {
            let (Some(sampler), Some(local)) = (
                animation.samplers.get(channel.sampler),
                pose.locals.get_mut(channel.node),
            ) else {
                continue;
            };
            let LocalTransform::Trs {
                translation,
                rotation,
                scale,
            } = local
            else {
                continue;
            };
            match channel.property {
                Property::Translation => {
                    let mut v = [0.0; 3];
                    sampler.sample(time, false, &mut v);
                    *translation = Vec3::from(v);
                }
                Property::Scale => {
                    let mut v = [0.0; 3];
                    sampler.sample(time, false, &mut v);
                    *scale = Vec3::from(v);
                }
                Property::Rotation => {
                    let mut v = [0.0; 4];
                    sampler.sample(time, true, &mut v);
                    *rotation = Quat::from_array(v).normalize();
                }
                Property::Weights => {
                    let weights = &mut pose.weights[channel.node];
                    if sampler.width() == weights.len() {
                        sampler.sample(time, false, weights);
                    }
                }
            }
        }
        Some(())
    }

    /// Each node's world transform in `pose` (parents before children whatever their
    /// order in [`Motion::nodes`]; the hierarchy must be a forest, as
    /// [`Motion::validate`] checks).
    pub fn world_transforms(&self, pose: &Pose) -> Vec<Mat4> {
        let mut world: Vec<Option<Mat4>> = vec![None; self.nodes.len()];
        let mut chain = Vec::new();
        for start in 0..self.nodes.len() {
            let mut node = Some(start);
            while let Some(n) = node.filter(|&n| world[n].is_none()) {
                chain.push(n);
                node = self.nodes[n].parent;
            }
            let mut parent = node.and_then(|n| world[n]);
            while let Some(n) = chain.pop() {
                let local = pose.locals[n].matrix();
                let m = parent.map_or(local, |p| p * local);
                world[n] = Some(m);
                parent = Some(m);
            }
        }
        world
            .into_iter()
            .map(|m| m.unwrap_or(Mat4::IDENTITY))
            .collect()
    }

    /// Each skin's joint matrices in a pose whose world transforms are `world`:
    /// `world(joint) · inverse_bind(joint)`.
    pub fn joint_matrices(&self, world: &[Mat4]) -> Vec<Vec<Mat4>> {
        self.skins
            .iter()
            .map(|skin| {
                skin.joints
                    .iter()
                    .zip(&skin.inverse_bind)
                    .map(|(&j, ibm)| world[j] * *ibm)
                    .collect()
            })
            .collect()
    }

    /// Checks the hierarchy, skins and animations: parents exist and form a forest;
    /// local transforms, weights and inverse bind matrices are finite; each skin has one
    /// inverse bind matrix per joint and its joints exist; each animation's channels
    /// name existing nodes and samplers, a node's transform only when it is given by
    /// translation, rotation and scale, and its samplers have strictly increasing
    /// finite times and finite values of the width the property needs.
    pub fn validate(&self) -> Result<(), String> {
        let count = self.nodes.len();
        for (i, node) in self.nodes.iter().enumerate() {
            if let Some(p) = node.parent.filter(|&p| p >= count) {
                return Err(format!(
                    "node {i}'s parent {p} does not exist ({count} nodes)"
                ));
            }
            let finite = match node.local {
                LocalTransform::Trs {
                    translation,
                    rotation,
                    scale,
                } => translation.is_finite() && rotation.is_finite() && scale.is_finite(),
                LocalTransform::Matrix(m) => m.is_finite(),
            };
            if !finite || !node.weights.iter().all(|w| w.is_finite()) {
                return Err(format!("node {i}'s transform or weights are not finite"));
            }
            if let Some(s) = node.skin.filter(|&s| s >= self.skins.len()) {
                return Err(format!("node {i}'s skin {s} does not exist"));
            }
        }
        // A forest: no parent chain is longer than the node count.
        for start in 0..count {
            let mut node = self.nodes[start].parent;
            let mut steps = 0;
            while let Some(n) = node {
                steps += 1;
                if steps > count {
                    return Err(format!("node {start}'s ancestors form a cycle"));
                }
                node = self.nodes[n].parent;
            }
        }
        for (i, skin) in self.skins.iter().enumerate() {
            if skin.joints.len() != skin.inverse_bind.len() {
                return Err(format!(
                    "skin {i} has {} joints but {} inverse bind matrices",
                    skin.joints.len(),
                    skin.inverse_bind.len()
                ));
            }
            if let Some(j) = skin.joints.iter().find(|&&j| j >= count) {
                return Err(format!("skin {i}'s joint node {j} does not exist"));
            }
            if !skin.inverse_bind.iter().all(|m| m.is_finite()) {
                return Err(format!("skin {i}'s inverse bind matrices are not finite"));
            }
        }
        for (a, animation) in self.animations.iter().enumerate() {
            let problem = |m: String| Err(format!("animation {a}: {m}"));
            for (s, sampler) in animation.samplers.iter().enumerate() {
                if sampler.times.is_empty() {
                    return problem(format!("sampler {s} has no keys"));
                }
                if !sampler.times.iter().all(|t| t.is_finite())
                    || sampler.times.windows(2).any(|w| w[0] >= w[1])
                {
                    return problem(format!(
                        "sampler {s}'s times are not finite and strictly increasing"
                    ));
                }
                let groups = if sampler.interpolation == Interpolation::CubicSpline {
                    3
                } else {
                    1
                };
                if sampler.values.len() % (sampler.times.len() * groups) != 0 {
                    return problem(format!(
                        "sampler {s} has {} values for {} keys",
                        sampler.values.len(),
                        sampler.times.len()
                    ));
                }
                if !sampler.values.iter().all(|v| v.is_finite()) {
                    return problem(format!("sampler {s}'s values are not finite"));
                }
            }
            for (c, channel) in animation.channels.iter().enumerate() {
                let Some(node) = self.nodes.get(channel.node) else {
                    return problem(format!(
                        "channel {c}'s node {} does not exist",
                        channel.node
                    ));
                };
                let Some(sampler) = animation.samplers.get(channel.sampler) else {
                    return problem(format!(
                        "channel {c}'s sampler {} does not exist",
                        channel.sampler
                    ));
                };
                let width = match channel.property {
                    Property::Translation | Property::Scale => 3,
                    Property::Rotation => 4,
                    Property::Weights => node.weights.len(),
                };
                if sampler.width() != width {
                    return problem(format!(
                        "channel {c} animates the {} of node {} ({width} values per key) with {} values per key",
                        channel.property.name(),
                        channel.node,
                        sampler.width()
                    ));
                }
                if channel.property != Property::Weights
                    && matches!(node.local, LocalTransform::Matrix(_))
                {
                    return problem(format!(
                        "channel {c} animates node {}, whose transform is a matrix",
                        channel.node
                    ));
                }
            }
        }
        Ok(())
    }
}

/// What a renderer needs of a pose: each object's transform and morph weights, each
/// skin's joint matrices ([`crate::Scene::pose_objects`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectPoses {
    /// Per object, its transform (the identity for a skinned object: its joints place
    /// its vertices in world space).
    pub transforms: Vec<Mat4>,
    /// Per object, its morph weights (empty where its mesh has no targets).
    pub weights: Vec<Vec<f32>>,
    /// Per skin, its joint matrices ([`Motion::joint_matrices`]).
    pub joints: Vec<Vec<Mat4>>,
}

/// The inverse transpose of `linear` up to a positive factor (what normals are
/// transformed by before they are normalised): its cofactor matrix, signed by its
/// determinant. Finite where the inverse is not (a joint scaled to 0 to hide a part);
/// deform.comp computes the same.
pub fn normal_transform(linear: &Mat3) -> Mat3 {
    let (a, b, c) = (linear.x_axis, linear.y_axis, linear.z_axis);
    let sign = if linear.determinant() < 0.0 {
        -1.0
    } else {
        1.0
    };
    Mat3::from_cols(b.cross(c), c.cross(a), a.cross(b)) * sign
}

/// Vertex `v` of `mesh` morphed by `weights` and placed by `joints` (its skin's joint
/// matrices) if it has influences, else by `transform`: position, normal (inverse
/// transpose, normalised) and tangent (normalised, sign kept; a zero normal or tangent
/// stays zero). The renderer's deform.comp does the same on the GPU.
pub fn pose_vertex(
    mesh: &Mesh,
    v: usize,
    weights: &[f32],
    joints: Option<&[Mat4]>,
    transform: &Mat4,
) -> Vertex {
    let mut vertex = mesh.vertices[v];
    let mut position = Vec3::from(vertex.position);
    let mut normal = Vec3::from(vertex.normal);
    let mut tangent = Vec3::from_slice(&vertex.tangent[..3]);
    for (target, &w) in mesh.morph_targets.iter().zip(weights) {
        if w == 0.0 {
            continue;
        }
        if let Some(d) = target.positions.get(v) {
            position += Vec3::from(*d) * w;
        }
        if let Some(d) = target.normals.get(v) {
            normal += Vec3::from(*d) * w;
        }
        if let Some(d) = target.tangents.get(v) {
            tangent += Vec3::from(*d) * w;
        }
    }
    let skinned = match (joints, &mesh.skin) {
        (Some(joints), Some(skin)) => {
            let mut sum = None;
            for (j, w) in skin.influences(v) {
                sum = Some(sum.unwrap_or(Mat4::ZERO) + joints[j as usize] * w);
            }
            sum
        }
        _ => None,
    };
    let m = skinned.unwrap_or(*transform);
    let linear = Mat3::from_mat4(m);
    position = m.transform_point3(position);
    // A vertex collapsed to a point keeps its normal (as deform.comp does).
    let transformed = normal_transform(&linear) * normal;
    if transformed != Vec3::ZERO {
        normal = transformed;
    }
    normal = normal.normalize_or_zero();
    tangent = (linear * tangent).normalize_or_zero();
    vertex.position = position.to_array();
    vertex.normal = normal.to_array();
    vertex.tangent = [tangent.x, tangent.y, tangent.z, vertex.tangent[3]];
    vertex
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(parent: Option<usize>, translation: Vec3, rotation: Quat) -> Node {
        Node {
            name: None,
            parent,
            local: LocalTransform::Trs {
                translation,
                rotation,
                scale: Vec3::ONE,
            },
            skin: None,
            weights: Vec::new(),
        }
    }

    /// A child listed before its parent is placed by the parent all the same; a chain of
    /// parents that loops is refused.
    #[test]
    fn world_transforms_follow_parents_in_any_order() {
        let turn = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        let mut motion = Motion {
            nodes: vec![
                node(Some(1), Vec3::X, Quat::IDENTITY),
                node(None, Vec3::Y, turn),
            ],
            ..Motion::default()
        };
        motion.validate().unwrap();
        let world = motion.world_transforms(&motion.rest_pose());
        // The child's origin: the parent's turn takes +x to −z, then up by one.
        let origin = world[0].transform_point3(Vec3::ZERO);
        assert!(
            origin.abs_diff_eq(Vec3::new(0.0, 1.0, -1.0), 1e-6),
            "{origin}"
        );
        motion.nodes[1].parent = Some(0);
        let error = motion.validate().unwrap_err();
        assert!(error.contains("cycle"), "{error}");
    }

    /// Blending by 0 is the first pose, by 1 the second, by ½ halfway (rotations along
    /// the arc).
    #[test]
    fn poses_blend_from_one_to_the_other() {
        let turn = Quat::from_rotation_z(1.0);
        let a = Pose {
            locals: vec![LocalTransform::IDENTITY],
            weights: vec![vec![0.0, 1.0]],
        };
        let b = Pose {
            locals: vec![LocalTransform::Trs {
                translation: Vec3::new(2.0, 0.0, 0.0),
                rotation: turn,
                scale: Vec3::splat(3.0),
            }],
            weights: vec![vec![1.0, 0.0]],
        };
        assert_eq!(a.blend(&b, 0.0), a);
        let LocalTransform::Trs {
            translation,
            rotation,
            scale,
        } = a.blend(&b, 1.0).locals[0]
        else {
            unreachable!()
        };
        assert!(translation == Vec3::new(2.0, 0.0, 0.0) && scale == Vec3::splat(3.0));
        assert!(rotation.abs_diff_eq(turn, 1e-6));
        let half = a.blend(&b, 0.5);
        let LocalTransform::Trs {
            translation,
            rotation,
            scale,
        } = half.locals[0]
        else {
            unreachable!()
        };
        assert_eq!((translation, scale), (Vec3::X, Vec3::splat(2.0)));
        assert!((rotation.angle_between(Quat::IDENTITY) - 0.5).abs() < 1e-6);
        assert_eq!(half.weights[0], [0.5, 0.5]);
    }
}
