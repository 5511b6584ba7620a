//! The lighting pass (fullscreen.vert + lighting.frag): per pixel, the G-buffer decoded
//! and every light (or the tile's list) shaded with the BRDF, plus the environment's
//! split sum and the emitted radiance in their variants, into the HDR image.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::bindings::{joined, Binding, BindingKind, SetDecl, FRAGMENT, LIT_BY, MATERIALS};
use crate::error::RenderError;
use crate::fullscreen::{begin_screen_rendering, end_rendering, FullscreenPass, TargetStart};
use crate::gpu_types::LightingPush;
use crate::graph::{BufferUse, ImageUse};
use crate::host::{AntiAliasing, OutputEncoding};
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::results::PassTimings;
use crate::targets::ImageRequest;
use crate::variant;
use crate::variant::ShaderVariant;

pub(crate) struct Lighting;

/// The lighting pass's own bindings (then `LIT_BY`'s).
const OWN_BINDINGS: &[Binding] = &[
    Binding::new(
        "gbuffer_base_color_metalness",
        BindingKind::Texture2D,
        FRAGMENT,
    ),
    Binding::new(
        "gbuffer_normal_roughness_anisotropy",
        BindingKind::Texture2D,
        FRAGMENT,
    ),
    Binding::new(
        "gbuffer_material_direction",
        BindingKind::UTexture2D,
        FRAGMENT,
    ),
    Binding::new("gbuffer_depth", BindingKind::Texture2D, FRAGMENT),
    MATERIALS,
    // Per 16×16 tile: the number of lights that can reach it, then their indices
    // (written by the light-culling pass; read only in frames that cull).
    Binding::new(
        "tile_lights",
        BindingKind::StorageBuffer {
            block: "TileLights",
            element: "uint",
        },
        FRAGMENT,
    ),
    // Emitted radiance (rgb) and occlusion (a) (EMISSIVE, OCCLUSION variants).
    Binding::new("gbuffer_emissive", BindingKind::Texture2D, FRAGMENT)
        .only_with(variant::EMISSIVE_OCCLUSION_TARGET.define),
    // The clear coat: its normal (octahedral, xy), roughness (z) and weight (w)
    // (CLEARCOAT variant).
    Binding::new("gbuffer_clearcoat", BindingKind::Texture2D, FRAGMENT)
        .only_with(variant::CLEARCOAT.define),
    // The sheen: its linear colour (rgb) and perceptual roughness (a) (SHEEN variant).
    Binding::new("gbuffer_sheen", BindingKind::Texture2D, FRAGMENT)
        .only_with(variant::SHEEN.define),
    // The thin film: its weight (r) and thickness in nm (g) (IRIDESCENCE variant).
    Binding::new("gbuffer_film", BindingKind::Texture2D, FRAGMENT)
        .only_with(variant::IRIDESCENCE.define),
    // The dielectric's specular colour (rgb) and factor (a) (SPECULAR variant).
    Binding::new("gbuffer_specular", BindingKind::Texture2D, FRAGMENT)
        .only_with(variant::SPECULAR.define),
    // The environment's visibility (the ambient-occlusion pass's image).
    Binding::new("ambient_occlusion", BindingKind::Texture2D, FRAGMENT)
        .only_with(super::ambient_occlusion::OPTION.define),
    // The environment's visibility (the ray-traced occlusion pass's image).
    Binding::new("ray_traced_occlusion", BindingKind::Texture2D, FRAGMENT)
        .only_with(super::ray_traced_occlusion::OPTION.define),
    // Which lights reach each pixel (the ray-traced shadows pass's image).
    Binding::new("ray_traced_shadows", BindingKind::UTexture2D, FRAGMENT)
        .only_with(super::ray_traced_shadows::OPTION.define),
];

/// The scene as the ray-traced occlusion pass built it, which the sampled environment
/// traces each of its directions against.
/// Declared where lighting.frag traces the scene: for the sampled environment's
/// directions (RAY_TRACED_OCCLUSION) or its paths (PATH_TRACE); then the path tracer's
/// surface and texture tables.
const TRACED: [Binding; 7] = {
    let [scene, cutouts, corners, alphas] =
        super::traced::bindings(FRAGMENT, Some(super::ray_traced_occlusion::OPTION.define));
    // lighting.frag defines it for PATH_TRACE and RAY_TRACED_REFLECTIONS.
    let surfaces = crate::bindings::TRACED_SURFACES;
    let [surface_table, texture_table] = crate::bindings::TRACED_SURFACE_TABLES;
    [
        scene.or_with(surfaces),
        cutouts.or_with(surfaces),
        corners.or_with(surfaces),
        alphas.or_with(surfaces),
        surface_table,
        texture_table,
        super::path_trace::ENVIRONMENT_IMPORTANCE,
    ]
};

const OWN_AND_TRACED: [Binding; OWN_BINDINGS.len() + TRACED.len()] = joined(OWN_BINDINGS, &TRACED);

const BINDINGS: [Binding; OWN_AND_TRACED.len() + LIT_BY.len()] = joined(&OWN_AND_TRACED, &LIT_BY);

/// The lighting pass's set: the G-buffer and depth, the material table, the tile light lists,
/// the emissive target (EMISSIVE variant), and what lights a surface (`LIT_BY`: lighting_terms.glsl).
pub(crate) static SET: SetDecl = SetDecl {
    name: "lighting",
    set: 0,
    bindings: &BINDINGS,
    includes: &["gpu_types.glsl"],
};

/// The name of the HDR image the lighting pass writes (what every later pass adds to,
/// and the output pass reads).
pub(crate) const HDR: &str = "hdr radiance";

/// The lighting pipeline of `variant` (its every feature a define), reading
/// `settings`' G-buffer storage into their HDR format.
fn key(variant: ShaderVariant, settings: &RendererSettings) -> PipelineKey {
    PipelineKey {
        pass: PassTimings::LIGHTING,
        variant: Some(variant),
        defines: settings.gbuffer.defines(),
        formats: vec![settings.hdr_format.vk()],
    }
}

/// The lighting pipeline of `variant` with the output pass's work folded in
/// (`OUTPUT_FOLDED`), writing targets of `format` as the output pass would.
fn folded_key(
    variant: ShaderVariant,
    settings: &RendererSettings,
    format: vk::Format,
) -> PipelineKey {
    let mut defines = settings.gbuffer.defines();
    defines.push(("OUTPUT_FOLDED", None));
    defines.extend(OutputEncoding::of(format).map_or_else(Vec::new, OutputEncoding::defines));
    PipelineKey {
        pass: PassTimings::LIGHTING,
        variant: Some(variant),
        defines,
        formats: vec![format],
    }
}

/// Whether `variant`'s lighting pipeline shades only the pixels where a surface was
/// drawn (its depth test: the frame's depth other than the far plane's, a depth that is
/// not a number included, which lighting.frag handles), the background's pixels left to
/// the background pipeline ([`background_key`]: the far plane's depth) or to the target's
/// clear: between them the two tests pass every pixel once.
/// On lavapipe a 4×4 block that fails the test as a whole runs no shader: on
/// builtin:grid-7x7, 80 % background, the lighting pass takes 13.75 ms instead of
/// 16.5 (docs/performance.md). Path-traced frames trace every pixel, the background's
/// too (path_trace.glsl), and are not tested.
fn shades_surfaces_only(variant: ShaderVariant) -> bool {
    !super::path_trace::wanted(variant)
}

/// The lighting pipeline of `variant` reading `settings`' G-buffer storage, with `extra`
/// defines, into `format`: depth-tested where it shades surfaces only.
fn pipeline(
    t: &crate::pipelines::PipelineTools<'_>,
    (variant, settings): (ShaderVariant, &RendererSettings),
    extra: &[(&'static str, Option<&'static str>)],
    format: vk::Format,
) -> Result<FullscreenPass, RenderError> {
    let mut defines = variant.defines();
    defines.extend(settings.gbuffer.defines());
    defines.extend_from_slice(extra);
    let test = shades_surfaces_only(variant).then_some(vk::CompareOp::NOT_EQUAL);
    lighting_frag(t, &defines, format, test)
}

/// lighting.frag built with `defines` into targets of `format`, depth-tested by `test`.
fn lighting_frag(
    t: &crate::pipelines::PipelineTools<'_>,
    defines: &[(&str, Option<&str>)],
    format: vk::Format,
    test: Option<vk::CompareOp>,
) -> Result<FullscreenPass, RenderError> {
    FullscreenPass::build(
        t.device,
        t.compiler,
        t.cache,
        ("lighting.frag", defines),
        t.layouts.of(&SET),
        std::mem::size_of::<LightingPush>() as u32,
        (format, combustion_vk::ColorBlend::Replace, test),
    )
}

/// The background pipeline of frames of `variant` into targets of `format`, the output
/// pass's work folded in for `folded` (its encoding's defines): lighting.frag built with
/// `BACKGROUND_PIXELS`, depth-tested to the pixels where no surface was drawn, writing
/// the background's radiance or the environment along the pixel's ray. Shared by every
/// variant with the same environment feature (nothing else of the variant is read).
fn background_key(
    variant: ShaderVariant,
    format: vk::Format,
    folded: Option<OutputEncoding>,
) -> PipelineKey {
    let mut defines = vec![("BACKGROUND_PIXELS", None)];
    if (variant::ENVIRONMENT.of)(&variant) {
        defines.push((variant::ENVIRONMENT.define, None));
    }
    if let Some(encoding) = folded {
        defines.push(("OUTPUT_FOLDED", None));
        defines.extend(encoding.defines());
    }
    PipelineKey {
        pass: PassTimings::LIGHTING,
        variant: None,
        defines,
        formats: vec![format],
    }
}

/// Builds the background pipeline of [`background_key`] (once for all the variants that
/// share it), for variants that shade surfaces only.
fn prepare_background(
    registry: &mut PipelineRegistry,
    variant: ShaderVariant,
    format: vk::Format,
    folded: Option<OutputEncoding>,
) -> Result<(), RenderError> {
    if !shades_surfaces_only(variant) {
        return Ok(());
    }
    let key = background_key(variant, format, folded);
    let defines = key.defines.clone();
    registry.build(key, |t| {
        Ok((
            lighting_frag(t, &defines, format, Some(vk::CompareOp::EQUAL))?,
            1,
        ))
    })?;
    Ok(())
}

/// Builds the lighting pipeline of `variant` that writes targets of `format` itself
/// (the output folded in), for renderers that fold ([`RendererSettings::fold_output`]):
/// for every prepared variant when a format's output passes are built, and for every
/// such format when a variant is prepared, so that no frame compiles one.
pub(crate) fn prepare_folded(
    registry: &mut PipelineRegistry,
    variant: ShaderVariant,
    settings: &RendererSettings,
    format: vk::Format,
) -> Result<(), RenderError> {
    let Some(encoding) = OutputEncoding::of(format) else {
        return Ok(());
    };
    if !settings.fold_output {
        return Ok(());
    }
    // The background's first: a frame folds where the folded pipeline is built
    // (folds_output), and it draws both.
    prepare_background(registry, variant, format, Some(encoding))?;
    registry.build(folded_key(variant, settings, format), |t| {
        let mut folded = vec![("OUTPUT_FOLDED", None)];
        folded.extend(encoding.defines());
        Ok((pipeline(t, (variant, settings), &folded, format)?, 1))
    })?;
    Ok(())
}

/// Whether `frame` has the lighting pass write its target itself, the output pass's
/// exposure, tone curve and encoding done per pixel there and the output pass not run:
/// where the renderer folds ([`RendererSettings::fold_output`]), the frame's HDR image
/// is not read back after it, no pass between the two runs (none reads or adds to the
/// radiance before it is shown), FXAA does not smooth its display values (it reads
/// their neighbours), and the folded pipeline is built for the frame's variant and
/// target format.
pub(crate) fn folds_output(frame: &FrameContext<'_>) -> bool {
    if !frame.settings.fold_output || frame.hdr_read_after {
        return false;
    }
    let format = frame.target.color.format;
    let Some(encoding) = OutputEncoding::of(format) else {
        return false;
    };
    if frame.inputs.anti_aliasing == AntiAliasing::Fxaa && encoding != OutputEncoding::Linear {
        return false;
    }
    frame
        .registry
        .get::<FullscreenPass>(&folded_key(frame.variant, frame.settings, format))
        .is_some()
        && super::between_lighting_and_output().all(|pass| !pass.runs(frame))
}

/// Declares what lights a surface (`bindings::LIT_BY`, lighting_terms.glsl) in `io`: the
/// frame's lights, the conductor table, the energy table, the environment (or its
/// placeholders) and the shadow maps (or placeholders), every binding written.
pub(super) fn lit_by(mut io: PassIo, frame: &FrameContext<'_>) -> PassIo {
    let (s, r) = (frame.slot, frame.shared);
    let read = BufferUse::FragmentStorageRead;
    let texel = ImageUse::FragmentSampled;
    io = io
        .buffer("lights", &s.lights, read)
        .buffer(
            "conductor_from_code",
            &frame.scene.gpu.conductor_table,
            read,
        )
        .bind_buffer("energy_white_albedo", &r.energy_table)
        .bind_buffer("sheen_albedo", &r.sheen_table);
    let environment = frame.environment.unwrap_or(&r.no_environment);
    let sampler = environment.sampler.raw();
    // The cubes were made ready for fragment reads by their bake.
    let cube_layout = texel.state().layout;
    io = io
        .bind_image(
            "environment_specular",
            environment.specular.view(),
            cube_layout,
            sampler,
        )
        .bind_image(
            "environment_irradiance",
            environment.irradiance.view(),
            cube_layout,
            sampler,
        );
    let tables = [
        ("environment_albedo", &environment.albedo),
        ("environment_code_albedo", &environment.code_albedo),
        (
            "environment_code_table_of_material",
            &environment.code_table_of_material,
        ),
    ];
    for (binding, table) in tables {
        io = io.buffer_if(frame.environment.is_some(), binding, table, read);
    }
    match frame.shadow_maps {
        Some((cascades, local)) => {
            for (binding, depths, maps) in [
                ("shadow_maps", "shadow_depths", cascades),
                ("local_shadow_maps", "local_shadow_depths", local),
            ] {
                io = io
                    .sampled_view(
                        binding,
                        &maps.image,
                        maps.array_view.raw(),
                        r.shadow_sampler.raw(),
                        ImageUse::DepthFragmentSampled,
                    )
                    .image_view(
                        depths,
                        &maps.image,
                        maps.array_view.raw(),
                        ImageUse::DepthFragmentSampled,
                    );
            }
        }
        // Not declared by pipelines without shadows: any image will do.
        None => {
            for binding in ["shadow_maps", "local_shadow_maps"] {
                io = io.bind_image(
                    binding,
                    r.absent_target.view(),
                    texel.state().layout,
                    r.shadow_sampler.raw(),
                );
            }
            for binding in ["shadow_depths", "local_shadow_depths"] {
                io = io.bind_image(
                    binding,
                    r.absent_target.view(),
                    texel.state().layout,
                    vk::Sampler::null(),
                );
            }
        }
    }
    io.bind_buffer("shadow_cascades", &s.shadow_cascades)
}

impl FramePass for Lighting {
    fn name(&self) -> &'static str {
        PassTimings::LIGHTING
    }

    fn sets(&self) -> &'static [&'static SetDecl] {
        // The overlay's, drawn over the target where the output is folded in.
        static SETS: [&SetDecl; 2] = [&SET, &crate::bindings::OVERLAY];
        &SETS
    }

    fn prepare(
        &self,
        variant: ShaderVariant,
        settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        let hdr = settings.hdr_format.vk();
        prepare_background(registry, variant, hdr, None)?;
        registry.build(key(variant, settings), |t| {
            Ok((pipeline(t, (variant, settings), &[], hdr)?, 1))
        })?;
        Ok(())
    }

    fn images(&self, variant: ShaderVariant, settings: &RendererSettings) -> Vec<ImageRequest> {
        // Temporal anti-aliasing copies its resolved radiance back in; the accumulation
        // of path-traced frames, their mean.
        let resolved_into = if super::temporal_anti_aliasing::wanted(variant)
            || super::path_accumulation::wanted(variant, settings)
        {
            vk::ImageUsageFlags::TRANSFER_DST
        } else {
            vk::ImageUsageFlags::empty()
        };
        vec![ImageRequest::new(
            HDR,
            settings.hdr_format.vk(),
            vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_SRC
                | resolved_into,
        )]
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let (s, g, r) = (frame.slot, &frame.gbuffer, frame.shared);
        let read = BufferUse::FragmentStorageRead;
        let texel = ImageUse::FragmentSampled;
        let mut io = PassIo::new(self.name())
            .slot_set(frame.slot, &SET)
            .image(
                "gbuffer_base_color_metalness",
                g.base_color_metalness,
                texel,
            )
            .image(
                "gbuffer_normal_roughness_anisotropy",
                g.normal_roughness_anisotropy,
                texel,
            )
            .image("gbuffer_material_direction", g.material_direction, texel)
            .image(
                "gbuffer_depth",
                g.depth,
                if shades_surfaces_only(frame.variant) {
                    // Also the depth test's attachment, read-only.
                    ImageUse::DepthAttachmentTestAndSampled
                } else {
                    ImageUse::DepthFragmentSampled
                },
            )
            .buffer("materials", &frame.scene.gpu.materials, read);
        // The HDR image, or the frame's target where the output is folded in (with the
        // overlay drawn over it: its set declared last).
        io = if frame.output_folded {
            io.touches(frame.color, ImageUse::ColorAttachmentWrite)
        } else {
            io.touches(frame.hdr.into(), ImageUse::ColorAttachmentWrite)
        };
        // Every binding is written, every frame: a driver may read a bound set's
        // descriptors, used or not, and a binding left as an earlier frame wrote it
        // would name an image retired since. Absent targets and environments get
        // placeholders, which no barrier concerns (never written, never read).
        for (name, target) in [
            ("gbuffer_emissive", g.emissive),
            ("gbuffer_clearcoat", g.clearcoat),
            ("gbuffer_sheen", g.sheen),
            ("gbuffer_film", g.film),
            ("gbuffer_specular", g.specular),
            (
                "ambient_occlusion",
                frame.images.find(super::ambient_occlusion::IMAGE),
            ),
            (
                "ray_traced_occlusion",
                frame.images.find(super::ray_traced_occlusion::IMAGE),
            ),
            (
                "ray_traced_shadows",
                frame.images.find(super::ray_traced_shadows::IMAGE),
            ),
        ] {
            io = match target {
                Some(image) => io.image(name, image, texel),
                None => io.bind_image(
                    name,
                    r.absent_target.view(),
                    texel.state().layout,
                    vk::Sampler::null(),
                ),
            };
        }
        io = io.buffer_if(
            frame.cull_push.is_some(),
            "tile_lights",
            &s.tile_lights,
            read,
        );
        if r.no_scene.is_some() {
            io = if super::ray_traced_occlusion::traces(frame) || super::frame_reads_surfaces(frame)
            {
                super::traced::scene(io, frame)
            } else {
                super::traced::nothing(io, frame)
            };
            io = super::path_trace::bind_surfaces(io, frame).bind_buffer(
                "environment_importance",
                &frame
                    .environment
                    .unwrap_or(&frame.shared.no_environment)
                    .importance,
            );
            if let Some(deform) = frame
                .scene
                .gpu
                .deform
                .as_ref()
                .filter(|_| super::frame_reads_surfaces(frame))
            {
                // Rays read the deformed occluders' posed vertices where they hit them.
                io = io.uses_buffer(&deform.posed, BufferUse::FragmentStorageRead);
            }
        }
        io = lit_by(io, frame);
        if frame.output_folded {
            io = super::output::overlay_io(io, frame);
        }
        io
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let tested = shades_surfaces_only(frame.variant);
        let depth = tested.then(|| frame.gbuffer.depth.view());
        let set = frame.slot.set(&SET);
        if frame.output_folded {
            // Every pixel written: by the surfaces' or the background's pipeline (tested;
            // their tests pass every pixel once), or by the one pipeline. Then the
            // overlay over it.
            let format = frame.target.color.format;
            let lighting: &FullscreenPass = frame
                .registry
                .get(&folded_key(frame.variant, frame.settings, format))
                .expect("built: checked by folds_output");
            let push = frame
                .lighting_push
                .with_output(frame.inputs.exposure, frame.inputs.tone_mapping as u32);
            let push = bytemuck::bytes_of(&push);
            let target = (frame.target.color.view, frame.extent());
            begin_screen_rendering(frame.device, cmd, target, TargetStart::Written, depth);
            lighting.draw(frame.device, cmd, set, push);
            if !tested {
                super::output::record_overlay(frame, cmd);
                end_rendering(frame.device, cmd);
                return;
            }
            let encoding = OutputEncoding::of(format);
            background(frame, format, encoding).draw(frame.device, cmd, set, push);
            end_rendering(frame.device, cmd);
            if frame.slot.overlay_quad_count > 0 {
                // The overlay's pipeline has no depth attachment: a rendering of its own,
                // after the pixels above are written.
                colour_writes_before_colour_writes(frame.device, cmd);
                begin_screen_rendering(frame.device, cmd, target, TargetStart::Load, None);
                super::output::record_overlay(frame, cmd);
                end_rendering(frame.device, cmd);
            }
            return;
        }
        let hdr = frame.hdr;
        // The rendering starts from the background's radiance (nothing where the
        // environment is the background), alpha 0 marking it: what a pixel lighting.frag
        // discards keeps (one whose depth is not a number), and, in tested pipelines,
        // every background pixel unless the environment is the background (then drawn by
        // the background's pipeline).
        let [r, g, b, environment] = frame.lighting_push.background;
        let lighting: &FullscreenPass = frame
            .registry
            .get(&key(frame.variant, frame.settings))
            .expect("prepared for the frame's variant");
        let push = bytemuck::bytes_of(&frame.lighting_push);
        let start = TargetStart::Clear([r, g, b, 0.0]);
        begin_screen_rendering(frame.device, cmd, (hdr.view(), hdr.extent()), start, depth);
        lighting.draw(frame.device, cmd, set, push);
        if tested && environment != 0.0 {
            background(frame, frame.settings.hdr_format.vk(), None).draw(
                frame.device,
                cmd,
                set,
                push,
            );
        }
        end_rendering(frame.device, cmd);
    }
}

/// The background pipeline of `frame` into targets of `format` ([`background_key`]).
fn background<'a>(
    frame: &'a FrameContext<'_>,
    format: vk::Format,
    folded: Option<OutputEncoding>,
) -> &'a FullscreenPass {
    frame
        .registry
        .get(&background_key(frame.variant, format, folded))
        .expect("prepared with the frame's variant")
}

/// A barrier between the colour writes of one rendering and the colour reads and writes
/// of the next on the same target.
fn colour_writes_before_colour_writes(device: &combustion_vk::Device, cmd: vk::CommandBuffer) {
    let stage = vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT;
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(stage)
        .src_access_mask(vk::AccessFlags2::COLOR_ATTACHMENT_WRITE)
        .dst_stage_mask(stage)
        .dst_access_mask(
            vk::AccessFlags2::COLOR_ATTACHMENT_READ | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        )];
    // SAFETY: recording, outside a rendering.
    unsafe {
        device.raw().cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&barrier),
        );
    }
}
