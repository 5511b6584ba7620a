//! The forward pass's pipeline: the blended objects (`AlphaMode::Blend`) drawn after the
//! deferred lighting, back to front ([`crate::mesh_draw::back_to_front`]), each fragment
//! lit at once from its own surface (gbuffer.vert + forward.frag, through the lighting
//! pass's terms) and blended "over" the HDR image with its alpha, depth-tested against
//! the G-buffer's depth without writing it. Built only for scenes with a blended object
//! (`ShaderVariant::blend`): the others have no such pipeline and the pass does not run.

use std::sync::Arc;

use combustion_vk::{
    vk, ColorBlend, DescriptorSetLayout, Device, GraphicsPipelineDesc, Image, Pipeline,
    PipelineCache, PipelineLayout, ShaderCompiler, ShaderModule, ShaderStage,
};

use crate::error::RenderError;
use crate::gbuffer::DEPTH_FORMAT;
use crate::gpu_types::ForwardPush;
use crate::mesh_draw::{back_to_front, draw_in_order, Faces};
use crate::scene_upload::GpuScene;
use crate::variant::ShaderVariant;

/// The sampler the forward pass reads the image behind transmissive objects with:
/// trilinear (a rough surface's lookup reads a coarser level), clamped at the edges.
pub(crate) fn behind_sampler(device: &Arc<Device>) -> Result<combustion_vk::Sampler, RenderError> {
    Ok(combustion_vk::Sampler::new(
        device,
        &vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .min_lod(0.0)
            .max_lod(vk::LOD_CLAMP_NONE),
    )?)
}

/// The forward pass's pipeline and its layout: set 0 `bindings::FORWARD`, set 1 one
/// material's textures, a [`ForwardPush`] to both stages.
pub struct ForwardPass {
    layout: PipelineLayout,
    pipeline: Pipeline,
}

/// What one forward pass draws into and with.
pub(crate) struct ForwardTargets<'a> {
    /// The HDR image the deferred lighting wrote (colour attachment, blended over).
    pub hdr: &'a Image,
    /// The G-buffer's depth (depth-tested against, read-only).
    pub depth: &'a Image,
}

impl ForwardPass {
    /// Compiles gbuffer.vert and forward.frag with `variant`'s `#define`s and builds the
    /// pipeline (through `cache`) for an HDR image of `hdr_format`.
    ///
    /// # Errors
    /// [`RenderError::Vulkan`] if a shader does not compile or the pipeline cannot be built.
    pub fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        [set_layout, material_set_layout]: [&DescriptorSetLayout; 2],
        variant: ShaderVariant,
        hdr_format: vk::Format,
    ) -> Result<Self, RenderError> {
        let defines = variant.defines();
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            offset: 0,
            size: std::mem::size_of::<ForwardPush>() as u32,
        }];
        let layout = PipelineLayout::new(device, &[set_layout, material_set_layout], &push)?;
        let module = |file: &str, stage| -> Result<ShaderModule, RenderError> {
            Ok(ShaderModule::new(
                device,
                &compiler.compile(file, stage, &defines)?,
                stage,
            )?)
        };
        let vertex = module("gbuffer.vert", ShaderStage::Vertex)?;
        let fragment = module("forward.frag", ShaderStage::Fragment)?;
        let (bindings, attributes) = crate::gbuffer::scene_vertex_input(variant);
        let pipeline = Pipeline::graphics(
            device,
            &GraphicsPipelineDesc {
                vertex: &vertex,
                fragment: &fragment,
                layout: &layout,
                vertex_bindings: &bindings,
                vertex_attributes: &attributes,
                color_formats: &[hdr_format],
                depth_format: Some(DEPTH_FORMAT),
                depth_write: false,
                blend: ColorBlend::Over,
                cache: Some(cache),
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            },
        )?;
        Ok(Self { layout, pipeline })
    }

    /// Records the pass: `scene`'s blended objects back to front as seen from `eye`,
    /// lit by the frame's first `light_count` lights. The HDR image must be in
    /// COLOR_ATTACHMENT_OPTIMAL and the depth in DEPTH_STENCIL_READ_ONLY_OPTIMAL.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        targets: ForwardTargets<'_>,
        scene: &GpuScene,
        placement: &crate::placement::Placement<'_>,
        set: vk::DescriptorSet,
        view_projection: glam::Mat4,
        eye: glam::Vec3,
        light_count: u32,
    ) {
        let extent = targets.hdr.extent();
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(targets.hdr.view())
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(targets.depth.view())
            .image_layout(vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::NONE);
        let rendering = vk::RenderingInfo::default()
            .render_area(crate::commands::whole(extent))
            .layer_count(1)
            .color_attachments(&color)
            .depth_attachment(&depth);
        let raw = device.raw();
        let mut push = ForwardPush {
            view_projection: view_projection.to_cols_array(),
            object_index: 0,
            light_count,
            object_scale: 1.0,
            object_extent: 0.0,
            camera_position: eye.extend(1.0).to_array(),
        };
        let mut bound_material = None;
        // SAFETY: recording into a command buffer in the recording state, with resources
        // that outlive the submission (a dropped scene is retired, not freed).
        unsafe {
            crate::commands::begin_scene_drawing(
                raw,
                cmd,
                &rendering,
                extent,
                (&self.pipeline, &self.layout),
                set,
            );
            let order = back_to_front(scene, placement.bounds, eye);
            draw_in_order(raw, cmd, scene, Faces::OfMaterial, &order, |object| {
                let material = scene.draw_materials[object];
                if bound_material != Some(material) {
                    raw.cmd_bind_descriptor_sets(
                        cmd,
                        vk::PipelineBindPoint::GRAPHICS,
                        self.layout.raw(),
                        1,
                        &[scene.gpu.textures.material_sets[material]],
                        &[],
                    );
                    bound_material = Some(material);
                }
                push.object_index = object as u32;
                push.object_scale = placement
                    .transform(scene, object)
                    .determinant()
                    .abs()
                    .cbrt();
                push.object_extent =
                    placement.bounds[object].map_or(0.0, |(min, max)| min.distance(max));
                raw.cmd_push_constants(
                    cmd,
                    self.layout.raw(),
                    vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                    0,
                    bytemuck::bytes_of(&push),
                );
            });
            raw.cmd_end_rendering(cmd);
        }
    }
}
