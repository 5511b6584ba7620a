//! What the passes that trace rays bind (the ray-traced occlusion and shadows passes, and
//! the lighting pass for the sampled environment's directions): the scene's top-level
//! structure and the tables its cut-outs are tested against (`crate::accel`;
//! traced_scene.glsl's `scene_blocks`), or the renderer's empty ones where a frame traces
//! nothing.

use combustion_vk::vk;

use super::FrameContext;
use crate::accel::TracedCutouts;
use crate::bindings::Binding;
use crate::pass_io::PassIo;

/// The four bindings, read by `stages`, declared in GLSL only with `only_with` if given
/// (`crate::bindings::traced_scene`).
pub(super) const fn bindings(
    stages: vk::ShaderStageFlags,
    only_with: Option<&'static str>,
) -> [Binding; 4] {
    crate::bindings::traced_scene(stages, only_with)
}

/// Records the build of the frame's traced scene (its deformed objects' structures and
/// its slot's top level, each object where the frame places it), once per frame: the
/// first traced pass of a frame builds it, the others find it built.
pub(super) fn record_build(frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
    let structures = frame
        .scene
        .gpu
        .structures
        .get()
        .expect("frames that trace have their scene's structures");
    let when = (frame.slot.index, frame.number, frame.placement.key);
    structures.record_build(frame.device, cmd, when, |object| {
        frame.placement.transform(frame.scene, object)
    });
}

/// `io` with the frame's traced scene bound: its slot's top-level structure (built by
/// the frame's first traced pass) and its cut-outs' tables.
pub(super) fn scene(io: PassIo, frame: &FrameContext<'_>) -> PassIo {
    let structures = frame
        .scene
        .gpu
        .structures
        .get()
        .expect("frames that trace have their scene's structures (checked at record)");
    bound(
        io,
        structures.top_level(frame.slot.index),
        &structures.cutouts,
    )
}

/// `io` with the renderer's empty structure and tables bound (a frame that traces
/// nothing; devices with ray queries only).
pub(super) fn nothing(io: PassIo, frame: &FrameContext<'_>) -> PassIo {
    let (top_level, cutouts) = frame
        .shared
        .no_scene
        .as_ref()
        .expect("devices with ray queries have the empty structure");
    bound(io, top_level.handle(), cutouts)
}

fn bound(io: PassIo, top_level: vk::AccelerationStructureKHR, cutouts: &TracedCutouts) -> PassIo {
    io.acceleration_structure("scene", top_level)
        .bind_buffer("cutouts", &cutouts.entries)
        .bind_buffer("cutout_corners", &cutouts.corners)
        .bind_buffer("cutout_alphas", &cutouts.alphas)
}
