//! Combustion: a Vulkan deferred renderer with physically based shading.
//!
//! This crate is the public facade: it re-exports the engine crates and offers
//! [`Headless`], the shortest path from a scene to pixels, used by the `combustion`
//! command-line tool, the examples and the tests alike; [`viewer`] shows a scene in a
//! window (`combustion view`).
//!
//! ```no_run
//! use combustion::{Headless, HeadlessDesc, SceneSource};
//! let mut headless = Headless::new(&HeadlessDesc::default())?;
//! let scene = SceneSource::parse("builtin:spheres").load()?;
//! let frame = headless.render(&scene, 1280, 720)?;
//! combustion::output::write_png("out.png".as_ref(), frame.width, frame.height, &frame.ldr)?;
//! # Ok::<(), combustion::Error>(())
//! ```

#![warn(missing_docs)]

// The command line's modules name the facade as its users do (`combustion::…`).
extern crate self as combustion;

pub mod animation;
pub mod cli;
pub mod diff;
pub mod end_to_end;
pub mod eval;
pub mod frame_mean;
pub mod input;
pub mod output;
pub mod report;
pub mod viewer;

use std::path::PathBuf;
use std::sync::Arc;

pub use combustion_optics as optics;
pub use combustion_reference as reference;
pub use combustion_renderer as renderer;
pub use combustion_scene as scene;
pub use combustion_spectra as spectra;
pub use combustion_vk as vk;

use combustion_renderer::{Frame, Readback, RenderError, Renderer, RendererSettings};
use combustion_scene::gltf::{ImportError, ImportOptions};
use combustion_scene::{Scene, SceneError};
use combustion_vk::{Device, DeviceDesc, DeviceSelector, ValidationLog, VkError};

pub use combustion_optics::{escaped, finite_number, shortened};

/// A comma-separated list of finite numbers whose length is one of `lengths` (any length
/// if `lengths` is empty): `eval`'s inputs and `plot`'s η, k and ηt lists. The error names
/// the bad part (shortened) or the count.
pub fn number_list(text: &str, lengths: &[usize]) -> Result<Vec<f64>, String> {
    let values = text
        .split(',')
        .map(|part| {
            finite_number(part).map_err(|why| format!("`{}` {why}", shortened(part.trim())))
        })
        .collect::<Result<Vec<f64>, String>>()?;
    if !lengths.is_empty() && !lengths.contains(&values.len()) {
        let expected: Vec<String> = lengths.iter().map(usize::to_string).collect();
        return Err(format!(
            "takes {} value(s), got {}",
            expected.join(" or "),
            values.len()
        ));
    }
    Ok(values)
}

/// Any failure of the facade, one line each.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The device or a Vulkan call failed (no device, device selection, creation).
    #[error(transparent)]
    Vulkan(#[from] VkError),
    /// The renderer refused a scene, size or setting, or a Vulkan call of its own failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// A built-in scene's name is unknown, or a scene failed validation.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A glTF file could not be read or imported.
    #[error(transparent)]
    Import(#[from] ImportError),
    /// An image could not be written.
    #[error(transparent)]
    Output(#[from] output::OutputError),
    /// A plot could not be drawn or written.
    #[error(transparent)]
    Plot(#[from] combustion_plots::PlotError),
    /// A command-line value that is not allowed; the message says which and why.
    #[error("{0}")]
    Usage(String),
    /// An earlier run's `report.csv` (`bench --report --against`) cannot be read or
    /// parsed.
    #[error("previous report `{}`: {message}", path.display())]
    PreviousReport {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// A scripted camera path that cannot be read or parsed (file and line named).
    #[error("{0}")]
    CameraPath(String),
    /// An animation sampled to a pose that is not finite (the scene, animation and time
    /// named).
    #[error("{0}")]
    Animation(String),
    /// A window cannot be opened: no display server is reached (neither Wayland nor X11),
    /// or the window has no usable handle.
    #[error("cannot open a window: {0} (set WAYLAND_DISPLAY or DISPLAY, or run under Xvfb)")]
    NoWindow(String),
    /// The window, its surface or its swapchain failed.
    #[error("{0}")]
    Window(String),
    /// The device cannot do what was asked (the message says what, naming the device).
    #[error("{0}")]
    Unsupported(String),
    /// A rendered frame holds NaN or infinite radiance, or in a 16-bit HDR frame
    /// radiance at f16's largest value (65504, where a driver may clamp an overflow
    /// rather than write infinity): the scene's radiances overflow the frame's floats.
    /// Nothing is written from such a frame.
    #[error("{count} of {pixels} pixels of the frame overflowed (NaN, infinite, or f16's largest, 65504, in a 16-bit frame): the scene's radiances are too large for the frame's floats (f32, or 65504 with --hdr-format f16); nothing written")]
    NonFiniteFrame {
        /// Pixels with a NaN or infinite channel.
        count: usize,
        /// Pixels in the frame.
        pixels: usize,
    },
    /// The Vulkan validation layer reported messages ([`check_validation`]).
    #[error("the Vulkan validation layer reported {count} message(s); first: {first}")]
    Validation {
        /// How many messages.
        count: usize,
        /// The first message.
        first: String,
    },
}

/// Where a scene comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneSource {
    /// `builtin:NAME`.
    Builtin(String),
    /// A scene file.
    File(PathBuf),
}

impl SceneSource {
    /// `builtin:NAME` for a built-in scene; any other text is a file path.
    pub fn parse(text: &str) -> Self {
        match text.strip_prefix("builtin:") {
            Some(name) => Self::Builtin(name.to_owned()),
            None => Self::File(PathBuf::from(text)),
        }
    }

    /// As [`SceneSource::parse`], for a command-line argument: a file path may be any
    /// bytes the system allows (not only UTF-8).
    pub fn parse_os(text: &std::ffi::OsStr) -> Self {
        match text.to_str() {
            Some(text) => Self::parse(text),
            None => Self::File(PathBuf::from(text)),
        }
    }

    /// `builtin:NAME` or the file's path.
    pub fn label(&self) -> String {
        match self {
            Self::Builtin(name) => format!("builtin:{name}"),
            Self::File(path) => path.display().to_string(),
        }
    }

    /// Builds or imports the scene. glTF files (.gltf, .glb) go through
    /// [`combustion_scene::gltf::import`] with default options (external URIs outside the
    /// scene's folder refused); warnings go to the log. A file is lit by its own lights
    /// (KHR_lights_punctual), if it has any, and by the built-in studio environment
    /// ([`combustion_scene::Environment::Studio`]): set [`Scene::environment`] to
    /// `None` for its lights alone, or clear [`Scene::lights`] for the studio alone (the
    /// command line: `--environment none`, `--scene-lights off`; the camera-relative
    /// [`default_light_rig`] is its `--light-rig`).
    pub fn load(&self) -> Result<Scene, Error> {
        self.load_with(&ImportOptions::default())
    }

    /// As [`SceneSource::load`], with import options for files.
    pub fn load_with(&self, options: &ImportOptions) -> Result<Scene, Error> {
        self.load_with_cameras(options).map(|(scene, _)| scene)
    }

    /// As [`SceneSource::load_with`], and the views the scene offers: a file's
    /// perspective cameras placed in the scene (`ImportReport::scene_cameras`), the
    /// scene's own camera first (added when it is none of them: built-in scenes,
    /// framing cameras).
    pub fn load_with_cameras(
        &self,
        options: &ImportOptions,
    ) -> Result<(Scene, Vec<combustion_scene::Camera>), Error> {
        match self {
            Self::Builtin(name) => {
                let scene = combustion_scene::builtin_scene_with(name, options.metal_colour)?;
                let cameras = vec![scene.camera];
                Ok((scene, cameras))
            }
            Self::File(path) => {
                // The importer logs its own warnings (and lists them in the report).
                let (mut scene, report) = combustion_scene::gltf::import(path, options)?;
                let mut cameras: Vec<_> = report.scene_cameras.iter().map(|c| c.camera).collect();
                // The scene's own camera first (the one ImportOptions::camera chose).
                match cameras.iter().position(|c| *c == scene.camera) {
                    Some(i) => cameras.rotate_left(i),
                    None => cameras.insert(0, scene.camera),
                }
                // Lit by default: by the file's own lights, if it has any, and by the
                // studio environment, as glTF viewers light a file (the command line's
                // --environment replaces it, `none` removes it).
                if scene.environment.is_none() {
                    scene.environment = Some(combustion_scene::Environment::Studio);
                }
                Ok((scene, cameras))
            }
        }
    }
}

/// The tone curve a scene is shown with by default: Khronos PBR Neutral for glTF files
/// (what glTF viewers show), Combustion's exponential curve for built-in scenes (their
/// goldens and figures).
pub fn default_tone_mapping(source: &SceneSource) -> combustion_renderer::ToneMapping {
    match source {
        SceneSource::File(_) => combustion_renderer::ToneMapping::PbrNeutral,
        SceneSource::Builtin(_) => combustion_renderer::ToneMapping::Exponential,
    }
}

/// Lights for scenes that bring none (most glTF sample models): a key light from the
/// upper left behind the camera (irradiance 3 W/m²) and a cooler, weaker fill from the
/// lower right (0.8 W/m²), both directional and fixed relative to the camera.
pub fn default_light_rig(camera: &combustion_scene::Camera) -> Vec<combustion_scene::Light> {
    let forward = (camera.target - camera.position).normalize();
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
    vec![
        combustion_scene::Light::Directional {
            direction: (forward - up * 0.8 + right * 0.6).normalize(),
            irradiance: [3.0, 2.95, 2.85],
            casts_shadows: true,
            angular_diameter: 0.0,
        },
        combustion_scene::Light::Directional {
            direction: (forward + up * 0.3 - right * 0.8).normalize(),
            irradiance: [0.7, 0.75, 0.8],
            casts_shadows: true,
            angular_diameter: 0.0,
        },
    ]
}

/// `scene` with `n` more point lights, each with a range of a fifth of the scene's
/// diagonal, scattered through its bounding box (a fixed sequence: the same lights on
/// every run), for measuring how frame time grows with localised lights. Intensity is
/// (range/4)² W/sr × a colour in [0.5, 1.5)³: about 1 W/m² at a quarter of the range.
pub fn with_localised_lights(scene: &Scene, n: usize) -> Scene {
    let mut out = scene.clone();
    let (lo, hi) = scene
        .world_bounds()
        .unwrap_or((glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0)));
    let range = ((hi - lo).length() * 0.2).max(1e-3);
    let mut state = 0x9e37_79b9_u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    let power = (range / 4.0) * (range / 4.0);
    for _ in 0..n {
        let t = glam::Vec3::new(next(), next(), next());
        out.lights.push(combustion_scene::Light::Point {
            position: lo + (hi - lo) * t,
            intensity: [
                power * (0.5 + next()),
                power * (0.5 + next()),
                power * (0.5 + next()),
            ],
            range: Some(range),
            casts_shadows: true,
            radius: 0.0,
        });
    }
    out
}

/// How to set up headless rendering.
#[derive(Clone, Debug, Default)]
pub struct HeadlessDesc {
    /// The device to create: selector, validation.
    pub device: DeviceDesc,
    /// The renderer's settings.
    pub settings: RendererSettings,
}

impl HeadlessDesc {
    /// Device chosen by `COMBUSTION_DEVICE` (or automatically), validation as given.
    pub fn from_env(validation: bool) -> Result<Self, Error> {
        Ok(Self {
            device: DeviceDesc {
                selector: DeviceSelector::from_env()?,
                validation,
                ..DeviceDesc::default()
            },
            settings: RendererSettings::default(),
        })
    }
}

/// A device and a renderer, rendering without a window.
pub struct Headless {
    renderer: Renderer,
    validation: ValidationLog,
}

impl Headless {
    /// Creates the device and the renderer (compiling the shaders and building the
    /// pipelines of plain scenes).
    ///
    /// # Errors
    /// [`Error::Vulkan`] if no device fits `desc.device` or it cannot be created;
    /// [`Error::Render`] if the settings are invalid or the pipelines cannot be built.
    pub fn new(desc: &HeadlessDesc) -> Result<Self, Error> {
        let device: Arc<Device> = Device::new(&desc.device)?;
        let validation = device.validation_log();
        let renderer = Renderer::new(device, desc.settings)?;
        Ok(Self {
            renderer,
            validation,
        })
    }

    /// The renderer, e.g. to change its settings or record frames of its own.
    pub fn renderer(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    /// Uploads `scene`, renders one frame and reads back the HDR and display images.
    pub fn render(&mut self, scene: &Scene, width: u32, height: u32) -> Result<Frame, Error> {
        let gpu_scene = self.renderer.upload(scene)?;
        let frame = self
            .renderer
            .render(&gpu_scene, width, height, Readback::IMAGES)?;
        Ok(frame)
    }

    /// The validation messages seen so far (stays readable after `self` is dropped).
    pub fn validation_log(&self) -> ValidationLog {
        self.validation.clone()
    }
}

/// Fails with [`Error::Validation`] if `log` holds any message.
pub fn check_validation(log: &ValidationLog) -> Result<(), Error> {
    let messages = log.messages();
    match messages.first() {
        None => Ok(()),
        Some(first) => Err(Error::Validation {
            count: messages.len(),
            first: first.clone(),
        }),
    }
}
