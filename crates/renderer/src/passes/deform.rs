//! The deform pass: the deformed objects' vertices morphed and skinned into their posed
//! streams (deform.comp; crate::deform), before any pass draws them. Runs in frames of
//! scenes with deformed objects only.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use std::sync::Arc;

use combustion_vk::{DescriptorSetLayout, Device, PipelineCache, ShaderCompiler};

use crate::compute::ComputePass;
use crate::deform::{DeformPush, SceneDeform, GROUP};
use crate::error::RenderError;
use crate::graph::BufferUse;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;

pub(crate) struct Deform;

/// Its one pipeline.
fn key() -> PipelineKey {
    PipelineKey::named(PassTimings::DEFORM)
}

/// Builds the deform pipeline unless it is built: for scenes with deformed objects, at
/// their upload or edit (the scene, not the variant, says whether frames deform).
pub(crate) fn prepare(registry: &mut PipelineRegistry) -> Result<(), RenderError> {
    registry.build(key(), |t| {
        let pipeline = DeformPipeline::new(
            t.device,
            t.compiler,
            t.cache,
            t.layouts.of(&bindings::DEFORM),
        )?;
        Ok((pipeline, 1))
    })?;
    Ok(())
}

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
        let (Some(deform), Some(pipeline)) = (
            &frame.scene.gpu.deform,
            frame.registry.get::<DeformPipeline>(&key()),
        ) else {
            return;
        };
        pipeline.record(frame.device, cmd, frame.slot.set(&bindings::DEFORM), deform);
    }
}

/// The deform pass's pipeline (made when the first scene with deformed objects is
/// uploaded: shaders are compiled at upload, never in a frame).
pub(crate) struct DeformPipeline {
    pass: ComputePass,
}

impl DeformPipeline {
    pub(crate) fn new(
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
            "deform.comp",
            &[],
            std::mem::size_of::<DeformPush>(),
        )?;
        Ok(Self { pass })
    }

    /// One dispatch per deformed object of `deform` (recording state; the set's
    /// resources in the states the pass declared).
    pub(crate) fn record(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        deform: &SceneDeform,
    ) {
        self.pass.bind(device, cmd, set, &[]);
        for object in &deform.objects {
            self.pass
                .push(device, cmd, bytemuck::bytes_of(&object.push));
            // SAFETY: recording state; the pipeline and its set are bound.
            unsafe {
                device
                    .raw()
                    .cmd_dispatch(cmd, object.push.vertices[1].div_ceil(GROUP), 1, 1)
            };
        }
    }
}
