//! Compute passes: one shader with its defines, one descriptor set (set 0) and push
//! constants; bound and dispatched in one call.

use std::sync::Arc;

use combustion_vk::{
    vk, DescriptorSetLayout, Device, Pipeline, PipelineCache, PipelineLayout, ShaderCompiler,
    ShaderModule, ShaderStage,
};

use crate::error::RenderError;

/// A compute pipeline and its layout.
pub(crate) struct ComputePass {
    layout: PipelineLayout,
    pipeline: Pipeline,
}

impl ComputePass {
    /// Compiles `shader` with `defines` (set 0 of `set_layout`, `push_bytes` of push
    /// constants) and builds its pipeline through `cache`.
    pub(crate) fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        set_layout: &DescriptorSetLayout,
        shader: &str,
        defines: &[(&str, Option<&str>)],
        push_bytes: usize,
    ) -> Result<Self, RenderError> {
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::COMPUTE,
            offset: 0,
            size: push_bytes as u32,
        }];
        let layout = PipelineLayout::new(device, &[set_layout], &push)?;
        let module = ShaderModule::new(
            device,
            &compiler.compile(shader, ShaderStage::Compute, defines)?,
            ShaderStage::Compute,
        )?;
        let pipeline = Pipeline::compute(device, &module, &layout, Some(cache))?;
        Ok(Self { layout, pipeline })
    }

    /// Binds the pipeline, `set` and `push` (recording state; the set's resources in the
    /// states the pass declared).
    pub(crate) fn bind(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        push: &[u8],
    ) {
        crate::commands::bind_pass(
            device.raw(),
            cmd,
            vk::PipelineBindPoint::COMPUTE,
            &self.pipeline,
            &self.layout,
            set,
            vk::ShaderStageFlags::COMPUTE,
            push,
        );
    }

    /// Pushes `push` again, between dispatches of the bound pipeline.
    pub(crate) fn push(&self, device: &Device, cmd: vk::CommandBuffer, push: &[u8]) {
        // SAFETY: recording state; the range is the layout's.
        unsafe {
            device.raw().cmd_push_constants(
                cmd,
                self.layout.raw(),
                vk::ShaderStageFlags::COMPUTE,
                0,
                push,
            )
        };
    }

    /// Binds as [`ComputePass::bind`] and dispatches `groups` workgroups.
    pub(crate) fn dispatch(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        push: &[u8],
        groups: [u32; 3],
    ) {
        self.bind(device, cmd, set, push);
        // SAFETY: recording state; the pipeline and its set are bound.
        unsafe {
            device
                .raw()
                .cmd_dispatch(cmd, groups[0], groups[1], groups[2])
        };
    }
}
