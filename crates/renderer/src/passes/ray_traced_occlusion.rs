//! Ray-traced occlusion (ray_traced_occlusion.comp), an optional pass
//! (`--environment-occlusion ray-traced`, off by default; devices with ray queries): per pixel, the
//! share of `RAYS` cosine-distributed rays from the surface that leave the scene — the
//! visibility of the environment's diffuse light, traced against the scene's
//! acceleration structures (`crate::accel`: what they hold and leave out). The lighting
//! pass darkens the environment's light by it as by the screen-space pass's (with glTF
//! occlusion textures: their minimum). Each pixel draws its own rays, the same in every
//! frame of the same sample seed (`FrameInputs::environment_seed`): no noise from frame
//! to frame; frames of other seeds draw others, and their mean converges
//! (`combustion render --accumulate-until`).
//!
//! With the sampled environment (`ShadingOptions::environment_samples`) the lighting
//! pass traces each of its directions against the structure this pass builds, and this
//! pass draws no rays of its own: that mode then converges to the direct environment
//! light of the rendering equation with the scene's geometry in the way.

use combustion_vk::vk;

use super::per_pixel::PerPixel;
use super::{FrameContext, FramePass};
use crate::bindings::{Binding, BindingKind, SetDecl, COMPUTE};
use crate::error::RenderError;
use crate::graph::ImageUse;
use crate::options::{OptionalPass, RendererSettings};
use crate::pass_io::PassIo;
use crate::pipelines::PipelineRegistry;
use crate::push::{push_block, PushBlock};
use crate::targets::ImageRequest;
use crate::variant::ShaderVariant;

pub(crate) struct RayTracedOcclusion;

/// Its option.
pub(crate) static OPTION: OptionalPass = OptionalPass {
    name: "ray-traced-occlusion",
    define: "RAY_TRACED_OCCLUSION",
    help: "64 rays a pixel by ray queries against the scene (with --environment-samples N, each sampled direction traced instead); devices with ray queries, else left out with a warning",
    needs_ray_queries: true,
    choice: Some((&crate::options::ENVIRONMENT_OCCLUSION, "ray-traced")),
    needs_environment: Some("nothing to block"),
};

/// The image it writes: each pixel's visibility (1: nothing in the way).
pub(crate) const IMAGE: &str = "ray-traced occlusion";

/// Rays per pixel.
const RAYS: u32 = 64;

/// Its set: the depth and normals it reads, the scene it traces, the visibility it
/// writes.
pub(crate) static SET: SetDecl = SetDecl {
    name: "ray_traced_occlusion",
    set: 0,
    bindings: &[
        Binding::new("gbuffer_depth", BindingKind::Texture2D, COMPUTE),
        Binding::new(
            "gbuffer_normal_roughness_anisotropy",
            BindingKind::Texture2D,
            COMPUTE,
        ),
        Binding::new(
            "visibility",
            BindingKind::StorageImage2D { format: "r32f" },
            COMPUTE,
        ),
        super::traced::bindings(COMPUTE, None)[0],
        super::traced::bindings(COMPUTE, None)[1],
        super::traced::bindings(COMPUTE, None)[2],
        super::traced::bindings(COMPUTE, None)[3],
    ],
    includes: &[],
};

push_block! {
    /// Its push constants (`push/ray_traced_occlusion.glsl`).
    pub(crate) struct RayTracedOcclusionPush in "ray_traced_occlusion" {
        /// Depth to world position (the inverse view-projection, column-major).
        inverse_view_projection: [f32; 16],
        /// The eye (w: 1).
        camera_position: [f32; 4],
        /// Rays per pixel.
        rays: u32,
        /// How far along its normal a ray starts, per metre of the point's distance from
        /// the eye (past the depth's rounding and the tessellation's flat facets).
        offset_per_distance: f32,
        /// How far a ray looks (past every object of the scene).
        reach: f32,
        /// The frame's sample seed (`FrameInputs::environment_seed`): each seed turns
        /// every pixel's rays anew, so that frames averaged converge.
        seed: u32,
    }
}

/// Its shader over the frame's pixels, its set and its image.
const PER_PIXEL: PerPixel = PerPixel {
    name: "ray-traced occlusion",
    shader: "ray_traced_occlusion.comp",
    set: &SET,
    push_size: std::mem::size_of::<RayTracedOcclusionPush>(),
    image: (IMAGE, vk::Format::R32_SFLOAT),
};

/// Whether frames of `variant` run it: asked for, in a scene with an environment. (The
/// renderer leaves the option out on a device without ray queries.)
fn wanted(variant: ShaderVariant) -> bool {
    variant.optional_passes.contains(&OPTION) && variant.environment
}

/// Whether the frame runs the pass (which builds the structure the lighting pass's
/// sampled environment traces, before it).
pub(super) fn traces(frame: &FrameContext<'_>) -> bool {
    wanted(frame.variant) && frame.scene.gpu.structures.get().is_some()
}

impl FramePass for RayTracedOcclusion {
    fn name(&self) -> &'static str {
        "ray-traced occlusion"
    }

    fn option(&self) -> Option<&'static OptionalPass> {
        Some(&OPTION)
    }

    fn traces(&self, variant: ShaderVariant) -> bool {
        wanted(variant)
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![RayTracedOcclusionPush::header()]
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        static SETS: [&SetDecl; 1] = [&SET];
        &SETS
    }

    fn prepare(
        &self,
        variant: ShaderVariant,
        settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        PER_PIXEL.prepare(wanted(variant), settings, registry)
    }

    fn images(&self, variant: ShaderVariant, _settings: &RendererSettings) -> Vec<ImageRequest> {
        PER_PIXEL.images(wanted(variant))
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        wanted(frame.variant)
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let io = PER_PIXEL.io(frame).image(
            "visibility",
            PER_PIXEL.output(frame),
            ImageUse::ComputeStorageWrite,
        );
        super::traced::scene(io, frame)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        super::traced::record_build(frame, cmd);
        let scene = frame.scene;
        if frame.variant.environment_samples > 0 {
            // The sampled environment traces its own directions in the lighting pass:
            // the structure is all it needs of this pass.
            return;
        }
        let reach = scene
            .world_bounds
            .map_or(1.0, |(lo, hi)| 2.0 * (hi - lo).length().max(1e-3));
        let push = RayTracedOcclusionPush {
            inverse_view_projection: frame.lighting_push.inverse_view_projection,
            camera_position: frame.inputs.camera.position.extend(1.0).to_array(),
            rays: RAYS,
            offset_per_distance: crate::accel::ENVIRONMENT_RAY_OFFSET as f32,
            reach,
            seed: frame.inputs.environment_seed,
        };
        PER_PIXEL.dispatch(frame, cmd, bytemuck::bytes_of(&push));
    }
}
