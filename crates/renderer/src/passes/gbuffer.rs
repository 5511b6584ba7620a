//! The G-buffer pass: every object of the scene rasterised into the G-buffer's colour
//! targets and depth (gbuffer.vert/.frag; docs/gbuffer.md).

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::graph::{BufferUse, ImageUse};
use crate::pass_io::PassIo;
use crate::results::PassTimings;

pub(crate) struct GBuffer;

impl FramePass for GBuffer {
    fn name(&self) -> &'static str {
        PassTimings::GBUFFER
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::GBUFFER];
        &SETS
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let g = &frame.targets.gbuffer;
        let mut io = PassIo::new(self.name())
            .slot_set(frame.slot, &bindings::GBUFFER)
            .buffer(
                "objects",
                frame.placement.table,
                BufferUse::VertexStorageRead,
            )
            .posed_vertices(frame.scene)
            .buffer(
                "materials",
                &frame.scene.gpu.materials,
                BufferUse::FragmentStorageRead,
            );
        for image in g.attachments() {
            io = io.touches(image.into(), ImageUse::ColorAttachmentWrite);
        }
        io.touches((&g.depth).into(), ImageUse::DepthAttachmentWrite)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        frame.pipelines().gbuffer.record(
            frame.device,
            cmd,
            &frame.targets.gbuffer,
            frame.scene,
            frame.slot.set(&bindings::GBUFFER),
            frame.view_projection,
        );
    }
}
