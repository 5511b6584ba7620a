//! Light culling (light_cull.comp), in frames whose lights have a range: per 16×16
//! tile, the depth range becomes a world box and the lights whose range reaches it are
//! listed in index order. Timed with the lighting pass it prepares.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::error::RenderError;
use crate::graph::{BufferUse, ImageUse};
use std::sync::Arc;

use combustion_vk::{DescriptorSetLayout, Device, PipelineCache, ShaderCompiler};

use crate::compute::ComputePass;
use crate::light_cull::tiles;
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::push::{push_block, PushBlock};
use crate::variant::ShaderVariant;

pub(crate) struct LightCull;

push_block! {
    /// The culling pass's push constants (`push/light_cull.glsl`).
    pub(crate) struct CullPush in "light_cull" {
        /// The inverse of the camera's view-projection matrix, column-major.
        inverse_view_projection: [f32; 16],
        /// x: lights; y: tiles across; z: list stride (1 + lights); w: tiles.
        counts: [u32; 4],
    }
}

/// Its one pipeline (every variant's frames may cull).
fn key() -> PipelineKey {
    PipelineKey::named("light culling")
}

impl FramePass for LightCull {
    fn name(&self) -> &'static str {
        "light culling"
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::LIGHT_CULL];
        &SETS
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![CullPush::header()]
    }

    fn prepare(
        &self,
        _variant: ShaderVariant,
        _settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        registry.build(key(), |t| {
            let pass = LightCullPass::new(
                t.device,
                t.compiler,
                t.cache,
                t.layouts.of(&bindings::LIGHT_CULL),
            )?;
            Ok((pass, 1))
        })?;
        Ok(())
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
                frame.gbuffer.depth,
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
        let pass: &LightCullPass = frame
            .registry
            .get(&key())
            .expect("prepared with every variant");
        pass.record(
            frame.device,
            cmd,
            frame.slot.set(&bindings::LIGHT_CULL),
            push,
            frame.extent(),
        );
    }
}

/// The culling pass's pipeline.
pub(crate) struct LightCullPass {
    pass: ComputePass,
}

impl LightCullPass {
    pub fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        set_layout: &DescriptorSetLayout,
    ) -> Result<Self, RenderError> {
        let pass = ComputePass::new(
            device,
            compiler,
            cache,
            set_layout,
            "light_cull.comp",
            &[],
            std::mem::size_of::<CullPush>(),
        )?;
        Ok(Self { pass })
    }

    /// Dispatches one invocation per tile of `extent` (64 to a workgroup).
    pub fn record(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        push: &CullPush,
        extent: vk::Extent2D,
    ) {
        let (x, y) = tiles(extent);
        let groups = (x * y).div_ceil(64);
        self.pass
            .dispatch(device, cmd, set, bytemuck::bytes_of(push), [groups, 1, 1]);
    }
}
