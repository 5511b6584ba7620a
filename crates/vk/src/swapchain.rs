//! Presenting to a window: a [`Surface`] and a [`Swapchain`] that shows CPU-side RGBA8
//! frames.
//!
//! The swapchain does not render into its images. [`Swapchain::present_rgba8`] copies
//! pixels the renderer already read back (the tonemapped, sRGB-encoded display image)
//! into a host-visible staging buffer and from there, with `vkCmdCopyBufferToImage`,
//! into the acquired image. This keeps the renderer exactly as it is for headless use;
//! the extra copy is cheap on lavapipe, where "GPU" memory is host memory anyway, and a
//! device-side blit can replace it when a real GPU makes it matter.

use std::ffi::CStr;
use std::sync::Arc;

use ash::{khr, vk};
use gpu_allocator::MemoryLocation;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::device::Device;
use crate::error::{VkError, VkResultExt};
use crate::resources::Buffer;

/// How long acquiring an image may take before the frame is given up as an error.
const ACQUIRE_TIMEOUT_NS: u64 = 10_000_000_000;

/// A `VkSurfaceKHR` for one window. Destroyed when dropped: after every [`Swapchain`]
/// made on it (which [`Swapchain::new`]'s borrow does not enforce) and before the window.
pub struct Surface {
    device: Arc<Device>,
    loader: khr::surface::Instance,
    raw: vk::SurfaceKHR,
}

impl Surface {
    /// The instance extensions a surface on this display needs; give them to
    /// [`crate::DeviceDesc::instance_extensions`].
    pub fn instance_extensions(display: RawDisplayHandle) -> Result<Vec<&'static CStr>, VkError> {
        let names = ash_window::enumerate_required_extensions(display).map_err(|_| {
            VkError::Unsupported(format!(
                "Vulkan cannot present on this window system ({display:?})"
            ))
        })?;
        // SAFETY: ash-window returns pointers to ash's static, NUL-terminated names.
        Ok(names
            .iter()
            .map(|&p| unsafe { CStr::from_ptr(p) })
            .collect())
    }

    /// Creates a surface for a window and checks that the device's queue can present to it.
    ///
    /// # Safety
    /// The handles must be valid and stay valid until the surface is dropped; `device`
    /// must have been created with [`Surface::instance_extensions`] of this display.
    pub unsafe fn new(
        device: &Arc<Device>,
        display: RawDisplayHandle,
        window: RawWindowHandle,
    ) -> Result<Surface, VkError> {
        let raw =
            ash_window::create_surface(device.entry(), device.instance(), display, window, None)
                .what("vkCreateSurfaceKHR")?;
        let surface = Surface {
            device: device.clone(),
            loader: khr::surface::Instance::new(device.entry(), device.instance()),
            raw,
        };
        let supported = surface
            .loader
            .get_physical_device_surface_support(
                device.physical_device(),
                device.queue_family(),
                raw,
            )
            .what("vkGetPhysicalDeviceSurfaceSupportKHR")?;
        if !supported {
            return Err(VkError::Unsupported(format!(
                "Vulkan device {} cannot present to this window (its graphics queue has no presentation support); pick another with --device",
                device.info().name
            )));
        }
        Ok(surface)
    }

    pub fn raw(&self) -> vk::SurfaceKHR {
        self.raw
    }

    /// Sizes, image counts, usages and transforms the surface allows now.
    fn capabilities(&self) -> Result<vk::SurfaceCapabilitiesKHR, VkError> {
        // SAFETY: valid handles.
        unsafe {
            self.loader
                .get_physical_device_surface_capabilities(self.device.physical_device(), self.raw)
        }
        .what("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: swapchains on this surface are dropped first (see the type's docs).
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}

/// What [`Swapchain::present_rgba8`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PresentOutcome {
    /// The frame is on its way to the screen.
    Presented,
    /// The frame was shown, but the swapchain no longer matches the surface well.
    PresentedSuboptimal,
    /// The swapchain no longer matches the surface (e.g. after a resize); nothing was
    /// shown. Recreate the swapchain.
    OutOfDate,
}

/// A swapchain with what it takes to copy CPU frames into its images: a command pool and
/// buffer, a fence, semaphores, and a host-visible staging buffer. Everything is
/// destroyed when dropped (after the device is idle). One frame is in flight at most:
/// each present waits for the previous copy to finish.
pub struct Swapchain {
    // The raw objects are destroyed in `Drop::drop`, before `staging` is freed.
    staging: Buffer,
    device: Arc<Device>,
    loader: khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    format: vk::Format,
    extent: vk::Extent2D,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    image_available: vk::Semaphore,
    /// One per swapchain image: signalled by the copy, waited on by the present.
    copy_done: Vec<vk::Semaphore>,
}

/// The swapchain formats that take sRGB-encoded bytes as they are, and whether the
/// red and blue channels are swapped relative to RGBA.
const UNORM_FORMATS: [(vk::Format, bool); 2] = [
    (vk::Format::B8G8R8A8_UNORM, true),
    (vk::Format::R8G8B8A8_UNORM, false),
];

impl Swapchain {
    /// Creates a swapchain of about `width`×`height` (the surface may dictate its own
    /// size: see [`Swapchain::extent`]). Drop the previous swapchain of the surface first.
    ///
    /// The image format is B8G8R8A8_UNORM or R8G8B8A8_UNORM: the frames are already
    /// sRGB-encoded, so an `_SRGB` format would encode them twice.
    pub fn new(
        device: &Arc<Device>,
        surface: &Surface,
        width: u32,
        height: u32,
    ) -> Result<Swapchain, VkError> {
        let pd = device.physical_device();
        let caps = surface.capabilities()?;
        // SAFETY: valid handles.
        let formats = unsafe {
            surface
                .loader
                .get_physical_device_surface_formats(pd, surface.raw)
        }
        .what("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
        let format = UNORM_FORMATS
            .iter()
            .find_map(|&(f, _)| {
                formats
                    .iter()
                    .find(|s| s.format == f && s.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR)
            })
            .copied()
            .ok_or_else(|| {
                VkError::Unsupported(format!(
                    "the window offers no B8G8R8A8_UNORM or R8G8B8A8_UNORM swapchain format (only {:?}); the viewer copies already sRGB-encoded bytes, which an _SRGB format would encode twice",
                    formats.iter().map(|f| f.format).collect::<Vec<_>>()
                ))
            })?;
        if !caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_DST)
        {
            return Err(VkError::Unsupported(
                "the window's swapchain images cannot be copied into (no TRANSFER_DST usage)"
                    .into(),
            ));
        }
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: width.clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: height.clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        if extent.width == 0 || extent.height == 0 {
            return Err(VkError::Unsupported(
                "the window has no area to present to".into(),
            ));
        }
        let mut image_count = caps.min_image_count + 1;
        if caps.max_image_count != 0 {
            image_count = image_count.min(caps.max_image_count);
        }
        let composite_alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|&a| caps.supported_composite_alpha.contains(a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE);
        let staging = Buffer::new(
            device,
            "swapchain staging",
            u64::from(extent.width) * u64::from(extent.height) * 4,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        let loader = khr::swapchain::Device::new(device.instance(), device.raw());
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(image_count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::TRANSFER_DST)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(composite_alpha)
            // FIFO: always available, no tearing; the renderer is slower than any
            // refresh rate on lavapipe anyway.
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true);
        // SAFETY: valid create info; from here on Drop destroys whatever was created.
        let raw = unsafe { loader.create_swapchain(&info, None) }.what("vkCreateSwapchainKHR")?;
        let mut this = Swapchain {
            staging,
            device: device.clone(),
            loader,
            raw,
            images: Vec::new(),
            format: format.format,
            extent,
            pool: vk::CommandPool::null(),
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            image_available: vk::Semaphore::null(),
            copy_done: Vec::new(),
        };
        let rd = device.raw();
        unsafe {
            this.images = this
                .loader
                .get_swapchain_images(raw)
                .what("vkGetSwapchainImagesKHR")?;
            let pool_info = vk::CommandPoolCreateInfo::default()
                .queue_family_index(device.queue_family())
                .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
            this.pool = rd
                .create_command_pool(&pool_info, None)
                .what("vkCreateCommandPool")?;
            let alloc = vk::CommandBufferAllocateInfo::default()
                .command_pool(this.pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(1);
            this.cmd = rd
                .allocate_command_buffers(&alloc)
                .what("vkAllocateCommandBuffers")?[0];
            let fence_info = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
            this.fence = rd.create_fence(&fence_info, None).what("vkCreateFence")?;
            let semaphore_info = vk::SemaphoreCreateInfo::default();
            this.image_available = rd
                .create_semaphore(&semaphore_info, None)
                .what("vkCreateSemaphore")?;
            for _ in 0..this.images.len() {
                let s = rd
                    .create_semaphore(&semaphore_info, None)
                    .what("vkCreateSemaphore")?;
                this.copy_done.push(s);
            }
        }
        log::info!(
            "swapchain: {} images of {}x{} {:?}",
            this.images.len(),
            extent.width,
            extent.height,
            format.format
        );
        Ok(this)
    }

    /// The size of the swapchain's images: render frames at this size.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    pub fn format(&self) -> vk::Format {
        self.format
    }

    /// Shows `pixels` — `extent().width × extent().height` RGBA8 texels, rows top-down,
    /// already sRGB-encoded (the renderer's `Frame::ldr`) — in the next swapchain image.
    /// Alpha is ignored (the window is opaque).
    pub fn present_rgba8(&mut self, pixels: &[[u8; 4]]) -> Result<PresentOutcome, VkError> {
        let (w, h) = (self.extent.width, self.extent.height);
        if pixels.len() != (w as usize) * (h as usize) {
            return Err(VkError::Unsupported(format!(
                "a frame of {} pixels does not fit a {w}x{h} swapchain",
                pixels.len()
            )));
        }
        let rd = self.device.raw();
        // The previous copy must be done before the staging buffer and command buffer
        // are reused.
        unsafe { rd.wait_for_fences(&[self.fence], true, ACQUIRE_TIMEOUT_NS) }
            .what("vkWaitForFences")?;
        // SAFETY: valid handles; the semaphore is unsignalled (the last submit waited on it).
        let acquired = unsafe {
            self.loader.acquire_next_image(
                self.raw,
                ACQUIRE_TIMEOUT_NS,
                self.image_available,
                vk::Fence::null(),
            )
        };
        let (index, suboptimal) = match acquired {
            Ok(r) => r,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => return Ok(PresentOutcome::OutOfDate),
            Err(result) => {
                return Err(VkError::Vk {
                    what: "vkAcquireNextImageKHR",
                    result,
                })
            }
        };
        let swap_red_blue = UNORM_FORMATS
            .iter()
            .any(|&(f, swap)| f == self.format && swap);
        let bytes: Vec<u8> = pixels
            .iter()
            .flat_map(|&[r, g, b, _]| {
                if swap_red_blue {
                    [b, g, r, 255]
                } else {
                    [r, g, b, 255]
                }
            })
            .collect();
        self.staging.write(0, &bytes)?;

        use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
        let image = self.images[index as usize];
        let range = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        };
        let to_dst = vk::ImageMemoryBarrier2::default()
            .src_stage_mask(S::COPY)
            .src_access_mask(A::NONE)
            .old_layout(L::UNDEFINED)
            .dst_stage_mask(S::COPY)
            .dst_access_mask(A::TRANSFER_WRITE)
            .new_layout(L::TRANSFER_DST_OPTIMAL)
            .image(image)
            .subresource_range(range);
        let to_present = vk::ImageMemoryBarrier2::default()
            .src_stage_mask(S::COPY)
            .src_access_mask(A::TRANSFER_WRITE)
            .old_layout(L::TRANSFER_DST_OPTIMAL)
            .dst_stage_mask(S::NONE)
            .dst_access_mask(A::NONE)
            .new_layout(L::PRESENT_SRC_KHR)
            .image(image)
            .subresource_range(range);
        let region = vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            })
            .image_extent(vk::Extent3D {
                width: w,
                height: h,
                depth: 1,
            });
        let copy_done = self.copy_done[index as usize];
        // SAFETY: the fence wait above makes the command buffer and staging buffer free;
        // the image was acquired and is only touched after `image_available`.
        unsafe {
            rd.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty())
                .what("vkResetCommandBuffer")?;
            rd.begin_command_buffer(
                self.cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .what("vkBeginCommandBuffer")?;
            rd.cmd_pipeline_barrier2(
                self.cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&[to_dst]),
            );
            rd.cmd_copy_buffer_to_image(
                self.cmd,
                self.staging.raw(),
                image,
                L::TRANSFER_DST_OPTIMAL,
                &[region],
            );
            rd.cmd_pipeline_barrier2(
                self.cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&[to_present]),
            );
            rd.end_command_buffer(self.cmd).what("vkEndCommandBuffer")?;
            let waits = [vk::SemaphoreSubmitInfo::default()
                .semaphore(self.image_available)
                .stage_mask(S::COPY)];
            let signals = [vk::SemaphoreSubmitInfo::default()
                .semaphore(copy_done)
                .stage_mask(S::COPY)];
            let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
            let submit = [vk::SubmitInfo2::default()
                .wait_semaphore_infos(&waits)
                .command_buffer_infos(&cmds)
                .signal_semaphore_infos(&signals)];
            rd.reset_fences(&[self.fence]).what("vkResetFences")?;
            self.device.submit(&submit, self.fence)?;
        }
        let wait = [copy_done];
        let swapchains = [self.raw];
        let indices = [index];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        let queue = self.device.queue();
        // SAFETY: the queue is externally synchronised by the device's mutex.
        match unsafe { self.loader.queue_present(*queue, &present) } {
            Ok(false) if !suboptimal => Ok(PresentOutcome::Presented),
            Ok(_) => Ok(PresentOutcome::PresentedSuboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(PresentOutcome::OutOfDate),
            Err(result) => Err(VkError::Vk {
                what: "vkQueuePresentKHR",
                result,
            }),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        if let Err(e) = self.device.wait_idle() {
            log::error!("waiting for the device before destroying the swapchain: {e}");
        }
        let rd = self.device.raw();
        // SAFETY: the device is idle, so nothing uses these objects any more.
        unsafe {
            for &s in &self.copy_done {
                rd.destroy_semaphore(s, None);
            }
            if self.image_available != vk::Semaphore::null() {
                rd.destroy_semaphore(self.image_available, None);
            }
            if self.fence != vk::Fence::null() {
                rd.destroy_fence(self.fence, None);
            }
            if self.pool != vk::CommandPool::null() {
                rd.destroy_command_pool(self.pool, None);
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
    }
}
