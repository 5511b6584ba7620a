//! The deferred renderer of Combustion.
//!
//! A frame ([`Renderer::record`] into a host's command buffer and image, or
//! [`Renderer::render`], which submits, waits and reads back) runs the pass list,
//! `passes::FRAME`, top to bottom; a pass the frame does not need does not run:
//! deform (skinned and morphed vertices), shadow maps, the G-buffer ([`gbuffer`]: base
//! colour, metalness, normal, roughness, anisotropy, material, depth; coat, sheen and
//! film targets where the scene has them), light culling (tile lists of lights with a
//! range), lighting (`lighting.frag`: every light and the environment's split sum per
//! pixel, with the full Fresnel equations; the pipeline holds only the parts of the
//! material model the scene uses, [`LightingFeatures`]), back faces and behind (what
//! transmissive objects refract), forward (blended and transmissive objects), output
//! (`tonemap.frag`: exposure, the tone curve, the sRGB encoding, FXAA and the overlay,
//! into the frame's target by its format), and depth copy (into a host's depth image).
//! README.md's "Frame flow" lists them a line each; docs/architecture.md says where each
//! lives.
//!
//! Each pass declares what it reads and writes once ([`graph`]); the descriptor writes
//! and the barriers between passes and frames derive from those declarations in one
//! place. Frames in flight: each frame slot has its own descriptor sets, light buffer,
//! timestamp queries and retire list. GPU timestamps bracket each pass
//! ([`Frame::timings`], [`Renderer::last_completed_timings`]).

#![warn(missing_docs)]

pub mod bindings;
pub mod environment;
pub mod gbuffer;
pub mod gpu_types;
pub mod graph;
pub mod light_cull;
pub mod overlay;
pub mod reference;

mod accel;
mod buffers;
mod color;
mod commands;
mod compute;
mod deform;
mod environment_importance;
mod error;
mod exposure;
mod frame;
mod fullscreen;
mod host;
#[cfg(test)]
mod layers;
mod mesh_draw;
mod offscreen;
pub use offscreen::MAX_SUPERSAMPLE;
/// Temporal anti-aliasing's jitter ([`temporal_jitter`]: Halton (2, 3), repeating every
/// [`TEMPORAL_JITTER_PERIOD`] frames) and the share of each frame in the history.
pub use passes::temporal_anti_aliasing::{
    jitter as temporal_jitter, JITTER_PERIOD as TEMPORAL_JITTER_PERIOD, TEMPORAL_BLEND,
};
/// Paths per pixel in a path-traced frame (`--path-trace on`).
pub use passes::PATHS_PER_FRAME;
mod options;
mod pass_io;
mod passes;
mod pipelines;
mod placeholders;
mod placement;
mod push;
mod results;
mod retire;
mod scene_edit;
mod scene_upload;
mod shader_sources;
mod shadows;
mod shared;
mod slot;
#[cfg(test)]
mod spirv;
mod targets;
mod textures;
mod variant;

use std::sync::atomic::Ordering;
use std::sync::Arc;

use combustion_scene::Scene;
use combustion_vk::{vk, Device};

pub use color::{
    f16_to_f32, linear_to_srgb, tonemap_aces, tonemap_agx, tonemap_exponential, tonemap_pbr_neutral,
};
pub use environment::FrameEnvironment;
pub use error::{RenderError, TargetImageProblem};
pub use exposure::{
    ev100_of_exposure, exposure_of_ev100, metered_ev100, AutoExposure, MeteredExposure,
    PhysicalCamera, HISTOGRAM_BINS, METERED_LOG2_LUMINANCE, METER_CALIBRATION,
};
pub use host::{
    AntiAliasing, Background, ColorTarget, DepthTarget, FrameInputs, FrameTarget, OutputEncoding,
    ToneMapping, DEFAULT_BLOOM_INTENSITY, DISPLAY_FORMAT,
};
pub use light_cull::{LightCulling, MAX_CULLED_LIGHTS, TILE_SIZE};
pub use options::{
    BaseColorStorage, DebugView, Distribution, FresnelModel, GBufferStorage, HdrFormat, Masking,
    MeasurementFloor, OptionalPass, OptionalPasses, PassChoice, Readback, RendererSettings,
    ShadingOptions, SurfaceStorage, ENVIRONMENT_SAMPLE_COUNTS, MAX_FRAMES_IN_FLIGHT, PATH_DEPTHS,
    TARGETS_KEPT_FOR_FRAMES,
};
pub use overlay::{Corner, OverlayImage, OverlayPanel};
pub use results::{Frame, PassTime, PassTimings, RendererStats};
pub use scene_edit::{EditError, MaterialId, MeshId, ObjectId, SceneEditor};
pub use scene_upload::{GpuScene, SceneEditReport};
pub use shadows::{
    cascade_splits, directional_cascades, local_texel_per_metre, shadow_distance, shadowed_lights,
    Cascade, ShadowFilter, ShadowKinds, ShadowSettings, ShadowShader, CASCADE_BLEND_BAND,
    LAYER_CUBE_FACE, LAYER_PERSPECTIVE, MAX_CASCADES, MAX_SHADOWED_LIGHTS, MAX_SHADOW_LAYERS,
    MAX_SPOT_CONE_ONE_LAYER, MIN_SHADOW_MAP_SIZE, PCF_RADIUS_TEXELS, SHADOW_MAP_FORMAT,
    SPLIT_LOGARITHMIC_WEIGHT,
};
pub use variant::{LightingFeatures, ShaderVariant};

/// The passes a frame runs only when asked ([`ShadingOptions::optional_passes`]), in the
/// frame's order.
pub fn optional_passes() -> impl Iterator<Item = &'static OptionalPass> {
    passes::optional_passes()
}

/// The optional pass named `name` (`ambient-occlusion`), if there is one.
pub fn optional_pass(name: &str) -> Option<&'static OptionalPass> {
    passes::optional_passes().find(|pass| pass.name == name)
}

/// `options` without the optional passes `device` cannot run (those that trace rays, on
/// a device without ray queries: the raster paths, never an error), each said once as a
/// warning.
fn usable_options(device: &Device, options: ShadingOptions) -> ShadingOptions {
    if device.ray_queries() {
        return options;
    }
    for pass in options
        .optional_passes
        .iter()
        .filter(|p| p.needs_ray_queries)
    {
        let option = pass.asked_as();
        log::warn!(
            "{} ({option}): the device has no ray queries; frames are rendered without it",
            pass.name
        );
    }
    ShadingOptions {
        optional_passes: options.optional_passes.without_ray_queries(),
        ..options
    }
}

/// The deferred renderer. One per device; renders [`GpuScene`]s at any size, into its
/// own images ([`Renderer::render`]) or into a host's command buffer and image
/// ([`Renderer::record`]), with frames in flight.
///
/// Pipelines are built by [`Renderer::new`], [`Renderer::upload`],
/// [`Renderer::edit_scene`], [`Renderer::set_shading`], [`Renderer::prepare`] and
/// [`Renderer::prepare_output`], never while a frame is recorded. Resources it replaces (targets of another size, an
/// edited scene's old buffers, a dropped [`GpuScene`] or [`FrameEnvironment`]) wait in
/// a retire list until the frames recorded before have completed.
///
/// Teardown: dropping it waits for its own submissions ([`Renderer::render`],
/// [`Renderer::submit_offscreen`]) and, on a device it created, for the device to be
/// idle; on a host's device that it recorded frames for, for the host's queue to drain
/// (frames still in flight complete before anything they read is freed;
/// docs/integration.md, "Teardown and errors").
pub struct Renderer {
    // Field order is drop order: everything below holds the device alive.
    /// Combustion's own submissions (render, bench), created on first use.
    offscreen: Option<offscreen::Offscreen>,
    slots: Vec<slot::FrameSlot>,
    /// The frames' images (G-buffer, HDR, …), each kept while frames of its size use it.
    images: targets::ImagePool,
    /// Every pipeline built, and what builds them.
    pipelines: pipelines::PipelineRegistry,
    /// Placeholders, samplers, tables and the overlay's font and image, which the
    /// frame's passes read.
    shared: shared::SharedResources,
    /// What this renderer's [`GpuScene`]s hand over when dropped, moved to the retire
    /// list of the frame recorded last when the next frame begins.
    retire_queue: Arc<retire::RetireQueue>,
    states: graph::ImageStates,
    /// The settings, their shading options the current ones ([`Renderer::set_shading`]).
    settings: RendererSettings,
    /// When frames cull their lights ([`Renderer::set_light_culling`]).
    light_culling: LightCulling,
    /// The cascades' shadow maps, made by the first frame with shadows and grown as
    /// frames need.
    shadow_maps: Option<shadows::ShadowMaps>,
    /// The spot and point lights' shadow maps, likewise.
    local_shadow_maps: Option<shadows::ShadowMaps>,
    /// Frames recorded so far.
    frame_number: u64,
    /// The slot of the frame recorded last: what is replaced now is retired to it, and
    /// freed when that slot is reused (its frame, and every earlier one, complete).
    last_slot: Option<usize>,
    last_timings: Option<PassTimings>,
    /// What the latest completed frame that metered its exposure used.
    last_metered: Option<MeteredExposure>,
    /// Temporal anti-aliasing's history between frames (the previous camera and
    /// transforms, the jitter's index).
    temporal: passes::temporal_anti_aliasing::TemporalState,
    /// The history of path-traced frames averaged on the GPU
    /// ([`RendererSettings::accumulate_paths`]).
    accumulation: passes::path_accumulation::AccumulationState,
    /// Whether a frame has metered its exposure since the renderer was made (or its
    /// unrun frames forgotten): the state the next metered frame adapts from.
    metering_continues: bool,
    stats: RendererStats,
    /// Timings of completed frames not yet taken ([`Renderer::take_completed_timings`]).
    completed_timings: std::collections::VecDeque<PassTimings>,
    device: Arc<Device>,
}

impl Renderer {
    /// Compiles the shaders and builds the pipelines of scenes without special
    /// features, and the output pass for [`DISPLAY_FORMAT`].
    pub fn new(device: Arc<Device>, settings: RendererSettings) -> Result<Self, RenderError> {
        Self::with_pipeline_cache(device, settings, &[])
    }

    /// As [`Renderer::new`], with a pipeline cache primed from `cache_data` (what
    /// [`Renderer::pipeline_cache_data`] returned on an earlier run; data from another
    /// driver is ignored).
    pub fn with_pipeline_cache(
        device: Arc<Device>,
        settings: RendererSettings,
        cache_data: &[u8],
    ) -> Result<Self, RenderError> {
        settings.validate(&device)?;
        let settings = RendererSettings {
            shading: usable_options(&device, settings.shading),
            ..settings
        };
        let pipelines = pipelines::PipelineRegistry::new(
            &device,
            cache_data,
            &passes::declared_sets(),
            passes::generated_headers(),
        )?;
        let shared = shared::SharedResources::new(&device, &settings)?;
        let slots = (0..settings.frames_in_flight)
            .enumerate()
            .map(|(index, _)| {
                slot::FrameSlot::new(&device, &pipelines.layouts, &passes::frame_sets(), index)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut renderer = Self {
            offscreen: None,
            slots,
            images: targets::ImagePool::default(),
            pipelines,
            shared,
            retire_queue: retire::RetireQueue::new(),
            states: graph::ImageStates::default(),
            settings,
            light_culling: LightCulling::Auto,
            shadow_maps: None,
            local_shadow_maps: None,
            frame_number: 0,
            last_slot: None,
            last_timings: None,
            last_metered: None,
            metering_continues: false,
            temporal: Default::default(),
            accumulation: Default::default(),
            completed_timings: std::collections::VecDeque::new(),
            stats: RendererStats::default(),
            device,
        };
        // The plain variant is built now, so shader errors surface at construction.
        renderer.prepare_variant(renderer.variant_of(ShaderVariant::default()))?;
        renderer.prepare_output(DISPLAY_FORMAT)?;
        Ok(renderer)
    }

    /// The device the renderer was created on.
    pub fn device(&self) -> &Arc<Device> {
        &self.device
    }

    /// The settings, with the shading options [`Renderer::set_shading`] chose last.
    pub fn settings(&self) -> RendererSettings {
        self.settings
    }

    /// The pipeline cache's contents, to save and pass to
    /// [`Renderer::with_pipeline_cache`] on the next run.
    pub fn pipeline_cache_data(&self) -> Result<Vec<u8>, RenderError> {
        Ok(self.pipelines.cache.data()?)
    }

    /// Validates and uploads a scene, and builds the pipelines it needs (never inside a
    /// frame's recording). A scene with an environment has it baked here, waiting for
    /// the GPU.
    ///
    /// # Errors
    /// [`RenderError::Scene`] if the scene fails validation; [`RenderError::TooLarge`]
    /// for an image beyond the device's 2D limit or a mesh of 2³² indices or more;
    /// [`RenderError::EnvironmentUnsupported`] for an environment the device cannot
    /// bake; [`RenderError::Vulkan`] if a pipeline, buffer or image cannot be made.
    pub fn upload(&mut self, scene: &Scene) -> Result<GpuScene, RenderError> {
        self.upload_owned(scene.clone())
    }

    /// [`Renderer::upload`], keeping `scene` itself as the uploaded scene
    /// ([`GpuScene::scene`]) rather than a copy of it: a caller done with its scene
    /// does not hold it twice (a million objects are 192 MB, a mesh its vertices).
    ///
    /// # Errors
    /// As [`Renderer::upload`].
    pub fn upload_owned(&mut self, scene: Scene) -> Result<GpuScene, RenderError> {
        scene.validate()?;
        let scene_ref = &scene;
        self.prepare_variant(self.variant_of(scene_upload::scene_variant(scene_ref)))?;
        self.prepare_deform(scene_ref)?;
        let environment = self.bake_scene_environment(scene_ref)?;
        let gpu_scene = GpuScene::new(
            &self.device,
            scene,
            self.pipelines.layouts.of(&bindings::MATERIAL_TEXTURES),
            environment,
            self.retire_queue.clone(),
        )?;
        self.prepare_structures(&gpu_scene, self.variant_of(gpu_scene.variant))?;
        Ok(gpu_scene)
    }

    /// The posed vertices of `scene`'s deformed objects (morphed, skinned) as the last
    /// frame of it left them: per deformed object, its index and its vertices as the
    /// passes that draw it read them (position, normal, tangent and sign, uv; a skinned
    /// object's in world space, a morphed one's in its own). Waits until the device is
    /// idle: for tests and tools (it is how the GPU's posing is checked against the f64
    /// pose), never in a frame. Empty for a scene without deformed objects.
    ///
    /// # Errors
    /// [`RenderError::SceneOfAnotherRenderer`]; [`RenderError::Vulkan`] when the wait, the
    /// copy or the readback buffer fails.
    pub fn read_posed_vertices(
        &mut self,
        scene: &GpuScene,
    ) -> Result<Vec<(usize, Vec<gpu_types::GpuVertex>)>, RenderError> {
        if !scene.belongs_to(&self.retire_queue) {
            return Err(RenderError::SceneOfAnotherRenderer);
        }
        let Some(deform) = &scene.gpu.deform else {
            return Ok(Vec::new());
        };
        self.device.wait_idle()?;
        let size = deform.posed.size();
        let readback = combustion_vk::Buffer::new(
            &self.device,
            "posed vertices readback",
            size,
            vk::BufferUsageFlags::TRANSFER_DST,
            combustion_vk::gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        let mut once = combustion_vk::OneShot::new(&self.device)?;
        let cmd = once.begin()?;
        let raw = self.device.raw();
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .src_access_mask(vk::AccessFlags2::MEMORY_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::COPY)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)];
        let to_host = [combustion_vk::copy_to_host_barrier()];
        // SAFETY: recording state; the device is idle, both buffers live past the wait.
        unsafe {
            raw.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&barrier),
            );
            raw.cmd_copy_buffer(
                cmd,
                deform.posed.raw(),
                readback.raw(),
                &[vk::BufferCopy {
                    src_offset: 0,
                    dst_offset: 0,
                    size,
                }],
            );
            raw.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&to_host),
            );
        }
        once.submit_and_wait()?;
        let bytes = readback.mapped()?;
        let vertex = std::mem::size_of::<gpu_types::GpuVertex>();
        Ok(deform
            .objects
            .iter()
            .map(|object| {
                let start = deform.posed_offsets[object.object()].unwrap_or(0) as usize;
                let count = object.push.vertices[1] as usize;
                let vertices = bytes[start..start + count * vertex]
                    .chunks_exact(vertex)
                    .map(bytemuck::pod_read_unaligned)
                    .collect();
                (object.object(), vertices)
            })
            .collect())
    }

    /// Builds the deform pass's pipeline if `scene` has deformed objects and it is not
    /// built yet (at upload and edits: never in a frame).
    fn prepare_deform(&mut self, scene: &Scene) -> Result<(), RenderError> {
        let deformed = (0..scene.objects.len()).any(|i| {
            let (skinned, morphed) = deform::deformation(scene, i);
            skinned || morphed
        });
        if deformed {
            passes::deform::prepare(&mut self.pipelines)?;
        }
        Ok(())
    }

    /// Bakes `environment` for `scene`'s materials, to light its frames in place of its
    /// own through [`FrameInputs::environment`] (a per-frame or per-view environment
    /// changed without a scene edit), and builds the pipelines such frames use (with
    /// the current shading options; [`Renderer::set_shading`] keeps them built when the
    /// options change, and so do edits). Waits for the GPU (0.4–1.6 s on lavapipe): an upload
    /// step, never inside a frame. On error nothing changes.
    ///
    /// # Errors
    /// [`RenderError::SceneOfAnotherRenderer`] for a scene another renderer uploaded;
    /// [`RenderError::Scene`] for an invalid environment; otherwise as
    /// [`Renderer::upload`]'s bake.
    pub fn bake_environment(
        &mut self,
        scene: &GpuScene,
        environment: &combustion_scene::Environment,
    ) -> Result<FrameEnvironment, RenderError> {
        if !scene.belongs_to(&self.retire_queue) {
            return Err(RenderError::SceneOfAnotherRenderer);
        }
        environment.validate()?;
        self.prepare_variant(self.variant_of(scene.lit_variant))?;
        let baked = self.bake(environment, scene.scene())?;
        scene.frame_environments.store(true, Ordering::Relaxed);
        Ok(FrameEnvironment::new(
            baked,
            scene.bake_materials.clone(),
            self.retire_queue.clone(),
        ))
    }

    /// The scene's environment baked for its materials (None without one).
    fn bake_scene_environment(
        &mut self,
        scene: &Scene,
    ) -> Result<Option<environment::GpuEnvironment>, RenderError> {
        match &scene.environment {
            Some(source) => self.bake(source, scene).map(Some),
            None => Ok(None),
        }
    }

    /// `source` baked for `scene`'s materials.
    fn bake(
        &mut self,
        source: &combustion_scene::Environment,
        scene: &Scene,
    ) -> Result<environment::GpuEnvironment, RenderError> {
        let baker = self.pipelines.environment_baker()?;
        let baked = baker.bake(&self.device, source, scene)?;
        self.stats.environment_bakes += 1;
        self.stats.environment_cubes_from_cache += u64::from(baked.cubes_from_cache);
        log::info!(
            "environment {} baked in {:.1} ms{}",
            source.name(),
            baked.bake_ms,
            if baked.cubes_from_cache {
                " (its cubes from the bake cache)"
            } else {
                ""
            }
        );
        Ok(baked)
    }

    /// Edits an uploaded scene between frames without uploading it again: `edit` changes
    /// a copy of its CPU scene by index (add, remove or change objects, materials,
    /// lights, meshes, textures); only what changed is uploaded (see
    /// [`SceneEditReport`]), the replaced parts are retired until the frames in flight
    /// that read them have completed, and a shader feature the edit needs is built now,
    /// ahead of the next frame. On error (an invalid edit) the scene is unchanged.
    /// [`Renderer::try_edit_scene`] edits by stable handle.
    pub fn edit_scene(
        &mut self,
        scene: &mut GpuScene,
        edit: impl FnOnce(&mut Scene),
    ) -> Result<SceneEditReport, RenderError> {
        self.try_edit_scene(scene, |editor| {
            edit(editor.scene_mut());
            Ok(())
        })
        .map(|((), report)| report)
    }

    /// As [`Renderer::edit_scene`], with the edit made through a [`SceneEditor`]: items
    /// added and removed by handle ([`ObjectId`], [`MaterialId`], [`MeshId`]: stable
    /// across edits; [`GpuScene::object_ids`] and its siblings give those of the items
    /// uploaded), and changes by index through [`SceneEditor::scene_mut`]. `edit` may
    /// refuse ([`EditError`]): the scene is then unchanged. Returns what `edit` returned
    /// (the handles it made, say) and what was rebuilt.
    pub fn try_edit_scene<T>(
        &mut self,
        scene: &mut GpuScene,
        edit: impl FnOnce(&mut SceneEditor) -> Result<T, EditError>,
    ) -> Result<(T, SceneEditReport), RenderError> {
        if !scene.belongs_to(&self.retire_queue) {
            return Err(RenderError::SceneOfAnotherRenderer);
        }
        let mut editor = SceneEditor::new(scene.scene().clone(), scene.ids.clone());
        let value = edit(&mut editor)?;
        let (next, ids) = editor.finish();
        next.validate()?;
        // The pipelines first: if they cannot be built, the scene stays as it was.
        let before = self.pipelines.built;
        self.prepare_variant(self.variant_of(scene_upload::scene_variant(&next)))?;
        if scene.frame_environments.load(Ordering::Relaxed) {
            self.prepare_variant(self.variant_of(scene_upload::lit_scene_variant(&next)))?;
        }
        self.prepare_deform(&next)?;
        let pipelines_built = self.pipelines.built - before;
        // The environment's tables follow the materials: bake again when the edit
        // changes what the bake reads — the environment or the material table (optics
        // and the outside medium, not names, textures, lights, objects or the camera) —
        // before anything of the scene is replaced, so a failed bake leaves it as it was.
        // (The old table as the bake read it is kept with the scene.)
        let environment = if !same_environment(&next.environment, &scene.scene().environment)
            || bytemuck::cast_slice::<_, u8>(&gpu_types::material_table(&next, &[]))
                != scene.bake_materials.as_slice()
        {
            Some(self.bake_scene_environment(&next)?)
        } else {
            None
        };
        let (report, retired) = scene.edited(
            &self.device,
            next,
            ids,
            self.pipelines.layouts.of(&bindings::MATERIAL_TEXTURES),
            environment,
        )?;
        for part in retired {
            self.retire_boxed(part);
        }
        Ok((
            value,
            SceneEditReport {
                pipelines_built,
                ..report
            },
        ))
    }

    /// Keeps `resource` (a buffer, image or anything holding them) alive until the
    /// frames recorded so far have completed, then drops it. A [`GpuScene`] needs no
    /// call: dropping it retires its resources this way.
    pub fn retire(&mut self, resource: impl std::any::Any + Send) {
        self.retire_boxed(Box::new(resource));
    }

    fn retire_boxed(&mut self, resource: retire::Retired) {
        match self.last_slot {
            Some(slot) => self.slots[slot].retire(resource),
            // No frame was ever recorded: nothing can be using it.
            None => drop(resource),
        }
    }

    /// The scene's variant with the renderer's shading options applied.
    pub(crate) fn variant_of(&self, scene_variant: ShaderVariant) -> ShaderVariant {
        self.settings.shading.variant(scene_variant)
    }

    /// Whether a frame of `scene` with `variant` has the acceleration structures its
    /// passes trace (or traces nothing).
    pub(crate) fn structures_ready(&self, scene: &GpuScene, variant: ShaderVariant) -> bool {
        if !(self.device.ray_queries() && passes::FRAME.iter().any(|p| p.traces(variant))) {
            return true;
        }
        scene.gpu.structures.get().is_some_and(|structures| {
            !passes::reads_surfaces(variant) || structures.surfaces.get().is_some()
        })
    }

    /// Builds `scene`'s acceleration structures if frames of `variant` trace rays (on a
    /// device with ray queries) and they are not built yet (waits for the build: never
    /// in a frame).
    pub(crate) fn prepare_structures(
        &mut self,
        scene: &GpuScene,
        variant: ShaderVariant,
    ) -> Result<(), RenderError> {
        if !self.structures_ready(scene, variant) {
            if scene.gpu.structures.get().is_none() {
                let structures = accel::SceneStructure::new(
                    &self.device,
                    scene.scene(),
                    scene.gpu.deform.as_ref(),
                    self.settings.frames_in_flight,
                )?;
                self.stats.acceleration_structure_bytes += structures.bytes();
                // Set once: found unset, and only `&mut self` sets it.
                let _ = scene.gpu.structures.set(structures);
            }
            if passes::reads_surfaces(variant) {
                if let Some(structures) = scene.gpu.structures.get() {
                    self.stats.acceleration_structure_bytes +=
                        structures.prepare_surfaces(&self.device, scene.scene())?;
                }
            }
        }
        Ok(())
    }

    /// Builds the pipelines of `variant` if they are not built yet, and the sheen's
    /// albedo table for the first variant with sheen.
    pub(crate) fn prepare_variant(&mut self, variant: ShaderVariant) -> Result<(), RenderError> {
        if variant.sheen {
            if let Some(placeholder) = self.shared.make_sheen_table(&self.device)? {
                self.retire(placeholder);
            }
        }
        passes::prepare_variant(&mut self.pipelines, variant, &self.settings)
    }

    /// Builds the output pass (and the overlay over it) for targets of `format`, so that
    /// [`Renderer::record`] can render into them. [`DISPLAY_FORMAT`] is prepared by
    /// [`Renderer::new`]. Formats: see [`OutputEncoding::of`].
    pub fn prepare_output(&mut self, format: vk::Format) -> Result<(), RenderError> {
        passes::prepare_output(&mut self.pipelines, format, &self.settings)
    }

    /// Prepares `format` ([`Renderer::prepare_output`]) and what frames of
    /// `anti_aliasing` need there: for [`AntiAliasing::Fxaa`] into a display format, the
    /// output pipeline with FXAA (linear formats get no anti-aliasing). Call it before
    /// recording such frames (their recording never compiles a shader); the offscreen
    /// paths ([`Renderer::render_with`], [`Renderer::submit_offscreen_with`]) call it.
    ///
    /// # Errors
    /// As [`Renderer::prepare_output`]; [`RenderError::Vulkan`] if the shader does not
    /// compile or the pipeline cannot be built.
    pub fn prepare_anti_aliasing(
        &mut self,
        format: vk::Format,
        anti_aliasing: AntiAliasing,
    ) -> Result<(), RenderError> {
        self.prepare_output(format)?;
        passes::output::prepare_anti_aliasing(&mut self.pipelines, format, anti_aliasing)
    }

    /// Builds the pipelines `scene` needs with the current shading options, if they are
    /// not built yet: for a scene left out of [`Renderer::set_shading`]'s list (uploads
    /// and edits build their own). Frames lit by a [`FrameEnvironment`] baked for the
    /// scene get theirs too.
    pub fn prepare(&mut self, scene: &GpuScene) -> Result<(), RenderError> {
        self.prepare_variant(self.variant_of(scene.variant))?;
        self.prepare_structures(scene, self.variant_of(scene.variant))?;
        if scene.frame_environments.load(Ordering::Relaxed) {
            self.prepare_variant(self.variant_of(scene.lit_variant))?;
        }
        Ok(())
    }

    /// Switches to `options` from the next frame on, all at once: first builds every
    /// pipeline the new options need for `scenes` (each scene's own, and those of frames
    /// lit by a [`crate::FrameEnvironment`] baked for it) and, when energy compensation
    /// is turned on for the first time, its table; then switches. The scenes listed need
    /// no [`Renderer::prepare`] before their next frame; a scene left out needs one (its
    /// frames fail with [`RenderError::VariantNotPrepared`] until then), and scenes
    /// uploaded or edited later get theirs then.
    ///
    /// # Errors
    /// [`RenderError::SceneOfAnotherRenderer`] for a scene another renderer uploaded;
    /// [`RenderError::Vulkan`] if a pipeline or the table cannot be built. On error the
    /// options stay as they were, and so do the frames rendered with them (pipelines
    /// already built for the new options are kept, unused until asked for).
    pub fn set_shading(
        &mut self,
        options: ShadingOptions,
        scenes: &[&GpuScene],
    ) -> Result<(), RenderError> {
        if let Some(shadows) = &options.shadows {
            shadows.validate(self.device.limits().max_image_dimension2_d)?;
        }
        options.validate_environment_samples()?;
        let options = usable_options(&self.device, options);
        for scene in scenes {
            if !scene.belongs_to(&self.retire_queue) {
                return Err(RenderError::SceneOfAnotherRenderer);
            }
            self.prepare_variant(options.variant(scene.variant))?;
            self.prepare_structures(scene, options.variant(scene.variant))?;
            if scene.frame_environments.load(Ordering::Relaxed) {
                self.prepare_variant(options.variant(scene.lit_variant))?;
            }
        }
        if options.energy_compensation {
            if let Some(placeholder) = self.shared.make_energy_table(&self.device)? {
                self.retire(placeholder);
            }
        }
        self.settings.shading = options;
        Ok(())
    }

    /// The shading options frames are rendered with ([`Renderer::set_shading`]).
    pub fn shading(&self) -> ShadingOptions {
        self.settings.shading
    }

    /// When frames cull their lights (tiled light lists, [`LightCulling`]); from the next
    /// frame on. Culling never changes a pixel: it leaves out only lights whose range
    /// window is exactly 0 over a whole tile.
    pub fn set_light_culling(&mut self, culling: LightCulling) {
        self.light_culling = culling;
    }

    /// When frames cull their lights ([`Renderer::set_light_culling`]).
    pub fn light_culling(&self) -> LightCulling {
        self.light_culling
    }

    /// The lighting features of the pipeline `scene`'s frames use now.
    pub fn lighting_features(&self, scene: &GpuScene) -> LightingFeatures {
        self.variant_of(scene.variant).features
    }
    /// Shows `image` over the frames recorded from now on (under their text panels, at
    /// the top-left, one texel a pixel), or no image. The previous image is kept until
    /// the frames in flight that show it have completed.
    pub fn set_overlay_image(&mut self, image: Option<&OverlayImage>) -> Result<(), RenderError> {
        let next = match image {
            Some(i) => {
                self.check_size(i.width, i.height)?;
                let texels = u64::from(i.width) * u64::from(i.height);
                if i.rgba.len() as u64 != texels {
                    return Err(RenderError::Overlay(format!(
                        "an overlay image of {}x{} needs {texels} texels, not {}",
                        i.width,
                        i.height,
                        i.rgba.len()
                    )));
                }
                let range = u64::from(self.device.limits().max_storage_buffer_range);
                if texels * 4 > range {
                    return Err(RenderError::Overlay(format!(
                        "an overlay image of {}x{} takes {} bytes; this device reads at most {range} from one buffer",
                        i.width,
                        i.height,
                        texels * 4
                    )));
                }
                Some((i.rgba.as_slice(), [i.width, i.height]))
            }
            None => None,
        };
        let old = self.shared.replace_overlay_image(&self.device, next)?;
        self.retire(old);
        Ok(())
    }

    /// The overlay's font (its atlas and text layout), e.g. to check a frame's overlay.
    pub fn overlay_font(&self) -> &overlay::OverlayFont {
        &self.shared.overlay_font
    }

    /// Builds the auto exposure's passes, so that frames whose inputs meter their
    /// exposure ([`FrameInputs::auto_exposure`]) can be recorded (their recording never
    /// compiles a shader); the offscreen paths call it.
    ///
    /// # Errors
    /// [`RenderError::Vulkan`] if a shader does not compile or a pipeline cannot be
    /// built.
    pub fn prepare_auto_exposure(&mut self) -> Result<(), RenderError> {
        passes::auto_exposure::prepare(&mut self.pipelines)
    }

    /// Paths a pixel the mean of the last frame recorded holds, where path-traced frames
    /// are averaged on the GPU ([`RendererSettings::accumulate_paths`]): the frames of
    /// its history × [`PATHS_PER_FRAME`]; 0 where the last frame did not accumulate.
    pub fn accumulated_paths(&self) -> u64 {
        self.accumulation.paths()
    }

    /// What the most recent completed frame that metered its exposure metered and used
    /// (read when its frame slot is reused, or at once for [`Renderer::render_with`]):
    /// the exposure, its EV100, the target and the histogram.
    pub fn last_metered_exposure(&self) -> Option<&MeteredExposure> {
        self.last_metered.as_ref()
    }

    /// The exposure the latest completed frame of `inputs` was shown at: the one it
    /// metered where `inputs` meter it, else `inputs.exposure` (what a CPU tone map of
    /// its radiance, as supersampling and accumulation make, applies).
    pub fn exposure_shown(&self, inputs: &FrameInputs<'_>) -> f32 {
        match (&inputs.auto_exposure, &self.last_metered) {
            (Some(_), Some(metered)) => metered.exposure,
            _ => inputs.exposure,
        }
    }

    /// The GPU times of the most recent frame known to have completed (read when its
    /// frame slot is reused; at once for [`Renderer::render`]).
    pub fn last_completed_timings(&self) -> Option<PassTimings> {
        self.last_timings.clone()
    }

    /// What this renderer has built so far.
    pub fn stats(&self) -> RendererStats {
        RendererStats {
            frames: self.frame_number,
            shaders_compiled: self.pipelines.compiler.compilations(),
            pipelines_built: self.pipelines.built,
            shaders_from_cache: self.pipelines.compiler.cache_hits(),
            shader_compile_micros: u64::try_from(
                self.pipelines.compiler.compile_time().as_micros(),
            )
            .unwrap_or(u64::MAX),
            ..self.stats
        }
    }

    /// The GPU times of every completed frame since the last call (oldest first; at
    /// most the last 1024 are kept).
    pub fn take_completed_timings(&mut self) -> Vec<PassTimings> {
        self.completed_timings.drain(..).collect()
    }

    /// The host has waited for every frame it submitted (e.g. at exit, before a pause, or
    /// after an error between `record` and its submission): collects the timings of
    /// every slot's last frame, so that [`Renderer::take_completed_timings`] has them
    /// all. Every slot is free afterwards. A frame recorded but never submitted (its
    /// end-of-frame marker unwritten) is forgotten with its work: its timings, the
    /// layouts it would have left images in and the shadow maps it would have rendered
    /// (the next frames render them again).
    pub fn frames_completed(&mut self) -> Result<(), RenderError> {
        let count = self.slots.len();
        let first = self.last_slot.map_or(0, |last| (last + 1) % count);
        let mut abandoned = false;
        for i in 0..count {
            let slot = (first + i) % count;
            if self.collect_timings(slot)? == results::SlotFrame::Pending {
                // The host's word: nothing is running, so this frame never ran.
                self.slots[slot].stamped.clear();
                self.slots[slot].recorded = 0;
                abandoned = true;
            }
        }
        if abandoned {
            self.forget_abandoned_frames();
        }
        Ok(())
    }

    /// Forgets what frames recorded but never run would have done on the GPU: the
    /// states the barriers believe images are in (every image starts again from
    /// `UNDEFINED`: each is written before it is read in a frame, the shadow maps once
    /// rendered again) and the shadow maps' contents.
    pub(crate) fn forget_abandoned_frames(&mut self) {
        self.states = graph::ImageStates::default();
        // The exposure state may be one no frame wrote: the next metered frame starts
        // from its own target; likewise the temporal history.
        self.metering_continues = false;
        self.temporal.forget();
        self.accumulation.forget();
        for maps in [&mut self.shadow_maps, &mut self.local_shadow_maps]
            .into_iter()
            .flatten()
        {
            maps.contents = None;
        }
        if let Some(offscreen) = &mut self.offscreen {
            offscreen.forget_display_states();
        }
    }

    /// Reads the timings of `slot`'s last frame once its end-of-frame marker says it
    /// has completed (never waits, never asks the driver: the frame copied them beside
    /// its marker); [`results::SlotFrame::Pending`] while it has not.
    pub(crate) fn collect_timings(
        &mut self,
        slot: usize,
    ) -> Result<results::SlotFrame, RenderError> {
        let s = &mut self.slots[slot];
        if !s.is_free() {
            return Ok(results::SlotFrame::Pending);
        }
        if std::mem::take(&mut s.metered) && s.recorded != 0 {
            self.last_metered = s.completed_exposure();
        }
        let s = &mut self.slots[slot];
        let Some(t) = s.timestamps.as_ref().filter(|_| !s.stamped.is_empty()) else {
            return Ok(results::SlotFrame::Completed);
        };
        // The start, each pass's end, and the frame's end.
        let written = s.stamped.len() + 2;
        let ms = t.ms_since_first(&s.completed_ticks(written));
        let timings = PassTimings::from_stamps(&std::mem::take(&mut s.stamped), &ms);
        self.last_timings = Some(timings.clone());
        if self.completed_timings.len() == results::COMPLETED_TIMINGS_KEPT {
            self.completed_timings.pop_front();
        }
        self.completed_timings.push_back(timings);
        Ok(results::SlotFrame::Completed)
    }

    fn check_size(&self, width: u32, height: u32) -> Result<(), RenderError> {
        let max = self.device.max_image_dimension_2d();
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::InvalidSize { width, height, max });
        }
        Ok(())
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        // Combustion's own submissions are waited for (bounded) by the frame ring's Drop.
        // Frames recorded into a host's command buffers may still be in flight (a host
        // returning an error with `?` drops the renderer at once): the queue they were
        // submitted on is drained before anything they read is freed. An owned device
        // is waited idle as well.
        drop(self.offscreen.take());
        if self.device.is_owned() {
            if let Err(e) = self.device.wait_idle() {
                log::error!("waiting for the device before teardown: {e}");
            }
        } else if self.frame_number > 0 {
            if let Err(e) = self.device.wait_queue_idle() {
                log::error!("waiting for the host's queue before teardown: {e}");
            }
        }
        // Every frame is complete now: what scenes dropped is freed, and scenes dropped
        // from here on free their resources at once.
        drop(self.retire_queue.close());
    }
}

/// Whether two scenes' environments are the same, an image shared through its `Arc` at
/// once (comparing 2²⁶ texels on every edit would cost more than the edit).
fn same_environment(
    a: &Option<combustion_scene::Environment>,
    b: &Option<combustion_scene::Environment>,
) -> bool {
    use combustion_scene::Environment::Image;
    match (a, b) {
        (Some(Image(a)), Some(Image(b))) => std::sync::Arc::ptr_eq(a, b) || a == b,
        _ => a == b,
    }
}
