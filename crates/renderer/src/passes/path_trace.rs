//! Path tracing (`--path-trace on`, off by default; devices with ray queries): the frame
//! as light that bounces. This pass builds the scene's acceleration structure for the
//! frame (`crate::accel`) and the table of what each instance's hits meet
//! (`accel::TracedSurfaces`: its mesh's vertices and indices, its material); the lighting
//! pass (lighting.frag, path_trace.glsl) then traces each pixel's paths instead of
//! shading the G-buffer, with the same GLSL material terms it shades the G-buffer with:
//! from the eye through the pixel's centre, next-event estimation to every light with a
//! shadow ray, the reflection sampled by GGX's visible normals, the cosine and a coat's
//! visible normals in one-sample balance, emitters and the environment found by the
//! bounces, Russian roulette — the rules of the f64 path tracer
//! (`combustion_reference::path`) it is measured against.
//!
//! Each frame is the mean of [`PATHS_PER_FRAME`] paths a pixel drawn from its own seed
//! (`FrameInputs::environment_seed`); frames of successive seeds are independent, so
//! their mean converges with a standard error from their spread (`combustion render
//! --path-trace on --accumulate-until E`).
//!
//! Glass is traced as the f64 tracer traces it (thin walls, and volumes with absorption
//! and total internal reflection); blended surfaces are met with probability α; objects
//! that block no light (glass, blended, casting no shadow) are in the structure for paths
//! alone (instance mask `accel::SEEN_ONLY`), in frames that path-trace only. A hit reads
//! its material's textures at level 0 (the surface table holds the scene's texels) and a
//! skinned or morphed object's posed vertices (an occluder's in every traced frame, one
//! that blocks no light in frames that path-trace).

use super::FrameContext;
use crate::bindings::{Binding, BindingKind};
use crate::options::OptionalPass;
use crate::pass_io::PassIo;
use crate::variant::ShaderVariant;

/// The pass (it builds the traced scene; the rays are another pass's).
pub(super) static PASS: super::traced::SceneForRays = super::traced::SceneForRays {
    name: "path trace",
    option: &OPTION,
    header: ("path_trace/constants.glsl", constants_header),
    wanted,
};

/// Its option.
pub(crate) static OPTION: OptionalPass = OptionalPass {
    name: "path-trace",
    define: "PATH_TRACE",
    help: "the frame path traced by ray queries (light that bounces), averaged over frames by --accumulate-until; devices with ray queries, else left out with a warning",
    needs_ray_queries: true,
    choice: None,
    needs_environment: None,
};

/// Paths per pixel in one frame.
pub const PATHS_PER_FRAME: u32 = 4;

/// The surface (from 1) from which Russian roulette may end a path, and the largest
/// probability it lets a path go on with (the f64 path tracer's rule).
pub const ROULETTE: (u32, f32) = (3, 0.95);

/// path_trace.glsl's constants, from this file's.
fn constants_header() -> String {
    format!(
        "// Generated from crates/renderer/src/passes/path_trace.rs: do not edit.\n\
         #ifndef COMBUSTION_PATH_TRACE_CONSTANTS_GLSL\n\
         #define COMBUSTION_PATH_TRACE_CONSTANTS_GLSL\n\
         #define PATHS_PER_FRAME {PATHS_PER_FRAME}u\n\
         #define PATH_ROULETTE_START {}u\n\
         #define PATH_ROULETTE_MAX {:.6}\n\
         {}\
         #endif\n",
        ROULETTE.0,
        ROULETTE.1,
        crate::environment_importance::constants_glsl()
    )
}

/// The lighting set's binding of the environment's distribution of directions
/// (`crate::environment_importance`; the frame's environment's, or a placeholder's).
pub(super) const ENVIRONMENT_IMPORTANCE: Binding = Binding::new(
    "environment_importance",
    BindingKind::StorageBuffer {
        block: "EnvironmentImportance",
        element: "float",
    },
    crate::bindings::FRAGMENT,
)
.for_ray_queries()
.only_with(OPTION.define);

/// Whether frames of `variant` are path traced.
pub(crate) fn wanted(variant: ShaderVariant) -> bool {
    variant.optional_passes.contains(&OPTION)
}

/// Whether the frame is path traced (its scene's structures built: on a device with ray
/// queries).
pub(super) fn traces(frame: &FrameContext<'_>) -> bool {
    PASS.traces(frame)
}

/// `io` with the surface and texture tables bound: the scene's where the frame is path
/// traced, else the renderer's empty ones (devices with ray queries only).
pub(super) fn bind_surfaces(io: PassIo, frame: &FrameContext<'_>) -> PassIo {
    let own = frame
        .scene
        .gpu
        .structures
        .get()
        .filter(|_| super::frame_reads_surfaces(frame))
        .and_then(|s| s.surfaces.get());
    match own.or(frame.shared.no_surfaces.as_ref()) {
        Some(surfaces) => io
            .bind_buffer("traced_surfaces", &surfaces.table)
            .bind_buffer("traced_textures", &surfaces.textures),
        None => io,
    }
}
