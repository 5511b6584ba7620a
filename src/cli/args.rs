//! The command line's declaration (clap derive): commands, their options, value parsers, and
//! what the options make (the scene as lit, the device and renderer settings).

use std::ffi::OsString;
use std::path::PathBuf;

use clap::builder::{OsStringValueParser, PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{ArgAction, ArgGroup, Args, Parser, Subcommand};

use combustion::optics::readable;
use combustion::renderer::{
    AntiAliasing, AutoExposure, Background, BaseColorStorage, Distribution, FresnelModel,
    GBufferStorage, HdrFormat, LightCulling, OptionalPasses, PhysicalCamera, RendererSettings,
    ShadingOptions, ShadowFilter, ShadowSettings, SurfaceStorage, ToneMapping, MAX_CASCADES,
    MAX_FRAMES_IN_FLIGHT, MAX_SUPERSAMPLE,
};
use combustion::report::ReportSection;
use combustion::scene::{DiffuseModel, Environment, Scene, BUILTIN_SCENES};
use combustion::spectra::{BuiltinMetal, MetalColour};
use combustion::vk::{DeviceDesc, DeviceSelector};
use combustion::{finite_number, number_list, output, shortened, Error, SceneSource};

use super::CliError;

pub(crate) const ABOUT: &str = "Vulkan deferred renderer with physically based shading";

pub(crate) const LONG_ABOUT: &str = "\
Vulkan deferred renderer with physically based shading: Cook-Torrance with GGX (isotropic
and anisotropic), Oren-Nayar diffuse and the full Fresnel equations with complex IOR and
the outside medium's index, checked against an f64 optics reference.

SCENE is builtin:NAME (the list is below; default builtin:spheres) or a glTF file (.gltf
or .glb; a file is lit by its own lights and the built-in studio environment).

`combustion COMMAND --help` explains each command's options.
Logging: COMBUSTION_LOG=error|warn|info|debug|trace (default warn).";

pub(crate) const BENCH_ABOUT: &str = "\
Submits N frames with frames in flight (default 2; 1 to 3): each waits only for the frame
that used its slot. Prints the GPU time of each pass (timestamps: median, p10, p90), the
wall-clock interval between submissions, and the throughput. The lighting pipeline is
specialised to what the scene's materials use; --specialised off measures the general
pipeline instead.

--report DIR measures variant sets on every built-in scene and the authored textured
glTF scene lit by the studio environment (or the scene named alone): the
default (full Fresnel, f32 HDR, specialised pipeline, height-correlated masking, GGX, each
material's diffuse model), each term changed alone (general pipeline; Schlick or F82;
f16; separable or approximate masking; Beckmann; Lambert, qualitative or full Oren-Nayar
for every material) and every cheap choice at once; per set the GPU time of each pass and
the error of one frame against the f64 reference (relative errors and mean FLIP), per
scene the measurement floors (trivial G-buffer fragment stage; lighting that only
fetches; plain GGX + Smith + conductor Fresnel), and frame time against size (0.5x, 1x,
1.5x) and against 1-256 localised lights culled and not (on grid-7x7, or the scene
named), and per scene each anti-aliasing method (none, FXAA, 2x2 and 3x3 supersampling)
against the frame supersampled 4x4 (mean FLIP) at its cost, and per scene lit by an
environment the split sum and the sampled environment at 1-256 samples a pixel and 16
frames of 64 averaged, against a finer f64 oracle, at their cost; written to DIR as
report.md, report.csv, floors.csv, scaling.csv, anti-aliasing.csv,
environment-sampling.csv, speed-vs-error.png (with the Pareto front),
scaling-resolution.png and scaling-lights.png.";

pub(crate) const VIEW_ABOUT: &str = "\
Opens a window (Wayland with WAYLAND_DISPLAY, else X11 with DISPLAY, e.g. under Xvfb)
and renders the scene every frame at the window's size, into the swapchain image on the
device, with frames in flight (default 2). The title and the statistics panel show the
GPU time; H lists the keys, X (or --error-view from the start) shows the error against
the f64 reference. Escape or closing the window quits, as does --frames N after N frames;
a summary is printed at exit.";

pub(crate) const PLOT_ABOUT: &str = "\
Draws PNG charts with the optics reference (no GPU): `reflectance` Rs, Rp and R against
the angle of incidence per RGB channel (rendering notes Figs. 10-11), `spectrum` a
table's n(λ), k(λ) with the RGB bands (Figs. 8-9), `dielectrics` R against angle for
several ηt (Fig. 12).";

pub(crate) const INFO_ABOUT: &str = "\
Prints what a scene holds (meshes, materials, lights, camera, outside medium) and which
renderer features it needs; for a glTF file also what the importer found. With
--max-error E it measures the report's variant sets on the scene at 640x360 (or
--width x --height) and says which is the fastest within E, as render --max-error E
chooses (measured there at the render's size).";

/// `--help`'s closing lines: the built-in scenes, in the order the viewer's number keys
/// follow.
pub(crate) fn builtin_scenes_note() -> String {
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
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Subcommand)]
pub(crate) enum Command {
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
    /// Compare two images (PNG with PNG, OpenEXR with OpenEXR): channel differences,
    /// FLIP, and pass/fail criteria (exit 1 when they fail)
    #[command(long_about = DIFF_ABOUT)]
    Diff(DiffArgs),
    /// Render a manifest's jobs in one process, compare them with goldens, and write
    /// results as JSON and JUnit XML (exit 1 unless every job passes)
    #[command(long_about = BATCH_ABOUT)]
    Batch(BatchArgs),
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

const DIFF_ABOUT: &str = "Compare two images as a CI compares a render with its golden: PNG with PNG (8-bit display values: each pixel's largest channel difference in 8-bit steps) or OpenEXR with OpenEXR (linear radiance: the largest channel difference relative to the larger value, at least 1e-4), and FLIP (Andersson et al. 2020, 67 pixels per degree; of the display images the render writes, for OpenEXR). With --criteria, exits 1 with one line naming the criterion that fails and by how much; 0 when they hold. Criteria are terms joined by `and` and `or` (`and` binds tighter): `max-channel-diff N/255 on at most P% of pixels` (PNG), `max-relative-diff X on at most P% of pixels` (OpenEXR), `mean-flip <= X`, `max-flip <= X`.";

const BATCH_ABOUT: &str = "Render every job of a manifest (JSON: docs/ci-rendering.md, schema docs/batch-manifest.schema.json) in one process on one device, each scene uploaded once for all its jobs. A job is a name, a scene, and any of `combustion render`'s options by their long names (\"width\": 320, \"camera\": \"orbit:30,20\", \"shadows\": true), with its outputs (png, exr), criteria against its golden (`diff`'s expressions; by default the same bytes) and optionally \"error\": true, its end-to-end error against the f64 reference. Writes DIR/NAME.png and DIR/NAME.exr, a FLIP heat map DIR/NAME.flip.png for a failed comparison, DIR/results.json and DIR/junit.xml, and nothing outside DIR (but the goldens, with --update-goldens). A failed job does not stop the others; the exit status is 1 unless all passed. --shard I/N renders the I-th of N shares (the jobs sorted by name, dealt in turn) for a CI matrix; --merge DIR... combines the shards' results.";

/// What `batch` runs, or merges.
#[derive(Args)]
pub(crate) struct BatchArgs {
    /// The manifest: a JSON file of jobs (paths in it are relative to its folder)
    #[arg(value_name = "MANIFEST", required_unless_present = "merge")]
    pub(crate) manifest: Option<PathBuf>,
    /// The folder outputs, results.json and junit.xml are written to (made if missing)
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub(crate) output: PathBuf,
    /// Compare each output with DIR/NAME.png (or .exr) by the job's criteria
    #[arg(long, value_name = "DIR")]
    pub(crate) goldens: Option<PathBuf>,
    /// Write each output as its golden in --goldens instead of comparing (the folder is
    /// made if missing)
    #[arg(long, requires = "goldens")]
    pub(crate) update_goldens: bool,
    /// Render only the I-th of N shares of the jobs (1 <= I <= N): the jobs sorted by
    /// name, dealt out in turn
    #[arg(long, value_name = "I/N", value_parser = super::manifest::Shard::parse)]
    pub(crate) shard: Option<super::manifest::Shard>,
    /// Combine the results of shards (their -o folders) into -o's results.json and
    /// junit.xml instead of rendering; every shard of the split must be given
    #[arg(long, value_name = "DIR", num_args = 1.., conflicts_with_all = ["manifest", "goldens", "update_goldens", "shard"])]
    pub(crate) merge: Vec<PathBuf>,
    #[command(flatten)]
    pub(crate) device: DeviceArgs,
}

/// What `diff` compares and how.
#[derive(Args)]
pub(crate) struct DiffArgs {
    /// The first image (a render, say): .png or .exr
    #[arg(value_name = "A")]
    pub(crate) a: PathBuf,
    /// The second image (its golden, say), of the same kind and size
    #[arg(value_name = "B")]
    pub(crate) b: PathBuf,
    /// Pass/fail criteria, e.g. "max-channel-diff 5/255 on at most 0.1% of pixels and
    /// mean-flip <= 0.01"
    #[arg(long, value_name = "CRITERIA", value_parser = criteria)]
    pub(crate) criteria: Option<combustion::diff::Criteria>,
    /// The criteria read from a file: the same expression, over as many lines as it
    /// takes (line breaks read as spaces; `#` starts a comment to the line's end)
    #[arg(long, value_name = "FILE", conflicts_with = "criteria")]
    pub(crate) criteria_file: Option<PathBuf>,
    /// Write the per-pixel FLIP as a heat map (magma: black 0 to light yellow 1) to
    /// this PNG, with a legend below it (the colour bar and its ends' labels; the PNG
    /// is 62 rows taller than the images)
    #[arg(long, value_name = "OUT.png")]
    pub(crate) heatmap: Option<PathBuf>,
    /// Print the figures (and the verdict) as JSON
    #[arg(long)]
    pub(crate) json: bool,
}

fn criteria(text: &str) -> Result<combustion::diff::Criteria, String> {
    combustion::diff::Criteria::parse(text)
}

/// The scene: positional, or as `--scene`.
#[derive(Args)]
pub(crate) struct SceneArg {
    /// builtin:NAME or a glTF file (.gltf, .glb) [default: builtin:spheres]
    #[arg(value_name = "SCENE", value_parser = scene_source())]
    pub(crate) scene: Option<SceneSource>,
    /// The same as SCENE
    #[arg(
        long = "scene",
        value_name = "SCENE",
        value_parser = scene_source(),
        conflicts_with = "scene"
    )]
    pub(crate) scene_option: Option<SceneSource>,
}

impl SceneArg {
    /// The scene named, if one was.
    pub(crate) fn given(&self) -> Option<&SceneSource> {
        self.scene.as_ref().or(self.scene_option.as_ref())
    }
    pub(crate) fn source(&self) -> SceneSource {
        self.given()
            .cloned()
            .unwrap_or_else(|| SceneSource::Builtin("spheres".to_owned()))
    }
}

/// What every frame is rendered with: size, exposure, Fresnel term, HDR target format.
#[derive(Args)]
pub(crate) struct FrameArgs {
    /// Image width in pixels (1 to 65536; the device's own limit applies too)
    #[arg(long, value_name = "N", default_value = "1280", value_parser = image_side)]
    pub(crate) width: u32,
    /// Image height in pixels (1 to 65536; the device's own limit applies too)
    #[arg(long, value_name = "N", default_value = "720", value_parser = image_side)]
    pub(crate) height: u32,
    /// Exposure: the factor applied to radiance before tone mapping (1 by default)
    #[arg(long, value_name = "X", value_parser = positive_finite::<f32>)]
    pub(crate) exposure: Option<f32>,
    /// Exposure in stops instead: the factor 2^EV (-64 to 64)
    #[arg(long, value_name = "EV", allow_hyphen_values = true, conflicts_with = "exposure", value_parser = exposure_value)]
    pub(crate) ev: Option<f32>,
    /// Exposure of a physical camera instead, with --shutter and --iso: the aperture's
    /// f-number N (0.5 to 128); the factor is 1 / (1.2 · 2^EV100), EV100 = log2(N²/t) -
    /// log2(S/100), luminance in cd/m² (docs/camera.md)
    #[arg(long, value_name = "N", requires_all = ["shutter", "iso"], conflicts_with_all = ["exposure", "ev"], value_parser = f_number)]
    pub(crate) aperture: Option<f32>,
    /// The physical camera's shutter time in seconds (1e-6 to 3600), with --aperture
    #[arg(long, value_name = "SECONDS", requires_all = ["aperture", "iso"], value_parser = shutter_time)]
    pub(crate) shutter: Option<f32>,
    /// The physical camera's sensitivity, ISO (1 to 1e6), with --aperture
    #[arg(long, value_name = "S", requires_all = ["aperture", "shutter"], value_parser = iso)]
    pub(crate) iso: Option<f32>,
    /// Exposure metered from the frame itself: `on` or `off` (the default). A histogram
    /// of the HDR image's log2 luminance; the mean of the pixels between the metering
    /// window's percentiles; a reflected-light meter's EV100 (K = 12.5) less the
    /// compensation. A still frame is exposed by its own radiance (docs/camera.md)
    #[arg(long, value_name = "on|off", value_parser = on_off())]
    pub(crate) auto_exposure: Option<bool>,
    /// With --auto-exposure on: stops added to the metered exposure (-16 to 16; 0 by
    /// default)
    #[arg(long, value_name = "EV", allow_hyphen_values = true, value_parser = compensation)]
    pub(crate) exposure_compensation: Option<f32>,
    /// With --auto-exposure on: the percentiles of the counted pixels, darkest first,
    /// whose mean log luminance is metered, LOW,HIGH (0 <= LOW < HIGH <= 100; 10,90 by
    /// default)
    #[arg(long, value_name = "LOW,HIGH", value_parser = metering_window)]
    pub(crate) metering_window: Option<[f32; 2]>,
    /// With bloom (`--bloom on`; the window's default): the fraction of the frame's
    /// radiance spread into the glow, 0 to 1 (0.05 by default); the total is kept
    #[arg(long, value_name = "X", value_parser = bloom_intensity)]
    pub(crate) bloom_intensity: Option<f32>,
    /// The Fresnel term: the full equations, or a comparison variant
    #[arg(long, value_name = "MODEL", default_value = FresnelModel::default().name(), value_parser = named([FresnelModel::Full, FresnelModel::Schlick, FresnelModel::F82].map(|m| (m.name(), m))))]
    pub(crate) fresnel: FresnelModel,
    /// The HDR target's format: 16- or 32-bit float per channel
    #[arg(long, value_name = "FORMAT", default_value = "f32", value_parser = named(HDR_FORMATS))]
    pub(crate) hdr_format: HdrFormat,
    /// The G-buffer's base colour and metalness: 8- or 16-bit unorm through the sRGB
    /// curve, or linear f16 (docs/gbuffer.md measures each)
    #[arg(long, value_name = "STORAGE", default_value = BaseColorStorage::default().name(), value_parser = named(BaseColorStorage::ALL.map(|s| (s.name(), s))))]
    pub(crate) gbuffer_base_color: BaseColorStorage,
    /// The G-buffer's normal, roughness and anisotropy strength: 16- or 8-bit unorm
    #[arg(long, value_name = "STORAGE", default_value = SurfaceStorage::default().name(), value_parser = named(SurfaceStorage::ALL.map(|s| (s.name(), s))))]
    pub(crate) gbuffer_surface: SurfaceStorage,
}

/// How a shown frame looks beyond its radiance (`render`, `view`): the background and the
/// tone curve.
#[derive(Args)]
pub(crate) struct PictureArgs {
    /// What shows where no surface is: `environment` (the environment lighting the
    /// scene), `none` (black) or `R,G,B` (a radiance, W/sr/m² per channel); by default
    /// the environment where one lights the scene, else none
    #[arg(long, value_name = "BACKGROUND", allow_hyphen_values = true, value_parser = parse_background)]
    pub(crate) background: Option<Background>,
    /// The tone curve of the PNG and the window: `exponential` (1 - e^-x), `pbr-neutral`
    /// (Khronos PBR Neutral, as glTF viewers show), `aces` (Narkowicz's ACES fit) or
    /// `agx` (AgX, Wrensch's minimal form); by
    /// default pbr-neutral for glTF files, exponential for built-in scenes (the EXR is
    /// radiance either way)
    #[arg(long, value_name = "CURVE", value_parser = named(ToneMapping::ALL.map(|t| (t.name(), t))))]
    pub(crate) tone_mapping: Option<ToneMapping>,
    /// Edge smoothing of the PNG and the window: `fxaa` (FXAA on the display values, by
    /// the output pass; the default) or `none`; a still render with `--supersample N`
    /// (exact) gets none. The EXR's radiance is never smoothed
    #[arg(long, value_name = "METHOD", value_parser = named(AntiAliasing::ALL.map(|a| (a.name(), a))))]
    pub(crate) anti_aliasing: Option<AntiAliasing>,
}

impl PictureArgs {
    /// The anti-aliasing asked for, else FXAA, or none for a frame supersampled
    /// `supersample` × `supersample` times (> 1).
    pub(crate) fn anti_aliasing_for(&self, supersample: u32) -> AntiAliasing {
        self.anti_aliasing.unwrap_or(if supersample > 1 {
            AntiAliasing::None
        } else {
            AntiAliasing::Fxaa
        })
    }

    /// The method given with `--anti-aliasing` that smooths (not `none`), if any: what
    /// `--supersample` cannot be combined with.
    pub(crate) fn smoothing_asked(&self) -> Option<AntiAliasing> {
        self.anti_aliasing.filter(|a| *a != AntiAliasing::None)
    }

    /// The background asked for, else the environment where `scene` has one, else none.
    pub(crate) fn background_for(&self, scene: &Scene) -> Background {
        Background::asked_or_default(self.background, scene)
    }

    /// The tone curve asked for, else [`default_tone_mapping`] of `source`.
    pub(crate) fn tone_mapping_for(&self, source: &SceneSource) -> ToneMapping {
        self.tone_mapping
            .unwrap_or_else(|| combustion::default_tone_mapping(source))
    }
}

/// A finite number within `range`, else a message with the range.
fn number_within(text: &str, [low, high]: [f32; 2], unit: &str) -> Result<f32, String> {
    let value = finite::<f32>(text.trim())?;
    if (low..=high).contains(&value) {
        return Ok(value);
    }
    Err(format!(
        "is not between {} and {}{unit}",
        readable(low),
        readable(high)
    ))
}

/// `--aperture`: an f-number the physical camera takes.
fn f_number(text: &str) -> Result<f32, String> {
    number_within(text, PhysicalCamera::F_NUMBERS, "")
}

/// `--shutter`: seconds the physical camera takes.
fn shutter_time(text: &str) -> Result<f32, String> {
    number_within(text, PhysicalCamera::SHUTTER_SECONDS, " seconds")
}

/// `--iso`: a sensitivity the physical camera takes.
fn iso(text: &str) -> Result<f32, String> {
    number_within(text, PhysicalCamera::ISOS, "")
}

/// `--bloom-intensity`: a fraction from 0 to 1.
fn bloom_intensity(text: &str) -> Result<f32, String> {
    number_within(text, [0.0, 1.0], "")
}

/// `--exposure-compensation`: stops within the auto exposure's range.
fn compensation(text: &str) -> Result<f32, String> {
    number_within(text, AutoExposure::COMPENSATION, " stops")
}

/// `--metering-window`: LOW,HIGH percentiles, 0 <= LOW < HIGH <= 100, as fractions.
fn metering_window(text: &str) -> Result<[f32; 2], String> {
    let parts: Vec<&str> = text.split(',').collect();
    let [low, high] = parts[..] else {
        return Err("takes two percentiles, LOW,HIGH (e.g. 10,90)".to_owned());
    };
    let low = number_within(low, [0.0, 100.0], " percent")?;
    let high = number_within(high, [0.0, 100.0], " percent")?;
    if low >= high {
        return Err(format!(
            "has its low percentile {} at or above its high one {}",
            readable(low),
            readable(high)
        ));
    }
    Ok([low / 100.0, high / 100.0])
}

/// `--adaptation-speed`: RISE,FALL in EV per second, each within the auto exposure's
/// range.
pub(crate) fn adaptation_speed(text: &str) -> Result<[f32; 2], String> {
    let parts: Vec<&str> = text.split(',').collect();
    let [rise, fall] = parts[..] else {
        return Err("takes two speeds in EV per second, RISE,FALL (e.g. 1,3)".to_owned());
    };
    Ok([
        number_within(rise, AutoExposure::SPEEDS, " EV per second")?,
        number_within(fall, AutoExposure::SPEEDS, " EV per second")?,
    ])
}

impl FrameArgs {
    /// The bloom intensity asked for (else the default), refused where the frame has no
    /// bloom (`bloom`: whether it has).
    pub(crate) fn bloom_intensity(&self, bloom: bool) -> Result<f32, Error> {
        match self.bloom_intensity {
            Some(_) if !bloom => Err(Error::Usage(
                "--bloom-intensity needs bloom (--bloom on; the window's default): there is no glow to set".into(),
            )),
            Some(intensity) => Ok(intensity),
            None => Ok(combustion::renderer::DEFAULT_BLOOM_INTENSITY),
        }
    }

    /// The exposure factor asked for by hand: `--ev`'s 2^EV, the physical camera's, or
    /// `--exposure` (1 by default).
    pub(crate) fn exposure_factor(&self) -> f32 {
        match (self.ev, self.aperture.zip(self.shutter).zip(self.iso)) {
            (Some(ev), _) => ev.exp2(),
            (None, Some(((f_number, shutter_seconds), iso))) => PhysicalCamera {
                f_number,
                shutter_seconds,
                iso,
            }
            .exposure(),
            (None, None) => self.exposure.unwrap_or(1.0),
        }
    }

    /// The auto exposure asked for (`--auto-exposure on`), refused beside an exposure
    /// set by hand, and its settings refused without it.
    pub(crate) fn auto_exposure(&self) -> Result<Option<AutoExposure>, Error> {
        let on = self.auto_exposure == Some(true);
        let by_hand = [
            (self.exposure.is_some(), "--exposure"),
            (self.ev.is_some(), "--ev"),
            (self.aperture.is_some(), "--aperture"),
        ];
        if let Some((_, hand)) = by_hand.iter().find(|(given, _)| *given).filter(|_| on) {
            return Err(Error::Usage(format!(
                "--auto-exposure on meters the exposure and {hand} sets it by hand: give one (--exposure-compensation shifts the metered one)"
            )));
        }
        let settings = [
            (
                self.exposure_compensation.is_some(),
                "--exposure-compensation",
            ),
            (self.metering_window.is_some(), "--metering-window"),
        ];
        if let Some((_, setting)) = settings.iter().find(|(given, _)| *given).filter(|_| !on) {
            return Err(Error::Usage(format!(
                "{setting} needs --auto-exposure on (it sets how the exposure is metered)"
            )));
        }
        let defaults = AutoExposure::default();
        Ok(on.then(|| AutoExposure {
            compensation: self.exposure_compensation.unwrap_or(defaults.compensation),
            window: self.metering_window.unwrap_or(defaults.window),
            ..defaults
        }))
    }
}

/// `--ev`: a finite number of stops within ±64 (2^±64 stays a normal f32 factor).
fn exposure_value(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(ev) if (-64.0..=64.0).contains(&ev) => Ok(ev),
        Ok(_) => Err(format!(
            "`{}` is not between -64 and 64 stops",
            shortened(text)
        )),
        Err(_) => Err(format!("`{}` is not a number", shortened(text))),
    }
}

/// `--background`: `environment`, `none` or `R,G,B` (each a radiance between 0 and the
/// scene's bound).
fn parse_background(text: &str) -> Result<Background, String> {
    match text {
        "environment" => return Ok(Background::Environment),
        "none" => return Ok(Background::None),
        _ => {}
    }
    let parts: Vec<&str> = text.split(',').collect();
    let [r, g, b] = parts[..] else {
        return Err("is not environment, none or R,G,B".to_owned());
    };
    Ok(Background::Color([
        radiance_channel(r)?,
        radiance_channel(g)?,
        radiance_channel(b)?,
    ]))
}

/// One channel of a radiance given on the command line: between 0 and the scene's
/// bound (an f32 the shading's products keep finite).
fn radiance_channel(part: &str) -> Result<f32, String> {
    match part.trim().parse::<f32>() {
        Ok(x) if (0.0..=combustion::scene::MAX_RADIANCE).contains(&x) => Ok(x),
        Ok(_) => Err(format!(
            "`{}` must be between 0 and {:e} (a radiance, W·sr⁻¹·m⁻²)",
            shortened(part),
            combustion::scene::MAX_RADIANCE
        )),
        Err(_) => Err(format!("`{}` is not a number", shortened(part))),
    }
}

pub(crate) const HDR_FORMATS: [(&str, HdrFormat); 2] = [
    ("f16", HdrFormat::Rgba16Float),
    ("f32", HdrFormat::Rgba32Float),
];

/// How the scene is shaded and lit (`render`, `bench`).
#[derive(Args)]
pub(crate) struct ShadingArgs {
    /// The microfacet distribution (beckmann: a comparison variant)
    #[arg(long, value_name = "KIND", default_value = "ggx", value_parser = named([Distribution::Ggx, Distribution::Beckmann].map(|d| (d.name(), d))))]
    pub(crate) distribution: Distribution,
    /// One diffuse model for every material (material: each its own)
    #[arg(long, value_name = "MODEL", default_value = "material", value_parser = diffuse_override())]
    // Spelled out so that clap takes the value as parsed (`material` is `None`) rather than
    // as an optional argument.
    pub(crate) diffuse: std::option::Option<DiffuseModel>,
    /// Light the scene by `studio` (an analytic sky, ground and two soft boxes),
    /// `uniform:R,G,B` or `uniform:L` (a uniform radiance, W/sr/m² per channel), an
    /// equirectangular Radiance .hdr or OpenEXR .exr image FILE (row 0 at +y, the centre
    /// column along -z), or `none`
    #[arg(long, value_name = "ENVIRONMENT", value_parser = OsStringValueParser::new().try_map(EnvironmentChoice::parse))]
    pub(crate) environment: Option<EnvironmentChoice>,
    /// Add the camera-relative key and fill lights (the earlier default for files without
    /// lights)
    #[arg(long)]
    pub(crate) light_rig: bool,
    /// A glTF file's own lights (KHR_lights_punctual), which light it with the studio
    /// environment by default: `off` leaves them out (`--environment none` leaves the
    /// environment out)
    #[arg(long, value_name = "on|off", default_value = "on", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) scene_lights: bool,
    /// How metals given by a measured spectrum (built-in scenes' metals, and glTF
    /// conductors naming a `metal` or `spectrum` without their own `colour`) get their
    /// RGB η, k: `bands` (the rendering notes' band means) or `colorimetric` (fitted to
    /// the colour the spectrum shows under D65, CIE 1931 observer: docs/metal-colours.md)
    #[arg(long, value_name = "METHOD", default_value = "bands", value_parser = named(MetalColour::ALL.map(|c| (c.name(), c))))]
    pub(crate) metal_colour: MetalColour,
    /// Environment lighting integrated by sampling, N samples per pixel of each of two
    /// strategies (GGX visible normals, cosine; balance heuristic): converges to the
    /// rendering equation, noisy at small N (0: the split sum, noiseless and approximate;
    /// N a power of two up to 1024)
    #[arg(long, value_name = "N", default_value = "0", value_parser = environment_samples)]
    pub(crate) environment_samples: u32,
    /// With --path-trace on: the most surfaces a path lights (1: direct light alone;
    /// Russian roulette ends most paths sooner), 1 to 64
    #[arg(long, value_name = "N", default_value = "16", value_parser = path_depth)]
    pub(crate) path_depth: u32,
    /// Scale every specular lobe by 1 + F0 (1 - E)/E (Turquin 2019), putting back the
    /// energy single-scattering GGX loses on rough surfaces (off by default: the f64
    /// reference is single-scattering)
    #[arg(long, value_name = "on|off", default_value = "off", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) energy_compensation: bool,
    /// Shadows of every light that casts them (cascaded maps for directional lights, a
    /// map per spot light, a cube per point light)
    #[arg(long, value_name = "on|off", default_value = "off", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) shadows: bool,
    /// With --shadows on: cascades per directional light (1 to 4)
    #[arg(long, value_name = "N", default_value_t = ShadowSettings::DEFAULT.cascades, value_parser = cascades)]
    pub(crate) shadow_cascades: u32,
    /// With --shadows on: each cascade's map side in texels (64 to the device's limit)
    #[arg(long, value_name = "N", default_value_t = ShadowSettings::DEFAULT.map_size, value_parser = shadow_map_side)]
    pub(crate) shadow_map_size: u32,
    /// With --shadows on: each spot light's map side, and each of a point light's six
    /// (64 to the device's limit)
    #[arg(long, value_name = "N", default_value_t = ShadowSettings::DEFAULT.local_map_size, value_parser = shadow_map_side)]
    pub(crate) shadow_local_map_size: u32,
    /// With --shadows on: how shadow lookups are filtered
    #[arg(long, value_name = "FILTER", default_value = ShadowSettings::DEFAULT.filter.name(), value_parser = named(ShadowFilter::ALL.map(|f| (f.name(), f))))]
    pub(crate) shadow_filter: ShadowFilter,
    #[command(flatten)]
    pub(crate) optional: OptionalPassArgs,
}

/// `--NAME on|off` for each optional pass the renderer declares
/// ([`combustion::renderer::optional_passes`]: its name is the flag, its help the help),
/// and `--CHOICE none|VALUE…` for each choice among passes (a pass with a
/// [`combustion::renderer::PassChoice`] is its value there), all off by default; the
/// flags form the group `optional_passes`.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct OptionalPassArgs {
    /// The passes switched on.
    pub(crate) passes: OptionalPasses,
}

impl OptionalPassArgs {
    /// The group of every optional pass's flag (what `bench --report` conflicts with).
    pub(crate) const GROUP: &'static str = "optional_passes";
}

impl clap::FromArgMatches for OptionalPassArgs {
    fn from_arg_matches(matches: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut args = Self::default();
        args.update_from_arg_matches(matches)?;
        Ok(args)
    }

    fn update_from_arg_matches(&mut self, matches: &clap::ArgMatches) -> Result<(), clap::Error> {
        for pass in combustion::renderer::optional_passes() {
            let on = match pass.choice {
                None => matches.get_one::<bool>(pass.name).copied(),
                Some((choice, value)) => matches
                    .get_one::<String>(choice.name)
                    .map(|chosen| chosen == value),
            };
            if let Some(on) = on {
                self.passes = self.passes.with(pass, on);
            }
        }
        Ok(())
    }
}

/// The value of a [`combustion::renderer::PassChoice`] that runs none of its passes.
pub(crate) const CHOICE_NONE: &str = "none";

/// The choices among optional passes, each once, in the passes' order, with its ways
/// (value, help).
fn pass_choices() -> Vec<(
    &'static combustion::renderer::PassChoice,
    Vec<(&'static str, &'static str)>,
)> {
    let mut choices: Vec<(&combustion::renderer::PassChoice, Vec<_>)> = Vec::new();
    for pass in combustion::renderer::optional_passes() {
        if let Some((choice, value)) = pass.choice {
            match choices.iter_mut().find(|(c, _)| std::ptr::eq(*c, choice)) {
                Some((_, ways)) => ways.push((value, pass.help)),
                None => choices.push((choice, vec![(value, pass.help)])),
            }
        }
    }
    choices
}

impl Args for OptionalPassArgs {
    fn augment_args(mut command: clap::Command) -> clap::Command {
        let mut names = Vec::new();
        for (choice, ways) in pass_choices() {
            let values: Vec<&'static str> = std::iter::once(CHOICE_NONE)
                .chain(ways.iter().map(|(value, _)| *value))
                .collect();
            let described: Vec<String> = ways
                .iter()
                .map(|(value, help)| format!("{value} ({help})"))
                .collect();
            command = command.arg(
                clap::Arg::new(choice.name)
                    .long(choice.name)
                    .value_name("WAY")
                    .default_value(CHOICE_NONE)
                    .action(ArgAction::Set)
                    .value_parser(clap::builder::PossibleValuesParser::new(values))
                    .help(format!(
                        "{}: {CHOICE_NONE} (the default), {}",
                        choice.help,
                        described.join(", ")
                    )),
            );
            names.push(choice.name);
        }
        for pass in combustion::renderer::optional_passes().filter(|p| p.choice.is_none()) {
            command = command.arg(
                clap::Arg::new(pass.name)
                    .long(pass.name)
                    .value_name("on|off")
                    .default_value("off")
                    .action(ArgAction::Set)
                    .value_parser(on_off())
                    .help(pass.help),
            );
            names.push(pass.name);
        }
        command.group(ArgGroup::new(Self::GROUP).multiple(true).args(names))
    }

    fn augment_args_for_update(command: clap::Command) -> clap::Command {
        Self::augment_args(command)
    }
}

impl ShadingArgs {
    /// `base` with the distribution, diffuse model, energy compensation and shadows
    /// asked for.
    pub(crate) fn options(&self, base: ShadingOptions) -> ShadingOptions {
        ShadingOptions {
            distribution: self.distribution,
            diffuse_override: self.diffuse,
            energy_compensation: self.energy_compensation,
            shadows: self.shadows(),
            environment_samples: self.environment_samples,
            optional_passes: self.optional.passes,
            path_depth: self.path_depth,
            ..base
        }
    }

    /// `--light-rig`'s lights for a frame seen from `camera` (none without it).
    pub(crate) fn light_rig(
        &self,
        camera: &combustion::scene::Camera,
    ) -> Vec<combustion::scene::Light> {
        if self.light_rig {
            combustion::default_light_rig(camera)
        } else {
            Vec::new()
        }
    }

    /// The shadow settings asked for (`None`: --shadows off).
    pub(crate) fn shadows(&self) -> Option<ShadowSettings> {
        self.shadows.then_some(ShadowSettings {
            cascades: self.shadow_cascades,
            map_size: self.shadow_map_size,
            local_map_size: self.shadow_local_map_size,
            filter: self.shadow_filter,
        })
    }
}

/// `--environment-samples`: one of the counts the renderer takes.
fn environment_samples(text: &str) -> Result<u32, String> {
    let value = whole_number::<u32>(text)?;
    if !combustion::renderer::ENVIRONMENT_SAMPLE_COUNTS.contains(&value) {
        return Err(format!(
            "is {value}; use 0 (the split sum) or a power of two from 1 to 1024"
        ));
    }
    Ok(value)
}

/// `--path-depth`: a depth the renderer takes.
fn path_depth(text: &str) -> Result<u32, String> {
    let value = whole_number::<u32>(text)?;
    let depths = combustion::renderer::PATH_DEPTHS;
    if !depths.contains(&value) {
        return Err(format!(
            "is {value}; use {} to {}",
            depths.start(),
            depths.end()
        ));
    }
    Ok(value)
}

/// The most paths a pixel `--samples` averages (its message says 65,536).
pub(crate) const MAX_PATH_SAMPLES: u32 = 65_536;

/// `--samples`: a whole number of frames' paths a pixel.
fn path_samples(text: &str) -> Result<u32, String> {
    let value = whole_number::<u32>(text)?;
    let per_frame = combustion::renderer::PATHS_PER_FRAME;
    if !(per_frame..=MAX_PATH_SAMPLES).contains(&value) || value % per_frame != 0 {
        return Err(format!(
            "is {value}; use a multiple of {per_frame} (the paths of one frame) from {per_frame} to 65,536"
        ));
    }
    Ok(value)
}

fn cascades(text: &str) -> Result<u32, String> {
    let value = whole_number::<u32>(text)?;
    if !(1..=MAX_CASCADES).contains(&value) {
        return Err(format!("is {value}; use 1 to {MAX_CASCADES}"));
    }
    Ok(value)
}

/// The Vulkan device and validation.
#[derive(Args)]
pub(crate) struct DeviceArgs {
    /// Pick a Vulkan device by index or by part of its name (e.g. llvmpipe); the
    /// COMBUSTION_DEVICE environment variable does the same
    #[arg(long, value_name = "SEL", value_parser = |text: &str| text.parse::<DeviceSelector>())]
    pub(crate) device: Option<DeviceSelector>,
    /// Turn on the Khronos validation layer and fail if it reports anything
    #[arg(long)]
    pub(crate) validate: bool,
}

#[derive(Args)]
pub(crate) struct RenderArgs {
    #[command(flatten)]
    pub(crate) scene: SceneArg,
    /// The tone-mapped image (PNG) [default: out.png when --hdr is not given]
    #[arg(short = 'o', long = "output", value_name = "OUT.png")]
    pub(crate) output: Option<PathBuf>,
    /// The linear radiance (OpenEXR, ZIP-compressed)
    #[arg(long, value_name = "OUT.exr")]
    pub(crate) hdr: Option<PathBuf>,
    /// With --environment-samples N, --environment-occlusion ray-traced or --path-trace on: render frames of
    /// successive sample sets and write their mean, until its relative standard error
    /// (the frames' spread, averaged over the lit pixels) is at most E (4 to 1024 frames)
    #[arg(long, value_name = "E", value_parser = relative_error)]
    pub(crate) accumulate_until: Option<f64>,
    /// With --path-trace on: N paths a pixel, the mean of N/4 frames of successive seeds
    /// (a multiple of 4, 4 to 65,536); the same image for the same N
    #[arg(long, value_name = "N", value_parser = path_samples, conflicts_with_all = ["accumulate_until", "supersample"])]
    pub(crate) samples: Option<u32>,
    /// An accuracy budget: render with the fastest variant set whose mean relative error
    /// against the f64 reference is within E, measured on this scene at this size (the
    /// set chooses the Fresnel term, distribution, diffuse model and HDR format: those
    /// options are not taken beside it)
    #[arg(long, value_name = "E", value_parser = relative_error, conflicts_with_all = ["fresnel", "distribution", "diffuse", "hdr_format"])]
    pub(crate) max_error: Option<f64>,
    /// N×N samples a pixel, averaged as radiance (a box filter over the pixel: the frame
    /// rendered N times as wide and high, then resolved), 1 to 4; the exact anti-aliasing
    /// of a still image (replaces --anti-aliasing)
    #[arg(long, value_name = "N", default_value = "1", value_parser = supersample_factor)]
    pub(crate) supersample: u32,
    #[command(flatten)]
    pub(crate) frame: FrameArgs,
    #[command(flatten)]
    pub(crate) camera: CameraArgs,
    #[command(flatten)]
    pub(crate) picture: PictureArgs,
    #[command(flatten)]
    pub(crate) animation: AnimationArgs,
    #[command(flatten)]
    pub(crate) shading: ShadingArgs,
    #[command(flatten)]
    pub(crate) device: DeviceArgs,
}

/// Where the frame is seen from: `--camera`.
#[derive(Args)]
pub(crate) struct CameraArgs {
    /// Where the frame is seen from: `scene` (the scene's own camera: a file's first
    /// camera, else one framing it), N (the glTF file's camera N, from 0), `framing` (a
    /// three-quarter view of the scene's bounding sphere in a 45° field of view: 30° from
    /// its +Z side towards +X, 20° above the horizon) or `orbit:AZIMUTH,ELEVATION[,DISTANCE]` (degrees about +Y from the +Z side towards
    /// +X, degrees above the horizon within ±89, and a multiple of the framing distance,
    /// 1 by default)
    #[arg(long, value_name = "VIEW", default_value = "scene", allow_hyphen_values = true, value_parser = CameraChoice::parse)]
    pub(crate) camera: CameraChoice,
}

/// `--camera`, as given ([`CameraChoice::load`] places it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum CameraChoice {
    /// The scene's own camera.
    Scene,
    /// The glTF file's camera of this index.
    File(usize),
    /// [`combustion::scene::Camera::framing`] of the scene's bounds.
    Framing,
    /// [`combustion::scene::Camera::orbiting`]: degrees, degrees, a factor.
    Orbit {
        azimuth: f32,
        elevation: f32,
        distance: f32,
    },
}

impl CameraChoice {
    pub(crate) fn parse(text: &str) -> Result<Self, String> {
        match text {
            "scene" => return Ok(Self::Scene),
            "framing" => return Ok(Self::Framing),
            _ => {}
        }
        if let Some(numbers) = text.strip_prefix("orbit:") {
            let values = number_list(numbers, &[2, 3])?;
            let (azimuth, elevation) = (values[0], values[1]);
            let distance = values.get(2).copied().unwrap_or(1.0);
            if !(-89.0..=89.0).contains(&elevation) {
                return Err(format!("elevation {elevation}° is not within ±89°"));
            }
            if !(1e-3..=1e6).contains(&distance) {
                return Err(format!(
                    "distance {} is not within 1e-3 and 1e6 (a multiple of the framing distance; nearer, the eye meets the target)",
                    combustion::optics::readable::readable(distance)
                ));
            }
            return Ok(Self::Orbit {
                azimuth: azimuth as f32,
                elevation: elevation as f32,
                distance: distance as f32,
            });
        }
        match text.parse::<usize>() {
            Ok(index) => Ok(Self::File(index)),
            Err(_) => Err(format!(
                "`{}` is not scene, framing, orbit:AZIMUTH,ELEVATION[,DISTANCE] or a camera's index",
                shortened(text)
            )),
        }
    }

    /// The import options choosing the file's camera N (an index the file has not is
    /// the importer's one-line error); a built-in scene has its own camera only.
    pub(crate) fn import_options(
        self,
        source: &SceneSource,
    ) -> Result<combustion::scene::gltf::ImportOptions, Error> {
        let Self::File(index) = self else {
            return Ok(Default::default());
        };
        if let SceneSource::Builtin(_) = source {
            return Err(Error::Usage(format!(
                "--camera {index}: {} has one camera (use scene, framing or orbit:…); camera indices name a glTF file's cameras",
                source.label()
            )));
        }
        Ok(combustion::scene::gltf::ImportOptions {
            camera: Some(index),
            ..Default::default()
        })
    }

    /// The camera of a frame of `scene` (loaded with [`CameraChoice::import_options`]):
    /// its own, or framing or orbiting its bounds at rest.
    pub(crate) fn place(self, scene: &Scene) -> combustion::scene::Camera {
        use combustion::scene::Camera;
        match self {
            Self::Scene | Self::File(_) => scene.camera,
            Self::Framing => Camera::framing(scene.framing_bounds()),
            Self::Orbit {
                azimuth,
                elevation,
                distance,
            } => Camera::orbiting(
                scene.world_bounds(),
                azimuth.to_radians(),
                elevation.to_radians(),
                distance,
            ),
        }
    }
}

/// Which of the scene's animations a frame shows, and when.
#[derive(Args)]
pub(crate) struct AnimationArgs {
    /// Show the scene at this time, seconds into its animation (--animation; the first
    /// by default); without it or --animation, the scene at rest
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true, value_parser = finite::<f32>)]
    pub(crate) time: Option<f32>,
    /// The animation to show: its name, or its index from 0 (at --time, else at 0 s)
    #[arg(long, value_name = "NAME|INDEX")]
    pub(crate) animation: Option<String>,
}

impl AnimationArgs {
    /// The pose asked for in `scene`, or `None` for the scene at rest.
    pub(crate) fn pose(
        &self,
        scene: &combustion::scene::Scene,
    ) -> Result<Option<combustion::scene::ObjectPoses>, combustion::Error> {
        combustion::animation::pose_at(scene, self.animation.as_deref(), self.time)
    }
}

#[derive(Args)]
pub(crate) struct BenchArgs {
    #[command(flatten)]
    pub(crate) scene: SceneArg,
    /// Frames to measure
    #[arg(long, value_name = "N", default_value = "30", value_parser = at_least_one)]
    pub(crate) frames: u32,
    /// Frames the CPU may record ahead of the GPU (1 to 3)
    #[arg(long, value_name = "N", default_value_t = RendererSettings::default().frames_in_flight, value_parser = frames_in_flight)]
    pub(crate) frames_in_flight: usize,
    /// Light pipelines specialised to the scene's materials (off: the general one)
    #[arg(long, value_name = "on|off", default_value = "on", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) specialised: bool,
    /// The output pass's work done by the lighting pass in frames where nothing reads the
    /// radiance between them (off: the two passes timed apart)
    #[arg(long, value_name = "on|off", default_value = "on", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) fold_output: bool,
    /// Add N point lights with a range (a fifth of the scene's size) scattered through it
    #[arg(long, value_name = "N", default_value = "0", value_parser = extra_lights)]
    pub(crate) extra_lights: usize,
    /// When frames cull their lights into 16×16-pixel tile lists (auto: when a light has
    /// a range; the culling pass is timed with the lighting pass). A frame of more than
    /// 1024 lights is not culled (a warning says so)
    #[arg(long, value_name = "WHEN", default_value = "auto", value_parser = named(LightCulling::ALL.map(|c| (c.name(), c))))]
    pub(crate) culling: LightCulling,
    /// The output pass's anti-aliasing: `none` or `fxaa` (timed with the output pass)
    #[arg(long, value_name = "METHOD", default_value = "none", value_parser = named(AntiAliasing::ALL.map(|a| (a.name(), a))))]
    pub(crate) anti_aliasing: AntiAliasing,
    /// Measure the variant sets and write the speed-against-error report to DIR
    #[arg(long, value_name = "DIR", conflicts_with_all = ["fresnel", "hdr_format", "anti_aliasing", "gbuffer_base_color", "gbuffer_surface", "exposure", "ev", "aperture", "shutter", "iso", "auto_exposure", "exposure_compensation", "metering_window", "bloom_intensity", "frames_in_flight", "specialised", "fold_output", "distribution", "diffuse", "extra_lights", "culling", "environment", "light_rig", "scene_lights", "energy_compensation", "shadows", "shadow_cascades", "shadow_map_size", "shadow_local_map_size", "shadow_filter", OptionalPassArgs::GROUP])]
    pub(crate) report: Option<PathBuf>,
    /// With --report: add how this run reproduces an earlier report (rows with identical
    /// error columns, the spread of the frame-time ratios)
    #[arg(long, value_name = "PREVIOUS_DIR", requires = "report")]
    pub(crate) against: Option<PathBuf>,
    /// With --report: the sections to measure, comma-separated: variants, floors (with
    /// variants), scaling, shadows, storage, anti-aliasing, environment-sampling,
    /// occlusion, light-transport (with --path-traced-frames). Default: every one,
    /// light-transport when --path-traced-frames is given. The files of the sections not
    /// measured are removed from DIR
    #[arg(long, value_name = "LIST", requires = "report", value_delimiter = ',', value_parser = named(ReportSection::ALL.map(|s| (s.name(), s))))]
    pub(crate) report_sections: Vec<ReportSection>,
    /// With --report: measure each scene's real-time frame against light that bounces,
    /// its frame path traced and N frames averaged (devices with ray queries; a traced
    /// frame costs a hundred real-time ones: off unless asked)
    #[arg(long, value_name = "N", requires = "report", value_parser = path_traced_frames)]
    pub(crate) path_traced_frames: Option<u32>,
    #[command(flatten)]
    pub(crate) frame: FrameArgs,
    /// With --time or --animation: the animation plays through the measured frames,
    /// 1/30 s of its time per frame from --time (0 by default), looping
    #[command(flatten)]
    pub(crate) animation: AnimationArgs,
    #[command(flatten)]
    pub(crate) shading: ShadingArgs,
    #[command(flatten)]
    pub(crate) device: DeviceArgs,
}

#[derive(Args)]
pub(crate) struct ViewArgs {
    #[command(flatten)]
    pub(crate) scene: SceneArg,
    /// Quit after N frames (default: run until the window is closed)
    #[arg(long, value_name = "N", value_parser = at_least_one)]
    pub(crate) frames: Option<u32>,
    /// Wait for the display's refresh (off: present at once where the window system
    /// allows it)
    #[arg(long, value_name = "on|off", default_value = "on", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) vsync: bool,
    /// Frames the CPU may record ahead of the GPU (1 to 3)
    #[arg(long, value_name = "N", default_value_t = RendererSettings::default().frames_in_flight, value_parser = frames_in_flight)]
    pub(crate) frames_in_flight: usize,
    /// Write the last frame of the run to this PNG (needs --frames)
    #[arg(long, value_name = "OUT.png", requires = "frames")]
    pub(crate) screenshot: Option<PathBuf>,
    /// A scripted camera path
    #[arg(long, value_name = "FILE")]
    pub(crate) camera_path: Option<PathBuf>,
    /// The statistics panel over the frames (Tab toggles it while running)
    #[arg(long, value_name = "on|off", default_value = "on", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) overlay: bool,
    /// Start in the error view (the error against the f64 reference)
    #[arg(long)]
    pub(crate) error_view: bool,
    /// Temporal anti-aliasing: a jittered camera, each pixel blended with its history
    /// (off by default; the T key toggles it)
    #[arg(long, value_name = "on|off", default_value = "off", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) temporal_anti_aliasing: bool,
    /// Bloom, the glow of bright things (on by default in the window; the Y key toggles
    /// it)
    #[arg(long, value_name = "on|off", default_value = "on", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) bloom: bool,
    /// Path tracing: light that bounces, each frame averaged with those before it while
    /// the view rests (off by default; devices with ray queries; the J key toggles it)
    #[arg(long, value_name = "on|off", default_value = "off", action = ArgAction::Set, value_parser = on_off())]
    pub(crate) path_trace: bool,
    /// Light the scene by `studio`, `uniform:R,G,B` or `uniform:L`, an equirectangular
    /// .hdr or .exr FILE, or `none`, in place of the environment it comes with (a glTF
    /// file's: the studio, beside its own lights); kept when the scene is reloaded
    #[arg(long, value_name = "ENVIRONMENT", value_parser = OsStringValueParser::new().try_map(EnvironmentChoice::parse))]
    pub(crate) environment: Option<EnvironmentChoice>,
    /// With --auto-exposure on: how fast the exposure follows the metered one, RISE,FALL
    /// in EV per second (towards a darker scene, towards a brighter one; 0.01 to 1000
    /// each; 1,3 by default)
    #[arg(long, value_name = "RISE,FALL", value_parser = adaptation_speed)]
    pub(crate) adaptation_speed: Option<[f32; 2]>,
    #[command(flatten)]
    pub(crate) frame: FrameArgs,
    #[command(flatten)]
    pub(crate) picture: PictureArgs,
    #[command(flatten)]
    pub(crate) device: DeviceArgs,
}

#[derive(Args)]
pub(crate) struct InfoArgs {
    /// builtin:NAME or a glTF file (.gltf, .glb)
    #[arg(value_name = "SCENE", value_parser = scene_source())]
    pub(crate) scene: SceneSource,
    /// An accuracy budget (the mean relative error against the f64 reference): measure
    /// the variant sets at --width x --height and say which is the fastest within it
    #[arg(long, value_name = "E", value_parser = relative_error)]
    pub(crate) max_error: Option<f64>,
    /// With --max-error: the width the variant sets are measured at (render --max-error
    /// measures at its own size)
    #[arg(long, value_name = "N", default_value = "640", value_parser = image_side, requires = "max_error")]
    pub(crate) width: u32,
    /// With --max-error: the height the variant sets are measured at
    #[arg(long, value_name = "N", default_value = "360", value_parser = image_side, requires = "max_error")]
    pub(crate) height: u32,
}

/// `eval`'s arguments: the term, and the numeric inputs of
/// [`combustion::eval::FLAGS`], declared from that table (see the `Args` impl).
pub(crate) struct EvalArgs {
    pub(crate) list: bool,
    pub(crate) term: Option<String>,
    pub(crate) inputs: combustion::eval::Inputs,
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
pub(crate) enum PlotCommand {
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
pub(crate) struct PlotImageArgs {
    /// The PNG to write [default: KIND.png, after the plot's kind]
    #[arg(short = 'o', long = "output", value_name = "OUT.png")]
    pub(crate) output: Option<PathBuf>,
    /// Width in pixels [default: 800]
    #[arg(long, value_name = "N", value_parser = whole_number::<u32>)]
    pub(crate) width: Option<u32>,
    /// Height in pixels [default: 500; 600 for `plot spectrum`]
    #[arg(long, value_name = "N", value_parser = whole_number::<u32>)]
    pub(crate) height: Option<u32>,
}

impl PlotImageArgs {
    pub(crate) fn size(&self, default: (u32, u32)) -> (u32, u32) {
        (
            self.width.unwrap_or(default.0),
            self.height.unwrap_or(default.1),
        )
    }

    /// The output path (default `KIND.png`), checked before any work is done.
    pub(crate) fn output(&self, kind: &str) -> Result<PathBuf, CliError> {
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
pub(crate) struct ReflectanceArgs {
    /// A built-in metal (name or chemical symbol)
    #[arg(long, value_name = "NAME", value_parser = builtin_metal)]
    pub(crate) metal: Option<BuiltinMetal>,
    /// A dielectric of index ETA
    #[arg(long, value_name = "ETA", value_parser = finite_number)]
    pub(crate) dielectric: Option<f64>,
    /// A conductor's η, one value or one per RGB channel
    #[arg(long, value_name = "E|R,G,B", value_parser = rgb)]
    pub(crate) eta: Option<[f64; 3]>,
    /// The conductor's k, one value or one per RGB channel [default: 0]
    // clap drops `requires` when a conflicting member of the group is present, so the
    // other materials are refused by name.
    #[arg(long, value_name = "K|R,G,B", value_parser = rgb, requires = "eta", conflicts_with_all = ["metal", "dielectric", "csv"])]
    pub(crate) k: Option<[f64; 3]>,
    /// A `wavelength_nm,n,k` table spanning 450-740 nm
    #[arg(long, value_name = "FILE")]
    pub(crate) csv: Option<PathBuf>,
    /// The outside medium's index ηi (1.33 for water)
    #[arg(long, value_name = "X", default_value = "1", value_parser = finite_number)]
    pub(crate) outside_ior: f64,
    /// The weight w of R = (1-w)Rs + wRp (0.5: unpolarised)
    #[arg(long, value_name = "W", default_value = "0.5", value_parser = finite_number)]
    pub(crate) polarisation: f64,
    #[command(flatten)]
    pub(crate) image: PlotImageArgs,
}

#[derive(Args)]
#[command(group(ArgGroup::new("table").required(true).args(["metal", "csv"])))]
pub(crate) struct SpectrumArgs {
    /// A built-in metal (name or chemical symbol)
    #[arg(long, value_name = "NAME", value_parser = builtin_metal)]
    pub(crate) metal: Option<BuiltinMetal>,
    /// A `wavelength_nm,n,k` table spanning 450-740 nm
    #[arg(long, value_name = "FILE")]
    pub(crate) csv: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) image: PlotImageArgs,
}

#[derive(Args)]
pub(crate) struct DielectricsArgs {
    /// The indices ηt to plot [default: 1.1,1.33,1.5,1.8,2.4,3]
    #[arg(long, value_name = "E,E,...", value_parser = |text: &str| number_list(text, &[]).map(Etas))]
    pub(crate) etas: Option<Etas>,
    /// The outside medium's index ηi
    #[arg(long, value_name = "X", default_value = "1", value_parser = finite_number)]
    pub(crate) outside_ior: f64,
    #[command(flatten)]
    pub(crate) image: PlotImageArgs,
}

/// `--etas`: one value holding a list (an `Option<Vec<_>>` field would be a list of
/// values to clap).
#[derive(Clone)]
pub(crate) struct Etas(pub(crate) Vec<f64>);

// ---- Value parsers: each says why a value is refused; clap shows the value and the flag.

/// A whole number of type `T`; the error says why not (negative, written with a point,
/// out of range) rather than only "invalid".
pub(crate) fn whole_number<T: std::str::FromStr>(text: &str) -> Result<T, String> {
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
pub(crate) fn whole_in<T>(text: &str, low: T, high: T) -> Result<T, String>
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display,
{
    let value = whole_number::<T>(text)?;
    if value < low || value > high {
        return Err(format!("is not between {low} and {high}"));
    }
    Ok(value)
}

/// The largest image side the command line takes (frame width and height, shadow map
/// sizes): beyond what any Vulkan implementation takes (the specification requires
/// 4096 per side of a 2D image; devices report up to 32768). Within it, the device's
/// own limit is checked once the device is known (a runtime error, exit 1); beyond it,
/// the value is bad usage (exit 2), whatever the device.
pub(crate) const MAX_IMAGE_SIDE: u32 = 65536;

/// An image side in pixels: 1 to [`MAX_IMAGE_SIDE`].
pub(crate) fn image_side(text: &str) -> Result<u32, String> {
    let value = at_least_one(text)?;
    if value > MAX_IMAGE_SIDE {
        return Err(format!(
            "is above {MAX_IMAGE_SIDE}, more pixels per side than any Vulkan device takes"
        ));
    }
    Ok(value)
}

/// A shadow map's side: at least `MIN_SHADOW_MAP_SIZE` (64), at most what an image side
/// may be; the device's own limit is checked when it is known.
pub(crate) fn shadow_map_side(text: &str) -> Result<u32, String> {
    let value = image_side(text)?;
    let least = combustion::renderer::MIN_SHADOW_MAP_SIZE;
    if value < least {
        return Err(format!(
            "is {value}; a shadow map's side is at least {least}"
        ));
    }
    Ok(value)
}

/// An image size or a frame count: at least 1.
/// `--path-traced-frames`: 2 (for a spread) to 1024.
fn path_traced_frames(text: &str) -> Result<u32, String> {
    let value = whole_number::<u32>(text)?;
    if !(2..=1024).contains(&value) {
        return Err(format!("is {value}; use 2 to 1024"));
    }
    Ok(value)
}

pub(crate) fn at_least_one(text: &str) -> Result<u32, String> {
    let value = whole_number::<u32>(text)?;
    if value == 0 {
        return Err("is 0; it must be at least 1".to_owned());
    }
    Ok(value)
}

pub(crate) fn supersample_factor(text: &str) -> Result<u32, String> {
    whole_in(text, 1, MAX_SUPERSAMPLE)
}

pub(crate) fn frames_in_flight(text: &str) -> Result<usize, String> {
    whole_in(text, 1, MAX_FRAMES_IN_FLIGHT)
}

pub(crate) fn extra_lights(text: &str) -> Result<usize, String> {
    whole_in(text, 0, 65536)
}

/// A finite number above 0.
/// A finite number (any sign).
pub(crate) fn finite<T: std::str::FromStr + Into<f64> + Copy>(text: &str) -> Result<T, String> {
    match text.parse::<T>() {
        Ok(value) if value.into().is_finite() => Ok(value),
        // A finite number too large for the option's type (1e308 for a 32-bit float)
        // parses to infinity: say so, not that it is not finite.
        Ok(_) if text.parse::<f64>().is_ok_and(f64::is_finite) => Err(format!(
            "is beyond the largest value this option takes ({})",
            if std::mem::size_of::<T>() == 4 {
                "3.40282e38"
            } else {
                "1.79769e308"
            }
        )),
        Ok(_) => Err("is not a finite number".to_owned()),
        Err(_) => Err("is not a number".to_owned()),
    }
}

pub(crate) fn positive_finite<T: std::str::FromStr + Into<f64> + Copy>(
    text: &str,
) -> Result<T, String> {
    match text.parse::<T>() {
        Ok(value) if value.into().is_finite() && value.into() > 0.0 => Ok(value),
        Ok(_) => Err("is not a finite number above 0".to_owned()),
        Err(_) => Err("is not a number".to_owned()),
    }
}

/// An accuracy budget: a relative error above 0.
pub(crate) fn relative_error(text: &str) -> Result<f64, String> {
    positive_finite::<f64>(text).map_err(|_| "is not a relative error above 0 (e.g. 1e-3)".into())
}

/// One value for all three RGB channels, or one per channel.
pub(crate) fn rgb(text: &str) -> Result<[f64; 3], String> {
    match number_list(text, &[1, 3])?.as_slice() {
        [x] => Ok([*x; 3]),
        [r, g, b] => Ok([*r, *g, *b]),
        _ => Err("takes 1 or 3 values".to_owned()),
    }
}

pub(crate) fn builtin_metal(name: &str) -> Result<BuiltinMetal, String> {
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
pub(crate) fn named<T, const N: usize>(
    options: [(&'static str, T); N],
) -> impl TypedValueParser<Value = T>
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

pub(crate) fn on_off() -> impl TypedValueParser<Value = bool> {
    named([("on", true), ("off", false)])
}

/// `--diffuse`: `material` (each material's own model) or one model for all.
pub(crate) fn diffuse_override() -> impl TypedValueParser<Value = Option<DiffuseModel>> {
    let [a, b, c] = DiffuseModel::ALL;
    named([
        ("material", None),
        (a.name(), Some(a)),
        (b.name(), Some(b)),
        (c.name(), Some(c)),
    ])
}

/// SCENE: `builtin:NAME`, or a file path in whatever bytes the system allows.
pub(crate) fn scene_source() -> impl TypedValueParser<Value = SceneSource> {
    OsStringValueParser::new().map(|text: OsString| SceneSource::parse_os(&text))
}

/// `--environment`, as given; [`EnvironmentChoice::load`] reads a file.
#[derive(Clone, Debug)]
pub(crate) enum EnvironmentChoice {
    None,
    Studio,
    Uniform([f32; 3]),
    File(PathBuf),
}

impl EnvironmentChoice {
    pub(crate) fn parse(text: OsString) -> Result<Self, String> {
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
            let channel = radiance_channel;
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
    pub(crate) fn load(&self) -> Result<Option<Environment>, Error> {
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

/// The scene of `source` seen from `camera`, with `--environment` and `--light-rig`
/// applied (the rig follows the camera); `--shadows on` where no light casts shadows is
/// said (once, as a warning).
pub(crate) fn lit_as_asked(
    source: &SceneSource,
    camera: CameraChoice,
    shading: &ShadingArgs,
) -> Result<Scene, Error> {
    let mut scene = loaded_as_asked(source, camera, shading)?;
    scene.camera = camera.place(&scene);
    scene.lights.extend(shading.light_rig(&scene.camera));
    let default = ShadowSettings::DEFAULT;
    let shadow_options_given: Vec<&str> = [
        (
            shading.shadow_cascades != default.cascades,
            "--shadow-cascades",
        ),
        (
            shading.shadow_map_size != default.map_size,
            "--shadow-map-size",
        ),
        (
            shading.shadow_local_map_size != default.local_map_size,
            "--shadow-local-map-size",
        ),
        (shading.shadow_filter != default.filter, "--shadow-filter"),
    ]
    .into_iter()
    .filter_map(|(given, name)| given.then_some(name))
    .collect();
    if !shading.shadows && !shadow_options_given.is_empty() {
        log::warn!(
            "{} {} nothing without --shadows on",
            shadow_options_given.join(", "),
            if shadow_options_given.len() == 1 {
                "does"
            } else {
                "do"
            }
        );
    }
    if let Some(settings) = shading.shadows() {
        // Lights past what the maps hold cast none: said, not silent.
        let casting: Vec<usize> = (0..scene.lights.len())
            .filter(|&i| scene.lights[i].casts_shadows())
            .collect();
        let kinds = combustion::renderer::ShadowKinds::of(&scene.lights);
        let shadowed: Vec<usize> =
            combustion::renderer::shadowed_lights(&scene.lights, &settings, kinds)
                .into_iter()
                .map(|(index, _)| index)
                .collect();
        let left_out: Vec<String> = casting
            .iter()
            .filter(|i| !shadowed.contains(i))
            .map(usize::to_string)
            .collect();
        if !left_out.is_empty() {
            log::warn!(
                "{}: --shadows on: {} of its {} lights that cast shadows cast none (lights {}): the maps hold {} layers — a sun one per cascade, a point light or wide spot six, a narrow spot one — and {} suns at most",
                source.label(),
                left_out.len(),
                casting.len(),
                left_out.join(", "),
                combustion::renderer::MAX_SHADOW_LAYERS,
                combustion::renderer::MAX_SHADOWED_LIGHTS
            );
        }
    }
    if shading.shadows && !scene.lights.iter().any(|l| l.casts_shadows()) {
        let lights = match scene.lights.len() {
            0 => "it has no lights".to_owned(),
            n => format!("none of its {n} lights casts shadows"),
        };
        log::warn!(
            "{}: --shadows on does nothing here: {lights} (shadow maps darken lights, not the environment)",
            source.label()
        );
    }
    Ok(scene)
}

/// The scene of `source` as [`lit_as_asked`] makes it before the camera is placed and
/// the rig added: the file's camera `camera` chooses, `--environment` and
/// `--scene-lights` applied. A file is lit by its own lights and the studio environment
/// ([`SceneSource::load`]); `--environment` replaces the studio, `--scene-lights off`
/// drops the file's lights. A file without lights (or with them dropped) is lit by the
/// studio alone unless `--environment` says otherwise or `--light-rig` lights it
/// instead, and only then is that said (once, as a warning).
pub(crate) fn loaded_as_asked(
    source: &SceneSource,
    camera: CameraChoice,
    shading: &ShadingArgs,
) -> Result<Scene, Error> {
    let options = combustion::scene::gltf::ImportOptions {
        metal_colour: shading.metal_colour,
        ..camera.import_options(source)?
    };
    let mut scene = source.load_with(&options)?;
    if !shading.scene_lights {
        scene.lights.clear();
    }
    let lit_by_default = matches!(source, SceneSource::File(_)) && scene.lights.is_empty();
    if let Some(environment) = &shading.environment {
        scene.environment = environment.load()?;
    } else if lit_by_default && shading.light_rig {
        scene.environment = None;
    }
    if lit_by_default && shading.environment.is_none() && !shading.light_rig {
        log::warn!(
            "{}: the scene has no lights; lighting it with the studio environment (--environment or --light-rig light it otherwise)",
            source.label()
        );
    }
    if scene.environment.is_none() {
        for (pass, nothing) in shading
            .optional
            .passes
            .iter()
            .filter_map(|p| Some((p, p.needs_environment?)))
        {
            log::warn!(
                "{}: {}: the scene is lit by no environment, so there is {nothing} (--environment studio lights it by one); frames are rendered without it",
                source.label(),
                pass.asked_as()
            );
        }
    }
    Ok(scene)
}

/// Warns, before rendering, of what would make a `width`×`height` frame of `scene` show
/// nothing or not what it holds ([`combustion::scene::ViewWarning`]): no object in
/// view, objects too far out for 32-bit positions (the first named, the rest counted).
pub(crate) fn warn_about_view(scene: &Scene, label: &str, width: u32, height: u32) {
    let warnings = scene.view_warnings(width as f32 / height as f32);
    let far = |w: &&combustion::scene::ViewWarning| {
        matches!(w, combustion::scene::ViewWarning::BeyondPrecision { .. })
    };
    let beyond_precision = warnings.iter().filter(far).count();
    for warning in warnings.iter().filter(|w| !far(w)) {
        log::warn!("{label}: {warning}");
    }
    if let Some(first) = warnings.iter().find(far) {
        let more = match beyond_precision - 1 {
            0 => String::new(),
            n => format!(" ({n} more objects likewise)"),
        };
        log::warn!("{label}: {first}{more}");
    }
}

/// Checks, before any scene or image is loaded, that the device `device` selects exists
/// and takes frames of `frame`'s size: a bad `--device` or a side beyond the device's
/// `maxImageDimension2D` is reported at once, not after the loading (an environment
/// image can take seconds and gigabytes to decode).
pub(crate) fn preflight(device: &DeviceDesc, frame: &FrameArgs) -> Result<(), Error> {
    preflight_size(device, frame.width, frame.height)
}

/// [`preflight`] for a size given apart (`info --max-error`'s).
pub(crate) fn preflight_size(device: &DeviceDesc, width: u32, height: u32) -> Result<(), Error> {
    let info = combustion::vk::Device::preflight(&device.selector)?;
    let max = info.max_image_dimension_2d;
    if width > max || height > max {
        return Err(combustion::renderer::RenderError::InvalidSize { width, height, max }.into());
    }
    Ok(())
}

/// The device (`--device`, else `COMBUSTION_DEVICE`, else automatic) and renderer
/// settings the options ask for.
pub(crate) fn device_and_settings(
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
    Ok((desc, renderer_settings(frame, frames_in_flight)))
}

/// The renderer settings `frame`'s options ask for.
pub(crate) fn renderer_settings(frame: &FrameArgs, frames_in_flight: usize) -> RendererSettings {
    RendererSettings {
        exposure: frame.exposure_factor(),
        hdr_format: frame.hdr_format,
        gbuffer: GBufferStorage {
            base_color: frame.gbuffer_base_color,
            surface: frame.gbuffer_surface,
        },
        shading: ShadingOptions {
            fresnel: frame.fresnel,
            ..ShadingOptions::default()
        },
        frames_in_flight,
        ..RendererSettings::default()
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
    fn the_gbuffer_storage_options_reach_the_renderer_settings() {
        use clap::Parser;
        use combustion::renderer::{BaseColorStorage, GBufferStorage, SurfaceStorage};
        let settings = |line: &str| {
            let words = ["combustion"].into_iter().chain(line.split_whitespace());
            let super::Command::Bench(o) = super::Cli::try_parse_from(words).unwrap().command
            else {
                panic!("not bench");
            };
            super::device_and_settings(&o.device, &o.frame, o.frames_in_flight)
                .unwrap()
                .1
                .gbuffer
        };
        assert_eq!(settings("bench --device llvmpipe"), GBufferStorage::DEFAULT);
        assert_eq!(
            settings("bench --device llvmpipe --gbuffer-base-color f16 --gbuffer-surface unorm8"),
            GBufferStorage {
                base_color: BaseColorStorage::LinearHalf,
                surface: SurfaceStorage::Unorm8,
            }
        );
    }

    #[test]
    fn every_option_reaches_its_field() {
        use clap::Parser;
        let frame = "--width 8 --height 9 --exposure 2 --fresnel f82 --hdr-format f16 \
                     --gbuffer-base-color srgb16 --gbuffer-surface unorm8";
        let shading = "--distribution beckmann --diffuse lambert --environment uniform:1,2,3 \
                       --light-rig --energy-compensation on --metal-colour colorimetric";
        let device = "--device llvmpipe --validate";
        let lines = [
            format!("render builtin:spheres -o a.png --hdr a.exr {frame} {shading} {device}"),
            format!("render builtin:spheres -o a.png --max-error 0.1 --width 8 --environment-samples 4 --energy-compensation on {device}"),
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
            "info builtin:spheres --max-error 1e-3 --width 320 --height 180".to_owned(),
            "devices".to_owned(),
            "diff a.png b.png --heatmap h.png --json --criteria-file c.txt".to_owned(),
            "render x.glb --camera 2".to_owned(),
            "render --camera orbit:-30,-10,0.5".to_owned(),
            "render --camera framing".to_owned(),
            "batch m.json -o out --goldens g --update-goldens --shard 2/3 --device llvmpipe --validate".to_owned(),
            "batch --merge a b c -o out".to_owned(),
            "diff a.exr b.exr --criteria max-flip<=1".to_owned(),
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
