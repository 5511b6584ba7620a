//! Shared helpers of the integration tests: a lavapipe device with validation on, golden
//! image comparison with FLIP, and scene pixel bookkeeping.
#![allow(dead_code)]

use std::path::PathBuf;

use combustion::renderer::{Frame, Readback, RendererSettings};
use combustion::scene::Scene;
use combustion::vk::{DeviceDesc, DeviceSelector, ValidationLog};
use combustion::{Headless, HeadlessDesc};

/// Tests always run on lavapipe (Mesa's CPU Vulkan driver), whatever else is installed,
/// so results don't depend on the machine's GPU. Validation is always on.
pub fn lavapipe(settings: RendererSettings) -> Headless {
    Headless::new(&HeadlessDesc {
        device: DeviceDesc {
            selector: DeviceSelector::NameContains("llvmpipe".into()),
            validation: true,
        },
        settings,
    })
    .expect("lavapipe with validation (install mesa-vulkan-drivers and vulkan-validationlayers: bash scripts/dev.sh test does)")
}

/// Drops `headless` (destroying the device, which makes the layer report leaks) and
/// fails if the validation layer said anything at all.
pub fn finish(headless: Headless) {
    let log: ValidationLog = headless.validation_log();
    drop(headless);
    let messages = log.messages();
    assert!(
        messages.is_empty(),
        "validation layer reported {} message(s):\n{}",
        messages.len(),
        messages.join("\n")
    );
}

/// Renders `scene` on lavapipe with validation and the given readback; checks validation.
pub fn render(
    scene: &Scene,
    width: u32,
    height: u32,
    settings: RendererSettings,
    readback: Readback,
) -> Frame {
    let mut headless = lavapipe(settings);
    let frame = {
        let renderer = headless.renderer();
        let gpu_scene = renderer.upload(scene).expect("upload");
        renderer
            .render(&gpu_scene, width, height, readback)
            .expect("render")
    };
    finish(headless);
    frame
}

pub fn goldens_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/goldens")
}

pub fn read_png(path: &std::path::Path) -> (u32, u32, Vec<[u8; 4]>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().expect("png header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("png data");
    assert_eq!(info.color_type, png::ColorType::Rgba, "{}", path.display());
    let pixels = buf[..info.buffer_size()]
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect();
    (info.width, info.height, pixels)
}

/// Compares the frame's display image with `tests/goldens/NAME.png` using FLIP and fails
/// when the mean FLIP error exceeds `max_mean_flip`. On failure writes
/// `NAME-actual.png` and `NAME-difference.png` (gitignored) beside the golden and names them.
///
/// To update goldens on purpose: `COMBUSTION_BLESS=1 cargo test --test images`, then check
/// the new images independently (see tests/goldens/README.md) before committing.
pub fn compare_with_golden(name: &str, frame: &Frame, max_mean_flip: f32) {
    let golden = goldens_dir().join(format!("{name}.png"));
    if std::env::var_os("COMBUSTION_BLESS").is_some() {
        combustion::output::write_png(&golden, frame.width, frame.height, &frame.ldr).unwrap();
        eprintln!(
            "blessed {}: check it independently before committing",
            golden.display()
        );
        return;
    }
    let (w, h, expected) = read_png(&golden);
    assert_eq!((w, h), (frame.width, frame.height), "golden size of {name}");
    let rgb = |pixels: &[[u8; 4]]| {
        pixels
            .iter()
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect::<Vec<u8>>()
    };
    let reference = nv_flip::FlipImageRgb8::with_data(w, h, &rgb(&expected));
    let test = nv_flip::FlipImageRgb8::with_data(w, h, &rgb(&frame.ldr));
    let error_map = nv_flip::flip(reference, test, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let pool = nv_flip::FlipPool::from_image(&error_map);
    let mean = pool.mean();
    eprintln!(
        "{name}: mean FLIP {mean:.6} (max {:.6}), allowed mean {max_mean_flip}",
        pool.max_value()
    );
    if mean > max_mean_flip {
        let actual = goldens_dir().join(format!("{name}-actual.png"));
        let difference = goldens_dir().join(format!("{name}-difference.png"));
        combustion::output::write_png(&actual, w, h, &frame.ldr).unwrap();
        let diff_rgb = error_map.apply_color_lut(&nv_flip::magma_lut()).to_vec();
        let diff: Vec<[u8; 4]> = diff_rgb
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2], 255])
            .collect();
        combustion::output::write_png(&difference, w, h, &diff).unwrap();
        panic!(
            "{name}: mean FLIP {mean:.6} exceeds {max_mean_flip}; see {} and {}",
            actual.display(),
            difference.display()
        );
    }
}

/// Luminance (Rec. 709) of linear RGB.
pub fn luminance(rgb: [f32; 4]) -> f64 {
    0.2126 * f64::from(rgb[0]) + 0.7152 * f64::from(rgb[1]) + 0.0722 * f64::from(rgb[2])
}
