//! Ambient occlusion (ambient_occlusion.comp), an optional pass (`--environment-occlusion
//! gtao`, off by default): per pixel, the cosine-weighted visibility of the hemisphere
//! above the surface, from the depth buffer, by ground-truth ambient occlusion (Jimenez
//! et al. 2016), into an image the lighting pass darkens the environment's light by (with
//! glTF occlusion textures: their minimum, so that occlusion both see counts once).

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

pub(crate) struct AmbientOcclusion;

/// Its option.
pub(crate) static OPTION: OptionalPass = OptionalPass {
    name: "ambient-occlusion",
    define: "AMBIENT_OCCLUSION",
    help: "ground-truth ambient occlusion from the depth buffer, every device",
    needs_ray_queries: false,
    choice: Some((&crate::options::ENVIRONMENT_OCCLUSION, "gtao")),
    needs_environment: Some("nothing to block"),
};

/// The image it writes: each pixel's visibility (1: nothing in the way).
pub(crate) const IMAGE: &str = "ambient occlusion";

/// Planes through the view direction per pixel, and depth samples on each side of one.
/// Two planes a pixel, turned over the 4×4 block whose pixels on one surface are
/// averaged (32 directions a block), measure as close to the form factor as eight did
/// (the resting sphere's ring −6.70 % against −6.66 %, mean |error| 7.81 % against
/// 7.79 %) at a third of the cost (builtin:resting at 1280×720: the pass 112 ms against
/// 345 ms, GPU medians of 10 frames).
const SLICES: u32 = 2;
const STEPS: u32 = 8;

/// The search radius, as a fraction of the diagonal of the scene's bounds.
const RADIUS_OF_SCENE: f32 = 0.25;

/// Its set: the depth and normals it reads, the visibility it writes.
pub(crate) static SET: SetDecl = SetDecl {
    name: "ambient_occlusion",
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
    ],
    includes: &[],
};

push_block! {
    /// Its push constants (`push/ambient_occlusion.glsl`).
    pub(crate) struct AmbientOcclusionPush in "ambient_occlusion" {
        /// Depth to world position (the inverse view-projection, column-major).
        inverse_view_projection: [f32; 16],
        /// The eye (w: 1).
        camera_position: [f32; 4],
        /// The unit view direction (xyz) and the pixels a unit length across it spans at
        /// unit distance along it (w).
        camera_forward: [f32; 4],
        /// The world radius searched for occluders.
        radius: f32,
        /// The largest screen radius searched, in pixels.
        max_radius_pixels: f32,
        /// Planes through the view direction per pixel.
        slices: u32,
        /// Depth samples on each side of a plane.
        steps: u32,
        /// The height above a pixel's tangent plane below which a sample does not occlude
        /// it, per square metre of the pixel's distance from the eye: 16 steps of the
        /// 32-bit depth there (16 · 2⁻²⁴ / near), so that a plane does not occlude itself.
        flat_tolerance: f32,
    }
}

/// Its shader over the frame's pixels, its set and its image.
const PER_PIXEL: PerPixel = PerPixel {
    name: "ambient occlusion",
    shader: "ambient_occlusion.comp",
    set: &SET,
    push_size: std::mem::size_of::<AmbientOcclusionPush>(),
    image: (IMAGE, vk::Format::R32_SFLOAT),
};

/// Whether frames of `variant` run it: asked for, in a scene with an environment (the
/// light it occludes).
fn wanted(variant: ShaderVariant) -> bool {
    variant.optional_passes.contains(&OPTION) && variant.environment
}

impl FramePass for AmbientOcclusion {
    fn name(&self) -> &'static str {
        "ambient occlusion"
    }

    fn option(&self) -> Option<&'static OptionalPass> {
        Some(&OPTION)
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![AmbientOcclusionPush::header()]
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
        PER_PIXEL.io(frame).image(
            "visibility",
            PER_PIXEL.output(frame),
            ImageUse::ComputeStorageWrite,
        )
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let camera = &frame.inputs.camera;
        let extent = frame.extent();
        let forward = (camera.target - camera.position).normalize();
        let pixels_per_unit = extent.height as f32 / (2.0 * (0.5 * camera.vertical_fov).tan());
        let radius = frame
            .scene
            .world_bounds
            .map_or(0.0, |(lo, hi)| RADIUS_OF_SCENE * (hi - lo).length());
        let push = AmbientOcclusionPush {
            inverse_view_projection: frame.lighting_push.inverse_view_projection,
            camera_position: camera.position.extend(1.0).to_array(),
            camera_forward: forward.extend(pixels_per_unit).to_array(),
            radius,
            max_radius_pixels: 0.5 * extent.height as f32,
            slices: SLICES,
            steps: STEPS,
            flat_tolerance: 16.0 * (-24f32).exp2() / camera.near,
        };
        PER_PIXEL.dispatch(frame, cmd, bytemuck::bytes_of(&push));
    }
}
