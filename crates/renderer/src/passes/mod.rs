//! The frame as a list of passes. Each pass is a type (one file each) that says whether
//! it runs this frame, declares what it reads and writes once ([`PassIo`]: the
//! descriptor writes and the barriers both come from it), and records its commands.
//! [`FRAME`] lists them top to bottom; `frame.rs` keeps the frame slots and runs the
//! list: for each pass that runs, its declaration is applied, its barriers recorded
//! ([`crate::graph::ImageStates::transition`]), its commands recorded, and its end
//! stamped under its name ([`crate::PassTimings`]).
//!
//! Adding a pass: a file here with a unit struct implementing [`FramePass`] — its
//! descriptor set ([`SetDecl`], which makes its GLSL header, layout and each frame slot's
//! set), its push constants (`push_block!`, which makes its GLSL block), its pipelines
//! (`prepare`), its images (`images`) and, for a pass that runs only when asked, its
//! option ([`FramePass::option`]: the command line's flag and the define of the passes
//! that read its output) all in that file — and one line in [`FRAME`]
//! (docs/architecture.md walks through one).

mod ambient_occlusion;
pub(crate) mod auto_exposure;
mod back_faces;
mod behind;
pub(crate) mod bloom;
pub(crate) mod deform;
mod depth_copy;
mod forward;
mod gbuffer;
mod light_cull;
pub(crate) mod lighting;
pub(crate) mod output;
pub(crate) mod path_accumulation;
pub(crate) mod path_trace;
mod per_pixel;
mod ray_traced_occlusion;
pub(crate) mod ray_traced_reflections;
pub(crate) mod ray_traced_refraction;
mod ray_traced_shadows;
mod shadow_maps;
pub(crate) mod temporal_anti_aliasing;
mod traced;

use combustion_vk::vk;

use crate::bindings::SetDecl;
use crate::environment::GpuEnvironment;
use crate::error::RenderError;
use crate::gbuffer::GBufferTargets;
use crate::gpu_types::LightingPush;
use crate::graph::TrackedImage;
use crate::host::{FrameInputs, FrameTarget};
use crate::options::{OptionalPass, RendererSettings};
use crate::pass_io::PassIo;
use crate::pipelines::PipelineRegistry;
use crate::scene_upload::GpuScene;
use crate::shared::SharedResources;
use crate::slot::FrameSlot;
use crate::targets::{FrameImages, ImageRequest};
use crate::variant::ShaderVariant;
pub(crate) use light_cull::CullPush;
pub use path_trace::PATHS_PER_FRAME;

/// Everything a frame's passes read, gathered once per frame.
pub(crate) struct FrameContext<'a> {
    /// The frame's number, from 1 (unique among the renderer's frames: its marker).
    pub number: u64,
    /// The device the frame is recorded for.
    pub device: &'a std::sync::Arc<combustion_vk::Device>,
    /// Every pipeline built (the frame's were built before it: checked).
    pub registry: &'a PipelineRegistry,
    /// The placeholders, samplers, tables and overlay resources the passes bind.
    pub shared: &'a SharedResources,
    /// The renderer's settings (its G-buffer storage and HDR format, which its passes'
    /// pipelines are built for).
    pub settings: &'a RendererSettings,
    /// The frame slot's sets and buffers (its previous frame has completed).
    pub slot: &'a FrameSlot,
    /// The images the frame's passes asked for (`FramePass::images`), by name.
    pub images: FrameImages<'a>,
    /// The G-buffer among them.
    pub gbuffer: GBufferTargets<'a>,
    /// The HDR image among them (the lighting pass's).
    pub hdr: &'a combustion_vk::Image,
    /// The scene drawn.
    pub scene: &'a GpuScene,
    /// The environment lighting the frame (the frame's own, else the scene's).
    pub environment: Option<&'a GpuEnvironment>,
    /// The frame's camera, exposure, lights and overlay.
    pub inputs: &'a FrameInputs<'a>,
    /// The host's (or the renderer's own) colour target and optional depth image.
    pub target: &'a FrameTarget,
    /// The frame's shader variant (its passes' pipelines are built for it).
    pub variant: crate::ShaderVariant,
    /// The camera's view-projection at the target's aspect ratio.
    pub view_projection: glam::Mat4,
    /// The lighting pass's push constants (with the tile grid in frames that cull).
    pub lighting_push: LightingPush,
    /// The culling pass's push constants, in frames that cull their lights.
    pub cull_push: Option<CullPush>,
    /// The colour target as the barriers track it.
    pub color: TrackedImage,
    /// The host's depth image as the barriers track it, if the frame has one.
    pub host_depth: Option<TrackedImage>,
    /// Where the frame's objects are (the scene's own placement, or the frame's pose).
    pub placement: crate::placement::Placement<'a>,
    /// The jitter's removal, the previous camera and the history's state, in frames of
    /// temporal anti-aliasing.
    pub temporal: Option<temporal_anti_aliasing::TemporalFrame>,
    /// The previous frame's posed vertices, in frames of temporal anti-aliasing of
    /// scenes that deform.
    pub previous_vertices: Option<&'a combustion_vk::Buffer>,
    /// The frame's place in its history of path-traced frames averaged on the GPU, in
    /// frames that accumulate ([`RendererSettings::accumulate_paths`]).
    pub accumulation: Option<path_accumulation::AccumulationFrame>,
    /// Whether the frame's HDR image is read after its passes (copied back to the host:
    /// an offscreen frame's readback).
    pub hdr_read_after: bool,
    /// Whether the lighting pass writes the frame's target itself, the output pass not
    /// run ([`lighting::folds_output`], decided once the rest of the context is known).
    pub output_folded: bool,
    /// Whether an earlier frame of the renderer metered its exposure (its state is the
    /// one an auto-exposed frame adapts from; else the frame takes its target at once).
    pub metering_continues: bool,
    /// The cascades' and the local lights' shadow maps, in frames whose variant has
    /// shadows.
    pub shadow_maps: Option<(
        &'a crate::shadows::ShadowMaps,
        &'a crate::shadows::ShadowMaps,
    )>,
}

impl FrameContext<'_> {
    /// The frame's extent: the colour target's.
    pub fn extent(&self) -> vk::Extent2D {
        self.target.color.extent
    }
}

/// One pass of the frame.
pub(crate) trait FramePass: Sync {
    /// The pass's name: its timings' ([`crate::PassTimings`]) and its barriers'.
    fn name(&self) -> &'static str;

    /// The descriptor sets it binds (each frame slot holds one of each:
    /// [`FrameSlot::set`]).
    fn sets(&self) -> &'static [&'static SetDecl] {
        &[]
    }

    /// The option that switches it on, for a pass that runs only when asked (declared
    /// in its file; [`crate::optional_passes`] lists them). Default: none, the pass is
    /// not optional.
    fn option(&self) -> Option<&'static OptionalPass> {
        None
    }

    /// Whether frames of `variant` have it trace rays against the scene's acceleration
    /// structures (built at upload, on devices with ray queries, for scenes whose frames
    /// have such a pass). Default: no.
    fn traces(&self, _variant: ShaderVariant) -> bool {
        false
    }

    /// The headers it generates for its shaders (its push block's,
    /// [`crate::push::PushBlock::header`]), by path and text. Default: none.
    fn headers(&self) -> Vec<(String, String)> {
        Vec::new()
    }

    /// Builds, in `registry` under keys of its own, the pipelines it records frames of
    /// `variant` with (before any such frame; never while one is recorded). Default:
    /// none.
    fn prepare(
        &self,
        _variant: ShaderVariant,
        _settings: &RendererSettings,
        _registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        Ok(())
    }

    /// The images it creates for frames of `variant` (each made by the pool at the
    /// frame's size the first time a frame asks for it; other passes find them by name in
    /// `FrameContext::images`). Default: none.
    fn images(&self, _variant: ShaderVariant, _settings: &RendererSettings) -> Vec<ImageRequest> {
        Vec::new()
    }

    /// Whether the pass runs this frame (default: always).
    fn runs(&self, _frame: &FrameContext<'_>) -> bool {
        true
    }

    /// Whether its end is stamped under its own name; `false` counts its time with the
    /// next pass that is (light culling with the lighting it prepares).
    fn timed(&self) -> bool {
        true
    }

    /// What it reads and writes this frame, each resource once.
    fn io(&self, frame: &FrameContext<'_>) -> PassIo;

    /// Records its commands into `cmd`, its resources in the states `io` declared.
    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer);
}

/// The frame, top to bottom.
pub(crate) const FRAME: &[&dyn FramePass] = &[
    &deform::Deform,
    &shadow_maps::ShadowMaps,
    &gbuffer::GBuffer,
    &temporal_anti_aliasing::Motion,
    &temporal_anti_aliasing::MotionHistory,
    &light_cull::LightCull,
    &ambient_occlusion::AmbientOcclusion,
    &ray_traced_occlusion::RayTracedOcclusion,
    &ray_traced_shadows::RayTracedShadows,
    &path_trace::PASS, // likewise (--path-trace on): the lighting pass then traces paths
    &ray_traced_reflections::PASS, // likewise: the lighting pass traces reflections
    &ray_traced_refraction::PASS, // likewise: the forward pass traces refraction
    &lighting::Lighting,
    &back_faces::BackFaces,
    &behind::Behind,
    &forward::Forward,
    &path_accumulation::PathAccumulation,
    &path_accumulation::PathAccumulationCopy,
    &temporal_anti_aliasing::TemporalResolve,
    &temporal_anti_aliasing::TemporalCopy,
    &bloom::BloomChain,
    &bloom::BloomEnergy,
    &bloom::Bloom,
    &auto_exposure::Metering,
    &auto_exposure::Adaptation,
    &output::Output,
    &depth_copy::DepthCopy,
];

/// Has every pass of the frame build its pipelines for `variant` (once: the registry
/// knows the variants prepared), and the lighting pass its pipelines with the output
/// folded in for each target format prepared.
pub(crate) fn prepare_variant(
    registry: &mut PipelineRegistry,
    variant: ShaderVariant,
    settings: &RendererSettings,
) -> Result<(), RenderError> {
    if registry.is_prepared(&variant) {
        return Ok(());
    }
    for pass in FRAME {
        pass.prepare(variant, settings, registry)?;
    }
    for format in registry.output_formats() {
        lighting::prepare_folded(registry, variant, settings, format)?;
    }
    registry.mark_prepared(variant);
    Ok(())
}

/// Builds the output passes into targets of `format`, and the lighting pass's pipelines
/// with the output folded in for each variant prepared.
pub(crate) fn prepare_output(
    registry: &mut PipelineRegistry,
    format: vk::Format,
    settings: &RendererSettings,
) -> Result<(), RenderError> {
    output::prepare_output(registry, format)?;
    for variant in registry.prepared_variants() {
        lighting::prepare_folded(registry, variant, settings, format)?;
    }
    Ok(())
}

/// The passes between the lighting and the output pass in [`FRAME`]: those that read or
/// add to the radiance before it is shown.
pub(crate) fn between_lighting_and_output() -> impl Iterator<Item = &'static dyn FramePass> {
    let position = |name: &str| {
        FRAME
            .iter()
            .position(|pass| pass.name() == name)
            .expect("a pass of the frame")
    };
    FRAME[position(crate::PassTimings::LIGHTING) + 1..position(crate::PassTimings::OUTPUT)]
        .iter()
        .copied()
}

/// The images every pass of the frame asks for in frames of `variant`.
pub(crate) fn frame_images(
    variant: ShaderVariant,
    settings: &RendererSettings,
) -> Vec<ImageRequest> {
    FRAME
        .iter()
        .flat_map(|pass| pass.images(variant, settings))
        .collect()
}

/// Whether frames of `variant` read what their rays meet (the surface table,
/// `accel::TracedSurfaces`): path tracing, ray-traced reflections and refraction.
pub(crate) fn reads_surfaces(variant: ShaderVariant) -> bool {
    path_trace::wanted(variant)
        || ray_traced_reflections::wanted(variant)
        || ray_traced_refraction::wanted(variant)
}

/// Whether the frame reads what its rays meet ([`reads_surfaces`], its scene's
/// structures built).
pub(super) fn frame_reads_surfaces(frame: &FrameContext<'_>) -> bool {
    path_trace::traces(frame)
        || ray_traced_reflections::traces(frame)
        || ray_traced_refraction::traces(frame)
}

/// The optional passes of the frame ([`FramePass::option`]), in the frame's order.
pub(crate) fn optional_passes() -> impl Iterator<Item = &'static OptionalPass> {
    FRAME.iter().filter_map(|pass| pass.option())
}

/// Every descriptor set declared: those of `bindings::ALL` and those the frame's passes
/// declare in their own files, each once.
pub(crate) fn declared_sets() -> Vec<&'static SetDecl> {
    let mut sets: Vec<&'static SetDecl> = crate::bindings::ALL.to_vec();
    for decl in frame_sets() {
        if !sets.iter().any(|d| std::ptr::eq(*d, decl)) {
            sets.push(decl);
        }
    }
    sets
}

/// The headers generated for the shaders: each declared set's bindings and each pass's
/// own ([`FramePass::headers`]).
pub(crate) fn generated_headers() -> Vec<(String, String)> {
    declared_sets()
        .iter()
        .map(|decl| (decl.header_path(), decl.glsl()))
        .chain(FRAME.iter().flat_map(|pass| pass.headers()))
        .collect()
}

/// The descriptor sets the frame's passes bind, each once, in the frame's order.
pub(crate) fn frame_sets() -> Vec<&'static SetDecl> {
    let mut sets: Vec<&'static SetDecl> = Vec::new();
    for decl in FRAME.iter().flat_map(|pass| pass.sets()) {
        if !sets.iter().any(|d| d.name == decl.name) {
            sets.push(decl);
        }
    }
    sets
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sets (whose headers and layouts are found by name), generated headers, passes
    /// (whose timings are) and optional passes (whose flags are) are named once each,
    /// and every optional pass fits in a set of them.
    #[test]
    fn sets_headers_passes_and_options_are_named_once() {
        fn once(what: &str, names: &[String]) {
            for (i, name) in names.iter().enumerate() {
                assert!(!names[..i].contains(name), "two {what} named {name}");
            }
        }
        once(
            "sets",
            &declared_sets()
                .iter()
                .map(|d| d.name.to_owned())
                .collect::<Vec<_>>(),
        );
        once(
            "headers",
            &generated_headers()
                .into_iter()
                .map(|(path, _)| path)
                .collect::<Vec<_>>(),
        );
        once(
            "passes",
            &FRAME
                .iter()
                .map(|p| p.name().to_owned())
                .collect::<Vec<_>>(),
        );
        let options: Vec<&OptionalPass> = optional_passes().collect();
        once(
            "optional passes",
            &options
                .iter()
                .map(|p| p.name.to_owned())
                .collect::<Vec<_>>(),
        );
        assert!(options.len() <= crate::options::OptionalPasses::CAPACITY);
        for option in options {
            assert!(
                option
                    .name
                    .split('-')
                    .all(|w| !w.is_empty() && w.bytes().all(|b| b.is_ascii_lowercase())),
                "{}: lower-case words joined by -",
                option.name
            );
            assert_eq!(
                option.define,
                option.name.to_uppercase().replace('-', "_"),
                "an optional pass's define is its name's"
            );
        }
    }

    /// A file of the workspace, by its path from the workspace's root.
    fn workspace_file(path: &str) -> String {
        let full = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join(path);
        std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}", full.display()))
    }

    /// The entries (`&module::Pass`) of the first `FRAME` list in `text`.
    fn frame_entries(text: &str) -> Vec<String> {
        let start = text
            .find("const FRAME: &[&dyn FramePass] = &[")
            .expect("a FRAME list");
        let list = &text[start..];
        let end = list.find("];").expect("the list's end");
        list[..end]
            .lines()
            .skip(1)
            .filter_map(|line| {
                let entry = line.trim().split("//").next()?.trim().trim_end_matches(',');
                (!entry.is_empty()).then(|| entry.to_owned())
            })
            .collect()
    }

    /// The README's frame flow names the passes of `FRAME`, one line each, in its order
    /// (each line: the pass's name, two spaces or more, what it does).
    #[test]
    fn the_readme_frame_flow_is_the_pass_list() {
        let readme = workspace_file("README.md");
        let section = &readme[readme.find("## Frame flow").expect("a Frame flow section")..];
        let block = section.split("```").nth(1).expect("a block of passes");
        let listed: Vec<&str> = block
            .lines()
            .filter(|line| !line.trim().is_empty())
            .map(|line| line.split("  ").next().unwrap_or("").trim())
            .collect();
        let passes: Vec<&str> = FRAME.iter().map(|p| p.name()).collect();
        assert_eq!(
            listed, passes,
            "README.md's frame flow against passes::FRAME"
        );
    }

    /// docs/architecture.md shows `FRAME` as this file declares it, entry for entry.
    #[test]
    fn the_architecture_page_shows_the_pass_list() {
        let shown = frame_entries(&workspace_file("docs/architecture.md"));
        let declared = frame_entries(include_str!("mod.rs"));
        assert_eq!(declared.len(), FRAME.len());
        assert_eq!(
            shown, declared,
            "docs/architecture.md's FRAME against passes/mod.rs"
        );
    }
}
