//! `combustion`: render built-in scenes headless, benchmark the passes, list devices,
//! evaluate optics terms, plot reflectance and spectra, describe scenes.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use combustion::renderer::{Distribution, FresnelModel, HdrFormat, Readback, RendererSettings};
use combustion::scene::gltf::{self, ImportOptions};
use combustion::scene::{DiffuseModel, Environment, Light, Material, Scene, BUILTIN_SCENES};
use combustion::spectra::{BuiltinMetal, Spectrum};
use combustion::vk::{DeviceDesc, DeviceSelector};
use combustion::{check_validation, output, Error, Headless, HeadlessDesc, SceneSource};
use combustion_plots::{PlotError, PlotMaterial, ReflectancePlot, FIGURE_12_ETAS};

const USAGE: &str = "\
combustion — Vulkan deferred renderer with physically based shading

USAGE:
  combustion render [SCENE] [-o OUT.png] [--hdr OUT.exr] [--width N] [--height N]
                    [--exposure X] [--hdr-format f16|f32] [--fresnel full|schlick|f82]
                    [--distribution ggx|beckmann] [--diffuse MODEL] [--max-error E]
                    [--environment studio|none|uniform:R,G,B|FILE] [--light-rig]
                    [--energy-compensation on|off]
                    [--device SEL] [--validate]
  combustion bench  [SCENE] [--width N] [--height N] [--frames N] [--frames-in-flight N]
                    [--hdr-format f16|f32] [--fresnel full|schlick|f82] [--specialised on|off]
                    [--distribution ggx|beckmann] [--diffuse MODEL]
                    [--extra-lights N] [--culling auto|always|never]
                    [--environment studio|none|uniform:R,G,B|FILE] [--light-rig]
                    [--energy-compensation on|off]
                    [--report DIR [--against PREVIOUS_DIR]]
                    [--device SEL] [--validate]
  combustion view   [SCENE] [--width N] [--height N] [--frames N] [--exposure X]
                    [--vsync on|off] [--frames-in-flight N] [--screenshot OUT.png]
                    [--camera-path FILE] [--overlay on|off] [--error-view] [--hdr-format f16|f32] [--fresnel full|schlick|f82] [--device SEL] [--validate]
  combustion eval TERM [--theta-v DEG --theta-l DEG ... | --v x,y,z --l x,y,z]
                    [--alpha A | --roughness R | --alpha-x A --alpha-y A] [--eta E|r,g,b]
                    [--k K|r,g,b] [--eta-i E] [--sigma S] [--polarisation W] [--rho R|r,g,b]
                    [--metalness M] [--dielectric-eta E] [--diffuse MODEL] [--f0 F]
  combustion eval --list
  combustion plot reflectance (--metal NAME | --dielectric ETA | --eta E|r,g,b [--k K|r,g,b]
                    | --csv FILE) [--outside-ior X] [--polarisation W] [PLOT OPTIONS]
  combustion plot spectrum (--metal NAME | --csv FILE) [PLOT OPTIONS]
  combustion plot dielectrics [--etas E,E,...] [--outside-ior X] [PLOT OPTIONS]
  combustion info SCENE [--max-error E]
  combustion devices
  combustion help

SCENE is builtin:NAME (see below; default builtin:spheres) or a glTF file (.gltf or
.glb; a file without lights is lit by the built-in studio environment).
--environment lights the scene by the studio (an analytic sky, ground and two soft
boxes), a uniform radiance (W/sr/m² per channel), an equirectangular Radiance .hdr or
OpenEXR .exr image (row 0 at +y, the centre column along -z), or none; --light-rig adds the
camera-relative key and fill lights (the earlier default for files without lights).
--energy-compensation on scales every specular lobe by 1 + F0 (1 - E)/E (Turquin 2019),
putting back the energy single-scattering GGX loses on rough surfaces (off by default:
the f64 reference is single-scattering).
--device SEL picks a Vulkan device by index or by part of its name (e.g. llvmpipe);
the COMBUSTION_DEVICE environment variable does the same. --validate turns on the
Khronos validation layer and fails if it reports anything.

plot draws PNG charts with the optics reference (no GPU): `reflectance` Rs, Rp and R
against the angle of incidence per RGB channel (rendering notes Figs. 10-11), `spectrum`
a table's n(λ), k(λ) with the RGB bands (Figs. 8-9), `dielectrics` R against angle for
several ηt (Fig. 12; default 1.1,1.33,1.5,1.8,2.4,3). --metal takes a built-in metal
(name or symbol), --csv a `wavelength_nm,n,k` table spanning 450-740 nm, --eta/--k one
value or one per RGB channel (k defaults to 0). --outside-ior is the medium's index ηi
(default 1; 1.33 for water), --polarisation the weight w of R = (1-w)Rs + wRp (default
0.5, unpolarised). PLOT OPTIONS: [-o OUT.png] [--width N] [--height N]; the default
output is reflectance.png, spectrum.png or dielectrics.png, the default size 800x500
(spectrum 800x600).

bench submits N frames with frames in flight (default 2; 1 to 3): each waits only for
the frame that used its slot. It prints the GPU time of each pass (timestamps: median,
p10, p90), the wall-clock interval between submissions, and the throughput. The
lighting pipeline is specialised to what the scene's materials use; --specialised off
measures the general pipeline instead. --extra-lights N adds N point lights with a
range (a fifth of the scene's size) scattered through it; --culling chooses when
frames cull their lights into 16×16-pixel tile lists (auto: when a light has a range;
the culling pass is timed with the lighting pass). --report DIR measures variant sets
on every built-in scene (or the scene named): the default (full Fresnel, f32 HDR,
specialised pipeline, height-correlated masking, GGX, each material's diffuse model),
each term changed alone (general pipeline; Schlick or F82; f16; separable or
approximate masking; Beckmann; Lambert, qualitative or full Oren-Nayar for every
material) and every cheap choice at once; per set the GPU time of each pass and the
error of one frame against the f64 reference (relative errors and mean FLIP), per scene
the measurement floors (trivial G-buffer fragment stage; lighting that only fetches;
plain GGX + Smith + conductor Fresnel), and frame time against size (0.5x, 1x, 1.5x)
and against 1-256 localised lights culled and not (on grid-7x7, or the scene named);
written to DIR as report.md, report.csv, floors.csv, scaling.csv, speed-vs-error.png
(with the Pareto front), scaling-resolution.png and scaling-lights.png.
--fresnel f82, --distribution beckmann and --diffuse MODEL (lambert,
oren-nayar-qualitative, oren-nayar-full; material: each its own) render or bench one
comparison variant. --against PREVIOUS_DIR adds how this run reproduces an earlier
report: rows with identical error columns, and the spread of the frame-time ratios.

view opens a window (Wayland with WAYLAND_DISPLAY, else X11 with DISPLAY, e.g. under
Xvfb) and renders the scene every frame at the window's size, into the swapchain image
on the device, with frames in flight (default 2); --vsync off presents without waiting
for the display's refresh where the window system allows it (default on). The title
and the statistics panel (--overlay off hides it; Tab while running) show the GPU time;
H lists the keys, X (or --error-view from the start) shows the error against the f64
reference. Escape or closing the
window quits, as does --frames N after N frames; a summary is printed at exit.

info prints what a scene holds (meshes, materials, lights, camera, outside medium) and
which renderer features it needs; for a glTF file also what the importer found. With
--max-error E (an accuracy budget: the mean relative error against the f64 reference)
it measures the report's variant sets on the scene at 640x360 and says which is the
fastest within E, as render --max-error E chooses (measured there at the render's size).
Logging: COMBUSTION_LOG=error|warn|info|debug|trace (default warn).";

/// Writes `text` to standard output: a closed pipe (`combustion … | head`) ends the
/// program quietly (exit 0: the reader has what it wanted); any other write error (a
/// full disk, `> /dev/full`) is reported in one line and exits 1, never ignored.
fn write_stdout(text: std::fmt::Arguments<'_>) {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(text).and_then(|()| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}

/// `println!` through [`write_stdout`].
macro_rules! outln {
    ($($arg:tt)*) => {
        write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

struct StderrLogger;

impl log::Log for StderrLogger {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.level() <= log::max_level()
    }
    fn log(&self, record: &log::Record<'_>) {
        if self.enabled(record.metadata()) {
            eprintln!("[{} {}] {}", record.level(), record.target(), record.args());
        }
    }
    fn flush(&self) {}
}

fn init_logging() {
    let level = std::env::var("COMBUSTION_LOG")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(log::LevelFilter::Warn);
    static LOGGER: StderrLogger = StderrLogger;
    let _ = log::set_logger(&LOGGER);
    log::set_max_level(level);
}

/// Options common to `render` and `bench`.
struct Options {
    scene: SceneSource,
    width: u32,
    height: u32,
    output: Option<PathBuf>,
    hdr: Option<PathBuf>,
    exposure: f32,
    hdr_format: HdrFormat,
    fresnel: FresnelModel,
    /// `render`, `bench`: the microfacet distribution.
    distribution: Distribution,
    /// `render`, `bench`: one diffuse model for every material (`None`: each its own).
    diffuse: Option<DiffuseModel>,
    frames: u32,
    /// `--frames` was given (`view` runs until closed otherwise).
    frames_given: bool,
    /// `bench`, `view`: frames the CPU may record ahead of the GPU.
    frames_in_flight: usize,
    /// `view`: wait for the display's refresh.
    vsync: bool,
    /// `view`: write the last frame to this PNG.
    screenshot: Option<PathBuf>,
    /// `view`: a scripted camera path.
    camera_path: Option<PathBuf>,
    /// `view`: the statistics panel over the frames.
    overlay: bool,
    /// `bench`: lighting pipelines specialised to the scene (off: the general one).
    specialised: bool,
    /// `view`: start in the error view.
    error_view: bool,
    /// `bench`: write the speed-against-error report here.
    report: Option<PathBuf>,
    /// `bench --report`: an earlier report's directory to compare this run with.
    against: Option<PathBuf>,
    /// `render`: the accuracy budget (mean relative error against the f64 reference).
    max_error: Option<f64>,
    /// `bench`: localised lights (with range) added to the scene.
    extra_lights: usize,
    /// `bench`: when frames cull their lights.
    culling: combustion::renderer::LightCulling,
    /// `render`, `bench`: the environment in place of the scene's own (`Some(None)`:
    /// none).
    environment: Option<Option<Environment>>,
    /// `render`, `bench`: add the camera-relative light rig.
    light_rig: bool,
    /// `render`, `bench`: multiple-scattering energy compensation.
    energy_compensation: bool,
    /// A scene was named on the command line.
    scene_given: bool,
    device: Option<DeviceSelector>,
    validate: bool,
}

/// `text` for an error message: at most 40 characters, the rest elided.
fn shortened(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((cut, _)) => format!("{}… ({} characters)", &text[..cut], text.chars().count()),
        None => text.to_owned(),
    }
}

fn number<T: std::str::FromStr>(flag: &str, value: &str) -> Result<T, Error> {
    value.parse().map_err(|_| {
        let shown = shortened(value);
        let numeric = value.parse::<f64>().is_ok_and(f64::is_finite);
        let whole_only = "0.5".parse::<T>().is_err();
        let reason = if !numeric {
            "is not a valid number"
        } else if value.starts_with('-') && "-1".parse::<T>().is_err() {
            "is negative; it takes a number of at least 0"
        } else if whole_only && value.contains(['.', 'e', 'E']) {
            "is not written as a whole number (digits only)"
        } else {
            "is out of range"
        };
        Error::Usage(format!("{flag}: `{shown}` {reason}"))
    })
}

/// An accuracy budget: a relative error above 0.
fn max_error(value: &str) -> Result<f64, Error> {
    match value.parse::<f64>() {
        Ok(e) if e.is_finite() && e > 0.0 => Ok(e),
        _ => Err(Error::Usage(format!(
            "--max-error: `{value}` is not a relative error above 0 (e.g. 1e-3)"
        ))),
    }
}

/// The option `value` names among `options` (name, value); otherwise a usage error
/// listing the names: "`--flag: `x` is not a, b or c`".
fn choice<T: Copy>(flag: &str, value: &str, options: &[(&str, T)]) -> Result<T, Error> {
    if let Some(&(_, chosen)) = options.iter().find(|(name, _)| *name == value) {
        return Ok(chosen);
    }
    let names: Vec<&str> = options.iter().map(|(name, _)| *name).collect();
    let listed = match names.split_last() {
        Some((last, [])) => (*last).to_owned(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    };
    Err(Error::Usage(format!(
        "{flag}: `{}` is not {listed}",
        shortened(value)
    )))
}

/// `--environment`: `studio`, `none`, `uniform:R,G,B` (radiance per channel) or an
/// equirectangular `.hdr` or `.exr` file.
fn environment_option(flag: &str, value: &str) -> Result<Option<Environment>, Error> {
    if let Some(rgb) = value.strip_prefix("uniform:") {
        let parts: Vec<&str> = rgb.split(',').collect();
        let channel = |text: &str| -> Result<f32, Error> { number(flag, text) };
        let radiance = match parts[..] {
            [r, g, b] => [channel(r)?, channel(g)?, channel(b)?],
            [l] => [channel(l)?; 3],
            _ => {
                return Err(Error::Usage(format!(
                    "{flag}: `{}` is not uniform:L or uniform:R,G,B",
                    shortened(value)
                )))
            }
        };
        return Ok(Some(Environment::Uniform(radiance)));
    }
    match value {
        "studio" => Ok(Some(Environment::Studio)),
        "none" => Ok(None),
        _ if [".hdr", ".exr"]
            .iter()
            .any(|e| value.to_ascii_lowercase().ends_with(e)) =>
        {
            let image = combustion::scene::EnvironmentImage::load(Path::new(value))?;
            Ok(Some(Environment::Image(std::sync::Arc::new(image))))
        }
        _ => Err(Error::Usage(format!(
            "{flag}: `{}` is not studio, none, uniform:R,G,B or an .hdr or .exr file",
            shortened(value)
        ))),
    }
}

/// The scene with `--environment` and `--light-rig` applied.
fn lit_as_asked(mut scene: Scene, o: &Options) -> Scene {
    if let Some(environment) = &o.environment {
        scene.environment = environment.clone();
    }
    if o.light_rig {
        scene
            .lights
            .extend(combustion::default_light_rig(&scene.camera));
    }
    scene
}

fn on_off(flag: &str, value: &str) -> Result<bool, Error> {
    choice(flag, value, &[("on", true), ("off", false)])
}

fn parse_options(args: &[String], command: &str) -> Result<Options, Error> {
    let mut o = Options {
        scene: SceneSource::parse("builtin:spheres"),
        width: 1280,
        height: 720,
        output: None,
        hdr: None,
        exposure: 1.0,
        hdr_format: HdrFormat::default(),
        fresnel: FresnelModel::default(),
        distribution: Distribution::Ggx,
        diffuse: None,
        frames: 30,
        frames_given: false,
        frames_in_flight: RendererSettings::default().frames_in_flight,
        vsync: true,
        screenshot: None,
        camera_path: None,
        overlay: true,
        specialised: true,
        error_view: false,
        report: None,
        against: None,
        max_error: None,
        extra_lights: 0,
        culling: combustion::renderer::LightCulling::Auto,
        environment: None,
        light_rig: false,
        energy_compensation: false,
        scene_given: false,
        device: None,
        validate: false,
    };
    let mut scene_given = false;
    let mut i = 0;
    while i < args.len() {
        let flag = args[i].as_str();
        let mut value = || -> Result<&str, Error> {
            i += 1;
            args.get(i)
                .map(String::as_str)
                .ok_or_else(|| Error::Usage(format!("{flag} needs a value")))
        };
        match flag {
            "--scene" => {
                o.scene = SceneSource::parse(value()?);
                scene_given = true;
            }
            "--width" => o.width = number(flag, value()?)?,
            "--height" => o.height = number(flag, value()?)?,
            "-o" | "--output" if command == "render" => o.output = Some(PathBuf::from(value()?)),
            "--hdr" if command == "render" => o.hdr = Some(PathBuf::from(value()?)),
            "--exposure" => o.exposure = number(flag, value()?)?,
            "--fresnel" => {
                let models = [FresnelModel::Full, FresnelModel::Schlick, FresnelModel::F82];
                o.fresnel = choice(flag, value()?, &models.map(|m| (m.name(), m)))?;
            }
            "--distribution" if command == "render" || command == "bench" => {
                let kinds = [Distribution::Ggx, Distribution::Beckmann];
                o.distribution = choice(flag, value()?, &kinds.map(|d| (d.name(), d)))?;
            }
            "--diffuse" if command == "render" || command == "bench" => {
                let mut options = vec![("material", None)];
                options.extend(DiffuseModel::ALL.map(|m| (m.name(), Some(m))));
                o.diffuse = choice(flag, value()?, &options)?;
            }
            "--environment" if command == "render" || command == "bench" => {
                o.environment = Some(environment_option(flag, value()?)?);
            }
            "--light-rig" if command == "render" || command == "bench" => o.light_rig = true,
            "--energy-compensation" if command == "render" || command == "bench" => {
                o.energy_compensation = on_off(flag, value()?)?;
            }
            "--hdr-format" => {
                o.hdr_format = choice(
                    flag,
                    value()?,
                    &[
                        ("f16", HdrFormat::Rgba16Float),
                        ("f32", HdrFormat::Rgba32Float),
                    ],
                )?;
            }
            "--frames" if command == "bench" || command == "view" => {
                o.frames = number(flag, value()?)?;
                o.frames_given = true;
            }
            "--screenshot" if command == "view" => o.screenshot = Some(PathBuf::from(value()?)),
            "--camera-path" if command == "view" => o.camera_path = Some(PathBuf::from(value()?)),
            "--vsync" if command == "view" => o.vsync = on_off(flag, value()?)?,
            "--overlay" if command == "view" => o.overlay = on_off(flag, value()?)?,
            "--specialised" if command == "bench" => o.specialised = on_off(flag, value()?)?,
            "--report" if command == "bench" => o.report = Some(PathBuf::from(value()?)),
            "--against" if command == "bench" => o.against = Some(PathBuf::from(value()?)),
            "--max-error" if command == "render" => o.max_error = Some(max_error(value()?)?),
            "--extra-lights" if command == "bench" => {
                o.extra_lights = number(flag, value()?)?;
                if o.extra_lights > 65536 {
                    return Err(Error::Usage(format!(
                        "--extra-lights: {} is more than 65536",
                        o.extra_lights
                    )));
                }
            }
            "--culling" if command == "bench" => {
                use combustion::renderer::LightCulling;
                o.culling = choice(
                    flag,
                    value()?,
                    &[
                        ("auto", LightCulling::Auto),
                        ("always", LightCulling::Always),
                        ("never", LightCulling::Never),
                    ],
                )?;
            }
            "--frames-in-flight" if command == "bench" || command == "view" => {
                o.frames_in_flight = number(flag, value()?)?;
                if !(1..=combustion::renderer::MAX_FRAMES_IN_FLIGHT).contains(&o.frames_in_flight) {
                    return Err(Error::Usage(format!(
                        "--frames-in-flight: {} is not between 1 and {}",
                        o.frames_in_flight,
                        combustion::renderer::MAX_FRAMES_IN_FLIGHT
                    )));
                }
            }
            "--device" => o.device = Some(value()?.parse()?),
            "--validate" => o.validate = true,
            "--error-view" if command == "view" => o.error_view = true,
            _ if !flag.starts_with('-') && !scene_given => {
                o.scene = SceneSource::parse(flag);
                scene_given = true;
                o.scene_given = true;
            }
            _ => {
                return Err(Error::Usage(format!(
                    "unknown argument `{flag}` for `combustion {command}` (see `combustion help`)"
                )))
            }
        }
        i += 1;
    }
    if command == "render" && o.output.is_none() && o.hdr.is_none() {
        o.output = Some(PathBuf::from("out.png"));
    }
    if o.width == 0 || o.height == 0 {
        return Err(Error::Usage(format!(
            "image size {}x{} is empty; --width and --height must be at least 1",
            o.width, o.height
        )));
    }
    if o.screenshot.is_some() && !o.frames_given {
        return Err(Error::Usage(
            "--screenshot writes the last frame of a run: give --frames N too".into(),
        ));
    }
    if (command == "bench" || o.frames_given) && o.frames == 0 {
        return Err(Error::Usage("--frames must be at least 1".into()));
    }
    Ok(o)
}

/// The device (`--device`, else `COMBUSTION_DEVICE`, else automatic) and renderer
/// settings the options ask for.
fn device_and_settings(o: &Options) -> Result<(DeviceDesc, RendererSettings), Error> {
    let selector = match &o.device {
        Some(s) => s.clone(),
        None => DeviceSelector::from_env()?,
    };
    let device = DeviceDesc {
        selector,
        validation: o.validate,
        synchronization_validation: o.validate,
        ..DeviceDesc::default()
    };
    let settings = RendererSettings {
        exposure: o.exposure,
        hdr_format: o.hdr_format,
        fresnel: o.fresnel,
        frames_in_flight: o.frames_in_flight,
    };
    Ok((device, settings))
}

fn headless(o: &Options) -> Result<Headless, Error> {
    let (device, settings) = device_and_settings(o)?;
    Headless::new(&HeadlessDesc { device, settings })
}

fn render(o: &Options) -> Result<(), Error> {
    // Fail on an unwritable destination before spending time on the render.
    let targets = o
        .output
        .iter()
        .chain(o.hdr.iter())
        .map(|path| output::check_writable(path))
        .collect::<Result<Vec<_>, _>>()?;
    if let [png, exr] = &targets[..] {
        if output::same_file(png, exr) {
            return Err(Error::Usage(format!(
                "-o and --hdr name the same file ({}): give each its own",
                png.display()
            )));
        }
    }
    let scene = lit_as_asked(o.scene.load()?, o);
    let (device, mut settings) = device_and_settings(o)?;
    // An accuracy budget: the fastest variant set within it, measured on this scene at
    // this size (5 frames each).
    let mut chosen = None;
    if let Some(budget) = o.max_error {
        let choice =
            combustion::report::choose(&o.scene, budget, o.width, o.height, 5, device.clone())?;
        let Some(set) = choice.chosen else {
            let best = choice
                .candidates
                .iter()
                .min_by(|a, b| a.mean_relative.total_cmp(&b.mean_relative));
            return Err(Error::Usage(format!(
                "--max-error {budget:e}: no variant set is within it on this scene (the most accurate, {}, has mean relative error {:.2e})",
                best.map_or("none".into(), |r| r.set.name()),
                best.map_or(f64::NAN, |r| r.mean_relative)
            )));
        };
        settings.fresnel = set.fresnel;
        settings.hdr_format = set.hdr;
        chosen = Some(set);
        outln!("variant set {} (--max-error {budget:e}; `combustion info SCENE --max-error {budget:e}` says why)", set.name());
    }
    let mut headless = Headless::new(&HeadlessDesc { device, settings })?;
    if let Some(set) = chosen {
        set.apply(headless.renderer());
    } else {
        headless.renderer().set_distribution(o.distribution);
        headless.renderer().set_diffuse_override(o.diffuse);
    }
    headless
        .renderer()
        .set_energy_compensation(o.energy_compensation)?;
    let frame = headless.render(&scene, o.width, o.height)?;
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    if let Some(path) = &o.output {
        output::write_png(path, frame.width, frame.height, &frame.ldr)?;
        outln!(
            "wrote {} ({}x{})",
            path.display(),
            frame.width,
            frame.height
        );
    }
    if let Some(path) = &o.hdr {
        output::write_exr(path, frame.width, frame.height, &frame.hdr)?;
        outln!(
            "wrote {} ({}x{}, linear float)",
            path.display(),
            frame.width,
            frame.height
        );
    }
    let t = frame.timings;
    outln!(
        "GPU time: G-buffer {:.2} ms, lighting {:.2} ms, tonemap {:.2} ms, total {:.2} ms (one frame; `combustion bench` for medians)",
        t.gbuffer_ms, t.lighting_ms, t.tonemap_ms, t.total_ms
    );
    Ok(())
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    let index = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[index]
}

/// `bench --report DIR`: every variant set on the built-in scenes (or the scene named).
fn bench_report(o: &Options, dir: &std::path::Path) -> Result<(), Error> {
    use combustion::report::{ReportDesc, VariantSet};
    if o.extra_lights > 0
        || o.culling != combustion::renderer::LightCulling::Auto
        || !o.specialised
        || o.fresnel != FresnelModel::default()
        || o.hdr_format != HdrFormat::default()
        || o.distribution != Distribution::Ggx
        || o.diffuse.is_some()
    {
        return Err(Error::Usage(
            "--report measures the variant sets and light counts itself; it takes no --fresnel, --hdr-format, --specialised, --distribution, --diffuse, --extra-lights or --culling".into(),
        ));
    }
    // An unreadable previous report and an unwritable report folder are refused before
    // minutes of measuring.
    let previous = o
        .against
        .as_deref()
        .map(combustion::report::PreviousRun::read)
        .transpose()?;
    std::fs::create_dir_all(dir).map_err(|e| {
        Error::Output(output::OutputError::Io {
            path: dir.to_path_buf(),
            source: e,
        })
    })?;
    output::check_writable(&dir.join("report.md"))?;
    let (device, _) = device_and_settings(o)?;
    let scenes = if o.scene_given {
        vec![o.scene.clone()]
    } else {
        combustion::scene::BUILTIN_SCENES
            .iter()
            .map(|name| SceneSource::Builtin((*name).to_owned()))
            .collect()
    };
    let desc = ReportDesc {
        scenes,
        sets: VariantSet::all(),
        width: o.width,
        height: o.height,
        frames: o.frames,
        device,
        floors: true,
        // Frame time against size and light count: on the scene named, else on the
        // performance scene.
        scaling: Some(if o.scene_given {
            o.scene.clone()
        } else {
            SceneSource::Builtin("grid-7x7".to_owned())
        }),
    };
    let started = Instant::now();
    let terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let measured = combustion::report::measure(&desc, |done, total, what| {
        let width = 30;
        let filled = done * width / total.max(1);
        let bar = format!(
            "[{}{}] {done}/{total} {what:<48.48}",
            "#".repeat(filled),
            ".".repeat(width - filled)
        );
        // A bar redrawn in place on a terminal; one line per step in a log.
        if terminal {
            eprint!("\r{bar}");
            if done == total {
                eprintln!();
            }
        } else {
            eprintln!("{}", bar.trim_end());
        }
    })?;
    let reproduction = previous.map(|p| p.compare(&measured.rows));
    combustion::report::write(dir, &measured, &desc, reproduction.as_ref())?;
    outln!(
        "wrote {} (report.md, report.csv, floors.csv, speed-vs-error.png, scaling.csv, scaling-*.png): {} scene(s) × {} variant sets, the floors and the scaling in {:.0} s",
        dir.display(),
        desc.scenes.len(),
        desc.sets.len(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

fn bench(o: &Options) -> Result<(), Error> {
    if let Some(dir) = &o.report {
        return bench_report(o, dir);
    }
    if o.against.is_some() {
        return Err(Error::Usage(
            "--against compares a --report run with an earlier one; give --report DIR too".into(),
        ));
    }
    let scene =
        combustion::with_localised_lights(&lit_as_asked(o.scene.load()?, o), o.extra_lights);
    let mut headless = headless(o)?;
    let device_name = {
        let renderer = headless.renderer();
        renderer.device().info().name.clone()
    };
    let renderer = headless.renderer();
    let frames_in_flight = renderer.settings().frames_in_flight;
    renderer.set_specialised(o.specialised);
    renderer.set_light_culling(o.culling);
    renderer.set_distribution(o.distribution);
    renderer.set_diffuse_override(o.diffuse);
    renderer.set_energy_compensation(o.energy_compensation)?;
    let gpu_scene = renderer.upload(&scene)?;
    let features = renderer.lighting_features(&gpu_scene);
    // One warm-up frame (first-touch allocations, driver caches) is not counted.
    renderer.render(&gpu_scene, o.width, o.height, Readback::default())?;
    renderer.take_completed_timings();
    // Frames in flight: each submission waits only for the frame that used its slot,
    // so CPU recording overlaps GPU work; the wall clock is taken between submissions.
    let mut wall_ms = Vec::with_capacity(o.frames as usize);
    let start = Instant::now();
    let mut last = start;
    for _ in 0..o.frames {
        renderer.submit_offscreen(&gpu_scene, o.width, o.height)?;
        let now = Instant::now();
        wall_ms.push((now - last).as_secs_f64() * 1e3);
        last = now;
    }
    renderer.finish_offscreen()?;
    let elapsed = start.elapsed().as_secs_f64();
    let timings = renderer.take_completed_timings();
    drop(gpu_scene);
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    let mut samples: [Vec<f64>; 4] = Default::default();
    for t in &timings {
        for (list, value) in
            samples
                .iter_mut()
                .zip([t.gbuffer_ms, t.lighting_ms, t.tonemap_ms, t.total_ms])
        {
            list.push(value);
        }
    }
    outln!(
        "scene {:?} at {}x{} on {device_name}, n={} frames ({} timed), {frames_in_flight} in flight (GPU timestamps, ms):",
        o.scene,
        o.width,
        o.height,
        o.frames,
        timings.len()
    );
    outln!(
        "lighting pipeline: {}",
        if features == combustion::renderer::LightingFeatures::ALL {
            "general (every feature)".to_owned()
        } else {
            format!("specialised to {features:?}")
        }
    );
    let ranged = scene.lights.iter().filter(|l| l.range().is_some()).count();
    outln!(
        "lights: {} ({ranged} with a range); light culling: {:?} ({})",
        scene.lights.len(),
        o.culling,
        if o.culling.culls(&scene.lights) {
            "culled into tile lists"
        } else {
            "every pixel loops over every light"
        }
    );
    outln!("{:<10} {:>9} {:>9} {:>9}", "pass", "median", "p10", "p90");
    for (name, list) in ["G-buffer", "lighting", "tonemap", "total"]
        .iter()
        .zip(&mut samples)
    {
        if list.is_empty() {
            continue;
        }
        list.sort_by(f64::total_cmp);
        outln!(
            "{:<10} {:>9.2} {:>9.2} {:>9.2}",
            name,
            percentile(list, 0.5),
            percentile(list, 0.1),
            percentile(list, 0.9)
        );
    }
    wall_ms.sort_by(f64::total_cmp);
    outln!(
        "{:<10} {:>9.2} {:>9.2} {:>9.2}",
        "wall",
        percentile(&wall_ms, 0.5),
        percentile(&wall_ms, 0.1),
        percentile(&wall_ms, 0.9)
    );
    outln!(
        "wall clock: {:.2} ms per frame ({:.1} frames/s) over {} frames; GPU total median {:.2} ms",
        elapsed * 1e3 / f64::from(o.frames),
        f64::from(o.frames) / elapsed,
        o.frames,
        if samples[3].is_empty() {
            f64::NAN
        } else {
            percentile(&samples[3], 0.5)
        }
    );
    Ok(())
}

fn view(o: &Options) -> Result<(), Error> {
    let (device, settings) = device_and_settings(o)?;
    let summary = combustion::viewer::run(&combustion::viewer::ViewerDesc {
        scene: o.scene.clone(),
        width: o.width,
        height: o.height,
        frames: o.frames_given.then_some(o.frames),
        device,
        settings,
        vsync: o.vsync,
        screenshot: o.screenshot.clone(),
        camera_path: o.camera_path.clone(),
        overlay: o.overlay,
        error_view: o.error_view,
    })?;
    let median = |list: &[f64]| {
        let mut sorted = list.to_vec();
        sorted.sort_by(f64::total_cmp);
        sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN)
    };
    outln!(
        "viewed {} frames at {}x{} on {}: GPU total median {:.2} ms, wall clock per frame median {:.2} ms ({} in flight, on-device presentation){}",
        summary.presented,
        summary.width,
        summary.height,
        summary.device_name,
        median(&summary.gpu_total_ms),
        median(&summary.frame_ms),
        settings.frames_in_flight,
        summary
            .screenshots
            .iter()
            .map(|p| format!("; screenshot {}", p.display()))
            .collect::<String>()
    );
    Ok(())
}

fn devices() -> Result<(), Error> {
    let devices = combustion::vk::Device::enumerate()?;
    if devices.is_empty() {
        return Err(Error::Vulkan(combustion::vk::VkError::NoDevice));
    }
    for d in devices {
        outln!(
            "{}: {} ({:?}, Vulkan {}.{}.{}, {}){}",
            d.index,
            d.name,
            d.device_type,
            d.api_version.0,
            d.api_version.1,
            d.api_version.2,
            d.driver,
            d.unsuitable_because
                .map(|why| format!(" — unusable: {why}"))
                .unwrap_or_default()
        );
    }
    Ok(())
}

fn eval(args: &[String]) -> Result<(), Error> {
    match args.split_first() {
        None => Err(Error::Usage(
            "`combustion eval` needs a term; `combustion eval --list` lists them".into(),
        )),
        Some((list, _)) if list == "--list" => {
            for (name, what) in combustion::eval::TERMS {
                outln!("{name:<24} {what}");
            }
            Ok(())
        }
        Some((term, rest)) => {
            outln!("{}", combustion::eval::evaluate(term, rest)?);
            Ok(())
        }
    }
}

/// `text` on one line: line breaks (an importer's or parser's detail) become "; ".
fn one_line(text: &str) -> String {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// Flags and values of a `plot` subcommand, in order; every flag takes one value.
struct PlotArgs {
    kind: &'static str,
    values: Vec<(String, String)>,
}

impl PlotArgs {
    fn parse(kind: &'static str, args: &[String], allowed: &[&str]) -> Result<Self, CliError> {
        let mut values: Vec<(String, String)> = Vec::new();
        let mut i = 0;
        while i < args.len() {
            let flag = args[i].as_str();
            let canonical = if flag == "--output" { "-o" } else { flag };
            if !allowed.contains(&canonical) {
                return Err(usage(format!(
                    "unknown argument `{flag}` for `combustion plot {kind}` (see `combustion help`)"
                )));
            }
            let value = args
                .get(i + 1)
                .ok_or_else(|| usage(format!("{flag} needs a value")))?;
            if values.iter().any(|(f, _)| f == canonical) {
                return Err(usage(format!("{flag} is given twice")));
            }
            values.push((canonical.to_owned(), value.clone()));
            i += 2;
        }
        Ok(Self { kind, values })
    }

    fn get(&self, flag: &str) -> Option<&str> {
        self.values
            .iter()
            .find(|(f, _)| f == flag)
            .map(|(_, v)| v.as_str())
    }

    fn number(&self, flag: &str, default: f64) -> Result<f64, CliError> {
        match self.get(flag) {
            None => Ok(default),
            Some(text) => Ok(parse_list(flag, text, &[1])?[0]),
        }
    }

    fn size(&self, default: (u32, u32)) -> Result<(u32, u32), CliError> {
        let dimension = |flag: &str, default: u32| -> Result<u32, CliError> {
            match self.get(flag) {
                None => Ok(default),
                Some(text) => Ok(number::<u32>(flag, text)?),
            }
        };
        Ok((
            dimension("--width", default.0)?,
            dimension("--height", default.1)?,
        ))
    }

    /// The output path (default `KIND.png`), checked before any work is done.
    fn output(&self) -> Result<PathBuf, CliError> {
        let path = PathBuf::from(
            self.get("-o")
                .map_or_else(|| format!("{}.png", self.kind), str::to_owned),
        );
        output::check_writable(&path)?;
        Ok(path)
    }
}

/// A comma-separated list of finite numbers whose length is one of `lengths` (any length
/// if `lengths` is empty).
fn parse_list(flag: &str, text: &str, lengths: &[usize]) -> Result<Vec<f64>, CliError> {
    let values = text
        .split(',')
        .map(|part| {
            let value: f64 = part
                .trim()
                .parse()
                .map_err(|_| usage(format!("{flag}: `{}` is not a number", part.trim())))?;
            if value.is_finite() {
                Ok(value)
            } else {
                Err(usage(format!("{flag}: {value} is not finite")))
            }
        })
        .collect::<Result<Vec<f64>, CliError>>()?;
    if !lengths.is_empty() && !lengths.contains(&values.len()) {
        let expected: Vec<String> = lengths.iter().map(usize::to_string).collect();
        return Err(usage(format!(
            "{flag} takes {} value(s), got {}",
            expected.join(" or "),
            values.len()
        )));
    }
    Ok(values)
}

/// One value for all three RGB channels, or one per channel.
fn rgb(flag: &str, text: &str) -> Result<[f64; 3], CliError> {
    match parse_list(flag, text, &[1, 3])?.as_slice() {
        [x] => Ok([*x; 3]),
        [r, g, b] => Ok([*r, *g, *b]),
        _ => unreachable!("parse_list checked the length"),
    }
}

fn builtin_metal(name: &str) -> Result<BuiltinMetal, CliError> {
    BuiltinMetal::from_name(name).ok_or_else(|| {
        let known: Vec<&str> = BuiltinMetal::ALL.iter().map(|m| m.name()).collect();
        usage(format!(
            "--metal: unknown metal `{name}`; built-in metals: {} (or their chemical symbols)",
            known.join(", ")
        ))
    })
}

/// Reads a `wavelength_nm,n,k` table; problems name the file and the line.
fn read_spectrum(path: &str) -> Result<Spectrum, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::Failed(format!("cannot read {path}: {e}")))?;
    Spectrum::from_csv(&text).map_err(|e| CliError::Failed(format!("{path}: {e}")))
}

/// The file name of `path` without its folder, for a plot's title.
fn file_label(path: &str) -> String {
    Path::new(path)
        .file_name()
        .map_or_else(|| path.to_owned(), |n| n.to_string_lossy().into_owned())
}

fn write_plot(path: &Path, png: &combustion_plots::Png) -> Result<(), CliError> {
    output::write_file_atomically(path, &png.bytes)?;
    outln!("wrote {} ({}x{})", path.display(), png.width, png.height);
    Ok(())
}

fn plot(args: &[String]) -> Result<(), CliError> {
    const COMMON: [&str; 3] = ["-o", "--width", "--height"];
    let Some((kind, rest)) = args.split_first() else {
        return Err(usage(
            "`combustion plot` needs a kind: reflectance, spectrum or dielectrics".into(),
        ));
    };
    match kind.as_str() {
        "reflectance" => {
            let a = PlotArgs::parse(
                "reflectance",
                rest,
                &[
                    &COMMON[..],
                    &[
                        "--metal",
                        "--dielectric",
                        "--eta",
                        "--k",
                        "--csv",
                        "--outside-ior",
                        "--polarisation",
                    ],
                ]
                .concat(),
            )?;
            let sources: Vec<&str> = ["--metal", "--dielectric", "--eta", "--csv"]
                .into_iter()
                .filter(|f| a.get(f).is_some())
                .collect();
            if sources.len() != 1 {
                return Err(usage(format!(
                    "`combustion plot reflectance` needs exactly one material: --metal NAME, --dielectric ETA, --eta (with --k) or --csv FILE{}",
                    if sources.is_empty() {
                        String::new()
                    } else {
                        format!("; got {}", sources.join(", "))
                    }
                )));
            }
            if a.get("--k").is_some() && a.get("--eta").is_none() {
                return Err(usage("--k needs --eta".into()));
            }
            let (width, height) = a.size((800, 500))?;
            let outside_eta = a.number("--outside-ior", 1.0)?;
            let polarisation_weight = a.number("--polarisation", 0.5)?;
            let path = a.output()?;
            let material = if let Some(name) = a.get("--metal") {
                PlotMaterial::Metal(builtin_metal(name)?)
            } else if let Some(eta) = a.get("--dielectric") {
                PlotMaterial::Dielectric {
                    eta: parse_list("--dielectric", eta, &[1])?[0],
                }
            } else if let Some(eta) = a.get("--eta") {
                PlotMaterial::Conductor {
                    eta: rgb("--eta", eta)?,
                    k: a.get("--k").map_or(Ok([0.0; 3]), |k| rgb("--k", k))?,
                }
            } else {
                let file = a.get("--csv").unwrap_or_default();
                PlotMaterial::Spectral {
                    name: file_label(file),
                    spectrum: read_spectrum(file)?,
                }
            };
            let png = combustion_plots::plot_reflectance(&ReflectancePlot {
                material,
                outside_eta,
                polarisation_weight,
                width,
                height,
            })?;
            write_plot(&path, &png)
        }
        "spectrum" => {
            let a = PlotArgs::parse(
                "spectrum",
                rest,
                &[&COMMON[..], &["--metal", "--csv"]].concat(),
            )?;
            let (width, height) = a.size((800, 600))?;
            let (name, spectrum) = match (a.get("--metal"), a.get("--csv")) {
                (Some(name), None) => {
                    let metal = builtin_metal(name)?;
                    (
                        format!("{} ({}, {})", metal.name(), metal.symbol(), metal.dataset()),
                        metal.spectrum().clone(),
                    )
                }
                (None, Some(file)) => {
                    let path = a.output()?;
                    let spectrum = read_spectrum(file)?;
                    let png = combustion_plots::plot_spectrum(
                        &file_label(file),
                        &spectrum,
                        width,
                        height,
                    )?;
                    return write_plot(&path, &png);
                }
                _ => return Err(usage(
                    "`combustion plot spectrum` needs exactly one of --metal NAME or --csv FILE"
                        .into(),
                )),
            };
            let path = a.output()?;
            let png = combustion_plots::plot_spectrum(&name, &spectrum, width, height)?;
            write_plot(&path, &png)
        }
        "dielectrics" => {
            let a = PlotArgs::parse(
                "dielectrics",
                rest,
                &[&COMMON[..], &["--etas", "--outside-ior"]].concat(),
            )?;
            let etas = match a.get("--etas") {
                None => FIGURE_12_ETAS.to_vec(),
                // How many is the plot's to judge (at least one, at most MAX_FAMILY).
                Some(text) => parse_list("--etas", text, &[])?,
            };
            let (width, height) = a.size((800, 500))?;
            let outside_eta = a.number("--outside-ior", 1.0)?;
            let path = a.output()?;
            let png = combustion_plots::plot_dielectric_family(&etas, outside_eta, width, height)?;
            write_plot(&path, &png)
        }
        other => Err(usage(format!(
            "unknown plot `{other}` (plots: reflectance, spectrum, dielectrics)"
        ))),
    }
}

/// `info SCENE`: what the scene holds and which renderer features it needs.
fn info(args: &[String]) -> Result<(), CliError> {
    let (source, budget) = match args {
        [source] => (source, None),
        [source, flag, value] if flag == "--max-error" => (source, Some(max_error(value)?)),
        _ => {
            return Err(usage(
                "`combustion info` takes one scene (builtin:NAME or a .gltf/.glb file), then optionally --max-error E".into(),
            ))
        }
    };
    let scene = match SceneSource::parse(source) {
        SceneSource::Builtin(name) => {
            let scene = combustion::scene::builtin_scene(&name).map_err(Error::from)?;
            outln!("scene: builtin:{name}");
            scene
        }
        SceneSource::File(path) => {
            let (mut scene, report) =
                gltf::import(&path, &ImportOptions::default()).map_err(Error::from)?;
            outln!("{report}");
            if !scene.name.is_empty() {
                outln!("scene: {}", scene.name);
            }
            if scene.lights.is_empty() && scene.environment.is_none() {
                // What `render` does with such a file (SceneSource::load).
                scene.environment = Some(Environment::Studio);
                outln!(
                    "note: the file has no lights; render lights it with the studio environment (--light-rig adds the camera-relative key and fill lights)"
                );
            }
            scene
        }
    };
    scene.validate().map_err(Error::from)?;
    write_stdout(format_args!("{}", describe_scene(&scene)));
    if let Some(budget) = budget {
        // What `render --max-error` would choose, measured here at 640×360.
        let device = DeviceDesc {
            selector: DeviceSelector::from_env().map_err(Error::from)?,
            ..DeviceDesc::default()
        };
        let choice =
            combustion::report::choose(&SceneSource::parse(source), budget, 640, 360, 10, device)?;
        outln!("variant sets measured at 640x360 (10 frames each), fastest first:");
        write_stdout(format_args!("{}", choice.explain(budget)));
    }
    Ok(())
}

fn fmt3(v: [f32; 3]) -> String {
    format!("({}, {}, {})", v[0], v[1], v[2])
}

/// `x` to 3 decimals, for printing.
fn round3(x: f32) -> f32 {
    (x * 1000.0).round() / 1000.0
}

/// `, range R m` for a light with a range.
fn fmt_range(range: Option<f32>) -> String {
    range.map_or(String::new(), |r| format!(", range {r} m"))
}

fn fmt_vec(v: glam::Vec3) -> String {
    format!("({}, {}, {})", round3(v.x), round3(v.y), round3(v.z))
}

/// One line per material: what its optics are.
fn describe_material(m: &Material, outside_ior: f32) -> String {
    let diffuse = match m.diffuse_model {
        DiffuseModel::Lambert => "Lambert",
        DiffuseModel::OrenNayarQualitative => "Oren-Nayar qualitative",
        DiffuseModel::OrenNayarFull => "Oren-Nayar full",
    };
    let dielectric = format!(
        "dielectric η {} over base colour {} ({diffuse})",
        m.dielectric_ior,
        fmt3(m.base_color)
    );
    let conductor = if m.conductor_from_base_color {
        "conductor η+ik from the base colour".to_owned()
    } else {
        let r = |v: [f32; 3]| fmt3(v.map(|x| (x * 1e4).round() / 1e4));
        format!("conductor η {} k {}", r(m.conductor.eta), r(m.conductor.k))
    };
    let mut parts = vec![if m.metalness >= 1.0 {
        conductor
    } else if m.metalness <= 0.0 {
        dielectric
    } else {
        format!("metalness {}: {conductor}; {dielectric}", m.metalness)
    }];
    parts.push(format!("roughness {}", m.roughness));
    if m.anisotropy_strength > 0.0 {
        parts.push(format!(
            "anisotropy {} at {}°",
            m.anisotropy_strength,
            m.anisotropy_rotation.to_degrees()
        ));
    }
    if m.outside_ior.is_some() {
        parts.push(format!("outside IOR {outside_ior} (own)"));
    }
    if m.polarisation_weight != 0.5 {
        parts.push(format!("polarisation weight {}", m.polarisation_weight));
    }
    let textures: Vec<&str> = m
        .texture_slots()
        .iter()
        .filter(|(_, t)| t.is_some())
        .map(|(slot, _)| slot.name())
        .collect();
    if !textures.is_empty() {
        parts.push(format!("textures: {}", textures.join(", ")));
    }
    parts.join(", ")
}

fn describe_scene(scene: &Scene) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let triangles: usize = scene.meshes.iter().map(|m| m.indices.len() / 3).sum();
    let drawn: usize = scene
        .objects
        .iter()
        .map(|o| scene.meshes[o.mesh].indices.len() / 3)
        .sum();
    let _ = writeln!(
        out,
        "meshes: {} ({triangles} triangles), objects: {} ({drawn} triangles drawn)",
        scene.meshes.len(),
        scene.objects.len()
    );
    let _ = writeln!(out, "materials: {}", scene.materials.len());
    for (i, m) in scene.materials.iter().enumerate() {
        let _ = writeln!(
            out,
            "  {i}: {}: {}",
            m.name,
            describe_material(m, scene.outside_ior_of(m))
        );
    }
    let _ = writeln!(
        out,
        "environment: {}",
        scene
            .environment
            .as_ref()
            .map_or("none".into(), |e| e.name())
    );
    let _ = writeln!(out, "lights: {}", scene.lights.len());
    for light in &scene.lights {
        let _ = match light {
            Light::Point {
                position,
                intensity,
                range,
            } => writeln!(
                out,
                "  point at {}, intensity {} W/sr{}",
                fmt_vec(*position),
                fmt3(*intensity),
                fmt_range(*range)
            ),
            Light::Directional {
                direction,
                irradiance,
            } => writeln!(
                out,
                "  directional along {}, irradiance {} W/m²",
                fmt_vec(direction.normalize()),
                fmt3(*irradiance)
            ),
            Light::Spot {
                position,
                direction,
                intensity,
                inner_cone,
                outer_cone,
                range,
            } => writeln!(
                out,
                "  spot at {} along {}, intensity {} W/sr, cone {:.1}°–{:.1}°{}",
                fmt_vec(*position),
                fmt_vec(direction.normalize()),
                fmt3(*intensity),
                inner_cone.to_degrees(),
                outer_cone.to_degrees(),
                fmt_range(*range)
            ),
        };
    }
    let c = &scene.camera;
    let _ = writeln!(
        out,
        "camera: at {} looking at {}, vertical field of view {:.1}°, near {} far {}",
        fmt_vec(c.position),
        fmt_vec(c.target),
        c.vertical_fov.to_degrees(),
        round3(c.near),
        round3(c.far)
    );
    let _ = writeln!(out, "outside medium IOR: {}", scene.outside_ior);
    let _ = writeln!(out, "renderer features needed:");
    for line in scene.features().to_string().lines() {
        let _ = writeln!(out, "  {line}");
    }
    out
}

/// A failure of the command: the facade's errors, or one of `plot`'s and `info`'s own
/// (a bad spectral table or scene file, a plot that could not be drawn).
enum CliError {
    Lib(Error),
    /// Exit status 1, message as is.
    Failed(String),
}

impl From<Error> for CliError {
    fn from(e: Error) -> Self {
        CliError::Lib(e)
    }
}

impl From<output::OutputError> for CliError {
    fn from(e: output::OutputError) -> Self {
        CliError::Lib(Error::Output(e))
    }
}

/// `plot`'s parameter errors are bad usage (exit 2); drawing and encoding failures are not.
impl From<PlotError> for CliError {
    fn from(e: PlotError) -> Self {
        match e {
            PlotError::InvalidSize { .. }
            | PlotError::InvalidParameter { .. }
            | PlotError::EmptyEtaList
            | PlotError::TooManyCurves { .. } => CliError::Lib(Error::Usage(e.to_string())),
            other => CliError::Failed(other.to_string()),
        }
    }
}

fn usage(message: String) -> CliError {
    CliError::Lib(Error::Usage(message))
}

fn run(args: &[String]) -> Result<(), CliError> {
    let (command, rest) = match args.split_first() {
        Some((c, rest)) => (c.as_str(), rest),
        None => ("help", &[][..]),
    };
    // `combustion COMMAND --help`: the command's lines of the usage.
    if rest.iter().any(|a| a == "--help" || a == "-h") {
        let known = ["render", "bench", "view", "eval", "plot", "info", "devices"];
        if known.contains(&command) {
            outln!("{}", command_usage(command));
            return Ok(());
        }
    }
    match command {
        "render" => Ok(render(&parse_options(rest, "render")?)?),
        "bench" => Ok(bench(&parse_options(rest, "bench")?)?),
        "view" => Ok(view(&parse_options(rest, "view")?)?),
        "devices" => Ok(devices()?),
        "eval" => Ok(eval(rest)?),
        "plot" => plot(rest),
        "info" => info(rest),
        "help" | "--help" | "-h" => {
            outln!("{USAGE}");
            outln!("Built-in scenes: {}.", BUILTIN_SCENES.join(", "));
            Ok(())
        }
        "--version" | "-V" => {
            outln!("combustion {}", env!("CARGO_PKG_VERSION"));
            Ok(())
        }
        other => Err(usage(format!(
            "unknown command `{other}` (commands: render, bench, view, eval, plot, info, devices, help)"
        ))),
    }
}

/// The usage lines of `command` (its entries in [`USAGE`] with their continuation lines).
fn command_usage(command: &str) -> String {
    let start = format!("  combustion {command} ");
    let bare = format!("  combustion {command}");
    let mut out = String::from("USAGE:\n");
    let mut inside = false;
    for line in USAGE.lines() {
        if line.starts_with("  combustion ") {
            inside = line.starts_with(&start) || line == bare;
        } else if !line.starts_with("    ") {
            inside = false;
        }
        if inside {
            out += line;
            out.push('\n');
        }
    }
    out + "(`combustion help` explains every option.)"
}

fn main() -> ExitCode {
    init_logging();
    // Arguments that are not UTF-8 (a file name with byte 0xff) are refused by name,
    // not a panic.
    let mut args = Vec::new();
    for (i, arg) in std::env::args_os().skip(1).enumerate() {
        match arg.into_string() {
            Ok(arg) => args.push(arg),
            Err(raw) => {
                eprintln!(
                    "error: argument {} (`{}`) is not valid UTF-8; Combustion takes UTF-8 arguments and file names",
                    i + 1,
                    shortened(&raw.to_string_lossy())
                );
                return ExitCode::from(2);
            }
        }
    }
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(CliError::Lib(e)) => {
            eprintln!("error: {}", one_line(&e.to_string()));
            match e {
                Error::Usage(_) => ExitCode::from(2),
                _ => ExitCode::FAILURE,
            }
        }
        Err(CliError::Failed(message)) => {
            eprintln!("error: {}", one_line(&message));
            ExitCode::FAILURE
        }
    }
}
