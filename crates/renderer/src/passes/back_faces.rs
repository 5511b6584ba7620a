//! The far sides of the transmissive objects with a volume (`crate::back_faces`): their
//! nearest back face's depth and normal at each pixel, where the forward pass's
//! refracted rays leave those objects. Runs in frames whose forward pass draws such an
//! object (the VOLUME variant).

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::graph::{BufferUse, ImageUse};
use crate::pass_io::PassIo;
use crate::results::PassTimings;

pub(crate) struct BackFaces;

impl FramePass for BackFaces {
    fn name(&self) -> &'static str {
        PassTimings::BACK_FACES
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::BACK_FACES];
        &SETS
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        // Built for VOLUME variants with a forward pass, whose targets have the back
        // faces (TargetKey::of).
        frame.pipelines().back_faces.is_some()
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let targets = frame
            .targets
            .back_faces
            .as_ref()
            .expect("runs only with them");
        PassIo::new(self.name())
            .slot_set(frame.slot, &bindings::BACK_FACES)
            .buffer(
                "objects",
                frame.placement.table,
                BufferUse::VertexStorageRead,
            )
            .posed_vertices(frame.scene)
            .touches((&targets.normal).into(), ImageUse::ColorAttachmentWrite)
            .touches((&targets.depth).into(), ImageUse::DepthAttachmentWrite)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let (Some(pass), Some(targets)) = (
            frame.pipelines().back_faces.as_ref(),
            frame.targets.back_faces.as_ref(),
        ) else {
            return;
        };
        pass.record(
            frame.device,
            cmd,
            targets,
            frame.scene,
            frame.slot.set(&bindings::BACK_FACES),
            frame.view_projection,
        );
    }
}
