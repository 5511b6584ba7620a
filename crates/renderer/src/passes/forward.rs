//! The forward pass (gbuffer.vert + forward.frag; `crate::forward`): the blended
//! objects over the lit HDR image, back to front, behind the G-buffer's depth. Runs only
//! in frames of a scene with a blended object whose variant built its pipeline (not in
//! debug views or measurement floors, which show the G-buffer's own surfaces).

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::error::RenderError;
use crate::forward::{ForwardPass, ForwardTargets};
use crate::graph::{BufferUse, ImageUse};
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;
use crate::variant::ShaderVariant;

pub(crate) struct Forward;

/// Whether frames of `variant` draw the forward pass: scenes with a blended or
/// transmissive object, not in debug views or measurement floors (which show the
/// G-buffer's own surfaces).
pub(super) fn draws(variant: ShaderVariant) -> bool {
    (variant.blend || variant.transmission) && !variant.debug_views && variant.floor.is_none()
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
            .touches((&frame.targets.hdr).into(), ImageUse::ColorAttachmentBlend);
        let absent = |io: PassIo, binding: &str| {
            // Not declared by pipelines without the feature: any image will do.
            io.bind_image(
                binding,
                frame.shared.absent_target.view(),
                ImageUse::FragmentSampled.state().layout,
                vk::Sampler::null(),
            )
        };
        let depth = &frame.targets.gbuffer.depth;
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
        let io = match &frame.targets.back_faces {
            Some(back_faces) if frame.variant.volume => io
                .image(
                    "back_face_depth",
                    &back_faces.depth,
                    ImageUse::DepthFragmentSampled,
                )
                .sampled(
                    "back_face_normal",
                    &back_faces.normal,
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
        let io = match &frame.targets.behind {
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
        super::lighting::lit_by(io, frame)
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
                hdr: &frame.targets.hdr,
                depth: &frame.targets.gbuffer.depth,
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
