//! Path-traced frames averaged on the GPU while nothing changes
//! ([`RendererSettings::accumulate_paths`], off by default; the viewer's): each
//! path-traced frame's radiance joins the mean of the frames before it since the
//! picture last changed, so a still view converges and a moved one starts again. Two
//! passes after the forward pass:
//! - the mean (path_accumulation.frag): this frame's radiance and the previous mean
//!   (an f32 history, two images used in turn) into the new mean, m_k = m_{k−1} +
//!   (x_k − m_{k−1}) / k — the first frame of a history takes its radiance alone;
//! - the copy: the mean into the HDR image (a blit: the history is f32 whatever the HDR
//!   format, so thousands of frames keep their share), which every later pass reads.
//!
//! What starts a history again ([`AccumulationKey`]): another scene or an edit of it,
//! another size, shader variant or shading option, camera, light, pose, background,
//! environment or seed — everything a frame's radiance depends on but the exposure,
//! tone curve, anti-aliasing and overlay, which act on it afterwards. Frame k of a
//! history (from 0) traces the paths of seed `environment_seed + k`
//! ([`crate::FrameInputs::environment_seed`]): the history's mean is then the mean of
//! frames of successive seeds, as `combustion render --samples` averages on the CPU.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{Binding, BindingKind, SetDecl, FRAGMENT};
use crate::error::RenderError;
use crate::fullscreen::FullscreenPass;
use crate::graph::ImageUse;
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::push::{push_block, PushBlock};
use crate::targets::ImageRequest;
use crate::variant::ShaderVariant;

/// The two histories of the mean, used in turn.
const HISTORY: [&str; 2] = ["path accumulation 0", "path accumulation 1"];
const HISTORY_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// The mean.
pub(crate) struct PathAccumulation;
/// The copy into the HDR image.
pub(crate) struct PathAccumulationCopy;

push_block! {
    /// The mean's push constants (`push/path_accumulation.glsl`).
    pub(crate) struct AccumulationPush in "path_accumulation" {
        /// This frame's place in the history, from 1 (1: the history starts here).
        frames: u32,
    }
}

/// The mean's set.
pub(crate) static SET: SetDecl = SetDecl {
    name: "path_accumulation",
    set: 0,
    bindings: &[
        Binding::new("hdr_image", BindingKind::Texture2D, FRAGMENT),
        Binding::new("history", BindingKind::Texture2D, FRAGMENT),
    ],
    includes: &[],
};

/// Everything a path-traced frame's radiance depends on that changes between frames:
/// a frame whose key differs from the last one's starts the history again.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct AccumulationKey {
    /// The scene (its address) and its geometry version (each edit makes a new one).
    pub scene: (usize, u64),
    /// The frame's size.
    pub extent: [u32; 2],
    /// The shader variant and the shading options.
    pub shading: (ShaderVariant, crate::ShadingOptions),
    /// The camera.
    pub camera: combustion_scene::Camera,
    /// The frame's lights.
    pub lights: Vec<combustion_scene::Light>,
    /// The frame's pose, if any.
    pub pose: Option<combustion_scene::ObjectPoses>,
    /// What shows where no surface is.
    pub background: crate::Background,
    /// The frame's own environment (its address), if it brings one.
    pub environment: Option<usize>,
    /// The seed of the history's first frame.
    pub seed: u32,
}

/// A frame's place in its history.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AccumulationFrame {
    /// The frames of the history with this one, from 1.
    pub frames: u32,
    /// Which history this frame writes (it reads the other).
    pub parity: usize,
}

/// What the renderer keeps between accumulated frames.
#[derive(Default)]
pub(crate) struct AccumulationState {
    /// The last frame's key and the frames of its history.
    last: Option<(AccumulationKey, u32)>,
}

impl AccumulationState {
    /// The frame of `key` after the last one: the next of its history, or the first of
    /// a new one.
    pub(crate) fn advance(&mut self, key: AccumulationKey) -> AccumulationFrame {
        let frames = match self.last.take() {
            // A history past u32::MAX frames starts again (its mean long converged).
            Some((last, frames)) if last == key && frames < u32::MAX => frames + 1,
            _ => 1,
        };
        self.last = Some((key, frames));
        AccumulationFrame {
            frames,
            parity: (frames % 2) as usize,
        }
    }

    /// Paths a pixel the last accumulated frame's mean holds (0: none accumulated).
    pub(crate) fn paths(&self) -> u64 {
        self.last.as_ref().map_or(0, |(_, frames)| {
            u64::from(*frames) * u64::from(super::PATHS_PER_FRAME)
        })
    }

    /// Forgets the history (frames that never ran, frames that do not accumulate).
    pub(crate) fn forget(&mut self) {
        self.last = None;
    }
}

/// Whether frames of `variant` accumulate under `settings`.
pub(crate) fn wanted(variant: ShaderVariant, settings: &RendererSettings) -> bool {
    settings.accumulate_paths && super::path_trace::wanted(variant)
}

fn key(settings: &RendererSettings) -> PipelineKey {
    PipelineKey {
        formats: vec![settings.hdr_format.vk()],
        ..PipelineKey::named("path accumulation")
    }
}

/// The frame's place in its history (frames that run it have one).
fn accumulated(frame: &FrameContext<'_>) -> AccumulationFrame {
    frame
        .accumulation
        .expect("made for every frame that runs it")
}

impl FramePass for PathAccumulation {
    fn name(&self) -> &'static str {
        "path accumulation mean"
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&SET];
        &SETS
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![AccumulationPush::header()]
    }

    fn prepare(
        &self,
        variant: ShaderVariant,
        settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        if !wanted(variant, settings) {
            return Ok(());
        }
        registry.build(key(settings), |t| {
            let pass = FullscreenPass::new(
                t.device,
                t.compiler,
                t.cache,
                "path_accumulation.frag",
                &[],
                t.layouts.of(&SET),
                std::mem::size_of::<AccumulationPush>() as u32,
                HISTORY_FORMAT,
            )?;
            Ok((pass, 1))
        })?;
        Ok(())
    }

    fn images(&self, variant: ShaderVariant, settings: &RendererSettings) -> Vec<ImageRequest> {
        if !wanted(variant, settings) {
            return Vec::new();
        }
        HISTORY
            .iter()
            .map(|name| {
                ImageRequest::new(
                    name,
                    HISTORY_FORMAT,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::SAMPLED
                        | vk::ImageUsageFlags::TRANSFER_SRC,
                )
            })
            .collect()
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        frame.accumulation.is_some()
    }

    /// Timed with the copy.
    fn timed(&self) -> bool {
        false
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let a = accumulated(frame);
        PassIo::new(self.name())
            .slot_set(frame.slot, &SET)
            .image("hdr_image", frame.hdr, ImageUse::FragmentSampled)
            .image(
                "history",
                frame.images.get(HISTORY[1 - a.parity]),
                ImageUse::FragmentSampled,
            )
            .touches(
                frame.images.get(HISTORY[a.parity]).into(),
                ImageUse::ColorAttachmentWrite,
            )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let a = accumulated(frame);
        let pass: &FullscreenPass = frame
            .registry
            .get(&key(frame.settings))
            .expect("prepared with the frame's variant");
        pass.record(
            frame.device,
            cmd,
            frame.images.get(HISTORY[a.parity]).view(),
            frame.extent(),
            frame.slot.set(&SET),
            bytemuck::bytes_of(&AccumulationPush { frames: a.frames }),
            None,
            |_| {},
        );
    }
}

impl FramePass for PathAccumulationCopy {
    fn name(&self) -> &'static str {
        "path accumulation"
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        frame.accumulation.is_some()
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let a = accumulated(frame);
        PassIo::new(self.name())
            .touches(
                frame.images.get(HISTORY[a.parity]).into(),
                ImageUse::BlitSource,
            )
            .touches(frame.hdr.into(), ImageUse::BlitDestination)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let a = accumulated(frame);
        let extent = frame.extent();
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let corner = vk::Offset3D {
            x: extent.width as i32,
            y: extent.height as i32,
            z: 1,
        };
        let region = vk::ImageBlit::default()
            .src_subresource(layers)
            .src_offsets([vk::Offset3D::default(), corner])
            .dst_subresource(layers)
            .dst_offsets([vk::Offset3D::default(), corner]);
        // SAFETY: recording state; both images are in the layouts `io` declared, of the
        // frame's size (a blit of equal extents converts the format texel by texel).
        unsafe {
            frame.device.raw().cmd_blit_image(
                cmd,
                frame.images.get(HISTORY[a.parity]).raw(),
                ImageUse::BlitSource.state().layout,
                frame.hdr.raw(),
                ImageUse::BlitDestination.state().layout,
                &[region],
                vk::Filter::NEAREST,
            )
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(seed: u32) -> AccumulationKey {
        AccumulationKey {
            scene: (1, 1),
            extent: [4, 4],
            shading: (ShaderVariant::default(), crate::ShadingOptions::DEFAULT),
            camera: combustion_scene::Camera::framing(None),
            lights: Vec::new(),
            pose: None,
            background: Default::default(),
            environment: None,
            seed,
        }
    }

    /// A history goes on while its key holds, starts again when it changes, and counts
    /// its paths.
    #[test]
    fn a_history_goes_on_until_anything_changes() {
        let mut state = AccumulationState::default();
        assert_eq!(state.paths(), 0);
        let frames: Vec<u32> = [0, 0, 0, 1, 1, 0]
            .into_iter()
            .map(|seed| state.advance(key(seed)).frames)
            .collect();
        assert_eq!(frames, [1, 2, 3, 1, 2, 1]);
        assert_eq!(state.paths(), u64::from(super::super::PATHS_PER_FRAME));
        state.forget();
        assert_eq!(state.advance(key(0)).frames, 1);
    }
}
