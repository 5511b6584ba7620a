//! The shadow-map pass: every object of the scene rendered, depth only, into one
//! shadow-map layer per cascade of each shadowed light (shadow.vert; crate::shadows);
//! cut-out casters through their alpha test.
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
        frame.variant.shadows.is_some()
            && !(frame.slot.shadow_layers.is_empty() && frame.slot.local_shadow_layers.is_empty())
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let (cascades, local) = frame
            .shadow_maps
            .expect("frames with shadow layers have shadow maps");
        let mut io = PassIo::new(self.name())
            .slot_set(frame.slot, &bindings::SHADOW_CASTERS)
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
        // Only the arrays rendered this frame: the other keeps its maps.
        for (maps, layers) in [
            (cascades, &frame.slot.shadow_layers),
            (local, &frame.slot.local_shadow_layers),
        ] {
            if !layers.is_empty() {
                io = io.touches((&maps.image).into(), ImageUse::DepthAttachmentWrite);
            }
        }
        io
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let (Some((cascades, local)), Some(casters)) =
            (frame.shadow_maps, &frame.registry.shadow_casters)
        else {
            return;
        };
        for (maps, layers) in [
            (cascades, &frame.slot.shadow_layers),
            (local, &frame.slot.local_shadow_layers),
        ] {
            casters.record(
                frame.device,
                cmd,
                maps,
                frame.scene,
                &frame.placement,
                frame.slot.set(&bindings::SHADOW_CASTERS),
                layers,
            );
        }
    }
}
