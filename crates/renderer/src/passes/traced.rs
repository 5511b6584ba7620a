//! What the passes that trace rays bind (the ray-traced occlusion and shadows passes, and
//! the lighting pass for the sampled environment's directions): the scene's top-level
//! structure and the tables its cut-outs are tested against (`crate::accel`;
//! traced_scene.glsl's `scene_blocks`), or the renderer's empty ones where a frame traces
//! nothing.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::accel::TracedCutouts;
use crate::bindings::Binding;
use crate::options::OptionalPass;
use crate::pass_io::PassIo;
use crate::variant::ShaderVariant;

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

/// A pass that builds the frame's traced scene for another pass's rays, and does nothing
/// else: path tracing, ray-traced reflections and refraction (the lighting or forward
/// pass traces the rays). Each is one of these, declared in its own file: its name, its
/// option, the header of its shaders' constants and which frames want it.
pub(super) struct SceneForRays {
    pub(super) name: &'static str,
    pub(super) option: &'static OptionalPass,
    /// The generated header its shaders include: its path and text.
    pub(super) header: (&'static str, fn() -> String),
    /// Whether frames of a variant want its rays (asked for, and what they need there).
    pub(super) wanted: fn(ShaderVariant) -> bool,
}

impl SceneForRays {
    /// Whether the frame traces its rays (wanted, its scene's structures built).
    pub(super) fn traces(&self, frame: &FrameContext<'_>) -> bool {
        (self.wanted)(frame.variant) && frame.scene.gpu.structures.get().is_some()
    }
}

impl FramePass for SceneForRays {
    fn name(&self) -> &'static str {
        self.name
    }

    fn option(&self) -> Option<&'static OptionalPass> {
        Some(self.option)
    }

    fn traces(&self, variant: ShaderVariant) -> bool {
        (self.wanted)(variant)
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![(self.header.0.into(), (self.header.1)())]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        SceneForRays::traces(self, frame)
    }

    fn io(&self, _frame: &FrameContext<'_>) -> PassIo {
        PassIo::new(self.name)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        record_build(frame, cmd);
    }
}
