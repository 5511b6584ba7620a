//! `combustion view`: a scene in a window (winit: Wayland or X11), re-rendered every frame.
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
//! presents hold semaphores no fence covers. While the window has no area, is minimised
//! or occluded (as far as the window system tells) no frame is drawn and no redraw is
//! asked for, so the loop sleeps in the event queue.
//!
//! Over the frame the renderer draws the statistics and help panels (its text overlay);
//! the error view ([`inspect`]) re-shades a frame in f64 and shows its relative error.
//! Closing the window, Escape, or reaching `frames` ends the loop; then the device is
//! idled and everything destroyed — swapchain, surface, scene, renderer, device — before
//! the window, and the validation log is checked.

pub mod camera;
pub mod controls;
pub mod inspect;

use std::path::PathBuf;
use std::time::Instant;

use combustion_renderer::{
    Background, ColorTarget, Corner, DebugView, FrameInputs, FrameTarget, OverlayPanel, Renderer,
    RendererSettings, ShadingOptions, ToneMapping,
};
use combustion_vk::{
    vk, Device, DeviceDesc, FrameRing, ImageState, PresentOutcome, Surface, Swapchain,
};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

use crate::{check_validation, Error, SceneSource};

/// How to run the viewer.
#[derive(Clone, Debug)]
pub struct ViewerDesc {
    /// The scene to show first.
    pub scene: SceneSource,
    /// Initial inner size of the window, in physical pixels.
    pub width: u32,
    /// Initial inner height of the window, in physical pixels.
    pub height: u32,
    /// Stop after this many presented frames; `None` runs until the window is closed.
    pub frames: Option<u32>,
    /// Device selector and validation; the surface extensions and `VK_KHR_swapchain`
    /// are added by the viewer.
    pub device: DeviceDesc,
    /// The renderer's settings.
    pub settings: RendererSettings,
    /// Wait for the display's refresh (FIFO); off: MAILBOX or IMMEDIATE where offered.
    pub vsync: bool,
    /// Write the last frame shown (with `frames`) to this PNG, copied from the
    /// swapchain image itself.
    pub screenshot: Option<PathBuf>,
    /// Move the camera along this path (see [`camera::CameraPath`]) instead of by the
    /// mouse and keys; frame n is shown at time n / [`PATH_FRAMES_PER_SECOND`], so a run
    /// is the same on any machine.
    pub camera_path: Option<PathBuf>,
    /// Draw the statistics panel over the frames (Tab toggles it while running).
    pub overlay: bool,
    /// Start in the error view (X toggles it while running).
    pub error_view: bool,
    /// What shows where no surface is; `None`: the environment where one lights the
    /// scene, else nothing.
    pub background: Option<Background>,
    /// The window's tone curve; `None`: [`crate::default_tone_mapping`] of the scene's
    /// source.
    pub tone_mapping: Option<ToneMapping>,
    /// The window's anti-aliasing.
    pub anti_aliasing: combustion_renderer::AntiAliasing,
    /// Whether the exposure is metered from the start (U toggles it), and how: the
    /// metering window, compensation and adaptation speeds (its `elapsed_seconds` is
    /// the viewer's: the wall clock between frames, 1/30 s a frame on a camera path).
    pub auto_exposure: (bool, combustion_renderer::AutoExposure),
    /// The fraction of radiance bloom spreads, in frames with bloom (Y toggles it).
    pub bloom_intensity: f32,
    /// The environment lighting the scene in place of the one it comes with (`Some(None)`:
    /// none; a file is lit by the studio beside its own lights), kept when it is reloaded;
    /// `None`: the scene's own.
    pub environment: Option<Option<combustion_scene::Environment>>,
}

/// The scene of `source` and its file's cameras, lit by `environment` where one is given
/// ([`ViewerDesc::environment`]).
fn load_scene(
    source: &SceneSource,
    environment: &Option<Option<combustion_scene::Environment>>,
) -> Result<(combustion_scene::Scene, Vec<combustion_scene::Camera>), Error> {
    let (mut scene, cameras) = source.load_with_cameras(&Default::default())?;
    if let Some(environment) = environment {
        scene.environment.clone_from(environment);
    }
    Ok((scene, cameras))
}

/// The error view of a path-traced view (the error view on, J): the view it is of,
/// the real-time frame's HDR radiance there (empty while the view settles), and the last
/// comparison with the path-traced mean.
struct TransportView {
    key: inspect::ViewKey,
    realtime: Vec<[f32; 4]>,
    measured: Option<inspect::TransportSummary>,
}

/// The clock of scripted runs: frame n of a camera path is at time n / 30 s.
pub const PATH_FRAMES_PER_SECOND: f32 = 30.0;

/// The keys and mouse buttons of the viewer, for the help text and the README.
pub const KEYS: &[(&str, &str)] = &[
    (
        "left drag",
        "orbit around the target (with W/A/S/D/Q/E held: look around)",
    ),
    ("right or middle drag", "pan"),
    ("wheel", "zoom"),
    ("W A S D / Q E", "fly forward, left, back, right / down, up"),
    ("F", "frame the whole scene"),
    ("R", "reset the camera"),
    (
        "C",
        "next camera of the glTF file (its placed perspective cameras)",
    ),
    ("P", "screenshot to combustion-NNNN.png"),
    (
        "1 … 9, 0",
        "the built-in scenes, in the order `combustion --help` lists them (0: the tenth)",
    ),
    ("drop a file", "open a glTF file"),
    (
        "F5",
        "reload the scene (also when its file changes on disk)",
    ),
    ("G", "Fresnel: full equations / Schlick / F82 (comparisons)"),
    ("K", "shadows on / off (every light casts them)"),
    ("L", "shadow filter: hard, PCF 8, 16, 32 taps"),
    (
        "B",
        "environment occlusion: none, screen-space (GTAO), ray-traced (with ray queries)",
    ),
    (
        "M",
        "diffuse model of every material: as loaded, Lambert, Oren–Nayar qualitative, full",
    ),
    ("O", "outside medium: as loaded, air, water (η 1.33)"),
    (
        "I",
        "type the outside medium's index (digits, Enter applies, Escape cancels)",
    ),
    ("+ / -", "exposure up / down half a stop (with auto exposure: its compensation)"),
    (
        "T",
        "temporal anti-aliasing on / off (a jittered camera, each pixel blended with its history)",
    ),
    (
        "Y",
        "bloom on / off (the glow of bright things; on by default)",
    ),
    (
        "J",
        "path tracing on / off (with ray queries: light that bounces, converging while the view rests)",
    ),
    (
        "U",
        "auto exposure on / off (metered from the frame; the statistics panel shows its EV and histogram)",
    ),
    (
        "V",
        "debug view: each G-buffer channel, the BRDF terms D, G2, F, diffuse, lights per tile",
    ),
    (
        "X",
        "error view: the frame re-shaded in f64, relative error as a heat map; with path tracing (J), the real-time frame against the converging paths",
    ),
    ("Space", "play / pause the scene's animation"),
    ("N", "next animation of the scene"),
    ("[ / ]", "animation speed half / twice"),
    (", / .", "animation back / forward 0.1 s"),
    ("H", "help (this list)"),
    ("Tab", "statistics panel on / off"),
    ("Escape", "quit"),
];

/// What a viewer run did.
#[derive(Clone, Debug, Default)]
pub struct ViewSummary {
    /// The name of the device rendered on.
    pub device_name: String,
    /// Size of the last presented frame.
    pub width: u32,
    /// Height of the last presented frame.
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
    /// Screenshots written.
    pub screenshots: Vec<PathBuf>,
}

/// Writes the pending screenshot, whose frame has completed. A `--screenshot` that
/// cannot be written is the run's error; one taken by the key is reported and the viewer
/// goes on.
fn write_screenshot(
    shot: Option<PendingScreenshot>,
    summary: &mut ViewSummary,
) -> Result<(), Error> {
    let Some(shot) = shot else {
        return Ok(());
    };
    let pixels: Vec<[u8; 4]> = shot
        .buffer
        .mapped()?
        .chunks_exact(4)
        .map(|c| {
            if shot.bgra {
                [c[2], c[1], c[0], 255]
            } else {
                [c[0], c[1], c[2], 255]
            }
        })
        .collect();
    let (w, h) = (shot.extent.width, shot.extent.height);
    match crate::output::write_png(&shot.path, w, h, &pixels) {
        Ok(()) => {
            log::info!("screenshot written to {} ({w}x{h})", shot.path.display());
            summary.screenshots.push(shot.path)
        }
        Err(e) if shot.requested => return Err(e.into()),
        Err(e) => log::error!("{e}"),
    }
    Ok(())
}

/// Records, after the frame's output pass (the image in `from`), a copy of the swapchain
/// image into a host-visible buffer, and the transition to `to` for presenting.
fn record_screenshot_copy(
    device: &std::sync::Arc<Device>,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    extent: vk::Extent2D,
    from: ImageState,
    to: ImageState,
) -> Result<combustion_vk::Buffer, Error> {
    let buffer = combustion_vk::Buffer::new(
        device,
        "screenshot",
        u64::from(extent.width) * u64::from(extent.height) * 4,
        vk::BufferUsageFlags::TRANSFER_DST,
        combustion_vk::gpu_allocator::MemoryLocation::GpuToCpu,
    )?;
    let range = vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    };
    let region = combustion_vk::color_level0_copy_region(extent);
    let raw = device.raw();
    let to_present = [combustion_vk::image_barrier(image, range, from, to)];
    let to_host = [combustion_vk::copy_to_host_barrier()];
    // SAFETY: recording state; the image was left in `from` (TRANSFER_SRC_OPTIMAL).
    unsafe {
        raw.cmd_copy_image_to_buffer(
            cmd,
            image,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            buffer.raw(),
            &[region],
        );
        raw.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default()
                .image_memory_barriers(&to_present)
                .memory_barriers(&to_host),
        );
    }
    Ok(buffer)
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

/// The largest window side asked of the window system: X11 sizes are 16-bit (a larger
/// one panics inside winit rather than failing).
pub const MAX_WINDOW_SIDE: u32 = u16::MAX as u32;

/// Refuses a window side above [`MAX_WINDOW_SIDE`] as bad usage ([`Error::Usage`]):
/// what the window system cannot take, whatever the device.
pub fn check_window_size(width: u32, height: u32) -> Result<(), Error> {
    if width > MAX_WINDOW_SIDE || height > MAX_WINDOW_SIDE {
        return Err(Error::Usage(format!(
            "a window of {width}x{height}: the window system takes at most {MAX_WINDOW_SIDE} pixels per side"
        )));
    }
    Ok(())
}

/// Opens a window on `desc.scene` and renders until it is closed (or `desc.frames` are
/// shown). Fails with [`Error::Usage`] for a window side above [`MAX_WINDOW_SIDE`]
/// (checked before anything is loaded), with [`Error::NoWindow`] when no window can be
/// opened, and with [`Error::Validation`] if validation is on and the layer reported
/// anything.
pub fn run(desc: &ViewerDesc) -> Result<ViewSummary, Error> {
    check_window_size(desc.width, desc.height)?;
    let path = desc
        .camera_path
        .as_deref()
        .map(camera::CameraPath::read)
        .transpose()
        .map_err(Error::CameraPath)?;
    // The display before the scene: without one, nothing is loaded.
    let event_loop = EventLoop::new().map_err(|e| Error::NoWindow(window_error(e)))?;
    let (scene, cameras) = load_scene(&desc.scene, &desc.environment)?;
    let mut app = App {
        desc,
        scene: Some((scene, cameras)),
        label: desc.scene.label(),
        state: None,
        error: None,
        summary: ViewSummary::default(),
        presented: 0,
        path,
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
    /// The CPU scene and its views, until it is uploaded.
    scene: Option<(combustion_scene::Scene, Vec<combustion_scene::Camera>)>,
    label: String,
    state: Option<State>,
    error: Option<Error>,
    summary: ViewSummary,
    /// Frames presented so far.
    presented: u64,
    /// The scripted camera, if any.
    path: Option<camera::CameraPath>,
}

/// A copy of a presented image in host-visible memory, and where it goes.
struct PendingScreenshot {
    /// The frame slot of the frame that copies it.
    slot: usize,
    buffer: combustion_vk::Buffer,
    path: PathBuf,
    /// Asked for on the command line (`--screenshot`): a failed write is the run's error.
    /// One taken by the key (P) is reported and the viewer goes on.
    requested: bool,
    extent: vk::Extent2D,
    bgra: bool,
}

/// Mouse buttons and keys held, and the cursor's last position.
#[derive(Default)]
struct Input {
    orbiting: bool,
    panning: bool,
    cursor: Option<(f64, f64)>,
    /// x right, y up, z forward: −1, 0 or 1 each.
    fly: [[bool; 2]; 3],
}

impl Input {
    fn flying(&self) -> bool {
        self.fly.iter().flatten().any(|&held| held)
    }

    fn motion(&self) -> glam::Vec3 {
        let axis =
            |[minus, plus]: [bool; 2]| f32::from(u8::from(plus)) - f32::from(u8::from(minus));
        glam::Vec3::new(axis(self.fly[0]), axis(self.fly[1]), axis(self.fly[2]))
    }
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
    /// When the camera was last moved by held keys.
    last_step: Instant,
    orbit: camera::OrbitCamera,
    input: Input,
    /// A screenshot to take of the next frame shown, and whether `--screenshot` asked
    /// for it (rather than the P key).
    screenshot: Option<(PathBuf, bool)>,
    /// Screenshots taken with the P key.
    screenshots_taken: u32,
    /// A screenshot copied by a frame that may still be in flight.
    pending_screenshot: Option<PendingScreenshot>,
    /// The title last set (it is set again only when it changes).
    title: String,
    /// Where the shown scene came from, the scene as loaded, and the toggles on it.
    source: SceneSource,
    original: combustion_scene::Scene,
    overrides: controls::Overrides,
    /// The environment asked for in place of the scene's ([`ViewerDesc::environment`]).
    environment: Option<Option<combustion_scene::Environment>>,
    exposure: f32,
    /// The auto exposure's settings, and whether it is on.
    auto_exposure: (bool, combustion_renderer::AutoExposure),
    /// The fraction of radiance bloom spreads (with bloom on).
    bloom_intensity: f32,
    /// When the last frame was recorded (the auto exposure adapts over the time since).
    last_recorded: Option<Instant>,
    /// The background asked for (`None`: the environment where one lights the scene).
    background: Option<Background>,
    /// The tone curve asked for (`None`: the default of the scene's source).
    tone_mapping: Option<ToneMapping>,
    /// The anti-aliasing asked for.
    anti_aliasing: combustion_renderer::AntiAliasing,
    /// The scene file's modification time when loaded, and when it was last checked.
    modified: Option<std::time::SystemTime>,
    last_poll: Instant,
    /// Recreate the swapchain before the next frame (resize, out of date, suboptimal).
    stale: bool,
    /// The views the scene offers (C cycles them) and the one shown last.
    cameras: Vec<combustion_scene::Camera>,
    camera_index: usize,
    /// Triangles drawn per frame (every object's mesh).
    triangles: usize,
    /// Counts scene loads and edits (an error map of an older scene is stale).
    scene_generation: u64,
    /// Panels shown: statistics (Tab), help (H).
    show_stats: bool,
    show_help: bool,
    /// The help panel's text (the keys never change).
    help_text: String,
    error_view: Option<inspect::ErrorView>,
    /// The error view of a path-traced view: its real-time frame, and the comparison
    /// with the mean of paths last made.
    transport: Option<TransportView>,
    /// When the view last changed while the error view was on.
    view_changed: Instant,
    /// The outside medium's index being typed (I), if any.
    typing: Option<String>,
    /// The scene's animation as it plays (Space, N, [ ], , .).
    playback: controls::Playback,
    /// The window is occluded, or minimised (as the window system says): no frames
    /// until it is shown again.
    occluded: bool,
    minimized: bool,
    window: Window,
}

/// Triangles drawn per frame: every object's mesh counted.
fn triangles_drawn(scene: &combustion_scene::Scene) -> usize {
    scene
        .objects
        .iter()
        .map(|o| scene.meshes[o.mesh].triangle_count())
        .sum()
}

/// Median of the last (up to) 30 values.
fn recent_median(values: &[f64]) -> Option<f64> {
    let mut recent: Vec<f64> = values.iter().rev().take(30).copied().collect();
    if recent.is_empty() {
        return None;
    }
    recent.sort_by(f64::total_cmp);
    Some(recent[recent.len() / 2])
}

fn shown_or_hidden(shown: bool) -> &'static str {
    if shown {
        "shown"
    } else {
        "hidden"
    }
}

/// How long the view must stay unchanged before the error view measures it again.
const ERROR_VIEW_SETTLE_SECONDS: f32 = 0.3;

impl State {
    fn new(
        event_loop: &ActiveEventLoop,
        desc: &ViewerDesc,
        scene: &combustion_scene::Scene,
        cameras: Vec<combustion_scene::Camera>,
        title: &str,
    ) -> Result<State, Error> {
        let source = desc.scene.clone();
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
        // Path-traced frames converge while the view rests, and start again when
        // anything moves.
        let settings = RendererSettings {
            accumulate_paths: true,
            ..desc.settings
        };
        let mut renderer = Renderer::new(device.clone(), settings)?;
        let gpu_scene = renderer.upload(scene)?;
        let ring = FrameRing::new(&device, desc.settings.frames_in_flight)?;
        Ok(State {
            swapchain: None,
            surface,
            ring,
            orbit: camera::OrbitCamera::new(&gpu_scene.scene().camera),
            gpu_scene,
            renderer,
            device,
            last_present: None,
            last_step: Instant::now(),
            input: Input::default(),
            screenshot: None,
            screenshots_taken: 0,
            pending_screenshot: None,
            title: String::new(),
            modified: controls::modified(&source),
            source,
            original: scene.clone(),
            overrides: controls::Overrides::default(),
            environment: desc.environment.clone(),
            exposure: desc.settings.exposure,
            auto_exposure: desc.auto_exposure,
            bloom_intensity: desc.bloom_intensity,
            last_recorded: None,
            background: desc.background,
            tone_mapping: desc.tone_mapping,
            anti_aliasing: desc.anti_aliasing,
            last_poll: Instant::now(),
            stale: true,
            cameras,
            camera_index: 0,
            triangles: triangles_drawn(scene),
            scene_generation: 0,
            show_stats: desc.overlay,
            show_help: false,
            help_text: inspect::help_text(KEYS),
            error_view: desc.error_view.then(inspect::ErrorView::default),
            transport: None,
            view_changed: Instant::now(),
            typing: None,
            playback: controls::Playback::new(),
            occluded: false,
            minimized: false,
            window,
        })
    }

    /// Occluded or minimised: nothing to draw.
    fn hidden(&self) -> bool {
        self.occluded || self.minimized
    }

    /// Asks the window system whether the window is minimised (on events that come
    /// with a change of it), and for a frame if it is shown.
    fn check_minimized(&mut self) {
        let was_hidden = self.hidden();
        self.minimized = self.window.is_minimized() == Some(true);
        if self.hidden() != was_hidden {
            log::info!(
                "drawing {}",
                if self.hidden() {
                    "paused (window hidden)"
                } else {
                    "resumed"
                }
            );
        }
        if !self.hidden() {
            self.window.request_redraw();
        }
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
        scripted: Option<combustion_scene::Camera>,
        summary: &mut ViewSummary,
    ) -> Result<Option<Option<f64>>, Error> {
        let size = self.window.inner_size();
        // Minimised or occluded: nothing is drawn and no redraw asked for until the
        // window is shown, resized or focused again.
        if size.width == 0 || size.height == 0 || self.hidden() {
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
            self.renderer
                .prepare_anti_aliasing(swapchain.format(), self.anti_aliasing)?;
            // Built with the window (U may turn it on later: no frame compiles a shader).
            self.renderer.prepare_auto_exposure()?;
            self.swapchain = Some(swapchain);
            summary.swapchains += 1;
            self.stale = false;
            self.last_present = None;
        }
        let extent = self.swapchain.as_ref().expect("created above").extent();
        // The camera: scripted, or moved by the keys held for the time since last frame.
        let now = Instant::now();
        let seconds = (now - self.last_step).as_secs_f32();
        self.last_step = now;
        if self.input.flying() {
            self.orbit.fly(self.input.motion(), seconds);
        }
        let camera = scripted.unwrap_or_else(|| self.orbit.camera());
        self.update_error_view(camera, extent, summary)?;
        let swapchain = self.swapchain.as_ref().expect("created above");
        if let (Some((path, requested)), false) = (&self.screenshot, swapchain.copyable()) {
            let message = format!(
                "{}: this window's swapchain images cannot be copied, so no screenshot can be taken",
                path.display()
            );
            if *requested {
                return Err(Error::Window(message));
            }
            log::error!("{message}");
            self.screenshot = None;
        }
        // The only wait of a frame: for the one that used this slot last.
        let frame = self.ring.begin()?;
        // This slot's previous frame has completed: a screenshot it took can be read.
        if self
            .pending_screenshot
            .as_ref()
            .is_some_and(|p| p.slot == frame.slot)
        {
            write_screenshot(self.pending_screenshot.take(), summary)?;
        }
        let Some(image) = swapchain.acquire(frame.slot)? else {
            self.stale = true;
            self.ring.submit(frame)?; // empty: keeps the ring's slots in step
            return Ok(None);
        };
        let screenshot = self.screenshot.take();
        let target = FrameTarget {
            color: ColorTarget {
                image: image.image,
                view: image.view,
                format: swapchain.format(),
                extent,
                usage: swapchain.image_usage(),
                // The acquisition's semaphore is waited for (at every stage) before the
                // layout change; the change's first scope must include a stage of that
                // wait, so it names colour output rather than none.
                before: ImageState::SWAPCHAIN_ACQUIRED,
                after: if screenshot.is_some() {
                    ImageState::COPY_SOURCE
                } else {
                    ImageState::PRESENT
                },
            },
            depth: None,
        };
        let stats = self.show_stats.then(|| self.stats_text(extent, summary));
        let help = self.show_help.then_some(self.help_text.as_str());
        let mut panels = Vec::new();
        if let Some(text) = &stats {
            panels.push(OverlayPanel {
                text,
                corner: Corner::TopLeft,
            });
        }
        if let Some(text) = &help {
            // Below the statistics (panels in one corner stack, never overlap).
            panels.push(OverlayPanel {
                text,
                corner: Corner::TopLeft,
            });
        }
        let pose = self.playback.pose(self.gpu_scene.scene());
        // The auto exposure adapts over the time since the last frame (a camera path's
        // frames are 1/30 s apart, so a scripted run is the same on any machine).
        let recorded = Instant::now();
        let elapsed = match (scripted, self.last_recorded.replace(recorded)) {
            (Some(_), Some(_)) => Some(1.0 / PATH_FRAMES_PER_SECOND),
            (None, Some(last)) => Some((recorded - last).as_secs_f32().min(3600.0)),
            (_, None) => None,
        };
        let inputs = FrameInputs {
            camera,
            auto_exposure: self.metered(elapsed),
            bloom_intensity: self.bloom_intensity,
            // Debug views are written for exposure 1 (their values come back as written).
            exposure: if self.renderer.shading().debug_view == DebugView::None {
                self.exposure
            } else {
                1.0
            },
            lights: &self.gpu_scene.scene().lights,
            overlay: &panels,
            environment: None,
            background: self.background(),
            tone_mapping: self.tone_mapping(),
            pose: pose.as_ref(),
            // The viewer shades environments by the split sum: no sample sets to vary.
            environment_seed: 0,
            anti_aliasing: self.anti_aliasing,
        };
        self.renderer
            .record(frame.cmd, frame.slot, &self.gpu_scene, &inputs, &target)?;
        if let Some((path, requested)) = screenshot {
            let buffer = record_screenshot_copy(
                &self.device,
                frame.cmd,
                image.image,
                extent,
                ImageState::COPY_SOURCE,
                ImageState::PRESENT,
            )?;
            // Read when the frame has completed: when its slot comes round again (the
            // ring waits for that anyway) or at the end; no frame waits for it.
            self.pending_screenshot = Some(PendingScreenshot {
                slot: frame.slot,
                buffer,
                path,
                requested,
                extent,
                bgra: swapchain.format() == vk::Format::B8G8R8A8_UNORM,
            });
        }
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

    /// Shows the scene from `source`: loaded, uploaded with the current overrides (the
    /// old upload retired until the frames in flight are done with it), the camera reset
    /// to the scene's own. On error the current scene stays.
    fn load(&mut self, source: SceneSource) -> Result<(), Error> {
        let (scene, cameras) = load_scene(&source, &self.environment)?;
        let upload = self.renderer.upload(&self.overrides.apply(&scene))?;
        let old = std::mem::replace(&mut self.gpu_scene, upload);
        self.renderer.retire(old);
        self.orbit = camera::OrbitCamera::new(&scene.camera);
        self.cameras = cameras;
        self.camera_index = 0;
        self.triangles = triangles_drawn(&scene);
        self.scene_generation += 1;
        self.modified = controls::modified(&source);
        self.original = scene;
        self.playback = controls::Playback::new();
        log::info!("{}: loaded", source.label());
        self.source = source;
        Ok(())
    }

    /// Applies the overrides to the scene as loaded, as an edit between frames.
    fn apply_overrides(&mut self) -> Result<(), Error> {
        let scene = self.overrides.apply(&self.original);
        self.renderer
            .edit_scene(&mut self.gpu_scene, move |s| *s = scene)?;
        self.scene_generation += 1;
        Ok(())
    }

    /// The statistics panel's text.
    fn stats_text(&self, extent: vk::Extent2D, summary: &ViewSummary) -> String {
        let label = self.source.label();
        inspect::Stats {
            label: &label,
            extent: (extent.width, extent.height),
            triangles: self.triangles,
            lights: self.gpu_scene.scene().lights.len(),
            frame_ms: recent_median(&summary.frame_ms),
            timings: self.renderer.last_completed_timings(),
            view: self.renderer.shading().debug_view.name(),
            fresnel: self.renderer.shading().fresnel,
            overrides: &self.overrides.describe(),
            exposure: self.exposure_text(),
            histogram: self
                .auto_exposure
                .0
                .then(|| self.renderer.last_metered_exposure())
                .flatten()
                .map(inspect::histogram_line),
            camera: (self.camera_index, self.cameras.len()),
            hdr_format: self.renderer.settings().hdr_format,
            error_view: self.error_view,
            typing: self.typing.as_deref(),
            animation: self.playback.describe(self.gpu_scene.scene()),
            accumulated_paths: self.renderer.accumulated_paths(),
            transport: self
                .transport
                .as_ref()
                .and_then(|t| t.measured)
                .filter(|_| self.path_traced()),
        }
        .text()
    }

    /// Whether the frames are path traced (J, `--path-trace on`).
    fn path_traced(&self) -> bool {
        combustion_renderer::optional_pass("path-trace")
            .is_some_and(|p| self.renderer.shading().optional_passes.contains(p))
    }

    /// Waits for the frames in flight and collects their GPU times: at the end, and
    /// before the error view's frames (which use the renderer's slots too: a
    /// diagnostic pause, not part of a normal frame).
    fn pause_for_a_measurement(&mut self, summary: &mut ViewSummary) -> Result<(), Error> {
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

    /// The error view of a path-traced view: once the view has settled, its real-time
    /// frame (the same inputs with path tracing off, read back once); then, each time the
    /// path-traced mean has reached [`inspect::TRANSPORT_FIRST_PATHS`] paths a pixel and
    /// each time they double, the mean read back (the next frame of the same history)
    /// and the real-time frame's relative error against it shown as the heat map.
    fn update_transport_view(
        &mut self,
        key: inspect::ViewKey,
        camera: combustion_scene::Camera,
        summary: &mut ViewSummary,
    ) -> Result<(), Error> {
        let (width, height) = key.extent;
        let pose = self.playback.current_pose(self.gpu_scene.scene());
        let lights = self.gpu_scene.scene().lights.clone();
        // The viewer's own frame's inputs, so that the mean read back is the history the
        // frames build (anything else would start it again); bloom's share 0 and no
        // overlay: the map is of radiance.
        let inputs = FrameInputs {
            camera,
            exposure: self.exposure,
            lights: &lights,
            overlay: &[],
            environment: None,
            background: self.background(),
            tone_mapping: self.tone_mapping(),
            pose: pose.as_ref(),
            environment_seed: 0,
            anti_aliasing: self.anti_aliasing,
            auto_exposure: None,
            bloom_intensity: 0.0,
        };
        match &mut self.transport {
            Some(view) if view.key == key && !view.realtime.is_empty() => {
                let paths = self.renderer.accumulated_paths();
                let next = view.measured.map_or(inspect::TRANSPORT_FIRST_PATHS, |m| {
                    m.paths.saturating_mul(2)
                });
                if paths < next {
                    return Ok(());
                }
                let realtime = std::mem::take(&mut view.realtime);
                self.pause_for_a_measurement(summary)?;
                let frame = self.renderer.render_with(
                    &self.gpu_scene,
                    &inputs,
                    width,
                    height,
                    combustion_renderer::Readback::IMAGES,
                )?;
                drop(self.renderer.take_completed_timings());
                let paths = self.renderer.accumulated_paths();
                let (errors, measured) = inspect::transport_errors(&realtime, &frame.hdr, paths);
                self.renderer
                    .set_overlay_image(Some(&inspect::transport_overlay(width, height, &errors)))?;
                log::info!(
                    "error view: the real-time frame against {paths} paths a pixel: mean relative error {:.3e}, p95 {:.3e}, radiance {:+.1} %",
                    measured.mean_relative,
                    measured.p95_relative,
                    measured.brightness * 100.0
                );
                if let Some(view) = self.transport.as_mut() {
                    view.realtime = realtime;
                    view.measured = Some(measured);
                }
                return Ok(());
            }
            Some(view) if view.key != key => {
                // Another view: its map goes at once; measured once it has stayed put.
                view.key = key;
                view.realtime.clear();
                view.measured = None;
                self.view_changed = Instant::now();
                self.renderer.set_overlay_image(None)?;
                return Ok(());
            }
            _ => {}
        }
        // The real-time frame of this view (measured at once when the error view or
        // path tracing was just turned on; after a move, once it has settled).
        if self.view_changed.elapsed().as_secs_f32() < ERROR_VIEW_SETTLE_SECONDS
            && self.transport.is_some()
        {
            return Ok(());
        }
        self.pause_for_a_measurement(summary)?;
        let traced = self.renderer.shading();
        let realtime_shading = ShadingOptions {
            optional_passes: traced.optional_passes.with(
                combustion_renderer::optional_pass("path-trace").expect("declared"),
                false,
            ),
            ..traced
        };
        self.renderer
            .set_shading(realtime_shading, &[&self.gpu_scene])?;
        let frame = self.renderer.render_with(
            &self.gpu_scene,
            &inputs,
            width,
            height,
            combustion_renderer::Readback::IMAGES,
        );
        // Back to path tracing whatever the render did (its history starts again).
        self.renderer.set_shading(traced, &[&self.gpu_scene])?;
        let frame = frame?;
        drop(self.renderer.take_completed_timings());
        self.transport = Some(TransportView {
            key,
            realtime: frame.hdr,
            measured: None,
        });
        Ok(())
    }

    /// Keeps the error view's map current: a map of another view is taken away at
    /// once, and the view is measured again once it has stopped changing.
    fn update_error_view(
        &mut self,
        camera: combustion_scene::Camera,
        extent: vk::Extent2D,
        summary: &mut ViewSummary,
    ) -> Result<(), Error> {
        if self.error_view.is_none() {
            return Ok(());
        }
        let key = inspect::ViewKey {
            camera,
            extent: (extent.width, extent.height),
            scene_generation: self.scene_generation,
            fresnel: self.renderer.shading().fresnel,
            animation: (self.playback.animation, self.playback.time),
        };
        if self.path_traced() {
            return self.update_transport_view(key, camera, summary);
        }
        if self.transport.take().is_some() {
            // Path tracing was turned off: the one-bounce map of this view, at once.
            self.renderer.set_overlay_image(None)?;
            if let Some(view) = self.error_view.as_mut() {
                *view = inspect::ErrorView::default();
            }
        }
        let Some(view) = self.error_view.as_mut() else {
            return Ok(());
        };
        match view.measured {
            Some((measured, _)) if measured == key => return Ok(()),
            Some(_) => {
                view.measured = None;
                view.pending = Some(key);
                self.view_changed = Instant::now();
                self.renderer.set_overlay_image(None)?;
                return Ok(());
            }
            None if view.pending.is_some_and(|pending| pending != key) => {
                // Still changing: wait until it has stayed put.
                view.pending = Some(key);
                self.view_changed = Instant::now();
                return Ok(());
            }
            None if view.pending.is_some()
                && self.view_changed.elapsed().as_secs_f32() < ERROR_VIEW_SETTLE_SECONDS =>
            {
                return Ok(())
            }
            None => {}
        }
        // The measured frame's GPU times are not the viewer's.
        self.pause_for_a_measurement(summary)?;
        let pose = self.playback.current_pose(self.gpu_scene.scene());
        let inputs = FrameInputs {
            camera,
            exposure: self.exposure,
            lights: &self.gpu_scene.scene().lights,
            overlay: &[],
            environment: None,
            // The error is measured on surfaces; the background stays black (the map
            // counts a lit background as a fault).
            background: Background::None,
            tone_mapping: ToneMapping::Exponential,
            pose: pose.as_ref(),
            environment_seed: 0,
            anti_aliasing: combustion_renderer::AntiAliasing::None,
            // The error is of radiance: the exposure only colours the frame shown, and
            // bloom (intensity 0 leaves every pixel as it was) would count as error.
            auto_exposure: None,
            bloom_intensity: 0.0,
        };
        let error = inspect::measure_error(
            &mut self.renderer,
            &self.gpu_scene,
            &inputs,
            (extent.width, extent.height),
        )?;
        drop(self.renderer.take_completed_timings());
        if let Some(view) = self.error_view.as_mut() {
            view.measured = Some((key, error));
        }
        Ok(())
    }

    /// Turns the error view on (measuring the next frame at once) or off.
    fn toggle_error_view(&mut self) -> Result<(), Error> {
        self.transport = None;
        if self.error_view.take().is_some() {
            self.renderer.set_overlay_image(None)?;
            return Ok(());
        }
        // The map is of radiance: the debug view goes back to it.
        let shading = ShadingOptions {
            debug_view: DebugView::None,
            ..self.renderer.shading()
        };
        self.renderer.set_shading(shading, &[&self.gpu_scene])?;
        // Measured at once: nothing is pending yet.
        self.error_view = Some(inspect::ErrorView::default());
        Ok(())
    }

    /// Applies the typed outside medium's index (I, then Enter).
    fn apply_typed_medium(&mut self, typed: &str) -> Result<(), Error> {
        let ior: f32 = typed
            .trim()
            .parse()
            .map_err(|_| Error::Usage(format!("outside medium: `{typed}` is not a number")))?;
        // The scene's validation (in the edit) refuses what no medium can be.
        let old = self.overrides;
        self.overrides.medium = Some(ior);
        if let Err(e) = self.apply_overrides() {
            self.overrides = old;
            return Err(e);
        }
        Ok(())
    }

    /// Reloads a scene file that changed on disk (checked once a second).
    fn poll_file(&mut self) -> Result<(), Error> {
        if self.last_poll.elapsed().as_secs_f32() < 1.0 {
            return Ok(());
        }
        self.last_poll = Instant::now();
        let now = controls::modified(&self.source);
        if now.is_some() && now != self.modified {
            log::info!("{}: changed on disk, reloading", self.source.label());
            // Tried once per change: a file broken on disk is reported once, not every
            // second, and read again when it changes next.
            self.modified = now;
            self.load(self.source.clone())?;
        }
        Ok(())
    }

    /// The window's title: the scene, the toggles, the error view, the GPU time.
    /// The background of the frames shown: the one asked for, else the environment
    /// where one lights the scene (none in debug views, whose values are not radiance).
    fn background(&self) -> Background {
        if self.renderer.shading().debug_view != DebugView::None {
            return Background::None;
        }
        Background::asked_or_default(self.background, self.gpu_scene.scene())
    }

    /// The tone curve of the frames shown: the one asked for, else the scene source's
    /// default; debug views always use the exponential curve, which their values are
    /// written through (inverted) to come back as written.
    fn tone_mapping(&self) -> ToneMapping {
        if self.renderer.shading().debug_view != DebugView::None {
            return ToneMapping::Exponential;
        }
        self.tone_mapping
            .unwrap_or_else(|| crate::default_tone_mapping(&self.source))
    }

    fn title(&self, gpu_ms: Option<f64>) -> String {
        let fresnel = self.renderer.shading().fresnel.description();
        let gpu = gpu_ms.map_or(String::new(), |ms| format!(" — {ms:.1} ms GPU"));
        let error = match self.error_view.map(|v| v.measured) {
            None => String::new(),
            Some(None) => " — error view (measuring)".to_owned(),
            Some(Some((_, e))) => format!(" — error view max {:.2e}", e.max_relative),
        };
        let typing = self
            .typing
            .as_ref()
            .map_or(String::new(), |t| format!(" — typing η {t}_"));
        let camera = if self.cameras.len() > 1 {
            format!(
                " — camera {} of {}",
                self.camera_index + 1,
                self.cameras.len()
            )
        } else {
            String::new()
        };
        format!(
            "combustion — {} — {} — {fresnel}, {}, {}{camera}{error}{typing}{gpu}",
            self.source.label(),
            self.renderer.shading().debug_view.name(),
            self.overrides.describe(),
            self.exposure_text()
        )
    }

    /// Switches the optional pass `name` on or off for the frames to come (its pipelines
    /// built now, between frames).
    fn toggle_pass(&mut self, name: &str) -> Result<(), Error> {
        let Some(pass) = combustion_renderer::optional_pass(name) else {
            return Ok(());
        };
        let mut shading = self.renderer.shading();
        let on = !shading.optional_passes.contains(pass);
        shading.optional_passes = shading.optional_passes.with(pass, on);
        self.renderer.set_shading(shading, &[&self.gpu_scene])?;
        // What the renderer took (a pass that needs ray queries is left out, with a
        // warning, on a device without them).
        let on = self.renderer.shading().optional_passes.contains(pass);
        log::info!("{name} {}", if on { "on" } else { "off" });
        Ok(())
    }

    /// The auto exposure of a frame recorded `elapsed` seconds after the previous one
    /// (None: the first), when it is on and the view shows radiance.
    fn metered(&self, elapsed: Option<f32>) -> Option<combustion_renderer::AutoExposure> {
        let (on, settings) = self.auto_exposure;
        (on && self.renderer.shading().debug_view == DebugView::None).then_some(
            combustion_renderer::AutoExposure {
                elapsed_seconds: elapsed,
                ..settings
            },
        )
    }

    /// The exposure as the title and the statistics say it: the factor, or the auto
    /// exposure's EV100, its target and the compensation (of the latest completed
    /// frame).
    fn exposure_text(&self) -> String {
        if !self.auto_exposure.0 {
            return format!("exposure {:.2}", self.exposure);
        }
        let compensation = self.auto_exposure.1.compensation;
        match self.renderer.last_metered_exposure() {
            Some(m) => format!(
                "auto EV100 {:.2} → {:.2} {compensation:+}",
                m.ev100, m.target_ev100
            ),
            None => format!("auto exposure {compensation:+}"),
        }
    }

    /// Waits for every frame in flight and collects their GPU times.
    fn finish(&mut self, summary: &mut ViewSummary) -> Result<(), Error> {
        self.pause_for_a_measurement(summary)?;
        write_screenshot(self.pending_screenshot.take(), summary)
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
        let scripted = self.path.as_ref().map(|path| {
            path.at(
                self.presented as f32 / PATH_FRAMES_PER_SECOND,
                &state.gpu_scene.scene().camera,
            )
        });
        if self
            .desc
            .frames
            .is_some_and(|n| self.presented + 1 == u64::from(n))
        {
            // The last frame of the run: the one --screenshot asks for.
            if let Some(path) = &self.desc.screenshot {
                state.screenshot = Some((path.clone(), true));
            }
        }
        match state.draw(self.desc.vsync, scripted, &mut self.summary) {
            Err(e) => self.fail(event_loop, e),
            Ok(None) => {
                // Out of date: try again at once; no area or hidden: wait for an event
                // that shows the window again (no busy loop).
                if state.stale && !state.hidden() {
                    let size = state.window.inner_size();
                    if size.width > 0 && size.height > 0 {
                        state.window.request_redraw();
                    }
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
                let title = state.title(self.summary.gpu_total_ms.last().copied());
                if title != state.title {
                    state.window.set_title(&title);
                    state.title = title;
                }
                if let Err(e) = state.poll_file() {
                    log::error!("{e}");
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
        let Some((scene, cameras)) = self.scene.take() else {
            return; // already set up (resumed is called again on some platforms)
        };
        let title = format!("combustion — {}", self.label);
        match State::new(event_loop, self.desc, &scene, cameras, &title) {
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
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(_) => {
                if let Some(state) = self.state.as_mut() {
                    state.stale = true;
                    state.check_minimized();
                }
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            WindowEvent::Occluded(hidden) => {
                // Minimised or fully covered: no frames (and no busy loop) until shown.
                if let Some(state) = self.state.as_mut() {
                    log::info!("window {}", if hidden { "occluded" } else { "shown" });
                    let was_hidden = state.hidden();
                    state.occluded = hidden;
                    if state.hidden() != was_hidden {
                        log::info!(
                            "drawing {}",
                            if hidden {
                                "paused (window hidden)"
                            } else {
                                "resumed"
                            }
                        );
                    }
                    state.check_minimized();
                }
            }
            WindowEvent::KeyboardInput { event, .. } => self.key(event_loop, &event),
            WindowEvent::Focused(focused) => {
                log::info!("window {}", if focused { "focused" } else { "unfocused" });
                if let Some(state) = self.state.as_mut() {
                    if !focused {
                        // Keys and buttons released elsewhere never come back as releases.
                        state.input = Input::default();
                    }
                    state.check_minimized();
                }
            }
            WindowEvent::CursorLeft { .. } => {
                if let Some(state) = self.state.as_mut() {
                    state.input.cursor = None;
                }
            }
            WindowEvent::DroppedFile(path) => {
                if let Some(state) = self.state.as_mut() {
                    if let Err(e) = state.load(controls::dropped(path)) {
                        log::error!("{e}");
                    }
                }
            }
            WindowEvent::MouseInput {
                state: pressed,
                button,
                ..
            } => {
                if let Some(state) = self.state.as_mut() {
                    let down = pressed == ElementState::Pressed;
                    match button {
                        MouseButton::Left => state.input.orbiting = down,
                        MouseButton::Right | MouseButton::Middle => state.input.panning = down,
                        _ => {}
                    }
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some(state) = self.state.as_mut() {
                    let now = (position.x, position.y);
                    if let Some((x, y)) = state.input.cursor.replace(now) {
                        let (dx, dy) = ((now.0 - x) as f32, (now.1 - y) as f32);
                        let height = state.window.inner_size().height as f32;
                        if state.input.orbiting && state.input.flying() {
                            state.orbit.look(dx, dy);
                        } else if state.input.orbiting {
                            state.orbit.orbit(dx, dy);
                        } else if state.input.panning {
                            state.orbit.pan(dx, dy, height);
                        }
                    }
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                if let Some(state) = self.state.as_mut() {
                    let steps = match delta {
                        MouseScrollDelta::LineDelta(_, y) => y,
                        MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                    };
                    state.orbit.zoom(steps);
                }
            }
            _ => {}
        }
    }
}

impl App<'_> {
    /// The keys that change the scene or its toggles; unknown keys do nothing.
    fn toggle(state: &mut State, text: &str) -> Result<(), Error> {
        match text {
            "g" | "G" => {
                let mut shading = state.renderer.shading();
                shading.fresnel = controls::toggle_fresnel(shading.fresnel);
                state.renderer.set_shading(shading, &[&state.gpu_scene])?;
            }
            "k" | "K" | "l" | "L" => {
                let mut shading = state.renderer.shading();
                shading.shadows = if text.eq_ignore_ascii_case("k") {
                    controls::toggle_shadows(shading.shadows)
                } else {
                    controls::cycle_shadow_filter(shading.shadows)
                };
                state.renderer.set_shading(shading, &[&state.gpu_scene])?;
                log::info!(
                    "shadows {}",
                    shading.shadows.map_or("off", |s| s.filter.name())
                );
            }
            "t" | "T" => state.toggle_pass("temporal-anti-aliasing")?,
            "y" | "Y" => state.toggle_pass("bloom")?,
            "j" | "J" => state.toggle_pass("path-trace")?,
            "b" | "B" => {
                let mut shading = state.renderer.shading();
                shading.optional_passes = controls::cycle_occlusion(
                    shading.optional_passes,
                    state.renderer.device().ray_queries(),
                );
                state.renderer.set_shading(shading, &[&state.gpu_scene])?;
                let names: Vec<&str> = shading.optional_passes.iter().map(|p| p.name).collect();
                log::info!(
                    "environment occlusion: {}",
                    if names.is_empty() {
                        "none".to_owned()
                    } else {
                        names.join(", ")
                    }
                );
            }
            "m" | "M" | "o" | "O" => {
                let old = state.overrides;
                if text.eq_ignore_ascii_case("m") {
                    state.overrides.cycle_diffuse();
                } else {
                    state.overrides.cycle_medium();
                }
                if let Err(e) = state.apply_overrides() {
                    state.overrides = old; // the edit changed nothing
                    return Err(e);
                }
            }
            "h" | "H" => {
                state.show_help = !state.show_help;
                log::info!("help panel {}", shown_or_hidden(state.show_help));
            }
            "i" | "I" => state.typing = Some(String::new()),
            "x" | "X" => state.toggle_error_view()?,
            "c" | "C" => {
                if !state.cameras.is_empty() {
                    state.camera_index = (state.camera_index + 1) % state.cameras.len();
                    state.orbit = camera::OrbitCamera::new(&state.cameras[state.camera_index]);
                    log::info!(
                        "camera {} of {}",
                        state.camera_index + 1,
                        state.cameras.len()
                    );
                }
            }
            "v" | "V" => {
                if state.error_view.is_some() {
                    state.toggle_error_view()?; // back to the debug views
                }
                let mut shading = state.renderer.shading();
                shading.debug_view = shading.debug_view.next();
                state.renderer.set_shading(shading, &[&state.gpu_scene])?;
            }
            " " => state.playback.playing = !state.playback.playing,
            "n" | "N" => state
                .playback
                .next_animation(state.gpu_scene.scene().motion.animations.len()),
            "[" | "]" => state.playback.change_speed(text == "]"),
            "," | "." => {
                state.playback.time += if text == "." {
                    controls::SCRUB_STEP
                } else {
                    -controls::SCRUB_STEP
                };
            }
            "+" | "=" | "-" | "_" if state.auto_exposure.0 => {
                let auto = &mut state.auto_exposure.1;
                let step = if matches!(text, "+" | "=") { 0.5 } else { -0.5 };
                let [low, high] = combustion_renderer::AutoExposure::COMPENSATION;
                auto.compensation = (auto.compensation + step).clamp(low, high);
            }
            "+" | "=" => state.exposure *= controls::EXPOSURE_STEP,
            "-" | "_" => state.exposure /= controls::EXPOSURE_STEP,
            "u" | "U" => {
                state.auto_exposure.0 = !state.auto_exposure.0;
                // Metering starts from the frame's own target.
                state.last_recorded = None;
            }
            digit => {
                if let Some(source) = digit.parse::<u32>().ok().and_then(controls::builtin_on_key) {
                    state.load(source)?;
                }
            }
        }
        Ok(())
    }

    /// While the outside medium's index is typed, keys edit it: digits and `.` add,
    /// Backspace removes, Enter applies, Escape cancels. Whether the key was taken.
    fn typing_key(state: Option<&mut State>, event: &KeyEvent) -> bool {
        let Some(state) = state else {
            return false;
        };
        let Some(typed) = state.typing.as_mut() else {
            return false;
        };
        match &event.logical_key {
            Key::Named(NamedKey::Escape) => state.typing = None,
            Key::Named(NamedKey::Backspace) => {
                typed.pop();
            }
            Key::Named(NamedKey::Enter) => {
                let typed = state.typing.take().unwrap_or_default();
                if let Err(e) = state.apply_typed_medium(&typed) {
                    log::error!("{e}");
                }
            }
            Key::Character(text) if typed.len() < 16 => {
                typed.extend(text.chars().filter(|c| c.is_ascii_digit() || *c == '.'));
            }
            _ => {}
        }
        true
    }

    /// Keys: fly (held), frame, reset, screenshot, quit.
    fn key(&mut self, event_loop: &ActiveEventLoop, event: &KeyEvent) {
        let down = event.state == ElementState::Pressed;
        if down && Self::typing_key(self.state.as_mut(), event) {
            return;
        }
        if down && event.logical_key == Key::Named(NamedKey::Escape) {
            event_loop.exit();
            return;
        }
        let Some(state) = self.state.as_mut() else {
            return;
        };
        if down && !event.repeat && event.logical_key == Key::Named(NamedKey::Tab) {
            state.show_stats = !state.show_stats;
            log::info!("statistics panel {}", shown_or_hidden(state.show_stats));
            return;
        }
        if down && !event.repeat && event.logical_key == Key::Named(NamedKey::F5) {
            let source = state.source.clone();
            if let Err(e) = state.load(source) {
                log::error!("{e}");
            }
            return;
        }
        let Key::Character(text) = &event.logical_key else {
            return;
        };
        if down && !event.repeat {
            if let Err(e) = Self::toggle(state, text) {
                log::error!("{e}");
            }
        }
        let fly = &mut state.input.fly;
        match text.to_lowercase().as_str() {
            "a" => fly[0][0] = down,
            "d" => fly[0][1] = down,
            "q" => fly[1][0] = down,
            "e" => fly[1][1] = down,
            "s" => fly[2][0] = down,
            "w" => fly[2][1] = down,
            "f" if down => {
                if let Some(bounds) = state.gpu_scene.scene().world_bounds() {
                    let size = state.window.inner_size();
                    let aspect = size.width.max(1) as f32 / size.height.max(1) as f32;
                    state.orbit.frame(bounds, aspect);
                }
            }
            "r" if down => state.orbit.reset(),
            "p" if down && !event.repeat => {
                // The first name not taken yet: earlier sessions' screenshots stay.
                let path = loop {
                    state.screenshots_taken += 1;
                    let path =
                        PathBuf::from(format!("combustion-{:04}.png", state.screenshots_taken));
                    if !path.exists() || state.screenshots_taken >= 9999 {
                        break path;
                    }
                };
                state.screenshot = Some((path, false));
            }
            _ => {}
        }
    }
}
