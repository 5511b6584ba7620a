//! Light culling (light_cull.comp), in frames whose lights have a range: per 16×16
//! tile, the depth range becomes a world box and the lights whose range reaches it are
//! listed in index order. Timed with the lighting pass it prepares.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::graph::{BufferUse, ImageUse};
use crate::pass_io::PassIo;

pub(crate) struct LightCull;

impl FramePass for LightCull {
    fn name(&self) -> &'static str {
        "light culling"
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::LIGHT_CULL];
        &SETS
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        frame.cull_push.is_some()
    }

    fn timed(&self) -> bool {
        false
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let s = frame.slot;
        PassIo::new(self.name())
            .slot_set(frame.slot, &bindings::LIGHT_CULL)
            .image(
                "gbuffer_depth",
                &frame.targets.gbuffer.depth,
                ImageUse::DepthComputeSampled,
            )
            .buffer("lights", &s.lights, BufferUse::ComputeStorageRead)
            .buffer(
                "tile_lights",
                &s.tile_lights,
                BufferUse::ComputeStorageWrite,
            )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let push = frame.cull_push.as_ref().expect("runs only with its push");
        frame.registry.light_cull.record(
            frame.device,
            cmd,
            frame.slot.set(&bindings::LIGHT_CULL),
            push,
            frame.extent(),
        );
    }
}
