//! `combustion view`: a scene in a window (winit, X11), re-rendered every frame.
//!
//! Each frame is rendered by the unchanged [`Renderer`] with the display image read back
//! (`Readback { images: true, .. }`), and [`Swapchain::present_rgba8`] copies those
//! sRGB-encoded bytes through a host-visible staging buffer into the swapchain image
//! (`vkCmdCopyBufferToImage`). This readback-and-copy path is deliberate: the renderer
//! stays exactly as headless rendering uses it, and on lavapipe "GPU" memory is host
//! memory anyway, so the round trip costs little. A device-side copy of the display
//! image into the swapchain image is the change to make for real GPUs.
//!
//! The swapchain is recreated when the window is resized (frames are skipped while it
//! has no area). Closing the window, Escape, or reaching `frames` ends the loop; then the
//! device is idled and everything destroyed — swapchain, surface, scene, renderer,
//! device — before the window, and the validation log is checked.

use std::time::Instant;

use combustion_renderer::{Readback, Renderer, RendererSettings};
use combustion_vk::{Device, DeviceDesc, PresentOutcome, Surface, Swapchain};
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
}

/// What a viewer run did.
#[derive(Clone, Debug, Default)]
pub struct ViewSummary {
    pub device_name: String,
    /// Size of the last presented frame.
    pub width: u32,
    pub height: u32,
    /// GPU time of each presented frame's passes (timestamps), ms.
    pub gpu_total_ms: Vec<f64>,
    /// Wall time of each presented frame: render, readback, copy and present, ms.
    pub frame_ms: Vec<f64>,
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
    };
    let result = event_loop.run_app(&mut app);
    // Vulkan objects go before the window, the device last of them (it is behind Arcs),
    // and only then is the validation log complete (leaks are reported at destruction).
    let validation = app.state.as_ref().map(|s| s.device.validation_log());
    if let Some(state) = app.state.take() {
        state.destroy();
    }
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
}

/// Everything the viewer owns while the window is open.
struct State {
    swapchain: Option<Swapchain>,
    surface: Surface,
    gpu_scene: combustion_renderer::GpuScene,
    renderer: Renderer,
    device: std::sync::Arc<Device>,
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
        Ok(State {
            swapchain: None,
            surface,
            gpu_scene,
            renderer,
            device,
            stale: true,
            window,
        })
    }

    /// Tears down in order: swapchain, surface, scene, renderer (waits idle), device, window.
    fn destroy(self) {
        let State {
            swapchain,
            surface,
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
        drop(gpu_scene);
        drop(renderer);
        drop(device);
        drop(window);
    }

    /// Renders and presents one frame. `Ok(None)` when nothing was shown (no area, or
    /// the swapchain went out of date), else the GPU total and the wall time in ms.
    fn draw(&mut self) -> Result<Option<(f64, f64)>, Error> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(None);
        }
        if self.stale || self.swapchain.is_none() {
            self.swapchain = None; // the old one must go before a new one is made
            self.swapchain = Some(Swapchain::new(
                &self.device,
                &self.surface,
                size.width,
                size.height,
            )?);
            self.stale = false;
        }
        let swapchain = self.swapchain.as_mut().expect("created above");
        let extent = swapchain.extent();
        let start = Instant::now();
        let frame = self.renderer.render(
            &self.gpu_scene,
            extent.width,
            extent.height,
            Readback {
                images: true,
                gbuffer: false,
            },
        )?;
        match swapchain.present_rgba8(&frame.ldr)? {
            PresentOutcome::Presented => {}
            PresentOutcome::PresentedSuboptimal => self.stale = true,
            PresentOutcome::OutOfDate => {
                self.stale = true;
                return Ok(None);
            }
        }
        let wall = start.elapsed().as_secs_f64() * 1e3;
        Ok(Some((frame.timings.total_ms, wall)))
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
        match state.draw() {
            Err(e) => self.fail(event_loop, e),
            Ok(None) => {
                // Out of date: try again at once; no area: wait for a resize.
                if state.stale {
                    state.window.request_redraw();
                }
            }
            Ok(Some((gpu_ms, wall_ms))) => {
                let extent = state.swapchain.as_ref().map(|s| s.extent());
                if let Some(extent) = extent {
                    self.summary.width = extent.width;
                    self.summary.height = extent.height;
                }
                self.summary.gpu_total_ms.push(gpu_ms);
                self.summary.frame_ms.push(wall_ms);
                state
                    .window
                    .set_title(&format!("combustion — {} — {gpu_ms:.1} ms GPU", self.label));
                let shown = self.summary.gpu_total_ms.len();
                if self.desc.frames.is_some_and(|n| shown >= n as usize) {
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
