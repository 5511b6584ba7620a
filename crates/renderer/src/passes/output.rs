//! The output pass (tonemap.frag) into the frame's colour target, by its format — the
//! exposure, then for display formats the tone curve and sRGB encoding — with the
//! overlay's text panels drawn over it in the same rendering.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::gpu_types::TonemapPush;
use crate::graph::ImageUse;
use crate::pass_io::PassIo;
use crate::results::PassTimings;

pub(crate) struct Output;

impl FramePass for Output {
    fn name(&self) -> &'static str {
        PassTimings::OUTPUT
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 2] = [&bindings::OUTPUT, &bindings::OVERLAY];
        &SETS
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let (s, r) = (frame.slot, frame.shared);
        PassIo::new(self.name())
            .slot_set(frame.slot, &bindings::OUTPUT)
            .image("hdr_image", &frame.targets.hdr, ImageUse::FragmentSampled)
            .touches(frame.color, ImageUse::ColorAttachmentWrite)
            // The overlay's quads are the CPU's, its atlas and image made at start.
            .slot_set(frame.slot, &bindings::OVERLAY)
            .bind_buffer("overlay_quads", &s.overlay_quads)
            .bind_buffer("overlay_atlas", &r.overlay_atlas)
            .bind_buffer("overlay_image", &r.overlay_image.0)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let (s, r) = (frame.slot, frame.shared);
        let device = frame.device;
        let extent = frame.extent();
        let push = TonemapPush {
            exposure: frame.inputs.exposure,
            curve: frame.inputs.tone_mapping as u32,
        };
        let passes = frame.output_pipelines();
        let image_width = r.overlay_image.1.map_or(1, |[w, _]| w);
        // AntiAliasing::Fxaa: the output pipeline with FXAA (built for display formats by
        // Renderer::prepare_anti_aliasing; linear formats have none and get the plain one).
        let output = match (frame.inputs.anti_aliasing, &passes.fxaa) {
            (crate::AntiAliasing::Fxaa, Some(fxaa)) => fxaa,
            _ => &passes.output,
        };
        output.record(
            device,
            cmd,
            frame.target.color.view,
            extent,
            s.set(&bindings::OUTPUT),
            bytemuck::bytes_of(&push),
            None,
            |cmd| {
                if s.overlay_quad_count > 0 {
                    passes.overlay.record(
                        device,
                        cmd,
                        extent,
                        s.set(&bindings::OVERLAY),
                        s.overlay_quad_count,
                        image_width,
                    );
                }
            },
        );
    }
}
