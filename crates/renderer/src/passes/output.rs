//! The output pass (tonemap.frag) into the frame's colour target, by its format — the
//! exposure, then for display formats the tone curve and sRGB encoding — with the
//! overlay's text panels drawn over it in the same rendering.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{self, SetDecl};
use crate::error::RenderError;
use crate::fullscreen::FullscreenPass;
use crate::gpu_types::TonemapPush;
use crate::graph::{BufferUse, ImageUse};
use crate::host::{AntiAliasing, OutputEncoding};
use crate::overlay::OverlayPass;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;

pub(crate) struct Output;

/// The passes that write a target of one format: the output pass and the overlay drawn
/// over it.
pub(crate) struct OutputPasses {
    output: FullscreenPass,
    /// The output pass with FXAA (`FXAA`), for display formats once a frame is to use
    /// it ([`prepare_anti_aliasing`]).
    fxaa: Option<FullscreenPass>,
    overlay: OverlayPass,
}

/// The output passes into targets of `format`.
fn key(format: vk::Format) -> PipelineKey {
    PipelineKey {
        formats: vec![format],
        ..PipelineKey::named(PassTimings::OUTPUT)
    }
}

/// Whether the output passes into targets of `format` are built, and with FXAA.
pub(crate) fn prepared(registry: &PipelineRegistry, format: vk::Format) -> Option<bool> {
    registry
        .get::<OutputPasses>(&key(format))
        .map(|p| p.fxaa.is_some())
}

/// The output pass with `defines` into `format`.
fn output_pipeline(
    t: &crate::pipelines::PipelineTools<'_>,
    defines: &[(&'static str, Option<&'static str>)],
    format: vk::Format,
) -> Result<FullscreenPass, RenderError> {
    FullscreenPass::new(
        t.device,
        t.compiler,
        t.cache,
        "tonemap.frag",
        defines,
        t.layouts.of(&bindings::OUTPUT),
        std::mem::size_of::<TonemapPush>() as u32,
        format,
    )
}

/// Builds the output pass (and the overlay over it) for targets of `format` unless they
/// are built.
pub(crate) fn prepare_output(
    registry: &mut PipelineRegistry,
    format: vk::Format,
) -> Result<(), RenderError> {
    let encoding =
        OutputEncoding::of(format).ok_or(RenderError::UnsupportedOutputFormat(format))?;
    registry.build(key(format), |t| {
        let passes = OutputPasses {
            output: output_pipeline(t, &encoding.defines(), format)?,
            fxaa: None,
            overlay: OverlayPass::new(
                t.device,
                t.compiler,
                t.cache,
                t.layouts.of(&bindings::OVERLAY),
                &encoding.defines(),
                format,
            )?,
        };
        Ok((passes, 2))
    })?;
    registry.mark_output_format(format);
    Ok(())
}

/// Prepares `format` and, for [`AntiAliasing::Fxaa`] into a display format, the output
/// pipeline with FXAA (linear formats get no anti-aliasing).
pub(crate) fn prepare_anti_aliasing(
    registry: &mut PipelineRegistry,
    format: vk::Format,
    anti_aliasing: AntiAliasing,
) -> Result<(), RenderError> {
    prepare_output(registry, format)?;
    let encoding =
        OutputEncoding::of(format).ok_or(RenderError::UnsupportedOutputFormat(format))?;
    if anti_aliasing != AntiAliasing::Fxaa || encoding == OutputEncoding::Linear {
        return Ok(());
    }
    registry.update(&key(format), |passes: &mut OutputPasses, t| {
        if passes.fxaa.is_some() {
            return Ok(0);
        }
        let mut defines = encoding.defines();
        defines.push(("FXAA", None));
        passes.fxaa = Some(output_pipeline(t, &defines, format)?);
        Ok(1)
    })
}

/// Declares the overlay's set in `io` (its quads the CPU's, its atlas and image made at
/// start): drawn over the frame's target by the pass that writes it — this one, or the
/// lighting pass where the output is folded into it.
pub(super) fn overlay_io(io: PassIo, frame: &FrameContext<'_>) -> PassIo {
    let (s, r) = (frame.slot, frame.shared);
    io.slot_set(frame.slot, &bindings::OVERLAY)
        .bind_buffer("overlay_quads", &s.overlay_quads)
        .bind_buffer("overlay_atlas", &r.overlay_atlas)
        .bind_buffer("overlay_image", &r.overlay_image.0)
}

/// Draws the frame's overlay (if it has quads) into the rendering of the frame's target
/// that `cmd` is in.
pub(super) fn record_overlay(frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
    let (s, r) = (frame.slot, frame.shared);
    if s.overlay_quad_count == 0 {
        return;
    }
    let passes: &OutputPasses = frame
        .registry
        .get(&key(frame.target.color.format))
        .expect("the target's format is prepared (checked before recording)");
    passes.overlay.record(
        frame.device,
        cmd,
        frame.extent(),
        s.set(&bindings::OVERLAY),
        s.overlay_quad_count,
        r.overlay_image.1.map_or(1, |[w, _]| w),
    );
}

impl FramePass for Output {
    fn name(&self) -> &'static str {
        PassTimings::OUTPUT
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 2] = [&bindings::OUTPUT, &bindings::OVERLAY];
        &SETS
    }

    /// Not where the lighting pass writes the target itself
    /// ([`super::lighting::folds_output`]).
    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        !frame.output_folded
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let r = frame.shared;
        let io = PassIo::new(self.name())
            .slot_set(frame.slot, &bindings::OUTPUT)
            .image("hdr_image", frame.hdr, ImageUse::FragmentSampled)
            // The auto exposure's factor, in frames that meter (bound in every frame).
            .buffer_if(
                frame.inputs.auto_exposure.is_some(),
                "exposure_state",
                &r.exposure_state,
                BufferUse::FragmentStorageRead,
            )
            .touches(frame.color, ImageUse::ColorAttachmentWrite);
        overlay_io(io, frame)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let s = frame.slot;
        let push = TonemapPush {
            exposure: frame.inputs.exposure,
            curve: frame.inputs.tone_mapping as u32,
            metered: u32::from(frame.inputs.auto_exposure.is_some()),
        };
        let passes: &OutputPasses = frame
            .registry
            .get(&key(frame.target.color.format))
            .expect("the target's format is prepared (checked before recording)");
        // AntiAliasing::Fxaa: the output pipeline with FXAA (built for display formats by
        // Renderer::prepare_anti_aliasing; linear formats have none and get the plain one).
        let output = match (frame.inputs.anti_aliasing, &passes.fxaa) {
            (crate::AntiAliasing::Fxaa, Some(fxaa)) => fxaa,
            _ => &passes.output,
        };
        output.record(
            frame.device,
            cmd,
            frame.target.color.view,
            frame.extent(),
            s.set(&bindings::OUTPUT),
            bytemuck::bytes_of(&push),
            None,
            |cmd| record_overlay(frame, cmd),
        );
    }
}
