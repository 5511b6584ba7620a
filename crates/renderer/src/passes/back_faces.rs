//! The far sides of the transmissive objects with a volume (`crate::back_faces`): their
//! nearest back face's depth and normal at each pixel, where the forward pass's
//! refracted rays leave those objects. Runs in frames whose forward pass draws such an
//! object (the VOLUME variant).

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::back_faces::BackFacesPass;
use crate::bindings::{self, SetDecl};
use crate::error::RenderError;
use crate::graph::{BufferUse, ImageUse};
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;
use crate::variant::ShaderVariant;

pub(crate) struct BackFaces;

/// Whether frames of `variant` draw the far sides: VOLUME variants with a forward pass
/// (their targets have the back faces: `TargetKey::of`).
fn draws(variant: ShaderVariant) -> bool {
    variant.volume && super::forward::draws(variant)
}

/// Its one pipeline (variant-independent: every such variant shares it).
fn key() -> PipelineKey {
    PipelineKey::named(PassTimings::BACK_FACES)
}

impl FramePass for BackFaces {
    fn name(&self) -> &'static str {
        PassTimings::BACK_FACES
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::BACK_FACES];
        &SETS
    }

    fn prepare(
        &self,
        variant: ShaderVariant,
        _settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        if draws(variant) {
            registry.build(key(), |t| {
                let pass = BackFacesPass::new(
                    t.device,
                    t.compiler,
                    t.cache,
                    t.layouts.of(&bindings::BACK_FACES),
                )?;
                Ok((pass, 1))
            })?;
        }
        Ok(())
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        draws(frame.variant)
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
            frame.registry.get::<BackFacesPass>(&key()),
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
