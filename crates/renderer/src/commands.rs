//! Command-recording helpers every pass uses: binding a pass's pipeline with its one
//! descriptor set and push constants, and setting a full-target viewport.

use combustion_vk::vk;

/// Binds `pipeline` at `bind_point` with its one descriptor set (set 0) and, if any,
/// its push constants for `stages`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn bind_pass(
    raw: &combustion_vk::ash::Device,
    cmd: vk::CommandBuffer,
    bind_point: vk::PipelineBindPoint,
    pipeline: &combustion_vk::Pipeline,
    layout: &combustion_vk::PipelineLayout,
    set: vk::DescriptorSet,
    stages: vk::ShaderStageFlags,
    push: &[u8],
) {
    // SAFETY: recording state is the caller's responsibility; the set matches the layout.
    unsafe {
        raw.cmd_bind_pipeline(cmd, bind_point, pipeline.raw());
        raw.cmd_bind_descriptor_sets(cmd, bind_point, layout.raw(), 0, &[set], &[]);
        if !push.is_empty() {
            raw.cmd_push_constants(cmd, layout.raw(), stages, 0, push);
        }
    }
}

/// Begins `rendering` over the whole of `extent` (viewport and scissor set to it) and
/// binds the graphics `pipeline` with its set 0: how every pass that rasterises the
/// scene starts.
pub(crate) fn begin_scene_drawing(
    raw: &combustion_vk::ash::Device,
    cmd: vk::CommandBuffer,
    rendering: &vk::RenderingInfo<'_>,
    extent: vk::Extent2D,
    (pipeline, layout): (&combustion_vk::Pipeline, &combustion_vk::PipelineLayout),
    set: vk::DescriptorSet,
) {
    // SAFETY: recording state is the caller's responsibility; the set matches the layout.
    unsafe { raw.cmd_begin_rendering(cmd, rendering) };
    set_viewport_and_scissor(raw, cmd, extent);
    bind_pass(
        raw,
        cmd,
        vk::PipelineBindPoint::GRAPHICS,
        pipeline,
        layout,
        set,
        vk::ShaderStageFlags::empty(),
        &[],
    );
}

/// A depth attachment of `view`, in the depth-attachment layout, cleared to the far
/// plane (1) and stored: what a pass that rasterises the scene with depth renders into.
pub(crate) fn cleared_depth_attachment(
    view: vk::ImageView,
) -> vk::RenderingAttachmentInfo<'static> {
    vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(crate::graph::ImageUse::DepthAttachmentWrite.state().layout)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        })
}

/// The whole of `extent`, from the origin: a pass's render area.
pub(crate) fn whole(extent: vk::Extent2D) -> vk::Rect2D {
    vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent,
    }
}

/// Sets the viewport (depth 0 to 1) and the scissor to the whole of `extent`.
pub(crate) fn set_viewport_and_scissor(
    raw: &combustion_vk::ash::Device,
    cmd: vk::CommandBuffer,
    extent: vk::Extent2D,
) {
    // SAFETY: recording state is the caller's responsibility.
    unsafe {
        raw.cmd_set_viewport(
            cmd,
            0,
            &[vk::Viewport {
                x: 0.0,
                y: 0.0,
                width: extent.width as f32,
                height: extent.height as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            }],
        );
        raw.cmd_set_scissor(
            cmd,
            0,
            &[vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent,
            }],
        );
    }
}

/// The copy of mip level 0, layer 0 of `aspect` over `extent` from one image to another
/// of the same size.
pub(crate) fn level_zero_copy(aspect: vk::ImageAspectFlags, extent: vk::Extent2D) -> vk::ImageCopy {
    let layers = vk::ImageSubresourceLayers {
        aspect_mask: aspect,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    };
    vk::ImageCopy::default()
        .src_subresource(layers)
        .dst_subresource(layers)
        .extent(vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        })
}
