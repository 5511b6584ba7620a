#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! A glTF file's node hierarchy, skins, morph targets and animations →
//! [`crate::motion`]: every value checked, every size charged to the importer's budget
//! for built data before it is kept.

use std::collections::HashMap;

use glam::{Mat4, Quat, Vec3};
use gltf::json;
use gltf::json::validation::Checked;

use super::accessor::{read_f32, read_floats, read_joints, read_unit_floats};
use super::import::Importer;
use super::ImportProblem;
use crate::motion::{
    Animation, Channel, Interpolation, LocalTransform, MorphTarget, Node, Property, Sampler, Skin,
    SkinWeights,
};

/// Most joints a skin may have (glTF's joint indices are unsigned shorts at most).
pub(crate) const MAX_JOINTS: usize = 1 << 16;
/// Most morph targets a primitive may have.
pub(crate) const MAX_MORPH_TARGETS: usize = 1 << 10;
/// Most `JOINTS_n`/`WEIGHTS_n` sets a primitive may have (4 influences each).
pub(crate) const MAX_INFLUENCE_SETS: usize = 8;

fn name_suffix(name: &Option<String>) -> String {
    name.as_deref()
        .map_or(String::new(), |n| format!(" (`{n}`)"))
}

impl Importer<'_> {
    /// Every node of the file, at rest: its parent (from the children lists), its
    /// transform (rotation normalised), its skin. Weights are filled in by
    /// [`Importer::node_weights`].
    pub(crate) fn motion_nodes(&self) -> Result<Vec<Node>, ImportProblem> {
        let root = self.root;
        let mut parents = vec![None; root.nodes.len()];
        for (i, node) in root.nodes.iter().enumerate() {
            for child in node.children.iter().flatten() {
                if let Some(p) = parents.get_mut(child.value()) {
                    *p = Some(i);
                }
            }
        }
        root.nodes
            .iter()
            .enumerate()
            .map(|(i, node)| {
                // Checks finiteness and the rotation's length, with the node's error.
                let matrix = self.local_transform(i)?;
                let local = if node.matrix.is_some() {
                    LocalTransform::Matrix(matrix)
                } else {
                    // Normalised as `local_transform` does (the same matrix, bit for bit).
                    let q = Quat::from_array(node.rotation.map_or([0.0, 0.0, 0.0, 1.0], |q| q.0));
                    LocalTransform::Trs {
                        translation: Vec3::from(node.translation.unwrap_or([0.0; 3])),
                        // Float division (glam's, which cannot panic), as written `q / |q|`.
                        rotation: std::ops::Div::div(q, q.length()),
                        scale: Vec3::from(node.scale.unwrap_or([1.0; 3])),
                    }
                };
                let skin = node.skin.map(|s| s.value());
                if let Some(s) = skin.filter(|&s| s >= root.skins.len()) {
                    return Err(self.node_error(i, format!("its skin {s} does not exist")));
                }
                Ok(Node {
                    name: node.name.clone(),
                    parent: parents.get(i).copied().flatten(),
                    local,
                    skin,
                    weights: Vec::new(),
                })
            })
            .collect()
    }

    /// The morph weights at rest of every node with a mesh that has targets: the node's
    /// `weights`, else its mesh's, else zeros, one per target (every primitive of the
    /// mesh has as many targets, as glTF requires).
    pub(crate) fn node_weights(&self, nodes: &mut [Node]) -> Result<(), ImportProblem> {
        let root = self.root;
        for (i, node) in root.nodes.iter().enumerate() {
            let Some(mesh) = node.mesh.and_then(|m| root.meshes.get(m.value())) else {
                continue;
            };
            let counts: Vec<usize> = mesh
                .primitives
                .iter()
                .map(|p| p.targets.as_ref().map_or(0, Vec::len))
                .collect();
            // glTF gives a mesh at least one primitive; one without is left alone here
            // (the mesh's own reading refuses it).
            let Some(&targets) = counts.first() else {
                continue;
            };
            if counts.iter().any(|&c| c != targets) {
                return Err(self.node_error(
                    i,
                    format!(
                        "its mesh's primitives have different numbers of morph targets ({})",
                        counts
                            .iter()
                            .map(usize::to_string)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            }
            if targets == 0 {
                continue;
            }
            if targets > MAX_MORPH_TARGETS {
                return Err(self.node_error(
                    i,
                    format!("its mesh has {targets} morph targets, at most {MAX_MORPH_TARGETS}"),
                ));
            }
            let weights = match (&node.weights, &mesh.weights) {
                (Some(w), _) | (None, Some(w)) => w.clone(),
                (None, None) => vec![0.0; targets],
            };
            if weights.len() != targets || !weights.iter().all(|w| w.is_finite()) {
                return Err(self.node_error(
                    i,
                    format!(
                        "has {} morph weights for {targets} morph targets, or a non-finite one: {}",
                        weights.len(),
                        crate::message_numbers(&weights)
                    ),
                ));
            }
            if let Some(node) = nodes.get_mut(i) {
                node.weights = weights;
            }
        }
        Ok(())
    }

    /// Every skin: its joints (at least one, at most [`MAX_JOINTS`]) and their inverse
    /// bind matrices (finite; identities without an accessor; at least one per joint).
    pub(crate) fn skins(&mut self) -> Result<Vec<Skin>, ImportProblem> {
        let root = self.root;
        let mut skins = Vec::with_capacity(root.skins.len());
        for (i, skin) in root.skins.iter().enumerate() {
            let problem = |m: String| {
                ImportProblem::Invalid(format!("skin {i}{}: {m}", name_suffix(&skin.name)))
            };
            let joints: Vec<usize> = skin.joints.iter().map(|j| j.value()).collect();
            if joints.is_empty() || joints.len() > MAX_JOINTS {
                return Err(problem(format!(
                    "has {} joints (from 1 to {MAX_JOINTS})",
                    joints.len()
                )));
            }
            if let Some(j) = joints.iter().find(|&&j| j >= root.nodes.len()) {
                return Err(problem(format!("its joint node {j} does not exist")));
            }
            self.charge_mesh_bytes((joints.len() as u64).saturating_mul(72))
                .map_err(problem)?;
            let inverse_bind = match skin.inverse_bind_matrices {
                None => vec![Mat4::IDENTITY; joints.len()],
                Some(a) => {
                    let matrices = read_f32::<16>(root, &mut self.buffers, a.value())
                        .map_err(|e| problem(format!("inverseBindMatrices: {e}")))?;
                    if matrices.len() < joints.len() {
                        return Err(problem(format!(
                            "has {} inverse bind matrices for {} joints",
                            matrices.len(),
                            joints.len()
                        )));
                    }
                    if let Some(m) = matrices
                        .iter()
                        .position(|m| !m.iter().all(|x| x.is_finite()))
                    {
                        return Err(problem(format!("inverse bind matrix {m} is not finite")));
                    }
                    matrices
                        .iter()
                        .take(joints.len())
                        .map(Mat4::from_cols_array)
                        .collect()
                }
            };
            skins.push(Skin {
                name: skin.name.clone(),
                joints,
                inverse_bind,
            });
        }
        Ok(skins)
    }

    /// The joint influences of a skinned primitive's built vertices (`sources`: each
    /// one's vertex in the primitive, of `count`), from every `JOINTS_n`/`WEIGHTS_n`
    /// pair of `attributes`, zero weights left out. Joints must be below `joints` (the
    /// skin's) and weights finite and not negative; a skinned primitive without
    /// `JOINTS_0` is an error.
    pub(crate) fn skin_weights(
        &mut self,
        attributes: &[(String, usize)],
        count: usize,
        sources: &[u32],
        joints: usize,
    ) -> Result<SkinWeights, String> {
        let root = self.root;
        let attribute = |name: String| attributes.iter().find(|(s, _)| *s == name).map(|(_, a)| *a);
        let mut sets = Vec::new();
        while let Some(j) = attribute(format!("JOINTS_{}", sets.len())) {
            let n = sets.len();
            if n == MAX_INFLUENCE_SETS {
                return Err(format!("has more than {MAX_INFLUENCE_SETS} JOINTS_n sets"));
            }
            let w = attribute(format!("WEIGHTS_{n}"))
                .ok_or_else(|| format!("has JOINTS_{n} but no WEIGHTS_{n}"))?;
            self.charge_mesh_bytes((sources.len() as u64).saturating_mul(32))?;
            let js =
                read_joints(root, &mut self.buffers, j).map_err(|e| format!("JOINTS_{n}: {e}"))?;
            let ws = read_unit_floats::<4>(root, &mut self.buffers, w, false)
                .map_err(|e| format!("WEIGHTS_{n}: {e}"))?;
            for (what, len) in [("JOINTS", js.len()), ("WEIGHTS", ws.len())] {
                if len != count {
                    return Err(format!(
                        "{what}_{n} has {len} elements but POSITION has {count}"
                    ));
                }
            }
            sets.push((js, ws));
        }
        if sets.is_empty() {
            return Err("is skinned (its node has a skin) but has no JOINTS_0".into());
        }
        let mut weights = SkinWeights {
            offsets: Vec::with_capacity(sources.len().saturating_add(1)),
            ..SkinWeights::default()
        };
        weights.offsets.push(0);
        for &s in sources {
            for (n, (js, ws)) in sets.iter().enumerate() {
                // Each set holds `count` elements (checked above), and each source is a
                // vertex of the primitive's `count`.
                let (Some(j4), Some(w4)) = (js.get(s as usize), ws.get(s as usize)) else {
                    return Err(format!("vertex {s} is past the {count} of JOINTS_{n}"));
                };
                for (&j, &w) in j4.iter().zip(w4) {
                    if !(w.is_finite() && w >= 0.0) {
                        return Err(format!(
                            "WEIGHTS_{n} of vertex {s} has weight {w}, not finite and non-negative"
                        ));
                    }
                    if w == 0.0 {
                        continue;
                    }
                    if j as usize >= joints {
                        return Err(format!(
                            "JOINTS_{n} of vertex {s} names joint {j}, but the skin has {joints}"
                        ));
                    }
                    weights.joints.push(j);
                    weights.weights.push(w);
                }
            }
            weights.offsets.push(weights.joints.len() as u32);
        }
        Ok(weights)
    }

    /// Primitive `primitive` of mesh `mesh`'s morph targets for its built vertices
    /// (`sources`: each one's vertex in the primitive, of `count`): position, normal and
    /// tangent displacements, each finite, at most [`MAX_MORPH_TARGETS`].
    pub(crate) fn morph_targets(
        &mut self,
        mesh: usize,
        primitive: usize,
        count: usize,
        sources: &[u32],
    ) -> Result<Vec<MorphTarget>, String> {
        let root = self.root;
        let targets = root
            .meshes
            .get(mesh)
            .and_then(|m| m.primitives.get(primitive))
            .and_then(|p| p.targets.as_deref())
            .unwrap_or_default();
        if targets.len() > MAX_MORPH_TARGETS {
            return Err(format!(
                "has {} morph targets, at most {MAX_MORPH_TARGETS}",
                targets.len()
            ));
        }
        let mut out = Vec::with_capacity(targets.len());
        for (t, target) in targets.iter().enumerate() {
            let mut read = |accessor: Option<json::Index<json::Accessor>>,
                            what: &str|
             -> Result<Vec<[f32; 3]>, String> {
                let Some(a) = accessor else {
                    return Ok(Vec::new());
                };
                self.charge_mesh_bytes((sources.len() as u64).saturating_mul(12))?;
                let values = read_floats::<3>(root, &mut self.buffers, a.value())
                    .map_err(|e| format!("morph target {t} {what}: {e}"))?;
                if values.len() != count {
                    return Err(format!(
                        "morph target {t} {what} has {} elements but POSITION has {count}",
                        values.len()
                    ));
                }
                if let Some(v) = values.iter().position(|d| !d.iter().all(|x| x.is_finite())) {
                    return Err(format!(
                        "morph target {t} {what} of vertex {v} is not finite"
                    ));
                }
                sources
                    .iter()
                    .map(|&s| {
                        values.get(s as usize).copied().ok_or_else(|| {
                            format!("morph target {t} {what}: vertex {s} is past its {count}")
                        })
                    })
                    .collect()
            };
            out.push(MorphTarget {
                positions: read(target.positions, "POSITION")?,
                normals: read(target.normals, "NORMAL")?,
                tangents: read(target.tangents, "TANGENT")?,
            });
        }
        Ok(out)
    }

    /// Every animation: its channels (each node and property once; a node given by a
    /// matrix is not animated, glTF's rule) and the samplers they use, key times finite
    /// and strictly increasing, values finite and as many as the keys, the property and
    /// the interpolation ask for; rotations of step and linear samplers normalised (a
    /// zero one is an error). `nodes` gives each node's morph-target count.
    pub(crate) fn animations(&mut self, nodes: &[Node]) -> Result<Vec<Animation>, ImportProblem> {
        let root = self.root;
        let mut animations = Vec::with_capacity(root.animations.len());
        for (a, animation) in root.animations.iter().enumerate() {
            let problem = |m: String| {
                ImportProblem::Invalid(format!(
                    "animation {a}{}: {m}",
                    name_suffix(&animation.name)
                ))
            };
            let mut samplers: Vec<Sampler> = Vec::new();
            // The file's sampler index → ours, with the property it was read for.
            let mut read: HashMap<usize, (usize, Property)> = HashMap::new();
            let mut channels: Vec<Channel> = Vec::with_capacity(animation.channels.len());
            for (c, channel) in animation.channels.iter().enumerate() {
                let node = channel.target.node.value();
                let Some(target) = nodes.get(node) else {
                    return Err(problem(format!("channel {c}'s node {node} does not exist")));
                };
                let property = match channel.target.path {
                    Checked::Valid(json::animation::Property::Translation) => Property::Translation,
                    Checked::Valid(json::animation::Property::Rotation) => Property::Rotation,
                    Checked::Valid(json::animation::Property::Scale) => Property::Scale,
                    Checked::Valid(json::animation::Property::MorphTargetWeights) => {
                        Property::Weights
                    }
                    Checked::Invalid => {
                        return Err(problem(format!("channel {c} has an invalid target path")))
                    }
                };
                if channels
                    .iter()
                    .any(|other| other.node == node && other.property == property)
                {
                    return Err(problem(format!(
                        "channel {c} animates the {} of node {node} a second time",
                        property.name()
                    )));
                }
                match (property, &target.local) {
                    (Property::Weights, _) if target.weights.is_empty() => {
                        return Err(problem(format!(
                            "channel {c} animates the morph weights of node {node}, whose mesh has no morph targets"
                        )))
                    }
                    (Property::Weights, _) => {}
                    (_, LocalTransform::Matrix(_)) => {
                        return Err(problem(format!(
                            "channel {c} animates node {node}, whose transform is a matrix (glTF: such nodes are not animated)"
                        )))
                    }
                    _ => {}
                }
                let s = channel.sampler.value();
                let sampler = match read.get(&s) {
                    Some(&(ours, read_as)) if read_as == property => ours,
                    Some(&(_, read_as)) => {
                        return Err(problem(format!(
                            "sampler {s} drives both the {} and the {}",
                            read_as.name(),
                            property.name()
                        )))
                    }
                    None => {
                        let json = animation.samplers.get(s).ok_or_else(|| {
                            problem(format!("channel {c}'s sampler {s} does not exist"))
                        })?;
                        let sampler = self
                            .sampler(json, property, target.weights.len())
                            .map_err(|e| problem(format!("sampler {s}: {e}")))?;
                        let index = samplers.len();
                        samplers.push(sampler);
                        read.insert(s, (index, property));
                        index
                    }
                };
                channels.push(Channel {
                    node,
                    property,
                    sampler,
                });
            }
            animations.push(Animation {
                name: animation.name.clone(),
                samplers,
                channels,
            });
        }
        Ok(animations)
    }

    /// One sampler read for `property` (`targets` values per key for morph weights).
    fn sampler(
        &mut self,
        json: &json::animation::Sampler,
        property: Property,
        targets: usize,
    ) -> Result<Sampler, String> {
        let root = self.root;
        let interpolation = match json.interpolation {
            Checked::Valid(json::animation::Interpolation::Step) => Interpolation::Step,
            Checked::Valid(json::animation::Interpolation::Linear) => Interpolation::Linear,
            Checked::Valid(json::animation::Interpolation::CubicSpline) => {
                Interpolation::CubicSpline
            }
            Checked::Invalid => return Err("invalid interpolation".into()),
        };
        // Charged before reading, at what the accessors declare (a file may alias one
        // buffer from a thousand samplers).
        let declared = |a: usize| {
            root.accessors.get(a).map_or(0, |a| {
                let width = match a.type_ {
                    Checked::Valid(json::accessor::Type::Vec3) => 3,
                    Checked::Valid(json::accessor::Type::Vec4) => 4,
                    _ => 1,
                };
                a.count.0.saturating_mul(width)
            })
        };
        // Saturating: a count near 2⁶⁴ is charged as more than any budget, not wrapped.
        let floats = declared(json.input.value()).saturating_add(declared(json.output.value()));
        self.charge_mesh_bytes(floats.saturating_mul(4))?;
        let times: Vec<f32> = read_f32::<1>(root, &mut self.buffers, json.input.value())
            .map_err(|e| format!("input: {e}"))?
            .into_iter()
            .map(|[t]| t)
            .collect();
        if times.is_empty() {
            return Err("has no keys".into());
        }
        if let Some(k) = times.iter().position(|t| !t.is_finite()) {
            return Err(format!("key time {k} is not finite"));
        }
        if let Some((k, [before, after])) = times
            .windows(2)
            .filter_map(|w| <[f32; 2]>::try_from(w).ok())
            .enumerate()
            .find(|(_, [a, b])| a >= b)
        {
            return Err(format!(
                "key times must strictly increase, but key {} is {after} after {before}",
                k.saturating_add(1)
            ));
        }
        let output = json.output.value();
        let values: Vec<f32> = match property {
            Property::Translation | Property::Scale => {
                read_f32::<3>(root, &mut self.buffers, output).map(|v| v.concat())
            }
            Property::Rotation => {
                read_unit_floats::<4>(root, &mut self.buffers, output, true).map(|v| v.concat())
            }
            Property::Weights => {
                read_unit_floats::<1>(root, &mut self.buffers, output, true).map(|v| v.concat())
            }
        }
        .map_err(|e| format!("output: {e}"))?;
        let width = match property {
            Property::Translation | Property::Scale => 3,
            Property::Rotation => 4,
            Property::Weights => targets,
        };
        let groups = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        let expected = times.len().saturating_mul(groups).saturating_mul(width);
        if values.len() != expected {
            return Err(format!(
                "has {} output values for {} keys ({expected} expected: {groups} × {width} per key)",
                values.len(),
                times.len()
            ));
        }
        if let Some(v) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!("output value {v} is not finite"));
        }
        let mut sampler = Sampler {
            interpolation,
            times,
            values,
        };
        if property == Property::Rotation && interpolation != Interpolation::CubicSpline {
            for (k, q) in sampler.values.chunks_exact_mut(4).enumerate() {
                let length = Quat::from_slice(q).length();
                if length < 1e-6 {
                    return Err(format!("rotation key {k} is not a unit quaternion"));
                }
                for x in q {
                    *x /= length;
                }
            }
        }
        Ok(sampler)
    }
}
