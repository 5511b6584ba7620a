//! Shared helpers of the integration tests: a lavapipe device with validation on, golden
//! image comparison with FLIP, scene pixel bookkeeping, and the analytic reference that
//! checks goldens of sphere scenes independently of the renderer.
#![allow(dead_code)]

pub mod shared_data;
pub mod weston;
pub mod xvfb;

#[allow(unused_imports)]
pub use shared_data::{shared_gltf_samples, REQUIRE_SHARED};

use std::path::PathBuf;

use combustion::optics::brdf::{brdf_evaluate, BrdfInputs, DiffuseModel};
use combustion::optics::microfacet::{alpha_from_perceptual_roughness, anisotropic_alphas};
use combustion::optics::vec3::Vec3 as V;
use combustion::reference::shading::light_at;
use combustion::renderer::{
    linear_to_srgb, tonemap_exponential, Frame, Readback, RendererSettings,
};
use combustion::scene::{Camera, Light, Material, Mesh, Object, Scene};
use combustion::vk::{DeviceDesc, DeviceSelector, ValidationLog};
use combustion::{Headless, HeadlessDesc};
use glam::{DMat4, DVec3, DVec4, Vec4Swizzles};

/// A fresh, empty folder of one test's files (`combustion-KIND-PID-NAME` in the
/// temporary folder), removed when the test is done with it; kept when the test fails,
/// to look at. The tests left some twenty such folders behind on every run.
pub struct Scratch(PathBuf);

impl Scratch {
    pub fn new(kind: &str, name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("combustion-{kind}-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }
}

impl std::ops::Deref for Scratch {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        &self.0
    }
}

impl AsRef<std::path::Path> for Scratch {
    fn as_ref(&self) -> &std::path::Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// Runs the `combustion` command on lavapipe: its exit code (-1 for a signal), standard
/// output and standard error; a panic, or an `error:` or `warning:` line written for Rust
/// rather than for people ([`assert_written_for_people`]), is a failure of the test,
/// whatever the command.
pub fn combustion(args: &[&str]) -> (i32, String, String) {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_combustion"))
        .args(args)
        .env("COMBUSTION_DEVICE", "llvmpipe")
        .output()
        .expect("run combustion");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert_written_for_people(args, &stderr);
    (
        output.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        stderr,
    )
}

/// docs/cli.md's message rule, on every `error:` and `warning:` line of a run: no Rust
/// path (`module::Item`), no `Debug` output (`Some(…)`, `None`, escaped quotes, a
/// struct's `{ field: … }`), no number of more than 12 digits.
pub fn assert_written_for_people(args: &[&str], stderr: &str) {
    for line in stderr
        .lines()
        .filter(|l| l.starts_with("error: ") || l.starts_with("warning: "))
    {
        let bytes = line.as_bytes();
        let rust_path = line.match_indices("::").any(|(at, _)| {
            at > 0
                && (bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_')
                && bytes
                    .get(at + 2)
                    .is_some_and(|b| b.is_ascii_alphabetic() || *b == b'_')
        });
        let debug = ["Some(", "None)", "Ok(", "Err(", "\\\"", ": None", " { "]
            .iter()
            .any(|marker| line.contains(marker));
        // A number of more than 12 digits (`1e-300` written out, a 39-digit 3.4e38):
        // messages write numbers short (combustion_optics::readable). What the user gave,
        // echoed in quotes ('…' or `…`, shortened), is theirs.
        let unquoted: String = line
            .split(['\'', '`'])
            .step_by(2)
            .collect::<Vec<_>>()
            .join(" ");
        let long_number = unquoted
            .split(|c: char| !(c.is_ascii_digit() || c == '.'))
            .any(|run| run.chars().filter(char::is_ascii_digit).count() > 12);
        assert!(
            !rust_path && !debug && !long_number,
            "{args:?}: a message written for Rust, not for people: {line}"
        );
    }
}

/// The names of the files in `dir`, sorted.
pub fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Tests always run on lavapipe (Mesa's CPU Vulkan driver), whatever else is installed,
/// so results don't depend on the machine's GPU. Validation is always on, synchronization
/// validation included.
pub fn lavapipe(settings: RendererSettings) -> Headless {
    Headless::new(&HeadlessDesc {
        device: DeviceDesc {
            selector: DeviceSelector::NameContains("llvmpipe".into()),
            validation: true,
            synchronization_validation: true,
            ..DeviceDesc::default()
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

/// Renders `scene` (its camera and lights) on lavapipe with validation, reading back
/// its HDR image and G-buffer, and compares every pixel with the f64 reference on
/// `threads` threads (`combustion_renderer::reference::error_map`).
pub fn render_with_error_map(
    scene: &Scene,
    width: u32,
    height: u32,
    settings: RendererSettings,
    threads: usize,
) -> (Frame, combustion::renderer::reference::ErrorMap) {
    use combustion::renderer::reference::{error_map, ReferenceShading};
    let frame = render(scene, width, height, settings, Readback::ALL);
    let inputs = frame_inputs(scene, &scene.lights);
    let map = error_map(
        &frame,
        &ReferenceShading::new(scene, &inputs, width, height),
        threads,
    );
    (frame, map)
}

/// How far (metres) the renderer may place a surface point at view distance `z` from the
/// true one, the bound tests/end_to_end.rs holds the G-buffer's depth to: eight steps of
/// the 32-bit depth there, z²/near · (far − near)/far · 2⁻²⁴ each, plus 1e-5 z for the
/// f32 camera.
pub fn position_bound(camera: &combustion::scene::Camera, z: f64) -> f64 {
    let (near, far) = (f64::from(camera.near), f64::from(camera.far));
    let step = z * z / near * (far - near) / far * 2f64.powi(-24);
    8.0 * step + 1e-5 * z
}

/// A frame of `scene` from its camera, exposure 1, lit by `lights`, no overlay, no
/// environment of its own.
pub fn frame_inputs<'a>(
    scene: &Scene,
    lights: &'a [Light],
) -> combustion::renderer::FrameInputs<'a> {
    combustion::renderer::FrameInputs {
        camera: scene.camera,
        exposure: 1.0,
        lights,
        overlay: &[],
        environment: None,
        background: combustion::renderer::Background::None,
        tone_mapping: combustion::renderer::ToneMapping::Exponential,
        pose: None,
        environment_seed: 0,
        anti_aliasing: combustion::renderer::AntiAliasing::None,
        auto_exposure: None,
        bloom_intensity: combustion::renderer::DEFAULT_BLOOM_INTENSITY,
    }
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

/// Renders `scene` lit by `lights` (its camera, exposure 1, [`exact_f32`] settings) and
/// reads back its HDR image and G-buffer.
pub fn render_with_lights(scene: &Scene, lights: &[Light], width: u32, height: u32) -> Frame {
    render_with_lights_in(scene, lights, width, height, exact_f32())
}

/// As [`render_with_lights`], with `settings`.
pub fn render_with_lights_in(
    scene: &Scene,
    lights: &[Light],
    width: u32,
    height: u32,
    settings: RendererSettings,
) -> Frame {
    let mut headless = lavapipe(settings);
    let frame = {
        let renderer = headless.renderer();
        let gpu_scene = renderer.upload(scene).expect("upload");
        let inputs = frame_inputs(scene, lights);
        let readback = Readback::ALL;
        renderer
            .render_with(&gpu_scene, &inputs, width, height, readback)
            .expect("render")
    };
    finish(headless);
    frame
}

/// Frames in one run of a scene when scenes alternate: more than the renderer's 16-frame
/// retire delay, so what the other scene's variant made is retired during the run.
pub const FRAMES_PAST_THE_RETIRE_DELAY: usize = 20;

/// `scene` (the sphere grid, `builtin:spheres`, or a scene made from it) with its
/// spheres made of 24 segments × 12 rings (528 triangles) instead of 96 × 48 (9 024),
/// for tests of frames, targets and resources rather than of what the spheres look like:
/// lavapipe spends most of a small frame of the full grid (216 576 triangles) setting up
/// triangles (docs/build.md, "Build cost"). Panics if the scene's first mesh is not the grid's
/// sphere.
pub fn with_coarse_grid_spheres(mut scene: Scene) -> Scene {
    let sphere = &scene.meshes[0];
    assert!(
        sphere.name == "sphere" && sphere.vertices.len() == 97 * 49,
        "not the sphere grid's sphere: {} ({} vertices)",
        sphere.name,
        sphere.vertices.len()
    );
    scene.meshes[0] = Mesh::uv_sphere("sphere", 0.42, 24, 12);
    scene
}

/// Renders `gpus` in turn, [`FRAMES_PAST_THE_RETIRE_DELAY`] frames each, twice round,
/// each frame with `inputs` of its scene at `width` × `height` and `readback` (everything,
/// or nothing: frames whose output is folded into the lighting pass), and hands every
/// frame to `check` with its scene's index.
pub fn alternate_scenes_past_the_retire_delay(
    renderer: &mut combustion::renderer::Renderer,
    gpus: &[combustion::renderer::GpuScene],
    ((width, height), readback): ((u32, u32), Readback),
    inputs: impl Fn(&combustion::renderer::GpuScene) -> combustion::renderer::FrameInputs<'_>,
    mut check: impl FnMut(usize, &Frame),
) {
    for _round in 0..2 {
        for (index, gpu) in gpus.iter().enumerate() {
            for _ in 0..FRAMES_PAST_THE_RETIRE_DELAY {
                let frame = renderer
                    .render_with(gpu, &inputs(gpu), width, height, readback)
                    .expect("frame");
                check(index, &frame);
            }
        }
    }
}

/// `scene`'s HDR radiance at `size` without and with the optional pass `pass` (by its
/// name), `exact_f32` settings otherwise.
pub fn radiance_without_and_with(
    scene: &Scene,
    (width, height): (u32, u32),
    pass: &str,
) -> [Vec<[f32; 4]>; 2] {
    let pass = combustion::renderer::optional_pass(pass).expect("the renderer declares it");
    [false, true].map(|on| {
        let mut settings = exact_f32();
        settings.shading.optional_passes =
            combustion::renderer::OptionalPasses::NONE.with(pass, on);
        render_images(scene, width, height, settings).hdr
    })
}

/// The f64 path tracer's frame of `scene` at `size`, `samples` paths a pixel (its
/// defaults otherwise), on two threads.
pub fn f64_path_traced(
    scene: &Scene,
    (width, height): (u32, u32),
    samples: u32,
) -> Vec<Option<combustion_optics::environment::Estimate>> {
    let bvh = combustion_reference::SceneBvh::new(scene);
    let casters = combustion_reference::SceneBvh::shadow_casters(scene);
    let shading =
        combustion_reference::shading::SceneShading::new(scene, &bvh, &scene.lights, width, height);
    let tracing = combustion_reference::path::PathTracing {
        samples,
        ..combustion_reference::path::PathTracing::default()
    };
    combustion_reference::path::PathTracer::new(&shading, &casters, tracing).render(2)
}

/// The exact model, f32 HDR, exposure 1, 2 frames in flight: what most tests render with.
pub fn exact_f32() -> RendererSettings {
    RendererSettings {
        hdr_format: combustion::renderer::HdrFormat::Rgba32Float,
        gbuffer: combustion::renderer::GBufferStorage::DEFAULT,
        exposure: 1.0,
        shading: combustion::renderer::ShadingOptions::DEFAULT,
        frames_in_flight: 2,
        targets_kept_for_frames: combustion::renderer::TARGETS_KEPT_FOR_FRAMES,
        fold_output: true,
        accumulate_paths: false,
    }
}

/// Renders `scene` with `settings` and reads back its HDR and display images.
pub fn render_images(scene: &Scene, width: u32, height: u32, settings: RendererSettings) -> Frame {
    render(scene, width, height, settings, Readback::IMAGES)
}

/// Pixels of two display images that differ by more than one 8-bit step in a channel.
pub fn pixels_apart(a: &Frame, b: &Frame) -> usize {
    a.ldr
        .iter()
        .zip(&b.ldr)
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 1))
        .count()
}

/// Pixels whose HDR radiance differs in any bit between two frames of one size.
pub fn hdr_pixels_differing(a: &Frame, b: &Frame) -> usize {
    a.hdr.iter().zip(&b.hdr).filter(|(p, q)| p != q).count()
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
/// when the mean FLIP error exceeds `max_mean_flip`, or when more than
/// [`GOLDEN_LOCAL_SHARE`] of the pixels differ by more than code-generation noise does: a
/// local regression (one mesh's normals, one material) is diluted in the mean but not
/// here. The noise level is measured per golden: the largest FLIP of the golden against
/// itself with every channel [`GOLDEN_NOISE_LEVELS`] 8-bit levels brighter. On failure
/// writes `NAME-actual.png` and `NAME-difference.png` (gitignored) beside the golden and
/// names them.
///
/// To update goldens on purpose: `COMBUSTION_BLESS=1 cargo test --test integration images::`,
/// then check the new images independently (see tests/goldens/README.md) before committing.
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
    let d = golden_difference(name, frame);
    eprintln!(
        "{name}: mean FLIP {:.6} (max {:.6}), allowed mean {max_mean_flip}; {} pixels above the noise level {:.4}, allowed {}",
        d.mean, d.max, d.above_noise, d.noise, d.allowed_above_noise
    );
    if d.mean > max_mean_flip || d.above_noise > d.allowed_above_noise {
        let (w, h) = (frame.width, frame.height);
        let actual = goldens_dir().join(format!("{name}-actual.png"));
        let difference = goldens_dir().join(format!("{name}-difference.png"));
        combustion::output::write_png(&actual, w, h, &frame.ldr).unwrap();
        combustion::output::write_png(&difference, w, h, &d.heat_map).unwrap();
        panic!(
            "{name}: mean FLIP {:.6} (allowed {max_mean_flip}), {} pixels above the noise level (allowed {}); see {} and {}",
            d.mean,
            d.above_noise,
            d.allowed_above_noise,
            actual.display(),
            difference.display()
        );
    }
}

/// A frame against its golden, by FLIP ([`compare_with_golden`]'s measures).
pub struct GoldenDifference {
    /// Mean FLIP.
    pub mean: f32,
    /// Largest FLIP.
    pub max: f32,
    /// The noise level: the largest FLIP of the golden against itself
    /// [`GOLDEN_NOISE_LEVELS`] levels brighter.
    pub noise: f32,
    /// Pixels whose FLIP exceeds the noise level.
    pub above_noise: usize,
    /// How many may ([`GOLDEN_LOCAL_SHARE`] of the pixels).
    pub allowed_above_noise: usize,
    /// The FLIP map in the magma colours, RGBA8.
    pub heat_map: Vec<[u8; 4]>,
}

/// Measures `frame` against `tests/goldens/NAME.png` (same size).
pub fn golden_difference(name: &str, frame: &Frame) -> GoldenDifference {
    let (w, h, expected) = read_png(&goldens_dir().join(format!("{name}.png")));
    assert_eq!((w, h), (frame.width, frame.height), "golden size of {name}");
    let rgb = |pixels: &[[u8; 4]]| {
        pixels
            .iter()
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect::<Vec<u8>>()
    };
    let flip = |a: &[[u8; 4]], b: &[[u8; 4]]| {
        nv_flip::flip(
            nv_flip::FlipImageRgb8::with_data(w, h, &rgb(a)),
            nv_flip::FlipImageRgb8::with_data(w, h, &rgb(b)),
            nv_flip::DEFAULT_PIXELS_PER_DEGREE,
        )
    };
    let error_map = flip(&expected, &frame.ldr);
    let pool = nv_flip::FlipPool::from_image(&error_map);
    // The FLIP of code-generation noise: the golden against itself a few levels off.
    let noisy: Vec<[u8; 4]> = expected
        .iter()
        .map(|p| p.map(|c| c.saturating_add(GOLDEN_NOISE_LEVELS)))
        .collect();
    let noise = nv_flip::FlipPool::from_image(&flip(&expected, &noisy)).max_value();
    GoldenDifference {
        mean: pool.mean(),
        max: pool.max_value(),
        noise,
        above_noise: error_map.to_vec().iter().filter(|&&v| v > noise).count(),
        allowed_above_noise: (GOLDEN_LOCAL_SHARE * f64::from(w * h)) as usize,
        heat_map: error_map
            .apply_color_lut(&nv_flip::magma_lut())
            .to_vec()
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2], 255])
            .collect(),
    }
}

/// Levels of 8-bit difference taken as code-generation noise (a different LLVM build's
/// rounding in isolated pixels: a few steps), for [`compare_with_golden`].
pub const GOLDEN_NOISE_LEVELS: u8 = 3;

/// The share of a golden's pixels that may differ by more than noise: 0.1 %, a few
/// dozen isolated pixels at the goldens' sizes (65 at 256×256), so a regression
/// confined to one object fails once the object covers more than a 8×8-pixel patch
/// (a 20×20 patch 30 levels off in spheres_256 fails this and passes the mean).
pub const GOLDEN_LOCAL_SHARE: f64 = 1e-3;

/// Luminance (Rec. 709) of linear RGB.
pub fn luminance(rgb: [f32; 4]) -> f64 {
    0.2126 * f64::from(rgb[0]) + 0.7152 * f64::from(rgb[1]) + 0.0722 * f64::from(rgb[2])
}

// ---------------------------------------------------------------------------------------
// The analytic reference: exact spheres, ray-cast and shaded in f64 with the optics crate.
// ---------------------------------------------------------------------------------------

/// One analytic sphere of a scene: where it is and which material it has.
#[derive(Clone, Copy, Debug)]
pub struct AnalyticSphere {
    pub centre: DVec3,
    pub radius: f64,
    pub material: usize,
    /// The scene object it stands for.
    pub object: usize,
}

/// A scene made only of spheres (every mesh a UV sphere centred at its origin, every
/// object placed by a translation and a uniform scale), replaced by exact spheres: rays
/// through pixel centres are intersected in f64 and shaded with the optics crate's
/// `brdf_evaluate` under every light of the scene (point, directional, spot), tone-mapped
/// and sRGB-encoded as the tonemap pass does (exposure 1). Nothing of the renderer is used
/// but its two documented CPU mirrors of the tone curve and the sRGB encoding.
pub struct AnalyticSpheres {
    pub scene: Scene,
    pub width: u32,
    pub height: u32,
    inverse_view_projection: DMat4,
    pub spheres: Vec<AnalyticSphere>,
}

impl AnalyticSpheres {
    /// Panics if an object is not a sphere placed by translation and uniform scale.
    pub fn new(scene: Scene, width: u32, height: u32) -> Self {
        let aspect = width as f32 / height as f32;
        let inverse_view_projection = scene.camera.view_projection(aspect).as_dmat4().inverse();
        let spheres = scene
            .objects
            .iter()
            .enumerate()
            .map(|(object, o)| {
                let mesh = &scene.meshes[o.mesh];
                let radius = glam::Vec3::from(mesh.vertices[0].position).length() as f64;
                for v in &mesh.vertices {
                    let r = glam::Vec3::from(v.position).length() as f64;
                    assert!(
                        (r - radius).abs() < 1e-5 * radius,
                        "mesh {} of object {object} is not a sphere centred at its origin",
                        mesh.name
                    );
                }
                let (scale, rotation, translation) = o.transform.to_scale_rotation_translation();
                assert!(
                    (scale - glam::Vec3::splat(scale.x)).abs().max_element() < 1e-6 * scale.x
                        && rotation.abs_diff_eq(glam::Quat::IDENTITY, 1e-6),
                    "object {object} must be placed by a translation and a uniform scale"
                );
                AnalyticSphere {
                    centre: translation.as_dvec3(),
                    radius: radius * f64::from(scale.x),
                    material: o.material,
                    object,
                }
            })
            .collect();
        Self {
            scene,
            width,
            height,
            inverse_view_projection,
            spheres,
        }
    }

    /// The camera ray through the point (x, y) of the image (pixel units, y down).
    pub fn ray(&self, x: f64, y: f64) -> (DVec3, DVec3) {
        let ndc = |z: f64| {
            let p = self.inverse_view_projection
                * DVec4::new(
                    x / f64::from(self.width) * 2.0 - 1.0,
                    y / f64::from(self.height) * 2.0 - 1.0,
                    z,
                    1.0,
                );
            p.xyz() / p.w
        };
        let (near, far) = (ndc(0.0), ndc(1.0));
        (near, (far - near).normalize())
    }

    /// Nearest sphere hit: (point, index into `spheres`).
    pub fn hit(&self, x: f64, y: f64) -> Option<(DVec3, usize)> {
        let (origin, dir) = self.ray(x, y);
        let mut best: Option<(f64, usize)> = None;
        for (i, s) in self.spheres.iter().enumerate() {
            let oc = origin - s.centre;
            let b = oc.dot(dir);
            let disc = b * b - (oc.length_squared() - s.radius * s.radius);
            if disc >= 0.0 {
                let t = -b - disc.sqrt();
                if t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                    best = Some((t, i));
                }
            }
        }
        best.map(|(t, i)| (origin + dir * t, i))
    }

    /// The pixel's analytic surface point if it is an *interior* pixel: its centre and its
    /// four neighbours' centres hit the same sphere, and the surface faces the camera
    /// (n·v ≥ 0.3; silhouette pixels depend on rasterisation coverage). Returns (point,
    /// normal, direction to the camera, sphere index).
    pub fn interior(&self, x: u32, y: u32) -> Option<(DVec3, DVec3, DVec3, usize)> {
        let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        let (p, sphere) = self.hit(px, py)?;
        for (dx, dy) in [(-1.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.0, 1.0)] {
            if self.hit(px + dx, py + dy).map(|h| h.1) != Some(sphere) {
                return None;
            }
        }
        let s = &self.spheres[sphere];
        let n = (p - s.centre) / s.radius;
        let v = (self.scene.camera.position.as_dvec3() - p).normalize();
        if n.dot(v) < 0.3 {
            return None;
        }
        Some((p, n, v, sphere))
    }

    /// The display bytes (0–255, unrounded) the analytic spheres give at pixel (x, y), for
    /// the analytic normal and for that normal tilted by `tilt` radians in four
    /// directions; None where the pixel is not interior (see [`Self::interior`]).
    pub fn display_bytes(&self, x: u32, y: u32, tilt: f64) -> Option<[[f64; 3]; 5]> {
        let (p, n, v, sphere) = self.interior(x, y)?;
        let (e1, e2) = n.any_orthonormal_pair();
        let mut out = [[0.0; 3]; 5];
        for (k, (a, b)) in [(0.0, 0.0), (1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)]
            .into_iter()
            .enumerate()
        {
            let tilted = (n + (e1 * a + e2 * b) * tilt).normalize();
            let radiance = self.shade(p, tilted, v, self.spheres[sphere].material);
            out[k] = radiance.map(|r| linear_to_srgb(tonemap_exponential(r)) * 255.0);
        }
        Some(out)
    }

    /// Radiance leaving point `p` with normal `n` toward `v`, summed over the lights.
    pub fn shade(&self, p: DVec3, n: DVec3, v: DVec3, material_index: usize) -> [f64; 3] {
        let mut radiance = [0.0; 3];
        for light in self.shade_per_light(p, n, v, material_index) {
            for c in 0..3 {
                radiance[c] += light[c];
            }
        }
        radiance
    }

    /// Radiance leaving point `p` with normal `n` toward `v`, per light of the scene.
    pub fn shade_per_light(
        &self,
        p: DVec3,
        n: DVec3,
        v: DVec3,
        material_index: usize,
    ) -> Vec<[f64; 3]> {
        // The UV sphere's tangent: along increasing longitude φ, n = (sinθcosφ, cosθ, −sinθsinφ).
        let phi = (-n.z).atan2(n.x);
        let t = DVec3::new(-phi.sin(), 0.0, -phi.cos());
        let material: &Material = &self.scene.materials[material_index];
        let rotation = f64::from(material.anisotropy_rotation);
        let b = n.cross(t);
        let direction = t * rotation.cos() + b * rotation.sin();
        let m = brdf_inputs(material, self.scene.outside_ior_of(material));
        let vec = |d: DVec3| V::new(d.x, d.y, d.z);
        self.scene
            .lights
            .iter()
            .map(|light| {
                let (l, e) = light_at(light, p);
                let cos = n.dot(l);
                if cos <= 0.0 {
                    return [0.0; 3];
                }
                let f = brdf_evaluate(
                    &m,
                    vec(n),
                    vec(direction),
                    vec(n.cross(direction)),
                    vec(v),
                    vec(l),
                );
                std::array::from_fn(|c| f[c] * e[c] * cos)
            })
            .collect()
    }
}

/// The optics crate's inputs for a material, in f64, exactly as the G-buffer + lighting
/// pass form them (but without the G-buffer's quantisation).
pub fn brdf_inputs(material: &Material, outside_ior: f32) -> BrdfInputs<f64> {
    let r = f64::from(material.roughness);
    let alpha = alpha_from_perceptual_roughness(r);
    let (alpha_x, alpha_y) = anisotropic_alphas(alpha, f64::from(material.anisotropy_strength));
    BrdfInputs {
        base_color: material.base_color.map(f64::from),
        metalness: f64::from(material.metalness),
        alpha_x,
        alpha_y,
        conductor_eta: material.conductor.eta.map(f64::from),
        conductor_k: material.conductor.k.map(f64::from),
        dielectric_eta: f64::from(material.dielectric_ior),
        outside_eta: f64::from(outside_ior),
        polarisation_weight: f64::from(material.polarisation_weight),
        diffuse_model: DiffuseModel::try_from(material.diffuse_model as u32).unwrap(),
        oren_nayar_sigma: combustion::optics::diffuse::oren_nayar_sigma_from_roughness(r),
    }
}

/// What comparing a golden PNG with the analytic spheres found.
#[derive(Debug)]
pub struct AnalyticComparison {
    /// Channel samples compared.
    pub compared: usize,
    /// Of those, samples whose analytic value is at least one 8-bit level (lit).
    pub lit: usize,
    /// Samples left out: their expected value moves by more than 2 levels when the normal
    /// is tilted by the tessellation error.
    pub ill_conditioned: usize,
    /// histogram[d]: compared samples d levels off.
    pub histogram: [usize; 256],
    /// Same, for the lit samples only.
    pub lit_histogram: [usize; 256],
    /// (levels, x, y) of the worst sample.
    pub worst: (u8, u32, u32),
}

impl AnalyticComparison {
    /// Fraction of compared samples within `levels` 8-bit levels.
    pub fn within(&self, levels: usize) -> f64 {
        self.histogram[..=levels].iter().sum::<usize>() as f64 / self.compared as f64
    }

    /// Fraction of lit compared samples within `levels` 8-bit levels.
    pub fn lit_within(&self, levels: usize) -> f64 {
        self.lit_histogram[..=levels].iter().sum::<usize>() as f64 / self.lit as f64
    }

    /// Fraction of the interior samples that were compared (not ill-conditioned).
    pub fn coverage(&self) -> f64 {
        self.compared as f64 / (self.compared + self.ill_conditioned) as f64
    }

    /// The bounds every golden is held to (derived in tests/images.rs for spheres_256).
    /// Two make sure the comparison is not vacuous, and depend on the analytic scene
    /// only: at least `min_compared` samples, covering at least 90 % of the interior.
    /// Three hold the image: the worst compared sample at most 3 levels off (8-bit base
    /// colour storage ≤ half a step of albedo, the output's rounding, and ≤ 2 levels of
    /// tessellation by the conditioning filter), and at least 99 % of all compared
    /// samples and 99 % of the lit ones (at least one level: the shading, not the black
    /// background) within one level (the reference's and the output's roundings, half
    /// a level each).
    pub fn assert_bounds(&self, name: &str, min_compared: usize) {
        assert!(
            self.compared >= min_compared,
            "{name}: too few interior samples compared: {} < {min_compared}",
            self.compared
        );
        assert!(
            self.coverage() >= 0.9,
            "{name}: the comparison must cover the bulk of the spheres ({:.4})",
            self.coverage()
        );
        assert!(
            self.worst.0 <= 3,
            "{name}: worst sample {} levels off at {:?}",
            self.worst.0,
            (self.worst.1, self.worst.2)
        );
        assert!(
            self.within(1) >= 0.99,
            "{name}: {:.4} within one level",
            self.within(1)
        );
        assert!(
            self.lit > 0 && self.lit_within(1) >= 0.99,
            "{name}: {:.4} of {} lit samples within one level",
            self.lit_within(1),
            self.lit
        );
    }
}

impl std::fmt::Display for AnalyticComparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} channel samples compared ({} lit; {} ill-conditioned left out, coverage {:.4}); within 0 levels: {:.4}, 1: {:.4}, 2: {:.4}; lit within 0: {:.4}, 1: {:.4}; worst {} levels at {:?}",
            self.compared,
            self.lit,
            self.ill_conditioned,
            self.coverage(),
            self.within(0),
            self.within(1),
            self.within(2),
            self.lit_within(0),
            self.lit_within(1),
            self.worst.0,
            (self.worst.1, self.worst.2)
        )
    }
}

/// Compares `tests/goldens/GOLDEN.png` — the file on disk, not a render — with the analytic
/// spheres of `scene`, pixel by pixel on the interior of every sphere. Samples whose
/// expected value changes by more than 2 levels when the normal is tilted by `tilt`
/// radians (the tessellation's normal error; the sharpest highlights and the edges where a
/// Fresnel factor reaches total internal reflection) can't be decided by an analytic
/// sphere and are counted but not compared.
pub fn compare_golden_with_analytic(scene: Scene, golden: &str, tilt: f64) -> AnalyticComparison {
    let (w, h, pixels) = read_png(&goldens_dir().join(format!("{golden}.png")));
    let reference = AnalyticSpheres::new(scene, w, h);
    let mut result = AnalyticComparison {
        compared: 0,
        lit: 0,
        ill_conditioned: 0,
        histogram: [0; 256],
        lit_histogram: [0; 256],
        worst: (0, 0, 0),
    };
    for y in 0..h {
        for x in 0..w {
            let Some(bytes) = reference.display_bytes(x, y, tilt) else {
                continue;
            };
            let pixel = pixels[(y * w + x) as usize];
            for c in 0..3 {
                let values = bytes.map(|b| b[c]);
                let spread = values.iter().cloned().fold(f64::MIN, f64::max)
                    - values.iter().cloned().fold(f64::MAX, f64::min);
                if spread > 2.0 {
                    result.ill_conditioned += 1;
                    continue;
                }
                result.compared += 1;
                let diff = (f64::from(pixel[c]) - values[0].round()).abs() as u8;
                result.histogram[diff as usize] += 1;
                if values[0] >= 1.0 {
                    result.lit += 1;
                    result.lit_histogram[diff as usize] += 1;
                }
                if diff > result.worst.0 {
                    result.worst = (diff, x, y);
                }
            }
        }
    }
    eprintln!("{golden}: {result}");
    result
}

/// The largest angle (radians) between the shading normal the rasteriser interpolates on
/// the scene's tessellated spheres and the analytic sphere normal at the same pixel, over
/// every interior pixel (see [`AnalyticSpheres::interior`]) of a `width` × `height` image:
/// each pixel's ray is intersected with the actual triangles in f64 and the vertex normals
/// are interpolated barycentrically there (what perspective-correct interpolation gives).
pub fn measure_tessellation_normal_error(scene: &Scene, width: u32, height: u32) -> f64 {
    let reference = AnalyticSpheres::new(scene.clone(), width, height);
    let mut worst = 0.0f64;
    for y in 0..height {
        for x in 0..width {
            let Some((p, n, _, sphere)) = reference.interior(x, y) else {
                continue;
            };
            let s = reference.spheres[sphere];
            let object = &scene.objects[s.object];
            let mesh = &scene.meshes[object.mesh];
            let transform = object.transform.as_dmat4();
            let (origin, dir) = reference.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
            let vertex = |i: u32| {
                let v = &mesh.vertices[i as usize];
                (
                    transform.transform_point3(glam::Vec3::from(v.position).as_dvec3()),
                    glam::Vec3::from(v.normal).as_dvec3(),
                )
            };
            let mut best: Option<(f64, DVec3)> = None;
            for tri in mesh.indices.chunks_exact(3) {
                let [(a, na), (b, nb), (c, nc)] = [vertex(tri[0]), vertex(tri[1]), vertex(tri[2])];
                // Only triangles near the analytic hit can be hit first.
                if (a - p).length() > 4.0 * (b - a).length().max((c - a).length()) + 1e-9 {
                    continue;
                }
                // Möller–Trumbore.
                let (e1, e2) = (b - a, c - a);
                let q = dir.cross(e2);
                let det = e1.dot(q);
                if det.abs() < 1e-15 {
                    continue;
                }
                let s0 = origin - a;
                let u = s0.dot(q) / det;
                let r = s0.cross(e1);
                let v = dir.dot(r) / det;
                if u < -1e-12 || v < -1e-12 || u + v > 1.0 + 1e-12 {
                    continue;
                }
                let t = e2.dot(r) / det;
                if t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                    best = Some((t, (na * (1.0 - u - v) + nb * u + nc * v).normalize()));
                }
            }
            let (_, interpolated) = best.expect("the ray hits the tessellated sphere too");
            worst = worst.max(interpolated.cross(n).length().atan2(interpolated.dot(n)));
        }
    }
    worst
}

/// Luminance (Rec. 709) of linear RGB in f64.
pub fn luminance3(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// The project's authored scene `assets/scenes/NAME/NAME.gltf`, imported, lit by its own
/// lights alone.
pub fn authored_scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("assets/scenes/{name}/{name}.gltf"));
    let mut scene = combustion::SceneSource::File(path).load().unwrap();
    // Its own lights alone: every authored scene has lights, and the tests compare it
    // with references of them (a file is lit by the studio environment as well by
    // default).
    scene.environment = None;
    scene
}

/// `grid-sun` (spheres on a floor under a shadow-casting sun) with every object hanging
/// from a node under one turntable node, and one animation: the turntable turns 0.6 rad
/// about y over 2 s (linear), sphere 0 jumps up 0.5 m for the second second (step), and
/// sphere 1 grows to 1.6× (cubic spline, flat tangents).
pub fn animated_grid() -> Scene {
    use combustion::scene::motion::{
        Animation, Channel, Interpolation, LocalTransform, Node, Property, Sampler,
    };
    use combustion::scene::NodeLink;
    use glam::{Quat, Vec3};
    let mut scene = combustion::scene::builtin_scene("grid-sun").unwrap();
    let mut nodes = vec![Node {
        name: Some("turntable".into()),
        parent: None,
        local: LocalTransform::IDENTITY,
        skin: None,
        weights: Vec::new(),
    }];
    for (i, object) in scene.objects.iter_mut().enumerate() {
        let (scale, rotation, translation) = object.transform.to_scale_rotation_translation();
        nodes.push(Node {
            name: Some(format!("object {i}")),
            parent: Some(0),
            local: LocalTransform::Trs {
                translation,
                rotation,
                scale,
            },
            skin: None,
            weights: Vec::new(),
        });
        object.node = Some(NodeLink {
            node: i + 1,
            offset: glam::Mat4::IDENTITY,
        });
    }
    let t0 = scene.objects[0].transform.w_axis.truncate();
    let up = t0 + Vec3::new(0.0, 0.5, 0.0);
    let samplers = vec![
        Sampler {
            interpolation: Interpolation::Linear,
            times: vec![0.0, 2.0],
            values: [Quat::IDENTITY, Quat::from_rotation_y(0.6)]
                .iter()
                .flat_map(|q| q.to_array())
                .collect(),
        },
        Sampler {
            interpolation: Interpolation::Step,
            times: vec![0.0, 1.0, 2.0],
            values: [t0, up, t0].iter().flat_map(|v| v.to_array()).collect(),
        },
        Sampler {
            interpolation: Interpolation::CubicSpline,
            times: vec![0.0, 2.0],
            values: [
                Vec3::ZERO,
                Vec3::ONE,
                Vec3::ZERO,
                Vec3::ZERO,
                Vec3::splat(1.6),
                Vec3::ZERO,
            ]
            .iter()
            .flat_map(|v| v.to_array())
            .collect(),
        },
    ];
    let channel = |node, property, sampler| Channel {
        node,
        property,
        sampler,
    };
    scene.motion = combustion::scene::Motion {
        nodes,
        skins: Vec::new(),
        animations: vec![Animation {
            name: Some("swing".into()),
            samplers,
            channels: vec![
                channel(0, Property::Rotation, 0),
                channel(1, Property::Translation, 1),
                channel(2, Property::Scale, 2),
            ],
        }],
    };
    scene.name = "animated grid".into();
    scene.validate().unwrap();
    scene
}

/// [`deformed_spheres`]' two deformed spheres alone on a floor under a sun that casts
/// shadows, seen from above and in front (no environment).
pub fn deformed_spheres_on_a_floor() -> Scene {
    let mut scene = deformed_spheres();
    let deformed = scene.objects.len() - 2;
    scene.objects.drain(..deformed);
    scene.meshes.push(Mesh::plane("floor", 20.0));
    scene.objects.push(Object::casting_shadows(
        scene.meshes.len() - 1,
        0,
        glam::Mat4::from_translation(glam::Vec3::new(0.0, -0.55, 1.2)),
    ));
    scene.lights = vec![Light::Directional {
        direction: glam::Vec3::new(0.3, -1.0, -0.4).normalize(),
        irradiance: [3.0; 3],
        casts_shadows: true,
        angular_diameter: 0.0,
    }];
    scene.camera = Camera {
        position: glam::Vec3::new(0.0, 2.0, 4.5),
        target: glam::Vec3::new(0.0, -0.2, 1.2),
        ..scene.camera
    };
    scene
}

/// The glTF file of Khronos sample model `model` under the shared samples' `root`: its
/// `glTF/` form where there is one, else its `glTF-Binary/` one.
pub fn sample_model_path(root: &std::path::Path, model: &str) -> PathBuf {
    let gltf = root.join(model).join(format!("glTF/{model}.gltf"));
    if gltf.exists() {
        gltf
    } else {
        root.join(model).join(format!("glTF-Binary/{model}.glb"))
    }
}

/// A skinned and a morphed sphere under a light, with one animation: the skinned sphere
/// (radius 0.5, 48 × 24) bends at its middle: the lower half follows joint 0 (node 1, at
/// rest), the upper half joint 1 (node 2, its child, 0.5 m up), blended over the middle
/// third; joint 1 turns 0.8 rad about z over 2 s (linear). The morphed sphere beside it
/// has one target pushing its upper half out by 0.2 m along the normal, its weight going
/// from 0 to 1 over 2 s (linear). Node 0 carries the skinned mesh (its own transform is
/// ignored: the joints place it), node 3 the morphed one.
pub fn deformed_spheres() -> Scene {
    use combustion::scene::motion::{
        Animation, Channel, Interpolation, LocalTransform, MorphTarget, Node, Property, Sampler,
        Skin, SkinWeights,
    };
    use combustion::scene::{Mesh, NodeLink, Object};
    use glam::{Mat4, Quat, Vec3};
    let mut scene = combustion::scene::builtin_scene("spheres").unwrap();
    let sphere = Mesh::uv_sphere("bending sphere", 0.5, 48, 24);
    // Joint 1's share: 0 below y = −1/6, 1 above 1/6, linear between.
    let weights = SkinWeights::from_influences(sphere.vertices.iter().map(|v| {
        let upper = ((v.position[1] + 1.0 / 6.0) * 3.0).clamp(0.0, 1.0);
        [(0, 1.0 - upper), (1, upper)]
    }));
    let mut skinned = sphere.clone();
    skinned.skin = Some(weights);
    let mut morphed = sphere.clone();
    morphed.name = "swelling sphere".into();
    morphed.morph_targets = vec![MorphTarget {
        positions: sphere
            .vertices
            .iter()
            .map(|v| {
                let out = if v.position[1] > 0.0 { 0.2 } else { 0.0 };
                (Vec3::from(v.normal) * out).to_array()
            })
            .collect(),
        normals: Vec::new(),
        tangents: Vec::new(),
    }];
    let first = scene.meshes.len();
    scene.meshes.push(skinned);
    scene.meshes.push(morphed);
    let material = 0;
    let place = |x: f32| Mat4::from_translation(Vec3::new(x, 0.0, 1.2));
    scene.objects.push(Object {
        node: Some(NodeLink {
            node: 0,
            offset: Mat4::IDENTITY,
        }),
        ..Object::casting_shadows(first, material, place(-0.7))
    });
    scene.objects.push(Object {
        node: Some(NodeLink {
            node: 3,
            offset: Mat4::IDENTITY,
        }),
        ..Object::casting_shadows(first + 1, material, place(0.7))
    });
    let trs = |t: Vec3| LocalTransform::Trs {
        translation: t,
        rotation: Quat::IDENTITY,
        scale: Vec3::ONE,
    };
    let node = |parent, local, skin, weights: Vec<f32>| Node {
        name: None,
        parent,
        local,
        skin,
        weights,
    };
    let joint_0 = Vec3::new(-0.7, 0.0, 1.2);
    scene.motion = combustion::scene::Motion {
        nodes: vec![
            node(None, trs(Vec3::new(5.0, 5.0, 5.0)), Some(0), Vec::new()),
            node(None, trs(joint_0), None, Vec::new()),
            node(Some(1), trs(Vec3::new(0.0, 0.5, 0.0)), None, Vec::new()),
            node(None, trs(Vec3::new(0.7, 0.0, 1.2)), None, vec![0.0]),
        ],
        skins: vec![Skin {
            name: None,
            joints: vec![1, 2],
            // Bind space: the mesh's own, the joints at (0, 0, 0) and (0, 0.5, 0).
            inverse_bind: vec![
                Mat4::IDENTITY,
                Mat4::from_translation(Vec3::new(0.0, -0.5, 0.0)),
            ],
        }],
        animations: vec![Animation {
            name: Some("bend and swell".into()),
            samplers: vec![
                Sampler {
                    interpolation: Interpolation::Linear,
                    times: vec![0.0, 2.0],
                    values: [Quat::IDENTITY, Quat::from_rotation_z(0.8)]
                        .iter()
                        .flat_map(|q| q.to_array())
                        .collect(),
                },
                Sampler {
                    interpolation: Interpolation::Linear,
                    times: vec![0.0, 2.0],
                    values: vec![0.0, 1.0],
                },
            ],
            channels: vec![
                Channel {
                    node: 2,
                    property: Property::Rotation,
                    sampler: 0,
                },
                Channel {
                    node: 3,
                    property: Property::Weights,
                    sampler: 1,
                },
            ],
        }],
    };
    scene.name = "deformed spheres".into();
    scene.validate().unwrap();
    scene
}

/// A frame of `gpu` (its scene's camera and lights, exposure 1) in `pose` (`None`: at
/// rest), `width`×`height`, its images and G-buffer read back.
pub fn render_posed(
    renderer: &mut combustion::renderer::Renderer,
    gpu: &combustion::renderer::GpuScene,
    pose: Option<&combustion::scene::ObjectPoses>,
    (width, height): (u32, u32),
) -> Frame {
    let inputs = combustion::renderer::FrameInputs {
        pose,
        ..combustion::renderer::FrameInputs::of_scene(gpu, 1.0)
    };
    renderer
        .render_with(gpu, &inputs, width, height, Readback::ALL)
        .unwrap()
}

/// A 100 m plane of `material` at the origin (facing +y), lit by `lights`, seen straight
/// down from 3 m (image up is −z, 60° vertical field of view): the tests' plane seen from
/// above.
pub fn plane_from_above(name: &str, material: Material, lights: Vec<Light>) -> Scene {
    Scene {
        name: name.into(),
        meshes: vec![Mesh::plane("plane", 100.0)],
        materials: vec![material],
        objects: vec![Object {
            mesh: 0,
            material: 0,
            transform: glam::Mat4::IDENTITY,
            casts_shadows: true,
            node: None,
        }],
        lights,
        camera: Camera {
            position: glam::Vec3::new(0.0, 3.0, 0.0),
            target: glam::Vec3::ZERO,
            up: glam::Vec3::NEG_Z,
            vertical_fov: 60f32.to_radians(),
            near: 0.1,
            far: 100.0,
        },
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

/// The pixels of `frame` (of `scene`, read back with its G-buffer) that a surface covers
/// and that are exactly black (every channel 0) where the f64 reference is not, with
/// the reference's radiance: it finds a channel of at least `combustion::renderer::reference::RADIANCE_FLOOR` there (a
/// third of an 8-bit step at black: a pixel at a light's terminator may be black on the
/// GPU and 1e-6 in f64, its normal's cosine to the light on either side of 0; 16 samples of each
/// strategy of the environment's integral where the scene has an environment), or
/// nothing to hit at the pixel's centre (`None`), with its textures sampled at its own
/// level of detail and half a level finer and coarser alike.
pub fn black_where_lit(
    scene: &Scene,
    frame: &combustion::renderer::Frame,
) -> Vec<(u32, u32, Option<[f64; 3]>)> {
    let gbuffer = frame.gbuffer.as_ref().expect("the G-buffer is read back");
    let black: Vec<(u32, u32)> = frame
        .hdr
        .iter()
        .zip(&gbuffer.texels)
        .enumerate()
        .filter(|(_, (hdr, texel))| texel.depth < 1.0 && hdr[..3].iter().all(|&c| c == 0.0))
        .map(|(i, _)| (i as u32 % frame.width, i as u32 / frame.width))
        .collect();
    if black.is_empty() {
        // No candidate: the scene's hierarchy and reference are not built.
        return Vec::new();
    }
    let drawn = scene.as_drawn(None);
    let drawn = drawn.as_ref();
    let bvh = combustion::reference::SceneBvh::new(drawn);
    let shading = |lod_bias: f64| {
        combustion::reference::shading::SceneShading::new(
            drawn,
            &bvh,
            &drawn.lights,
            frame.width,
            frame.height,
        )
        .with_environment(16)
        .with_lod_bias(lod_bias)
    };
    // Textures at the level of detail the reference computes, and half a level finer and
    // coarser (the latitude the Vulkan specification gives a driver's level of detail):
    // a pixel is lit only where it is lit at all three.
    let lods = [0.0, -0.5, 0.5].map(shading);
    let floor = combustion::renderer::reference::RADIANCE_FLOOR;
    black
        .into_iter()
        .filter_map(|(x, y)| {
            let black_at = |r: Option<[f64; 3]>| r.is_some_and(|r| r.iter().all(|&c| c < floor));
            let reference = lods[0].pixel(x, y).map(|p| p.radiance);
            let lit = !black_at(reference)
                && !lods[1..]
                    .iter()
                    .any(|lod| black_at(lod.pixel(x, y).map(|p| p.radiance)));
            lit.then_some((x, y, reference))
        })
        .collect()
}
