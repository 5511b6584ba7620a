//! Ray-traced refraction (`--ray-traced-refraction on`, off by default; devices with ray
//! queries, scenes with transmissive objects): the forward pass's transmission traced
//! through the scene instead of looked up on the screen. This pass builds the frame's
//! traced scene and the table of what its hits meet (`accel::TracedSurfaces`, as path
//! tracing does; glass and blended objects are in it for these rays); the forward pass
//! (forward.frag, RAY_TRACED_REFRACTION) then follows each transmissive fragment's view
//! ray: refracted in by Snell's law and the exact Fresnel transmittance; in a volume
//! (KHR_materials_volume), to the interface it meets inside — whichever object's — where
//! it is refracted out, and the part reflected there to the interface it meets next; out
//! of it (or straight through a thin wall) to the surface it meets, shaded with its
//! emission, every light's light with shadow rays and the environment's split sum —
//! through the walls of thin-walled transmissive surfaces it meets on the way (up to
//! [`THIN_WALLS`]) — or, where it meets nothing, the environment (its level by the
//! surface's roughness). The interfaces' Fresnel terms, the light's round trips inside
//! and Beer–Lambert absorption are the screen-space rules'.
//!
//! A rough thin wall averages [`ROUGH_RAYS`] rays, their directions drawn from the spread
//! of its two rough interfaces (the path tracer's rule). Not traced: a volume a ray meets
//! beyond the first (shaded by what it reflects), a rough volume's spread (one ray, sharp
//! behind it; only the environment is blurred).
//! The behind and back-faces passes, whose images only screen-space refraction reads, do
//! not run in its frames.

use super::FrameContext;
use crate::options::OptionalPass;
use crate::variant::ShaderVariant;

/// The pass (it builds the traced scene; the rays are another pass's).
pub(super) static PASS: super::traced::SceneForRays = super::traced::SceneForRays {
    name: "ray-traced refraction",
    option: &OPTION,
    header: ("ray_traced_refraction/constants.glsl", constants_header),
    wanted,
};

/// Its option.
pub(crate) static OPTION: OptionalPass = OptionalPass {
    name: "ray-traced-refraction",
    define: "RAY_TRACED_REFRACTION",
    help: "transmissive objects show what lies behind them by rays traced through the scene (ray queries), not by screen-space lookups; devices with ray queries, else left out with a warning",
    needs_ray_queries: true,
    choice: None,
    needs_environment: None,
};

/// Thin-walled transmissive surfaces a refracted ray passes through before what it
/// shows.
pub const THIN_WALLS: u32 = 4;

/// Rays a rough thin wall's transmission averages (directions drawn from the spread of
/// its two rough interfaces).
pub const ROUGH_RAYS: u32 = 8;

/// The random-number stream of a fragment's refracted rays.
const STREAM: u32 = 0x7EF2;

/// forward.frag's constants, from this file's.
fn constants_header() -> String {
    format!(
        "// Generated from crates/renderer/src/passes/ray_traced_refraction.rs: do not edit.\n\
         #ifndef COMBUSTION_RAY_TRACED_REFRACTION_CONSTANTS_GLSL\n\
         #define COMBUSTION_RAY_TRACED_REFRACTION_CONSTANTS_GLSL\n\
         #define REFRACTION_THIN_WALLS {THIN_WALLS}u\n\
         #define REFRACTION_ROUGH_RAYS {ROUGH_RAYS}u\n\
         #define REFRACTION_STREAM {STREAM}u\n\
         #endif\n"
    )
}

/// Whether frames of `variant` trace refraction: asked for, in a scene with transmissive
/// objects (the renderer leaves the option out on a device without ray queries).
pub(crate) fn wanted(variant: ShaderVariant) -> bool {
    variant.optional_passes.contains(&OPTION)
        && variant.transmission
        && super::forward::draws(variant)
}

/// Whether the frame traces refraction (its scene's structures built).
pub(super) fn traces(frame: &FrameContext<'_>) -> bool {
    PASS.traces(frame)
}
