//! `combustion bench --report`: the measurement on lavapipe with validation (a small
//! size and few frames: timings are not checked, only that they exist), its error
//! columns equal to the parity test's error map of the same frame, and the three files
//! written and readable.

use crate::common;

use combustion::renderer::{
    Distribution, FresnelModel, HdrFormat, Masking, PassTimings, RendererSettings, ShadingOptions,
};
use combustion::report::{ReportDesc, VariantSet};
use combustion::scene::{builtin_scene, DiffuseModel};
use combustion::vk::{DeviceDesc, DeviceSelector};
use combustion::SceneSource;

const W: u32 = 96;
const H: u32 = 64;

fn lavapipe_with_validation() -> DeviceDesc {
    DeviceDesc {
        selector: DeviceSelector::NameContains("llvmpipe".into()),
        validation: true,
        synchronization_validation: true,
        ..DeviceDesc::default()
    }
}

#[test]
fn report_measures_every_set_and_its_errors_match_the_parity_check() {
    let sets = vec![
        VariantSet::DEFAULT,
        VariantSet::with(ShadingOptions {
            fresnel: FresnelModel::Schlick,
            specialised: false,
            ..ShadingOptions::DEFAULT
        }),
        VariantSet {
            hdr: HdrFormat::Rgba16Float,
            shading: ShadingOptions {
                masking: Masking::Separable,
                ..ShadingOptions::DEFAULT
            },
        },
    ];
    let desc = ReportDesc {
        floors: true,
        scaling: Some(SceneSource::Builtin("spheres".into())),
        anti_aliasing: true,
        ..ReportDesc::rows_only(
            vec![
                SceneSource::Builtin("spheres".into()),
                SceneSource::Builtin("underwater".into()),
            ],
            sets.clone(),
            (W, H),
            3,
            lavapipe_with_validation(),
        )
    };
    let mut steps = Vec::new();
    let measured =
        combustion::report::measure(&desc, |done, total, _| steps.push((done, total))).unwrap();
    let (rows, device) = (&measured.rows, &measured.device);
    assert!(device.contains("llvmpipe"), "{device}");
    assert_eq!(rows.len(), 6);
    // Per scene: its floors, then its sets; then the scaling measurement (3 sizes, 5
    // light counts culled and not); then each scene's anti-aliasing.
    assert_eq!(steps.first(), Some(&(0, 23)));
    assert_eq!(steps.last(), Some(&(23, 23)));
    assert!(steps.windows(2).all(|w| w[1].0 == w[0].0 + 1), "{steps:?}");
    let scaling = &measured.scaling;
    assert_eq!(scaling.len(), 13);
    let sizes: Vec<(u32, u32)> = scaling[..3].iter().map(|r| (r.width, r.height)).collect();
    assert_eq!(sizes, [(48, 32), (96, 64), (144, 96)]);
    assert!(scaling[..3]
        .iter()
        .all(|r| r.localised_lights.is_none() && !r.culled));
    for (i, r) in scaling[3..].iter().enumerate() {
        assert_eq!(
            r.localised_lights,
            Some([1, 4, 16, 64, 256][i / 2]),
            "{r:?}"
        );
        assert_eq!(r.culled, i % 2 == 0, "{r:?}");
        let lighting = r.passes.get(PassTimings::LIGHTING);
        assert!(lighting.median > 0.0 && r.total.median >= lighting.median);
    }
    assert_eq!(measured.floors.len(), 2);
    for f in &measured.floors {
        assert!(
            f.geometry.median > 0.0 && f.fetch.median > 0.0 && f.plain_ggx.median > 0.0,
            "{f:?}"
        );
    }
    for row in rows {
        assert_eq!(row.frames, 3, "{row:?}");
        assert!(
            row.total.median > 0.0 && row.passes.get(PassTimings::LIGHTING).median > 0.0,
            "{row:?}"
        );
        assert!(row.total.p10 <= row.total.median && row.total.median <= row.total.p90);
        assert!(row.compared > 500, "{row:?}");
        assert!(row.mean_relative <= row.rms_relative && row.rms_relative <= row.max_relative);
        assert!(row.flip_mean.is_finite() && row.flip_mean >= 0.0, "{row:?}");
    }
    // The full equations in f32 against Schlick under water: Schlick misses the medium.
    let underwater = |set: &VariantSet| {
        rows.iter()
            .find(|r| r.scene == "builtin:underwater" && r.set == *set)
            .unwrap()
    };
    assert!(underwater(&sets[1]).mean_relative > 100.0 * underwater(&sets[0]).mean_relative);
    // ... and FLIP sees it too.
    assert!(underwater(&sets[1]).flip_mean > underwater(&sets[0]).flip_mean);
    // The separable masking term (and f16 storage) move away from the reference.
    assert!(underwater(&sets[2]).mean_relative > underwater(&sets[0]).mean_relative);
    // End to end (the frame against the scene itself), every row: pixels compared,
    // nothing wrong away from silhouettes; the default's error is mostly the G-buffer
    // storage's share (8-bit sRGB base colour), far below Schlick's under water.
    for row in rows {
        let e = row.end_to_end.expect("no environment: compared end to end");
        // At 96×64 the spheres' edges are most of them: at least 1 % of the frame.
        assert!(
            e.compared * 100 >= (W * H) as usize && e.away == 0,
            "{row:?}"
        );
        assert!(
            e.total.mean <= e.total.max && e.storage.mean <= e.storage.max,
            "{e:?}"
        );
    }
    let default_e2e = underwater(&sets[0]).end_to_end.unwrap();
    assert!(
        default_e2e.rest.mean < 0.1 * default_e2e.storage.mean,
        "{default_e2e:?}"
    );
    assert!(underwater(&sets[1]).end_to_end.unwrap().total.mean > 100.0 * default_e2e.total.mean);

    // The error columns are the parity check's error map of the same frame.
    let settings = RendererSettings {
        hdr_format: HdrFormat::Rgba32Float,
        ..RendererSettings::default()
    };
    let (_, map) =
        common::render_with_error_map(&builtin_scene("spheres").unwrap(), W, H, settings, 1);
    let row = rows
        .iter()
        .find(|r| r.scene == "builtin:spheres" && r.set == sets[0])
        .unwrap();
    // Max and count exactly; the mean up to the order of the sum (threads).
    assert_eq!(
        (row.max_relative, row.compared),
        (map.max_relative, map.lit_pixels)
    );
    assert!((row.mean_relative - map.mean_relative).abs() <= 1e-12 * map.mean_relative);

    let dir = std::env::temp_dir().join(format!("combustion-report-{}", std::process::id()));
    combustion::report::write(&dir, &measured, &desc, None).unwrap();
    // A run compared with itself: every row matched, every error column identical,
    // every time ratio exactly 1.
    let itself = combustion::report::PreviousRun::read(&dir)
        .unwrap()
        .compare(&measured.rows);
    assert_eq!(
        (itself.matched, itself.errors_identical),
        (rows.len(), rows.len())
    );
    // Times are written with 3 decimals (±0.0005 ms), so the ratio is 1 within that
    // rounding over the shortest frame.
    let shortest = rows.iter().map(|r| r.total.median).fold(f64::MAX, f64::min);
    for ratio in [itself.total_ratio_min, itself.total_ratio_max] {
        assert!((ratio - 1.0).abs() <= 0.0005 / shortest, "{itself:?}");
    }
    let missing = combustion::report::PreviousRun::read(&dir.join("nowhere")).unwrap_err();
    assert!(
        missing.to_string().starts_with("previous report `"),
        "{missing}"
    );
    let floors = std::fs::read_to_string(dir.join("floors.csv")).unwrap();
    assert_eq!(floors.lines().count(), 3, "{floors}");
    let csv = std::fs::read_to_string(dir.join("report.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + rows.len());
    assert!(csv.lines().all(|l| l.split(',').count() == 32), "{csv}");
    let scaling_csv = std::fs::read_to_string(dir.join("scaling.csv")).unwrap();
    assert_eq!(scaling_csv.lines().count(), 14, "{scaling_csv}");
    // Anti-aliasing: each method on each scene against its 4×4-supersampled frame.
    let aa = &measured.anti_aliasing;
    assert_eq!(
        aa.len(),
        2 * combustion::report::anti_aliasing::Method::ALL.len()
    );
    for r in aa {
        assert!(r.flip_mean.is_finite() && r.flip_mean >= 0.0, "{r:?}");
        assert!(r.total.median > 0.0 && r.output.median > 0.0, "{r:?}");
    }
    for scene in ["builtin:spheres", "builtin:underwater"] {
        let flip = |name: &str| {
            aa.iter()
                .find(|r| r.scene == scene && r.method.name() == name)
                .unwrap()
                .flip_mean
        };
        assert!(
            flip("supersample 3x3") < flip("supersample 2x2")
                && flip("supersample 2x2") < flip("none"),
            "{aa:?}"
        );
        // Temporal anti-aliasing's sixteen still frames come nearer than one.
        assert!(flip("temporal") < flip("none"), "{aa:?}");
    }
    let aa_csv = std::fs::read_to_string(dir.join("anti-aliasing.csv")).unwrap();
    assert_eq!(aa_csv.lines().count(), 1 + aa.len(), "{aa_csv}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("## Anti-aliasing"), "{md}");
    for set in &sets {
        assert!(md.contains(&format!("| {} |", set.name())), "{md}");
    }
    assert!(md.contains("| yes |"), "a Pareto front is marked");
    assert!(md.contains("| builtin:spheres | "), "{md}");
    assert!(md.contains("## Against the floors"), "{md}");
    assert!(
        md.contains("## End to end: the frame against the scene"),
        "{md}"
    );
    assert!(md.contains("## Scaling (builtin:spheres"), "{md}");
    for (file, size) in [
        ("speed-vs-error.png", (1000, 620)),
        ("scaling-resolution.png", (900, 560)),
        ("scaling-lights.png", (900, 560)),
    ] {
        let plot = std::fs::File::open(dir.join(file)).unwrap();
        let reader = png::Decoder::new(std::io::BufReader::new(plot))
            .read_info()
            .unwrap();
        assert_eq!((reader.info().width, reader.info().height), size, "{file}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// The comparison variants of each term, measured against the f64 reference on the same
/// G-buffer: Hoffman's F82 is closer than Schlick's curve on metals (it passes through a
/// second exact point, as the optics crate's f64 test shows per angle); a diffuse model
/// forced on every material moves the error of a scene with three models by orders of
/// magnitude and changes nothing on a scene whose materials all use it already;
/// Beckmann's D is a different model (its error is far above rounding) and stays finite.
#[test]
fn comparison_variants_move_the_error_as_their_physics_says() {
    let d = VariantSet::DEFAULT;
    let o = ShadingOptions::DEFAULT;
    let f82 = VariantSet::with(ShadingOptions {
        fresnel: FresnelModel::F82,
        ..o
    });
    let schlick = VariantSet::with(ShadingOptions {
        fresnel: FresnelModel::Schlick,
        ..o
    });
    let beckmann = VariantSet::with(ShadingOptions {
        distribution: Distribution::Beckmann,
        ..o
    });
    let overrides = [
        DiffuseModel::Lambert,
        DiffuseModel::OrenNayarQualitative,
        DiffuseModel::OrenNayarFull,
    ]
    .map(|model| {
        VariantSet::with(ShadingOptions {
            diffuse_override: Some(model),
            ..o
        })
    });
    let mut sets = vec![d, f82, schlick, beckmann];
    sets.extend(overrides);
    let desc = ReportDesc::rows_only(
        ["gold-copper", "diffuse-models", "spheres"]
            .map(|s| SceneSource::Builtin(s.into()))
            .to_vec(),
        sets,
        (W, H),
        1,
        lavapipe_with_validation(),
    );
    let rows = combustion::report::measure(&desc, |_, _, _| {})
        .unwrap()
        .rows;
    let row = |scene: &str, set: VariantSet| {
        rows.iter()
            .find(|r| r.scene == format!("builtin:{scene}") && r.set == set)
            .unwrap()
    };
    for r in &rows {
        eprintln!(
            "{} {}: mean {:.3e} max {:.3e} FLIP {:.3e}",
            r.scene,
            r.set.name(),
            r.mean_relative,
            r.max_relative,
            r.flip_mean
        );
    }
    let (g_f82, g_schlick) = (row("gold-copper", f82), row("gold-copper", schlick));
    assert!(g_f82.mean_relative < g_schlick.mean_relative);
    assert!(g_f82.max_relative < g_schlick.max_relative);

    let base = row("diffuse-models", d);
    for set in overrides {
        let r = row("diffuse-models", set);
        assert!(
            r.mean_relative > 100.0 * base.mean_relative,
            "{}",
            set.name()
        );
        assert_eq!(r.compared, base.compared);
    }
    let spheres = row("spheres", d);
    let lambert = row("spheres", overrides[0]);
    assert_eq!(
        (
            lambert.max_relative,
            lambert.mean_relative,
            lambert.compared
        ),
        (
            spheres.max_relative,
            spheres.mean_relative,
            spheres.compared
        )
    );

    let b = row("spheres", beckmann);
    assert!(b.mean_relative > 100.0 * spheres.mean_relative);
    assert!(b.mean_relative.is_finite() && b.max_relative.is_finite());
    assert_eq!(
        b.compared, spheres.compared,
        "no pixel is lost to a non-finite value"
    );
}

/// A scene lit by an environment is measured against the f64 rendering equation on a
/// grid of pixels (`report::ENVIRONMENT_SAMPLING`): the split sum's error is in the
/// report beside the other variants', and its mean-FLIP cell says why it is empty.
#[test]
fn the_split_sum_error_is_in_the_report() {
    let desc = ReportDesc::rows_only(
        vec![SceneSource::Builtin("spheres-studio".into())],
        vec![VariantSet::DEFAULT],
        (320, 192),
        1,
        lavapipe_with_validation(),
    );
    let measured = combustion::report::measure(&desc, |_, _, _| {}).unwrap();
    let md = combustion::report::markdown(&measured, &desc);
    let row = &measured.rows[0];
    eprintln!(
        "spheres-studio: {} pixels, mean {:.3e}, max {:.3e}",
        row.compared, row.mean_relative, row.max_relative
    );
    let stride = combustion::report::ENVIRONMENT_SAMPLING.stride;
    // Lit pixels on the grid only: fewer than one per stride² block.
    assert!(row.compared > 20 && row.compared <= ((320 / stride) * (192 / stride)) as usize);
    // The split sum's error (tests/environment.rs: mean 8.5 %), not the missing
    // environment's (the reference without it would be ~100 % off).
    assert!(
        row.mean_relative > 1e-3 && row.mean_relative < 0.15,
        "{}",
        row.mean_relative
    );
    assert!(row.flip_mean.is_nan() && row.environment);
    // End to end on the same grid: the scene's own reference integrating the
    // environment; the error is the split sum's, no pixel shows another material.
    let e = row.end_to_end.expect("compared end to end");
    assert!(e.compared > 20 && e.compared <= ((320 / stride) * (192 / stride)) as usize);
    assert_eq!(e.away, 0);
    assert!(e.total.mean > 1e-3 && e.total.mean < 0.15, "{:?}", e.total);
    assert!(
        md.contains("## Environment lighting: the split sum against the rendering equation"),
        "{md}"
    );
    assert!(md.contains("— (environment)"), "{md}");
}

/// The report's shadow section on grid-sun: each setting is measured (frame times with a
/// static and a moving camera, the shadow-map pass timed only where shadows are on), and
/// against exact visibility shadows are less wrong than none: fewer misclassified pixels
/// and a lower mean error; the ray-traced shadows' row (ray queries) fewer than the maps'.
/// Written as shadows.csv and a section of report.md.
#[test]
fn report_measures_shadows_against_exact_visibility() {
    use combustion::report::shadows::SHADOW_SETTINGS;
    let desc = ReportDesc {
        shadows: SHADOW_SETTINGS[..2].to_vec(),
        ..ReportDesc::rows_only(
            vec![SceneSource::Builtin("grid-sun".into())],
            vec![VariantSet::DEFAULT],
            (192, 128),
            2,
            lavapipe_with_validation(),
        )
    };
    let measured = combustion::report::measure(&desc, |_, _, _| {}).unwrap();
    let rows = &measured.shadows;
    // The maps' two settings, then the ray-traced shadows (lavapipe has ray queries).
    assert_eq!(rows.len(), 3);
    let (off, on, traced) = (&rows[0], &rows[1], &rows[2]);
    assert!(traced.traced && traced.settings.is_none());
    assert_eq!(traced.compared, on.compared);
    assert!(
        traced.misclassified() < on.misclassified(),
        "ray-traced {} misclassified, maps {}",
        traced.misclassified(),
        on.misclassified()
    );
    assert!(traced.maps.median > 0.0, "the rays' pass is timed");
    assert!(off.settings.is_none() && on.settings.is_some());
    assert!(off.compared > 0 && off.compared == on.compared);
    // Without shadows every exactly shadowed pixel is lit: a large share of the floor.
    assert!(
        on.misclassified() * 10 < off.misclassified(),
        "with shadows {} misclassified, without {}",
        on.misclassified(),
        off.misclassified()
    );
    // Without shadows the only mistakes are shadowed pixels left lit.
    assert_eq!(off.shadowed_should_be_lit, 0);
    assert!(off.edge_error.0 > 0.0 && off.edge_error.1 >= off.edge_error.0);
    assert!(on.mean_relative < off.mean_relative);
    assert!(on.maps.median > 0.0 && off.maps.median.is_nan());
    assert!(on.static_total.median > 0.0 && on.moving_total.median > 0.0);
    let dir = std::env::temp_dir().join(format!("combustion-shadow-report-{}", std::process::id()));
    combustion::report::write(&dir, &measured, &desc, None).unwrap();
    let csv = std::fs::read_to_string(dir.join("shadows.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    assert!(
        csv.lines().nth(2).unwrap().contains(",hard-4x2048-1024,"),
        "{csv}"
    );
    assert!(
        csv.lines().nth(3).unwrap().contains(",ray-traced,"),
        "{csv}"
    );
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("## Shadows"), "{md}");
    // The settings' own speed-against-error plot and front: the least wrong setting is on
    // the front whatever the timings — the ray-traced shadows, fewer misclassified than
    // the maps (asserted above); whether the maps or "off" are too depends on their being
    // faster, which a tiny frame on a shared machine does not promise (at 192×128 the
    // traced frame can be the faster).
    assert!(dir.join("shadows-speed-vs-error.png").is_file());
    let row = |name: &str| {
        md.lines()
            .find(|l| l.starts_with(&format!("| {name} |")))
            .unwrap_or_else(|| panic!("no {name} row in {md}"))
    };
    assert!(row("ray-traced").ends_with("| yes |"), "{md}");
    row("off");
    row("hard-4x2048-1024");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The report's G-buffer storage section on spot-box (a Lambert floor under a spot
/// light): every storage measured, one row each, the default first; end to end, the
/// 16-bit sRGB and f16 base colours are less wrong than 8-bit sRGB (whose floor is
/// 1.12e-3 low), the 8-bit normal more wrong than the 16-bit one; no pixel shows another
/// material away from an edge. Written as
/// gbuffer-storage.csv and a section of report.md.
#[test]
fn report_measures_every_gbuffer_storage_end_to_end() {
    use combustion::renderer::{BaseColorStorage, GBufferStorage, SurfaceStorage};
    use combustion::report::storage::all_storages;
    let desc = ReportDesc {
        storages: all_storages(),
        ..ReportDesc::rows_only(
            vec![SceneSource::Builtin("spot-box".into())],
            vec![VariantSet::DEFAULT],
            (160, 120),
            2,
            lavapipe_with_validation(),
        )
    };
    let measured = combustion::report::measure(&desc, |_, _, _| {}).unwrap();
    let rows = &measured.storages;
    assert_eq!(rows.len(), 6);
    let error = |base_color, surface| {
        let row = rows
            .iter()
            .find(|r| {
                r.storage
                    == GBufferStorage {
                        base_color,
                        surface,
                    }
            })
            .unwrap();
        assert!(row.errors.compared > 0 && row.total.median > 0.0 && row.gbuffer.median > 0.0);
        assert_eq!(row.errors.away, 0, "{:?}", row.storage);
        row.errors.total.mean
    };
    assert_eq!(rows[0].storage, GBufferStorage::DEFAULT);
    let eight_bit = error(BaseColorStorage::Srgb8, SurfaceStorage::Unorm16);
    assert!(error(BaseColorStorage::Srgb16, SurfaceStorage::Unorm16) < 0.1 * eight_bit);
    assert!(error(BaseColorStorage::LinearHalf, SurfaceStorage::Unorm16) < 0.5 * eight_bit);
    assert!(error(BaseColorStorage::Srgb8, SurfaceStorage::Unorm8) > eight_bit);
    let dir =
        std::env::temp_dir().join(format!("combustion-storage-report-{}", std::process::id()));
    combustion::report::write(&dir, &measured, &desc, None).unwrap();
    let csv = std::fs::read_to_string(dir.join("gbuffer-storage.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7, "{csv}");
    assert!(
        csv.lines()
            .nth(1)
            .unwrap()
            .starts_with("builtin:spot-box,srgb16+unorm16,24,"),
        "{csv}"
    );
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("## G-buffer storage"), "{md}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The sampled-environment section: on a scene lit by an environment alone, the split
/// sum, each sample count, and frames of successive seeds averaged, each against the
/// finer oracle with its own noise beside; the sampled mode's error falls as its samples
/// grow, past the split sum's (its convergence to under 1 % is tests/environment.rs's);
/// a scene without an environment has no rows.
#[test]
fn report_measures_the_sampled_environment_against_the_split_sum() {
    use combustion::report::environment_sampling::{self, Mode};
    let desc = ReportDesc {
        environment_sampling: true,
        studio_scenes: vec![SceneSource::File(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("assets/scenes/textured/textured.gltf"),
        )],
        ..ReportDesc::rows_only(
            ["spheres-studio", "spheres"]
                .map(|s| SceneSource::Builtin(s.into()))
                .to_vec(),
            vec![VariantSet::DEFAULT],
            (320, 192),
            2,
            lavapipe_with_validation(),
        )
    };
    let mut steps = Vec::new();
    let measured =
        combustion::report::measure(&desc, |done, total, _| steps.push((done, total))).unwrap();
    // Three scenes in one set (the textured glTF scene last, lit by the studio
    // environment), then a sampled-environment step for each lit scene.
    assert_eq!(steps.last(), Some(&(5, 5)), "{steps:?}");
    let textured = measured
        .rows
        .iter()
        .find(|r| r.scene.ends_with("textured.gltf (studio)"))
        .expect("the textured scene's row");
    eprintln!(
        "textured glTF under studio: {} pixels, mean {:.3e}",
        textured.compared, textured.mean_relative
    );
    assert!(
        textured.environment && textured.compared > 50,
        "{textured:?}"
    );
    assert!(textured.mean_relative.is_finite(), "{textured:?}");
    assert_eq!(
        measured.environment_sampling.len(),
        2 * Mode::all().len(),
        "the textured scene is lit by an environment too"
    );
    let rows: Vec<_> = measured
        .environment_sampling
        .iter()
        .filter(|r| r.scene == "builtin:spheres-studio")
        .cloned()
        .collect();
    let rows = &rows;
    assert_eq!(rows.iter().map(|r| r.mode).collect::<Vec<_>>(), Mode::all());
    for r in rows {
        eprintln!(
            "{} {} ({} samples): {} pixels, mean {:.3e}, median {:.3e}, max {:.3e}, oracle σ {:.1e}, lighting {:.2} ms",
            r.scene,
            r.mode.name(),
            r.mode.samples(),
            r.compared,
            r.mean_relative,
            r.median_relative,
            r.max_relative,
            r.oracle_sigma_mean,
            r.lighting.median
        );
        assert!(r.compared >= 15, "{r:?}");
        assert!(r.median_relative <= r.max_relative && r.mean_relative <= r.max_relative);
        assert!(
            r.oracle_sigma_mean > 0.0 && r.oracle_sigma_mean < 0.01,
            "{r:?}"
        );
        assert!(r.lighting.median > 0.0 && r.total.median >= r.lighting.median);
    }
    let mean = |mode: Mode| rows.iter().find(|r| r.mode == mode).unwrap().mean_relative;
    let counts = environment_sampling::SAMPLE_COUNTS;
    assert!(
        counts
            .windows(2)
            .all(|w| mean(Mode::Sampled(w[1])) < mean(Mode::Sampled(w[0]))),
        "{rows:?}"
    );
    assert!(mean(Mode::Sampled(256)) < mean(Mode::SplitSum), "{rows:?}");
    let (frames, samples) = environment_sampling::ACCUMULATED;
    assert!(
        mean(Mode::Accumulated { frames, samples }) < mean(Mode::Sampled(samples)),
        "{rows:?}"
    );
    let csv = environment_sampling::csv(&measured.environment_sampling);
    let written = measured.environment_sampling.len();
    assert_eq!(csv.lines().count(), 1 + written, "{csv}");
    assert!(csv.lines().all(|l| l.split(',').count() == 11), "{csv}");
    let md = environment_sampling::markdown(rows);
    assert!(
        md.contains("| builtin:spheres-studio | accumulated | 1024 |"),
        "{md}"
    );
}

/// The report's occlusion section on builtin:resting: no occlusion, the screen-space
/// pass and the traced pass (lavapipe has ray queries), each against the reference with
/// the environment's visibility: the traced frame least wrong, the screen-space one next
/// (measured at 160×96: 2.2e-2, 8.8e-2 and 0.36 mean), the passes timed. Written as occlusion.csv and a section of report.md.
#[test]
fn report_measures_environment_occlusion_against_the_reference() {
    let desc = ReportDesc {
        occlusion: true,
        ..ReportDesc::rows_only(
            vec![SceneSource::Builtin("resting".into())],
            vec![VariantSet::DEFAULT],
            (160, 96),
            2,
            lavapipe_with_validation(),
        )
    };
    let measured = combustion::report::measure(&desc, |_, _, _| {}).unwrap();
    let rows = &measured.occlusion;
    let methods: Vec<&str> = rows.iter().map(|r| r.method).collect();
    assert_eq!(methods, ["none", "screen-space", "ray-traced"]);
    for r in rows {
        eprintln!(
            "{}: mean relative error {:.3e}, p95 {:.3e}, frame {:.2} ms, pass {:.2} ms",
            r.method, r.mean_relative, r.p95_relative, r.total.median, r.pass.median
        );
        assert!(r.compared > 20, "{r:?}");
    }
    let (none, screen, traced) = (&rows[0], &rows[1], &rows[2]);
    assert!(
        traced.mean_relative < screen.mean_relative && screen.mean_relative < none.mean_relative,
        "traced {:.3e}, screen-space {:.3e}, none {:.3e}",
        traced.mean_relative,
        screen.mean_relative,
        none.mean_relative
    );
    assert!(none.pass.median.is_nan() && traced.pass.median > 0.0);
    let dir = std::env::temp_dir().join(format!(
        "combustion-occlusion-report-{}",
        std::process::id()
    ));
    combustion::report::write(&dir, &measured, &desc, None).unwrap();
    let csv = std::fs::read_to_string(dir.join("occlusion.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("## Environment occlusion"), "{md}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The light-transport section: each real-time setting against the path-traced frame.
/// Under the studio, builtin:resting's frame with ray-traced occlusion is nearer light
/// that bounces than the frame without (RMS error with the reference's noise removed at
/// most half: the environment blocked as the paths find it blocked); the closed box's
/// real-time frame misses the lamp's light and every bounce: more than half darker.
#[test]
fn report_measures_the_real_time_frame_against_light_that_bounces() {
    let desc = ReportDesc {
        path_traced_frames: 16,
        ..ReportDesc::rows_only(
            vec![
                SceneSource::Builtin("resting".into()),
                SceneSource::Builtin("cornell-box".into()),
            ],
            vec![VariantSet::DEFAULT],
            (96, 54),
            2,
            lavapipe_with_validation(),
        )
    };
    let measured = combustion::report::measure(&desc, |_, _, _| {}).unwrap();
    let rows = &measured.light_transport;
    for r in rows {
        eprintln!(
            "{} {}: mean relative error {:.3e}, p95 {:.3e}, RMS noise removed {:.3e}, mean radiance {:+.4}, reference noise {:.3e}, frame {:.2} ms, {} pixels",
            r.scene, r.setting, r.mean_relative, r.p95_relative, r.rms_relative, r.mean_radiance, r.reference_noise, r.total.median, r.compared
        );
        assert!(r.compared > 1000, "{r:?}");
        assert!(r.mean_relative.is_finite() && r.total.median > 0.0, "{r:?}");
    }
    let settings: Vec<(&str, &str)> = rows.iter().map(|r| (r.scene.as_str(), r.setting)).collect();
    assert_eq!(
        settings,
        [
            ("builtin:resting", "default"),
            ("builtin:resting", "ray-traced occlusion"),
            ("builtin:resting", "ray-traced reflections"),
            ("builtin:resting", "path traced (1 frame)"),
            ("builtin:cornell-box", "default"),
            ("builtin:cornell-box", "ray-traced shadows"),
            ("builtin:cornell-box", "path traced (1 frame)"),
        ]
    );
    assert!(
        rows[1].rms_relative < 0.5 * rows[0].rms_relative,
        "occluded {:.3e} against {:.3e}",
        rows[1].rms_relative,
        rows[0].rms_relative
    );
    // builtin:resting has no smooth surface: its reflections are the split sum's.
    assert_eq!(
        rows[2].mean_relative, rows[0].mean_relative,
        "{:?}",
        rows[2]
    );
    // The real-time box misses the lamp's light and every bounce: far darker.
    assert!(rows[4].mean_radiance < -0.5, "{:?}", rows[4]);
    let dir = std::env::temp_dir().join(format!(
        "combustion-light-transport-report-{}",
        std::process::id()
    ));
    combustion::report::write(&dir, &measured, &desc, None).unwrap();
    let csv = std::fs::read_to_string(dir.join("light-transport.csv")).unwrap();
    assert_eq!(csv.lines().count(), 8, "{csv}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("## Against light that bounces"), "{md}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `bench --report-sections`: only the sections asked are measured and written, and the
/// files of an earlier run's other sections are removed from the folder (they would read
/// as this run's): here the light-transport section alone, over an earlier report's
/// report.csv and environment-sampling.csv.
#[test]
fn report_sections_measure_and_write_only_what_is_asked() {
    let dir =
        std::env::temp_dir().join(format!("combustion-report-sections-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for earlier in ["report.csv", "environment-sampling.csv"] {
        std::fs::write(dir.join(earlier), "an earlier run's\n").unwrap();
    }
    let (code, stdout, stderr) = common::combustion(&[
        "bench",
        "--report",
        dir.to_str().unwrap(),
        "--scene",
        "builtin:cornell-box",
        "--report-sections",
        "light-transport",
        "--path-traced-frames",
        "2",
        "--width",
        "48",
        "--height",
        "27",
        "--frames",
        "2",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(files, ["light-transport.csv", "report.md"], "{stdout}");
    assert!(
        stdout.contains("light-transport.csv") && stdout.contains("light-transport in"),
        "{stdout}"
    );
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("## Against light that bounces"), "{md}");
    assert!(!md.contains("## Variant sets"), "{md}");
    // The default frame, ray-traced shadows and one path-traced frame.
    let csv = std::fs::read_to_string(dir.join("light-transport.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    std::fs::remove_dir_all(&dir).unwrap();
}
