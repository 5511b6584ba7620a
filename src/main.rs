//! `combustion`: render built-in scenes headless, benchmark the passes, list devices,
//! evaluate optics terms, plot reflectance and spectra, describe scenes.
//!
//! The command line is declared with clap's derive API below: every subcommand has
//! `--help`, bad usage exits 2 with clap's message, paths are taken as `OsString`s (any
//! bytes the system allows), and `combustion completions SHELL` prints completions made
//! from the same declaration.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::builder::{OsStringValueParser, PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{ArgAction, ArgGroup, Args, CommandFactory, Parser, Subcommand};

use combustion::renderer::{
    Distribution, FresnelModel, HdrFormat, LightCulling, Readback, RendererSettings,
    MAX_FRAMES_IN_FLIGHT,
};
use combustion::scene::gltf::{self, ImportOptions};
use combustion::scene::{DiffuseModel, Environment, Light, Material, Scene, BUILTIN_SCENES};
use combustion::spectra::{BuiltinMetal, Spectrum};
use combustion::vk::{DeviceDesc, DeviceSelector};
use combustion::{
    check_validation, finite_number, number_list, output, shortened, Error, Headless, HeadlessDesc,
    SceneSource,
};
use combustion_plots::{PlotError, PlotMaterial, ReflectancePlot, FIGURE_12_ETAS};

const ABOUT: &str = "Vulkan deferred renderer with physically based shading";

const LONG_ABOUT: &str = "\
Vulkan deferred renderer with physically based shading: Cook-Torrance with GGX (isotropic
and anisotropic), Oren-Nayar diffuse and the full Fresnel equations with complex IOR and
the outside medium's index, checked against an f64 optics reference.

SCENE is builtin:NAME (the list is below; default builtin:spheres) or a glTF file (.gltf
or .glb; a file without lights is lit by the built-in studio environment).

`combustion COMMAND --help` explains each command's options.
Logging: COMBUSTION_LOG=error|warn|info|debug|trace (default warn).";

const BENCH_ABOUT: &str = "\
Submits N frames with frames in flight (default 2; 1 to 3): each waits only for the frame
that used its slot. Prints the GPU time of each pass (timestamps: median, p10, p90), the
wall-clock interval between submissions, and the throughput. The lighting pipeline is
specialised to what the scene's materials use; --specialised off measures the general
pipeline instead.

--report DIR measures variant sets on every built-in scene (or the scene named): the
default (full Fresnel, f32 HDR, specialised pipeline, height-correlated masking, GGX, each
material's diffuse model), each term changed alone (general pipeline; Schlick or F82;
f16; separable or approximate masking; Beckmann; Lambert, qualitative or full Oren-Nayar
for every material) and every cheap choice at once; per set the GPU time of each pass and
the error of one frame against the f64 reference (relative errors and mean FLIP), per
scene the measurement floors (trivial G-buffer fragment stage; lighting that only
fetches; plain GGX + Smith + conductor Fresnel), and frame time against size (0.5x, 1x,
1.5x) and against 1-256 localised lights culled and not (on grid-7x7, or the scene
named); written to DIR as report.md, report.csv, floors.csv, scaling.csv,
speed-vs-error.png (with the Pareto front), scaling-resolution.png and
scaling-lights.png.";

const VIEW_ABOUT: &str = "\
Opens a window (Wayland with WAYLAND_DISPLAY, else X11 with DISPLAY, e.g. under Xvfb)
and renders the scene every frame at the window's size, into the swapchain image on the
device, with frames in flight (default 2). The title and the statistics panel show the
GPU time; H lists the keys, X (or --error-view from the start) shows the error against
the f64 reference. Escape or closing the window quits, as does --frames N after N frames;
a summary is printed at exit.";

const PLOT_ABOUT: &str = "\
Draws PNG charts with the optics reference (no GPU): `reflectance` Rs, Rp and R against
the angle of incidence per RGB channel (rendering notes Figs. 10-11), `spectrum` a
table's n(λ), k(λ) with the RGB bands (Figs. 8-9), `dielectrics` R against angle for
several ηt (Fig. 12).";

const INFO_ABOUT: &str = "\
Prints what a scene holds (meshes, materials, lights, camera, outside medium) and which
renderer features it needs; for a glTF file also what the importer found. With
--max-error E it measures the report's variant sets on the scene at 640x360 and says
which is the fastest within E, as render --max-error E chooses (measured there at the
render's size).";

/// `--help`'s closing lines: the built-in scenes, in the order the viewer's number keys
/// follow.
fn builtin_scenes_note() -> String {
    format!("Built-in scenes: {}.", BUILTIN_SCENES.join(", "))
}

#[derive(Parser)]
#[command(
    name = "combustion",
    version,
    about = ABOUT,
    long_about = LONG_ABOUT,
    after_help = builtin_scenes_note(),
    subcommand_required = true,
    arg_required_else_help = true
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene headless to a PNG (tone-mapped) and/or an OpenEXR file (linear)
    #[command(allow_negative_numbers = true, args_override_self = true, after_help = builtin_scenes_note())]
    Render(RenderArgs),
    /// Measure the passes' GPU time over many frames, or write the speed-against-error
    /// report
    #[command(long_about = BENCH_ABOUT, allow_negative_numbers = true, args_override_self = true, after_help = builtin_scenes_note())]
    Bench(BenchArgs),
    /// Open a window and render the scene every frame
    #[command(long_about = VIEW_ABOUT, allow_negative_numbers = true, args_override_self = true, after_help = builtin_scenes_note())]
    View(ViewArgs),
    /// Evaluate one term of the f64 optics reference (or the whole BRDF) and print JSON
    Eval(EvalArgs),
    /// Draw reflectance and spectrum charts as PNG files
    #[command(long_about = PLOT_ABOUT, subcommand)]
    Plot(PlotCommand),
    /// Describe what a scene holds and which renderer features it needs
    #[command(long_about = INFO_ABOUT, allow_negative_numbers = true, args_override_self = true, after_help = builtin_scenes_note())]
    Info(InfoArgs),
    /// List the Vulkan devices and whether each can run the renderer
    Devices,
    /// Print shell completions for this command line (e.g. `combustion completions bash
    /// > /etc/bash_completion.d/combustion`)
    Completions {
        /// The shell to complete for
        #[arg(value_parser = clap::value_parser!(clap_complete::Shell))]
        shell: clap_complete::Shell,
    },
}

/// The scene: positional, or as `--scene`.
#[derive(Args)]
struct SceneArg {
    /// builtin:NAME or a glTF file (.gltf, .glb) [default: builtin:spheres]
    #[arg(value_name = "SCENE", value_parser = scene_source())]
    scene: Option<SceneSource>,
    /// The same as SCENE
    #[arg(
        long = "scene",
        value_name = "SCENE",
        value_parser = scene_source(),
        conflicts_with = "scene"
    )]
    scene_option: Option<SceneSource>,
}

impl SceneArg {
    /// The scene named, if one was.
    fn given(&self) -> Option<&SceneSource> {
        self.scene.as_ref().or(self.scene_option.as_ref())
    }
    fn source(&self) -> SceneSource {
        self.given()
            .cloned()
            .unwrap_or_else(|| SceneSource::Builtin("spheres".to_owned()))
    }
}

/// What every frame is rendered with: size, exposure, Fresnel term, HDR target format.
#[derive(Args)]
struct FrameArgs {
    /// Image width in pixels
    #[arg(long, value_name = "N", default_value = "1280", value_parser = at_least_one)]
    width: u32,
    /// Image height in pixels
    #[arg(long, value_name = "N", default_value = "720", value_parser = at_least_one)]
    height: u32,
    /// Exposure: the factor applied to radiance before tone mapping
    #[arg(long, value_name = "X", default_value = "1", value_parser = positive_finite::<f32>)]
    exposure: f32,
    /// The Fresnel term: the full equations, or a comparison variant
    #[arg(long, value_name = "MODEL", default_value = FresnelModel::default().name(), value_parser = named([FresnelModel::Full, FresnelModel::Schlick, FresnelModel::F82].map(|m| (m.name(), m))))]
    fresnel: FresnelModel,
    /// The HDR target's format: 16- or 32-bit float per channel
    #[arg(long, value_name = "FORMAT", default_value = "f32", value_parser = named(HDR_FORMATS))]
    hdr_format: HdrFormat,
}

const HDR_FORMATS: [(&str, HdrFormat); 2] = [
    ("f16", HdrFormat::Rgba16Float),
    ("f32", HdrFormat::Rgba32Float),
];

/// How the scene is shaded and lit (`render`, `bench`).
#[derive(Args)]
struct ShadingArgs {
    /// The microfacet distribution (beckmann: a comparison variant)
    #[arg(long, value_name = "KIND", default_value = "ggx", value_parser = named([Distribution::Ggx, Distribution::Beckmann].map(|d| (d.name(), d))))]
    distribution: Distribution,
    /// One diffuse model for every material (material: each its own)
    #[arg(long, value_name = "MODEL", default_value = "material", value_parser = diffuse_override())]
    // Spelled out so that clap takes the value as parsed (`material` is `None`) rather than
    // as an optional argument.
    diffuse: std::option::Option<DiffuseModel>,
    /// Light the scene by `studio` (an analytic sky, ground and two soft boxes),
    /// `uniform:R,G,B` or `uniform:L` (a uniform radiance, W/sr/m² per channel), an
    /// equirectangular Radiance .hdr or OpenEXR .exr image FILE (row 0 at +y, the centre
    /// column along -z), or `none`
    #[arg(long, value_name = "ENVIRONMENT", value_parser = OsStringValueParser::new().try_map(EnvironmentChoice::parse))]
    environment: Option<EnvironmentChoice>,
    /// Add the camera-relative key and fill lights (the earlier default for files without
    /// lights)
    #[arg(long)]
    light_rig: bool,
    /// Scale every specular lobe by 1 + F0 (1 - E)/E (Turquin 2019), putting back the
    /// energy single-scattering GGX loses on rough surfaces (off by default: the f64
    /// reference is single-scattering)
    #[arg(long, value_name = "on|off", default_value = "off", action = ArgAction::Set, value_parser = on_off())]
    energy_compensation: bool,
}

/// The Vulkan device and validation.
#[derive(Args)]
struct DeviceArgs {
    /// Pick a Vulkan device by index or by part of its name (e.g. llvmpipe); the
    /// COMBUSTION_DEVICE environment variable does the same
    #[arg(long, value_name = "SEL", value_parser = |text: &str| text.parse::<DeviceSelector>())]
    device: Option<DeviceSelector>,
    /// Turn on the Khronos validation layer and fail if it reports anything
    #[arg(long)]
    validate: bool,
}

#[derive(Args)]
struct RenderArgs {
    #[command(flatten)]
    scene: SceneArg,
    /// The tone-mapped image (PNG) [default: out.png when --hdr is not given]
    #[arg(short = 'o', long = "output", value_name = "OUT.png")]
    output: Option<PathBuf>,
    /// The linear radiance (OpenEXR, ZIP-compressed)
    #[arg(long, value_name = "OUT.exr")]
    hdr: Option<PathBuf>,
    /// An accuracy budget: render with the fastest variant set whose mean relative error
    /// against the f64 reference is within E, measured on this scene at this size
    #[arg(long, value_name = "E", value_parser = relative_error)]
    max_error: Option<f64>,
    #[command(flatten)]
    frame: FrameArgs,
    #[command(flatten)]
    shading: ShadingArgs,
    #[command(flatten)]
    device: DeviceArgs,
}

#[derive(Args)]
struct BenchArgs {
    #[command(flatten)]
    scene: SceneArg,
    /// Frames to measure
    #[arg(long, value_name = "N", default_value = "30", value_parser = at_least_one)]
    frames: u32,
    /// Frames the CPU may record ahead of the GPU (1 to 3)
    #[arg(long, value_name = "N", default_value_t = RendererSettings::default().frames_in_flight, value_parser = frames_in_flight)]
    frames_in_flight: usize,
    /// Light pipelines specialised to the scene's materials (off: the general one)
    #[arg(long, value_name = "on|off", default_value = "on", action = ArgAction::Set, value_parser = on_off())]
    specialised: bool,
    /// Add N point lights with a range (a fifth of the scene's size) scattered through it
    #[arg(long, value_name = "N", default_value = "0", value_parser = extra_lights)]
    extra_lights: usize,
    /// When frames cull their lights into 16×16-pixel tile lists (auto: when a light has
    /// a range; the culling pass is timed with the lighting pass)
    #[arg(long, value_name = "WHEN", default_value = "auto", value_parser = named(CULLING))]
    culling: LightCulling,
    /// Measure the variant sets and write the speed-against-error report to DIR
    #[arg(long, value_name = "DIR", conflicts_with_all = ["fresnel", "hdr_format", "exposure", "frames_in_flight", "specialised", "distribution", "diffuse", "extra_lights", "culling", "environment", "light_rig", "energy_compensation"])]
    report: Option<PathBuf>,
    /// With --report: add how this run reproduces an earlier report (rows with identical
    /// error columns, the spread of the frame-time ratios)
    #[arg(long, value_name = "PREVIOUS_DIR", requires = "report")]
    against: Option<PathBuf>,
    #[command(flatten)]
    frame: FrameArgs,
    #[command(flatten)]
    shading: ShadingArgs,
    #[command(flatten)]
    device: DeviceArgs,
}

const CULLING: [(&str, LightCulling); 3] = [
    ("auto", LightCulling::Auto),
    ("always", LightCulling::Always),
    ("never", LightCulling::Never),
];

#[derive(Args)]
struct ViewArgs {
    #[command(flatten)]
    scene: SceneArg,
    /// Quit after N frames (default: run until the window is closed)
    #[arg(long, value_name = "N", value_parser = at_least_one)]
    frames: Option<u32>,
    /// Wait for the display's refresh (off: present at once where the window system
    /// allows it)
    #[arg(long, value_name = "on|off", default_value = "on", action = ArgAction::Set, value_parser = on_off())]
    vsync: bool,
    /// Frames the CPU may record ahead of the GPU (1 to 3)
    #[arg(long, value_name = "N", default_value_t = RendererSettings::default().frames_in_flight, value_parser = frames_in_flight)]
    frames_in_flight: usize,
    /// Write the last frame of the run to this PNG (needs --frames)
    #[arg(long, value_name = "OUT.png", requires = "frames")]
    screenshot: Option<PathBuf>,
    /// A scripted camera path
    #[arg(long, value_name = "FILE")]
    camera_path: Option<PathBuf>,
    /// The statistics panel over the frames (Tab toggles it while running)
    #[arg(long, value_name = "on|off", default_value = "on", action = ArgAction::Set, value_parser = on_off())]
    overlay: bool,
    /// Start in the error view (the error against the f64 reference)
    #[arg(long)]
    error_view: bool,
    #[command(flatten)]
    frame: FrameArgs,
    #[command(flatten)]
    device: DeviceArgs,
}

#[derive(Args)]
struct InfoArgs {
    /// builtin:NAME or a glTF file (.gltf, .glb)
    #[arg(value_name = "SCENE", value_parser = scene_source())]
    scene: SceneSource,
    /// An accuracy budget (the mean relative error against the f64 reference): measure
    /// the variant sets at 640x360 and say which is the fastest within it
    #[arg(long, value_name = "E", value_parser = relative_error)]
    max_error: Option<f64>,
}

/// `eval`'s arguments: the term, and the numeric inputs of
/// [`combustion::eval::FLAGS`], declared from that table (see the `Args` impl).
struct EvalArgs {
    list: bool,
    term: Option<String>,
    inputs: combustion::eval::Inputs,
}

impl clap::FromArgMatches for EvalArgs {
    fn from_arg_matches(matches: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut inputs = combustion::eval::Inputs::default();
        for flag in combustion::eval::FLAGS {
            if let Some(values) = matches.get_one::<Vec<f64>>(flag.long()) {
                inputs.set(flag, values.clone());
            }
        }
        if let Some(model) = matches.get_one("diffuse") {
            inputs.set_diffuse(*model);
        }
        Ok(Self {
            list: matches.get_flag("list"),
            term: matches.get_one::<String>("term").cloned(),
            inputs,
        })
    }

    fn update_from_arg_matches(&mut self, matches: &clap::ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Args for EvalArgs {
    fn augment_args(command: clap::Command) -> clap::Command {
        use clap::Arg;
        let terms = combustion::eval::TERMS
            .iter()
            .map(|(name, what)| PossibleValue::new(*name).help(*what));
        let command = command
            .about(
                "Evaluate one term of the f64 optics reference (or the whole BRDF) and print JSON",
            )
            .long_about(
                "Evaluates one term of the f64 optics reference, or the whole BRDF, and prints \
                 JSON: the term, the input as given, what was evaluated from it (directions \
                 normalised or made from angles, the half vector, α after its clamp) and the \
                 result. Directions are in the local shading frame (z = normal, x = tangent, \
                 y = bitangent), as angles or as vectors.",
            )
            .allow_negative_numbers(true)
            .args_override_self(true)
            .arg(
                Arg::new("term")
                    .value_name("TERM")
                    .help("The term to evaluate")
                    .value_parser(PossibleValuesParser::new(terms))
                    .required_unless_present("list"),
            )
            .arg(
                Arg::new("list")
                    .long("list")
                    .action(ArgAction::SetTrue)
                    .conflicts_with("term")
                    .help("List the terms with what each evaluates"),
            )
            .arg(
                Arg::new("diffuse")
                    .long("diffuse")
                    .value_name("MODEL")
                    .help("`brdf`: the diffuse model (default lambert)")
                    .value_parser(named(combustion::eval::DIFFUSE_MODELS)),
            );
        combustion::eval::FLAGS
            .iter()
            .fold(command, |command, flag| {
                let value_name = match flag.lengths {
                    [1] => "X",
                    [3] => "X,Y,Z",
                    _ => "X|R,G,B",
                };
                command.arg(
                    Arg::new(flag.long())
                        .long(flag.long())
                        .value_name(value_name)
                        .help(flag.help)
                        // Lists may start with a minus sign (`--v -1,0,1`), which clap would
                        // take for a flag; single numbers are negative numbers to it.
                        .allow_hyphen_values(flag.lengths != [1])
                        .value_parser(move |text: &str| combustion::eval::parse_value(flag, text)),
                )
            })
    }

    fn augment_args_for_update(command: clap::Command) -> clap::Command {
        Self::augment_args(command)
    }
}

#[derive(Subcommand)]
enum PlotCommand {
    /// Rs, Rp and R against the angle of incidence per RGB channel (Figs. 10-11)
    #[command(allow_negative_numbers = true, args_override_self = true)]
    Reflectance(ReflectanceArgs),
    /// A table's n(λ), k(λ) with the RGB bands (Figs. 8-9)
    #[command(allow_negative_numbers = true, args_override_self = true)]
    Spectrum(SpectrumArgs),
    /// R against the angle of incidence for several dielectrics (Fig. 12)
    #[command(allow_negative_numbers = true, args_override_self = true)]
    Dielectrics(DielectricsArgs),
}

/// Where a plot goes and its size.
#[derive(Args)]
struct PlotImageArgs {
    /// The PNG to write [default: KIND.png, after the plot's kind]
    #[arg(short = 'o', long = "output", value_name = "OUT.png")]
    output: Option<PathBuf>,
    /// Width in pixels [default: 800]
    #[arg(long, value_name = "N", value_parser = whole_number::<u32>)]
    width: Option<u32>,
    /// Height in pixels [default: 500; 600 for `plot spectrum`]
    #[arg(long, value_name = "N", value_parser = whole_number::<u32>)]
    height: Option<u32>,
}

impl PlotImageArgs {
    fn size(&self, default: (u32, u32)) -> (u32, u32) {
        (
            self.width.unwrap_or(default.0),
            self.height.unwrap_or(default.1),
        )
    }

    /// The output path (default `KIND.png`), checked before any work is done.
    fn output(&self, kind: &str) -> Result<PathBuf, CliError> {
        let path = self
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("{kind}.png")));
        output::check_writable(&path)?;
        Ok(path)
    }
}

#[derive(Args)]
#[command(group(ArgGroup::new("material").required(true).args(["metal", "dielectric", "eta", "csv"])))]
struct ReflectanceArgs {
    /// A built-in metal (name or chemical symbol)
    #[arg(long, value_name = "NAME", value_parser = builtin_metal)]
    metal: Option<BuiltinMetal>,
    /// A dielectric of index ETA
    #[arg(long, value_name = "ETA", value_parser = finite_number)]
    dielectric: Option<f64>,
    /// A conductor's η, one value or one per RGB channel
    #[arg(long, value_name = "E|R,G,B", value_parser = rgb)]
    eta: Option<[f64; 3]>,
    /// The conductor's k, one value or one per RGB channel [default: 0]
    // clap drops `requires` when a conflicting member of the group is present, so the
    // other materials are refused by name.
    #[arg(long, value_name = "K|R,G,B", value_parser = rgb, requires = "eta", conflicts_with_all = ["metal", "dielectric", "csv"])]
    k: Option<[f64; 3]>,
    /// A `wavelength_nm,n,k` table spanning 450-740 nm
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// The outside medium's index ηi (1.33 for water)
    #[arg(long, value_name = "X", default_value = "1", value_parser = finite_number)]
    outside_ior: f64,
    /// The weight w of R = (1-w)Rs + wRp (0.5: unpolarised)
    #[arg(long, value_name = "W", default_value = "0.5", value_parser = finite_number)]
    polarisation: f64,
    #[command(flatten)]
    image: PlotImageArgs,
}

#[derive(Args)]
#[command(group(ArgGroup::new("table").required(true).args(["metal", "csv"])))]
struct SpectrumArgs {
    /// A built-in metal (name or chemical symbol)
    #[arg(long, value_name = "NAME", value_parser = builtin_metal)]
    metal: Option<BuiltinMetal>,
    /// A `wavelength_nm,n,k` table spanning 450-740 nm
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    #[command(flatten)]
    image: PlotImageArgs,
}

#[derive(Args)]
struct DielectricsArgs {
    /// The indices ηt to plot [default: 1.1,1.33,1.5,1.8,2.4,3]
    #[arg(long, value_name = "E,E,...", value_parser = |text: &str| number_list(text, &[]).map(Etas))]
    etas: Option<Etas>,
    /// The outside medium's index ηi
    #[arg(long, value_name = "X", default_value = "1", value_parser = finite_number)]
    outside_ior: f64,
    #[command(flatten)]
    image: PlotImageArgs,
}

/// `--etas`: one value holding a list (an `Option<Vec<_>>` field would be a list of
/// values to clap).
#[derive(Clone)]
struct Etas(Vec<f64>);

// ---- Value parsers: each says why a value is refused; clap shows the value and the flag.

/// A whole number of type `T`; the error says why not (negative, written with a point,
/// out of range) rather than only "invalid".
fn whole_number<T: std::str::FromStr>(text: &str) -> Result<T, String> {
    text.parse().map_err(|_| {
        let numeric = text.parse::<f64>().is_ok_and(f64::is_finite);
        if !numeric {
            "is not a valid number"
        } else if text.starts_with('-') && "-1".parse::<T>().is_err() {
            "is negative"
        } else if text.contains(['.', 'e', 'E']) {
            "is not written as a whole number (digits only)"
        } else {
            "is out of range"
        }
        .to_owned()
    })
}

/// A whole number in `low..=high`.
fn whole_in<T>(text: &str, low: T, high: T) -> Result<T, String>
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display,
{
    let value = whole_number::<T>(text)?;
    if value < low || value > high {
        return Err(format!("is not between {low} and {high}"));
    }
    Ok(value)
}

/// An image size or a frame count: at least 1.
fn at_least_one(text: &str) -> Result<u32, String> {
    let value = whole_number::<u32>(text)?;
    if value == 0 {
        return Err("is 0; it must be at least 1".to_owned());
    }
    Ok(value)
}

fn frames_in_flight(text: &str) -> Result<usize, String> {
    whole_in(text, 1, MAX_FRAMES_IN_FLIGHT)
}

fn extra_lights(text: &str) -> Result<usize, String> {
    whole_in(text, 0, 65536)
}

/// A finite number above 0.
fn positive_finite<T: std::str::FromStr + Into<f64> + Copy>(text: &str) -> Result<T, String> {
    match text.parse::<T>() {
        Ok(value) if value.into().is_finite() && value.into() > 0.0 => Ok(value),
        Ok(_) => Err("is not a finite number above 0".to_owned()),
        Err(_) => Err("is not a number".to_owned()),
    }
}

/// An accuracy budget: a relative error above 0.
fn relative_error(text: &str) -> Result<f64, String> {
    positive_finite::<f64>(text).map_err(|_| "is not a relative error above 0 (e.g. 1e-3)".into())
}

/// One value for all three RGB channels, or one per channel.
fn rgb(text: &str) -> Result<[f64; 3], String> {
    match number_list(text, &[1, 3])?.as_slice() {
        [x] => Ok([*x; 3]),
        [r, g, b] => Ok([*r, *g, *b]),
        _ => Err("takes 1 or 3 values".to_owned()),
    }
}

fn builtin_metal(name: &str) -> Result<BuiltinMetal, String> {
    BuiltinMetal::from_name(name).ok_or_else(|| {
        let known: Vec<&str> = BuiltinMetal::ALL.iter().map(|m| m.name()).collect();
        format!(
            "not a built-in metal; built-in metals: {} (or their chemical symbols)",
            known.join(", ")
        )
    })
}

/// A value parser choosing among named values; clap lists the names in `--help` and in
/// its error for any other value.
fn named<T, const N: usize>(options: [(&'static str, T); N]) -> impl TypedValueParser<Value = T>
where
    T: Copy + Send + Sync + 'static,
{
    PossibleValuesParser::new(options.map(|(name, _)| name)).map(move |chosen: String| {
        options
            .iter()
            .find(|(name, _)| *name == chosen)
            .map(|(_, value)| *value)
            .unwrap_or(options[0].1)
    })
}

fn on_off() -> impl TypedValueParser<Value = bool> {
    named([("on", true), ("off", false)])
}

/// `--diffuse`: `material` (each material's own model) or one model for all.
fn diffuse_override() -> impl TypedValueParser<Value = Option<DiffuseModel>> {
    let [a, b, c] = DiffuseModel::ALL;
    named([
        ("material", None),
        (a.name(), Some(a)),
        (b.name(), Some(b)),
        (c.name(), Some(c)),
    ])
}

/// SCENE: `builtin:NAME`, or a file path in whatever bytes the system allows.
fn scene_source() -> impl TypedValueParser<Value = SceneSource> {
    OsStringValueParser::new().map(|text: OsString| SceneSource::parse_os(&text))
}

/// `--environment`, as given; [`EnvironmentChoice::load`] reads a file.
#[derive(Clone, Debug)]
enum EnvironmentChoice {
    None,
    Studio,
    Uniform([f32; 3]),
    File(PathBuf),
}

impl EnvironmentChoice {
    fn parse(text: OsString) -> Result<Self, String> {
        const EXPECTED: &str = "is not studio, none, uniform:R,G,B or an .hdr or .exr file";
        let path = PathBuf::from(&text);
        let image = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("hdr") || e.eq_ignore_ascii_case("exr"));
        let Some(text) = text.to_str() else {
            return if image {
                Ok(Self::File(path))
            } else {
                Err(EXPECTED.to_owned())
            };
        };
        if let Some(rgb) = text.strip_prefix("uniform:") {
            // A radiance: finite as the f32 the renderer keeps, and ≥ 0.
            let channel = |part: &str| -> Result<f32, String> {
                match part.trim().parse::<f32>() {
                    Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
                    Ok(_) => Err(format!(
                        "`{}` must be finite and ≥ 0 (a radiance)",
                        shortened(part)
                    )),
                    Err(_) => Err(format!("`{}` is not a number", shortened(part))),
                }
            };
            let parts: Vec<&str> = rgb.split(',').collect();
            return match parts[..] {
                [r, g, b] => Ok(Self::Uniform([channel(r)?, channel(g)?, channel(b)?])),
                [l] => Ok(Self::Uniform([channel(l)?; 3])),
                _ => Err("is not uniform:L or uniform:R,G,B".to_owned()),
            };
        }
        match text {
            "studio" => Ok(Self::Studio),
            "none" => Ok(Self::None),
            _ if image => Ok(Self::File(path)),
            _ => Err(EXPECTED.to_owned()),
        }
    }

    /// The environment (a file read and checked here).
    fn load(&self) -> Result<Option<Environment>, Error> {
        Ok(match self {
            Self::None => None,
            Self::Studio => Some(Environment::Studio),
            Self::Uniform(radiance) => Some(Environment::Uniform(*radiance)),
            Self::File(path) => {
                let image = combustion::scene::EnvironmentImage::load(path)?;
                Some(Environment::Image(std::sync::Arc::new(image)))
            }
        })
    }
}

/// The scene with `--environment` and `--light-rig` applied.
fn lit_as_asked(mut scene: Scene, shading: &ShadingArgs) -> Result<Scene, Error> {
    if let Some(environment) = &shading.environment {
        scene.environment = environment.load()?;
    }
    if shading.light_rig {
        scene
            .lights
            .extend(combustion::default_light_rig(&scene.camera));
    }
    Ok(scene)
}

/// The device (`--device`, else `COMBUSTION_DEVICE`, else automatic) and renderer
/// settings the options ask for.
fn device_and_settings(
    device: &DeviceArgs,
    frame: &FrameArgs,
    frames_in_flight: usize,
) -> Result<(DeviceDesc, RendererSettings), Error> {
    let selector = match &device.device {
        Some(s) => s.clone(),
        None => DeviceSelector::from_env()?,
    };
    let desc = DeviceDesc {
        selector,
        validation: device.validate,
        synchronization_validation: device.validate,
        ..DeviceDesc::default()
    };
    let settings = RendererSettings {
        exposure: frame.exposure,
        hdr_format: frame.hdr_format,
        fresnel: frame.fresnel,
        frames_in_flight,
    };
    Ok((desc, settings))
}

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

fn render(o: &RenderArgs) -> Result<(), Error> {
    // Fail on an unwritable destination before spending time on the render.
    let default_output = (o.output.is_none() && o.hdr.is_none()).then(|| PathBuf::from("out.png"));
    let png_path = o.output.clone().or(default_output);
    let targets = png_path
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
    let source = o.scene.source();
    let scene = lit_as_asked(source.load()?, &o.shading)?;
    let (device, mut settings) = device_and_settings(
        &o.device,
        &o.frame,
        RendererSettings::default().frames_in_flight,
    )?;
    // An accuracy budget: the fastest variant set within it, measured on this scene at
    // this size (5 frames each).
    let mut chosen = None;
    if let Some(budget) = o.max_error {
        let choice = combustion::report::choose(
            &source,
            budget,
            o.frame.width,
            o.frame.height,
            5,
            device.clone(),
        )?;
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
        headless.renderer().set_distribution(o.shading.distribution);
        headless.renderer().set_diffuse_override(o.shading.diffuse);
    }
    headless
        .renderer()
        .set_energy_compensation(o.shading.energy_compensation)?;
    let frame = headless.render(&scene, o.frame.width, o.frame.height)?;
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    if let Some(path) = &png_path {
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
fn bench_report(o: &BenchArgs, dir: &std::path::Path) -> Result<(), Error> {
    use combustion::report::{ReportDesc, VariantSet};
    // clap refuses --report with the options it sets itself (--fresnel, --hdr-format,
    // --specialised, --distribution, --diffuse, --extra-lights, --culling).
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
    let (device, _) = device_and_settings(&o.device, &o.frame, o.frames_in_flight)?;
    let scenes = if let Some(scene) = o.scene.given() {
        vec![scene.clone()]
    } else {
        combustion::scene::BUILTIN_SCENES
            .iter()
            .map(|name| SceneSource::Builtin((*name).to_owned()))
            .collect()
    };
    let desc = ReportDesc {
        scenes,
        sets: VariantSet::all(),
        width: o.frame.width,
        height: o.frame.height,
        frames: o.frames,
        device,
        floors: true,
        // Frame time against size and light count: on the scene named, else on the
        // performance scene.
        scaling: Some(if let Some(scene) = o.scene.given() {
            scene.clone()
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

fn bench(o: &BenchArgs) -> Result<(), Error> {
    if let Some(dir) = &o.report {
        return bench_report(o, dir);
    }
    let scene = combustion::with_localised_lights(
        &lit_as_asked(o.scene.source().load()?, &o.shading)?,
        o.extra_lights,
    );
    let (device, settings) = device_and_settings(&o.device, &o.frame, o.frames_in_flight)?;
    let mut headless = Headless::new(&HeadlessDesc { device, settings })?;
    let device_name = {
        let renderer = headless.renderer();
        renderer.device().info().name.clone()
    };
    let renderer = headless.renderer();
    let frames_in_flight = renderer.settings().frames_in_flight;
    renderer.set_specialised(o.specialised);
    renderer.set_light_culling(o.culling);
    renderer.set_distribution(o.shading.distribution);
    renderer.set_diffuse_override(o.shading.diffuse);
    renderer.set_energy_compensation(o.shading.energy_compensation)?;
    let gpu_scene = renderer.upload(&scene)?;
    let features = renderer.lighting_features(&gpu_scene);
    // One warm-up frame (first-touch allocations, driver caches) is not counted.
    renderer.render(
        &gpu_scene,
        o.frame.width,
        o.frame.height,
        Readback::default(),
    )?;
    renderer.take_completed_timings();
    // Frames in flight: each submission waits only for the frame that used its slot,
    // so CPU recording overlaps GPU work; the wall clock is taken between submissions.
    let mut wall_ms = Vec::with_capacity(o.frames as usize);
    let start = Instant::now();
    let mut last = start;
    for _ in 0..o.frames {
        renderer.submit_offscreen(&gpu_scene, o.frame.width, o.frame.height)?;
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
        o.scene.source(),
        o.frame.width,
        o.frame.height,
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

fn view(o: &ViewArgs) -> Result<(), Error> {
    let (device, settings) = device_and_settings(&o.device, &o.frame, o.frames_in_flight)?;
    let summary = combustion::viewer::run(&combustion::viewer::ViewerDesc {
        scene: o.scene.source(),
        width: o.frame.width,
        height: o.frame.height,
        frames: o.frames,
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

/// `text` on one line: line breaks (an importer's or parser's detail) become "; ".
fn one_line(text: &str) -> String {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// Reads a `wavelength_nm,n,k` table; problems name the file and the line.
fn read_spectrum(path: &Path) -> Result<Spectrum, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::Failed(format!("cannot read {}: {e}", path.display())))?;
    Spectrum::from_csv(&text).map_err(|e| CliError::Failed(format!("{}: {e}", path.display())))
}

/// The file name of `path` without its folder, for a plot's title.
fn file_label(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

fn write_plot(path: &Path, png: &combustion_plots::Png) -> Result<(), CliError> {
    output::write_file_atomically(path, &png.bytes)?;
    outln!("wrote {} ({}x{})", path.display(), png.width, png.height);
    Ok(())
}

fn eval(o: &EvalArgs) -> Result<(), Error> {
    if o.list {
        for (name, what) in combustion::eval::TERMS {
            outln!("{name:<24} {what}");
        }
        return Ok(());
    }
    // clap requires TERM without --list.
    let term = o.term.as_deref().unwrap_or_default();
    outln!("{}", combustion::eval::evaluate(term, &o.inputs)?);
    Ok(())
}

fn plot(command: &PlotCommand) -> Result<(), CliError> {
    match command {
        PlotCommand::Reflectance(a) => {
            let (width, height) = a.image.size((800, 500));
            let path = a.image.output("reflectance")?;
            // clap's group admits exactly one material.
            let material = if let Some(metal) = a.metal {
                PlotMaterial::Metal(metal)
            } else if let Some(eta) = a.dielectric {
                PlotMaterial::Dielectric { eta }
            } else if let Some(eta) = a.eta {
                PlotMaterial::Conductor {
                    eta,
                    k: a.k.unwrap_or([0.0; 3]),
                }
            } else {
                let file = a.csv.as_deref().unwrap_or(Path::new(""));
                PlotMaterial::Spectral {
                    name: file_label(file),
                    spectrum: read_spectrum(file)?,
                }
            };
            let png = combustion_plots::plot_reflectance(&ReflectancePlot {
                material,
                outside_eta: a.outside_ior,
                polarisation_weight: a.polarisation,
                width,
                height,
            })?;
            write_plot(&path, &png)
        }
        PlotCommand::Spectrum(a) => {
            let (width, height) = a.image.size((800, 600));
            let path = a.image.output("spectrum")?;
            // clap's group admits exactly one of --metal and --csv.
            let (name, spectrum) = match (a.metal, &a.csv) {
                (Some(metal), _) => (
                    format!("{} ({}, {})", metal.name(), metal.symbol(), metal.dataset()),
                    metal.spectrum().clone(),
                ),
                (None, file) => {
                    let file = file.as_deref().unwrap_or(Path::new(""));
                    (file_label(file), read_spectrum(file)?)
                }
            };
            let png = combustion_plots::plot_spectrum(&name, &spectrum, width, height)?;
            write_plot(&path, &png)
        }
        PlotCommand::Dielectrics(a) => {
            // How many is the plot's to judge (at least one, at most MAX_FAMILY).
            let etas = a
                .etas
                .as_ref()
                .map_or_else(|| FIGURE_12_ETAS.to_vec(), |e| e.0.clone());
            let (width, height) = a.image.size((800, 500));
            let path = a.image.output("dielectrics")?;
            let png =
                combustion_plots::plot_dielectric_family(&etas, a.outside_ior, width, height)?;
            write_plot(&path, &png)
        }
    }
}

/// `info SCENE`: what the scene holds and which renderer features it needs.
fn info(o: &InfoArgs) -> Result<(), CliError> {
    let scene = match &o.scene {
        SceneSource::Builtin(name) => {
            let scene = combustion::scene::builtin_scene(name).map_err(Error::from)?;
            outln!("scene: builtin:{name}");
            scene
        }
        SceneSource::File(path) => {
            let (mut scene, report) =
                gltf::import(path, &ImportOptions::default()).map_err(Error::from)?;
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
    if let Some(budget) = o.max_error {
        // What `render --max-error` would choose, measured here at 640×360.
        let device = DeviceDesc {
            selector: DeviceSelector::from_env().map_err(Error::from)?,
            ..DeviceDesc::default()
        };
        let choice = combustion::report::choose(&o.scene, budget, 640, 360, 10, device)?;
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

fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Render(o) => Ok(render(&o)?),
        Command::Bench(o) => Ok(bench(&o)?),
        Command::View(o) => Ok(view(&o)?),
        Command::Devices => Ok(devices()?),
        Command::Eval(o) => Ok(eval(&o)?),
        Command::Plot(kind) => plot(&kind),
        Command::Info(o) => info(&o),
        Command::Completions { shell } => {
            let mut script = Vec::new();
            clap_complete::generate(shell, &mut Cli::command(), "combustion", &mut script);
            write_stdout(format_args!("{}", String::from_utf8_lossy(&script)));
            Ok(())
        }
    }
}

/// A command line clap refused, or `--help`/`--version`: help and version go to standard
/// output (exit 0); usage errors to standard error with clap's message (exit 2), a long
/// value shortened to 40 characters.
fn refused(mut error: clap::Error) -> ExitCode {
    use clap::error::{ContextKind, ContextValue};
    if !error.use_stderr() {
        write_stdout(format_args!("{}", error.render()));
        return ExitCode::SUCCESS;
    }
    if let Some(ContextValue::String(value)) = error.get(ContextKind::InvalidValue) {
        let short = shortened(value);
        if short != *value {
            error.insert(ContextKind::InvalidValue, ContextValue::String(short));
        }
    }
    let _ = error.print();
    ExitCode::from(u8::try_from(error.exit_code()).unwrap_or(2))
}

fn main() -> ExitCode {
    init_logging();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => return refused(error),
    };
    match run(cli) {
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

#[cfg(test)]
mod tests {
    /// clap's own consistency checks of the declaration (names, groups, requirements).
    #[test]
    fn the_command_line_declaration_is_consistent() {
        use clap::CommandFactory;
        super::Cli::command().debug_assert();
    }

    /// Every option of every command, given at once where they go together: each value
    /// reaches its field with the type its parser makes (a mismatch would panic here,
    /// not in a user's hands).
    #[test]
    fn a_repeated_option_takes_its_last_value() {
        use clap::Parser;
        let line =
            "combustion render --width 8 --width 16 --validate --validate --light-rig --light-rig";
        let Ok(super::Cli {
            command: super::Command::Render(render),
        }) = super::Cli::try_parse_from(line.split(' '))
        else {
            panic!("{line} is refused");
        };
        assert_eq!(render.frame.width, 16);
        assert!(render.device.validate && render.shading.light_rig);
    }

    #[test]
    fn every_option_reaches_its_field() {
        use clap::Parser;
        let frame = "--width 8 --height 9 --exposure 2 --fresnel f82 --hdr-format f16";
        let shading = "--distribution beckmann --diffuse lambert --environment uniform:1,2,3 \
                       --light-rig --energy-compensation on";
        let device = "--device llvmpipe --validate";
        let lines = [
            format!("render builtin:spheres -o a.png --hdr a.exr --max-error 0.1 {frame} {shading} {device}"),
            format!("render --scene x.gltf --environment sky.EXR {frame}"),
            format!("bench builtin:grid-7x7 --frames 3 --frames-in-flight 3 --specialised off \
                     --extra-lights 4 --culling always {frame} {shading} {device}"),
            "bench --report r --against q --frames 2".to_owned(),
            format!("view --frames 2 --vsync off --frames-in-flight 1 --screenshot s.png \
                     --camera-path p.txt --overlay off --error-view {frame} {device}"),
            "eval brdf --theta-v 10 --phi-v -30 --l -1,0,1 --alpha 0.2 --roughness 0.3 \
             --alpha-x 0.1 --alpha-y 0.2 --eta 1,2,3 --k 2 --eta-i 1.33 --dielectric-eta 1.5 \
             --f0 0.04 --sigma 0.3 --polarisation 0.4 --rho 0.5 --metalness 1 \
             --oren-nayar-a 0.5 --diffuse oren-nayar-full --m 0,0,1 --theta-l 5 --phi-l 3 --v 0,0,1"
                .to_owned(),
            "eval --list".to_owned(),
            "plot reflectance --eta 1,2,3 --k 4 --outside-ior 1.33 --polarisation 0 -o a.png --width 10 --height 20".to_owned(),
            "plot reflectance --metal Au".to_owned(),
            "plot reflectance --dielectric 1.5".to_owned(),
            "plot reflectance --csv m.csv".to_owned(),
            "plot spectrum --metal gold -o s.png".to_owned(),
            "plot spectrum --csv m.csv".to_owned(),
            "plot dielectrics --etas 1.1,2 --outside-ior 1.33".to_owned(),
            "info builtin:spheres --max-error 1e-3".to_owned(),
            "devices".to_owned(),
            "completions zsh".to_owned(),
        ];
        for line in lines {
            let words = std::iter::once("combustion").chain(line.split_whitespace());
            if let Err(e) = super::Cli::try_parse_from(words) {
                panic!("{line}: {e}");
            }
        }
    }
}
