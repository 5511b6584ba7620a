#![allow(dead_code)] // shared with tests/host.rs, which uses a different part of it
//! The host with a window: its final image is the swapchain image it acquired. The
//! host owns the surface, the swapchain and the semaphores; Combustion only records into
//! the host's command buffer, as in the headless case.

use std::ffi::CStr;
use std::time::Instant;

use combustion::scene::Scene;
use combustion::vk::ash::{khr, vk};
use combustion::vk::ImageState;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

use crate::app::{FinalTarget, Host};
use crate::vulkan::HostVulkan;

/// How to run the windowed host.
#[derive(Clone, Debug)]
pub struct WindowOptions {
    pub width: u32,
    pub height: u32,
    /// Stop after this many presented frames (`None`: until the window is closed); with
    /// `resize_at`, not before the resize has arrived (at most ten times as many).
    pub frames: Option<u64>,
    pub frames_in_flight: usize,
    pub validation: bool,
    pub device: String,
    /// At this presented frame, ask the window for another size (a resize mid-run).
    pub resize_at: Option<(u64, u32, u32)>,
}

/// What a windowed run did.
#[derive(Clone, Debug, Default)]
pub struct WindowSummary {
    pub presented: u64,
    /// Swapchains created (1 + recreations after resizes and out-of-date swapchains).
    pub swapchains: u64,
    /// Wall-clock time between presented frames, ms.
    pub frame_ms: Vec<f64>,
    /// Combustion's GPU time per completed frame, ms.
    pub gpu_ms: Vec<f64>,
    pub validation_messages: Vec<String>,
}

/// The host's swapchain and what goes with each of its images.
struct HostSwapchain {
    loader: khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    views: Vec<vk::ImageView>,
    /// Signalled when the frame rendered into image i may be presented.
    render_done: Vec<vk::Semaphore>,
    extent: vk::Extent2D,
}

impl HostSwapchain {
    fn new(
        vulkan: &HostVulkan,
        surface_loader: &khr::surface::Instance,
        surface: vk::SurfaceKHR,
        size: PhysicalSize<u32>,
    ) -> Result<Self, String> {
        let pd = vulkan.physical_device;
        let caps = unsafe { surface_loader.get_physical_device_surface_capabilities(pd, surface) }
            .map_err(|e| format!("surface capabilities: {e}"))?;
        let formats = unsafe { surface_loader.get_physical_device_surface_formats(pd, surface) }
            .map_err(|e| format!("surface formats: {e}"))?;
        let format = [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM]
            .into_iter()
            .find_map(|f| formats.iter().find(|s| s.format == f).copied())
            .ok_or("the surface offers no 8-bit UNORM format")?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size
                    .width
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: size
                    .height
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_DST)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true);
        let loader = khr::swapchain::Device::new(&vulkan.instance, &vulkan.device);
        let raw = unsafe { loader.create_swapchain(&info, None) }
            .map_err(|e| format!("vkCreateSwapchainKHR: {e}"))?;
        let images = unsafe { loader.get_swapchain_images(raw) }.map_err(|e| e.to_string())?;
        let mut swapchain = Self {
            loader,
            raw,
            images: images.clone(),
            views: Vec::new(),
            render_done: Vec::new(),
            extent,
        };
        let d = &vulkan.device;
        for image in images {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(format.format)
                .subresource_range(crate::app::range(vk::ImageAspectFlags::COLOR));
            swapchain
                .views
                .push(unsafe { d.create_image_view(&view_info, None) }.map_err(|e| e.to_string())?);
            swapchain.render_done.push(
                unsafe { d.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                    .map_err(|e| e.to_string())?,
            );
        }
        Ok(swapchain)
    }

    /// Destroys the swapchain; the host has waited for every frame that used it.
    fn destroy(self, vulkan: &HostVulkan) {
        unsafe {
            for view in self.views {
                vulkan.device.destroy_image_view(view, None);
            }
            for semaphore in self.render_done {
                vulkan.device.destroy_semaphore(semaphore, None);
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
    }
}

/// Everything alive while the window is open.
struct State {
    swapchain: Option<HostSwapchain>,
    /// One per frame slot: signalled when the acquired image may be written.
    acquired: Vec<vk::Semaphore>,
    surface_loader: khr::surface::Instance,
    surface: vk::SurfaceKHR,
    host: Host,
    window: Window,
    stale: bool,
}

impl State {
    fn destroy(mut self) -> Vec<String> {
        let _ = self.host.wait_frames();
        // The present engine may still hold semaphores of the last presents: the host
        // owns its device and may wait for its queue to drain here, at teardown.
        if let Ok(queue) = self.host.vulkan.queue.lock() {
            let _ = unsafe { self.host.vulkan.device.queue_wait_idle(*queue) };
        }
        if let Some(swapchain) = self.swapchain.take() {
            swapchain.destroy(&self.host.vulkan);
        }
        unsafe {
            for semaphore in self.acquired.drain(..) {
                self.host.vulkan.device.destroy_semaphore(semaphore, None);
            }
            self.surface_loader.destroy_surface(self.surface, None);
        }
        let log = self.host.vulkan.message_log();
        drop(self.host);
        drop(self.window);
        let messages = log.lock().map(|m| m.clone()).unwrap_or_default();
        messages
    }

    /// Renders and presents one frame; `Ok(false)` when nothing was presented.
    fn draw(&mut self, summary: &mut WindowSummary) -> Result<bool, String> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(false); // minimised: no frame until it has an area again
        }
        if self.stale || self.swapchain.is_none() {
            // The old swapchain's images may still be in use by frames in flight, and
            // its semaphores by presents, which no fence covers: the host waits for its
            // own queue to drain (its device; Combustion never does this), then
            // replaces it.
            self.host.wait_frames()?;
            {
                let queue = self.host.vulkan.queue.lock().map_err(|_| "queue lock")?;
                unsafe { self.host.vulkan.device.queue_wait_idle(*queue) }
                    .map_err(|e| format!("vkQueueWaitIdle: {e}"))?;
            }
            if let Some(old) = self.swapchain.take() {
                old.destroy(&self.host.vulkan);
            }
            self.swapchain = Some(HostSwapchain::new(
                &self.host.vulkan,
                &self.surface_loader,
                self.surface,
                size,
            )?);
            summary.swapchains += 1;
            self.stale = false;
        }
        let swapchain = self.swapchain.as_ref().expect("created above");
        if swapchain.extent.width <= 2 * crate::app::BORDER
            || swapchain.extent.height <= 2 * crate::app::BORDER
        {
            return Ok(false);
        }
        let (slot, cmd) = self.host.begin_frame()?;
        let acquired = self.acquired[slot];
        let index = match unsafe {
            swapchain.loader.acquire_next_image(
                swapchain.raw,
                u64::MAX,
                acquired,
                vk::Fence::null(),
            )
        } {
            Ok((index, suboptimal)) => {
                self.stale |= suboptimal;
                index as usize
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.stale = true;
                // The command buffer was begun: end and submit it empty to keep the
                // ring consistent.
                self.host.submit_frame(slot)?;
                return Ok(false);
            }
            Err(e) => return Err(format!("vkAcquireNextImageKHR: {e}")),
        };
        let target = FinalTarget {
            image: swapchain.images[index],
            view: swapchain.views[index],
            extent: swapchain.extent,
        };
        // The acquire semaphore is waited for at every stage; the first barrier's first
        // scope names a stage of that wait (colour output) so that the layout change
        // comes after it. The image's old contents are not needed.
        self.host.record_frame(
            slot,
            cmd,
            0,
            target,
            ImageState::SWAPCHAIN_ACQUIRED,
            ImageState::PRESENT,
        )?;
        let render_done = swapchain.render_done[index];
        self.host
            .submit_frame_with(slot, Some((acquired, render_done)))?;
        let swapchains = [swapchain.raw];
        let indices = [index as u32];
        let waits = [render_done];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        let result = {
            let queue = self.host.vulkan.queue.lock().map_err(|_| "queue lock")?;
            unsafe { swapchain.loader.queue_present(*queue, &info) }
        };
        match result {
            Ok(false) => {}
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.stale = true,
            Err(e) => return Err(format!("vkQueuePresentKHR: {e}")),
        }
        summary.gpu_ms.extend(
            self.host
                .renderer()
                .take_completed_timings()
                .iter()
                .map(|t| t.total_ms),
        );
        Ok(true)
    }
}

struct App {
    options: WindowOptions,
    scenes: Vec<Scene>,
    state: Option<State>,
    error: Option<String>,
    summary: WindowSummary,
    last_present: Option<Instant>,
}

impl App {
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<State, String> {
        let window = event_loop
            .create_window(
                Window::default_attributes()
                    .with_title("Combustion in a host's frame")
                    .with_inner_size(PhysicalSize::new(self.options.width, self.options.height)),
            )
            .map_err(|e| format!("cannot open a window: {e}"))?;
        let display = window.display_handle().map_err(|e| e.to_string())?.as_raw();
        let handle = window.window_handle().map_err(|e| e.to_string())?.as_raw();
        let extensions: Vec<&'static CStr> = ash_window::enumerate_required_extensions(display)
            .map_err(|e| format!("no Vulkan surface for this window system: {e}"))?
            .iter()
            .map(|&p| unsafe { CStr::from_ptr(p) })
            .collect();
        let vulkan = HostVulkan::new(
            &self.options.device,
            self.options.validation,
            &extensions,
            &[khr::swapchain::NAME],
        )?;
        let surface = unsafe {
            ash_window::create_surface(&vulkan.entry, &vulkan.instance, display, handle, None)
        }
        .map_err(|e| format!("vkCreateSurfaceKHR: {e}"))?;
        let surface_loader = khr::surface::Instance::new(&vulkan.entry, &vulkan.instance);
        let supported = unsafe {
            surface_loader.get_physical_device_surface_support(
                vulkan.physical_device,
                vulkan.queue_family,
                surface,
            )
        }
        .unwrap_or(false);
        if !supported {
            unsafe { surface_loader.destroy_surface(surface, None) };
            return Err("the device's graphics queue cannot present to this window".into());
        }
        let host = Host::new(vulkan, self.options.frames_in_flight, &self.scenes)?;
        let mut acquired = Vec::new();
        for _ in 0..self.options.frames_in_flight {
            acquired.push(
                unsafe {
                    host.vulkan
                        .device
                        .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
                }
                .map_err(|e| e.to_string())?,
            );
        }
        Ok(State {
            swapchain: None,
            acquired,
            surface_loader,
            surface,
            host,
            window,
            stale: true,
        })
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(state) = self.state.as_mut() else {
            return;
        };
        match state.draw(&mut self.summary) {
            Err(e) => {
                self.error.get_or_insert(e);
                event_loop.exit();
            }
            Ok(presented) => {
                if presented {
                    self.summary.presented += 1;
                    let now = Instant::now();
                    if let Some(last) = self.last_present.replace(now) {
                        self.summary.frame_ms.push((now - last).as_secs_f64() * 1e3);
                    }
                    if let Some((at, w, h)) = self.options.resize_at {
                        if self.summary.presented == at {
                            let _ = state.window.request_inner_size(PhysicalSize::new(w, h));
                        }
                    }
                    // With a resize requested, the run goes on (up to ten times as
                    // long) until the window system has delivered it.
                    let resized = self.options.resize_at.is_none() || self.summary.swapchains >= 2;
                    if self.options.frames.is_some_and(|n| {
                        self.summary.presented >= n && (resized || self.summary.presented >= 10 * n)
                    }) {
                        event_loop.exit();
                        return;
                    }
                }
                state.window.request_redraw();
            }
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(state) => {
                state.window.request_redraw();
                self.state = Some(state);
            }
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested
            | WindowEvent::KeyboardInput {
                event:
                    KeyEvent {
                        logical_key: Key::Named(NamedKey::Escape),
                        state: ElementState::Pressed,
                        ..
                    },
                ..
            } => event_loop.exit(),
            WindowEvent::Resized(_) => {
                if let Some(state) = self.state.as_mut() {
                    state.stale = true;
                    state.window.request_redraw();
                }
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            _ => {}
        }
    }
}

/// Opens a window and runs the host in it until it is closed or `options.frames` have
/// been presented.
pub fn run(options: &WindowOptions, scenes: &[Scene]) -> Result<WindowSummary, String> {
    let mut builder = EventLoop::builder();
    {
        // Tests run this off the main thread; X11 allows it.
        use winit::platform::x11::EventLoopBuilderExtX11;
        builder.with_any_thread(true);
    }
    let event_loop = builder
        .build()
        .map_err(|e| format!("cannot open a window: {e} (set DISPLAY, or run under Xvfb)"))?;
    let mut app = App {
        options: options.clone(),
        scenes: scenes.to_vec(),
        state: None,
        error: None,
        summary: WindowSummary::default(),
        last_present: None,
    };
    let result = event_loop.run_app(&mut app);
    if let Some(state) = app.state.take() {
        app.summary.validation_messages = state.destroy();
    }
    if let Some(e) = app.error {
        return Err(e);
    }
    result.map_err(|e| format!("the event loop failed: {e}"))?;
    Ok(app.summary)
}
