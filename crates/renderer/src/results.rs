//! What the renderer gives back: a rendered [`Frame`], the GPU times of its passes
//! ([`PassTimings`]), and counts of what it built ([`RendererStats`]).

use crate::gbuffer::GBufferReadback;
#[cfg(doc)]
use crate::Readback;
#[cfg(doc)]
use crate::Renderer;

/// A rendered frame.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear HDR radiance, RGBA, row-major from the top-left (empty without readback).
    pub hdr: Vec<[f32; 4]>,
    /// Tonemapped, sRGB-encoded RGBA8 (empty without readback).
    pub ldr: Vec<[u8; 4]>,
    /// The G-buffer, with [`Readback::gbuffer`] (else `None`).
    pub gbuffer: Option<GBufferReadback>,
    /// The frame's GPU pass times (zero where the device has no timestamps).
    pub timings: PassTimings,
}

impl Frame {
    /// Pixels of the HDR image with a NaN or infinite colour channel: radiance that
    /// overflowed the frame's floats (0 without readback).
    pub fn non_finite_pixels(&self) -> usize {
        self.hdr
            .iter()
            .filter(|p| !p[..3].iter().all(|c| c.is_finite()))
            .count()
    }

    /// Pixels whose radiance overflowed a frame of `format`: [`Frame::non_finite_pixels`],
    /// and in a 16-bit frame those at f16's largest value too (65504), where a driver
    /// may clamp an overflow rather than write infinity (lavapipe does).
    pub fn overflowed_pixels(&self, format: crate::HdrFormat) -> usize {
        const F16_MAX: f32 = 65504.0;
        match format {
            crate::HdrFormat::Rgba32Float => self.non_finite_pixels(),
            crate::HdrFormat::Rgba16Float => self
                .hdr
                .iter()
                .filter(|p| p[..3].iter().any(|&c| !c.is_finite() || c >= F16_MAX))
                .count(),
        }
    }
}

/// The GPU times of one frame's passes, by name, from timestamp queries, in
/// milliseconds: whatever passes the frame ran, in the order it ran them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassTimings {
    /// Each pass the frame ran, in order.
    pub passes: Vec<PassTime>,
    /// From the frame's first command to the end of its last pass.
    pub total_ms: f64,
}

/// One pass's GPU time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PassTime {
    /// The pass's name ([`PassTimings::GBUFFER`], …).
    pub name: &'static str,
    /// Milliseconds from the end of the pass before (or the frame's start) to its end.
    pub ms: f64,
}

impl PassTimings {
    /// The deformed objects' morphing and skinning (scenes with them).
    pub const DEFORM: &'static str = "deform";
    /// The G-buffer pass.
    pub const GBUFFER: &'static str = "gbuffer";
    /// The shadow maps of the frame's shadowed lights (frames with shadows).
    pub const SHADOW_MAPS: &'static str = "shadow maps";
    /// The lighting pass, with the light culling that precedes it.
    pub const LIGHTING: &'static str = "lighting";
    /// The far sides (depth, normals) of transmissive objects with a volume (scenes
    /// with them).
    pub const BACK_FACES: &'static str = "back faces";
    /// The copy of the lit image (with its mip chain) behind transmissive objects
    /// (scenes with them).
    pub const BEHIND: &'static str = "behind";
    /// The forward pass: the blended and transmissive objects over the lit image
    /// (scenes with them).
    pub const FORWARD: &'static str = "forward";
    /// The output pass (tone curve, encoding) and its overlay.
    pub const OUTPUT: &'static str = "output";
    /// The copy of the scene's depth into a host's depth image (frames given one).
    pub const DEPTH_COPY: &'static str = "depth copy";

    /// The time of the pass named `name`, if the frame ran it.
    pub fn ms(&self, name: &str) -> Option<f64> {
        self.passes.iter().find(|p| p.name == name).map(|p| p.ms)
    }

    /// The names of the passes the frame ran, in order.
    pub fn names(&self) -> Vec<&'static str> {
        self.passes.iter().map(|p| p.name).collect()
    }

    /// The time of the pass named `name`, 0 if the frame did not run it.
    pub fn ms_or_zero(&self, name: &str) -> f64 {
        self.ms(name).unwrap_or(0.0)
    }
}

/// Counts of what a renderer has built, for hosts and tests that check that steady
/// frames build nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RendererStats {
    /// Frames recorded.
    pub frames: u64,
    /// Frames that made images of their own (G-buffer targets, the HDR image, …): a new
    /// size, or a feature's target a frame needed first.
    pub targets_built: u64,
    /// Times images were retired after going unused (those of one size and kind that
    /// went unused together retire together).
    pub targets_retired: u64,
    /// Pipelines built (graphics and compute; the environment bake's are counted as
    /// bakes).
    pub pipelines_built: u64,
    /// Display images of [`Renderer::render`] and [`Renderer::submit_offscreen`] made.
    pub display_images_built: u64,
    /// Shaders compiled (GLSL to SPIR-V, at start-up and when a new pipeline variant is
    /// first needed; never while a frame records).
    pub shaders_compiled: u64,
    /// How many of those were read from the SPIR-V cache on disk instead of compiled
    /// (`combustion_vk::default_spirv_cache_dir`: `$COMBUSTION_SPIRV_CACHE`, `off` for
    /// none, else the user's cache folder).
    pub shaders_from_cache: u64,
    /// Wall time those compilations and lookups took, in microseconds (pipeline
    /// creation, the driver's own compilation, not included).
    pub shader_compile_micros: u64,
    /// Environments baked (at upload, edit or [`Renderer::bake_environment`]).
    pub environment_bakes: u64,
    /// How many of those copied their cubes (specular and irradiance) from an earlier
    /// bake of the same environment kept on disk instead of computing them
    /// (`environment::default_environment_cache_dir`: `$COMBUSTION_ENVIRONMENT_CACHE`,
    /// `off` for none, else the user's cache folder).
    pub environment_cubes_from_cache: u64,
    /// Frames read back to the CPU ([`Renderer::render`] and its kin; never in a
    /// frame a host records).
    pub readbacks: u64,
    /// Bytes of acceleration structures built so far (ray queries: each scene's meshes'
    /// and its top-level structures, with their instance and scratch buffers), counted
    /// when they are built.
    pub acceleration_structure_bytes: u64,
}

/// How many completed frames' timings are kept until taken.
pub(crate) const COMPLETED_TIMINGS_KEPT: usize = 1024;

/// Whether a slot's last frame has completed, as its timestamps tell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SlotFrame {
    /// Completed (its timings were read), or nothing to tell: no frame was recorded in
    /// the slot since it was last known complete, or the device has no timestamps.
    Completed,
    /// Some timestamp of the slot's last frame is not written yet.
    Pending,
}

impl PassTimings {
    /// From a frame's timestamps in ms since its start (the start, the end of each pass
    /// in `passes`, then the end of its last command).
    pub(crate) fn from_stamps(passes: &[&'static str], ms: &[f64]) -> Self {
        Self {
            passes: passes
                .iter()
                .zip(ms.windows(2))
                .map(|(&name, pair)| PassTime {
                    name,
                    ms: pair[1] - pair[0],
                })
                .collect(),
            total_ms: ms.get(passes.len()).map_or(0.0, |end| end - ms[0]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_pixels_are_counted_by_their_colour() {
        let frame = Frame {
            width: 5,
            height: 1,
            hdr: vec![
                [1.0, 2.0, 3.0, 1.0],
                [f32::NAN, 0.0, 0.0, 1.0],
                [0.0, f32::INFINITY, 0.0, 1.0],
                [0.0, 0.0, f32::NEG_INFINITY, 1.0],
                // Alpha is not radiance.
                [0.0, 0.0, 0.0, f32::NAN],
            ],
            ..Frame::default()
        };
        assert_eq!(frame.non_finite_pixels(), 3);
        assert_eq!(Frame::default().non_finite_pixels(), 0);
    }
}
