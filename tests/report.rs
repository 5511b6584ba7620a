//! `combustion bench --report`: the measurement on lavapipe with validation (a small
//! size and few frames: timings are not checked, only that they exist), its error
//! columns equal to the parity test's error map of the same frame, and the three files
//! written and readable.

mod common;

use combustion::renderer::{FresnelModel, HdrFormat, Masking, RendererSettings};
use combustion::report::{ReportDesc, VariantSet};
use combustion::scene::builtin_scene;
use combustion::vk::{DeviceDesc, DeviceSelector};
use combustion::SceneSource;

const W: u32 = 96;
const H: u32 = 64;

#[test]
fn report_measures_every_set_and_its_errors_match_the_parity_check() {
    let sets = vec![
        VariantSet::DEFAULT,
        VariantSet {
            fresnel: FresnelModel::Schlick,
            specialised: false,
            ..VariantSet::DEFAULT
        },
        VariantSet {
            hdr: HdrFormat::Rgba16Float,
            masking: Masking::Separable,
            ..VariantSet::DEFAULT
        },
    ];
    let desc = ReportDesc {
        scenes: vec![
            SceneSource::Builtin("spheres".into()),
            SceneSource::Builtin("underwater".into()),
        ],
        sets: sets.clone(),
        width: W,
        height: H,
        frames: 3,
        device: DeviceDesc {
            selector: DeviceSelector::NameContains("llvmpipe".into()),
            validation: true,
            synchronization_validation: true,
            ..DeviceDesc::default()
        },
        floors: true,
    };
    let mut steps = Vec::new();
    let measured =
        combustion::report::measure(&desc, |done, total, _| steps.push((done, total))).unwrap();
    let (rows, device) = (&measured.rows, &measured.device);
    assert!(device.contains("llvmpipe"), "{device}");
    assert_eq!(rows.len(), 6);
    // Per scene: its floors, then its sets.
    assert_eq!(steps.first(), Some(&(0, 8)));
    assert_eq!(steps.last(), Some(&(8, 8)));
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
            row.total.median > 0.0 && row.lighting.median > 0.0,
            "{row:?}"
        );
        assert!(row.total.p10 <= row.total.median && row.total.median <= row.total.p90);
        assert!(row.compared > 500, "{row:?}");
        assert!(row.mean_relative <= row.rms_relative && row.rms_relative <= row.max_relative);
    }
    // The full equations in f32 against Schlick under water: Schlick misses the medium.
    let underwater = |set: &VariantSet| {
        rows.iter()
            .find(|r| r.scene == "builtin:underwater" && r.set == *set)
            .unwrap()
    };
    assert!(underwater(&sets[1]).mean_relative > 100.0 * underwater(&sets[0]).mean_relative);
    // The separable masking term (and f16 storage) move away from the reference.
    assert!(underwater(&sets[2]).mean_relative > underwater(&sets[0]).mean_relative);

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
    combustion::report::write(&dir, &measured, &desc).unwrap();
    let floors = std::fs::read_to_string(dir.join("floors.csv")).unwrap();
    assert_eq!(floors.lines().count(), 3, "{floors}");
    let csv = std::fs::read_to_string(dir.join("report.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + rows.len());
    assert!(csv.lines().all(|l| l.split(',').count() == 22), "{csv}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for set in &sets {
        assert!(md.contains(&format!("| {} |", set.name())), "{md}");
    }
    assert!(md.contains("| yes |"), "a Pareto front is marked");
    assert!(md.contains("| builtin:spheres | "), "{md}");
    assert!(md.contains("## Against the floors"), "{md}");
    let plot = std::fs::File::open(dir.join("speed-vs-error.png")).unwrap();
    let reader = png::Decoder::new(std::io::BufReader::new(plot))
        .read_info()
        .unwrap();
    assert_eq!((reader.info().width, reader.info().height), (1000, 620));
    std::fs::remove_dir_all(dir).unwrap();
}
