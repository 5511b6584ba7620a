#![allow(dead_code)] // shared with tests/host.rs, which uses a different part of it
//! The host's frame: it owns a final image (offscreen here; a swapchain image in a
//! window), clears it, has Combustion render the scene into a viewport image of its own
//! with its own depth buffer, composes that viewport onto the final image with a blit and
//! draws a frame of its own around it — all on the device, with frames in flight, no
//! readback. Shared by the example (`cargo run --example host`) and tests/host.rs.

use std::sync::Arc;

use combustion::renderer::{
    ColorTarget, DepthTarget, FrameEnvironment, FrameInputs, FrameTarget, GpuScene, Renderer,
    RendererSettings,
};
use combustion::scene::{Camera, Light, Scene};
use combustion::vk::ash::vk;
use combustion::vk::gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use combustion::vk::gpu_allocator::MemoryLocation;
use combustion::vk::{Device, ImageState};

use crate::vulkan::HostVulkan;

/// Pixels between the final image's edge and the viewport Combustion renders.
pub const BORDER: u32 = 16;
/// The host's background (RGBA8, what its clear writes).
pub const BACKGROUND: [f32; 4] = [0.1, 0.2, 0.4, 1.0];
/// The host's own drawing: a bar along the top border.
pub const BAR: [f32; 4] = [1.0, 0.5, 0.0, 1.0];

/// One host image with its memory (the host's own, from the shared allocator).
pub struct HostImage {
    pub image: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    /// What the image was created with (it points to nothing: no queue family list).
    created: vk::ImageCreateInfo<'static>,
    allocation: Option<Allocation>,
}

impl HostImage {
    pub fn new(
        host: &HostVulkan,
        name: &str,
        format: vk::Format,
        extent: vk::Extent2D,
        usage: vk::ImageUsageFlags,
    ) -> Result<Self, String> {
        let info = image_info(format, extent, usage);
        let d = &host.device;
        let image = unsafe { d.create_image(&info, None) }.map_err(|e| e.to_string())?;
        let requirements = unsafe { d.get_image_memory_requirements(image) };
        let allocation = host
            .allocator
            .lock()
            .map_err(|_| "allocator lock")?
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| e.to_string())?;
        unsafe { d.bind_image_memory(image, allocation.memory(), allocation.offset()) }
            .map_err(|e| e.to_string())?;
        let aspect = if format == vk::Format::D32_SFLOAT {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        };
        let view_info = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(range(aspect));
        let view = unsafe { d.create_image_view(&view_info, None) }.map_err(|e| e.to_string())?;
        Ok(Self {
            image,
            view,
            format,
            extent,
            created: info,
            allocation: Some(allocation),
        })
    }

    /// This image as the colour target of a Combustion frame, described by the create
    /// info it was created with.
    pub fn color_target(
        &self,
        before: ImageState,
        after: ImageState,
    ) -> Result<ColorTarget, String> {
        ColorTarget::from_create_info(self.image, self.view, &self.created, before, after)
            .map_err(|e| e.to_string())
    }

    /// This image as the depth target of a Combustion frame.
    pub fn depth_target(
        &self,
        before: ImageState,
        after: ImageState,
    ) -> Result<DepthTarget, String> {
        DepthTarget::from_create_info(self.image, &self.created, before, after)
            .map_err(|e| e.to_string())
    }

    pub fn destroy(mut self, host: &HostVulkan) {
        unsafe {
            host.device.destroy_image_view(self.view, None);
            host.device.destroy_image(self.image, None);
        }
        if let (Some(a), Ok(mut allocator)) = (self.allocation.take(), host.allocator.lock()) {
            let _ = allocator.free(a);
        }
    }
}

/// The create info of a host image: 2D, one mip level, one layer, one sample.
pub fn image_info(
    format: vk::Format,
    extent: vk::Extent2D,
    usage: vk::ImageUsageFlags,
) -> vk::ImageCreateInfo<'static> {
    vk::ImageCreateInfo::default()
        .image_type(vk::ImageType::TYPE_2D)
        .format(format)
        .extent(vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        })
        .mip_levels(1)
        .array_layers(1)
        .samples(vk::SampleCountFlags::TYPE_1)
        .tiling(vk::ImageTiling::OPTIMAL)
        .usage(usage)
        .initial_layout(vk::ImageLayout::UNDEFINED)
}

pub fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

fn layers(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceLayers {
    vk::ImageSubresourceLayers {
        aspect_mask: aspect,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    }
}

pub fn barrier(
    device: &combustion::vk::ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    from: ImageState,
    to: ImageState,
) {
    let b = [combustion::vk::image_barrier(
        image,
        range(aspect),
        from,
        to,
    )];
    unsafe {
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&b),
        )
    };
}

/// The viewport Combustion renders into (the host's images) at one size.
pub struct Viewport {
    pub color: HostImage,
    pub depth: HostImage,
    pub color_state: ImageState,
    pub depth_state: ImageState,
}

impl Viewport {
    pub fn new(host: &HostVulkan, extent: vk::Extent2D) -> Result<Self, String> {
        Ok(Self {
            color: HostImage::new(
                host,
                "host viewport",
                vk::Format::R8G8B8A8_UNORM,
                extent,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            )?,
            depth: HostImage::new(
                host,
                "host depth",
                vk::Format::D32_SFLOAT,
                extent,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSFER_DST
                    | vk::ImageUsageFlags::TRANSFER_SRC,
            )?,
            color_state: ImageState::UNDEFINED,
            depth_state: ImageState::UNDEFINED,
        })
    }

    pub fn destroy(self, host: &HostVulkan) {
        self.color.destroy(host);
        self.depth.destroy(host);
    }
}

/// The camera of frame `n`: an orbit around the scene's own camera target.
pub fn camera_at(base: &Camera, n: u64) -> Camera {
    let angle = n as f32 * 0.02;
    let offset = base.position - base.target;
    let rotation = glam::Quat::from_axis_angle(base.up.normalize(), angle);
    Camera {
        position: base.target + rotation * offset,
        ..*base
    }
}

/// The pose of frame `n`: the scene's first animation at n/30 s, and on top of it the
/// host's own animation, every joint of every skin swaying about its own z axis, out
/// of phase along the skin (placed through the scene's hierarchy by
/// `Scene::pose_objects`, which gives the joint matrices); `None` for a scene with
/// neither animations nor skins (it is drawn at rest).
pub fn pose_at(scene: &combustion::scene::Scene, n: u64) -> Option<combustion::scene::ObjectPoses> {
    use combustion::scene::motion::LocalTransform;
    if scene.motion.skins.is_empty() && scene.motion.animations.is_empty() {
        return None;
    }
    let mut pose = scene
        .motion
        .sample(0, n as f32 / 30.0)
        .unwrap_or_else(|| scene.motion.rest_pose());
    for skin in &scene.motion.skins {
        for (j, &node) in skin.joints.iter().enumerate() {
            if let LocalTransform::Trs { rotation, .. } = &mut pose.locals[node] {
                let sway = 0.15 * (n as f32 * 0.1 + j as f32 * 0.5).sin();
                *rotation *= glam::Quat::from_rotation_z(sway);
            }
        }
    }
    Some(scene.pose_objects(&pose))
}

/// Every this many frames, [`lights_at`] adds a light.
pub const EXTRA_LIGHT_EVERY: u64 = 4;

/// The lights of frame `n`: the scene's, with the first one's power breathing, and every
/// [`EXTRA_LIGHT_EVERY`] frames an extra point light (the light list changes length
/// between frames).
pub fn lights_at(base: &[Light], n: u64) -> Vec<Light> {
    let mut lights = base.to_vec();
    let scale = 0.75 + 0.25 * (n as f32 * 0.1).cos();
    if let Some(first) = lights.first_mut() {
        match first {
            Light::Point { intensity, .. } | Light::Spot { intensity, .. } => {
                *intensity = intensity.map(|c| c * scale)
            }
            Light::Directional { irradiance, .. } => *irradiance = irradiance.map(|c| c * scale),
        }
    }
    if n % EXTRA_LIGHT_EVERY == 0 {
        lights.push(Light::Point {
            position: glam::Vec3::new(0.0, 3.0, 3.0),
            intensity: [5.0, 5.0, 5.0],
            range: None,
            casts_shadows: true,
            radius: 0.0,
        });
    }
    lights
}

/// The image a host frame ends in: an offscreen image, or a swapchain image.
#[derive(Clone, Copy, Debug)]
pub struct FinalTarget {
    pub image: vk::Image,
    pub view: vk::ImageView,
    pub extent: vk::Extent2D,
}

impl From<&HostImage> for FinalTarget {
    fn from(image: &HostImage) -> Self {
        Self {
            image: image.image,
            view: image.view,
            extent: image.extent,
        }
    }
}

/// Per frame in flight: the host's command buffer, its fence, and what the host itself
/// retired while that frame was the latest.
struct HostSlot {
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    retired: Vec<Viewport>,
}

/// A host: its Vulkan, Combustion on it, and its frame ring.
pub struct Host {
    // Drop order matters: Combustion's objects go before the host's device.
    /// Per scene (by index), the environment its frames are lit by in place of its own
    /// (`FrameInputs::environment`); none where absent.
    pub frame_environments: Vec<Option<FrameEnvironment>>,
    pub scenes: Vec<GpuScene>,
    pub renderer: Option<Renderer>,
    pub combustion_device: Option<Arc<Device>>,
    slots: Vec<HostSlot>,
    pub viewport: Option<Viewport>,
    pub frame: u64,
    /// How long each `Renderer::record` call took on the CPU, ms (the last 4,096).
    pub record_ms: std::collections::VecDeque<f64>,
    pub vulkan: HostVulkan,
}

impl Host {
    pub fn new(
        vulkan: HostVulkan,
        frames_in_flight: usize,
        scenes: &[Scene],
    ) -> Result<Self, String> {
        let settings = RendererSettings {
            frames_in_flight,
            ..RendererSettings::default()
        };
        Self::with_settings(vulkan, settings, scenes)
    }

    /// As [`Host::new`], with Combustion's renderer made with `settings` (its frames
    /// in flight are the host's).
    pub fn with_settings(
        vulkan: HostVulkan,
        settings: RendererSettings,
        scenes: &[Scene],
    ) -> Result<Self, String> {
        let frames_in_flight = settings.frames_in_flight;
        let device = Device::from_host(vulkan.for_combustion()).map_err(|e| e.to_string())?;
        let mut renderer = Renderer::new(device.clone(), settings).map_err(|e| e.to_string())?;
        let gpu_scenes = scenes
            .iter()
            .map(|s| renderer.upload(s))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        let mut slots = Vec::new();
        for _ in 0..frames_in_flight {
            let (pool, cmd, fence) = vulkan.command_buffer(true)?;
            slots.push(HostSlot {
                pool,
                cmd,
                fence,
                retired: Vec::new(),
            });
        }
        Ok(Self {
            frame_environments: Vec::new(),
            scenes: gpu_scenes,
            renderer: Some(renderer),
            combustion_device: Some(device),
            slots,
            viewport: None,
            frame: 0,
            record_ms: std::collections::VecDeque::new(),
            vulkan,
        })
    }

    pub fn frames_in_flight(&self) -> usize {
        self.slots.len()
    }

    pub fn renderer(&mut self) -> &mut Renderer {
        self.renderer.as_mut().expect("alive until drop")
    }

    /// Begins frame `self.frame`: waits for the fence of the frame that used this slot
    /// (the only wait), frees what the host retired then, and begins its command buffer.
    pub fn begin_frame(&mut self) -> Result<(usize, vk::CommandBuffer), String> {
        let slot = (self.frame % self.slots.len() as u64) as usize;
        let d = &self.vulkan.device;
        let s = &mut self.slots[slot];
        unsafe { d.wait_for_fences(&[s.fence], true, u64::MAX) }.map_err(|e| e.to_string())?;
        for viewport in s.retired.drain(..) {
            viewport.destroy(&self.vulkan);
        }
        unsafe {
            d.reset_command_pool(s.pool, vk::CommandPoolResetFlags::empty())
                .map_err(|e| e.to_string())?;
            d.begin_command_buffer(
                s.cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .map_err(|e| e.to_string())?;
        }
        Ok((slot, s.cmd))
    }

    /// Ends and submits the frame begun with [`Host::begin_frame`].
    pub fn submit_frame(&mut self, slot: usize) -> Result<(), String> {
        self.submit_frame_with(slot, None)
    }

    /// As [`Host::submit_frame`], waiting for `wait` (at colour output and transfers)
    /// and signalling `signal` (a swapchain image's acquire and present semaphores).
    pub fn submit_frame_with(
        &mut self,
        slot: usize,
        semaphores: Option<(vk::Semaphore, vk::Semaphore)>,
    ) -> Result<(), String> {
        let s = &self.slots[slot];
        let d = &self.vulkan.device;
        unsafe { d.end_command_buffer(s.cmd) }.map_err(|e| e.to_string())?;
        unsafe { d.reset_fences(&[s.fence]) }.map_err(|e| e.to_string())?;
        self.vulkan.submit(s.cmd, s.fence, semaphores)?;
        self.frame += 1;
        Ok(())
    }

    /// Makes the viewport `extent`; an old one of another size is retired to the current
    /// slot (destroyed when that slot's fence has signalled), never waited for.
    pub fn ensure_viewport(&mut self, slot: usize, extent: vk::Extent2D) -> Result<(), String> {
        if self
            .viewport
            .as_ref()
            .is_some_and(|v| v.color.extent == extent)
        {
            return Ok(());
        }
        let new = Viewport::new(&self.vulkan, extent)?;
        if let Some(old) = self.viewport.replace(new) {
            self.slots[slot].retired.push(old);
        }
        Ok(())
    }

    /// Records the whole host frame into `cmd`: clear the final image, Combustion's
    /// frame into the viewport (scene `scene`, frame `n`'s camera and lights), the
    /// viewport blitted into the final image inside the border, and the host's bar.
    /// `final_image` is left in `final_after`.
    #[allow(clippy::too_many_arguments)]
    pub fn record_frame(
        &mut self,
        slot: usize,
        cmd: vk::CommandBuffer,
        scene: usize,
        final_image: FinalTarget,
        final_before: ImageState,
        final_after: ImageState,
    ) -> Result<(), String> {
        let n = self.frame;
        let extent = final_image.extent;
        let inner = vk::Extent2D {
            width: extent.width.saturating_sub(2 * BORDER).max(1),
            height: extent.height.saturating_sub(2 * BORDER).max(1),
        };
        self.ensure_viewport(slot, inner)?;
        let d = self.vulkan.device.clone();
        let color = vk::ImageAspectFlags::COLOR;

        // The host's own work before Combustion: clear its final image.
        barrier(
            &d,
            cmd,
            final_image.image,
            color,
            final_before,
            ImageState::BLIT_DESTINATION,
        );
        unsafe {
            d.cmd_clear_color_image(
                cmd,
                final_image.image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &vk::ClearColorValue {
                    float32: BACKGROUND,
                },
                &[range(color)],
            )
        };

        // Combustion's frame into the host's viewport and depth.
        let gpu_scene = &self.scenes[scene];
        let camera = camera_at(&gpu_scene.scene().camera, n);
        let lights = lights_at(&gpu_scene.scene().lights, n);
        let pose = pose_at(gpu_scene.scene(), n);
        let inputs = FrameInputs {
            camera,
            exposure: 1.0,
            lights: &lights,
            overlay: &[],
            environment: self.frame_environments.get(scene).and_then(Option::as_ref),
            background: combustion::renderer::Background::None,
            tone_mapping: combustion::renderer::ToneMapping::Exponential,
            pose: pose.as_ref(),
            // Sampled environment light (ShadingOptions::environment_samples) would take
            // another sample set each frame; the split sum ignores it.
            environment_seed: (n % 1024) as u32,
            anti_aliasing: combustion::renderer::AntiAliasing::None,
            auto_exposure: None,
            bloom_intensity: combustion::renderer::DEFAULT_BLOOM_INTENSITY,
        };
        let viewport = self.viewport.as_mut().expect("ensured");
        let target = FrameTarget {
            color: viewport
                .color
                .color_target(viewport.color_state, ImageState::BLIT_SOURCE)?,
            depth: Some(viewport.depth.depth_target(
                viewport.depth_state,
                ImageState::DEPTH_ATTACHMENT_READ_WRITE,
            )?),
        };
        let renderer = self.renderer.as_mut().expect("alive until drop");
        let started = std::time::Instant::now();
        renderer
            .record(cmd, slot, &self.scenes[scene], &inputs, &target)
            .map_err(|e| e.to_string())?;
        if self.record_ms.len() == 4096 {
            self.record_ms.pop_front();
        }
        self.record_ms
            .push_back(started.elapsed().as_secs_f64() * 1e3);
        viewport.color_state = ImageState::BLIT_SOURCE;
        viewport.depth_state = ImageState::DEPTH_ATTACHMENT_READ_WRITE;

        // Compose on the device: the viewport into the final image, 1:1, after the clear.
        barrier(
            &d,
            cmd,
            final_image.image,
            color,
            ImageState::BLIT_DESTINATION,
            ImageState::BLIT_DESTINATION,
        );
        let blit = vk::ImageBlit::default()
            .src_subresource(layers(color))
            .src_offsets([
                vk::Offset3D::default(),
                vk::Offset3D {
                    x: inner.width as i32,
                    y: inner.height as i32,
                    z: 1,
                },
            ])
            .dst_subresource(layers(color))
            .dst_offsets([
                vk::Offset3D {
                    x: BORDER as i32,
                    y: BORDER as i32,
                    z: 0,
                },
                vk::Offset3D {
                    x: (BORDER + inner.width) as i32,
                    y: (BORDER + inner.height) as i32,
                    z: 1,
                },
            ]);
        unsafe {
            d.cmd_blit_image(
                cmd,
                viewport.color.image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                final_image.image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[blit],
                vk::Filter::NEAREST,
            )
        };

        // The host draws its own: a bar across the top border, in a rendering pass of
        // its own on the final image.
        barrier(
            &d,
            cmd,
            final_image.image,
            color,
            ImageState::BLIT_DESTINATION,
            ImageState::COLOR_ATTACHMENT_READ_WRITE,
        );
        let attachment = [vk::RenderingAttachmentInfo::default()
            .image_view(final_image.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let rendering = vk::RenderingInfo::default()
            .render_area(vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent,
            })
            .layer_count(1)
            .color_attachments(&attachment);
        unsafe {
            d.cmd_begin_rendering(cmd, &rendering);
            d.cmd_clear_attachments(
                cmd,
                &[vk::ClearAttachment {
                    aspect_mask: color,
                    color_attachment: 0,
                    clear_value: vk::ClearValue {
                        color: vk::ClearColorValue { float32: BAR },
                    },
                }],
                &[vk::ClearRect {
                    rect: vk::Rect2D {
                        offset: vk::Offset2D { x: 0, y: 0 },
                        extent: vk::Extent2D {
                            width: extent.width,
                            height: (BORDER / 2).min(extent.height),
                        },
                    },
                    base_array_layer: 0,
                    layer_count: 1,
                }],
            );
            d.cmd_end_rendering(cmd);
        }
        barrier(
            &d,
            cmd,
            final_image.image,
            color,
            ImageState::COLOR_ATTACHMENT_READ_WRITE,
            final_after,
        );
        Ok(())
    }

    /// Waits for the host's own frames (its fences; never the device).
    pub fn wait_frames(&self) -> Result<(), String> {
        let fences: Vec<_> = self.slots.iter().map(|s| s.fence).collect();
        unsafe { self.vulkan.device.wait_for_fences(&fences, true, u64::MAX) }
            .map_err(|e| e.to_string())
    }
}

impl Drop for Host {
    fn drop(&mut self) {
        // The GPU must be done with everything before anything goes: the host's fences.
        if let Err(e) = self.wait_frames() {
            eprintln!("waiting for the host's frames: {e}");
        }
        self.frame_environments.clear();
        self.scenes.clear();
        self.renderer = None;
        self.combustion_device = None;
        let d = &self.vulkan.device;
        for s in self.slots.drain(..) {
            for viewport in s.retired {
                viewport.destroy(&self.vulkan);
            }
            unsafe {
                d.destroy_fence(s.fence, None);
                d.destroy_command_pool(s.pool, None);
            }
        }
        if let Some(viewport) = self.viewport.take() {
            viewport.destroy(&self.vulkan);
        }
    }
}
