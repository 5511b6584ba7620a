//! Where a frame's objects are: as the scene was uploaded, or where the frame's pose
//! ([`crate::FrameInputs::pose`]) puts them. A posed frame writes its own object table
//! into its frame slot (host-visible, so no barrier and no copy: the passes' vertex
//! stages read it in place of the scene's), with each object's world box and the
//! scene's, which shadow cascades, shadow-caster culling and the forward pass's
//! back-to-front order use. A frame without a pose reads the scene's own table and
//! boxes: a still scene pays nothing.

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use combustion_scene::{ObjectPoses, Scene};
use combustion_vk::{Buffer, Device};
use glam::{Mat4, Vec3};

use crate::buffers::{storage_buffer, write_growing, CPU_TO_GPU};
use crate::error::RenderError;
use crate::gpu_types::GpuObject;
use crate::scene_upload::GpuScene;

/// A box in world space: its (min, max) corners.
pub(crate) type Bounds = (Vec3, Vec3);

const OBJECT_TABLE: &str = "frame object table";

/// Checks a frame's pose against `scene`: one transform per object, each finite (a
/// singular one, a node scaled to 0, hides its object); one weight per morph target for each object whose mesh has targets, each
/// finite; one matrix per joint for each skin, each finite.
pub(crate) fn check_pose(scene: &Scene, pose: &ObjectPoses) -> Result<(), RenderError> {
    let invalid = |what: String| Err(RenderError::InvalidPose(what));
    let objects = scene.objects.len();
    if pose.transforms.len() != objects || pose.weights.len() != objects {
        return invalid(format!(
            "{} transforms and {} weight lists for {objects} objects",
            pose.transforms.len(),
            pose.weights.len()
        ));
    }
    for (i, (object, transform)) in scene.objects.iter().zip(&pose.transforms).enumerate() {
        if !transform.is_finite() {
            return invalid(format!("object {i}'s transform is not finite"));
        }
        let targets = scene.meshes[object.mesh].morph_targets.len();
        let weights = &pose.weights[i];
        if targets > 0 && (weights.len() != targets || !weights.iter().all(|w| w.is_finite())) {
            return invalid(format!(
                "object {i} has {} morph weights for {targets} targets, or a non-finite one",
                weights.len()
            ));
        }
    }
    if pose.joints.len() != scene.motion.skins.len() {
        return invalid(format!(
            "{} joint lists for {} skins",
            pose.joints.len(),
            scene.motion.skins.len()
        ));
    }
    for (s, (joints, skin)) in pose.joints.iter().zip(&scene.motion.skins).enumerate() {
        if joints.len() != skin.joints.len() || !joints.iter().all(|m| m.is_finite()) {
            return invalid(format!(
                "skin {s} has {} joint matrices for {} joints, or a non-finite one",
                joints.len(),
                skin.joints.len()
            ));
        }
    }
    Ok(())
}

/// A frame slot's placement of the objects, for its frame's pose.
pub(crate) struct SlotPlacement {
    /// The object table of the slot's frame when it has a pose (grows).
    table: Buffer,
    /// Whether the slot's frame has a pose (else it reads the scene's own table).
    posed: bool,
    /// Per object, its transform in the pose.
    transforms: Vec<Mat4>,
    /// Per object, its world box in the pose.
    bounds: Vec<Option<Bounds>>,
    world_bounds: Option<Bounds>,
    /// A digest of the pose: shadow maps rendered in one pose are kept while the frames'
    /// pose digests the same.
    key: u64,
}

impl SlotPlacement {
    pub(crate) fn new(device: &Arc<Device>) -> Result<Self, RenderError> {
        Ok(Self {
            table: storage_buffer(
                device,
                OBJECT_TABLE,
                std::mem::size_of::<GpuObject>() as u64,
                CPU_TO_GPU,
            )?,
            posed: false,
            transforms: Vec::new(),
            bounds: Vec::new(),
            world_bounds: None,
            key: 0,
        })
    }

    /// Places `scene`'s objects for the slot's frame: as uploaded without a pose, else
    /// where `pose` (checked: [`check_pose`]) puts them. The slot's previous frame has
    /// completed.
    pub(crate) fn place(
        &mut self,
        device: &Arc<Device>,
        scene: &GpuScene,
        pose: Option<&ObjectPoses>,
    ) -> Result<(), RenderError> {
        let Some(pose) = pose else {
            self.posed = false;
            return Ok(());
        };
        // The table's entries made again from the scene (not kept as uploaded: 144 bytes
        // an object, 144 MB for a million placements), placed by the pose; whether a
        // mesh has colours was found at upload.
        let table: Vec<GpuObject> = scene
            .scene()
            .objects
            .iter()
            .zip(&pose.transforms)
            .map(|(object, transform)| {
                GpuObject::new(object, scene.mesh_colors[object.mesh]).placed(transform)
            })
            .collect();
        write_growing(
            device,
            &mut self.table,
            OBJECT_TABLE,
            bytemuck::cast_slice(&table),
        )?;
        self.transforms.clone_from(&pose.transforms);
        self.bounds = scene
            .scene()
            .objects
            .iter()
            .zip(&pose.transforms)
            .map(|(object, transform)| {
                combustion_scene::placed_bounds(scene.mesh_bounds[object.mesh], transform)
            })
            .collect();
        if let Some(deform) = &scene.gpu.deform {
            for (object, bounds) in deform.bounds(pose) {
                self.bounds[object] = bounds;
            }
        }
        self.world_bounds = self
            .bounds
            .iter()
            .flatten()
            .copied()
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)));
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        for m in pose.transforms.iter().chain(pose.joints.iter().flatten()) {
            m.to_cols_array().map(f32::to_bits).hash(&mut hasher);
        }
        for w in pose.weights.iter().flatten() {
            w.to_bits().hash(&mut hasher);
        }
        self.key = hasher.finish() | 1;
        self.posed = true;
        Ok(())
    }

    /// The placement the slot's frame draws `scene` with.
    pub(crate) fn of<'a>(&'a self, scene: &'a GpuScene) -> Placement<'a> {
        if self.posed {
            Placement {
                table: &self.table,
                transforms: Some(&self.transforms),
                bounds: &self.bounds,
                world_bounds: self.world_bounds,
                key: self.key,
            }
        } else {
            Placement {
                table: &scene.gpu.objects,
                transforms: None,
                bounds: &scene.object_bounds,
                world_bounds: scene.world_bounds,
                key: 0,
            }
        }
    }
}

/// Where one frame's objects are.
#[derive(Clone, Copy)]
pub(crate) struct Placement<'a> {
    /// The object table the vertex stages read.
    pub table: &'a Buffer,
    /// Per object, its transform (`None`: the scene's own).
    transforms: Option<&'a [Mat4]>,
    /// Per object, its world box.
    pub bounds: &'a [Option<Bounds>],
    /// The box around every object.
    pub world_bounds: Option<Bounds>,
    /// 0 for the scene as uploaded, else a digest of the pose.
    pub key: u64,
}

impl Placement<'_> {
    /// Object `index`'s transform this frame (a skinned object's is the identity: its
    /// joints place its posed vertices in world space, as the object table says).
    pub(crate) fn transform(&self, scene: &GpuScene, index: usize) -> Mat4 {
        match self.transforms {
            Some(transforms) => transforms[index],
            None if crate::deform::deformation(scene.scene(), index).0 => Mat4::IDENTITY,
            None => scene.scene().objects[index].transform,
        }
    }
}
