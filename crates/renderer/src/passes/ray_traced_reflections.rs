//! Ray-traced reflections (`--ray-traced-reflections on`, off by default; devices with
//! ray queries, frames lit by an environment): a smooth surface's split-sum specular
//! lookup — the environment's prefiltered radiance along the lobe's dominant direction —
//! replaced by one ray along that direction through the scene's acceleration structure,
//! so that a mirror-like surface shows its neighbours instead of the sky behind them.
//! This pass builds the frame's traced scene and the table of what its hits meet
//! (`accel::TracedSurfaces`, as path tracing does); the lighting pass traces the rays
//! (traced_reflections.glsl) and shades what each meets with its emission, every light's
//! light with shadow rays and the environment's split sum, all at the hit's own material
//! (the G-buffer pass's surface code, textures at level 0). A ray that meets nothing
//! takes the same prefiltered radiance as without the option: a lone object's frame is
//! unchanged.
//!
//! The share traced: 1 up to perceptual roughness [`ROUGHNESS`].0, 0 from
//! [`ROUGHNESS`].1, linear between (one ray cannot stand for a broad lobe). Not traced: a
//! clear coat's own lobe (its lookup stays the prefiltered one); light through a
//! transmissive surface a ray meets (it is shaded by what it reflects). Blended surfaces
//! and lights with a size are met by chance (each pixel's own random numbers, turned by
//! the frame's sample seed).

use super::FrameContext;
use crate::options::OptionalPass;
use crate::variant::ShaderVariant;

/// The pass (it builds the traced scene; the rays are another pass's).
pub(super) static PASS: super::traced::SceneForRays = super::traced::SceneForRays {
    name: "ray-traced reflections",
    option: &OPTION,
    header: ("ray_traced_reflections/constants.glsl", constants_header),
    wanted,
};

/// Its option.
pub(crate) static OPTION: OptionalPass = OptionalPass {
    name: "ray-traced-reflections",
    define: "RAY_TRACED_REFLECTIONS",
    help: "smooth surfaces reflect the scene by one ray a pixel (ray queries against the scene), not the environment's prefiltered radiance; frames lit by an environment, devices with ray queries, else left out with a warning",
    needs_ray_queries: true,
    choice: None,
    needs_environment: Some("no sky in the reflections to replace"),
};

/// The perceptual roughness up to which a surface's specular lookup is wholly traced,
/// and from which none of it is.
pub const ROUGHNESS: (f32, f32) = (0.1, 0.25);

/// The random-number stream of a pixel's reflection ray (beside the path tracer's).
const STREAM: u32 = 0x5EF1;

/// traced_reflections.glsl's constants, from this file's.
fn constants_header() -> String {
    format!(
        "// Generated from crates/renderer/src/passes/ray_traced_reflections.rs: do not edit.\n\
         #ifndef COMBUSTION_RAY_TRACED_REFLECTIONS_CONSTANTS_GLSL\n\
         #define COMBUSTION_RAY_TRACED_REFLECTIONS_CONSTANTS_GLSL\n\
         #define REFLECTIONS_ROUGHNESS_FULL {:.6}\n\
         #define REFLECTIONS_ROUGHNESS_NONE {:.6}\n\
         #define REFLECTIONS_STREAM {STREAM}u\n\
         #endif\n",
        ROUGHNESS.0, ROUGHNESS.1
    )
}

/// Whether frames of `variant` trace reflections: asked for, in a scene with an
/// environment (the renderer leaves the option out on a device without ray queries).
pub(crate) fn wanted(variant: ShaderVariant) -> bool {
    variant.optional_passes.contains(&OPTION) && variant.environment
}

/// Whether the frame traces reflections (its scene's structures built).
pub(super) fn traces(frame: &FrameContext<'_>) -> bool {
    PASS.traces(frame)
}
