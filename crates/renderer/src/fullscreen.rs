//! Full-screen passes (lighting, tonemap): one triangle, inputs read with texelFetch.

use std::sync::Arc;

use combustion_vk::{
    vk, DescriptorSetLayout, Device, GraphicsPipelineDesc, Pipeline, PipelineCache, PipelineLayout,
    ShaderCompiler, ShaderModule, ShaderStage,
};

use crate::error::RenderError;

/// What [`screen_pipeline`] builds: shaders by name, one descriptor set, push constants
/// for `push_stages`, one colour target, no vertex input and no depth.
pub(crate) struct ScreenPipelineDesc<'a> {
    pub vertex_shader: &'a str,
    pub fragment_shader: &'a str,
    /// `#define`s of the fragment shader.
    pub defines: &'a [(&'a str, Option<&'a str>)],
    pub set_layout: &'a DescriptorSetLayout,
    pub push_stages: vk::ShaderStageFlags,
    pub push_size: u32,
    pub format: vk::Format,
    pub blend: combustion_vk::ColorBlend,
}

/// A pipeline drawing into one colour target without vertex buffers (the full-screen
/// passes, the overlay), and its layout.
pub(crate) fn screen_pipeline(
    device: &Arc<Device>,
    compiler: &ShaderCompiler,
    cache: &PipelineCache,
    desc: &ScreenPipelineDesc<'_>,
) -> Result<(PipelineLayout, Pipeline), RenderError> {
    let push = [vk::PushConstantRange {
        stage_flags: desc.push_stages,
        offset: 0,
        size: desc.push_size,
    }];
    let layout = PipelineLayout::new(device, &[desc.set_layout], &push)?;
    let vertex = ShaderModule::new(
        device,
        &compiler.compile(desc.vertex_shader, ShaderStage::Vertex, &[])?,
        ShaderStage::Vertex,
    )?;
    let fragment = ShaderModule::new(
        device,
        &compiler.compile(desc.fragment_shader, ShaderStage::Fragment, desc.defines)?,
        ShaderStage::Fragment,
    )?;
    let pipeline = Pipeline::graphics(
        device,
        &GraphicsPipelineDesc {
            vertex: &vertex,
            fragment: &fragment,
            layout: &layout,
            vertex_bindings: &[],
            vertex_attributes: &[],
            color_formats: &[desc.format],
            depth_format: None,
            depth_write: false,
            blend: desc.blend,
            cache: Some(cache),
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
        },
    )?;
    Ok((layout, pipeline))
}

/// A full-screen pass: a fragment shader with one descriptor set and push constants.
pub struct FullscreenPass {
    layout: PipelineLayout,
    pipeline: Pipeline,
    push_size: u32,
    /// Its fragments are blended over what the target holds (loaded first).
    blends: bool,
}

impl FullscreenPass {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        fragment_shader: &str,
        defines: &[(&str, Option<&str>)],
        set_layout: &DescriptorSetLayout,
        push_size: u32,
        output_format: vk::Format,
    ) -> Result<Self, RenderError> {
        let shader = (fragment_shader, defines);
        let target = (output_format, combustion_vk::ColorBlend::Replace);
        Self::build(
            device, compiler, cache, shader, set_layout, push_size, target,
        )
    }

    /// A pass whose fragments (colour, α) are blended over the target's contents:
    /// colour · α + target · (1 − α), the target's alpha kept (bloom's composite).
    pub fn blending(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        fragment_shader: &str,
        set_layout: &DescriptorSetLayout,
        push_size: u32,
        output_format: vk::Format,
    ) -> Result<Self, RenderError> {
        let target = (output_format, combustion_vk::ColorBlend::OverKeepingAlpha);
        let shader = (fragment_shader, &[][..]);
        Self::build(
            device, compiler, cache, shader, set_layout, push_size, target,
        )
    }

    /// The pass of `fragment_shader` with `defines` into `format` by `blend` (it loads
    /// the target unless it replaces it).
    fn build(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        (fragment_shader, defines): (&str, &[(&str, Option<&str>)]),
        set_layout: &DescriptorSetLayout,
        push_size: u32,
        (format, blend): (vk::Format, combustion_vk::ColorBlend),
    ) -> Result<Self, RenderError> {
        let desc = ScreenPipelineDesc {
            vertex_shader: "fullscreen.vert",
            fragment_shader,
            defines,
            set_layout,
            push_stages: vk::ShaderStageFlags::FRAGMENT,
            push_size,
            format,
            blend,
        };
        let (layout, pipeline) = screen_pipeline(device, compiler, cache, &desc)?;
        Ok(Self {
            layout,
            pipeline,
            push_size,
            blends: blend != combustion_vk::ColorBlend::Replace,
        })
    }

    /// Records the pass over every pixel of `output` (a view in
    /// COLOR_ATTACHMENT_OPTIMAL of `extent`), then `then` records more draws into the
    /// same rendering (e.g. the overlay over the output pass). `clear`: the value the
    /// rendering starts from, which the pixels the shader discards keep (`None`: the
    /// shader writes every pixel, nothing is loaded; a blending pass loads the target).
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        output: vk::ImageView,
        extent: vk::Extent2D,
        set: vk::DescriptorSet,
        push: &[u8],
        clear: Option<[f32; 4]>,
        then: impl FnOnce(vk::CommandBuffer),
    ) {
        debug_assert_eq!(push.len() as u32, self.push_size);
        let load = match clear {
            Some(_) => vk::AttachmentLoadOp::CLEAR,
            None if self.blends => vk::AttachmentLoadOp::LOAD,
            None => vk::AttachmentLoadOp::DONT_CARE,
        };
        let attachment = [vk::RenderingAttachmentInfo::default()
            .image_view(output)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(load)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: clear.unwrap_or_default(),
                },
            })];
        let rendering = vk::RenderingInfo::default()
            .render_area(vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent,
            })
            .layer_count(1)
            .color_attachments(&attachment);
        let raw = device.raw();
        // SAFETY: recording into a command buffer in the recording state.
        unsafe {
            raw.cmd_begin_rendering(cmd, &rendering);
            crate::commands::set_viewport_and_scissor(raw, cmd, extent);
            raw.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
            crate::commands::bind_pass(
                raw,
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                &self.pipeline,
                &self.layout,
                set,
                vk::ShaderStageFlags::FRAGMENT,
                push,
            );
            raw.cmd_draw(cmd, 3, 1, 0, 0);
        }
        then(cmd);
        // SAFETY: as above; ends the rendering begun here.
        unsafe {
            raw.cmd_end_rendering(cmd);
        }
    }
}
