//! Morph targets and skins on the GPU: a compute pass (deform.comp) at the top of the
//! frame writes each deformed object's posed vertices, which every pass that draws the
//! scene then reads as the object's first vertex stream (G-buffer, shadow maps, back
//! faces, forward) — one posing per frame however many passes draw it.
//!
//! What the scene holds (made at upload, only for a scene with deformed objects: an
//! object hanging from a node whose mesh has morph targets, or joint influences and a
//! skinned node): each deformed mesh's rest vertices, influences and displacements once,
//! and one posed stream per deformed object. What a frame brings (its pose, else the
//! scene at rest): the skins' joint matrices and the objects' morph weights, written into
//! the frame slot like its lights. A scene without deformed objects has none of it: no
//! pass, no buffer, no pipeline. The pass and its pipeline are `passes/deform.rs`.

use std::sync::Arc;

use combustion_scene::{ObjectPoses, Scene};
use combustion_vk::{vk, Buffer, Device};
use glam::{Mat4, Vec3};

use crate::error::RenderError;
use crate::gpu_types::GpuVertex;
use crate::placement::Bounds;

/// The deform pass's push constants (`DeformPush` in deform.comp).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct DeformPush {
    /// First rest vertex, vertex count, first posed vertex, first displacement (vec4s).
    pub vertices: [u32; 4],
    /// Target count, first weight, first joint matrix (`NOT_SKINNED`: none), unused.
    pub deform: [u32; 4],
}

/// `DeformPush::deform[2]` of an object that is morphed only.
const NOT_SKINNED: u32 = u32::MAX;

/// Invocations per workgroup (`local_size_x` in deform.comp).
pub(crate) const GROUP: u32 = 64;

/// One deformed object of the scene.
pub(crate) struct DeformedObject {
    pub push: DeformPush,
    /// What its boxes in a pose are made from.
    shape: DeformShape,
}

impl DeformedObject {
    /// Its index in the object table.
    pub(crate) fn object(&self) -> usize {
        self.shape.object
    }
}

/// What bounds a deformed object in any pose: its skin, the rest box of what each of
/// its joints moves, and how far its morph targets can move a vertex.
pub(crate) struct DeformShape {
    /// The object (index into the scene's objects).
    object: usize,
    /// Its skin (index into the scene's skins), if its joints place it.
    skin: Option<usize>,
    /// Per joint influencing its mesh: the joint, and the box (in the mesh's bind space)
    /// of the rest vertices it influences.
    joint_boxes: Vec<(u32, Bounds)>,
    /// Its mesh's box at rest, in its own space.
    mesh_box: Option<Bounds>,
    /// Per morph target, the largest displacement of a position along each axis.
    target_extents: Vec<Vec3>,
}

impl DeformShape {
    /// Object `object` of `scene`, placed by `skin` if skinned.
    pub(crate) fn of(scene: &Scene, object: usize, skin: Option<usize>) -> Self {
        let mesh = &scene.meshes[scene.objects[object].mesh];
        let mut joint_boxes: Vec<(u32, Bounds)> = Vec::new();
        if let (Some(_), Some(weights)) = (skin, &mesh.skin) {
            let mut boxes: std::collections::BTreeMap<u32, Bounds> = Default::default();
            for (v, vertex) in mesh.vertices.iter().enumerate() {
                let p = Vec3::from(vertex.position);
                for (j, _) in weights.influences(v) {
                    let b = boxes.entry(j).or_insert((p, p));
                    *b = (b.0.min(p), b.1.max(p));
                }
            }
            joint_boxes = boxes.into_iter().collect();
        }
        let target_extents = mesh
            .morph_targets
            .iter()
            .map(|t| {
                t.positions
                    .iter()
                    .fold(Vec3::ZERO, |m, d| m.max(Vec3::from(*d).abs()))
            })
            .collect();
        Self {
            object,
            skin,
            joint_boxes,
            mesh_box: mesh.bounds(),
            target_extents,
        }
    }

    /// Its world box in `poses` (it holds every posed vertex for joint weights that sum
    /// to at most 1): a skinned object's is the union of its joints' boxes placed by the
    /// joints' matrices, each grown by the weighted largest morph displacements; a
    /// morphed one's, its mesh's box grown the same way, placed by its transform.
    pub(crate) fn bounds(&self, poses: &ObjectPoses) -> Option<Bounds> {
        let weights = &poses.weights[self.object];
        let margin = self
            .target_extents
            .iter()
            .zip(weights)
            .fold(Vec3::ZERO, |m, (e, w)| m + *e * w.abs());
        let grow = |(lo, hi): Bounds| Some((lo - margin, hi + margin));
        match self.skin {
            Some(skin) => self
                .joint_boxes
                .iter()
                .filter_map(|&(j, b)| {
                    combustion_scene::placed_bounds(grow(b), &poses.joints[skin][j as usize])
                })
                .reduce(|(a, b), (c, e)| (a.min(c), b.max(e))),
            None => combustion_scene::placed_bounds(
                self.mesh_box.and_then(grow),
                &poses.transforms[self.object],
            ),
        }
    }
}

/// A scene's deformed objects on the GPU.
pub(crate) struct SceneDeform {
    /// Every deformed mesh's rest vertices (`GpuVertex`), each mesh once.
    pub rest: Buffer,
    /// Per rest vertex, its first influence and their count (`uvec2`).
    pub ranges: Buffer,
    /// Influences: the joint (within its skin) and the weight's bits (`uvec2`).
    pub influences: Buffer,
    /// Per target of each morphed mesh, per vertex: position, normal and tangent
    /// displacements (`vec4` each).
    pub displacements: Buffer,
    /// Every deformed object's posed vertices (`GpuVertex`), written by the pass and
    /// read as vertex stream 0.
    pub posed: Buffer,
    /// The objects, in object-table order.
    pub objects: Vec<DeformedObject>,
    /// Per object of the scene, the byte offset of its posed vertices in `posed` (`None`:
    /// it is not deformed and draws its mesh's own).
    pub posed_offsets: Vec<Option<u64>>,
    /// The scene at rest (what a frame without a pose shows).
    pub rest_poses: ObjectPoses,
}

/// Whether object `i` of `scene` is skinned (its node has a skin, its mesh influences)
/// and whether it is morphed (its mesh has targets and it hangs from a node).
pub(crate) fn deformation(scene: &Scene, i: usize) -> (bool, bool) {
    let object = &scene.objects[i];
    let mesh = &scene.meshes[object.mesh];
    let Some(link) = object.node else {
        return (false, false);
    };
    let skinned = mesh.skin.is_some() && scene.motion.nodes[link.node].skin.is_some();
    (skinned, !mesh.morph_targets.is_empty())
}

fn bytes_of<T: bytemuck::Pod>(values: &[T]) -> &[u8] {
    bytemuck::cast_slice(values)
}

impl SceneDeform {
    /// The deformed objects of `scene` (validated) and their buffers; `None` when it has
    /// none.
    pub(crate) fn new(device: &Arc<Device>, scene: &Scene) -> Result<Option<Self>, RenderError> {
        let deformed: Vec<(usize, bool, bool)> = (0..scene.objects.len())
            .map(|i| {
                let (skinned, morphed) = deformation(scene, i);
                (i, skinned, morphed)
            })
            .filter(|&(_, skinned, morphed)| skinned || morphed)
            .collect();
        if deformed.is_empty() {
            return Ok(None);
        }
        let mut skin_bases = Vec::with_capacity(scene.motion.skins.len());
        let mut joint_count = 0;
        for skin in &scene.motion.skins {
            skin_bases.push(joint_count);
            joint_count += skin.joints.len();
        }
        // Each deformed mesh's rest data once.
        let mut rest: Vec<GpuVertex> = Vec::new();
        let mut ranges: Vec<[u32; 2]> = Vec::new();
        let mut influences: Vec<[u32; 2]> = Vec::new();
        let mut displacements: Vec<[f32; 4]> = Vec::new();
        // Per mesh: (first rest vertex, first displacement).
        let mut mesh_bases: std::collections::HashMap<usize, (u32, u32)> = Default::default();
        let too_large = |what: &str| {
            RenderError::TooLarge(format!("the deformed meshes' {what} exceed 2³² entries"))
        };
        let mut objects = Vec::with_capacity(deformed.len());
        let mut posed_offsets = vec![None; scene.objects.len()];
        let (mut posed_vertices, mut weight_count) = (0u64, 0usize);
        for &(i, skinned, _) in &deformed {
            let object = &scene.objects[i];
            let mesh = &scene.meshes[object.mesh];
            let (rest_base, displacement_base) = match mesh_bases.get(&object.mesh) {
                Some(&bases) => bases,
                None => {
                    let bases = (
                        u32::try_from(rest.len()).map_err(|_| too_large("vertices"))?,
                        u32::try_from(displacements.len())
                            .map_err(|_| too_large("displacements"))?,
                    );
                    rest.extend(mesh.vertices.iter().map(GpuVertex::new));
                    for v in 0..mesh.vertices.len() {
                        let start =
                            u32::try_from(influences.len()).map_err(|_| too_large("influences"))?;
                        if let Some(skin) = &mesh.skin {
                            influences.extend(skin.influences(v).map(|(j, w)| [j, w.to_bits()]));
                        }
                        ranges.push([start, influences.len() as u32 - start]);
                    }
                    for target in &mesh.morph_targets {
                        let d = |list: &[[f32; 3]], v: usize| {
                            list.get(v).map_or([0.0; 4], |d| [d[0], d[1], d[2], 0.0])
                        };
                        for v in 0..mesh.vertices.len() {
                            displacements.push(d(&target.positions, v));
                            displacements.push(d(&target.normals, v));
                            displacements.push(d(&target.tangents, v));
                        }
                    }
                    mesh_bases.insert(object.mesh, bases);
                    bases
                }
            };
            let link = object.node.expect("a deformed object hangs from a node");
            let skin = if skinned {
                scene.motion.nodes[link.node].skin
            } else {
                None
            };
            let vertex_count = mesh.vertices.len() as u32;
            let push = DeformPush {
                vertices: [
                    rest_base,
                    vertex_count,
                    u32::try_from(posed_vertices).map_err(|_| too_large("posed vertices"))?,
                    displacement_base,
                ],
                deform: [
                    mesh.morph_targets.len() as u32,
                    weight_count as u32,
                    skin.map_or(NOT_SKINNED, |s| skin_bases[s] as u32),
                    0,
                ],
            };
            posed_offsets[i] = Some(posed_vertices * std::mem::size_of::<GpuVertex>() as u64);
            posed_vertices += u64::from(vertex_count);
            weight_count += mesh.morph_targets.len();
            objects.push(DeformedObject {
                push,
                shape: DeformShape::of(scene, i, skin),
            });
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let filled = |name: &str, bytes: &[u8]| -> Result<Buffer, RenderError> {
            let bytes = if bytes.is_empty() {
                &[0u8; 16][..]
            } else {
                bytes
            };
            Ok(Buffer::with_data(device, name, bytes, storage)?)
        };
        let posed_bytes = (posed_vertices * std::mem::size_of::<GpuVertex>() as u64).max(4);
        // On a device with ray queries the posed vertices are also what the deformed
        // objects' acceleration structures are built from (crate::accel).
        let traceable = if device.ray_queries() {
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
                | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS
        } else {
            vk::BufferUsageFlags::empty()
        };
        Ok(Some(Self {
            rest: filled("deform rest vertices", bytes_of(&rest))?,
            ranges: filled("deform influence ranges", bytes_of(&ranges))?,
            influences: filled("deform influences", bytes_of(&influences))?,
            displacements: filled("deform displacements", bytes_of(&displacements))?,
            posed: Buffer::new(
                device,
                "posed vertices",
                posed_bytes,
                storage
                    | vk::BufferUsageFlags::VERTEX_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | traceable,
                crate::buffers::GPU_ONLY,
            )?,
            objects,
            posed_offsets,
            rest_poses: scene.pose_objects(&scene.motion.rest_pose()),
        }))
    }

    /// The joint matrices (skin after skin) and morph weights (deformed object after
    /// object) a frame in `poses` gives the pass, as it reads them.
    pub(crate) fn frame_inputs(&self, poses: &ObjectPoses) -> (Vec<Mat4>, Vec<f32>) {
        let weights = self
            .objects
            .iter()
            .flat_map(|object| {
                let given = &poses.weights[object.object()];
                let targets = object.push.deform[0] as usize;
                (0..targets).map(move |t| given.get(t).copied().unwrap_or(0.0))
            })
            .collect();
        (poses.joints.concat(), weights)
    }

    /// Per deformed object, its world box in `poses` ([`DeformShape::bounds`]).
    pub(crate) fn bounds<'a>(
        &'a self,
        poses: &'a ObjectPoses,
    ) -> impl Iterator<Item = (usize, Option<Bounds>)> + 'a {
        self.objects
            .iter()
            .map(move |d| (d.object(), d.shape.bounds(poses)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use combustion_scene::motion::{LocalTransform, MorphTarget, Node, Skin, SkinWeights};
    use combustion_scene::{Mesh, NodeLink, Object};
    use glam::{Mat4, Quat};

    /// A sphere whose upper half rides joint 1 (a child of joint 0), blended over its
    /// middle, with a target swelling its upper half; placed by node 0.
    fn bending_sphere() -> Scene {
        let mut scene = combustion_scene::builtin_scene("spheres").unwrap();
        let mut mesh = Mesh::uv_sphere("bending", 0.5, 24, 12);
        let weights = SkinWeights::from_influences(mesh.vertices.iter().map(|v| {
            let upper = ((v.position[1] + 1.0 / 6.0) * 3.0).clamp(0.0, 1.0);
            [(0, 1.0 - upper), (1, upper)]
        }));
        mesh.morph_targets = vec![MorphTarget {
            positions: mesh
                .vertices
                .iter()
                .map(|v| (Vec3::from(v.normal) * v.position[1].max(0.0)).to_array())
                .collect(),
            ..MorphTarget::default()
        }];
        mesh.skin = Some(weights);
        scene.meshes.push(mesh);
        let node = |parent, translation: Vec3, skin, weights: Vec<f32>| Node {
            name: None,
            parent,
            local: LocalTransform::Trs {
                translation,
                rotation: Quat::IDENTITY,
                scale: Vec3::ONE,
            },
            skin,
            weights,
        };
        scene.motion.nodes = vec![
            node(None, Vec3::ZERO, Some(0), vec![0.0]),
            node(None, Vec3::new(0.3, 0.0, 0.0), None, Vec::new()),
            node(Some(1), Vec3::new(0.0, 0.5, 0.0), None, Vec::new()),
        ];
        scene.motion.skins = vec![Skin {
            name: None,
            joints: vec![1, 2],
            inverse_bind: vec![
                Mat4::IDENTITY,
                Mat4::from_translation(Vec3::new(0.0, -0.5, 0.0)),
            ],
        }];
        scene.objects.push(Object {
            node: Some(NodeLink {
                node: 0,
                offset: Mat4::IDENTITY,
            }),
            ..Object::casting_shadows(scene.meshes.len() - 1, 0, Mat4::IDENTITY)
        });
        scene.validate().unwrap();
        scene
    }

    /// The box of a skinned and morphed object holds every vertex posed
    /// (`combustion_scene::motion::pose_vertex`) in poses that turn, move and scale its
    /// joints and swell its target; and it follows the pose (it moves with the joints).
    #[test]
    fn the_box_of_a_deformed_object_holds_every_posed_vertex() {
        let scene = bending_sphere();
        let object = scene.objects.len() - 1;
        let shape = DeformShape::of(&scene, object, Some(0));
        let mesh = &scene.meshes[scene.objects[object].mesh];
        let mut centres = Vec::new();
        for k in 0..12 {
            let a = k as f32 * 0.7;
            let mut pose = scene.motion.rest_pose();
            pose.locals[1] = LocalTransform::Trs {
                translation: Vec3::new(0.3 + a.sin(), 0.2 * a, -a.cos()),
                rotation: Quat::from_rotation_y(a),
                scale: Vec3::splat(1.0 + 0.1 * k as f32),
            };
            pose.locals[2] = LocalTransform::Trs {
                translation: Vec3::new(0.0, 0.5, 0.0),
                rotation: Quat::from_rotation_z(0.4 * a) * Quat::from_rotation_x(0.3 * a),
                scale: Vec3::new(1.0, 0.5 + 0.2 * k as f32, 1.0),
            };
            pose.weights[0] = vec![(k as f32 / 11.0) * 2.0 - 0.5];
            let poses = scene.pose_objects(&pose);
            let (lo, hi) = shape.bounds(&poses).expect("a box");
            let joints = scene.object_joints(object, &poses);
            let slack = 1e-5 * (hi - lo).max_element();
            for v in 0..mesh.vertices.len() {
                let p = Vec3::from(
                    combustion_scene::motion::pose_vertex(
                        mesh,
                        v,
                        &poses.weights[object],
                        joints,
                        &poses.transforms[object],
                    )
                    .position,
                );
                assert!(
                    p.cmpge(lo - slack).all() && p.cmple(hi + slack).all(),
                    "pose {k}: vertex {v} at {p} outside {lo} … {hi}"
                );
            }
            centres.push((lo + hi) * 0.5);
        }
        assert!(
            centres.windows(2).all(|w| w[0] != w[1]),
            "the box does not move"
        );
    }
}
