//! Bloom (`--bloom on`, off by default): the glow of bright things, as a camera's lens
//! and an eye scatter it, redistributing a fraction of the frame's radiance and adding
//! none (docs/camera.md). Three passes after the forward pass:
//! - the chain (bloom_chain.comp): the HDR image filtered down to half size up to
//!   [`MAX_LEVELS`] times (13-tap filter, Karis's average on the first level), then each
//!   level plus the 3×3 tent of the next smaller one, back up to the largest, in one
//!   image holding every level side by side ([`level_rects`]);
//! - the energy (bloom_energy.comp): the frame's radiance and the glow's (the largest
//!   level's tent at each pixel) summed per channel, and their ratio kept;
//! - the composite (bloom_composite.frag, timed as `bloom` with the two before it): the
//!   glow × that ratio blended over the HDR image at the frame's intensity
//!   ([`crate::FrameInputs::bloom_intensity`]): (1 − i)·L + i·glow per pixel, so the
//!   frame's total radiance is unchanged (to f32 rounding in the sums and the HDR
//!   format's in the blend; tests/bloom.rs) whatever i is. The auto exposure and the
//!   output pass see the result.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{Binding, BindingKind, SetDecl, COMPUTE, FRAGMENT};
use crate::compute::ComputePass;
use crate::error::RenderError;
use crate::fullscreen::FullscreenPass;
use crate::graph::{BufferUse, ImageUse};
use crate::options::{OptionalPass, RendererSettings};
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::push::{push_block, PushBlock};
use crate::targets::ImageRequest;
use crate::variant::ShaderVariant;

/// Its option.
pub(crate) static OPTION: OptionalPass = OptionalPass {
    name: "bloom",
    define: "BLOOM",
    help: "the glow of bright things: a fraction of the frame's radiance (--bloom-intensity) spread by a chain of blurs, none added",
    needs_ray_queries: false,
    choice: None,
    needs_environment: None,
};

/// The most halvings of the frame the chain filters down by (the largest glow: 2⁶ = 64
/// pixels a level's texel, its tent three of them).
pub const MAX_LEVELS: usize = 6;

/// The image of the levels (an atlas: [`level_rects`]).
const LEVELS: &str = "bloom levels";

/// Partial sums of the energy pass (and groups of its first dispatch).
const PARTIALS: u32 = 256;

/// The chain.
pub(crate) struct BloomChain;
/// The energy.
pub(crate) struct BloomEnergy;
/// The composite.
pub(crate) struct Bloom;

/// The levels of a frame of `extent` in the atlas, largest first: level k (from 1) is
/// ⌈W/2ᵏ⌉ × ⌈H/2ᵏ⌉ texels; the first at (0, 0), the others side by side below it. As
/// many levels as keep the smaller side of the last at 2 texels or more (and the atlas
/// within the frame's size: a frame with a side under 4 pixels has none, and no glow).
pub fn level_rects(extent: vk::Extent2D) -> Vec<[u32; 4]> {
    let (w, h) = (extent.width, extent.height);
    let smaller = w.min(h);
    // ⌊log2(smaller)⌋ − 1 levels: the last's smaller side ⌈smaller/2ᴸ⌉ ≥ 2.
    let count = (smaller.max(1).ilog2() as usize)
        .saturating_sub(1)
        .min(MAX_LEVELS);
    let mut rects = Vec::with_capacity(count);
    let mut x = 0;
    for k in 1..=count as u32 {
        let size = [w.div_ceil(1 << k), h.div_ceil(1 << k)];
        if k == 1 {
            rects.push([0, 0, size[0], size[1]]);
        } else {
            rects.push([x, rects[0][3], size[0], size[1]]);
            x += size[0];
        }
    }
    rects
}

push_block! {
    /// The chain's push constants (`push/bloom_chain.glsl`).
    pub(crate) struct ChainPush in "bloom_chain" {
        /// The level read (x, y, width, height in the atlas; unused from the HDR image).
        source: [u32; 4],
        /// The level written.
        target: [u32; 4],
        /// 0: down from the HDR image; 1: down from `source`; 2: `target` plus the tent
        /// of `source`.
        mode: u32,
    }
}

push_block! {
    /// The energy pass's push constants (`push/bloom_energy.glsl`).
    pub(crate) struct EnergyPush in "bloom_energy" {
        /// The largest level (its tent is the glow at each pixel).
        largest: [u32; 4],
        /// 0: partial sums; 1: their sum and the scale.
        stage: u32,
    }
}

push_block! {
    /// The composite's push constants (`push/bloom_composite.glsl`).
    pub(crate) struct CompositePush in "bloom_composite" {
        /// The largest level.
        largest: [u32; 4],
        /// The fraction of the frame's radiance redistributed.
        intensity: f32,
    }
}

/// The energy pass's sums: the partial sums (8 floats each), then the scale and totals.
const SUMS: Binding = Binding::new(
    "sums",
    BindingKind::RwStorageBuffer {
        block: "BloomSums",
        element: "float",
    },
    COMPUTE,
);

/// The chain's set.
pub(crate) static CHAIN_SET: SetDecl = SetDecl {
    name: "bloom_chain",
    set: 0,
    bindings: &[
        Binding::new("hdr_image", BindingKind::Texture2D, COMPUTE),
        Binding::new(
            "levels",
            BindingKind::RwStorageImage2D { format: "rgba32f" },
            COMPUTE,
        ),
    ],
    includes: &[],
};

/// The energy pass's set.
pub(crate) static ENERGY_SET: SetDecl = SetDecl {
    name: "bloom_energy",
    set: 0,
    bindings: &[
        Binding::new("hdr_image", BindingKind::Texture2D, COMPUTE),
        Binding::new("levels", BindingKind::Texture2D, COMPUTE),
        SUMS,
    ],
    includes: &[],
};

/// The composite's set.
pub(crate) static COMPOSITE_SET: SetDecl = SetDecl {
    name: "bloom_composite",
    set: 0,
    bindings: &[
        Binding::new("levels", BindingKind::Texture2D, FRAGMENT),
        Binding::new(
            "sums",
            BindingKind::StorageBuffer {
                block: "BloomSums",
                element: "float",
            },
            FRAGMENT,
        ),
    ],
    includes: &[],
};

/// Whether frames of `variant` run it.
fn wanted(variant: ShaderVariant) -> bool {
    variant.optional_passes.contains(&OPTION)
}

/// Whether this frame runs it: asked for, and the frame large enough for a level.
fn runs(frame: &FrameContext<'_>) -> bool {
    wanted(frame.variant) && !level_rects(frame.extent()).is_empty()
}

/// Its pipelines: the two compute shaders and the composite into the HDR format.
struct BloomPipelines {
    chain: ComputePass,
    energy: ComputePass,
    composite: FullscreenPass,
}

fn key(settings: &RendererSettings) -> PipelineKey {
    PipelineKey {
        formats: vec![settings.hdr_format.vk()],
        ..PipelineKey::named("bloom")
    }
}

fn pipelines<'a>(frame: &FrameContext<'a>) -> &'a BloomPipelines {
    frame
        .registry
        .get(&key(frame.settings))
        .expect("prepared with the frame's variant")
}

/// A barrier from the compute writes before it to the compute reads and writes after
/// it (between the dispatches of one pass, on its own image and buffer).
fn compute_barrier(frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
    use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
    let memory = [vk::MemoryBarrier2::default()
        .src_stage_mask(S::COMPUTE_SHADER)
        .src_access_mask(A::SHADER_STORAGE_WRITE)
        .dst_stage_mask(S::COMPUTE_SHADER)
        .dst_access_mask(A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE)];
    // SAFETY: a plain memory barrier outside any rendering, `cmd` recording.
    unsafe {
        frame
            .device
            .raw()
            .cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&memory))
    };
}

impl FramePass for BloomChain {
    fn name(&self) -> &'static str {
        "bloom chain"
    }

    fn option(&self) -> Option<&'static OptionalPass> {
        Some(&OPTION)
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&CHAIN_SET];
        &SETS
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![ChainPush::header()]
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
            let compute = |set: &SetDecl, shader: &str, push: usize| {
                ComputePass::new(
                    t.device,
                    t.compiler,
                    t.cache,
                    t.layouts.of(set),
                    shader,
                    &[],
                    push,
                )
            };
            let pipelines = BloomPipelines {
                chain: compute(
                    &CHAIN_SET,
                    "bloom_chain.comp",
                    std::mem::size_of::<ChainPush>(),
                )?,
                energy: compute(
                    &ENERGY_SET,
                    "bloom_energy.comp",
                    std::mem::size_of::<EnergyPush>(),
                )?,
                composite: FullscreenPass::blending(
                    t.device,
                    t.compiler,
                    t.cache,
                    "bloom_composite.frag",
                    t.layouts.of(&COMPOSITE_SET),
                    std::mem::size_of::<CompositePush>() as u32,
                    settings.hdr_format.vk(),
                )?,
            };
            Ok((pipelines, 3))
        })?;
        Ok(())
    }

    fn images(&self, variant: ShaderVariant, _settings: &RendererSettings) -> Vec<ImageRequest> {
        if !wanted(variant) {
            return Vec::new();
        }
        vec![ImageRequest::new(
            LEVELS,
            vk::Format::R32G32B32A32_SFLOAT,
            vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::SAMPLED,
        )]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        runs(frame)
    }

    /// Timed with the composite.
    fn timed(&self) -> bool {
        false
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        PassIo::new(self.name())
            .slot_set(frame.slot, &CHAIN_SET)
            .image("hdr_image", frame.hdr, ImageUse::ComputeSampled)
            .image(
                "levels",
                frame.images.get(LEVELS),
                ImageUse::ComputeStorageWrite,
            )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let rects = level_rects(frame.extent());
        let chain = &pipelines(frame).chain;
        let set = frame.slot.set(&CHAIN_SET);
        let dispatch = |push: ChainPush| {
            let [_, _, w, h] = push.target;
            chain.dispatch(
                frame.device,
                cmd,
                set,
                bytemuck::bytes_of(&push),
                [w.div_ceil(8), h.div_ceil(8), 1],
            );
        };
        // Down: the HDR image to the first level, each level to the next.
        for (k, &target) in rects.iter().enumerate() {
            if k > 0 {
                compute_barrier(frame, cmd);
            }
            dispatch(ChainPush {
                source: if k == 0 { [0; 4] } else { rects[k - 1] },
                target,
                mode: u32::from(k > 0),
            });
        }
        // Up: each level plus the tent of the next smaller, smallest first.
        for k in (0..rects.len().saturating_sub(1)).rev() {
            compute_barrier(frame, cmd);
            dispatch(ChainPush {
                source: rects[k + 1],
                target: rects[k],
                mode: 2,
            });
        }
    }
}

impl FramePass for BloomEnergy {
    fn name(&self) -> &'static str {
        "bloom energy"
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&ENERGY_SET];
        &SETS
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![EnergyPush::header()]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        runs(frame)
    }

    /// Timed with the composite.
    fn timed(&self) -> bool {
        false
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        PassIo::new(self.name())
            .slot_set(frame.slot, &ENERGY_SET)
            .image("hdr_image", frame.hdr, ImageUse::ComputeSampled)
            .image("levels", frame.images.get(LEVELS), ImageUse::ComputeSampled)
            .buffer(
                "sums",
                &frame.shared.bloom_sums,
                BufferUse::ComputeStorageWrite,
            )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let largest = level_rects(frame.extent())[0];
        let energy = &pipelines(frame).energy;
        let set = frame.slot.set(&ENERGY_SET);
        for stage in 0..2 {
            if stage > 0 {
                compute_barrier(frame, cmd);
            }
            let push = EnergyPush { largest, stage };
            let groups = if stage == 0 { PARTIALS } else { 1 };
            energy.dispatch(
                frame.device,
                cmd,
                set,
                bytemuck::bytes_of(&push),
                [groups, 1, 1],
            );
        }
    }
}

impl FramePass for Bloom {
    fn name(&self) -> &'static str {
        "bloom"
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&COMPOSITE_SET];
        &SETS
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![CompositePush::header()]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        runs(frame)
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        PassIo::new(self.name())
            .slot_set(frame.slot, &COMPOSITE_SET)
            .image(
                "levels",
                frame.images.get(LEVELS),
                ImageUse::FragmentSampled,
            )
            .buffer(
                "sums",
                &frame.shared.bloom_sums,
                BufferUse::FragmentStorageRead,
            )
            .touches(frame.hdr.into(), ImageUse::ColorAttachmentBlend)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let push = CompositePush {
            largest: level_rects(frame.extent())[0],
            intensity: frame.inputs.bloom_intensity,
        };
        pipelines(frame).composite.record(
            frame.device,
            cmd,
            frame.hdr.view(),
            frame.extent(),
            frame.slot.set(&COMPOSITE_SET),
            bytemuck::bytes_of(&push),
            None,
            |_| {},
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Levels halve (rounding up), the last keeps a smaller side of 2 or more, at most
    /// six; the atlas lies within the frame and its rectangles do not overlap.
    #[test]
    fn the_levels_fit_the_frame() {
        for (w, h) in [
            (1280, 720),
            (1, 1),
            (3, 7),
            (4, 4),
            (8, 9),
            (1366, 768),
            (17, 4096),
        ] {
            let rects = level_rects(vk::Extent2D {
                width: w,
                height: h,
            });
            assert!(rects.len() <= MAX_LEVELS);
            for (k, r) in rects.iter().enumerate() {
                let k = k as u32 + 1;
                assert_eq!([r[2], r[3]], [w.div_ceil(1 << k), h.div_ceil(1 << k)]);
                assert!(r[0] + r[2] <= w && r[1] + r[3] <= h, "{w}x{h}: {r:?}");
                assert!(r[2].min(r[3]) >= 2, "{w}x{h}: {r:?}");
            }
            for (i, a) in rects.iter().enumerate() {
                for b in &rects[i + 1..] {
                    let apart = a[0] + a[2] <= b[0]
                        || b[0] + b[2] <= a[0]
                        || a[1] + a[3] <= b[1]
                        || b[1] + b[3] <= a[1];
                    assert!(apart, "{w}x{h}: {a:?} {b:?}");
                }
            }
        }
        assert_eq!(
            level_rects(vk::Extent2D {
                width: 1280,
                height: 720
            })
            .len(),
            6
        );
    }
}
