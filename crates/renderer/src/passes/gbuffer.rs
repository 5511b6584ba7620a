//! The G-buffer pass: every object of the scene rasterised into the G-buffer's colour
//! targets and depth (gbuffer.vert/.frag; docs/gbuffer.md), with its pipelines: the
//! plain one, the cut-outs' (alpha tested) and the points' and lines'.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::error::RenderError;
use std::sync::Arc;

use combustion_scene::Topology;
use combustion_vk::{
    DescriptorSetLayout, Device, GraphicsPipelineDesc, Pipeline, PipelineCache, PipelineLayout,
    ShaderCompiler, ShaderModule, ShaderStage,
};

use crate::gbuffer::{
    GBufferTargets, CLEARCOAT_FORMAT, DEPTH_FORMAT, FILM_FORMAT, MATERIAL_DIRECTION_FORMAT,
    SHEEN_FORMAT, SPECULAR_FORMAT,
};
use crate::gpu_types::GBufferPush;
use crate::graph::{BufferUse, ImageUse};
use crate::options::GBufferStorage;
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;
use crate::scene_upload::GpuScene;
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

/// The G-buffer pass: rasterises every object, writing the G-buffer and depth; cut-out
/// objects (`AlphaMode::Mask`) after the others, through an alpha-testing pipeline, then
/// points and lines through pipelines of their own.
/// Reads: vertex/index buffers, the object table, the material table. Writes: [`GBufferTargets`].
pub struct GBufferPass {
    pub(crate) layout: PipelineLayout,
    pipeline: Pipeline,
    /// The cut-out objects' pipeline (`ALPHA_MASK`: alpha tested, discarded where the
    /// surface is absent), in variants with cut-out materials.
    masked: Option<Pipeline>,
    /// The line lists' pipeline (the opaque one's shaders), in variants with lines.
    lines: Option<Pipeline>,
    /// The point lists' pipeline (gbuffer.vert built with `POINTS`), in variants with
    /// points.
    points: Option<Pipeline>,
}

impl GBufferPass {
    /// Compiles `gbuffer.vert` and `gbuffer.frag` with `variant`'s and `storage`'s `#define`s and builds the
    /// pass's graphics pipeline (through `cache`): set 0 of `set_layout` (object and material
    /// tables), set 1 of `material_set_layout` (one material's textures), the view-projection
    /// and object index as vertex push constants, a fourth colour attachment of
    /// `emissive_format` in variants with the emissive + occlusion target, and then the
    /// clear coat's ([`CLEARCOAT_FORMAT`]), the sheen's ([`SHEEN_FORMAT`]) and the thin
    /// film's ([`FILM_FORMAT`]) and the specular one ([`SPECULAR_FORMAT`]) in variants
    /// with them.
    ///
    /// # Errors
    /// [`RenderError::Vulkan`] if a shader does not compile or the pipeline cannot be built.
    pub fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        [set_layout, material_set_layout]: [&DescriptorSetLayout; 2],
        variant: ShaderVariant,
        storage: GBufferStorage,
        emissive_format: vk::Format,
    ) -> Result<Self, RenderError> {
        let mut defines = variant.defines();
        defines.extend(storage.defines());
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX,
            offset: 0,
            size: std::mem::size_of::<GBufferPush>() as u32,
        }];
        let layout = PipelineLayout::new(device, &[set_layout, material_set_layout], &push)?;
        let vertex_shader = |defines: &[(&str, Option<&str>)]| {
            ShaderModule::new(
                device,
                &compiler.compile("gbuffer.vert", ShaderStage::Vertex, defines)?,
                ShaderStage::Vertex,
            )
        };
        let vertex = vertex_shader(&defines)?;
        let fragment = |defines: &[(&str, Option<&str>)]| {
            ShaderModule::new(
                device,
                &compiler.compile("gbuffer.frag", ShaderStage::Fragment, defines)?,
                ShaderStage::Fragment,
            )
        };
        let (bindings, attributes) = scene_vertex_input(variant);
        let mut color_formats = vec![
            storage.base_color.vk(),
            storage.surface.vk(),
            MATERIAL_DIRECTION_FORMAT,
        ];
        if variant.has_emissive_occlusion_target() {
            color_formats.push(emissive_format);
        }
        if variant.clearcoat {
            color_formats.push(CLEARCOAT_FORMAT);
        }
        if variant.sheen {
            color_formats.push(SHEEN_FORMAT);
        }
        if variant.iridescence {
            color_formats.push(FILM_FORMAT);
        }
        if variant.specular {
            color_formats.push(SPECULAR_FORMAT);
        }
        let pipeline_of = |topology, vertex: &ShaderModule, fragment: &ShaderModule| {
            Pipeline::graphics(
                device,
                &GraphicsPipelineDesc {
                    topology,
                    vertex,
                    fragment,
                    layout: &layout,
                    vertex_bindings: &bindings,
                    vertex_attributes: &attributes,
                    color_formats: &color_formats,
                    depth_format: Some(DEPTH_FORMAT),
                    depth_write: true,
                    depth_compare: vk::CompareOp::LESS,
                    blend: combustion_vk::ColorBlend::Replace,
                    cache: Some(cache),
                },
            )
        };
        let pipeline = |fragment: &ShaderModule| {
            pipeline_of(vk::PrimitiveTopology::TRIANGLE_LIST, &vertex, fragment)
        };
        let opaque_fragment = fragment(&defines)?;
        let opaque = pipeline(&opaque_fragment)?;
        let masked = if variant.alpha_mask {
            let mut defines = defines.clone();
            defines.push(("ALPHA_MASK", None));
            Some(pipeline(&fragment(&defines)?)?)
        } else {
            None
        };
        let lines = variant
            .lines
            .then(|| pipeline_of(vk::PrimitiveTopology::LINE_LIST, &vertex, &opaque_fragment))
            .transpose()?;
        let points = if variant.points {
            let mut defines = defines.clone();
            defines.push(("POINTS", None));
            let vertex = vertex_shader(&defines)?;
            Some(pipeline_of(
                vk::PrimitiveTopology::POINT_LIST,
                &vertex,
                &opaque_fragment,
            )?)
        } else {
            None
        };
        Ok(Self {
            layout,
            pipeline: opaque,
            masked,
            lines,
            points,
        })
    }

    /// How many pipelines it has for points and lines (0 to 2).
    pub(crate) fn stroke_pipelines(&self) -> u64 {
        u64::from(self.lines.is_some()) + u64::from(self.points.is_some())
    }

    /// Records the pass. Targets must be in COLOR_ATTACHMENT / DEPTH_ATTACHMENT layouts.
    pub fn record(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        targets: &GBufferTargets<'_>,
        scene: &GpuScene,
        set: vk::DescriptorSet,
        view_projection: glam::Mat4,
    ) {
        let extent = targets.depth.extent();
        let color_attachments: Vec<_> = targets
            .attachments()
            .iter()
            .map(|image| {
                vk::RenderingAttachmentInfo::default()
                    .image_view(image.view())
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue {
                        color: vk::ClearColorValue { uint32: [0; 4] },
                    })
            })
            .collect();
        let depth_attachment = crate::commands::cleared_depth_attachment(targets.depth.view());
        let rendering = vk::RenderingInfo::default()
            .render_area(crate::commands::whole(extent))
            .layer_count(1)
            .color_attachments(&color_attachments)
            .depth_attachment(&depth_attachment);
        let raw = device.raw();
        // SAFETY: recording into a command buffer in the recording state, with resources
        // that outlive the submission.
        unsafe {
            crate::commands::begin_scene_drawing(
                raw,
                cmd,
                &rendering,
                extent,
                (&self.pipeline, &self.layout),
                set,
            );
            // Stream 1 (coordinate set 1) is read only by the TEXTURE_TRANSFORMS
            // pipelines. The cut-outs last, behind the opaque objects' depth.
            let rounds = crate::mesh_draw::TwoRounds {
                layout: &self.layout,
                cut_out_pipeline: self.masked.as_ref(),
                view_projection,
                textures_in_opaque_round: true,
            };
            rounds.record(raw, cmd, scene, crate::mesh_draw::Faces::OfMaterial, |_| {
                true
            });
            // Points and lines last (in variants with them).
            rounds.record_strokes(
                raw,
                cmd,
                scene,
                [
                    (Topology::Lines, self.lines.as_ref()),
                    (Topology::Points, self.points.as_ref()),
                ],
            );
            raw.cmd_end_rendering(cmd);
        }
    }
}

/// The vertex streams and attributes gbuffer.vert reads in `variant`: stream 0
/// (`GpuVertex`: position, normal, tangent, and the first coordinate set where a
/// material samples a texture) at locations 0–3, the
/// second coordinate set at 4 (TEXTURE_TRANSFORMS) and the colours at 5 (VERTEX_COLORS),
/// each a stream of its own read only where the shader reads it. Every pass that runs
/// gbuffer.vert declares these.
pub(crate) fn scene_vertex_input(
    variant: ShaderVariant,
) -> (
    Vec<vk::VertexInputBindingDescription>,
    Vec<vk::VertexInputAttributeDescription>,
) {
    use crate::gpu_types::GpuVertex as Vertex;
    let stride = std::mem::size_of::<Vertex>() as u32;
    let mut bindings = vec![vk::VertexInputBindingDescription {
        binding: 0,
        stride,
        input_rate: vk::VertexInputRate::VERTEX,
    }];
    let mut attributes = vec![
        vk::VertexInputAttributeDescription {
            location: 0,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: std::mem::offset_of!(Vertex, position) as u32,
        },
        vk::VertexInputAttributeDescription {
            location: 1,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: std::mem::offset_of!(Vertex, normal) as u32,
        },
        vk::VertexInputAttributeDescription {
            location: 2,
            binding: 0,
            format: vk::Format::R32G32B32A32_SFLOAT,
            offset: std::mem::offset_of!(Vertex, tangent) as u32,
        },
    ];
    // The first coordinate set where a material samples a texture (TEXTURES).
    if variant.textures || variant.texture_transforms {
        attributes.push(vk::VertexInputAttributeDescription {
            location: 3,
            binding: 0,
            format: vk::Format::R32G32_SFLOAT,
            offset: std::mem::offset_of!(Vertex, uv) as u32,
        });
    }
    // The second coordinate set and the colours, streams of their own, only where the
    // shader reads them.
    use crate::mesh_draw::ExtraStream;
    if variant.texture_transforms {
        ExtraStream::SecondCoordinates.declare(4, &mut bindings, &mut attributes);
    }
    if variant.vertex_colors {
        ExtraStream::Colors.declare(5, &mut bindings, &mut attributes);
    }
    (bindings, attributes)
}
