//! The shadow-map pass: every object of the scene rendered, depth only, into one
//! shadow-map layer per cascade of each shadowed light (shadow.vert; crate::shadows).
//! Runs in frames whose variant has shadows and that have a directional light.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::graph::{BufferUse, ImageUse};
use crate::pass_io::PassIo;
use crate::results::PassTimings;

pub(crate) struct ShadowMaps;

impl FramePass for ShadowMaps {
    fn name(&self) -> &'static str {
        PassTimings::SHADOW_MAPS
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::SHADOW_CASTERS];
        &SETS
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        frame.variant.shadows.is_some() && !frame.slot.shadow_layers.is_empty()
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let maps = frame
            .shadow_maps
            .expect("frames with shadow layers have shadow maps");
        PassIo::new(self.name())
            .slot_set(frame.slot, &bindings::SHADOW_CASTERS)
            .buffer(
                "objects",
                &frame.scene.gpu.objects,
                BufferUse::VertexStorageRead,
            )
            .touches((&maps.image).into(), ImageUse::DepthAttachmentWrite)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let (Some(maps), Some(casters)) = (frame.shadow_maps, &frame.renderer.shadow_casters)
        else {
            return;
        };
        casters.record(
            &frame.renderer.device,
            cmd,
            maps,
            frame.scene,
            frame.slot.set(&bindings::SHADOW_CASTERS),
            &frame.slot.shadow_layers,
        );
    }
}
