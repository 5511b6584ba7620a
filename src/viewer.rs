//! `combustion view`: a scene in a window (winit, X11), re-rendered every frame.
//!
//! The viewer is a host of the engine API ([`Renderer::record`]), like a game engine:
//! each frame takes the next slot of its [`FrameRing`] (waiting only for the frame that
//! used that slot last), acquires a swapchain image, records the deferred frame with the
//! output pass writing straight into the swapchain image (its exact sRGB encoding into an
//! 8-bit UNORM image), submits waiting for the acquisition and signalling the image's
//! "rendered" semaphore, and presents. No pixel goes through the CPU.
//!
//! The swapchain is recreated when the window is resized, or the swapchain is out of date
//! or suboptimal; that is the one place the viewer waits for its (own) device, because
//! presents hold semaphores no fence covers. While the window has no area (minimised) no
//! frame is drawn and no redraw is asked for, so the loop sleeps in the event queue.
//! Closing the window, Escape, or reaching `frames` ends the loop; then the device is
//! idled and everything destroyed — swapchain, surface, scene, renderer, device — before
//! the window, and the validation log is checked.

use std::time::Instant;

use combustion_renderer::{ColorTarget, FrameInputs, FrameTarget, Renderer, RendererSettings};
use combustion_vk::{
    vk, Device, DeviceDesc, FrameRing, ImageState, PresentOutcome, Surface, Swapchain,
};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

use crate::{check_validation, Error, SceneSource};

/// How to run the viewer.
#[derive(Clone, Debug)]
pub struct ViewerDesc {
    pub scene: SceneSource,
    /// Initial inner size of the window, in physical pixels.
    pub width: u32,
    pub height: u32,
    /// Stop after this many presented frames; `None` runs until the window is closed.
    pub frames: Option<u32>,
    /// Device selector and validation; the surface extensions and `VK_KHR_swapchain`
    /// are added by the viewer.
    pub device: DeviceDesc,
    pub settings: RendererSettings,
    /// Wait for the display's refresh (FIFO); off: MAILBOX or IMMEDIATE where offered.
    pub vsync: bool,
}

/// What a viewer run did.
#[derive(Clone, Debug, Default)]
pub struct ViewSummary {
    pub device_name: String,
    /// Size of the last presented frame.
    pub width: u32,
    pub height: u32,
    /// GPU time of the passes of each completed frame (timestamps), ms.
    pub gpu_total_ms: Vec<f64>,
    /// Wall-clock time from one presented frame to the next, ms (frames in flight: the
    /// CPU records a frame while the GPU renders the previous one).
    pub frame_ms: Vec<f64>,
    /// Swapchains created (1 + recreations after resizes and out-of-date swapchains).
    pub swapchains: u32,
    /// Frames presented.
    pub presented: u64,
}

/// A winit error without its "os error at FILE:LINE: " prefix (the crate's source path
/// means nothing to a user), naming DISPLAY when the X server could not be reached.
fn window_error(error: impl std::fmt::Display) -> String {
    let text = error.to_string();
    let text = match text.strip_prefix("os error at ") {
        Some(rest) => rest
            .split_once(": ")
            .map_or(rest, |(_location, message)| message)
            .to_owned(),
        None => text,
    };
    match std::env::var("DISPLAY") {
        Ok(display) if text.contains("X server") => format!("{text} (DISPLAY={display})"),
        _ => text,
    }
}

/// `builtin:NAME` or the file's path, for the window title.
fn scene_label(source: &SceneSource) -> String {
    match source {
        SceneSource::Builtin(name) => format!("builtin:{name}"),
        SceneSource::File(path) => path.display().to_string(),
    }
}

/// Opens a window on `desc.scene` and renders until it is closed (or `desc.frames` are
/// shown). Fails with [`Error::NoWindow`] when no window can be opened, and with
/// [`Error::Validation`] if validation is on and the layer reported anything.
pub fn run(desc: &ViewerDesc) -> Result<ViewSummary, Error> {
    let scene = desc.scene.load()?;
    let event_loop = EventLoop::new().map_err(|e| Error::NoWindow(window_error(e)))?;
    let mut app = App {
        desc,
        scene: Some(scene),
        label: scene_label(&desc.scene),
        state: None,
        error: None,
        summary: ViewSummary::default(),
        presented: 0,
    };
    let result = event_loop.run_app(&mut app);
    // Vulkan objects go before the window, the device last of them (it is behind Arcs),
    // and only then is the validation log complete (leaks are reported at destruction).
    let validation = app.state.as_ref().map(|s| s.device.validation_log());
    if let Some(mut state) = app.state.take() {
        if let Err(e) = state.finish(&mut app.summary) {
            app.error.get_or_insert(e);
        }
        state.destroy();
    }
    app.summary.presented = app.presented;
    if let Some(e) = app.error.take() {
        return Err(e);
    }
    result.map_err(|e| {
        Error::Window(format!(
            "the window's event loop failed: {}",
            window_error(e)
        ))
    })?;
    if let Some(log) = validation {
        check_validation(&log)?;
    }
    Ok(app.summary)
}

struct App<'a> {
    desc: &'a ViewerDesc,
    /// The CPU scene, until it is uploaded.
    scene: Option<combustion_scene::Scene>,
    label: String,
    state: Option<State>,
    error: Option<Error>,
    summary: ViewSummary,
    /// Frames presented so far.
    presented: u64,
}

/// Everything the viewer owns while the window is open.
struct State {
    swapchain: Option<Swapchain>,
    surface: Surface,
    /// The viewer's command buffers and fences, one per frame in flight.
    ring: FrameRing,
    gpu_scene: combustion_renderer::GpuScene,
    renderer: Renderer,
    device: std::sync::Arc<Device>,
    /// When the last frame was presented.
    last_present: Option<Instant>,
    /// Recreate the swapchain before the next frame (resize, out of date, suboptimal).
    stale: bool,
    window: Window,
}

impl State {
    fn new(
        event_loop: &ActiveEventLoop,
        desc: &ViewerDesc,
        scene: &combustion_scene::Scene,
        title: &str,
    ) -> Result<State, Error> {
        let attributes = Window::default_attributes()
            .with_title(title)
            .with_inner_size(PhysicalSize::new(desc.width, desc.height));
        let window = event_loop
            .create_window(attributes)
            .map_err(|e| Error::NoWindow(window_error(e)))?;
        let handle_error = |e: winit::raw_window_handle::HandleError| {
            Error::NoWindow(format!("the window has no usable handle: {e}"))
        };
        let display = window.display_handle().map_err(handle_error)?.as_raw();
        let window_handle = window.window_handle().map_err(handle_error)?.as_raw();
        let mut device_desc = desc.device.clone();
        device_desc
            .instance_extensions
            .extend(Surface::instance_extensions(display)?);
        device_desc.swapchain = true;
        let device = Device::new(&device_desc)?;
        // SAFETY: the window outlives the surface: `State` drops it last (field order,
        // and `destroy` drops the surface explicitly before it).
        let surface = unsafe { Surface::new(&device, display, window_handle) }?;
        let mut renderer = Renderer::new(device.clone(), desc.settings)?;
        let gpu_scene = renderer.upload(scene)?;
        let ring = FrameRing::new(&device, desc.settings.frames_in_flight)?;
        Ok(State {
            swapchain: None,
            surface,
            ring,
            gpu_scene,
            renderer,
            device,
            last_present: None,
            stale: true,
            window,
        })
    }

    /// Tears down in order: swapchain, surface, frame ring, scene, renderer, device,
    /// window (after waiting for the viewer's own device).
    fn destroy(self) {
        let State {
            swapchain,
            surface,
            ring,
            gpu_scene,
            renderer,
            device,
            window,
            ..
        } = self;
        if let Err(e) = device.wait_idle() {
            log::error!("waiting for the device before teardown: {e}");
        }
        drop(swapchain);
        drop(surface);
        drop(ring);
        drop(gpu_scene);
        drop(renderer);
        drop(device);
        drop(window);
    }

    /// Renders and presents one frame. `Ok(None)` when nothing was shown (no area, or
    /// the swapchain went out of date), else the wall time since the last present in ms
    /// (`None` for the first frame).
    fn draw(
        &mut self,
        vsync: bool,
        summary: &mut ViewSummary,
    ) -> Result<Option<Option<f64>>, Error> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(None);
        }
        if self.stale || self.swapchain.is_none() {
            // The old swapchain's images and semaphores may still be in use by presents,
            // which no fence covers: the viewer waits for its own device, once per
            // recreation (never per frame).
            self.device.wait_idle()?;
            self.swapchain = None; // the old one must go before a new one is made
            let swapchain = Swapchain::new(
                &self.device,
                &self.surface,
                size.width,
                size.height,
                vsync,
                self.ring.frames_in_flight(),
            )?;
            self.renderer.prepare_output(swapchain.format())?;
            self.swapchain = Some(swapchain);
            summary.swapchains += 1;
            self.stale = false;
            self.last_present = None;
        }
        let swapchain = self.swapchain.as_ref().expect("created above");
        let extent = swapchain.extent();
        // The only wait of a frame: for the one that used this slot last.
        let frame = self.ring.begin()?;
        let Some(image) = swapchain.acquire(frame.slot)? else {
            self.stale = true;
            self.ring.submit(frame)?; // empty: keeps the ring's slots in step
            return Ok(None);
        };
        let present_state = ImageState::new(
            vk::PipelineStageFlags2::NONE,
            vk::AccessFlags2::NONE,
            vk::ImageLayout::PRESENT_SRC_KHR,
        );
        let target = FrameTarget {
            color: ColorTarget {
                image: image.image,
                view: image.view,
                format: swapchain.format(),
                extent,
                // The acquisition's semaphore is waited for before any command.
                before: ImageState::UNDEFINED,
                after: present_state,
            },
            depth: None,
        };
        let inputs = FrameInputs::of_scene(&self.gpu_scene, self.renderer.settings().exposure);
        self.renderer
            .record(frame.cmd, frame.slot, &self.gpu_scene, &inputs, &target)?;
        self.ring
            .submit_with(frame, Some(image.acquired), Some(image.rendered))?;
        match swapchain.present(&image)? {
            PresentOutcome::Presented => {}
            PresentOutcome::PresentedSuboptimal | PresentOutcome::OutOfDate => self.stale = true,
        }
        summary.gpu_total_ms.extend(
            self.renderer
                .take_completed_timings()
                .iter()
                .map(|t| t.total_ms),
        );
        let now = Instant::now();
        let wall = self
            .last_present
            .replace(now)
            .map(|last| (now - last).as_secs_f64() * 1e3);
        Ok(Some(wall))
    }

    /// Waits for every frame in flight and collects their GPU times.
    fn finish(&mut self, summary: &mut ViewSummary) -> Result<(), Error> {
        self.ring.wait_all()?;
        self.renderer.frames_completed()?;
        summary.gpu_total_ms.extend(
            self.renderer
                .take_completed_timings()
                .iter()
                .map(|t| t.total_ms),
        );
        Ok(())
    }
}

impl App<'_> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        self.error.get_or_insert(error);
        event_loop.exit();
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(state) = self.state.as_mut() else {
            return;
        };
        match state.draw(self.desc.vsync, &mut self.summary) {
            Err(e) => self.fail(event_loop, e),
            Ok(None) => {
                // Out of date: try again at once; no area: wait for a resize.
                if state.stale {
                    state.window.request_redraw();
                }
            }
            Ok(Some(wall_ms)) => {
                let extent = state.swapchain.as_ref().map(|s| s.extent());
                if let Some(extent) = extent {
                    self.summary.width = extent.width;
                    self.summary.height = extent.height;
                }
                self.presented += 1;
                self.summary.frame_ms.extend(wall_ms);
                if let Some(gpu_ms) = self.summary.gpu_total_ms.last() {
                    state
                        .window
                        .set_title(&format!("combustion — {} — {gpu_ms:.1} ms GPU", self.label));
                }
                if self
                    .desc
                    .frames
                    .is_some_and(|n| self.presented >= u64::from(n))
                {
                    event_loop.exit();
                } else {
                    state.window.request_redraw();
                }
            }
        }
    }
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        let Some(scene) = self.scene.take() else {
            return; // already set up (resumed is called again on some platforms)
        };
        let title = format!("combustion — {}", self.label);
        match State::new(event_loop, self.desc, &scene, &title) {
            Ok(state) => {
                self.summary.device_name = state.device.info().name.clone();
                state.window.request_redraw();
                self.state = Some(state);
            }
            Err(e) => self.fail(event_loop, e),
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
