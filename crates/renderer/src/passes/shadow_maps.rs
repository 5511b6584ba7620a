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
use std::sync::Arc;

use combustion_scene::box_corners;
use combustion_vk::{
    DescriptorSetLayout, Device, GraphicsPipelineDesc, Pipeline, PipelineCache, PipelineLayout,
    ShaderCompiler, ShaderModule, ShaderStage,
};
use glam::{Mat4, Vec3};

use crate::gpu_types::GBufferPush;
use crate::scene_upload::GpuScene;
use crate::shadows::{ShadowMaps as MapArray, SHADOW_MAP_FORMAT};
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

/// The depth-only pipelines that render the scene's objects into a shadow map
/// (shadow.vert, and shadow.frag, which writes nothing): positions only, both faces
/// (a caster blocks light with either face, as the f64 visibility oracle counts it).
/// Cut-out casters (`AlphaMode::Mask`) are drawn by a second pipeline, built with
/// `ALPHA_MASK` once a scene has them, that reads their base colour's alpha and
/// discards where the surface is absent.
pub(crate) struct ShadowCasterPass {
    layout: PipelineLayout,
    pipeline: Pipeline,
    masked: Option<Pipeline>,
}

impl ShadowCasterPass {
    /// Builds the opaque casters' pipeline: set 0 of `set_layout` (the object and
    /// material tables), set 1 of `material_set_layout` (read by the cut-out pipeline
    /// only), the map's view-projection and the object index as vertex push constants.
    pub(crate) fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        [set_layout, material_set_layout]: [&DescriptorSetLayout; 2],
    ) -> Result<Self, RenderError> {
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX,
            offset: 0,
            size: std::mem::size_of::<GBufferPush>() as u32,
        }];
        let layout = PipelineLayout::new(device, &[set_layout, material_set_layout], &push)?;
        let pipeline = Self::pipeline(device, compiler, cache, &layout, false)?;
        Ok(Self {
            layout,
            pipeline,
            masked: None,
        })
    }

    /// Whether the cut-out casters' pipeline is built.
    pub(crate) fn has_masked(&self) -> bool {
        self.masked.is_some()
    }

    /// Builds the cut-out casters' pipeline (once; nothing replaces a pipeline a frame
    /// in flight may use).
    pub(crate) fn add_masked(
        &mut self,
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
    ) -> Result<(), RenderError> {
        if self.masked.is_none() {
            self.masked = Some(Self::pipeline(device, compiler, cache, &self.layout, true)?);
        }
        Ok(())
    }

    fn pipeline(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        layout: &PipelineLayout,
        masked: bool,
    ) -> Result<Pipeline, RenderError> {
        let defines: &[(&str, Option<&str>)] = if masked { &[("ALPHA_MASK", None)] } else { &[] };
        let vertex = ShaderModule::new(
            device,
            &compiler.compile("shadow.vert", ShaderStage::Vertex, defines)?,
            ShaderStage::Vertex,
        )?;
        let fragment = ShaderModule::new(
            device,
            &compiler.compile("shadow.frag", ShaderStage::Fragment, defines)?,
            ShaderStage::Fragment,
        )?;
        use crate::gpu_types::GpuVertex as Vertex;
        let mut bindings = vec![vk::VertexInputBindingDescription {
            binding: 0,
            stride: std::mem::size_of::<Vertex>() as u32,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let mut attributes = vec![vk::VertexInputAttributeDescription {
            location: 0,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: std::mem::offset_of!(Vertex, position) as u32,
        }];
        if masked {
            // Both coordinate sets (the base colour slot may sample either) and the
            // colours (their alpha; objects without them read white).
            attributes.push(vk::VertexInputAttributeDescription {
                location: 1,
                binding: 0,
                format: vk::Format::R32G32_SFLOAT,
                offset: std::mem::offset_of!(Vertex, uv) as u32,
            });
            use crate::mesh_draw::ExtraStream;
            ExtraStream::SecondCoordinates.declare(2, &mut bindings, &mut attributes);
            ExtraStream::Colors.declare(3, &mut bindings, &mut attributes);
        }
        Ok(Pipeline::graphics(
            device,
            &GraphicsPipelineDesc {
                vertex: &vertex,
                fragment: &fragment,
                layout,
                vertex_bindings: &bindings,
                vertex_attributes: &attributes,
                color_formats: &[],
                depth_format: Some(SHADOW_MAP_FORMAT),
                depth_write: true,
                depth_compare: vk::CompareOp::LESS,
                blend: combustion_vk::ColorBlend::Replace,
                cache: Some(cache),
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            },
        )?)
    }

    /// Records `cascades` (one per layer view of `maps`, in order): each layer cleared
    /// to the far depth and every object of `scene` drawn into it. The maps must be in
    /// the depth-attachment layout.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        maps: &MapArray,
        scene: &GpuScene,
        placement: &crate::placement::Placement<'_>,
        set: vk::DescriptorSet,
        cascades: &[Mat4],
    ) {
        let extent = maps.image.extent();
        let raw = device.raw();
        for (view, world_to_clip) in maps.layer_views.iter().zip(cascades) {
            let depth_attachment = crate::commands::cleared_depth_attachment(view.raw());
            let rendering = vk::RenderingInfo::default()
                .render_area(crate::commands::whole(extent))
                .layer_count(1)
                .depth_attachment(&depth_attachment);
            // SAFETY: recording state (the frame's); the maps and the scene outlive the
            // frame (replaced ones are retired).
            unsafe { raw.cmd_begin_rendering(cmd, &rendering) };
            crate::commands::set_viewport_and_scissor(raw, cmd, extent);
            // Push constants per object, below.
            crate::commands::bind_pass(
                raw,
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                &self.pipeline,
                &self.layout,
                set,
                vk::ShaderStageFlags::VERTEX,
                &[],
            );
            // The opaque casters, then the cut-out ones with their own pipeline.
            crate::mesh_draw::TwoRounds {
                layout: &self.layout,
                cut_out_pipeline: self.masked.as_ref(),
                view_projection: *world_to_clip,
                textures_in_opaque_round: false,
            }
            .record(raw, cmd, scene, crate::mesh_draw::Faces::Both, |object| {
                let index = object.object_index as usize;
                if !scene.casts_shadows.get(index).copied().unwrap_or(true) {
                    return false;
                }
                // Objects wholly beside the map cast nothing into it (along the
                // light, the map spans the whole scene).
                !matches!(
                    placement.bounds.get(index),
                    Some(Some((lo, hi))) if beside_map(world_to_clip, *lo, *hi)
                )
            });
            // SAFETY: as above.
            unsafe { raw.cmd_end_rendering(cmd) };
        }
    }
}

/// Whether the box (lo, hi) lies wholly outside one side of the map `world_to_clip`
/// renders (x or y beyond ±w at every corner, in homogeneous coordinates: right for an
/// orthographic and a perspective map alike, corners behind a light included).
fn beside_map(world_to_clip: &Mat4, lo: Vec3, hi: Vec3) -> bool {
    let corners = box_corners(lo, hi).map(|corner| *world_to_clip * corner.extend(1.0));
    let all = |outside: fn(&glam::Vec4) -> bool| corners.iter().all(outside);
    all(|c| c.x > c.w)
        || all(|c| c.x < -c.w)
        || all(|c| c.y > c.w)
        || all(|c| c.y < -c.w)
        || all(|c| c.w <= 0.0)
}
