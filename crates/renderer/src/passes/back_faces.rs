//! The far sides of the transmissive objects with a volume: their
//! nearest back face's depth and normal at each pixel, where the forward pass's
//! refracted rays leave those objects. Runs in frames whose forward pass draws such an
//! object (the VOLUME variant).
//!
//! Its pipeline (back_faces.vert + back_faces.frag): the far sides of the
//! transmissive objects that have a volume (KHR_materials_volume), front faces culled,
//! the nearest at each pixel: its depth and its world-space normal
//! ([`BackFaceTargets`]). forward.frag's VOLUME variant follows each ray
//! refracted into such an object to where its depth says the ray leaves, and refracts it
//! out through the normal there. Built only for scenes with such an object
//! (`ShaderVariant::volume`).

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::error::RenderError;
use crate::gbuffer::DEPTH_FORMAT;
use crate::gpu_types::GBufferPush;
use crate::graph::{BufferUse, ImageUse};
use crate::mesh_draw::{draw_in_order, Faces};
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;
use crate::scene_upload::GpuScene;
use crate::targets::{FrameImages, ImageRequest};
use crate::variant::ShaderVariant;
use combustion_vk::Image;
use combustion_vk::{
    vk, DescriptorSetLayout, Device, Pipeline, PipelineCache, PipelineLayout, ShaderCompiler,
};
use std::sync::Arc;

pub(crate) struct BackFaces;

/// The names of the far sides' depth and normal images.
const BACK_FACE_DEPTH: &str = "transmissive volumes' back face depth";
const BACK_FACE_NORMAL: &str = "transmissive volumes' back face normal";

/// The format of [`BackFaceTargets::normal`].
const BACK_FACE_NORMAL_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// The nearest back face of the transmissive volumes at each pixel: where a ray
/// refracted into such an object leaves it.
pub(crate) struct BackFaceTargets<'a> {
    /// Its depth (`DEPTH_FORMAT`, 1 where there is none).
    pub depth: &'a Image,
    /// Its world-space normal, as the mesh gives it (facing out of the object), in rgb.
    pub normal: &'a Image,
}

impl<'a> BackFaceTargets<'a> {
    /// The far sides among a frame's `images`, in frames of VOLUME variants.
    pub(crate) fn of(images: &FrameImages<'a>) -> Option<Self> {
        Some(Self {
            depth: images.find(BACK_FACE_DEPTH)?,
            normal: images.find(BACK_FACE_NORMAL)?,
        })
    }
}

/// Whether frames of `variant` draw the far sides: VOLUME variants with a forward pass
/// that refract by screen-space lookups (their frames have the back faces' images:
/// `images`; traced refraction meets the far sides by its rays).
fn draws(variant: ShaderVariant) -> bool {
    has_images(variant) && super::forward::draws(variant)
}

/// Whether frames of `variant` have the back faces' images.
fn has_images(variant: ShaderVariant) -> bool {
    variant.volume && super::behind::screen_space_refraction(variant)
}

/// Its one pipeline (variant-independent: every such variant shares it).
fn key() -> PipelineKey {
    PipelineKey::named(PassTimings::BACK_FACES)
}

impl FramePass for BackFaces {
    fn name(&self) -> &'static str {
        PassTimings::BACK_FACES
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&bindings::BACK_FACES];
        &SETS
    }

    fn prepare(
        &self,
        variant: ShaderVariant,
        _settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        if draws(variant) {
            registry.build(key(), |t| {
                let pass = BackFacesPass::new(
                    t.device,
                    t.compiler,
                    t.cache,
                    t.layouts.of(&bindings::BACK_FACES),
                )?;
                Ok((pass, 1))
            })?;
        }
        Ok(())
    }

    fn images(&self, variant: ShaderVariant, _settings: &RendererSettings) -> Vec<ImageRequest> {
        if !has_images(variant) {
            return Vec::new();
        }
        vec![
            ImageRequest::new(
                BACK_FACE_DEPTH,
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            ),
            ImageRequest::new(
                BACK_FACE_NORMAL,
                BACK_FACE_NORMAL_FORMAT,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            ),
        ]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        draws(frame.variant)
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let targets = BackFaceTargets::of(&frame.images).expect("runs only with them");
        PassIo::new(self.name())
            .slot_set(frame.slot, &bindings::BACK_FACES)
            .buffer(
                "objects",
                frame.placement.table,
                BufferUse::VertexStorageRead,
            )
            .posed_vertices(frame.scene)
            .touches(targets.normal.into(), ImageUse::ColorAttachmentWrite)
            .touches(targets.depth.into(), ImageUse::DepthAttachmentWrite)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let (Some(pass), Some(targets)) = (
            frame.registry.get::<BackFacesPass>(&key()),
            BackFaceTargets::of(&frame.images),
        ) else {
            return;
        };
        pass.record(
            frame.device,
            cmd,
            &targets,
            frame.scene,
            frame.slot.set(&bindings::BACK_FACES),
            frame.view_projection,
        );
    }
}

/// The back faces pass's pipeline and its layout: set 0 `bindings::BACK_FACES`, a
/// [`GBufferPush`] to the vertex stage.
pub struct BackFacesPass {
    layout: PipelineLayout,
    pipeline: Pipeline,
}

impl BackFacesPass {
    /// Compiles back_faces.vert and back_faces.frag and builds the pipeline through
    /// `cache`: positions and normals of the scene's first vertex stream.
    ///
    /// # Errors
    /// [`RenderError::Vulkan`] if a shader does not compile or the pipeline cannot be built.
    pub fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        set_layout: &DescriptorSetLayout,
    ) -> Result<Self, RenderError> {
        use crate::gpu_types::GpuVertex as Vertex;
        let (layout, pipeline) = crate::mesh_draw::first_stream_pipeline(
            device,
            compiler,
            cache,
            set_layout,
            ("back_faces.vert", "back_faces.frag"),
            (
                vk::ShaderStageFlags::VERTEX,
                std::mem::size_of::<GBufferPush>() as u32,
            ),
            &[
                (0, std::mem::offset_of!(Vertex, position)),
                (1, std::mem::offset_of!(Vertex, normal)),
            ],
            BACK_FACE_NORMAL_FORMAT,
        )?;
        Ok(Self { layout, pipeline })
    }

    /// Records the pass: the back faces of `scene`'s transmissive objects with a volume,
    /// into `targets` (normal in COLOR_ATTACHMENT_OPTIMAL, depth in the depth-attachment
    /// layout; both cleared: normal 0, depth 1).
    pub(crate) fn record(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        targets: &BackFaceTargets<'_>,
        scene: &GpuScene,
        set: vk::DescriptorSet,
        view_projection: glam::Mat4,
    ) {
        let extent = targets.depth.extent();
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(targets.normal.view())
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue::default())];
        let depth = crate::commands::cleared_depth_attachment(targets.depth.view());
        let rendering = vk::RenderingInfo::default()
            .render_area(crate::commands::whole(extent))
            .layer_count(1)
            .color_attachments(&color)
            .depth_attachment(&depth);
        let raw = device.raw();
        let mut push = GBufferPush {
            view_projection: view_projection.to_cols_array(),
            object_index: 0,
            _pad: [0; 3],
        };
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
            draw_in_order(raw, cmd, scene, Faces::Back, &scene.volumes, |object| {
                push.object_index = object as u32;
                raw.cmd_push_constants(
                    cmd,
                    self.layout.raw(),
                    vk::ShaderStageFlags::VERTEX,
                    0,
                    bytemuck::bytes_of(&push),
                );
            });
            raw.cmd_end_rendering(cmd);
        }
    }
}
