//! Ray-traced shadows (ray_traced_shadows.comp), an optional pass
//! (`--ray-traced-shadows on`, off by default; devices with ray queries): per pixel, for
//! each of the frame's first 32 lights that casts shadows, one ray from the surface to the
//! light against the scene's acceleration structures (`crate::accel`: what they hold and
//! leave out) — hard shadows by exact visibility, with the f64 reference's offset rule
//! (`combustion_reference::shadow_ray_origin`: 10⁻⁴ · max(1, ‖p‖∞) along the normal the
//! lighting pass shades with; a segment to a point or spot light ends as far short of
//! it). A light with a size (a point or spot light's radius, a directional light's
//! angular diameter) gets 15 rays instead (5 × 3 stratified points: the count that reach
//! fits a nibble, so the share stored is the share traced), towards stratified points of the
//! disc it is seen as (the f64 reference's `disc_visibility` and `sun_visibility`: the
//! disc of its radius facing the point; the cone of its angular diameter), turned per
//! pixel: soft shadows. Nibble i of the pixel's 128 bits holds how many of light i's rays
//! reach it, of 15 (15 for a light that casts no shadow); the lighting pass scales each
//! light by that share, leaving out those none reach. Lights past the 32nd are not
//! shadowed by it.

use combustion_vk::vk;

use super::per_pixel::PerPixel;
use super::{FrameContext, FramePass};
use crate::bindings::{Binding, BindingKind, SetDecl, COMPUTE};
use crate::error::RenderError;
use crate::graph::{BufferUse, ImageUse};
use crate::options::{OptionalPass, RendererSettings};
use crate::pass_io::PassIo;
use crate::pipelines::PipelineRegistry;
use crate::push::{push_block, PushBlock};
use crate::targets::ImageRequest;
use crate::variant::ShaderVariant;

pub(crate) struct RayTracedShadows;

/// Its option.
pub(crate) static OPTION: OptionalPass = OptionalPass {
    name: "ray-traced-shadows",
    define: "RAY_TRACED_SHADOWS",
    help: "Shadows of the first 32 lights that cast them, by ray queries against the scene's acceleration structures: exact visibility, soft for lights with a size (15 rays over their disc or cone); devices with ray queries, else left out with a warning",
    needs_ray_queries: true,
    choice: None,
    needs_environment: None,
};

/// The image it writes: per pixel, bit i set where light i reaches it.
pub(crate) const IMAGE: &str = "ray-traced shadows";

/// The lights it shadows: the frame's first 32 (four bits each).
const MAX_LIGHTS: usize = 32;

/// Its set: the depth and normals it reads, the frame's lights, the scene it traces,
/// the light bits it writes.
pub(crate) static SET: SetDecl = SetDecl {
    name: "ray_traced_shadows",
    set: 0,
    bindings: &[
        Binding::new("gbuffer_depth", BindingKind::Texture2D, COMPUTE),
        Binding::new(
            "gbuffer_normal_roughness_anisotropy",
            BindingKind::Texture2D,
            COMPUTE,
        ),
        Binding::new(
            "lights",
            BindingKind::StorageBuffer {
                block: "Lights",
                element: "GpuLight",
            },
            COMPUTE,
        ),
        Binding::new(
            "light_bits",
            BindingKind::UStorageImage2D { format: "rgba32ui" },
            COMPUTE,
        ),
        super::traced::bindings(COMPUTE, None)[0],
        super::traced::bindings(COMPUTE, None)[1],
        super::traced::bindings(COMPUTE, None)[2],
        super::traced::bindings(COMPUTE, None)[3],
    ],
    includes: &["gpu_types.glsl"],
};

push_block! {
    /// Its push constants (`push/ray_traced_shadows.glsl`).
    pub(crate) struct RayTracedShadowsPush in "ray_traced_shadows" {
        /// Depth to world position (the inverse view-projection, column-major).
        inverse_view_projection: [f32; 16],
        /// The eye (w: 1).
        camera_position: [f32; 4],
        /// The lights it traces: the frame's, at most 32.
        lights: u32,
        /// Bit i: light i casts shadows.
        casting: u32,
        /// Unused (the block's size, a multiple of 16).
        unused: [u32; 2],
    }
}

/// Its shader over the frame's pixels, its set and its image.
const PER_PIXEL: PerPixel = PerPixel {
    name: "ray-traced shadows",
    shader: "ray_traced_shadows.comp",
    set: &SET,
    push_size: std::mem::size_of::<RayTracedShadowsPush>(),
    image: (IMAGE, vk::Format::R32G32B32A32_UINT),
};

/// Whether frames of `variant` run it. (The renderer leaves the option out on a device
/// without ray queries.)
fn wanted(variant: ShaderVariant) -> bool {
    variant.optional_passes.contains(&OPTION)
}

impl FramePass for RayTracedShadows {
    fn name(&self) -> &'static str {
        "ray-traced shadows"
    }

    fn option(&self) -> Option<&'static OptionalPass> {
        Some(&OPTION)
    }

    fn traces(&self, variant: ShaderVariant) -> bool {
        wanted(variant)
    }

    fn headers(&self) -> Vec<(String, String)> {
        vec![RayTracedShadowsPush::header()]
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
        let io = PER_PIXEL
            .io(frame)
            .buffer("lights", &frame.slot.lights, BufferUse::ComputeStorageRead)
            .image(
                "light_bits",
                PER_PIXEL.output(frame),
                ImageUse::ComputeStorageWrite,
            );
        super::traced::scene(io, frame)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        super::traced::record_build(frame, cmd);
        let lights = frame.inputs.lights.len().min(MAX_LIGHTS);
        let casting = frame.inputs.lights[..lights]
            .iter()
            .enumerate()
            .filter(|(_, light)| light.casts_shadows())
            .fold(0u32, |bits, (i, _)| bits | (1 << i));
        let push = RayTracedShadowsPush {
            inverse_view_projection: frame.lighting_push.inverse_view_projection,
            camera_position: frame.inputs.camera.position.extend(1.0).to_array(),
            lights: lights as u32,
            casting,
            unused: [0; 2],
        };
        PER_PIXEL.dispatch(frame, cmd, bytemuck::bytes_of(&push));
    }
}
