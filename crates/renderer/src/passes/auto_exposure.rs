//! Auto exposure (exposure_metering.comp, exposure_adaptation.comp), in frames whose
//! inputs ask for it ([`crate::FrameInputs::auto_exposure`]): after the forward pass
//! the HDR image's log2 luminance is counted in a histogram, and one group turns the
//! histogram into the exposure the output pass applies (`crate::exposure` states the
//! relations and units). The histogram and the exposure state are the renderer's, one
//! each, carried from frame to frame (the adaptation steps from the previous frame's
//! exposure); the frame's end copies the state into its slot for the host
//! ([`crate::Renderer::last_metered_exposure`]). Their pipelines are built by
//! [`crate::Renderer::prepare_auto_exposure`], never while a frame is recorded.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{Binding, BindingKind, SetDecl, COMPUTE};
use crate::compute::ComputePass;
use crate::error::RenderError;
use crate::exposure::{ev100_of_exposure, METERED_LOG2_LUMINANCE, METER_CALIBRATION};
use crate::graph::{BufferUse, ImageUse};
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::push::{push_block, PushBlock};

/// Counts the HDR image's pixels by log2 luminance.
pub(crate) struct Metering;

/// Makes the histogram the frame's exposure.
pub(crate) struct Adaptation;

/// A storage buffer of `uint`s written by compute shaders.
const fn words(name: &'static str, block: &'static str) -> Binding {
    Binding::new(
        name,
        BindingKind::RwStorageBuffer {
            block,
            element: "uint",
        },
        COMPUTE,
    )
}

/// The metering pass's set: the HDR image, the histogram it adds to.
pub(crate) static METERING_SET: SetDecl = SetDecl {
    name: "exposure_metering",
    set: 0,
    bindings: &[
        Binding::new("hdr_image", BindingKind::Texture2D, COMPUTE),
        words("histogram", "ExposureHistogram"),
    ],
    includes: &[],
};

/// The adaptation pass's set: the histogram it reads and clears, the state it writes.
pub(crate) static ADAPTATION_SET: SetDecl = SetDecl {
    name: "exposure_adaptation",
    set: 0,
    bindings: &[
        words("histogram", "ExposureHistogram"),
        words("exposure_state", "ExposureState"),
    ],
    includes: &[],
};

push_block! {
    /// The metering pass's push constants (`push/exposure_metering.glsl`).
    pub(crate) struct MeteringPush in "exposure_metering" {
        /// The log2 luminances the histogram spans ([`METERED_LOG2_LUMINANCE`]).
        log2_luminance: [f32; 2],
    }
}

push_block! {
    /// The adaptation pass's push constants (`push/exposure_adaptation.glsl`).
    pub(crate) struct AdaptationPush in "exposure_adaptation" {
        /// The log2 luminances the histogram spans.
        log2_luminance: [f32; 2],
        /// The ranks metered, as fractions of the pixels counted.
        window: [f32; 2],
        /// log2(100 / K): the meter's EV100 less the mean log2 luminance.
        meter_offset: f32,
        /// Stops added to the exposure.
        compensation: f32,
        /// EV per second the exposure rises at.
        rise: f32,
        /// EV per second it falls at.
        fall: f32,
        /// Seconds since the previous frame.
        elapsed: f32,
        /// 1: take the target at once (a still frame, or the renderer's first metered one).
        reset: u32,
        /// The EV100 of the frame's own exposure: a first frame's when no pixel counts.
        fallback_ev100: f32,
    }
}

/// Both passes' pipelines (built together, for every variant).
struct AutoExposurePipelines {
    metering: ComputePass,
    adaptation: ComputePass,
}

fn key() -> PipelineKey {
    PipelineKey::named("auto exposure")
}

/// Builds both passes' pipelines unless they are built.
pub(crate) fn prepare(registry: &mut PipelineRegistry) -> Result<(), RenderError> {
    registry.build(key(), |t| {
        let pipelines = AutoExposurePipelines {
            metering: ComputePass::new(
                t.device,
                t.compiler,
                t.cache,
                t.layouts.of(&METERING_SET),
                "exposure_metering.comp",
                &[],
                std::mem::size_of::<MeteringPush>(),
            )?,
            adaptation: ComputePass::new(
                t.device,
                t.compiler,
                t.cache,
                t.layouts.of(&ADAPTATION_SET),
                "exposure_adaptation.comp",
                &[],
                std::mem::size_of::<AdaptationPush>(),
            )?,
        };
        Ok((pipelines, 2))
    })?;
    Ok(())
}

/// Whether they are built.
pub(crate) fn prepared(registry: &PipelineRegistry) -> bool {
    registry.get::<AutoExposurePipelines>(&key()).is_some()
}

fn pipelines<'a>(frame: &FrameContext<'a>) -> &'a AutoExposurePipelines {
    frame
        .registry
        .get(&key())
        .expect("prepared before a metered frame is recorded (checked)")
}

impl FramePass for Metering {
    fn name(&self) -> &'static str {
        "exposure metering"
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&METERING_SET];
        &SETS
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![MeteringPush::header()]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        frame.inputs.auto_exposure.is_some()
    }

    /// Timed with the adaptation.
    fn timed(&self) -> bool {
        false
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        PassIo::new(self.name())
            .slot_set(frame.slot, &METERING_SET)
            .image("hdr_image", frame.hdr, ImageUse::ComputeSampled)
            .buffer(
                "histogram",
                &frame.shared.exposure_histogram,
                BufferUse::ComputeStorageWrite,
            )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let push = MeteringPush {
            log2_luminance: METERED_LOG2_LUMINANCE,
        };
        let extent = frame.extent();
        pipelines(frame).metering.dispatch(
            frame.device,
            cmd,
            frame.slot.set(&METERING_SET),
            bytemuck::bytes_of(&push),
            [extent.width.div_ceil(128), extent.height.div_ceil(128), 1],
        );
    }
}

impl FramePass for Adaptation {
    fn name(&self) -> &'static str {
        "auto exposure"
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&ADAPTATION_SET];
        &SETS
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![AdaptationPush::header()]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        frame.inputs.auto_exposure.is_some()
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let r = frame.shared;
        PassIo::new(self.name())
            .slot_set(frame.slot, &ADAPTATION_SET)
            .buffer(
                "histogram",
                &r.exposure_histogram,
                BufferUse::ComputeStorageWrite,
            )
            .buffer(
                "exposure_state",
                &r.exposure_state,
                BufferUse::ComputeStorageWrite,
            )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let auto = frame
            .inputs
            .auto_exposure
            .expect("runs only in frames that meter");
        let elapsed = auto.elapsed_seconds.filter(|_| frame.metering_continues);
        let push = AdaptationPush {
            log2_luminance: METERED_LOG2_LUMINANCE,
            window: auto.window,
            meter_offset: (100.0 / METER_CALIBRATION).log2(),
            compensation: auto.compensation,
            rise: auto.rise_per_second,
            fall: auto.fall_per_second,
            elapsed: elapsed.unwrap_or(0.0),
            reset: u32::from(elapsed.is_none()),
            fallback_ev100: ev100_of_exposure(frame.inputs.exposure),
        };
        pipelines(frame).adaptation.dispatch(
            frame.device,
            cmd,
            frame.slot.set(&ADAPTATION_SET),
            bytemuck::bytes_of(&push),
            [1, 1, 1],
        );
    }
}
