//! The scene's pose in f64: an animation sampled at a time, node world transforms,
//! skin joint matrices, and every object's vertices morphed and skinned in world space,
//! from the scene's [`Motion`] and meshes alone (the player's f32 arithmetic, and the
//! renderer's, are what this measures).
//!
//! The rules are glTF's, written again here in f64 rather than shared: keys are clamped
//! at both ends; STEP holds the previous key; LINEAR interpolates linearly and rotations
//! along the shorter great arc; CUBICSPLINE is the cubic Hermite spline of each key's
//! value and tangents (scaled by the interval), a rotation normalised after. A vertex is
//! morphed (rest plus the weighted displacements), then placed by the weighted sum of its
//! joints' `world · inverse_bind` (or, without influences, by the object's transform);
//! its normal by that sum's inverse transpose, its tangent by the sum, both normalised.

use combustion_scene::motion::{Interpolation, LocalTransform, Motion, Property, Sampler};
use combustion_scene::Scene;
use glam::{DMat3, DMat4, DQuat, DVec3, DVec4};

/// Every node's local transform and weights at one moment, in f64.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseF64 {
    /// Per node, its local transform.
    pub locals: Vec<DMat4>,
    /// Per node, its morph weights.
    pub weights: Vec<Vec<f64>>,
}

/// One vertex placed in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PosedVertex {
    /// Position, metres.
    pub position: DVec3,
    /// Unit normal.
    pub normal: DVec3,
    /// Unit tangent (its sign w is the mesh's).
    pub tangent: DVec3,
}

fn trs(translation: DVec3, rotation: DQuat, scale: DVec3) -> DMat4 {
    DMat4::from_scale_rotation_translation(scale, rotation, translation)
}

fn local_f64(local: &LocalTransform) -> (DVec3, DQuat, DVec3, Option<DMat4>) {
    match *local {
        LocalTransform::Trs {
            translation,
            rotation,
            scale,
        } => (
            translation.as_dvec3(),
            rotation.as_dquat(),
            scale.as_dvec3(),
            None,
        ),
        LocalTransform::Matrix(m) => (DVec3::ZERO, DQuat::IDENTITY, DVec3::ONE, Some(m.as_dmat4())),
    }
}

/// The shorter-arc spherical interpolation, in f64 (linear, normalised, within 1e-9 of
/// parallel).
pub fn slerp_f64(q0: DQuat, q1: DQuat, s: f64) -> DQuat {
    let q0 = DVec4::from(q0.to_array());
    let mut q1 = DVec4::from(q1.to_array());
    let mut cos = q0.dot(q1);
    if cos < 0.0 {
        q1 = -q1;
        cos = -cos;
    }
    let q = if cos > 1.0 - 1e-9 {
        q0 + (q1 - q0) * s
    } else {
        let angle = cos.min(1.0).acos();
        (q0 * ((1.0 - s) * angle).sin() + q1 * (s * angle).sin()) / angle.sin()
    };
    DQuat::from_vec4(q.normalize())
}

/// Sampler `sampler`'s `width` values at `time`, in f64 (a rotation when `rotation`).
pub fn sample_f64(sampler: &Sampler, time: f64, width: usize, rotation: bool) -> Vec<f64> {
    let cubic = sampler.interpolation == Interpolation::CubicSpline;
    let groups = if cubic { 3 } else { 1 };
    let group = |k: usize, g: usize| -> Vec<f64> {
        let start = (k * groups + g) * width;
        sampler.values[start..start + width]
            .iter()
            .map(|&v| f64::from(v))
            .collect()
    };
    let value = usize::from(cubic);
    let times: Vec<f64> = sampler.times.iter().map(|&t| f64::from(t)).collect();
    let last = times.len() - 1;
    if time <= times[0] {
        return group(0, value);
    }
    if time >= times[last] {
        return group(last, value);
    }
    let k = times.iter().rposition(|&t| t <= time).unwrap_or(0);
    let dt = times[k + 1] - times[k];
    let s = (time - times[k]) / dt;
    let mut out = match sampler.interpolation {
        Interpolation::Step => group(k, 0),
        Interpolation::Linear if rotation => {
            let q = |v: Vec<f64>| DQuat::from_xyzw(v[0], v[1], v[2], v[3]);
            slerp_f64(q(group(k, 0)), q(group(k + 1, 0)), s)
                .to_array()
                .to_vec()
        }
        Interpolation::Linear => {
            let (a, b) = (group(k, 0), group(k + 1, 0));
            a.iter().zip(&b).map(|(a, b)| a + (b - a) * s).collect()
        }
        Interpolation::CubicSpline => {
            let (v0, b0, v1, a1) = (group(k, 1), group(k, 2), group(k + 1, 1), group(k + 1, 0));
            let (s2, s3) = (s * s, s * s * s);
            (0..width)
                .map(|i| {
                    (2.0 * s3 - 3.0 * s2 + 1.0) * v0[i]
                        + (s3 - 2.0 * s2 + s) * dt * b0[i]
                        + (-2.0 * s3 + 3.0 * s2) * v1[i]
                        + (s3 - s2) * dt * a1[i]
                })
                .collect()
        }
    };
    if rotation {
        let length = out.iter().map(|x| x * x).sum::<f64>().sqrt();
        out.iter_mut().for_each(|x| *x /= length);
    }
    out
}

/// The pose of `motion` with animation `animation` at `time` (`None`: at rest).
pub fn pose_f64(motion: &Motion, animation: Option<(usize, f64)>) -> PoseF64 {
    let mut parts: Vec<_> = motion.nodes.iter().map(|n| local_f64(&n.local)).collect();
    let mut weights: Vec<Vec<f64>> = motion
        .nodes
        .iter()
        .map(|n| n.weights.iter().map(|&w| f64::from(w)).collect())
        .collect();
    if let Some(animation) = animation.and_then(|(a, t)| Some((motion.animations.get(a)?, t))) {
        let (animation, time) = animation;
        for channel in &animation.channels {
            let sampler = &animation.samplers[channel.sampler];
            let (t, r, s, matrix) = &mut parts[channel.node];
            if matrix.is_some() && channel.property != Property::Weights {
                continue;
            }
            match channel.property {
                Property::Translation => {
                    *t = DVec3::from_slice(&sample_f64(sampler, time, 3, false))
                }
                Property::Scale => *s = DVec3::from_slice(&sample_f64(sampler, time, 3, false)),
                Property::Rotation => {
                    let v = sample_f64(sampler, time, 4, true);
                    *r = DQuat::from_xyzw(v[0], v[1], v[2], v[3]);
                }
                Property::Weights => {
                    let width = weights[channel.node].len();
                    weights[channel.node] = sample_f64(sampler, time, width, false);
                }
            }
        }
    }
    PoseF64 {
        locals: parts
            .into_iter()
            .map(|(t, r, s, m)| m.unwrap_or_else(|| trs(t, r, s)))
            .collect(),
        weights,
    }
}

/// Each node's world transform in `pose` (recursively up the parents; the hierarchy
/// must be a forest).
pub fn world_f64(motion: &Motion, pose: &PoseF64) -> Vec<DMat4> {
    fn world(motion: &Motion, pose: &PoseF64, n: usize, memo: &mut Vec<Option<DMat4>>) -> DMat4 {
        if let Some(m) = memo[n] {
            return m;
        }
        let local = pose.locals[n];
        let m = match motion.nodes[n].parent {
            Some(p) => world(motion, pose, p, memo) * local,
            None => local,
        };
        memo[n] = Some(m);
        m
    }
    let mut memo = vec![None; motion.nodes.len()];
    (0..motion.nodes.len())
        .map(|n| world(motion, pose, n, &mut memo))
        .collect()
}

/// Every object's vertices, morphed and placed in world space, in the pose of
/// `animation` at `time` (`None`: at rest), in f64. Objects without a node keep their
/// transform and shape.
pub fn posed_objects(scene: &Scene, animation: Option<(usize, f64)>) -> Vec<Vec<PosedVertex>> {
    let motion = &scene.motion;
    let pose = pose_f64(motion, animation);
    let world = world_f64(motion, &pose);
    let joints: Vec<Vec<DMat4>> = motion
        .skins
        .iter()
        .map(|skin| {
            skin.joints
                .iter()
                .zip(&skin.inverse_bind)
                .map(|(&j, ibm)| world[j] * ibm.as_dmat4())
                .collect()
        })
        .collect();
    scene
        .objects
        .iter()
        .map(|object| {
            let mesh = &scene.meshes[object.mesh];
            // A skinned object's joints place it in world space (a vertex without
            // influences stays where it is); the others are placed by their node.
            let (transform, weights, skin) = match object.node {
                Some(link) => {
                    let skin = motion.nodes[link.node]
                        .skin
                        .and_then(|s| joints.get(s))
                        .filter(|_| mesh.skin.is_some());
                    let transform = match skin {
                        Some(_) => DMat4::IDENTITY,
                        None => world[link.node] * link.offset.as_dmat4(),
                    };
                    (transform, pose.weights[link.node].clone(), skin)
                }
                None => (object.transform.as_dmat4(), Vec::new(), None),
            };
            (0..mesh.vertices.len())
                .map(|v| {
                    let vertex = &mesh.vertices[v];
                    let mut p = DVec3::from(vertex.position.map(f64::from));
                    let mut n = DVec3::from(vertex.normal.map(f64::from));
                    let mut t = DVec3::new(
                        f64::from(vertex.tangent[0]),
                        f64::from(vertex.tangent[1]),
                        f64::from(vertex.tangent[2]),
                    );
                    for (target, &w) in mesh.morph_targets.iter().zip(&weights) {
                        let d = |list: &[[f32; 3]]| {
                            list.get(v)
                                .map_or(DVec3::ZERO, |d| DVec3::from(d.map(f64::from)))
                        };
                        p += d(&target.positions) * w;
                        n += d(&target.normals) * w;
                        t += d(&target.tangents) * w;
                    }
                    let m = match (skin, &mesh.skin) {
                        (Some(joints), Some(influences)) => {
                            let mut sum = None;
                            for (j, w) in influences.influences(v) {
                                sum = Some(
                                    sum.unwrap_or(DMat4::ZERO) + joints[j as usize] * f64::from(w),
                                );
                            }
                            sum.unwrap_or(transform)
                        }
                        _ => transform,
                    };
                    let linear = DMat3::from_mat4(m);
                    PosedVertex {
                        position: m.transform_point3(p),
                        normal: (linear.inverse().transpose() * n).normalize_or_zero(),
                        tangent: (linear * t).normalize_or_zero(),
                    }
                })
                .collect()
        })
        .collect()
}
