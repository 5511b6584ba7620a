//! The scene's objects as draws, for every pass that rasterises the scene: the object
//! iteration in the object table's order, each mesh's vertex streams and indices bound
//! when they change, the cull mode of each object's material (double-sided or not), and
//! one indexed draw per object. The G-buffer pass uses it; a depth-only pass (a shadow
//! map) uses it too, with its own pipeline and per-object push constants.

use combustion_vk::ash;
use combustion_vk::vk;

use crate::scene_upload::GpuScene;

/// Which faces of each object a pass rasterises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Faces {
    /// As its material says: front faces only, both for a double-sided material (what
    /// the camera sees).
    OfMaterial,
    /// Both faces of every object (shadow casters: a face blocks light either way).
    Both,
}

/// What a pass learns of each object before it is drawn.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ObjectDraw {
    /// The object's index in the object table (what shaders index it by).
    pub object_index: u32,
    /// Its material's index (the scene's material table and texture sets).
    pub material: usize,
}

/// Records one indexed draw per object of `scene` into `cmd` (recording, inside a
/// rendering instance whose pipeline reads vertex stream 0 — and stream 1, the second
/// coordinate set, if it declares one), culling the faces `faces` says. `per_object`
/// runs before each draw, to bind what the pass binds per object and push its
/// constants.
pub(crate) fn draw_objects(
    raw: &ash::Device,
    cmd: vk::CommandBuffer,
    scene: &GpuScene,
    faces: Faces,
    mut per_object: impl FnMut(ObjectDraw) -> bool,
) {
    let mut bound_mesh = None;
    for (object_index, ((&mesh, &double_sided), &material)) in scene
        .draw_meshes
        .iter()
        .zip(&scene.double_sided)
        .zip(&scene.draw_materials)
        .enumerate()
    {
        let buffers = &scene.gpu.meshes[mesh];
        // SAFETY: recording state (the caller's); the buffers live as long as the scene,
        // which outlives the frame (a dropped scene is retired, not freed).
        unsafe {
            if bound_mesh != Some(mesh) {
                raw.cmd_bind_vertex_buffers(
                    cmd,
                    0,
                    &[buffers.vertices.raw(), buffers.uv1.raw()],
                    &[0, 0],
                );
                raw.cmd_bind_index_buffer(cmd, buffers.indices.raw(), 0, vk::IndexType::UINT32);
                bound_mesh = Some(mesh);
            }
            raw.cmd_set_cull_mode(
                cmd,
                if double_sided || faces == Faces::Both {
                    vk::CullModeFlags::NONE
                } else {
                    vk::CullModeFlags::BACK
                },
            );
        }
        if !per_object(ObjectDraw {
            object_index: object_index as u32,
            material,
        }) {
            continue;
        }
        // SAFETY: as above.
        unsafe { raw.cmd_draw_indexed(cmd, buffers.index_count, 1, 0, 0, 0) };
    }
}
