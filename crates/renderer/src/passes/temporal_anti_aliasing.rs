//! Temporal anti-aliasing (`--anti-aliasing taa`: the optional pass
//! `temporal-anti-aliasing`): each frame's camera is moved by a sub-pixel jitter (the
//! Halton (2, 3) sequence less its mean, [`jitter`]), and each pixel's radiance is blended with the
//! history of the pixels its surface covered in the frames before (docs/camera.md).
//! Three passes:
//! - motion vectors (motion.vert, motion.frag), after the G-buffer: the objects drawn
//!   again into a target of their motion since the previous frame — the camera's and
//!   each object's transform's — and their view depth then and now, with a depth buffer
//!   of their own;
//! - the resolve (temporal_resolve.frag, timed with the copy): the history reprojected
//!   by the motion, rejected on disocclusion, clipped to this frame's neighbourhood in
//!   YCoCg, blended one tenth this frame to nine tenths history, into this frame's
//!   history (two images used in turn);
//! - the copy: the resolved radiance into the HDR image, which bloom, the auto exposure
//!   and the output pass read.
//!
//! (A fourth, the motion history, keeps the posed vertices for the next frame in scenes
//! with skinned or morphed objects.)
//!
//! Skinned and morphed vertices move from their previous pose: the deform pass's posed
//! vertices are copied, after the motion pass has read them, into a buffer the next
//! frame's motion pass reads as the previous pose (the motion history pass).
//!
//! Rule for what the motion pass does not see: blended and transmissive surfaces (drawn
//! by the forward pass) take the motion of the opaque surface behind them; the
//! neighbourhood clipping bounds their ghosting.

use combustion_vk::{
    vk, DescriptorSetLayout, Device, Image, Pipeline, PipelineCache, PipelineLayout, ShaderCompiler,
};
use glam::Mat4;
use std::sync::Arc;

use super::{FrameContext, FramePass};
use crate::bindings::{Binding, BindingKind, SetDecl, FRAGMENT, OBJECTS, VERTEX};
use crate::error::RenderError;
use crate::fullscreen::FullscreenPass;
use crate::gbuffer::DEPTH_FORMAT;
use crate::graph::{BufferUse, ImageUse};
use crate::mesh_draw::{draw_objects, Faces};
use crate::options::{OptionalPass, RendererSettings};
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::push::{push_block, PushBlock};
use crate::targets::ImageRequest;
use crate::variant::ShaderVariant;

/// Its option.
pub(crate) static OPTION: OptionalPass = OptionalPass {
    name: "temporal-anti-aliasing",
    define: "TEMPORAL_ANTI_ALIASING",
    help: "temporal anti-aliasing: a jittered camera, each pixel blended with its reprojected history (--anti-aliasing taa)",
    needs_ray_queries: false,
    choice: None,
    needs_environment: None,
};

/// The share of this frame in each resolved pixel (the history keeps the rest).
pub const TEMPORAL_BLEND: f32 = 0.2;

/// Frames of the jitter sequence before it repeats.
pub const JITTER_PERIOD: u64 = 16;

/// The motion target: motion in pixels (xy), view depth a frame ago (z) and now (w).
const MOTION: &str = "motion vectors";
const MOTION_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
/// The motion pass's own depth buffer.
const MOTION_DEPTH: &str = "motion vectors' depth";
/// The two history images, used in turn.
const HISTORY: [&str; 2] = ["temporal history 0", "temporal history 1"];

/// The motion pass.
pub(crate) struct Motion;
/// The copy of this frame's posed vertices for the next frame's motion.
pub(crate) struct MotionHistory;
/// The resolve.
pub(crate) struct TemporalResolve;
/// The copy into the HDR image.
pub(crate) struct TemporalCopy;

/// What a frame of temporal anti-aliasing needs beyond the frame's own (the renderer's
/// [`TemporalState`] makes it).
#[derive(Clone, Copy, Debug)]
pub(crate) struct TemporalFrame {
    /// The camera's view-projection without the jitter.
    pub unjittered: Mat4,
    /// The previous frame's, without its jitter.
    pub previous: Mat4,
    /// The history is not to be read (the first frame, or another scene or size).
    pub reset: bool,
    /// Which history this frame writes (it reads the other).
    pub parity: usize,
}

/// What a history belongs to: a scene (its address and geometry version) at a size.
pub(crate) type HistoryKey = (usize, u64, [u32; 2]);

/// Marks an object without posed vertices in the previous-vertex bases.
pub(crate) const NOT_POSED: u32 = u32::MAX;

/// What the renderer keeps between frames of temporal anti-aliasing.
#[derive(Default)]
pub(crate) struct TemporalState {
    /// The previous frame's posed vertices (`GpuVertex`), for scenes with skinned or
    /// morphed objects: the scene's posed buffer copied at the end of each frame's
    /// motion pass; made at the first such frame, the size of the scene's.
    pub(crate) previous_vertices: Option<combustion_vk::Buffer>,
    /// The last frame's scene (its address and geometry version), size, unjittered
    /// view-projection and object transforms.
    last: Option<(HistoryKey, Mat4, Vec<Mat4>)>,
    /// Frames rendered since the history started.
    frames: u64,
}

impl TemporalState {
    /// The frame after the last one: its jitter index, and the previous camera and
    /// transforms (this frame's own where the history starts again). Remembers this
    /// frame's for the next.
    pub(crate) fn advance(
        &mut self,
        key: HistoryKey,
        unjittered: Mat4,
        transforms: Vec<Mat4>,
    ) -> (TemporalFrame, Vec<Mat4>) {
        let (previous, previous_transforms, reset) = match self.last.take() {
            Some((last_key, camera, models)) if last_key == key => (camera, models, false),
            _ => {
                self.frames = 0;
                (unjittered, transforms.clone(), true)
            }
        };
        let frame = TemporalFrame {
            unjittered,
            previous,
            reset,
            parity: (self.frames % 2) as usize,
        };
        self.frames += 1;
        self.last = Some((key, unjittered, transforms));
        (frame, previous_transforms)
    }

    /// The history's frames so far (the jitter's index).
    pub(crate) fn frames(&self) -> u64 {
        self.frames
    }

    /// Forgets the history (frames that never ran, a change of shading); keeps the
    /// previous vertices' buffer (the next history starts by writing it).
    pub(crate) fn forget(&mut self) {
        self.last = None;
        self.frames = 0;
    }

    /// A buffer for the previous posed vertices of `scene` (made, or replaced by a
    /// larger one, here: the old one is returned to be retired), or `None` for a scene
    /// without deformed objects.
    pub(crate) fn fit_previous_vertices(
        &mut self,
        device: &Arc<Device>,
        scene: &crate::scene_upload::GpuScene,
    ) -> Result<Option<combustion_vk::Buffer>, RenderError> {
        let Some(deform) = &scene.gpu.deform else {
            return Ok(None);
        };
        let size = deform.posed.size();
        if self
            .previous_vertices
            .as_ref()
            .is_some_and(|b| b.size() >= size)
        {
            return Ok(None);
        }
        let made = combustion_vk::Buffer::new(
            device,
            "temporal previous posed vertices",
            size,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            crate::buffers::GPU_ONLY,
        )?;
        // The history over the old buffer is gone with it.
        self.forget();
        Ok(self.previous_vertices.replace(made))
    }
}

/// The radical inverse of `index` in `base`: the Halton sequence's element.
fn halton(mut index: u64, base: u64) -> f32 {
    let (mut result, mut f) = (0.0f64, 1.0f64);
    while index > 0 {
        f /= base as f64;
        result += f * (index % base) as f64;
        index /= base;
    }
    result as f32
}

/// The jitter of frame `index` of a history, in pixels: Halton (2, 3) from its first
/// element, repeating every [`JITTER_PERIOD`] frames, less the period's mean (so that a
/// history converges on the pixel's centre: the sixteen points' own mean is off it by
/// (−0.029, −0.037) of a pixel).
pub fn jitter(index: u64) -> [f32; 2] {
    let point = |i: u64| {
        [
            halton(i % JITTER_PERIOD + 1, 2),
            halton(i % JITTER_PERIOD + 1, 3),
        ]
    };
    let mut mean = [0.0f32; 2];
    for i in 0..JITTER_PERIOD {
        let p = point(i);
        mean[0] += p[0] / JITTER_PERIOD as f32;
        mean[1] += p[1] / JITTER_PERIOD as f32;
    }
    let p = point(index);
    [p[0] - mean[0], p[1] - mean[1]]
}

/// `view_projection` moved by `jitter` pixels in a frame of `extent`.
pub(crate) fn jittered(view_projection: Mat4, jitter: [f32; 2], extent: vk::Extent2D) -> Mat4 {
    let dx = 2.0 * jitter[0] / extent.width as f32;
    let dy = 2.0 * jitter[1] / extent.height as f32;
    // Clip x' = x + dx·w: a translation of NDC by (dx, dy).
    let shift = Mat4::from_cols(
        glam::Vec4::X,
        glam::Vec4::Y,
        glam::Vec4::Z,
        glam::Vec4::new(dx, dy, 0.0, 1.0),
    );
    shift * view_projection
}

/// Whether frames of `variant` run it.
pub(crate) fn wanted(variant: ShaderVariant) -> bool {
    variant.optional_passes.contains(&OPTION)
}

push_block! {
    /// The motion pass's push constants (`push/motion.glsl`, both stages).
    pub(crate) struct MotionPush in "motion" {
        /// The jittered view-projection (where the G-buffer drew).
        view_projection: [f32; 16],
        /// The view-projection without the jitter.
        unjittered: [f32; 16],
        /// The previous frame's, without its jitter.
        previous: [f32; 16],
        /// The frame's size in pixels.
        extent: [f32; 2],
        /// The drawn object's index.
        object_index: u32,
    }
}

push_block! {
    /// The resolve's push constants (`push/temporal_resolve.glsl`).
    pub(crate) struct ResolvePush in "temporal_resolve" {
        /// The inverse of the unjittered view-projection.
        inverse_unjittered: [f32; 16],
        /// The previous frame's unjittered view-projection.
        previous: [f32; 16],
        /// This frame's share.
        blend: f32,
        /// 1: no history.
        reset: u32,
    }
}

/// The motion pass's set: the object table and each object's previous transform.
pub(crate) static MOTION_SET: SetDecl = SetDecl {
    name: "motion",
    set: 0,
    bindings: &[
        OBJECTS,
        Binding::new(
            "previous_models",
            BindingKind::StorageBuffer {
                block: "PreviousModels",
                element: "mat4",
            },
            VERTEX,
        ),
        Binding::new(
            "previous_vertex_bases",
            BindingKind::StorageBuffer {
                block: "PreviousVertexBases",
                element: "uint",
            },
            VERTEX,
        ),
        Binding::new(
            "previous_vertices",
            BindingKind::StorageBuffer {
                block: "PreviousVertices",
                element: "float",
            },
            VERTEX,
        ),
    ],
    includes: &["gpu_types.glsl"],
};

/// The resolve's set.
pub(crate) static RESOLVE_SET: SetDecl = SetDecl {
    name: "temporal_resolve",
    set: 0,
    bindings: &[
        Binding::new("hdr_image", BindingKind::Texture2D, FRAGMENT),
        Binding::new("motion_vectors", BindingKind::Texture2D, FRAGMENT),
        Binding::new("gbuffer_depth", BindingKind::Texture2D, FRAGMENT),
        Binding::new("history", BindingKind::Texture2D, FRAGMENT),
    ],
    includes: &[],
};

/// The motion pass's pipeline.
struct MotionPipeline {
    layout: PipelineLayout,
    pipeline: Pipeline,
}

impl MotionPipeline {
    fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        set_layout: &DescriptorSetLayout,
    ) -> Result<Self, RenderError> {
        let (layout, pipeline) = crate::mesh_draw::first_stream_pipeline(
            device,
            compiler,
            cache,
            set_layout,
            ("motion.vert", "motion.frag"),
            (
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                std::mem::size_of::<MotionPush>() as u32,
            ),
            &[(
                0,
                std::mem::offset_of!(crate::gpu_types::GpuVertex, position),
            )],
            MOTION_FORMAT,
        )?;
        Ok(Self { layout, pipeline })
    }
}

/// Its pipelines.
struct TemporalPipelines {
    motion: MotionPipeline,
    resolve: FullscreenPass,
}

fn key(settings: &RendererSettings) -> PipelineKey {
    PipelineKey {
        formats: vec![settings.hdr_format.vk()],
        ..PipelineKey::named("temporal anti-aliasing")
    }
}

fn pipelines<'a>(frame: &FrameContext<'a>) -> &'a TemporalPipelines {
    frame
        .registry
        .get(&key(frame.settings))
        .expect("prepared with the frame's variant")
}

/// The scene's deformation (its posed vertices) and the previous frame's copy of them,
/// in frames whose motion history runs.
fn posed_and_previous<'a>(
    frame: &FrameContext<'a>,
) -> (&'a crate::deform::SceneDeform, &'a combustion_vk::Buffer) {
    let deform = frame
        .scene
        .gpu
        .deform
        .as_ref()
        .expect("runs only with them");
    (deform, frame.previous_vertices.expect("runs only with it"))
}

/// The frame's temporal inputs (frames that run it have them).
fn temporal(frame: &FrameContext<'_>) -> TemporalFrame {
    frame.temporal.expect("made for every frame that runs it")
}

impl FramePass for Motion {
    fn name(&self) -> &'static str {
        "motion vectors"
    }

    fn option(&self) -> Option<&'static OptionalPass> {
        Some(&OPTION)
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&MOTION_SET];
        &SETS
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![MotionPush::header()]
    }

    fn prepare(
        &self,
        variant: ShaderVariant,
        settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        if !wanted(variant) {
            return Ok(());
        }
        registry.build(key(settings), |t| {
            let pipelines = TemporalPipelines {
                motion: MotionPipeline::new(
                    t.device,
                    t.compiler,
                    t.cache,
                    t.layouts.of(&MOTION_SET),
                )?,
                resolve: FullscreenPass::new(
                    t.device,
                    t.compiler,
                    t.cache,
                    "temporal_resolve.frag",
                    &[],
                    t.layouts.of(&RESOLVE_SET),
                    std::mem::size_of::<ResolvePush>() as u32,
                    settings.hdr_format.vk(),
                )?,
            };
            Ok((pipelines, 2))
        })?;
        Ok(())
    }

    fn images(&self, variant: ShaderVariant, settings: &RendererSettings) -> Vec<ImageRequest> {
        if !wanted(variant) {
            return Vec::new();
        }
        let history = |name| {
            ImageRequest::new(
                name,
                settings.hdr_format.vk(),
                vk::ImageUsageFlags::COLOR_ATTACHMENT
                    | vk::ImageUsageFlags::SAMPLED
                    | vk::ImageUsageFlags::TRANSFER_SRC,
            )
        };
        vec![
            ImageRequest::new(
                MOTION,
                MOTION_FORMAT,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            ),
            ImageRequest::new(
                MOTION_DEPTH,
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            ),
            history(HISTORY[0]),
            history(HISTORY[1]),
        ]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        wanted(frame.variant)
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let io = PassIo::new(self.name())
            .slot_set(frame.slot, &MOTION_SET)
            .buffer(
                "objects",
                frame.placement.table,
                BufferUse::VertexStorageRead,
            )
            .bind_buffer("previous_models", &frame.slot.previous_models)
            .bind_buffer("previous_vertex_bases", &frame.slot.previous_vertex_bases);
        // The previous pose, where the scene deforms (else a placeholder never read:
        // every object's base says it has none).
        let io = match (frame.previous_vertices, &frame.scene.gpu.deform) {
            (Some(previous), Some(_)) => {
                io.buffer("previous_vertices", previous, BufferUse::VertexStorageRead)
            }
            _ => io.bind_buffer("previous_vertices", &frame.slot.previous_vertex_bases),
        };
        io.posed_vertices(frame.scene)
            .touches(
                frame.images.get(MOTION).into(),
                ImageUse::ColorAttachmentWrite,
            )
            .touches(
                frame.images.get(MOTION_DEPTH).into(),
                ImageUse::DepthAttachmentWrite,
            )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let t = temporal(frame);
        let pass = &pipelines(frame).motion;
        let motion: &Image = frame.images.get(MOTION);
        let extent = frame.extent();
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(motion.view())
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue::default())];
        let depth =
            crate::commands::cleared_depth_attachment(frame.images.get(MOTION_DEPTH).view());
        let rendering = vk::RenderingInfo::default()
            .render_area(crate::commands::whole(extent))
            .layer_count(1)
            .color_attachments(&color)
            .depth_attachment(&depth);
        let raw = frame.device.raw();
        let mut push = MotionPush {
            view_projection: frame.view_projection.to_cols_array(),
            unjittered: t.unjittered.to_cols_array(),
            previous: t.previous.to_cols_array(),
            extent: [extent.width as f32, extent.height as f32],
            object_index: 0,
        };
        // SAFETY: recording into a command buffer in the recording state, with resources
        // that outlive the submission (a dropped scene is retired, not freed).
        unsafe {
            crate::commands::begin_scene_drawing(
                raw,
                cmd,
                &rendering,
                extent,
                (&pass.pipeline, &pass.layout),
                frame.slot.set(&MOTION_SET),
            );
            // The surfaces the G-buffer holds: opaque and cut-out triangles (a cut-out's
            // holes move with it: drawn whole, the surface behind shows its own motion
            // only where nothing is drawn in front).
            draw_objects(
                raw,
                cmd,
                frame.scene,
                Faces::OfMaterial,
                |object| object.in_round(false, false),
                |object| {
                    push.object_index = object.object_index;
                    raw.cmd_push_constants(
                        cmd,
                        pass.layout.raw(),
                        vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                        0,
                        bytemuck::bytes_of(&push),
                    );
                },
            );
            raw.cmd_end_rendering(cmd);
        }
    }
}

impl FramePass for MotionHistory {
    fn name(&self) -> &'static str {
        "motion history"
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        wanted(frame.variant)
            && frame.scene.gpu.deform.is_some()
            && frame.previous_vertices.is_some()
    }

    /// Timed with the next timed pass.
    fn timed(&self) -> bool {
        false
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let (deform, previous) = posed_and_previous(frame);
        PassIo::new(self.name())
            .uses_buffer(&deform.posed, BufferUse::TransferSource)
            .uses_buffer(previous, BufferUse::TransferDestination)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let (deform, previous) = posed_and_previous(frame);
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: deform.posed.size(),
        }];
        // SAFETY: outside any rendering; the previous buffer is at least the posed one's
        // size (TemporalState::fit_previous_vertices).
        unsafe {
            frame
                .device
                .raw()
                .cmd_copy_buffer(cmd, deform.posed.raw(), previous.raw(), &region)
        };
    }
}

impl FramePass for TemporalResolve {
    fn name(&self) -> &'static str {
        "temporal resolve"
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&RESOLVE_SET];
        &SETS
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![ResolvePush::header()]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        wanted(frame.variant)
    }

    /// Timed with the copy.
    fn timed(&self) -> bool {
        false
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let t = temporal(frame);
        PassIo::new(self.name())
            .slot_set(frame.slot, &RESOLVE_SET)
            .image("hdr_image", frame.hdr, ImageUse::FragmentSampled)
            .image(
                "motion_vectors",
                frame.images.get(MOTION),
                ImageUse::FragmentSampled,
            )
            .image(
                "gbuffer_depth",
                frame.gbuffer.depth,
                ImageUse::DepthFragmentSampled,
            )
            .image(
                "history",
                frame.images.get(HISTORY[1 - t.parity]),
                ImageUse::FragmentSampled,
            )
            .touches(
                frame.images.get(HISTORY[t.parity]).into(),
                ImageUse::ColorAttachmentWrite,
            )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let t = temporal(frame);
        let push = ResolvePush {
            inverse_unjittered: t.unjittered.inverse().to_cols_array(),
            previous: t.previous.to_cols_array(),
            blend: TEMPORAL_BLEND,
            reset: u32::from(t.reset),
        };
        pipelines(frame).resolve.record(
            frame.device,
            cmd,
            frame.images.get(HISTORY[t.parity]).view(),
            frame.extent(),
            frame.slot.set(&RESOLVE_SET),
            bytemuck::bytes_of(&push),
            None,
            |_| {},
        );
    }
}

impl FramePass for TemporalCopy {
    fn name(&self) -> &'static str {
        "temporal anti-aliasing"
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        wanted(frame.variant)
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let t = temporal(frame);
        PassIo::new(self.name())
            .touches(
                frame.images.get(HISTORY[t.parity]).into(),
                ImageUse::TransferSource,
            )
            .touches(frame.hdr.into(), ImageUse::TransferDestination)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let t = temporal(frame);
        let region = crate::commands::level_zero_copy(vk::ImageAspectFlags::COLOR, frame.extent());
        // SAFETY: recording state; both images are in the layouts `io` declared, of one
        // format and the frame's size.
        unsafe {
            frame.device.raw().cmd_copy_image(
                cmd,
                frame.images.get(HISTORY[t.parity]).raw(),
                ImageUse::TransferSource.state().layout,
                frame.hdr.raw(),
                ImageUse::TransferDestination.state().layout,
                &[region],
            )
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The jitter is Halton (2, 3) less the period's mean: its points differ as the
    /// sequence's do, lie within 0.55 of a pixel of the centre, and average to it.
    #[test]
    fn the_jitter_is_halton_two_three() {
        let (a, b) = (jitter(0), jitter(1));
        assert!((a[0] - b[0] - (0.5 - 0.25)).abs() < 1e-6, "{a:?} {b:?}");
        assert!(
            (a[1] - b[1] - (1.0 / 3.0 - 2.0 / 3.0)).abs() < 1e-6,
            "{a:?} {b:?}"
        );
        let mut mean = [0.0f32; 2];
        for i in 0..JITTER_PERIOD {
            let j = jitter(i);
            assert!(j.iter().all(|v| v.abs() < 0.55), "{j:?}");
            mean[0] += j[0] / JITTER_PERIOD as f32;
            mean[1] += j[1] / JITTER_PERIOD as f32;
        }
        assert!(mean[0].abs() < 1e-6 && mean[1].abs() < 1e-6, "{mean:?}");
        assert_eq!(jitter(JITTER_PERIOD), jitter(0));
    }
}
