//! The G-buffer pass: every object of the scene rasterised into the G-buffer's colour
//! targets and depth (gbuffer.vert/.frag; docs/gbuffer.md).

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::error::RenderError;
use crate::gbuffer::GBufferPass;
use crate::graph::{BufferUse, ImageUse};
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;
use crate::targets::ImageRequest;
use crate::variant::ShaderVariant;

pub(crate) struct GBuffer;

/// The G-buffer pipelines of `variant`: kept by the part of it the G-buffer shaders read
/// (variants that differ only in their lighting share them), in `settings`' storage.
fn key(variant: ShaderVariant, settings: &RendererSettings) -> PipelineKey {
    PipelineKey {
        pass: PassTimings::GBUFFER,
        variant: Some(variant.gbuffer_part()),
        defines: settings.gbuffer.defines(),
        formats: vec![settings.hdr_format.vk()],
    }
}

impl FramePass for GBuffer {
    fn name(&self) -> &'static str {
        PassTimings::GBUFFER
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::GBUFFER];
        &SETS
    }

    fn prepare(
        &self,
        variant: ShaderVariant,
        settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        registry.build(key(variant, settings), |t| {
            let pass = GBufferPass::new(
                t.device,
                t.compiler,
                t.cache,
                [
                    t.layouts.of(&bindings::GBUFFER),
                    t.layouts.of(&bindings::MATERIAL_TEXTURES),
                ],
                variant.gbuffer_part(),
                settings.gbuffer,
                settings.hdr_format.vk(),
            )?;
            let count = 1 + pass.stroke_pipelines();
            Ok((pass, count))
        })?;
        Ok(())
    }

    fn images(&self, variant: ShaderVariant, settings: &RendererSettings) -> Vec<ImageRequest> {
        crate::gbuffer::requests(variant, settings.gbuffer, settings.hdr_format.vk())
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let g = &frame.gbuffer;
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
        io.touches(g.depth.into(), ImageUse::DepthAttachmentWrite)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let pass: &GBufferPass = frame
            .registry
            .get(&key(frame.variant, frame.settings))
            .expect("prepared for the frame's variant");
        pass.record(
            frame.device,
            cmd,
            &frame.gbuffer,
            frame.scene,
            frame.slot.set(&bindings::GBUFFER),
            frame.view_projection,
        );
    }
}
