//! Presenting to a window: a [`Surface`] and a [`Swapchain`] whose images frames are
//! rendered into on the device.
//!
//! A frame acquires an image ([`Swapchain::acquire`], signalling the frame slot's
//! semaphore), renders into its view (the renderer's output pass writes the swapchain
//! image directly: `COLOR_ATTACHMENT` usage, an 8-bit UNORM format that takes the
//! shader's exact sRGB encoding), waits for the acquisition and signals the image's
//! "rendered" semaphore in its submission, and presents ([`Swapchain::present`]). No
//! pixel goes through the CPU.

use std::ffi::CStr;
use std::sync::Arc;

use ash::{khr, vk};
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::device::Device;
use crate::error::{VkError, VkResultExt};

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
    ///
    /// # Errors
    /// [`VkError::Unsupported`] when Vulkan cannot present on this window system.
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
    ///
    /// # Errors
    /// [`VkError::Unsupported`] when the device's queue cannot present to the window;
    /// [`VkError`] when a Vulkan call fails.
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
                "Vulkan device {} cannot present to this window (the queue Combustion submits to has no presentation support); pick another with --device",
                device.info().name
            )));
        }
        Ok(surface)
    }

    /// The Vulkan surface, valid while `self` lives.
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

/// What a present did.
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

/// An image acquired for one frame.
#[derive(Clone, Copy, Debug)]
pub struct AcquiredImage {
    /// The image's index in the swapchain (what the present names).
    pub index: u32,
    /// The swapchain image, in an undefined layout until the frame moves it (see
    /// [`crate::ImageState::SWAPCHAIN_ACQUIRED`]).
    pub image: vk::Image,
    /// A 2D colour view of the image.
    pub view: vk::ImageView,
    /// Signalled when the image may be written: the frame's submission waits for it.
    pub acquired: vk::Semaphore,
    /// The frame's submission signals it; the present waits for it.
    pub rendered: vk::Semaphore,
    /// The swapchain still works but no longer matches the surface: recreate it after
    /// this frame.
    pub suboptimal: bool,
}

/// A swapchain whose images are rendered into on the device, with one acquisition
/// semaphore per frame in flight and one "rendered" semaphore per image. Drop it only
/// when its queue has drained (presents wait for its semaphores, and no fence tells when
/// they are done): the viewer waits for its own device once per recreation. Nothing
/// here waits for the device.
pub struct Swapchain {
    device: Arc<Device>,
    loader: khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    views: Vec<vk::ImageView>,
    format: vk::Format,
    extent: vk::Extent2D,
    present_mode: vk::PresentModeKHR,
    /// The images can be copied from (`TRANSFER_SRC`).
    copyable: bool,
    /// Per frame slot: signalled by the acquisition of that slot's image.
    acquired: Vec<vk::Semaphore>,
    /// Per image: signalled by the frame rendered into it, waited for by its present.
    rendered: Vec<vk::Semaphore>,
}

/// The swapchain formats the renderer's output pass writes with the exact sRGB encoding.
const UNORM_FORMATS: [vk::Format; 2] = [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM];

impl Swapchain {
    /// Creates a swapchain of about `width`×`height` (the surface may dictate its own
    /// size: see [`Swapchain::extent`]) for `frames_in_flight` frames. `vsync`: FIFO
    /// (wait for the display's refresh); without it MAILBOX or IMMEDIATE where the
    /// surface offers one, else FIFO. Drop the previous swapchain of the surface first.
    ///
    /// The image format is B8G8R8A8_UNORM or R8G8B8A8_UNORM: the renderer encodes sRGB
    /// exactly in its shader, which an `_SRGB` format would do again.
    ///
    /// # Errors
    /// [`VkError::Unsupported`] when the surface offers neither format, cannot be
    /// rendered into, or has no area (a minimised window); [`VkError`] when a Vulkan call
    /// fails.
    pub fn new(
        device: &Arc<Device>,
        surface: &Surface,
        width: u32,
        height: u32,
        vsync: bool,
        frames_in_flight: usize,
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
            .find_map(|&f| {
                formats
                    .iter()
                    .find(|s| s.format == f && s.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR)
            })
            .copied()
            .ok_or_else(|| {
                VkError::Unsupported(format!(
                    "the window offers no B8G8R8A8_UNORM or R8G8B8A8_UNORM swapchain format (only {:?}); the renderer encodes sRGB itself, which an _SRGB format would do twice",
                    formats.iter().map(|f| f.format).collect::<Vec<_>>()
                ))
            })?;
        if !caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::COLOR_ATTACHMENT)
        {
            return Err(VkError::Unsupported(
                "the window's swapchain images cannot be rendered into (no COLOR_ATTACHMENT usage)"
                    .into(),
            ));
        }
        let modes = unsafe {
            surface
                .loader
                .get_physical_device_surface_present_modes(pd, surface.raw)
        }
        .what("vkGetPhysicalDeviceSurfacePresentModesKHR")?;
        let present_mode = if vsync {
            vk::PresentModeKHR::FIFO
        } else {
            [vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE]
                .into_iter()
                .find(|m| modes.contains(m))
                .unwrap_or(vk::PresentModeKHR::FIFO)
        };
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
        // Copies out of the images (screenshots) where the surface allows them.
        let copyable = caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_SRC);
        let loader = khr::swapchain::Device::new(device.instance(), device.raw());
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(image_count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(image_usage(copyable))
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(composite_alpha)
            .present_mode(present_mode)
            .clipped(true);
        // SAFETY: valid create info; from here on Drop destroys whatever was created.
        let raw = unsafe { loader.create_swapchain(&info, None) }.what("vkCreateSwapchainKHR")?;
        let mut this = Swapchain {
            device: device.clone(),
            loader,
            raw,
            images: Vec::new(),
            views: Vec::new(),
            format: format.format,
            extent,
            present_mode,
            copyable,
            acquired: Vec::new(),
            rendered: Vec::new(),
        };
        let rd = device.raw();
        let semaphore_info = vk::SemaphoreCreateInfo::default();
        unsafe {
            this.images = this
                .loader
                .get_swapchain_images(raw)
                .what("vkGetSwapchainImagesKHR")?;
            for &image in &this.images.clone() {
                let view_info = vk::ImageViewCreateInfo::default()
                    .image(image)
                    .view_type(vk::ImageViewType::TYPE_2D)
                    .format(format.format)
                    .subresource_range(vk::ImageSubresourceRange {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        base_mip_level: 0,
                        level_count: 1,
                        base_array_layer: 0,
                        layer_count: 1,
                    });
                this.views.push(
                    rd.create_image_view(&view_info, None)
                        .what("vkCreateImageView")?,
                );
                this.rendered.push(
                    rd.create_semaphore(&semaphore_info, None)
                        .what("vkCreateSemaphore")?,
                );
            }
            for _ in 0..frames_in_flight.max(1) {
                this.acquired.push(
                    rd.create_semaphore(&semaphore_info, None)
                        .what("vkCreateSemaphore")?,
                );
            }
        }
        log::info!(
            "swapchain: {} images of {}x{} {:?}, {:?}",
            this.images.len(),
            extent.width,
            extent.height,
            format.format,
            present_mode
        );
        Ok(this)
    }

    /// The size of the swapchain's images: render frames at this size.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// The images' format (B8G8R8A8_UNORM or R8G8B8A8_UNORM).
    pub fn format(&self) -> vk::Format {
        self.format
    }

    /// The present mode chosen (FIFO with vsync; else MAILBOX, IMMEDIATE or FIFO).
    pub fn present_mode(&self) -> vk::PresentModeKHR {
        self.present_mode
    }

    /// Whether the images can be copied from (for screenshots).
    pub fn copyable(&self) -> bool {
        self.copyable
    }

    /// The usage flags the images were created with.
    pub fn image_usage(&self) -> vk::ImageUsageFlags {
        image_usage(self.copyable)
    }

    /// Acquires the next image for the frame in `frame_slot` (whose previous frame has
    /// completed, so its semaphore is free). `Ok(None)`: the swapchain is out of date;
    /// recreate it. Waits at most 10 s for an image.
    ///
    /// # Errors
    /// [`VkError`] when the acquisition fails or times out (e.g. [`VkError::DeviceLost`],
    /// or a lost surface).
    pub fn acquire(&self, frame_slot: usize) -> Result<Option<AcquiredImage>, VkError> {
        let acquired = self.acquired[frame_slot % self.acquired.len()];
        // SAFETY: valid handles; the semaphore is unsignalled (its last wait completed).
        let result = unsafe {
            self.loader.acquire_next_image(
                self.raw,
                ACQUIRE_TIMEOUT_NS,
                acquired,
                vk::Fence::null(),
            )
        };
        match result {
            Ok((index, suboptimal)) => Ok(Some(AcquiredImage {
                index,
                image: self.images[index as usize],
                view: self.views[index as usize],
                acquired,
                rendered: self.rendered[index as usize],
                suboptimal,
            })),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(None),
            Err(result) => Err(VkError::from_result("vkAcquireNextImageKHR", result)),
        }
    }

    /// Presents `image` once its frame (submitted with `image.rendered` to signal) is done,
    /// on the device's queue (under its lock).
    ///
    /// # Errors
    /// [`VkError`] when the present fails other than by the swapchain being out of date
    /// (which is [`PresentOutcome::OutOfDate`]).
    pub fn present(&self, image: &AcquiredImage) -> Result<PresentOutcome, VkError> {
        let wait = [image.rendered];
        let swapchains = [self.raw];
        let indices = [image.index];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        let queue = self.device.queue();
        // SAFETY: the queue is externally synchronised by the device's lock.
        match unsafe { self.loader.queue_present(*queue, &present) } {
            Ok(false) if !image.suboptimal => Ok(PresentOutcome::Presented),
            Ok(_) => Ok(PresentOutcome::PresentedSuboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(PresentOutcome::OutOfDate),
            Err(result) => Err(VkError::from_result("vkQueuePresentKHR", result)),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        let rd = self.device.raw();
        // SAFETY: the caller has waited for every frame that used the swapchain (see the
        // type's docs); presents still pending hold only the swapchain, destroyed last.
        unsafe {
            for &s in self.acquired.iter().chain(&self.rendered) {
                rd.destroy_semaphore(s, None);
            }
            for &view in &self.views {
                rd.destroy_image_view(view, None);
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
    }
}

/// The swapchain images' usage: rendered into, and copied from where the surface allows.
fn image_usage(copyable: bool) -> vk::ImageUsageFlags {
    if copyable {
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC
    } else {
        vk::ImageUsageFlags::COLOR_ATTACHMENT
    }
}
