//! The deform pass: the deformed objects' vertices morphed and skinned into their posed
//! streams (deform.comp; crate::deform), before any pass draws them. Runs in frames of
//! scenes with deformed objects only.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::graph::BufferUse;
use crate::pass_io::PassIo;
use crate::results::PassTimings;

pub(crate) struct Deform;

impl FramePass for Deform {
    fn name(&self) -> &'static str {
        PassTimings::DEFORM
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::DEFORM];
        &SETS
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        frame.scene.gpu.deform.is_some()
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let deform = frame
            .scene
            .gpu
            .deform
            .as_ref()
            .expect("runs with deformed objects");
        let s = frame.slot;
        PassIo::new(self.name())
            .slot_set(s, &bindings::DEFORM)
            .bind_buffer("rest_vertices", &deform.rest)
            .bind_buffer("influence_ranges", &deform.ranges)
            .bind_buffer("influences", &deform.influences)
            .bind_buffer("morph_displacements", &deform.displacements)
            .buffer(
                "morph_weights",
                &s.morph_weights,
                BufferUse::ComputeStorageRead,
            )
            .buffer(
                "joint_matrices",
                &s.joint_matrices,
                BufferUse::ComputeStorageRead,
            )
            .buffer(
                "posed_vertices",
                &deform.posed,
                BufferUse::ComputeStorageWrite,
            )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let (Some(deform), Some(pipeline)) = (&frame.scene.gpu.deform, &frame.registry.deform)
        else {
            return;
        };
        pipeline.record(frame.device, cmd, frame.slot.set(&bindings::DEFORM), deform);
    }
}
