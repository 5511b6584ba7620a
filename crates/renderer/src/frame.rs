//! The renderer's frames: recording one into a command buffer (the checks of `record`,
//! the frame slot's resources written, the passes in order with the barriers their
//! declarations imply, the retire list), and the renderer's own frames submitted into
//! its display image and read back (`render`, `submit_offscreen`; the ring and the
//! readback buffers are `offscreen.rs`'s).

use combustion_vk::{vk, ImageState};

use crate::buffers::{storage_buffer, write_growing, GPU_ONLY};
use crate::environment::GpuEnvironment;
use crate::error::RenderError;
use crate::gpu_types::{GpuLight, LightingPush};
use crate::graph::{ImageUse, TrackedImage};
use crate::host::{ColorTarget, FrameInputs, FrameTarget, DISPLAY_FORMAT};
use crate::offscreen::{Offscreen, ReadbackBuffers, DISPLAY_SIZES_KEPT, MAX_SUPERSAMPLE};
use crate::options::Readback;
use crate::passes::CullPush;
use crate::passes::FrameContext;
use crate::results::Frame;
use crate::scene_upload::GpuScene;
use crate::slot::{
    JOINT_MATRICES, LIGHTS, MORPH_WEIGHTS, OVERLAY_QUADS, PREVIOUS_MODELS, PREVIOUS_VERTEX_BASES,
    SHADOW_CASCADES, TILE_LISTS,
};
use crate::Renderer;
use combustion_vk::{Image, ImageDesc, RingFrame};

/// The environment lighting a frame: the frame's own, else the scene's (if any).
fn frame_environment<'a>(
    scene: &'a GpuScene,
    inputs: &FrameInputs<'a>,
) -> Option<&'a GpuEnvironment> {
    match inputs.environment {
        Some(environment) => Some(&environment.gpu),
        None => scene.gpu.environment.as_ref(),
    }
}

fn color_range() -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

fn depth_range() -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::DEPTH,
        ..color_range()
    }
}

impl Renderer {
    /// Records the deferred frame of `scene` into the host's command buffer `cmd`
    /// (recording, outside any render pass), rendering into `target`.
    ///
    /// `frame_slot` (0 to `frames_in_flight − 1`) names the per-frame resources to use.
    /// The host promises that the GPU has completed the frame it last recorded with the
    /// same slot (it has waited for that frame's fence), and that it submits frames on
    /// the device's queue in the order they were recorded. Nothing here waits, reads
    /// back or compiles: pipelines for the scene and for the target's format must have
    /// been built ([`Renderer::upload`], [`Renderer::prepare_output`]). Every argument is
    /// checked before anything is recorded, so an error leaves `cmd` untouched.
    ///
    /// # Host contract
    /// Not checked (Vulkan cannot be asked): `cmd` is a primary command buffer of this
    /// device in the recording state, outside any render pass or rendering instance,
    /// from a pool of the device's queue family (graphics and compute), and is submitted
    /// on the device's queue; the target's images and views stay alive until the frame
    /// has completed, and their `format`, `extent` and `usage` are theirs as created
    /// ([`ColorTarget`]). The images' synchronisation follows
    /// [`ColorTarget::before`](crate::ColorTarget::before) and
    /// [`ColorTarget::after`](crate::ColorTarget::after) (and those of
    /// [`DepthTarget`](crate::DepthTarget)). `record` leaves its own
    /// pipelines, descriptor sets, push constants, viewport and scissor bound in `cmd`;
    /// bind yours again after it.
    ///
    /// # Errors
    /// - [`RenderError::InvalidFrameSlot`]: `frame_slot` out of range;
    ///   [`RenderError::FrameSlotInFlight`]: its last frame has visibly not completed.
    /// - [`RenderError::InvalidSize`]: a target side of 0 or beyond the device's limit.
    /// - [`RenderError::InvalidExposure`], [`RenderError::InvalidBackground`],
    ///   [`RenderError::Scene`]: the inputs' exposure, background, camera or lights.
    /// - [`RenderError::UnsupportedOutputFormat`], [`RenderError::OutputNotPrepared`]: the
    ///   target's format; [`RenderError::AntiAliasingNotPrepared`]: the frame's
    ///   anti-aliasing into it.
    /// - [`RenderError::SceneOfAnotherRenderer`], [`RenderError::EnvironmentOfAnotherScene`],
    ///   [`RenderError::VariantNotPrepared`]: the scene, the frame's environment, or
    ///   pipelines not built for the scene after a change of shading options.
    /// - [`RenderError::InvalidAfterLayout`], [`RenderError::InvalidTargetImage`] (missing
    ///   usage), [`RenderError::InvalidDepthTarget`]: the targets.
    /// - [`RenderError::Vulkan`]: allocating the frame's targets or buffers failed.
    pub fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        frame_slot: usize,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        target: &FrameTarget,
    ) -> Result<(), RenderError> {
        let variant = self.check_frame(frame_slot, scene, inputs, target)?;
        // The host's frames: nothing reads their HDR image after them.
        self.record_checked(cmd, frame_slot, scene, inputs, target, (variant, false))
    }

    /// [`Renderer::record`] once its arguments have passed [`Renderer::check_frame`].
    pub(crate) fn record_checked(
        &mut self,
        cmd: vk::CommandBuffer,
        frame_slot: usize,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        target: &FrameTarget,
        (variant, hdr_read_after): (crate::variant::ShaderVariant, bool),
    ) -> Result<(), RenderError> {
        let extent = target.color.extent;
        // The slot's previous frame has completed: read its timings, free what it
        // retired, and reuse its resources.
        self.begin_slot(frame_slot)?;
        let requests = crate::passes::frame_images(variant, &self.settings);
        self.ensure_images(&requests, extent)?;
        self.slots[frame_slot]
            .placement
            .place(&self.device, scene, inputs.pose)?;
        self.write_frame_deformation(frame_slot, scene, inputs)?;
        let shadowed = self.prepare_shadows(frame_slot, scene, inputs, extent, variant)?;
        self.write_frame_lights(frame_slot, inputs, &shadowed)?;
        self.prepare_culling(frame_slot, inputs, extent)?;
        self.write_frame_overlay(frame_slot, inputs, extent)?;
        let temporal = self.prepare_temporal(frame_slot, scene, inputs, extent, variant)?;
        let accumulation = self.prepare_accumulation(scene, inputs, extent, variant);
        self.record_passes(
            cmd,
            frame_slot,
            &requests,
            scene,
            (variant, temporal, accumulation, hdr_read_after),
            inputs,
            target,
        );
        self.frame_number += 1;
        self.last_slot = Some(frame_slot);
        self.retire_unused_images();
        Ok(())
    }

    /// Checks everything [`Renderer::record`] is given; the variant the scene needs.
    pub(crate) fn check_frame(
        &self,
        frame_slot: usize,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        target: &FrameTarget,
    ) -> Result<crate::variant::ShaderVariant, RenderError> {
        let frames_in_flight = self.slots.len();
        if frame_slot >= frames_in_flight {
            return Err(RenderError::InvalidFrameSlot {
                slot: frame_slot,
                frames_in_flight,
            });
        }
        let extent = target.color.extent;
        self.check_size(extent.width, extent.height)?;
        if !(inputs.exposure.is_finite() && inputs.exposure > 0.0) {
            return Err(RenderError::InvalidExposure(inputs.exposure));
        }
        if !(0.0..=1.0).contains(&inputs.bloom_intensity) {
            return Err(RenderError::InvalidBloomIntensity(inputs.bloom_intensity));
        }
        if let Some(auto) = &inputs.auto_exposure {
            auto.validate()?;
            if !crate::passes::auto_exposure::prepared(&self.pipelines) {
                return Err(RenderError::AutoExposureNotPrepared);
            }
        }
        inputs.background.validate()?;
        inputs.camera.validate()?;
        combustion_scene::validate_lights(inputs.lights)?;
        if let Some(pose) = inputs.pose {
            crate::placement::check_pose(scene.scene(), pose)?;
        }
        let output = crate::passes::output::prepared(&self.pipelines, target.color.format);
        if output.is_none() {
            return Err(match crate::host::OutputEncoding::of(target.color.format) {
                Some(_) => RenderError::OutputNotPrepared(target.color.format),
                None => RenderError::UnsupportedOutputFormat(target.color.format),
            });
        }
        if inputs.anti_aliasing == crate::AntiAliasing::Fxaa
            && crate::host::OutputEncoding::of(target.color.format)
                != Some(crate::host::OutputEncoding::Linear)
            && output == Some(false)
        {
            return Err(RenderError::AntiAliasingNotPrepared {
                format: target.color.format,
                anti_aliasing: inputs.anti_aliasing,
            });
        }
        if !scene.belongs_to(&self.retire_queue) {
            return Err(RenderError::SceneOfAnotherRenderer);
        }
        let variant = match inputs.environment {
            None => self.variant_of(scene.variant),
            Some(environment) if environment.lights(&scene.bake_materials, &self.retire_queue) => {
                self.variant_of(scene.lit_variant)
            }
            Some(_) => return Err(RenderError::EnvironmentOfAnotherScene),
        };
        if !self.pipelines.is_prepared(&variant) || !self.structures_ready(scene, variant) {
            return Err(RenderError::VariantNotPrepared);
        }
        for (what, layout) in [
            ("colour", Some(target.color.after.layout)),
            ("depth", target.depth.map(|d| d.after.layout)),
        ] {
            if matches!(
                layout,
                Some(vk::ImageLayout::UNDEFINED | vk::ImageLayout::PREINITIALIZED)
            ) {
                return Err(RenderError::InvalidAfterLayout(what));
            }
        }
        let missing_usage = |target, usage: vk::ImageUsageFlags, needed| {
            if usage.contains(needed) {
                Ok(())
            } else {
                Err(RenderError::InvalidTargetImage {
                    target,
                    problem: crate::error::TargetImageProblem::MissingUsage(needed),
                })
            }
        };
        missing_usage(
            "colour",
            target.color.usage,
            vk::ImageUsageFlags::COLOR_ATTACHMENT,
        )?;
        if let Some(depth) = &target.depth {
            missing_usage("depth", depth.usage, vk::ImageUsageFlags::TRANSFER_DST)?;
            if depth.format != crate::gbuffer::DEPTH_FORMAT || depth.extent != extent {
                return Err(RenderError::InvalidDepthTarget {
                    got: depth.format,
                    got_width: depth.extent.width,
                    got_height: depth.extent.height,
                    width: extent.width,
                    height: extent.height,
                });
            }
        }
        // The state each image is left in must be one its usage allows (a layout
        // transition into it is recorded).
        let after_usage = |target, layout, usage: vk::ImageUsageFlags| match layout_usage(layout) {
            Some(needs) if !usage.intersects(needs) => Err(RenderError::InvalidTargetImage {
                target,
                problem: crate::error::TargetImageProblem::AfterLayoutNeedsUsage { layout, needs },
            }),
            _ => Ok(()),
        };
        after_usage("colour", target.color.after.layout, target.color.usage)?;
        if let Some(depth) = &target.depth {
            after_usage("depth", depth.after.layout, depth.usage)?;
        }

        Ok(variant)
    }

    /// Marks the start of a frame in `slot`: its previous frame must be complete (the
    /// host's promise, checked where the device has timestamps: the slot's last
    /// timestamp, written after every command of its frame, must be available). What
    /// scenes dropped since the last frame joins the retire list of the frame recorded
    /// last (the last that may read it); then what this slot's frame retired is freed.
    fn begin_slot(&mut self, slot: usize) -> Result<(), RenderError> {
        if self.collect_timings(slot)? == crate::results::SlotFrame::Pending {
            return Err(RenderError::FrameSlotInFlight { slot });
        }
        for dropped in self.retire_queue.take() {
            self.retire_boxed(dropped);
        }
        self.slots[slot].retired.clear();
        Ok(())
    }

    /// Makes sure the frame's images (`requests`, at `extent`) exist and marks them used
    /// by this frame.
    fn ensure_images(
        &mut self,
        requests: &[crate::targets::ImageRequest],
        extent: vk::Extent2D,
    ) -> Result<(), RenderError> {
        if self
            .images
            .ensure(&self.device, requests, extent, self.frame_number)?
        {
            self.stats.targets_built += 1;
        }
        Ok(())
    }

    /// Images no frame used for more than `settings.targets_kept_for_frames` frames (a
    /// window resized, a viewport closed, a variant's own targets) go to the retire list
    /// of the frame just recorded.
    fn retire_unused_images(&mut self) {
        let kept = u64::from(self.settings.targets_kept_for_frames);
        let stale = self.images.take_unused(self.frame_number, kept);
        if stale.is_empty() {
            return;
        }
        for image in &stale {
            self.states.forget(image.raw());
        }
        self.retire(stale);
        self.stats.targets_retired += 1;
    }

    /// Places the shadow cascades of the frame's shadowed lights (frames whose variant
    /// has shadows), writes their table into the slot, and makes sure the shadow maps
    /// have a layer for each. Returns, per shadowed light, its index among the frame's
    /// lights and its first layer.
    fn prepare_shadows(
        &mut self,
        slot: usize,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        extent: vk::Extent2D,
        variant: crate::variant::ShaderVariant,
    ) -> Result<Vec<(usize, u32)>, RenderError> {
        self.slots[slot].shadow_layers.clear();
        self.slots[slot].local_shadow_layers.clear();
        let (Some(settings), Some(shader)) = (self.settings.shading.shadows, variant.shadows)
        else {
            return Ok(Vec::new());
        };
        let placement = self.slots[slot].placement.of(scene);
        let pose_key = placement.key;
        let lights = crate::shadows::frame_shadows(
            inputs.lights,
            &inputs.camera,
            extent.width as f32 / extent.height as f32,
            placement.world_bounds,
            &settings,
            shader.kinds,
        );
        // The table, light after light; each entry names its layer in its own array.
        let mut table = Vec::new();
        let mut shadowed = Vec::new();
        let (mut cascade_layers, mut local_layers) = (Vec::new(), Vec::new());
        for (index, layers) in &lights {
            shadowed.push((*index, table.len() as u32));
            for layer in layers {
                let in_array = if layer.local {
                    &mut local_layers
                } else {
                    &mut cascade_layers
                };
                let mut gpu = layer.gpu;
                gpu.view_forward[3] = in_array.len() as f32;
                in_array.push(layer.world_to_clip());
                table.push(gpu);
            }
        }
        if table.is_empty() {
            table.push(bytemuck::Zeroable::zeroed());
        }
        write_growing(
            &self.device,
            &mut self.slots[slot].shadow_cascades,
            SHADOW_CASCADES,
            bytemuck::cast_slice(&table),
        )?;
        // The lighting pipeline samples both arrays whether or not a light is shadowed
        // this frame: they exist (one layer at least) in every frame with shadows. Each
        // is rendered again only when the scene's geometry or one of its layers'
        // placement changed since it was last rendered.
        for (size, layers, local) in [
            (settings.map_size, cascade_layers, false),
            (settings.local_map_size, local_layers, true),
        ] {
            let count = (layers.len() as u32).max(1);
            let contents = (
                scene.geometry_version,
                pose_key,
                layers.iter().map(|m| m.to_cols_array()).collect::<Vec<_>>(),
            );
            let maps = self.fitted_shadow_maps(local, size, count)?;
            if maps.contents.as_ref() == Some(&contents) {
                continue;
            }
            maps.contents = Some(contents);
            let s = &mut self.slots[slot];
            if local {
                s.local_shadow_layers = layers;
            } else {
                s.shadow_layers = layers;
            }
        }
        Ok(shadowed)
    }

    /// One array of shadow maps (`local`: the spot and point lights', else the
    /// cascades'), made, or replaced and the old one retired, to hold `layers` layers of
    /// `size`².
    fn fitted_shadow_maps(
        &mut self,
        local: bool,
        size: u32,
        layers: u32,
    ) -> Result<&mut crate::shadows::ShadowMaps, RenderError> {
        fn array(r: &mut Renderer, local: bool) -> &mut Option<crate::shadows::ShadowMaps> {
            if local {
                &mut r.local_shadow_maps
            } else {
                &mut r.shadow_maps
            }
        }
        if !array(self, local)
            .as_ref()
            .is_some_and(|m| m.fits(size, layers))
        {
            let made = crate::shadows::ShadowMaps::new(&self.device, size, layers, local)?;
            if let Some(old) = array(self, local).replace(made) {
                self.states.forget(old.image.raw());
                self.retire(old);
            }
        }
        Ok(array(self, local).as_mut().expect("made above"))
    }

    /// Writes the frame's lights into the slot; `shadowed` lights (index, first shadow
    /// layer) carry their layer.
    fn write_frame_lights(
        &mut self,
        slot: usize,
        inputs: &FrameInputs<'_>,
        shadowed: &[(usize, u32)],
    ) -> Result<(), RenderError> {
        let mut lights: Vec<GpuLight> = inputs.lights.iter().map(GpuLight::new).collect();
        for &(index, first_layer) in shadowed {
            lights[index].spot_cone[3] = (first_layer + 1) as f32;
        }
        let s = &mut self.slots[slot];
        write_growing(
            &self.device,
            &mut s.lights,
            LIGHTS,
            bytemuck::cast_slice(&lights),
        )?;
        Ok(())
    }

    /// Writes the joint matrices and morph weights of the frame's pose (else the scene's
    /// rest) into the slot, for a scene with deformed objects.
    fn write_frame_deformation(
        &mut self,
        slot: usize,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
    ) -> Result<(), RenderError> {
        let Some(deform) = &scene.gpu.deform else {
            return Ok(());
        };
        let poses = inputs.pose.unwrap_or(&deform.rest_poses);
        let (joints, weights) = deform.frame_inputs(poses);
        let s = &mut self.slots[slot];
        write_growing(
            &self.device,
            &mut s.joint_matrices,
            JOINT_MATRICES,
            bytemuck::cast_slice(&joints),
        )?;
        write_growing(
            &self.device,
            &mut s.morph_weights,
            MORPH_WEIGHTS,
            bytemuck::cast_slice(&weights),
        )?;
        Ok(())
    }

    /// Decides whether the slot's frame culls its lights, and makes its tile lists large
    /// enough.
    fn prepare_culling(
        &mut self,
        slot: usize,
        inputs: &FrameInputs<'_>,
        extent: vk::Extent2D,
    ) -> Result<(), RenderError> {
        let culls = self.light_culling.culls(inputs.lights);
        let s = &mut self.slots[slot];
        s.culling = None;
        if !culls {
            return Ok(());
        }
        let (x, y) = crate::light_cull::tiles(extent);
        let stride = inputs.lights.len() as u32 + 1;
        let words = u64::from(x) * u64::from(y) * u64::from(stride);
        let limit = u64::from(self.device.limits().max_storage_buffer_range);
        if words * 4 > limit {
            // The lists would not fit one buffer binding: this frame lights every pixel
            // with every light (the same image, slower).
            return Ok(());
        }
        if words * 4 > s.tile_lights.size() {
            // Its last reader, this slot's previous frame, has completed.
            let bytes = (words * 4).next_power_of_two().min(limit);
            let old = std::mem::replace(
                &mut s.tile_lights,
                storage_buffer(&self.device, TILE_LISTS, bytes, GPU_ONLY)?,
            );
            self.states.forget_buffer(old.raw());
        }
        s.culling = Some((x, stride));
        Ok(())
    }

    /// In frames of temporal anti-aliasing: the previous camera and each object's
    /// previous transform (written into the slot for the motion pass), the history's
    /// state; the renderer remembers this frame's for the next. `None` in other frames
    /// (and the history is forgotten).
    fn prepare_temporal(
        &mut self,
        slot: usize,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        extent: vk::Extent2D,
        variant: crate::variant::ShaderVariant,
    ) -> Result<Option<crate::passes::temporal_anti_aliasing::TemporalFrame>, RenderError> {
        if !crate::passes::temporal_anti_aliasing::wanted(variant) {
            self.temporal.forget();
            return Ok(None);
        }
        if let Some(old) = self.temporal.fit_previous_vertices(&self.device, scene)? {
            self.states.forget_buffer(old.raw());
            self.retire(old);
        }
        let placement = self.slots[slot].placement.of(scene);
        let transforms: Vec<glam::Mat4> = (0..scene.scene().objects.len())
            .map(|i| placement.transform(scene, i))
            .collect();
        let unjittered = inputs
            .camera
            .view_projection(extent.width as f32 / extent.height as f32);
        let key = (
            scene as *const GpuScene as usize,
            scene.geometry_version,
            [extent.width, extent.height],
        );
        let (frame, previous) = self.temporal.advance(key, unjittered, transforms);
        let mut table: Vec<[f32; 16]> = previous.iter().map(|m| m.to_cols_array()).collect();
        if table.is_empty() {
            table.push([0.0; 16]);
        }
        write_growing(
            &self.device,
            &mut self.slots[slot].previous_models,
            PREVIOUS_MODELS,
            bytemuck::cast_slice(&table),
        )?;
        // Each posed object's first vertex in the previous pose (vertices of 48 bytes).
        let not_posed = crate::passes::temporal_anti_aliasing::NOT_POSED;
        let mut bases: Vec<u32> = (0..scene.scene().objects.len())
            .map(|i| {
                scene
                    .gpu
                    .deform
                    .as_ref()
                    .and_then(|d| d.posed_offsets[i])
                    .map_or(not_posed, |offset| {
                        (offset / std::mem::size_of::<crate::gpu_types::GpuVertex>() as u64) as u32
                    })
            })
            .collect();
        if bases.is_empty() {
            bases.push(not_posed);
        }
        write_growing(
            &self.device,
            &mut self.slots[slot].previous_vertex_bases,
            PREVIOUS_VERTEX_BASES,
            bytemuck::cast_slice(&bases),
        )?;
        Ok(Some(frame))
    }

    /// In frames whose path-traced radiance is averaged on the GPU
    /// ([`RendererSettings::accumulate_paths`]): the frame's place in its history (the
    /// next of the last frame's, or the first of a new one where anything its radiance
    /// depends on changed). `None` in other frames (and the history is forgotten).
    fn prepare_accumulation(
        &mut self,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        extent: vk::Extent2D,
        variant: crate::variant::ShaderVariant,
    ) -> Option<crate::passes::path_accumulation::AccumulationFrame> {
        use crate::passes::path_accumulation::{wanted, AccumulationKey};
        if !wanted(variant, &self.settings) {
            self.accumulation.forget();
            return None;
        }
        Some(
            self.accumulation.advance(AccumulationKey {
                scene: (scene as *const GpuScene as usize, scene.geometry_version),
                extent: [extent.width, extent.height],
                shading: (variant, self.settings.shading),
                camera: inputs.camera,
                lights: inputs.lights.to_vec(),
                pose: inputs.pose.cloned(),
                background: inputs.background,
                environment: inputs
                    .environment
                    .map(|e| e as *const crate::environment::FrameEnvironment as usize),
                seed: inputs.environment_seed,
            }),
        )
    }

    fn write_frame_overlay(
        &mut self,
        slot: usize,
        inputs: &FrameInputs<'_>,
        extent: vk::Extent2D,
    ) -> Result<(), RenderError> {
        let quads = self.shared.overlay_font.layout(
            inputs.overlay,
            [extent.width, extent.height],
            self.shared.overlay_image.1,
        );
        let s = &mut self.slots[slot];
        s.overlay_quad_count = quads.len() as u32;
        if quads.is_empty() {
            return Ok(());
        }
        write_growing(
            &self.device,
            &mut s.overlay_quads,
            OVERLAY_QUADS,
            bytemuck::cast_slice(&quads),
        )?;
        Ok(())
    }

    /// Runs the frame's pass list ([`crate::passes::FRAME`]) into `cmd`: for each pass
    /// that runs, its declaration's descriptor writes and barriers, its commands, and
    /// a timestamp under its name; the host's images are released to their `after`
    /// states at the end.
    #[allow(clippy::too_many_arguments)]
    fn record_passes(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        requests: &[crate::targets::ImageRequest],
        scene: &GpuScene,
        (variant, temporal, accumulation, hdr_read_after): (
            crate::variant::ShaderVariant,
            Option<crate::passes::temporal_anti_aliasing::TemporalFrame>,
            Option<crate::passes::path_accumulation::AccumulationFrame>,
            bool,
        ),
        inputs: &FrameInputs<'_>,
        target: &FrameTarget,
    ) {
        // The barrier states, carried across frames, are the one thing the passes'
        // recording changes: taken out so the passes can read the renderer meanwhile.
        let mut states = std::mem::take(&mut self.states);
        let extent = target.color.extent;
        let mut view_projection = inputs
            .camera
            .view_projection(extent.width as f32 / extent.height as f32);
        // Temporal anti-aliasing moves every pass's camera by the frame's jitter (the
        // history's frame index: the previous frames' were the ones before it).
        if temporal.is_some() {
            use crate::passes::temporal_anti_aliasing::{jitter, jittered};
            let index = self.temporal.frames() - 1;
            view_projection = jittered(view_projection, jitter(index), extent);
        }
        let s = &self.slots[slot];
        let mut lighting_push = LightingPush::new(
            view_projection,
            inputs.camera.position,
            inputs.lights.len() as u32,
            self.settings.shading.debug_view as u32,
        )
        .with_background(inputs.background)
        // An accumulated frame traces the seed after its history's last frame's.
        .with_sampling(
            accumulation.map_or(inputs.environment_seed, |a| {
                inputs.environment_seed.wrapping_add(a.frames - 1)
            }),
            self.settings.shading.path_depth,
        );
        let cull_push = s.culling.map(|(tiles_x, stride)| {
            lighting_push = lighting_push.with_tile_lists(tiles_x, stride);
            CullPush {
                inverse_view_projection: lighting_push.inverse_view_projection,
                counts: [
                    inputs.lights.len() as u32,
                    tiles_x,
                    stride,
                    tiles_x * crate::light_cull::tiles(extent).1,
                ],
            }
        });
        let images = self.images.frame_images(requests, extent);
        let mut frame = FrameContext {
            number: self.frame_number + 1,
            device: &self.device,
            registry: &self.pipelines,
            shared: &self.shared,
            settings: &self.settings,
            slot: s,
            gbuffer: crate::gbuffer::GBufferTargets::of(&images),
            hdr: images.get(crate::passes::lighting::HDR),
            images,
            scene,
            environment: frame_environment(scene, inputs),
            inputs,
            target,
            variant,
            view_projection,
            lighting_push,
            cull_push,
            color: TrackedImage {
                raw: target.color.image,
                range: color_range(),
            },
            host_depth: target.depth.map(|depth| TrackedImage {
                raw: depth.image,
                range: depth_range(),
            }),
            shadow_maps: self
                .shadow_maps
                .as_ref()
                .zip(self.local_shadow_maps.as_ref())
                .filter(|_| variant.shadows.is_some()),
            placement: s.placement.of(scene),
            metering_continues: self.metering_continues,
            hdr_read_after,
            output_folded: false,
            temporal,
            previous_vertices: self
                .temporal
                .previous_vertices
                .as_ref()
                .filter(|_| temporal.is_some()),
            accumulation,
        };
        frame.output_folded = crate::passes::lighting::folds_output(&frame);
        let device = &*self.device;
        let raw = device.raw();
        // The host's images stand where the host left them.
        states.set(frame.color.raw, target.color.before);
        if let (Some(image), Some(depth)) = (frame.host_depth, &target.depth) {
            states.set(image.raw, depth.before);
        }
        // The frame's start, then the end of each timed pass by name ([`PassTimings`]).
        let timestamps = s.timestamps.as_ref();
        if let Some(t) = timestamps {
            t.record_reset(cmd);
            t.record(cmd, vk::PipelineStageFlags2::ALL_COMMANDS, 0);
        }
        let mut stamped = Vec::new();
        for pass in crate::passes::FRAME {
            if !pass.runs(&frame) {
                continue;
            }
            let uses = pass.io(&frame).apply(device);
            states.transition(raw, cmd, &uses);
            pass.record(&frame, cmd);
            if let (Some(t), true) = (timestamps, pass.timed()) {
                t.record(
                    cmd,
                    vk::PipelineStageFlags2::ALL_COMMANDS,
                    stamped.len() as u32 + 1,
                );
                stamped.push(pass.name());
            }
        }
        // The host's images are the host's again: their states come with the next frame.
        if let (Some(image), Some(depth)) = (frame.host_depth, &target.depth) {
            states.release(raw, cmd, image, depth.after);
            states.forget(image.raw);
        }
        states.release(raw, cmd, frame.color, target.color.after);
        states.forget(frame.color.raw);
        // The end of the frame's last command.
        if let Some(t) = timestamps {
            let end = stamped.len() as u32 + 1;
            t.record(cmd, vk::PipelineStageFlags2::ALL_COMMANDS, end);
        }
        // A metered frame's exposure state, for the host, beside its marker.
        let metered = inputs.auto_exposure.is_some();
        if metered {
            let state = &self.shared.exposure_state;
            let copy = crate::graph::PassUses::images("exposure readout", Vec::new())
                .with_buffers(vec![(state.raw(), crate::graph::BufferUse::TransferSource)]);
            states.transition(raw, cmd, &copy);
            let region = [vk::BufferCopy {
                src_offset: 0,
                dst_offset: crate::slot::FRAME_END_BYTES,
                size: crate::exposure::MeteredExposure::BYTES,
            }];
            // SAFETY: outside any rendering; both ranges lie within their buffers (the
            // frame-end record holds the state after its timestamps).
            unsafe { raw.cmd_copy_buffer(cmd, state.raw(), s.frame_end.raw(), &region) };
        }
        // After every command: the frame's timestamps copied and its marker written into
        // the slot's host-visible frame-end record, the GPU's word that it completed.
        let marker = self.frame_number + 1;
        record_frame_end(device, cmd, s, stamped.len() as u32 + 2, marker);
        self.states = states;
        self.metering_continues |= metered;
        self.slots[slot].stamped = stamped;
        self.slots[slot].recorded = marker;
        self.slots[slot].metered = metered;
    }
}

/// Records the end of `slot`'s frame into `cmd`, after every command before it: its
/// first `stamps` timestamps copied into the slot's frame-end record, then `marker`
/// written at its start, made visible to the host.
fn record_frame_end(
    device: &combustion_vk::Device,
    cmd: vk::CommandBuffer,
    slot: &crate::slot::FrameSlot,
    stamps: u32,
    marker: u64,
) {
    let raw = device.raw();
    let barrier = |src: (vk::PipelineStageFlags2, vk::AccessFlags2),
                   dst: (vk::PipelineStageFlags2, vk::AccessFlags2)| {
        let memory = [vk::MemoryBarrier2::default()
            .src_stage_mask(src.0)
            .src_access_mask(src.1)
            .dst_stage_mask(dst.0)
            .dst_access_mask(dst.1)];
        // SAFETY: a plain memory barrier outside any rendering, `cmd` recording.
        unsafe {
            raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&memory))
        };
    };
    let transfer = (
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_WRITE,
    );
    barrier(
        (
            vk::PipelineStageFlags2::ALL_COMMANDS,
            vk::AccessFlags2::MEMORY_WRITE,
        ),
        transfer,
    );
    if let Some(t) = &slot.timestamps {
        t.record_copy(cmd, slot.frame_end.raw(), 8, stamps);
        barrier(transfer, transfer);
    }
    // SAFETY: 8 bytes at offset 0 of a TRANSFER_DST buffer, outside any rendering.
    unsafe { raw.cmd_update_buffer(cmd, slot.frame_end.raw(), 0, &marker.to_le_bytes()) };
    barrier(
        transfer,
        (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
    );
}

/// The usages one of which an image must have to be put in `layout` (Vulkan's valid
/// usage of a layout transition); `None` for layouts any image may take (`GENERAL`,
/// `PRESENT_SRC_KHR`, …).
fn layout_usage(layout: vk::ImageLayout) -> Option<vk::ImageUsageFlags> {
    use vk::ImageLayout as L;
    use vk::ImageUsageFlags as U;
    Some(match layout {
        L::COLOR_ATTACHMENT_OPTIMAL => U::COLOR_ATTACHMENT,
        L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL
        | L::DEPTH_ATTACHMENT_OPTIMAL
        | L::STENCIL_ATTACHMENT_OPTIMAL
        | L::DEPTH_ATTACHMENT_STENCIL_READ_ONLY_OPTIMAL
        | L::DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL => U::DEPTH_STENCIL_ATTACHMENT,
        L::DEPTH_STENCIL_READ_ONLY_OPTIMAL
        | L::DEPTH_READ_ONLY_OPTIMAL
        | L::STENCIL_READ_ONLY_OPTIMAL => {
            U::DEPTH_STENCIL_ATTACHMENT | U::SAMPLED | U::INPUT_ATTACHMENT
        }
        L::SHADER_READ_ONLY_OPTIMAL => U::SAMPLED | U::INPUT_ATTACHMENT,
        L::TRANSFER_SRC_OPTIMAL => U::TRANSFER_SRC,
        L::TRANSFER_DST_OPTIMAL => U::TRANSFER_DST,
        L::ATTACHMENT_OPTIMAL => U::COLOR_ATTACHMENT | U::DEPTH_STENCIL_ATTACHMENT,
        L::READ_ONLY_OPTIMAL => U::SAMPLED | U::INPUT_ATTACHMENT | U::DEPTH_STENCIL_ATTACHMENT,
        _ => return None,
    })
}

/// A host-provided image's state, for the renderer's own display image.
pub(crate) fn display_after(readback: bool) -> ImageState {
    if readback {
        ImageUse::TransferSource.state()
    } else {
        ImageUse::FragmentSampled.state()
    }
}

impl Renderer {
    /// A still frame of `scene` at `width`×`height` with `factor`×`factor` samples a
    /// pixel (1 to [`MAX_SUPERSAMPLE`]): rendered at `factor` times the size (the same
    /// camera, so the samples lie on a regular grid inside each pixel), its radiance
    /// averaged per pixel in f64 (a box filter: the mean radiance over the pixel's area)
    /// and then exposed and tone-mapped as the output pass does
    /// ([`crate::ToneMapping::display_codes`]). The frame's own anti-aliasing is not
    /// applied. Images only; the timings are the large frame's.
    ///
    /// # Errors
    /// [`RenderError::InvalidSupersample`] for a factor outside its range;
    /// [`RenderError::InvalidSize`] when the large frame exceeds the device's image
    /// size; as [`Renderer::render_with`] otherwise.
    pub fn render_supersampled(
        &mut self,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
        factor: u32,
    ) -> Result<Frame, RenderError> {
        if !(1..=MAX_SUPERSAMPLE).contains(&factor) {
            return Err(RenderError::InvalidSupersample(factor));
        }
        let plain = FrameInputs {
            anti_aliasing: crate::AntiAliasing::None,
            ..*inputs
        };
        let large = self.render_with(
            scene,
            &plain,
            width.saturating_mul(factor),
            height.saturating_mul(factor),
            Readback::IMAGES,
        )?;
        // The large frame's metered exposure, where it metered one.
        let exposure = self.exposure_shown(inputs);
        let (w, h, f) = (width as usize, height as usize, factor as usize);
        let samples = (f * f) as f64;
        let mut hdr = Vec::with_capacity(w * h);
        let mut ldr = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0.0f64; 4];
                for sy in 0..f {
                    let row = (y * f + sy) * w * f;
                    for sx in 0..f {
                        let p = large.hdr[row + x * f + sx];
                        for c in 0..4 {
                            sum[c] += f64::from(p[c]);
                        }
                    }
                }
                let mean = sum.map(|s| s / samples);
                hdr.push(mean.map(|m| m as f32));
                let exposed = [0, 1, 2].map(|c| mean[c] * f64::from(exposure));
                let [r, g, b] = inputs.tone_mapping.display_codes(exposed);
                ldr.push([r, g, b, 255]);
            }
        }
        Ok(Frame {
            width,
            height,
            hdr,
            ldr,
            gbuffer: None,
            timings: large.timings,
        })
    }

    /// Renders `scene` (its own camera and lights, the settings' exposure) at
    /// `width`×`height`, submits, waits for the GPU and copies back what `readback`
    /// asks for. The convenience path of the command line and the tests; a host records
    /// its frames with [`Renderer::record`] instead.
    pub fn render(
        &mut self,
        scene: &GpuScene,
        width: u32,
        height: u32,
        readback: Readback,
    ) -> Result<Frame, RenderError> {
        let inputs = FrameInputs::of_scene(scene, self.settings.exposure);
        self.render_with(scene, &inputs, width, height, readback)
    }

    /// As [`Renderer::render`], with the frame's camera, exposure, lights and overlay
    /// given (e.g. a viewer's current frame, rendered again to be read back). A host
    /// that records its own frames ([`Renderer::record`]) calls it only once all of
    /// them have completed: both use the renderer's frame slots (docs/integration.md).
    pub fn render_with(
        &mut self,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
        readback: Readback,
    ) -> Result<Frame, RenderError> {
        let frame = self.submit_with_offscreen(scene, inputs, width, height, Some(readback))?;
        let offscreen = self.offscreen.as_ref().expect("created by the submission");
        offscreen.ring.wait(frame.slot)?;
        self.collect_timings(frame.slot)?;
        self.stats.readbacks += 1;
        let variant = self.variant_of(scene.variant);
        let timings = self.last_timings.clone().unwrap_or_default();
        let offscreen = self.offscreen.as_ref().expect("created by the submission");
        offscreen.read_back(
            &self.settings,
            timings,
            (width, height),
            readback,
            [
                variant.clearcoat,
                variant.sheen,
                variant.iridescence,
                variant.specular,
                variant.has_emissive_occlusion_target(),
            ],
        )
    }

    /// Records and submits a frame of `scene` into the renderer's display image without
    /// waiting for it: the frame ring waits only for the frame that used the same slot
    /// (frames in flight). [`Renderer::last_completed_timings`] then gives the GPU times
    /// of the latest completed frame; [`Renderer::finish_offscreen`] waits for all.
    pub fn submit_offscreen(
        &mut self,
        scene: &GpuScene,
        width: u32,
        height: u32,
    ) -> Result<(), RenderError> {
        let inputs = FrameInputs::of_scene(scene, self.settings.exposure);
        self.submit_with_offscreen(scene, &inputs, width, height, None)
            .map(|_| ())
    }

    /// As [`Renderer::submit_offscreen`], with the frame's camera, exposure, lights and
    /// overlay given (a camera moving from frame to frame, say).
    pub fn submit_offscreen_with(
        &mut self,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
    ) -> Result<(), RenderError> {
        self.submit_with_offscreen(scene, inputs, width, height, None)
            .map(|_| ())
    }

    /// Waits for every frame submitted by [`Renderer::submit_offscreen`] and collects
    /// the timings of those not collected yet, oldest first.
    pub fn finish_offscreen(&mut self) -> Result<(), RenderError> {
        let Some(offscreen) = &self.offscreen else {
            return Ok(());
        };
        offscreen.ring.wait_all()?;
        self.frames_completed()
    }

    fn submit_with_offscreen(
        &mut self,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
        readback: Option<Readback>,
    ) -> Result<RingFrame, RenderError> {
        self.check_size(width, height)?;
        // The offscreen frames' display image: its anti-aliasing's pipeline is built
        // here, before the frame is recorded (once; later frames find it built).
        self.prepare_anti_aliasing(crate::DISPLAY_FORMAT, inputs.anti_aliasing)?;
        if inputs.auto_exposure.is_some() {
            self.prepare_auto_exposure()?;
        }
        let mut offscreen = match self.offscreen.take() {
            Some(o) => o,
            None => Offscreen::new(&self.device, self.slots.len())?,
        };
        let result = self.submit_frame(&mut offscreen, scene, inputs, width, height, readback);
        self.offscreen = Some(offscreen);
        result
    }

    fn submit_frame(
        &mut self,
        offscreen: &mut Offscreen,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
        readback: Option<Readback>,
    ) -> Result<RingFrame, RenderError> {
        let extent = vk::Extent2D { width, height };
        match offscreen
            .displays
            .iter()
            .position(|(image, _)| image.extent() == extent)
        {
            Some(i) => {
                let found = offscreen.displays.remove(i);
                offscreen.displays.push(found);
            }
            None => {
                let display = Image::new(
                    &self.device,
                    &ImageDesc::new(
                        "display (sRGB-encoded)",
                        DISPLAY_FORMAT,
                        width,
                        height,
                        vk::ImageUsageFlags::COLOR_ATTACHMENT
                            | vk::ImageUsageFlags::SAMPLED
                            | vk::ImageUsageFlags::TRANSFER_SRC,
                    ),
                )?;
                self.stats.display_images_built += 1;
                offscreen.displays.push((display, ImageState::UNDEFINED));
                if offscreen.displays.len() > DISPLAY_SIZES_KEPT {
                    let (old, _) = offscreen.displays.remove(0);
                    self.retire(old);
                }
            }
        }
        let wants_copies = readback.is_some_and(|r| r.images || r.gbuffer);
        let wants_gbuffer = readback.is_some_and(|r| r.gbuffer);
        if wants_copies
            && offscreen
                .readback
                .as_ref()
                .is_none_or(|r| r.extent != extent || (wants_gbuffer && r.clearcoat.is_none()))
        {
            let buffers = ReadbackBuffers::new(
                &self.device,
                extent,
                self.settings.hdr_format,
                self.settings.gbuffer,
                wants_gbuffer,
            )?;
            if let Some(old) = offscreen.readback.replace(buffers) {
                for buffer in old.all() {
                    self.states.forget_buffer(buffer.raw());
                }
                self.retire(old);
            }
        }
        let (display, display_state) = offscreen.displays.last_mut().expect("made above");
        let after = display_after(readback.is_some_and(|r| r.images));
        let target = FrameTarget {
            color: ColorTarget {
                image: display.raw(),
                view: display.view(),
                format: DISPLAY_FORMAT,
                extent,
                usage: display.usage(),
                before: *display_state,
                after,
            },
            depth: None,
        };
        // Checked before the ring advances: a refused frame takes no slot.
        let variant = self.check_frame(offscreen.ring.next_slot(), scene, inputs, &target)?;
        let frame = offscreen.ring.begin()?;
        let hdr_read_after = readback.is_some_and(|r| r.images);
        self.record_checked(
            frame.cmd,
            frame.slot,
            scene,
            inputs,
            &target,
            (variant, hdr_read_after),
        )?;
        *display_state = after;
        if let (Some(readback), Some(buffers)) = (readback, &offscreen.readback) {
            let requests = crate::passes::frame_images(variant, &self.settings);
            let images = self.images.frame_images(&requests, extent);
            let gbuffer = crate::gbuffer::GBufferTargets::of(&images);
            Offscreen::record_copies(
                &self.device,
                &mut self.states,
                frame.cmd,
                display,
                buffers,
                (images.get(crate::passes::lighting::HDR), &gbuffer),
                readback,
            );
        }
        if let Err(e) = offscreen.ring.submit(frame) {
            // The frame will never run: its slot is not waiting for it, and what its
            // recording committed (image states, shadow maps) is forgotten.
            self.slots[frame.slot].stamped.clear();
            self.slots[frame.slot].recorded = 0;
            self.forget_abandoned_frames();
            offscreen.forget_display_states();
            return Err(e.into());
        }
        Ok(frame)
    }
}
