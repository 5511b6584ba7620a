//! Full-screen passes (lighting, tonemap): one triangle, inputs read with texelFetch.

use std::sync::Arc;

use combustion_vk::{
    vk, DescriptorSetLayout, Device, GraphicsPipelineDesc, Pipeline, PipelineCache, PipelineLayout,
    ShaderCompiler, ShaderModule, ShaderStage,
};

use crate::error::RenderError;

/// What [`screen_pipeline`] builds: shaders by name, one descriptor set, push constants
/// for `push_stages`, one colour target, no vertex input, and a depth test against the
/// frame's depth (read-only) or none.
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
    /// The full-screen triangle at the far plane (depth 1), compared with the depth
    /// attachment's by this test (fragments where it fails are not shaded), or `None`:
    /// no depth attachment.
    pub depth_test: Option<vk::CompareOp>,
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
    let vertex_defines: &[(&str, Option<&str>)] = match desc.depth_test {
        Some(_) => &[("AT_FAR_PLANE", None)],
        None => &[],
    };
    let vertex = ShaderModule::new(
        device,
        &compiler.compile(desc.vertex_shader, ShaderStage::Vertex, vertex_defines)?,
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
            depth_format: desc.depth_test.map(|_| crate::gbuffer::DEPTH_FORMAT),
            depth_write: false,
            depth_compare: desc.depth_test.unwrap_or(vk::CompareOp::ALWAYS),
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

/// How a rendering of a full-screen target starts with the target's contents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum TargetStart {
    /// Cleared to this value, which the pixels no draw writes keep.
    Clear([f32; 4]),
    /// Loaded: what the target holds (a blending pass, or draws over an earlier rendering).
    Load,
    /// Undefined: every pixel is written.
    Written,
}

/// Begins a rendering of `output` (a view in COLOR_ATTACHMENT_OPTIMAL of `extent`) that
/// starts as `start` says, with `depth` (a view of the frame's depth, read-only in
/// DEPTH_STENCIL_READ_ONLY_OPTIMAL) as its depth attachment for depth-tested passes;
/// viewport, scissor and cull mode set. End it with [`end_rendering`].
pub(crate) fn begin_screen_rendering(
    device: &Device,
    cmd: vk::CommandBuffer,
    (output, extent): (vk::ImageView, vk::Extent2D),
    start: TargetStart,
    depth: Option<vk::ImageView>,
) {
    let (load, clear) = match start {
        TargetStart::Clear(value) => (vk::AttachmentLoadOp::CLEAR, value),
        TargetStart::Load => (vk::AttachmentLoadOp::LOAD, [0.0; 4]),
        TargetStart::Written => (vk::AttachmentLoadOp::DONT_CARE, [0.0; 4]),
    };
    let attachment = [vk::RenderingAttachmentInfo::default()
        .image_view(output)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(load)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            color: vk::ClearColorValue { float32: clear },
        })];
    let depth_attachment = depth.map(|view| {
        vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::NONE)
    });
    let mut rendering = vk::RenderingInfo::default()
        .render_area(crate::commands::whole(extent))
        .layer_count(1)
        .color_attachments(&attachment);
    if let Some(depth_attachment) = &depth_attachment {
        rendering = rendering.depth_attachment(depth_attachment);
    }
    let raw = device.raw();
    // SAFETY: recording into a command buffer in the recording state.
    unsafe {
        raw.cmd_begin_rendering(cmd, &rendering);
        crate::commands::set_viewport_and_scissor(raw, cmd, extent);
        raw.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
    }
}

/// Ends the rendering [`begin_screen_rendering`] began.
pub(crate) fn end_rendering(device: &Device, cmd: vk::CommandBuffer) {
    // SAFETY: recording, inside a rendering begun by begin_screen_rendering.
    unsafe {
        device.raw().cmd_end_rendering(cmd);
    }
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
        let target = (output_format, combustion_vk::ColorBlend::Replace, None);
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
        let target = (
            output_format,
            combustion_vk::ColorBlend::OverKeepingAlpha,
            None,
        );
        let shader = (fragment_shader, &[][..]);
        Self::build(
            device, compiler, cache, shader, set_layout, push_size, target,
        )
    }

    /// The pass of `fragment_shader` with `defines` into `format` by `blend` (it loads
    /// the target unless it replaces it), depth-tested by `depth_test` or not: with a
    /// test its fragments are shaded only where the frame's depth passes it against the
    /// far plane's depth (1) — `NOT_EQUAL` where a surface was drawn, `EQUAL` where none
    /// was — and it is recorded with [`FullscreenPass::draw`] inside a rendering given
    /// that depth ([`begin_screen_rendering`]).
    pub(crate) fn build(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        (fragment_shader, defines): (&str, &[(&str, Option<&str>)]),
        set_layout: &DescriptorSetLayout,
        push_size: u32,
        (format, blend, depth_test): (vk::Format, combustion_vk::ColorBlend, Option<vk::CompareOp>),
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
            depth_test,
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
        let start = match clear {
            Some(value) => TargetStart::Clear(value),
            None if self.blends => TargetStart::Load,
            None => TargetStart::Written,
        };
        begin_screen_rendering(device, cmd, (output, extent), start, None);
        self.draw(device, cmd, set, push);
        then(cmd);
        end_rendering(device, cmd);
    }

    /// Draws the full-screen triangle through this pass's pipeline with `set` and
    /// `push`, inside a rendering whose attachments it was built for.
    pub(crate) fn draw(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        push: &[u8],
    ) {
        debug_assert_eq!(push.len() as u32, self.push_size);
        let raw = device.raw();
        // SAFETY: recording into a command buffer in the recording state, inside a
        // rendering.
        unsafe {
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
    }
}
