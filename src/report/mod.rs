//! `combustion bench --report DIR`: speed against error. For each scene and each
//! *variant set* (Fresnel model, HDR storage, lighting pipeline, masking term: the
//! default, each term changed alone, and all the cheap choices together), the GPU time of every
//! pass over N frames after a warm-up (median, p10, p90; timestamps), and the error of
//! one frame against the f64 reference (`combustion_renderer::reference`: every pixel
//! re-shaded from its own G-buffer with the full Fresnel equations; max, mean and RMS
//! relative error); and per scene, in the same run, the measurement floors
//! (`MeasurementFloor`) every pass is stated as a multiple of. Written as `report.md`,
//! `report.csv`, `floors.csv` and `speed-vs-error.png` (one point per variant set — time
//! and error averaged over the scenes — with the Pareto front).

pub mod anti_aliasing;
pub mod environment_sampling;
pub mod light_transport;
pub mod occlusion;
pub mod shadows;
pub mod storage;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use combustion_plots::{
    pareto_front, plot_scaling, plot_speed_vs_error, Png, Series, SpeedErrorPoint, XAxis,
};
use combustion_reference::SceneBvh;
use combustion_renderer::reference::{error_map, EnvironmentSampling, ErrorMap, ReferenceShading};

use crate::end_to_end::{precision_of, EndToEndErrors, EnvironmentReference, SceneReference};

/// How the report's reference integrates an environment: 2 000 samples of each strategy
/// (oracle noise ≈ 1–3 % at the noisiest pixels, `tests/environment.rs`) at one pixel in
/// 16 × 16; the mean FLIP column is left empty for such scenes (no whole reference).
pub const ENVIRONMENT_SAMPLING: EnvironmentSampling = EnvironmentSampling {
    iterations: 2_000,
    stride: 16,
};
use combustion_renderer::{
    Distribution, Frame, FrameInputs, FresnelModel, GBufferStorage, GpuScene, HdrFormat,
    LightCulling, Masking, MeasurementFloor, PassTimings, Readback, Renderer, RendererSettings,
    ShadingOptions, ToneMapping,
};
use combustion_scene::DiffuseModel;
use combustion_vk::DeviceDesc;

use crate::{check_validation, output, Error, Headless, HeadlessDesc, SceneSource};

/// One combination of the renderer's measured options: shading options and the HDR
/// format (fixed when a renderer is made, so each format gets its own renderer).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VariantSet {
    /// The shading options (the report varies the Fresnel term, the pipeline, the masking
    /// term, the distribution and the diffuse override; the rest stay at their defaults).
    pub shading: ShadingOptions,
    /// The HDR image's format.
    pub hdr: HdrFormat,
}

impl VariantSet {
    /// The renderer's defaults: the exact model, f32 HDR, specialised pipeline.
    pub const DEFAULT: VariantSet = VariantSet {
        shading: ShadingOptions::DEFAULT,
        hdr: HdrFormat::Rgba32Float,
    };

    /// The default set with other shading options.
    pub const fn with(shading: ShadingOptions) -> VariantSet {
        VariantSet {
            shading,
            hdr: HdrFormat::Rgba32Float,
        }
    }

    /// Every set the report measures: the default; each term changed alone (the general
    /// pipeline; Schlick's and Hoffman's F82 Fresnel; f16 HDR; the separable and the
    /// approximate masking term; Beckmann's D; Lambert, qualitative and full Oren–Nayar
    /// for every material); and every cheap choice at once.
    pub fn all() -> Vec<VariantSet> {
        let d = Self::DEFAULT;
        let o = ShadingOptions::DEFAULT;
        vec![
            d,
            Self::with(ShadingOptions {
                specialised: false,
                ..o
            }),
            Self::with(ShadingOptions {
                fresnel: FresnelModel::Schlick,
                ..o
            }),
            Self::with(ShadingOptions {
                fresnel: FresnelModel::F82,
                ..o
            }),
            VariantSet {
                hdr: HdrFormat::Rgba16Float,
                ..d
            },
            Self::with(ShadingOptions {
                masking: Masking::Separable,
                ..o
            }),
            Self::with(ShadingOptions {
                masking: Masking::Approximate,
                ..o
            }),
            Self::with(ShadingOptions {
                distribution: Distribution::Beckmann,
                ..o
            }),
            Self::with(ShadingOptions {
                diffuse_override: Some(DiffuseModel::Lambert),
                ..o
            }),
            Self::with(ShadingOptions {
                diffuse_override: Some(DiffuseModel::OrenNayarQualitative),
                ..o
            }),
            Self::with(ShadingOptions {
                diffuse_override: Some(DiffuseModel::OrenNayarFull),
                ..o
            }),
            VariantSet {
                shading: ShadingOptions {
                    fresnel: FresnelModel::Schlick,
                    masking: Masking::Approximate,
                    diffuse_override: Some(DiffuseModel::Lambert),
                    ..o
                },
                hdr: HdrFormat::Rgba16Float,
            },
        ]
    }

    /// A short name, e.g. `full/f32/specialised/correlated/ggx/material`: Fresnel, HDR,
    /// pipeline, masking, distribution, diffuse.
    pub fn name(&self) -> String {
        let o = &self.shading;
        format!(
            "{}/{}/{}/{}/{}/{}",
            o.fresnel.name(),
            match self.hdr {
                HdrFormat::Rgba32Float => "f32",
                HdrFormat::Rgba16Float => "f16",
            },
            if o.specialised {
                "specialised"
            } else {
                "general"
            },
            o.masking.name(),
            o.distribution.name(),
            diffuse_name(o.diffuse_override)
        )
    }

    /// What differs from [`VariantSet::DEFAULT`], joined by `+` (`default` for it), e.g.
    /// `schlick+f16`: the plot's labels.
    pub fn short_name(&self) -> String {
        let name = self.name();
        let default = Self::DEFAULT.name();
        let changed: Vec<&str> = name
            .split('/')
            .zip(default.split('/'))
            .filter(|(a, b)| a != b)
            .map(|(a, _)| a)
            .collect();
        if changed.is_empty() {
            "default".to_owned()
        } else {
            changed.join("+")
        }
    }
}

/// The report's name of a diffuse override.
fn diffuse_name(diffuse: Option<DiffuseModel>) -> &'static str {
    match diffuse {
        None => "material",
        Some(model) => model.name(),
    }
}

/// Median and spread of one pass's GPU time, ms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spread {
    /// The median, ms.
    pub median: f64,
    /// The 10th percentile (the sorted value at index round(0.1 · (n − 1))), ms.
    pub p10: f64,
    /// The 90th percentile (the sorted value at index round(0.9 · (n − 1))), ms.
    pub p90: f64,
}

impl Spread {
    /// No measurement: NaN throughout.
    pub const NONE: Spread = Spread {
        median: f64::NAN,
        p10: f64::NAN,
        p90: f64::NAN,
    };

    /// The spread of `values` ([`Spread::NONE`] when there are none).
    pub fn of(mut values: Vec<f64>) -> Spread {
        if values.is_empty() {
            return Spread::NONE;
        }
        values.sort_by(f64::total_cmp);
        let at = |p: f64| values[((values.len() - 1) as f64 * p).round() as usize];
        Spread {
            median: at(0.5),
            p10: at(0.1),
            p90: at(0.9),
        }
    }
}

/// Each pass's GPU time over the frames measured, by name ([`PassTimings::passes`]),
/// in the order the frames ran the passes: the report's columns follow whatever passes
/// ran.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassSpreads(pub Vec<(&'static str, Spread)>);

impl PassSpreads {
    /// The spread of each pass over `timings`.
    pub fn of(timings: &[PassTimings]) -> Self {
        let mut lists: Vec<(&'static str, Vec<f64>)> = Vec::new();
        for t in timings {
            for pass in &t.passes {
                match lists.iter_mut().find(|(name, _)| *name == pass.name) {
                    Some((_, list)) => list.push(pass.ms),
                    None => lists.push((pass.name, vec![pass.ms])),
                }
            }
        }
        Self(
            lists
                .into_iter()
                .map(|(name, list)| (name, Spread::of(list)))
                .collect(),
        )
    }

    /// The spread of the pass named `name` (NaN where the frames did not run it).
    pub fn get(&self, name: &str) -> Spread {
        self.0
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(Spread::NONE, |(_, spread)| *spread)
    }

    /// The names of the passes of any of `rows`, in order of first appearance.
    fn names<'a>(rows: impl IntoIterator<Item = &'a PassSpreads>) -> Vec<&'static str> {
        let mut names = Vec::new();
        for spreads in rows {
            for (name, _) in &spreads.0 {
                if !names.contains(name) {
                    names.push(*name);
                }
            }
        }
        names
    }
}

/// CSV columns `NAME_ms,NAME_p10,NAME_p90` for each of `names` (a space in a name
/// becomes `_`).
fn spread_columns(names: &[&str]) -> Vec<String> {
    names
        .iter()
        .flat_map(|name| {
            let name = name.replace(' ', "_");
            [
                format!("{name}_ms"),
                format!("{name}_p10"),
                format!("{name}_p90"),
            ]
        })
        .collect()
}

/// The CSV values of `spreads` in the columns of `names`.
fn spread_values(spreads: &[Spread]) -> Vec<String> {
    spreads
        .iter()
        .flat_map(|s| [s.median, s.p10, s.p90].map(|ms| format!("{ms:.3}")))
        .collect()
}

/// `columns` as the header of a CSV table.
fn table(columns: Vec<String>) -> combustion_report_csv::Table {
    let names: Vec<&str> = columns.iter().map(String::as_str).collect();
    combustion_report_csv::Table::new(&names)
}

/// `names` as owned column names.
fn columns(names: &str) -> Vec<String> {
    names.split(',').map(str::to_owned).collect()
}

/// One scene under one variant set.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportRow {
    /// The scene's label (`builtin:NAME` or the file's path).
    pub scene: String,
    /// The variant set rendered.
    pub set: VariantSet,
    /// Each pass's time.
    pub passes: PassSpreads,
    /// Whole frame's GPU time.
    pub total: Spread,
    /// Frames timed.
    pub frames: usize,
    /// The largest per-pixel relative error against the f64 reference.
    pub max_relative: f64,
    /// The mean per-pixel relative error against the f64 reference.
    pub mean_relative: f64,
    /// The root mean square of the per-pixel relative errors.
    pub rms_relative: f64,
    /// Pixels compared with the reference.
    pub compared: usize,
    /// Mean FLIP between the display image and the reference's ([`flip_against_reference`]).
    pub flip_mean: f64,
    /// The scene is lit by an environment: its error is the split sum's against the
    /// f64 rendering equation, on a grid of pixels ([`ENVIRONMENT_SAMPLING`]).
    pub environment: bool,
    /// The frame against the scene itself ([`crate::end_to_end`]: ray cast and shaded
    /// in f64 from the scene, not from the G-buffer); `None` for scenes lit by an
    /// environment, which that reference does not integrate.
    pub end_to_end: Option<EndToEndErrors>,
}

/// A scene's measurement floors (f32 HDR, full Fresnel, specialised pipeline), ms.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorRow {
    /// The scene's label.
    pub scene: String,
    /// G-buffer pass with a trivial fragment stage.
    pub geometry: Spread,
    /// Lighting pass that only fetches the G-buffer and writes.
    pub fetch: Spread,
    /// Lighting pass with a plain GGX + Smith + full conductor Fresnel per light.
    pub plain_ggx: Spread,
}

/// Light counts the scaling measurement replaces the scene's lights with.
pub const SCALING_LIGHT_COUNTS: [usize; 5] = [1, 4, 16, 64, 256];

/// Sizes the scaling measurement renders at, as multiples of the report's size.
pub const SCALING_SIZES: [f64; 3] = [0.5, 1.0, 1.5];

/// One configuration of the scaling measurement (the default variant set, f32 HDR).
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingRow {
    /// Width rendered, pixels.
    pub width: u32,
    /// Height rendered, pixels.
    pub height: u32,
    /// Localised lights ([`crate::with_localised_lights`]) in place of the scene's own
    /// (`None`: the scene's lights).
    pub localised_lights: Option<usize>,
    /// Whether frames culled their lights into tile lists.
    pub culled: bool,
    /// Each pass's time.
    pub passes: PassSpreads,
    /// Whole frame's GPU time.
    pub total: Spread,
}

/// Everything measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurements {
    /// One row per scene and variant set.
    pub rows: Vec<ReportRow>,
    /// Each scene's measurement floors (empty unless [`ReportDesc::floors`]).
    pub floors: Vec<FloorRow>,
    /// Frame time against size (the scene's lights), then against localised lights
    /// culled and not culled; empty unless [`ReportDesc::scaling`] names a scene.
    pub scaling: Vec<ScalingRow>,
    /// The scaling measurement's scene.
    pub scaling_scene: String,
    /// The name of the device measured on.
    pub device: String,
    /// The shadow settings on each scene with lights (empty unless
    /// [`ReportDesc::shadows`] names some).
    pub shadows: Vec<shadows::ShadowRow>,
    /// Each G-buffer storage on each scene without an environment (empty unless
    /// [`ReportDesc::storages`] names some).
    pub storages: Vec<storage::StorageRow>,
    /// Each anti-aliasing method on each scene (empty unless
    /// [`ReportDesc::anti_aliasing`]).
    pub anti_aliasing: Vec<anti_aliasing::AntiAliasingRow>,
    /// The split sum and the sampled environment at each count on each scene lit by an
    /// environment (empty unless [`ReportDesc::environment_sampling`]).
    pub environment_sampling: Vec<environment_sampling::EnvironmentSamplingRow>,
    /// Each occlusion method on each scene lit by an environment, against the reference
    /// with the environment's visibility (empty unless [`ReportDesc::occlusion`]).
    pub occlusion: Vec<occlusion::OcclusionRow>,
    /// Each real-time setting on each scene against the path-traced frame (empty unless
    /// [`ReportDesc::path_traced_frames`] and the device has ray queries).
    pub light_transport: Vec<light_transport::LightTransportRow>,
}

/// GPU timings of `frames` frames of `scene` (after the frames already taken).
fn time_frames(
    renderer: &mut Renderer,
    scene: &GpuScene,
    width: u32,
    height: u32,
    frames: u32,
) -> Result<Vec<PassTimings>, Error> {
    let inputs = FrameInputs::of_scene(scene, renderer.settings().exposure);
    time_frames_with(renderer, scene, &inputs, (width, height), frames)
}

/// GPU timings of `frames` frames of `scene` with `inputs` at `width`×`height`.
fn time_frames_with(
    renderer: &mut Renderer,
    scene: &GpuScene,
    inputs: &FrameInputs<'_>,
    (width, height): (u32, u32),
    frames: u32,
) -> Result<Vec<PassTimings>, Error> {
    renderer.take_completed_timings();
    for _ in 0..frames {
        renderer.submit_offscreen_with(scene, inputs, width, height)?;
    }
    renderer.finish_offscreen()?;
    Ok(renderer.take_completed_timings())
}

/// A section of the report (`bench --report-sections`): each measures its own rows and
/// writes its own files.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReportSection {
    /// The variant sets against the f64 reference (report.csv, speed-vs-error.png).
    Variants,
    /// The measurement floors (floors.csv).
    Floors,
    /// Frame time against size and light count (scaling.csv and its plots).
    Scaling,
    /// Shadow settings against exact visibility (shadows.csv and its plot).
    Shadows,
    /// G-buffer storages end to end (gbuffer-storage.csv).
    Storage,
    /// Anti-aliasing methods against 4×4 supersampling (anti-aliasing.csv).
    AntiAliasing,
    /// The split sum and the sampled environment (environment-sampling.csv).
    EnvironmentSampling,
    /// The environment's occlusion (occlusion.csv).
    Occlusion,
    /// The real-time frame against light that bounces (light-transport.csv).
    LightTransport,
}

impl ReportSection {
    /// Every section, in the report's order.
    pub const ALL: [ReportSection; 9] = [
        ReportSection::Variants,
        ReportSection::Floors,
        ReportSection::Scaling,
        ReportSection::Shadows,
        ReportSection::Storage,
        ReportSection::AntiAliasing,
        ReportSection::EnvironmentSampling,
        ReportSection::Occlusion,
        ReportSection::LightTransport,
    ];

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ReportSection::Variants => "variants",
            ReportSection::Floors => "floors",
            ReportSection::Scaling => "scaling",
            ReportSection::Shadows => "shadows",
            ReportSection::Storage => "storage",
            ReportSection::AntiAliasing => "anti-aliasing",
            ReportSection::EnvironmentSampling => "environment-sampling",
            ReportSection::Occlusion => "occlusion",
            ReportSection::LightTransport => "light-transport",
        }
    }
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct ReportDesc {
    /// The scenes to measure.
    pub scenes: Vec<SceneSource>,
    /// Scenes measured lit by the studio environment alone (their lights removed),
    /// after [`ReportDesc::scenes`], labelled `FILE (studio)`: a textured glTF scene's
    /// rows against the environment oracle.
    pub studio_scenes: Vec<SceneSource>,
    /// The variant sets each scene is measured under.
    pub sets: Vec<VariantSet>,
    /// Width of the frames, pixels.
    pub width: u32,
    /// Height of the frames, pixels.
    pub height: u32,
    /// Frames timed per scene and set (after one warm-up frame).
    pub frames: u32,
    /// The device to measure on.
    pub device: DeviceDesc,
    /// Measure each scene's floors too.
    pub floors: bool,
    /// Measure frame time against size and light count on this scene
    /// ([`SCALING_SIZES`], [`SCALING_LIGHT_COUNTS`] culled and not).
    pub scaling: Option<SceneSource>,
    /// The shadow settings measured on each scene with lights
    /// ([`shadows::SHADOW_SETTINGS`]; empty: none).
    pub shadows: Vec<Option<combustion_renderer::ShadowSettings>>,
    /// The G-buffer storages measured on each scene without an environment
    /// ([`storage::all_storages`]; empty: none).
    pub storages: Vec<GBufferStorage>,
    /// Measure each anti-aliasing method on each scene against its 4×4-supersampled
    /// frame ([`anti_aliasing::Method::ALL`]).
    pub anti_aliasing: bool,
    /// Measure the split sum and the sampled environment at each count
    /// ([`environment_sampling::Mode::all`]) on each scene lit by an environment, against
    /// a finer oracle ([`environment_sampling::ORACLE`]).
    pub environment_sampling: bool,
    /// Measure the environment's occlusion (none, the screen-space pass, the traced pass
    /// on devices with ray queries) on each scene lit by an environment
    /// ([`occlusion`]).
    pub occlusion: bool,
    /// Measure each scene's real-time frame against its path-traced frame, this many
    /// path-traced frames averaged ([`light_transport`]; 0: not measured).
    pub path_traced_frames: u32,
}

impl ReportDesc {
    /// A headless renderer on the report's device with `settings`, its lighting and
    /// output passes kept apart (the report times them pass by pass).
    pub(crate) fn headless(&self, settings: RendererSettings) -> Result<Headless, Error> {
        Headless::new(&HeadlessDesc {
            device: self.device.clone(),
            settings: RendererSettings {
                fold_output: false,
                ..settings
            },
        })
    }

    /// The variant sets' rows alone, on `scenes` at `width` × `height` over `frames`
    /// frames: no floors, scaling, shadows, storages, anti-aliasing, sampled environment
    /// or studio-lit files (add them with struct update syntax).
    pub fn rows_only(
        scenes: Vec<SceneSource>,
        sets: Vec<VariantSet>,
        (width, height): (u32, u32),
        frames: u32,
        device: DeviceDesc,
    ) -> ReportDesc {
        ReportDesc {
            scenes,
            studio_scenes: Vec::new(),
            sets,
            width,
            height,
            frames,
            device,
            floors: false,
            scaling: None,
            shadows: Vec::new(),
            storages: Vec::new(),
            anti_aliasing: false,
            environment_sampling: false,
            occlusion: false,
            path_traced_frames: 0,
        }
    }

    /// Steps of the light-transport measurement on `scenes`.
    fn light_transport_steps(&self, scenes: &[(String, combustion_scene::Scene)]) -> usize {
        if self.path_traced_frames == 0 {
            return 0;
        }
        light_transport::steps(scenes)
    }

    /// Steps of the shadow measurement on `scenes`.
    fn shadow_steps(&self, scenes: &[(String, combustion_scene::Scene)]) -> usize {
        let suns = scenes
            .iter()
            .filter(|(_, scene)| !scene.lights.is_empty())
            .count();
        suns * self.shadows.len()
    }

    /// Steps of the sampled-environment measurement on `scenes`: one per scene lit by an
    /// environment.
    fn environment_sampling_steps(&self, scenes: &[(String, combustion_scene::Scene)]) -> usize {
        if !self.environment_sampling {
            return 0;
        }
        scenes
            .iter()
            .filter(|(_, scene)| scene.environment.is_some())
            .count()
    }

    /// Steps of the occlusion measurement on `scenes`: one per method on each scene lit
    /// by an environment (the traced one counted, on any device).
    fn occlusion_steps(&self, scenes: &[(String, combustion_scene::Scene)]) -> usize {
        if !self.occlusion {
            return 0;
        }
        3 * scenes
            .iter()
            .filter(|(_, scene)| scene.environment.is_some())
            .count()
    }

    /// Steps of the storage measurement on `scenes`.
    fn storage_steps(&self, scenes: &[(String, combustion_scene::Scene)]) -> usize {
        let lit_by_lights = scenes
            .iter()
            .filter(|(_, scene)| scene.environment.is_none())
            .count();
        lit_by_lights * self.storages.len()
    }

    /// Steps of the scaling measurement.
    fn scaling_steps(&self) -> usize {
        if self.scaling.is_some() {
            SCALING_SIZES.len() + 2 * SCALING_LIGHT_COUNTS.len()
        } else {
            0
        }
    }
}

/// Times `scene` at `width`×`height` with `culling` (one warm-up frame, then
/// `frames`), with the renderer's current variant set.
fn time_configuration(
    renderer: &mut Renderer,
    scene: &combustion_scene::Scene,
    (width, height): (u32, u32),
    culling: LightCulling,
    frames: u32,
    localised_lights: Option<usize>,
) -> Result<ScalingRow, Error> {
    renderer.set_light_culling(culling);
    let gpu = renderer.upload(scene)?;
    renderer.render(&gpu, width, height, Readback::default())?;
    let timings = time_frames(renderer, &gpu, width, height, frames)?;
    renderer.retire(gpu);
    renderer.set_light_culling(LightCulling::Auto);
    Ok(ScalingRow {
        width,
        height,
        localised_lights,
        culled: culling.culls(&scene.lights),
        passes: PassSpreads::of(&timings),
        total: Spread::of(timings.iter().map(|t| t.total_ms).collect()),
    })
}

/// The scaling measurement on `scene` (default variant set): `step(what)` before each.
fn measure_scaling(
    renderer: &mut Renderer,
    scene: &combustion_scene::Scene,
    desc: &ReportDesc,
    mut step: impl FnMut(&str),
) -> Result<Vec<ScalingRow>, Error> {
    renderer.set_shading(VariantSet::DEFAULT.shading, &[])?;
    let mut rows = Vec::new();
    for factor in SCALING_SIZES {
        let size = (
            ((f64::from(desc.width) * factor).round() as u32).max(1),
            ((f64::from(desc.height) * factor).round() as u32).max(1),
        );
        step(&format!("scaling {}×{}", size.0, size.1));
        rows.push(time_configuration(
            renderer,
            scene,
            size,
            LightCulling::Auto,
            desc.frames,
            None,
        )?);
    }
    let unlit = combustion_scene::Scene {
        lights: Vec::new(),
        ..scene.clone()
    };
    for n in SCALING_LIGHT_COUNTS {
        let lit = crate::with_localised_lights(&unlit, n);
        for culling in [LightCulling::Auto, LightCulling::Never] {
            step(&format!("scaling {n} lights, culling {}", culling.name()));
            rows.push(time_configuration(
                renderer,
                &lit,
                (desc.width, desc.height),
                culling,
                desc.frames,
                Some(n),
            )?);
        }
    }
    Ok(rows)
}

/// Measures every scene under every variant set, and each scene's floors (with the
/// f32 renderer); `progress(done, total, what)` is called before each measurement.
pub fn measure(
    desc: &ReportDesc,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<Measurements, Error> {
    let mut device_name = String::new();
    let mut floors = Vec::new();
    let mut scenes = desc
        .scenes
        .iter()
        .map(|source| Ok((source.label(), source.load()?)))
        .collect::<Result<Vec<_>, Error>>()?;
    for source in &desc.studio_scenes {
        let mut scene = source.load()?;
        scene.lights.clear();
        scene.environment = Some(combustion_scene::Environment::Studio);
        scenes.push((format!("{} (studio)", source.label()), scene));
    }
    let scaling_scene = match &desc.scaling {
        Some(source) => Some((source.label(), source.load()?)),
        None => None,
    };
    let total = scenes.len() * (desc.sets.len() + usize::from(desc.floors))
        + desc.scaling_steps()
        + desc.shadow_steps(&scenes)
        + desc.storage_steps(&scenes)
        + if desc.anti_aliasing { scenes.len() } else { 0 }
        + desc.environment_sampling_steps(&scenes)
        + desc.occlusion_steps(&scenes)
        + desc.light_transport_steps(&scenes);
    let mut rows = Vec::with_capacity(total);
    let mut scaling = Vec::new();
    let mut shadow_rows = Vec::new();
    // One renderer per HDR format (a renderer's HDR storage is fixed at creation).
    for hdr in [HdrFormat::Rgba32Float, HdrFormat::Rgba16Float] {
        let sets: Vec<VariantSet> = desc.sets.iter().copied().filter(|s| s.hdr == hdr).collect();
        // The floors, shadows and scaling are measured with the f32 renderer, variant
        // sets or not.
        let f32_sections = hdr == HdrFormat::Rgba32Float
            && (desc.floors || !desc.shadows.is_empty() || scaling_scene.is_some());
        if sets.is_empty() && !f32_sections {
            continue;
        }
        let mut headless = desc.headless(RendererSettings {
            hdr_format: hdr,
            ..RendererSettings::default()
        })?;
        let renderer = headless.renderer();
        device_name.clone_from(&renderer.device().info().name);
        for (label, scene) in &scenes {
            let gpu = renderer.upload(scene)?;
            if desc.floors && hdr == HdrFormat::Rgba32Float {
                progress(
                    rows.len() + floors.len() + scaling.len(),
                    total,
                    &format!("{label} floors"),
                );
                let mut spreads = Vec::new();
                for floor in [
                    MeasurementFloor::Geometry,
                    MeasurementFloor::LightingFetch,
                    MeasurementFloor::LightingPlainGgx,
                ] {
                    let shading = ShadingOptions {
                        measurement_floor: Some(floor),
                        ..VariantSet::DEFAULT.shading
                    };
                    renderer.set_shading(shading, &[&gpu])?;
                    renderer.render(&gpu, desc.width, desc.height, Readback::default())?;
                    let timings =
                        time_frames(renderer, &gpu, desc.width, desc.height, desc.frames)?;
                    spreads.push(Spread::of(
                        timings
                            .iter()
                            .map(|t| match floor {
                                MeasurementFloor::Geometry => t.ms_or_zero(PassTimings::GBUFFER),
                                _ => t.ms_or_zero(PassTimings::LIGHTING),
                            })
                            .collect(),
                    ));
                }
                floors.push(FloorRow {
                    scene: label.clone(),
                    geometry: spreads[0],
                    fetch: spreads[1],
                    plain_ggx: spreads[2],
                });
            }
            // What every set is measured against: one f64 reference per scene and size,
            // from the G-buffer (the lighting pass's error) and from the scene itself
            // (the frame's, end to end; for environment lighting on the same sampled
            // pixels as the lighting pass's reference).
            let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
            let inputs = FrameInputs::of_scene(&gpu, 1.0);
            // (Made only for variant sets: at 1280×720 each takes seconds.)
            let bvh = (!sets.is_empty()).then(|| SceneBvh::new(gpu.scene()));
            let references = bvh.as_ref().map(|bvh| {
                let size = (desc.width, desc.height);
                let scene_reference =
                    scene_reference(gpu.scene(), bvh, size, GBufferStorage::DEFAULT, threads);
                let mut reference =
                    ReferenceShading::new(gpu.scene(), &inputs, desc.width, desc.height);
                if let Some(environment) = &gpu.scene().environment {
                    reference =
                        reference.with_environment(environment.clone(), ENVIRONMENT_SAMPLING);
                }
                (scene_reference, reference)
            });
            for (set, (scene_reference, reference)) in sets
                .iter()
                .filter_map(|set| Some((set, references.as_ref()?)))
            {
                progress(
                    rows.len() + floors.len() + scaling.len(),
                    total,
                    &format!("{label} {}", set.name()),
                );
                renderer.set_shading(set.shading, &[&gpu])?;
                // The error of one frame (read back), which is also the warm-up.
                let frame =
                    renderer.render_with(&gpu, &inputs, desc.width, desc.height, Readback::ALL)?;
                let map = error_map(&frame, reference, threads);
                let end_to_end = Some(scene_reference.compare(&frame).summary());
                let flip_mean = flip_against_reference(&frame, &map, inputs.exposure);
                let timings = time_frames(renderer, &gpu, desc.width, desc.height, desc.frames)?;
                if timings.is_empty() {
                    return Err(Error::Usage(
                        "this device gives no GPU timestamps; the report needs them".into(),
                    ));
                }
                rows.push(ReportRow {
                    scene: label.clone(),
                    set: *set,
                    passes: PassSpreads::of(&timings),
                    total: Spread::of(timings.iter().map(|t| t.total_ms).collect()),
                    frames: timings.len(),
                    max_relative: map.max_relative,
                    mean_relative: map.mean_relative,
                    rms_relative: map.rms_relative,
                    compared: map.lit_pixels,
                    flip_mean,
                    environment: gpu.scene().environment.is_some(),
                    end_to_end,
                });
            }
            if hdr == HdrFormat::Rgba32Float && !desc.shadows.is_empty() && !scene.lights.is_empty()
            {
                let done = rows.len() + floors.len() + scaling.len() + shadow_rows.len();
                let mut i = 0;
                shadow_rows.extend(shadows::measure_scene(
                    renderer,
                    &gpu,
                    label,
                    desc,
                    threads,
                    |what| {
                        progress(done + i, total, what);
                        i += 1;
                    },
                )?);
            }
            renderer.retire(gpu);
        }
        if let (Some((_, scene)), HdrFormat::Rgba32Float) = (&scaling_scene, hdr) {
            let done = rows.len() + floors.len() + scaling.len() + shadow_rows.len();
            let mut i = 0;
            scaling = measure_scaling(renderer, scene, desc, |what| {
                progress(done + i, total, what);
                i += 1;
            })?;
        }
        let validation = headless.validation_log();
        drop(headless);
        check_validation(&validation)?;
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let done = rows.len() + floors.len() + scaling.len() + shadow_rows.len();
    let mut i = 0;
    let storage_rows = storage::measure(&scenes, desc, threads, |what| {
        progress(done + i, total, what);
        i += 1;
    })?;
    let anti_aliasing_rows = if desc.anti_aliasing {
        let done = done + storage_rows.len();
        let mut i = 0;
        anti_aliasing::measure(&scenes, desc, |what| {
            progress(done + i, total, what);
            i += 1;
        })?
    } else {
        Vec::new()
    };
    let environment_sampling_rows = if desc.environment_sampling {
        let done = done + storage_rows.len() + if desc.anti_aliasing { scenes.len() } else { 0 };
        let mut i = 0;
        environment_sampling::measure(&scenes, desc, threads, |what| {
            progress(done + i, total, what);
            i += 1;
        })?
    } else {
        Vec::new()
    };
    let occlusion_rows = if desc.occlusion {
        let done = total - desc.occlusion_steps(&scenes) - desc.light_transport_steps(&scenes);
        let mut i = 0;
        occlusion::measure(&scenes, desc, threads, |what| {
            progress(done + i, total, what);
            i += 1;
        })?
    } else {
        Vec::new()
    };
    let light_transport_rows = if desc.path_traced_frames > 0 {
        let done = total - desc.light_transport_steps(&scenes);
        let mut i = 0;
        light_transport::measure(&scenes, desc, |what| {
            progress(done + i, total, what);
            i += 1;
        })?
    } else {
        Vec::new()
    };
    progress(total, total, "done");
    Ok(Measurements {
        environment_sampling: environment_sampling_rows,
        occlusion: occlusion_rows,
        light_transport: light_transport_rows,
        storages: storage_rows,
        anti_aliasing: anti_aliasing_rows,
        rows,
        floors,
        scaling,
        scaling_scene: scaling_scene.map(|(label, _)| label).unwrap_or_default(),
        device: device_name,
        shadows: shadow_rows,
    })
}

/// Mean FLIP (the perceptual image difference of Andersson et al. 2020, `nv-flip`, at
/// its default 67 pixels per degree) between `frame`'s display image and the reference
/// radiance of `map` through the same output transform: × `exposure`, the exponential
/// tone curve, the exact sRGB encoding, rounded to 8 bits. Pixels the reference does
/// not shade carry the GPU's own values (`ErrorMap::reference_radiance`), so this is
/// the shading's (and the HDR storage's) error as a viewer would see it.
pub fn flip_against_reference(frame: &Frame, map: &ErrorMap, exposure: f32) -> f64 {
    flip_against_radiance(
        frame,
        &map.reference_radiance,
        exposure,
        ToneMapping::Exponential,
    )
}

/// Mean FLIP between `frame`'s display image and `radiance` (one value a pixel, row-major)
/// through the output transform the frame had: × `exposure`, `tone_mapping` (its f64
/// mirror), the exact sRGB encoding, rounded to 8 bits; NaN if the sizes differ.
pub fn flip_against_radiance(
    frame: &Frame,
    radiance: &[[f32; 3]],
    exposure: f32,
    tone_mapping: ToneMapping,
) -> f64 {
    let n = (frame.width * frame.height) as usize;
    if frame.ldr.len() != n || radiance.len() != n {
        return f64::NAN;
    }
    let encode =
        |p: &[f32; 3]| tone_mapping.display_codes(p.map(|c| f64::from(c) * f64::from(exposure)));
    let reference: Vec<u8> = radiance.iter().flat_map(encode).collect();
    let test: Vec<u8> = frame.ldr.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
    let flip = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(frame.width, frame.height, &reference),
        nv_flip::FlipImageRgb8::with_data(frame.width, frame.height, &test),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    f64::from(nv_flip::FlipPool::from_image(&flip).mean())
}

/// The "Metal colours" section: per built-in metal, the band method's colour against the
/// colorimetric one (ΔE*ab and per channel) and the fitted constants
/// (`combustion_spectra::metal_colour_table`), with the fit's time measured here. Their
/// GPU cost is the band constants': the same shader evaluates either.
fn metal_colours_markdown() -> String {
    let started = std::time::Instant::now();
    for metal in combustion_spectra::BuiltinMetal::ALL {
        // The table fits them again: this measures the fit alone.
        let _ = combustion_spectra::colorimetric_optical_constants(metal.spectrum());
    }
    let fit_ms = started.elapsed().as_secs_f64() * 1e3;
    let table = combustion_spectra::metal_colour_table()
        .unwrap_or_else(|e| format!("(the table could not be made: {e})\n"));
    format!(
        "## Metal colours\n\nEach built-in metal at normal incidence in air: its RGB reflectance by the band method (`--metal-colour bands`, the default) and the colour its measured spectrum shows (CIE 1931 2° observer, D65, linear sRGB), and the constants fitted to that colour (`--metal-colour colorimetric`). Per-pixel cost: the same as the band constants' (one shader evaluates either); the fit of all nine took {fit_ms:.1} ms on the CPU here, once at load.\n\n{table}\n"
    )
}

/// The f64 reference of frames of `scene` (its camera and lights) at `size`, drawn from
/// the scene itself (each pixel's ray traced in `bvh`, [`SceneBvh::new`] of `scene`),
/// stored as G-buffers of `storage` store it; a scene lit by an environment is shaded at
/// one pixel in [`ENVIRONMENT_SAMPLING`]'s stride² with its samples.
pub fn scene_reference<'a>(
    scene: &'a combustion_scene::Scene,
    bvh: &'a SceneBvh,
    size: (u32, u32),
    storage: GBufferStorage,
    threads: usize,
) -> SceneReference<'a> {
    let precision = precision_of(storage);
    if scene.environment.is_some() {
        let sampling = EnvironmentReference {
            samples: ENVIRONMENT_SAMPLING.iterations,
            stride: ENVIRONMENT_SAMPLING.stride,
        };
        SceneReference::with_environment(
            scene,
            bvh,
            &scene.lights,
            size,
            precision,
            sampling,
            threads,
        )
    } else {
        SceneReference::new(scene, bvh, &scene.lights, size, precision, threads)
    }
}

/// A frame's error against the f64 reference of the scene it shows, end to end
/// ([`frame_physics_error`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicsError {
    /// Pixels compared (both see the same material, away from silhouettes; for a scene
    /// lit by an environment, the sampled pixels among them).
    pub compared: usize,
    /// Pixels whose material differs from the reference's away from any edge (the frame
    /// shows something wrong there).
    pub wrong_surface: usize,
    /// The compared pixels' largest channel error relative to the reference radiance
    /// (mean and max).
    pub relative: crate::end_to_end::MeanMax,
    /// Mean FLIP between the frame's display image and the reference radiance through
    /// the same output transform (the frame's own values where nothing was compared);
    /// `None` for a scene lit by an environment (a sampled reference, no whole image).
    pub flip_mean: Option<f64>,
}

/// The error of `frame` (read back with its G-buffer: [`Readback::ALL`]) against the f64
/// reference of `scene` as the frame showed it (its camera, lights and pose: a scene
/// [`combustion_scene::Scene::as_drawn`] gives), drawn from the scene itself and stored
/// as `storage` stores it; the frame's display image was made with `exposure` and
/// `tone_mapping`.
pub fn frame_physics_error(
    scene: &combustion_scene::Scene,
    frame: &Frame,
    storage: GBufferStorage,
    exposure: f32,
    tone_mapping: ToneMapping,
) -> PhysicsError {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let bvh = SceneBvh::new(scene);
    let reference = scene_reference(scene, &bvh, (frame.width, frame.height), storage, threads);
    let comparison = reference.compare(frame);
    let summary = comparison.summary();
    let flip_mean = scene.environment.is_none().then(|| {
        let mut radiance: Vec<[f32; 3]> = frame.hdr.iter().map(|p| [p[0], p[1], p[2]]).collect();
        for p in &comparison.pixels {
            if let Some(pixel) = reference.pixel(p.x, p.y) {
                radiance[(p.y * frame.width + p.x) as usize] = pixel.exact.map(|c| c as f32);
            }
        }
        flip_against_radiance(frame, &radiance, exposure, tone_mapping)
    });
    PhysicsError {
        compared: summary.compared,
        wrong_surface: summary.away,
        relative: summary.total,
        flip_mean,
    }
}

/// What an accuracy budget chose for a scene ([`choose`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// The fastest set whose mean relative error is within the budget (`None`: none is).
    pub chosen: Option<VariantSet>,
    /// Every set measured, fastest first.
    pub candidates: Vec<ReportRow>,
}

/// The accuracy budget: measures every variant set on `scene` (without floors) and
/// picks the fastest whose mean relative error against the f64 reference is at most
/// `max_error`.
pub fn choose(
    scene: &SceneSource,
    max_error: f64,
    width: u32,
    height: u32,
    frames: u32,
    device: DeviceDesc,
) -> Result<Choice, Error> {
    let desc = ReportDesc::rows_only(
        vec![scene.clone()],
        VariantSet::all(),
        (width, height),
        frames,
        device,
    );
    let mut candidates = measure(&desc, |_, _, _| {})?.rows;
    candidates.sort_by(|a, b| a.total.median.total_cmp(&b.total.median));
    // A budget is met only where something was compared: a scene with no lit pixel (no
    // object in view, or emission alone) says nothing about any set's error.
    let chosen = candidates
        .iter()
        .find(|r| r.compared > 0 && r.mean_relative <= max_error)
        .map(|r| r.set);
    Ok(Choice { chosen, candidates })
}

impl Choice {
    /// Whether no set compared a single pixel with the reference (the budget then
    /// chooses nothing).
    pub fn nothing_compared(&self) -> bool {
        self.candidates.iter().all(|r| r.compared == 0)
    }
}

impl Choice {
    /// What was chosen and why: every candidate with its time and errors.
    pub fn explain(&self, max_error: f64) -> String {
        let mut out = format!(
            "accuracy budget: mean relative error ≤ {max_error:.1e} against the f64 reference\n"
        );
        for r in &self.candidates {
            let verdict = if Some(r.set) == self.chosen {
                "chosen: the fastest within the budget"
            } else if r.mean_relative <= max_error {
                "within, slower"
            } else {
                "over the budget"
            };
            let _ = writeln!(
                out,
                "  {:<38} {:>8.2} ms  mean {:.2e}  max {:.2e}  {verdict}",
                r.set.name(),
                r.total.median,
                r.mean_relative,
                r.max_relative
            );
        }
        if self.nothing_compared() {
            out += "  no pixel was compared with the reference (nothing lit in view): the budget says nothing about this scene\n";
        } else if self.chosen.is_none() {
            out += "  no variant set is within the budget\n";
        }
        out
    }
}

/// One variant set over every scene measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SetSummary {
    /// The variant set.
    pub set: VariantSet,
    /// Mean over the scenes of the total frame time's median, ms.
    pub ms: f64,
    /// Mean over the scenes of the mean relative error.
    pub mean_relative: f64,
    /// The largest max relative error of any scene.
    pub max_relative: f64,
    /// Mean over the scenes of the mean FLIP.
    pub flip_mean: f64,
}

/// Per variant set, in the order first measured: its time and errors over the scenes
/// lit by lights (the comparison variants change lights only; scenes lit by an
/// environment alone are summarised by [`environment_markdown`]), or over every scene
/// when all are lit by an environment.
pub fn summarise(rows: &[ReportRow]) -> Vec<SetSummary> {
    let lit: Vec<ReportRow> = rows.iter().filter(|r| !r.environment).cloned().collect();
    let rows = if lit.is_empty() { rows } else { &lit[..] };
    let mut sets: Vec<VariantSet> = Vec::new();
    for row in rows {
        if !sets.contains(&row.set) {
            sets.push(row.set);
        }
    }
    sets.into_iter()
        .map(|set| {
            let of: Vec<&ReportRow> = rows.iter().filter(|r| r.set == set).collect();
            let n = of.len() as f64;
            let mean_of = |f: fn(&ReportRow) -> f64| of.iter().map(|r| f(r)).sum::<f64>() / n;
            SetSummary {
                set,
                ms: mean_of(|r| r.total.median),
                mean_relative: mean_of(|r| r.mean_relative),
                max_relative: of.iter().map(|r| r.max_relative).fold(0.0, f64::max),
                // Scenes lit by an environment have no whole reference image to FLIP.
                flip_mean: {
                    let finite: Vec<f64> = of
                        .iter()
                        .map(|r| r.flip_mean)
                        .filter(|f| f.is_finite())
                        .collect();
                    finite.iter().sum::<f64>() / finite.len() as f64
                },
            }
        })
        .collect()
}

/// One plot point per variant set: its mean frame time and mean relative error.
fn points(rows: &[ReportRow]) -> Vec<SpeedErrorPoint> {
    summarise(rows)
        .iter()
        .map(|s| SpeedErrorPoint {
            label: s.set.short_name(),
            ms: s.ms,
            error: s.mean_relative,
        })
        .collect()
}

/// The CSV: one row per scene and variant set.
pub fn csv(rows: &[ReportRow]) -> String {
    let names = PassSpreads::names(rows.iter().map(|r| &r.passes));
    let mut header = columns("scene,fresnel,hdr,pipeline,masking,distribution,diffuse,frames");
    header.extend(spread_columns(&names));
    header.extend(spread_columns(&["total"]));
    header.extend(columns("max_relative_error,mean_relative_error,rms_relative_error,pixels_compared,flip_mean,end_to_end_max_relative_error,end_to_end_mean_relative_error,end_to_end_storage_mean,end_to_end_pixels_compared,through_glass_pixels,through_glass_mean_relative_error,through_glass_max_relative_error"));
    let mut out = table(header);
    for r in rows {
        // The error columns as PreviousRun::compare reads them back.
        let (_, [max, mean, rms, flip]) = csv_key_and_errors(r);
        let mut fields = vec![r.scene.clone()];
        fields.extend(r.set.name().split('/').map(str::to_owned));
        fields.push(r.frames.to_string());
        let spreads: Vec<Spread> = names.iter().map(|n| r.passes.get(n)).collect();
        fields.extend(spread_values(&spreads));
        fields.extend(spread_values(&[r.total]));
        fields.extend([max, mean, rms, r.compared.to_string(), flip]);
        match &r.end_to_end {
            Some(e) => fields.extend([
                format!("{:.3e}", e.total.max),
                format!("{:.3e}", e.total.mean),
                format!("{:.3e}", e.storage.mean),
                e.compared.to_string(),
                e.through_glass.to_string(),
                format!("{:.3e}", e.glass.mean),
                format!("{:.3e}", e.glass.max),
            ]),
            None => fields.extend(std::iter::repeat_n(String::new(), 7)),
        }
        out.row(fields);
    }
    out.finish()
}

/// The section on the frame against the scene itself, default variant set: per scene,
/// the end-to-end error and its split into the G-buffer storage's share and the rest.
pub fn end_to_end_markdown(rows: &[ReportRow]) -> String {
    let compared: Vec<(&ReportRow, &EndToEndErrors)> = rows
        .iter()
        .filter(|r| r.set == VariantSet::DEFAULT)
        .filter_map(|r| r.end_to_end.as_ref().map(|e| (r, e)))
        .collect();
    if compared.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "## End to end: the frame against the scene\n\nDefault variant set. Each pixel's primary ray cast in f64 against the scene's triangles through the camera's own description, the hit shaded from the scene's own materials, textures and lights with the optics crate (`combustion::end_to_end`, `combustion_reference::shading`): it shares no code with the GPU path, so the error is every error the renderer makes, G-buffer storage included. The reference also shades each surface as the G-buffer stores it (the default storage: 16-bit sRGB base colour and metalness, 16-bit roughness and octahedral normal), splitting the error into the storage's share and the rest (rasterisation, interpolation, texture sampling, f32 shading). Pixels at edges (silhouettes, where objects or materials meet, creases) are counted, not compared; \"wrong\" counts pixels showing another material away from any edge. tests/end_to_end.rs holds every pixel's rest to a bound derived from the formats and the Vulkan specification (docs/accuracy.md). Relative error per pixel as above. Scenes lit by an environment are compared at one pixel in 16×16 (the reference integrates the environment with 2 000 samples of each strategy; edges and wrong pixels are counted over the whole frame): their error is mostly the split sum's approximation, which no bound holds per pixel. Pixels seen through glass (transmissive surfaces) are compared apart, against the reference's light followed through the glass (`combustion_reference::transmission`): their error is the screen-space transmission's (docs/gltf.md, \"Transmission\"), measured, not bounded.\n\n| scene | pixels | at edges | wrong | error mean | max | storage's share: mean | max | the rest: mean | max | through glass: pixels | mean | max |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (r, e) in compared {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {} | {} |",
            md_cell(&r.scene),
            e.compared,
            e.silhouette,
            e.away,
            e.total.mean,
            e.total.max,
            e.storage.mean,
            e.storage.max,
            e.rest.mean,
            e.rest.max,
            e.through_glass,
            if e.through_glass > 0 {
                format!("{:.2e} | {:.2e}", e.glass.mean, e.glass.max)
            } else {
                "— | —".to_owned()
            }
        );
    }
    out + "\n"
}

/// `text` for a Markdown table cell (a line break, which would end the row, shown as
/// `\\n`).
fn md_cell(text: &str) -> String {
    text.replace('|', "\\|")
        .replace('\r', "\\r")
        .replace('\n', "\\n")
}

/// The floors' CSV: one row per scene.
pub fn floors_csv(floors: &[FloorRow]) -> String {
    let mut out = table(columns("scene,geometry_floor_ms,geometry_floor_p10,geometry_floor_p90,fetch_floor_ms,fetch_floor_p10,fetch_floor_p90,plain_ggx_ms,plain_ggx_p10,plain_ggx_p90"));
    for f in floors {
        let mut fields = vec![f.scene.clone()];
        fields.extend(spread_values(&[f.geometry, f.fetch, f.plain_ggx]));
        out.row(fields);
    }
    out.finish()
}

/// The floors and each pass of the default set ([`VariantSet::DEFAULT`]) as a multiple of
/// them, per scene.
fn floors_markdown(m: &Measurements) -> String {
    if m.floors.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "## Against the floors (same run)\n\nFloors: the G-buffer pass with a trivial fragment stage (geometry), the lighting pass that only fetches the G-buffer and writes (fetch), and a lighting pass with a plain isotropic GGX, height-correlated Smith and the full conductor Fresnel per light (plain GGX); the same scene, lights, size and frames. Passes of the default set, full/f32/specialised/correlated.\n\n| scene | geometry floor ms | G-buffer ms (× floor) | fetch floor ms | plain GGX ms | lighting ms (× fetch, × plain GGX) |\n|---|---|---|---|---|---|\n",
    );
    let default = VariantSet::DEFAULT;
    for f in &m.floors {
        let Some(r) = m
            .rows
            .iter()
            .find(|r| r.scene == f.scene && r.set == default)
        else {
            continue;
        };
        let _ = writeln!(
            out,
            "| {} | {:.2} | {:.2} (×{:.2}) | {:.2} | {:.2} | {:.2} (×{:.1}, ×{:.2}) |",
            md_cell(&f.scene),
            f.geometry.median,
            r.passes.get(PassTimings::GBUFFER).median,
            r.passes.get(PassTimings::GBUFFER).median / f.geometry.median,
            f.fetch.median,
            f.plain_ggx.median,
            r.passes.get(PassTimings::LIGHTING).median,
            r.passes.get(PassTimings::LIGHTING).median / f.fetch.median,
            r.passes.get(PassTimings::LIGHTING).median / f.plain_ggx.median
        );
    }
    out + "\n"
}

/// The scaling measurement's CSV: one row per configuration.
pub fn scaling_csv(rows: &[ScalingRow]) -> String {
    let names = PassSpreads::names(rows.iter().map(|r| &r.passes));
    let mut header = columns("width,height,localised_lights,culled");
    header.extend(spread_columns(&names));
    header.extend(spread_columns(&["total"]));
    let mut out = table(header);
    for r in rows {
        let lights = r
            .localised_lights
            .map_or("scene".to_owned(), |n| n.to_string());
        let mut fields = vec![
            r.width.to_string(),
            r.height.to_string(),
            lights,
            r.culled.to_string(),
        ];
        let spreads: Vec<Spread> = names.iter().map(|n| r.passes.get(n)).collect();
        fields.extend(spread_values(&spreads));
        fields.extend(spread_values(&[r.total]));
        out.row(fields);
    }
    out.finish()
}

/// The scaling section: frame time against size, and against localised lights.
fn scaling_markdown(m: &Measurements) -> String {
    if m.scaling.is_empty() {
        return String::new();
    }
    let mut out = format!(
        "## Scaling ({}, default variant set)\n\nFrame time against size (the scene's own lights):\n\n| size | megapixels | G-buffer ms | lighting ms | total ms | total ms per megapixel |\n|---|---|---|---|---|---|\n",
        md_cell(&m.scaling_scene)
    );
    for r in m.scaling.iter().filter(|r| r.localised_lights.is_none()) {
        let mp = f64::from(r.width) * f64::from(r.height) / 1e6;
        let _ = writeln!(
            out,
            "| {}×{} | {mp:.2} | {:.2} | {:.2} | {:.2} | {:.1} |",
            r.width,
            r.height,
            r.passes.get(PassTimings::GBUFFER).median,
            r.passes.get(PassTimings::LIGHTING).median,
            r.total.median,
            r.total.median / mp
        );
    }
    out += "\n![frame time against size](scaling-resolution.png)\n\nAgainst light count: the scene's lights replaced by N localised point lights (each with a range of a fifth of the scene's diagonal, scattered through it); lighting ms includes the culling pass. × 4 lights: the lighting pass against the same set's 4-light figure.\n\n| lights | culled lighting ms (× 4 lights) | unculled lighting ms (× 4 lights) | culled total ms | unculled total ms |\n|---|---|---|---|---|\n";
    let lighting_of = |n: usize, culled: bool| {
        m.scaling
            .iter()
            .find(|r| r.localised_lights == Some(n) && r.culled == culled)
    };
    for n in SCALING_LIGHT_COUNTS {
        let (Some(c), Some(u)) = (lighting_of(n, true), lighting_of(n, false)) else {
            continue;
        };
        let ratio = |r: &ScalingRow, culled: bool| {
            lighting_of(4, culled).map_or(f64::NAN, |four| {
                r.passes.get(PassTimings::LIGHTING).median
                    / four.passes.get(PassTimings::LIGHTING).median
            })
        };
        let _ = writeln!(
            out,
            "| {n} | {:.2} (×{:.2}) | {:.2} (×{:.2}) | {:.2} | {:.2} |",
            c.passes.get(PassTimings::LIGHTING).median,
            ratio(c, true),
            u.passes.get(PassTimings::LIGHTING).median,
            ratio(u, false),
            c.total.median,
            u.total.median
        );
    }
    out + "\n![frame time against light count](scaling-lights.png)\n\n"
}

/// The scaling plots: (size, lights) PNGs.
fn scaling_plots(m: &Measurements, device: &str) -> Result<(Png, Png), Error> {
    let series = |label: &str, f: &dyn Fn(&ScalingRow) -> Option<(f64, f64)>| Series {
        label: label.to_owned(),
        points: m.scaling.iter().filter_map(f).collect(),
    };
    let by_size = |pass: fn(&ScalingRow) -> f64| {
        move |r: &ScalingRow| {
            r.localised_lights
                .is_none()
                .then(|| (f64::from(r.width) * f64::from(r.height) / 1e6, pass(r)))
        }
    };
    let size = plot_scaling(
        "Frame time against size",
        &format!("{device}, {}; GPU medians", m.scaling_scene),
        "megapixels",
        "GPU ms (median)",
        XAxis::Linear,
        &[
            series("total", &by_size(|r| r.total.median)),
            series(
                "G-buffer",
                &by_size(|r| r.passes.get(PassTimings::GBUFFER).median),
            ),
            series(
                "lighting",
                &by_size(|r| r.passes.get(PassTimings::LIGHTING).median),
            ),
        ],
        900,
        560,
    )?;
    let by_lights = |culled: bool| {
        move |r: &ScalingRow| {
            r.localised_lights
                .filter(|_| r.culled == culled)
                .map(|n| (n as f64, r.passes.get(PassTimings::LIGHTING).median))
        }
    };
    let lights = plot_scaling(
        "Lighting pass against light count",
        &format!(
            "{device}, {}; localised point lights; GPU medians",
            m.scaling_scene
        ),
        "localised lights",
        "lighting ms (median, with culling)",
        XAxis::Log2,
        &[
            series("tiled culling", &by_lights(true)),
            series("every light per pixel", &by_lights(false)),
        ],
        900,
        560,
    )?;
    Ok((size, lights))
}

/// The Markdown report.
pub fn markdown(m: &Measurements, desc: &ReportDesc) -> String {
    let (rows, device) = (&m.rows[..], &m.device);
    if rows.is_empty() {
        // Sections without the variant sets (`bench --report-sections`).
        let out = format!(
            "# Speed against error\n\n{device}, {}×{}, GPU timestamps over {} frames after one warm-up frame per scene and setting. The variant sets were not measured in this run (`--report-sections`); the sections that were follow.\n\n",
            desc.width, desc.height, desc.frames
        );
        return out + &sections_markdown(m, desc);
    }
    let mut out = format!(
        "# Speed against error\n\n{device}, {}×{}, GPU timestamps over {} frames after one warm-up frame per scene and variant set. Error of the lighting pass: every lit pixel of one frame re-shaded in f64 from its own G-buffer with the full Fresnel equations (`combustion_renderer::reference`); relative error per pixel = largest channel |gpu − f64| / max(|f64|, 1e-4). Error of the whole frame, end to end: the same frame against the scene itself ray cast and shaded in f64 (section \"End to end\" and the per-scene table's last columns). Mean FLIP (Andersson et al. 2020, 67 pixels per degree): the display image against the reference radiance through the same exposure, tone curve and sRGB encoding.\n\nVariant sets (fresnel/hdr/pipeline/masking/distribution/diffuse): Fresnel `full` (the equations with complex η + ik and the outside medium), `schlick` (Schlick's curve through the exact normal-incidence reflectance) or `f82` (Hoffman 2019: Schlick's curve less b μ(1 − μ)⁶, through the exact reflectance at normal incidence and at cos θ = 1/7); HDR storage `f32` or `f16`; lighting pipeline `specialised` to the scene's materials or `general`; masking–shadowing `correlated` (Smith height-correlated, the reference's), `separable` (G₁·G₁) or `approximate` (Hammon 2017); normal distribution `ggx` (the reference's) or `beckmann` (with Beckmann's Smith Λ, Walter et al. 2007); diffuse `material` (each material's own model, the reference's) or one model for every material (`lambert`, `oren-nayar-qualitative`, `oren-nayar-full`). The default, each term changed alone, and every cheap choice at once.\n\n",
        desc.width, desc.height, desc.frames
    );
    let summary = summarise(rows);
    let front = pareto_front(&points(rows));
    let _ = write!(
        out,
        "Pareto front, fastest first: each set less wrong, by more than {:.0} % of the error, than the front's previous set (errors closer than that differ by rounding).\n\n",
        combustion_plots::PARETO_ERROR_TOLERANCE * 100.0
    );
    out += "## Variant sets (mean over the scenes)\n\n| variant set | in the plot | frame ms | mean relative error | largest max relative error | mean FLIP | Pareto front |\n|---|---|---|---|---|---|---|\n";
    for (i, s) in summary.iter().enumerate() {
        let _ = writeln!(
            out,
            "| {} | {} | {:.2} | {:.2e} | {:.2e} | {:.2e} | {} |",
            s.set.name(),
            s.set.short_name(),
            s.ms,
            s.mean_relative,
            s.max_relative,
            s.flip_mean,
            if front.contains(&i) { "yes" } else { "" }
        );
    }
    out += "\n![speed against error](speed-vs-error.png)\n\n";
    out += &end_to_end_markdown(rows);
    out += &environment_markdown(rows);
    out += &sections_markdown(m, desc);
    out += &metal_colours_markdown();
    out += "## Per scene\n\nErrors of the lighting pass (from the frame's own G-buffer) and, where the scene has no environment, of the frame end to end (from the scene).\n\n| scene | variant set | G-buffer ms | lighting ms (p10–p90) | output ms | total ms | max rel. error | mean | RMS | pixels | mean FLIP | end to end: mean | max |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let _ = writeln!(
            out,
            "| {} | {} | {:.2} | {:.2} ({:.2}–{:.2}) | {:.2} | {:.2} | {:.2e} | {:.2e} | {:.2e} | {} | {} | {} |",
            md_cell(&r.scene),
            r.set.name(),
            r.passes.get(PassTimings::GBUFFER).median,
            r.passes.get(PassTimings::LIGHTING).median,
            r.passes.get(PassTimings::LIGHTING).p10,
            r.passes.get(PassTimings::LIGHTING).p90,
            r.passes.get(PassTimings::OUTPUT).median,
            r.total.median,
            r.max_relative,
            r.mean_relative,
            r.rms_relative,
            r.compared,
            if r.flip_mean.is_finite() {
                format!("{:.2e}", r.flip_mean)
            } else {
                "— (environment)".into()
            },
            r.end_to_end.map_or("— | —".into(), |e| format!(
                "{:.2e} | {:.2e}",
                e.total.mean, e.total.max
            ))
        );
    }
    out
}

/// The sections after the variant sets', each empty where it was not measured.
fn sections_markdown(m: &Measurements, desc: &ReportDesc) -> String {
    [
        floors_markdown(m),
        scaling_markdown(m),
        shadows::markdown(&m.shadows),
        storage::markdown(&m.storages),
        anti_aliasing::markdown(&m.anti_aliasing),
        environment_sampling::markdown(&m.environment_sampling),
        occlusion::markdown(&m.occlusion),
        light_transport::markdown(&m.light_transport, desc.path_traced_frames),
    ]
    .concat()
}

/// The section on scenes lit by an environment: the split sum's error against the f64
/// rendering equation per scene, with the default variant set.
pub fn environment_markdown(rows: &[ReportRow]) -> String {
    let lit: Vec<&ReportRow> = rows
        .iter()
        .filter(|r| r.environment && r.set == VariantSet::DEFAULT)
        .collect();
    if lit.is_empty() {
        return String::new();
    }
    let sampling = ENVIRONMENT_SAMPLING;
    let mut out = format!(
        "## Environment lighting: the split sum against the rendering equation

Scenes lit by an environment alone, default variant set: the GPU's split sum (prefiltered radiance × each material's full-Fresnel directional albedo, irradiance × its diffuse albedo; `combustion_renderer::environment`) against the f64 rendering equation integrated by Monte Carlo at one pixel in {s}×{s} ({} samples of each strategy; `combustion_optics::environment::integrate_environment`). These rows are left out of the variant sets' means above: the comparison variants change the lights' shading, not the environment term, so their errors here are the default's.

| scene | pixels | max rel. error | mean | RMS | total ms |
|---|---|---|---|---|---|
",
        sampling.iterations,
        s = sampling.stride
    );
    for r in lit {
        let _ = writeln!(
            out,
            "| {} | {} | {:.2e} | {:.2e} | {:.2e} | {:.2} |",
            md_cell(&r.scene),
            r.compared,
            r.max_relative,
            r.mean_relative,
            r.rms_relative,
            r.total.median
        );
    }
    out + "
"
}

/// The rows of an earlier run's `report.csv` ([`csv`]): per scene and variant set (the
/// first seven columns joined), its total frame time and its error columns as written.
#[derive(Clone, Debug, PartialEq)]
pub struct PreviousRun {
    /// The CSV's path (for the report's text).
    pub path: std::path::PathBuf,
    rows: Vec<combustion_report_csv::PreviousRow>,
}

/// The key and error columns of a row as [`csv`] writes them.
fn csv_key_and_errors(r: &ReportRow) -> (String, [String; 4]) {
    let key = format!("{},{}", r.scene, r.set.name().replace('/', ","));
    let errors = [
        format!("{:.3e}", r.max_relative),
        format!("{:.3e}", r.mean_relative),
        format!("{:.3e}", r.rms_relative),
        format!("{:.3e}", r.flip_mean),
    ];
    (key, errors)
}

impl PreviousRun {
    /// Reads `dir/report.csv` of an earlier `bench --report` run.
    pub fn read(dir: &Path) -> Result<PreviousRun, Error> {
        let path = dir.join("report.csv");
        let problem = |message: String| Error::PreviousReport {
            path: path.clone(),
            message,
        };
        let text = crate::input::read_text(&path, crate::input::MAX_REPORT_BYTES, "a report's CSV")
            .map_err(problem)?;
        let rows = combustion_report_csv::PreviousReport::parse(&text)
            .map_err(|e| problem(e.to_string()))?
            .rows;
        Ok(PreviousRun { path, rows })
    }

    /// This run against the previous one: rows matched, rows whose error columns are
    /// identical, and the spread (min, median, max) of this run's total frame time over
    /// the previous run's, per matched row.
    pub fn compare(&self, rows: &[ReportRow]) -> Reproduction {
        let mut ratios = Vec::new();
        let mut identical = 0;
        for r in rows {
            let (key, errors) = csv_key_and_errors(r);
            if let Some(previous) = self.rows.iter().find(|p| p.key == key) {
                ratios.push(r.total.median / previous.total_ms);
                identical += usize::from(previous.errors == errors);
            }
        }
        ratios.sort_by(f64::total_cmp);
        Reproduction {
            previous: self.path.clone(),
            matched: ratios.len(),
            errors_identical: identical,
            total_ratio_min: ratios.first().copied().unwrap_or(f64::NAN),
            total_ratio_median: ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN),
            total_ratio_max: ratios.last().copied().unwrap_or(f64::NAN),
        }
    }
}

/// A run against an earlier one ([`PreviousRun::compare`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Reproduction {
    /// The previous run's report file.
    pub previous: std::path::PathBuf,
    /// Rows (scene × variant set) found in both runs.
    pub matched: usize,
    /// Matched rows whose max, mean, RMS relative error and mean FLIP are equal as written.
    pub errors_identical: usize,
    /// This run's total frame time over the previous run's: smallest, median, largest.
    pub total_ratio_min: f64,
    /// Median ratio.
    pub total_ratio_median: f64,
    /// Largest ratio.
    pub total_ratio_max: f64,
}

impl Reproduction {
    fn markdown(&self) -> String {
        if self.matched == 0 {
            return format!(
                "## Against a previous run

The run before this one (`{}`) has no scene × variant set row in common with this one: nothing to compare.

",
                self.previous.display()
            );
        }
        let percent = |r: f64| format!("{:+.1} %", (r - 1.0) * 100.0);
        format!(
            "## Against a previous run

The same measurement run before this one (`{}`): {} scene × variant set rows in both; their error columns (max, mean, RMS relative error, mean FLIP) are identical in {} of them; this run's total frame time against that run's, per row: {} … {} (median {}).

",
            self.previous.display(),
            self.matched,
            self.errors_identical,
            percent(self.total_ratio_min),
            percent(self.total_ratio_max),
            percent(self.total_ratio_median)
        )
    }
}

/// Writes `report.md` and each measured section's files ([`REPORT_FILES`]) into `dir`
/// (made if needed), with the comparison against a previous run if there is one, and
/// removes the files of sections this run did not measure (an earlier run's, which would
/// read as this one's). Returns the names written.
pub fn write(
    dir: &Path,
    m: &Measurements,
    desc: &ReportDesc,
    reproduction: Option<&Reproduction>,
) -> Result<Vec<&'static str>, Error> {
    let (rows, device) = (&m.rows[..], &m.device);
    output::make_folder(dir)?;
    // Every file made before any is written, then written as one set.
    let mut files: Vec<(&'static str, Vec<u8>)> = Vec::new();
    if !rows.is_empty() {
        let png = plot_speed_vs_error(
            "Speed against error",
            &format!(
                "{device}, {}×{}, {} scene(s); labels: what differs from the default; red: Pareto front",
                desc.width,
                desc.height,
                desc.scenes.len()
            ),
            "frame time, GPU ms (median)",
            combustion_plots::RELATIVE_ERROR_AXIS,
            &points(rows),
            1000,
            620,
        )?;
        files.push(("speed-vs-error.png", png.bytes));
        files.push(("report.csv", csv(rows).into_bytes()));
    }
    if !m.floors.is_empty() {
        files.push(("floors.csv", floors_csv(&m.floors).into_bytes()));
    }
    if !m.shadows.is_empty() {
        files.push(("shadows.csv", shadows::csv(&m.shadows).into_bytes()));
        let png = shadows::plot(&m.shadows, device, desc)?;
        files.push(("shadows-speed-vs-error.png", png.bytes));
    }
    if !m.storages.is_empty() {
        files.push((
            "gbuffer-storage.csv",
            storage::csv(&m.storages).into_bytes(),
        ));
    }
    if !m.anti_aliasing.is_empty() {
        files.push((
            "anti-aliasing.csv",
            anti_aliasing::csv(&m.anti_aliasing).into_bytes(),
        ));
    }
    if !m.environment_sampling.is_empty() {
        files.push((
            "environment-sampling.csv",
            environment_sampling::csv(&m.environment_sampling).into_bytes(),
        ));
    }
    if !m.occlusion.is_empty() {
        files.push(("occlusion.csv", occlusion::csv(&m.occlusion).into_bytes()));
    }
    if !m.light_transport.is_empty() {
        files.push((
            "light-transport.csv",
            light_transport::csv(&m.light_transport).into_bytes(),
        ));
    }
    if !m.scaling.is_empty() {
        let (size, lights) = scaling_plots(m, device)?;
        files.push(("scaling-resolution.png", size.bytes));
        files.push(("scaling-lights.png", lights.bytes));
        files.push(("scaling.csv", scaling_csv(&m.scaling).into_bytes()));
    }
    let mut md = markdown(m, desc);
    if let Some(r) = reproduction {
        md += &r.markdown();
    }
    files.push(("report.md", md.into_bytes()));
    debug_assert!(files.iter().all(|(name, _)| REPORT_FILES.contains(name)));
    let written: Vec<&str> = files.iter().map(|(name, _)| *name).collect();
    let files: Vec<(PathBuf, Vec<u8>)> = files
        .into_iter()
        .map(|(name, bytes)| (dir.join(name), bytes))
        .collect();
    output::write_files_atomically(&files)?;
    // An earlier report's files this one did not measure would read as this run's.
    for name in REPORT_FILES.iter().filter(|name| !written.contains(name)) {
        match std::fs::remove_file(dir.join(name)) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(Error::Output(output::OutputError::Io {
                    path: dir.join(name),
                    source: e,
                }))
            }
            _ => {}
        }
    }
    Ok(written)
}

/// Every file a report may write into its folder.
pub const REPORT_FILES: [&str; 14] = [
    "anti-aliasing.csv",
    "light-transport.csv",
    "environment-sampling.csv",
    "occlusion.csv",
    "report.md",
    "speed-vs-error.png",
    "report.csv",
    "floors.csv",
    "shadows.csv",
    "shadows-speed-vs-error.png",
    "gbuffer-storage.csv",
    "scaling-resolution.png",
    "scaling-lights.png",
    "scaling.csv",
];

/// Checks, before anything is measured, that the report can be written into `dir`:
/// every file it may write there ([`REPORT_FILES`]) by the output rule
/// (`output::check_writable`). The folder must exist (made by the caller).
pub fn check_report_folder(dir: &Path) -> Result<(), Error> {
    for name in REPORT_FILES {
        output::check_writable(&dir.join(name))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 28, defect 7: an earlier report whose `total_ms` is not a frame time — NaN,
    /// infinite, zero, negative, or beyond f64 — is refused naming the line, instead
    /// of giving "NaN %", "+inf %" or "−1543 %" ratios.
    #[test]
    fn a_previous_report_with_a_frame_time_that_is_not_one_is_refused() {
        let dir = std::env::temp_dir().join(format!("combustion-previous-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let header = csv(&[]);
        for total in ["NaN", "inf", "-inf", "0", "-3.5", "1e400", "twelve"] {
            let row = format!(
                "builtin:spheres,full,f32,specialised,correlated,ggx,material,30,{total},1,2,1e-3,1e-4,2e-4,100,0.01,5e-2,5e-3,4e-3,90,0,0,0\n"
            );
            std::fs::write(dir.join("report.csv"), format!("{header}{row}")).unwrap();
            let error = PreviousRun::read(&dir).unwrap_err().to_string();
            assert!(
                error.contains(&format!("line 2: total_ms `{total}` is not a frame time")),
                "{total}: {error}"
            );
        }
        let row = "builtin:spheres,full,f32,specialised,correlated,ggx,material,30,12.5,1,2,1e-3,1e-4,2e-4,100,0.01,5e-2,5e-3,4e-3,90,0,0,0\n";
        std::fs::write(dir.join("report.csv"), format!("{header}{row}")).unwrap();
        let previous = PreviousRun::read(&dir).unwrap();
        assert_eq!(previous.rows.len(), 1);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Issue 28, defect 7: a report written for a scene whose path holds a line break,
    /// a comma and a quote (which the writer quotes) reads back as written: it used to
    /// be read line by line ("line 2 has 1 fields").
    #[test]
    fn a_report_for_a_scene_with_a_line_break_in_its_path_reads_back() {
        let dir = std::env::temp_dir().join(format!("combustion-newline-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let header = csv(&[]);
        let scene = "my\r\nscenes,\"new\"\n/a.gltf";
        let row = format!(
            "{},full,f32,specialised,correlated,ggx,material,30,12.5,1,2,1e-3,1e-4,2e-4,100,0.01,5e-2,5e-3,4e-3,90,0,0,0\r\n",
            combustion_report_csv::field(scene)
        );
        let second = "builtin:spheres,full,f32,specialised,correlated,ggx,material,30,20,1,2,1e-3,1e-4,2e-4,100,0.01,5e-2,5e-3,4e-3,90,0,0,0";
        std::fs::write(dir.join("report.csv"), format!("{header}{row}{second}")).unwrap();
        let previous = PreviousRun::read(&dir).unwrap();
        assert_eq!(previous.rows.len(), 2);
        assert!(
            previous.rows[0].key.starts_with(&format!("{scene},full,")),
            "{:?}",
            previous.rows[0].key
        );
        assert_eq!(
            (previous.rows[0].total_ms, previous.rows[1].total_ms),
            (12.5, 20.0)
        );
        // A record broken off mid-way is named by the line it starts on.
        std::fs::write(dir.join("report.csv"), format!("{header}{row}\"x\ny\",1\n")).unwrap();
        let error = PreviousRun::read(&dir).unwrap_err().to_string();
        assert!(error.contains("line 5 has 2 fields"), "{error}");
        assert_eq!(md_cell("a|b\nc"), "a\\|b\\nc");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Issue 28, defect 7: a comparison with no row in common says so, instead of
    /// printing NaN percentages.
    #[test]
    fn a_comparison_with_no_row_in_common_says_there_is_nothing_to_compare() {
        let previous = PreviousRun {
            path: "old/report.csv".into(),
            rows: Vec::new(),
        };
        let reproduction = previous.compare(&[]);
        assert_eq!(reproduction.matched, 0);
        let md = reproduction.markdown();
        assert!(md.contains("nothing to compare"), "{md}");
        assert!(!md.contains("NaN"), "{md}");
    }
}
