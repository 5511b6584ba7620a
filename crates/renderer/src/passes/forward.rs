//! The forward pass (gbuffer.vert + forward.frag): the blended objects over the lit HDR
//! image, back to front, behind the G-buffer's depth. Runs only in frames of a scene
//! with a blended or transmissive object (not in debug views or measurement floors,
//! which show the G-buffer's own surfaces).
//!
//! Its pipeline: the blended objects (`AlphaMode::Blend`) drawn after the
//! deferred lighting, back to front ([`crate::mesh_draw::back_to_front`]), each fragment
//! lit at once from its own surface (gbuffer.vert + forward.frag, through the lighting
//! pass's terms) and blended "over" the HDR image with its alpha, depth-tested against
//! the G-buffer's depth without writing it. Built only for scenes with a blended object
//! (`ShaderVariant::blend`): the others have no such pipeline and the pass does not run.

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::error::RenderError;
use crate::gbuffer::DEPTH_FORMAT;
use crate::gpu_types::ForwardPush;
use crate::graph::{BufferUse, ImageUse};
use crate::mesh_draw::{back_to_front, draw_in_order, Faces};
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;
use crate::scene_upload::GpuScene;
use crate::variant::ShaderVariant;
use combustion_vk::{
    vk, ColorBlend, DescriptorSetLayout, Device, GraphicsPipelineDesc, Image, Pipeline,
    PipelineCache, PipelineLayout, ShaderCompiler, ShaderModule, ShaderStage,
};
use std::sync::Arc;

pub(crate) struct Forward;

/// Whether frames of `variant` draw the forward pass: scenes with a blended or
/// transmissive object, not in debug views or measurement floors (which show the
/// G-buffer's own surfaces), nor in path-traced frames (the paths are the frame).
pub(super) fn draws(variant: ShaderVariant) -> bool {
    (variant.blend || variant.transmission)
        && !variant.debug_views
        && variant.floor.is_none()
        && !super::path_trace::wanted(variant)
}

/// `io` with the traced scene and what its rays meet bound (ray-traced refraction; the
/// renderer's empty ones where the frame traces none, on devices with ray queries).
fn traced(io: PassIo, frame: &FrameContext<'_>) -> PassIo {
    if frame.shared.no_scene.is_none() {
        return io;
    }
    let io = if super::ray_traced_refraction::traces(frame) {
        super::traced::scene(io, frame)
    } else {
        super::traced::nothing(io, frame)
    };
    let io = super::path_trace::bind_surfaces(io, frame);
    match frame
        .scene
        .gpu
        .deform
        .as_ref()
        .filter(|_| super::ray_traced_refraction::traces(frame))
    {
        // Refracted rays read the deformed occluders' posed vertices where they hit them.
        Some(deform) => io.uses_buffer(&deform.posed, BufferUse::FragmentStorageRead),
        None => io,
    }
}

/// The forward pipelines of `variant`, into `settings`' HDR format.
fn key(variant: ShaderVariant, settings: &RendererSettings) -> PipelineKey {
    PipelineKey {
        pass: PassTimings::FORWARD,
        variant: Some(variant),
        defines: Vec::new(),
        formats: vec![settings.hdr_format.vk()],
    }
}

impl FramePass for Forward {
    fn name(&self) -> &'static str {
        PassTimings::FORWARD
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::FORWARD];
        &SETS
    }

    fn prepare(
        &self,
        variant: ShaderVariant,
        settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        if !draws(variant) {
            return Ok(());
        }
        registry.build(key(variant, settings), |t| {
            let pass = ForwardPass::new(
                t.device,
                t.compiler,
                t.cache,
                [
                    t.layouts.of(&bindings::FORWARD),
                    t.layouts.of(&bindings::MATERIAL_TEXTURES),
                ],
                variant,
                settings.hdr_format.vk(),
            )?;
            Ok((pass, 1))
        })?;
        Ok(())
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        draws(frame.variant)
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let io = PassIo::new(self.name())
            .slot_set(frame.slot, &bindings::FORWARD)
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
            )
            .touches(frame.hdr.into(), ImageUse::ColorAttachmentBlend);
        let absent = |io: PassIo, binding: &str| {
            // Not declared by pipelines without the feature: any image will do.
            io.bind_image(
                binding,
                frame.shared.absent_target.view(),
                ImageUse::FragmentSampled.state().layout,
                vk::Sampler::null(),
            )
        };
        let depth = frame.gbuffer.depth;
        // The TRANSMISSION variant reads the depth it is tested against: how far behind
        // glass the opaque surfaces are, and what rays leaving a volume march against.
        let io = if frame.variant.transmission {
            io.image(
                "scene_depth",
                depth,
                ImageUse::DepthAttachmentTestAndSampled,
            )
        } else {
            absent(
                io.touches(depth.into(), ImageUse::DepthAttachmentTest),
                "scene_depth",
            )
        };
        let io = match super::back_faces::BackFaceTargets::of(&frame.images) {
            Some(back_faces) if frame.variant.volume => io
                .image(
                    "back_face_depth",
                    back_faces.depth,
                    ImageUse::DepthFragmentSampled,
                )
                .sampled(
                    "back_face_normal",
                    back_faces.normal,
                    frame.shared.behind_sampler.raw(),
                    ImageUse::FragmentSampled,
                ),
            _ => absent(io, "back_face_depth").bind_image(
                "back_face_normal",
                frame.shared.absent_target.view(),
                ImageUse::FragmentSampled.state().layout,
                frame.shared.behind_sampler.raw(),
            ),
        };
        let io = match frame.images.find(super::behind::BEHIND) {
            Some(behind) if frame.variant.transmission => io.sampled(
                "behind",
                behind,
                frame.shared.behind_sampler.raw(),
                ImageUse::FragmentSampled,
            ),
            // Not declared by pipelines without transmission: any image will do.
            _ => io.bind_image(
                "behind",
                frame.shared.absent_target.view(),
                ImageUse::FragmentSampled.state().layout,
                frame.shared.behind_sampler.raw(),
            ),
        };
        super::lighting::lit_by(traced(io, frame), frame)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let forward: &ForwardPass = frame
            .registry
            .get(&key(frame.variant, frame.settings))
            .expect("prepared for the frame's variant");
        let push = &frame.lighting_push;
        let [x, y, z, _] = push.camera_position;
        forward.record(
            frame.device,
            cmd,
            ForwardTargets {
                hdr: frame.hdr,
                depth: frame.gbuffer.depth,
            },
            frame.scene,
            &frame.placement,
            frame.slot.set(&bindings::FORWARD),
            frame.view_projection,
            glam::Vec3::new(x, y, z),
            push.counts[0],
        );
    }
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
        let (bindings, attributes) = super::gbuffer::scene_vertex_input(variant);
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
                depth_compare: vk::CompareOp::LESS,
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
