#![allow(dead_code)] // shared with tests/host.rs, which uses a different part of it
//! The host without a window: its final image is an offscreen image. Runs a number of
//! frames, or a soak (scene edits every few frames, resizes every few hundred, memory
//! reported every 1,000), and can read its final image back once at the end (for tests;
//! never in the frame loop).

use combustion::scene::Scene;
use combustion::vk::ash::vk;
use combustion::vk::gpu_allocator::vulkan::{AllocationCreateDesc, AllocationScheme};
use combustion::vk::gpu_allocator::MemoryLocation;
use combustion::vk::ImageState;

use crate::app::{barrier, Host, HostImage};

/// The host's offscreen final image and the state it was left in.
pub struct FinalImage {
    pub image: HostImage,
    pub state: ImageState,
}

impl FinalImage {
    pub fn new(host: &Host, extent: vk::Extent2D) -> Result<Self, String> {
        Ok(Self {
            image: HostImage::new(
                &host.vulkan,
                "host final image",
                vk::Format::R8G8B8A8_UNORM,
                extent,
                vk::ImageUsageFlags::COLOR_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSFER_DST
                    | vk::ImageUsageFlags::TRANSFER_SRC,
            )?,
            state: ImageState::UNDEFINED,
        })
    }
}

/// Records and submits one host frame of `scene` into `output`.
pub fn frame(host: &mut Host, output: &mut FinalImage, scene: usize) -> Result<(), String> {
    let (slot, cmd) = host.begin_frame()?;
    host.record_frame(
        slot,
        cmd,
        scene,
        (&output.image).into(),
        output.state,
        ImageState::COPY_SOURCE,
    )?;
    output.state = ImageState::COPY_SOURCE;
    host.submit_frame(slot)
}

/// Memory in use at one point of a soak.
#[derive(Clone, Copy, Debug)]
pub struct MemorySample {
    pub frame: u64,
    /// Resident set size of the process, bytes (from /proc/self/statm).
    pub rss_bytes: u64,
    /// Live allocations in the shared GPU allocator (host and Combustion).
    pub allocations: usize,
    /// Bytes those allocations take, alignment padding included (so it varies a little
    /// with where they were placed).
    pub allocated_bytes: u64,
    /// Bytes of device memory the allocator holds (its blocks).
    pub capacity_bytes: u64,
}

/// The process's resident set size in bytes (0 where /proc is missing).
pub fn rss_bytes() -> u64 {
    let page = 4096;
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<u64>().ok())
        .map_or(0, |pages| pages * page)
}

/// What a soak does, and how often.
#[derive(Clone, Copy, Debug)]
pub struct SoakPlan {
    pub frames: u64,
    /// Every this many frames the current scene is edited: an object moved, with
    /// `Renderer::edit_scene` three times in four and by uploading the scene anew (the
    /// old upload dropped, not waited for) the fourth.
    pub edit_every: u64,
    /// The scenes alternate every this many frames.
    pub scene_every: u64,
    /// The final image (and so Combustion's viewport) alternates between the two sizes
    /// every this many frames.
    pub resize_every: u64,
    /// Memory is reported every this many frames.
    pub report_every: u64,
    pub sizes: [vk::Extent2D; 2],
}

impl SoakPlan {
    /// The frames after which the whole pattern repeats: edits, scenes, sizes, the
    /// frame's lights, and which frame slot each frame uses.
    pub fn period(&self, frames_in_flight: u64) -> u64 {
        let lcm = |a: u64, b: u64| {
            let (mut x, mut y) = (a, b);
            while y != 0 {
                (x, y) = (y, x % y);
            }
            a / x * b
        };
        // Edits cycle through 4 positions; scenes through 2 (the tests' soaks alternate
        // two); sizes through 2.
        let pattern = lcm(
            lcm(4 * self.edit_every, 2 * self.scene_every),
            2 * self.resize_every,
        );
        lcm(
            lcm(pattern, crate::app::EXTRA_LIGHT_EVERY),
            frames_in_flight,
        )
    }
}

/// Soak: frames with the plan's edits, scene changes and resizes; lights and camera
/// change every frame. Calls `report` with the memory every `plan.report_every` frames.
pub fn soak(
    host: &mut Host,
    scenes: &[Scene],
    plan: &SoakPlan,
    mut report: impl FnMut(MemorySample),
) -> Result<(), String> {
    let (sizes, frames, every) = (plan.sizes, plan.frames, plan.report_every);
    let mut size_index = 0;
    let mut output = FinalImage::new(host, sizes[0])?;
    let mut retired_outputs: Vec<(u64, FinalImage)> = Vec::new();
    for n in 0..frames {
        if n > 0 && n % plan.resize_every == 0 {
            size_index = 1 - size_index;
            let new = FinalImage::new(host, sizes[size_index])?;
            // Destroyed once every frame that used it has completed.
            retired_outputs.push((host.frame, std::mem::replace(&mut output, new)));
        }
        let in_flight = host.frames_in_flight() as u64;
        let (done, kept): (Vec<_>, Vec<_>) = retired_outputs
            .drain(..)
            .partition(|(frame, _)| host.frame >= frame + in_flight);
        retired_outputs = kept;
        if !done.is_empty() {
            // Their last frame's slot has been waited for by `begin_frame` since.
            for (_, old) in done {
                old.image.destroy(&host.vulkan);
            }
        }
        let scene = ((n / plan.scene_every) % scenes.len() as u64) as usize;
        if n % plan.edit_every == 0 {
            // The first object moves to one of four places; three edits in four go
            // through `edit_scene` (only the tables are rebuilt), the fourth uploads the
            // edited scene anew and retires the old upload.
            let step = (n / plan.edit_every) % 4;
            let original = scenes[scene].objects.first().map(|o| o.transform);
            let place = move |edited: &mut Scene| {
                if let (Some(object), Some(original)) = (edited.objects.first_mut(), original) {
                    let shift = glam::Vec3::new(0.1 * step as f32, 0.0, 0.0);
                    object.transform = glam::Mat4::from_translation(shift) * original;
                }
            };
            if step == 3 {
                let mut edited = scenes[scene].clone();
                place(&mut edited);
                let upload = host.renderer().upload(&edited).map_err(|e| e.to_string())?;
                // The old upload is dropped while frames in flight read it: Combustion
                // keeps its resources until those frames have completed.
                drop(std::mem::replace(&mut host.scenes[scene], upload));
            } else {
                let renderer = host.renderer.as_mut().expect("alive until drop");
                renderer
                    .edit_scene(&mut host.scenes[scene], place)
                    .map_err(|e| e.to_string())?;
            }
        }
        frame(host, &mut output, scene)?;
        if (n + 1) % every == 0 {
            let (allocations, allocated_bytes, capacity_bytes) = host.vulkan.allocator_usage();
            report(MemorySample {
                frame: n + 1,
                rss_bytes: rss_bytes(),
                allocations,
                allocated_bytes,
                capacity_bytes,
            });
        }
    }
    host.wait_frames()?;
    for (_, old) in retired_outputs {
        old.image.destroy(&host.vulkan);
    }
    output.image.destroy(&host.vulkan);
    Ok(())
}

/// Copies `image` (in `from`) to host memory after waiting for the host's frames; for
/// tests and screenshots, never in the frame loop. Tightly packed texels of the image's
/// format (4 bytes for RGBA8 and D32, 8 for RGBA16F, 16 for RGBA32F).
pub fn read_back(
    host: &Host,
    image: &HostImage,
    from: ImageState,
    aspect: vk::ImageAspectFlags,
) -> Result<Vec<u8>, String> {
    host.wait_frames()?;
    let v = &host.vulkan;
    let d = &v.device;
    let bytes_per_texel = match image.format {
        vk::Format::R16G16B16A16_SFLOAT => 8,
        vk::Format::R32G32B32A32_SFLOAT => 16,
        _ => 4,
    };
    let size = u64::from(image.extent.width) * u64::from(image.extent.height) * bytes_per_texel;
    let buffer = unsafe {
        d.create_buffer(
            &vk::BufferCreateInfo::default()
                .size(size)
                .usage(vk::BufferUsageFlags::TRANSFER_DST),
            None,
        )
    }
    .map_err(|e| e.to_string())?;
    let requirements = unsafe { d.get_buffer_memory_requirements(buffer) };
    let allocation = v
        .allocator
        .lock()
        .map_err(|_| "allocator lock")?
        .allocate(&AllocationCreateDesc {
            name: "host readback",
            requirements,
            location: MemoryLocation::GpuToCpu,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })
        .map_err(|e| e.to_string())?;
    unsafe { d.bind_buffer_memory(buffer, allocation.memory(), allocation.offset()) }
        .map_err(|e| e.to_string())?;
    let (pool, cmd, fence) = v.command_buffer(false)?;
    unsafe {
        d.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())
            .map_err(|e| e.to_string())?;
    }
    barrier(d, cmd, image.image, aspect, from, ImageState::COPY_SOURCE);
    let region = vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: aspect,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(vk::Extent3D {
            width: image.extent.width,
            height: image.extent.height,
            depth: 1,
        });
    unsafe {
        d.cmd_copy_image_to_buffer(
            cmd,
            image.image,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            buffer,
            &[region],
        );
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&to_host),
        );
        d.end_command_buffer(cmd).map_err(|e| e.to_string())?;
    }
    v.submit(cmd, fence, None)?;
    unsafe { d.wait_for_fences(&[fence], true, u64::MAX) }.map_err(|e| e.to_string())?;
    let bytes = allocation
        .mapped_slice()
        .map(|s| s[..size as usize].to_vec())
        .ok_or("readback memory is not mapped")?;
    unsafe {
        d.destroy_fence(fence, None);
        d.destroy_command_pool(pool, None);
        d.destroy_buffer(buffer, None);
    }
    if let Ok(mut a) = v.allocator.lock() {
        let _ = a.free(allocation);
    }
    Ok(bytes)
}
