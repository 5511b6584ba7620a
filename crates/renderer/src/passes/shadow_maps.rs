//! The shadow-map pass: every object of the scene rendered, depth only, into one
//! shadow-map layer per cascade of each shadowed light (shadow.vert; crate::shadows);
//! cut-out casters through their alpha test.
//! Runs in frames whose variant has shadows and that have a directional light.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::error::RenderError;
use crate::graph::{BufferUse, ImageUse};
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;
use crate::shadows::ShadowCasterPass;
use crate::variant::ShaderVariant;

pub(crate) struct ShadowMaps;

/// The casters' pipelines (variant-independent: the cut-out casters' is added for the
/// first variant with cut-outs).
fn key() -> PipelineKey {
    PipelineKey::named(PassTimings::SHADOW_MAPS)
}

impl FramePass for ShadowMaps {
    fn name(&self) -> &'static str {
        PassTimings::SHADOW_MAPS
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::SHADOW_CASTERS];
        &SETS
    }

    fn prepare(
        &self,
        variant: ShaderVariant,
        _settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        if variant.shadows.is_none() {
            return Ok(());
        }
        registry.build(key(), |t| {
            let pass = ShadowCasterPass::new(
                t.device,
                t.compiler,
                t.cache,
                [
                    t.layouts.of(&bindings::SHADOW_CASTERS),
                    t.layouts.of(&bindings::MATERIAL_TEXTURES),
                ],
            )?;
            Ok((pass, 1))
        })?;
        if variant.alpha_mask {
            registry.update(&key(), |casters: &mut ShadowCasterPass, t| {
                if casters.has_masked() {
                    return Ok(0);
                }
                casters.add_masked(t.device, t.compiler, t.cache)?;
                Ok(1)
            })?;
        }
        Ok(())
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
        let (Some((cascades, local)), Some(casters)) = (
            frame.shadow_maps,
            frame.registry.get::<ShadowCasterPass>(&key()),
        ) else {
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
