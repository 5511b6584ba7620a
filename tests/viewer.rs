//! `combustion view` under a virtual X server (Xvfb): frames are rendered, presented and
//! everything torn down with the validation layer silent; without a display the command
//! fails with one line.

use crate::common;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::weston::Weston;
use common::xvfb::Xvfb;

/// No error and no logged warning on stderr (info lines, or a driver's own banner, are
/// tolerated).
fn assert_quiet(stderr: &str) {
    let loud = stderr
        .lines()
        .filter(|l| !l.starts_with("[INFO"))
        .any(|l| l.contains("error") || l.starts_with("warning:"));
    assert!(!loud, "{stderr}");
}

/// Runs `combustion view ARGS` with `DISPLAY=display`, killing it after 60 s.
fn view(display: &str, args: &[&str]) -> (Option<i32>, String, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_combustion"));
    command
        .env("DISPLAY", display)
        .env_remove("WAYLAND_DISPLAY");
    run_view(command, args)
}

/// Runs `combustion view ARGS` on the Wayland compositor `weston` (no X display).
fn view_on_wayland(weston: &Weston, args: &[&str]) -> (Option<i32>, String, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_combustion"));
    command
        .env_remove("DISPLAY")
        .env("XDG_RUNTIME_DIR", &weston.runtime_dir)
        .env("WAYLAND_DISPLAY", &weston.socket);
    run_view(command, args)
}

/// Runs `command view ARGS` on lavapipe, killing it after 60 s; its exit code and output.
fn run_view(mut command: Command, args: &[&str]) -> (Option<i32>, String, String) {
    let mut child = command
        .arg("view")
        .args(args)
        .env("COMBUSTION_DEVICE", "llvmpipe")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run combustion");
    let deadline = Instant::now() + Duration::from_secs(60);
    while child.try_wait().expect("poll combustion").is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let Output {
        status,
        stdout,
        stderr,
    } = child.wait_with_output().expect("combustion output");
    let stderr = String::from_utf8_lossy(&stderr).into_owned();
    // docs/cli.md's message rule, as for every other command.
    common::assert_written_for_people(args, &stderr);
    (
        status.code(),
        String::from_utf8_lossy(&stdout).into_owned(),
        stderr,
    )
}

#[test]
fn view_renders_frames_in_a_window_and_exits_cleanly() {
    let xvfb = Xvfb::start();
    for extra in [
        &["--vsync", "on"][..],
        &["--vsync", "off", "--frames-in-flight", "3"][..],
    ] {
        let mut args = vec![
            "builtin:spheres",
            "--width",
            "160",
            "--height",
            "120",
            "--frames",
            "5",
            "--validate",
        ];
        args.extend_from_slice(extra);
        let (code, stdout, stderr) = view(&format!(":{}", xvfb.display), &args);
        assert_eq!(
            code,
            Some(0),
            "{args:?}\nstdout: {stdout}\nstderr: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
        // No error and no logged warning (a driver's own banner would be tolerated).
        assert_quiet(&stderr);
        assert!(
            stdout.starts_with("viewed 5 frames at 160x120 on llvmpipe"),
            "{stdout}"
        );
        assert!(stdout.contains("on-device presentation"), "{stdout}");
        assert_eq!(stdout.lines().count(), 1, "{stdout}");
    }
    // One frame: too few to time the wall clock between frames, which the summary says
    // (it printed "median NaN ms").
    let (code, stdout, stderr) = view(
        &format!(":{}", xvfb.display),
        &[
            "builtin:spheres",
            "--width",
            "64",
            "--height",
            "48",
            "--frames",
            "1",
        ],
    );
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(
        stdout.starts_with("viewed 1 frame at 64x48")
            && stdout.contains("wall clock per frame median not measured")
            && !stdout.contains("NaN"),
        "{stdout}"
    );
    drop(xvfb);
    let (code, _, stderr) = view(":0", &["--vsync", "sometimes"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("invalid value 'sometimes' for '--vsync <on|off>'")
            && stderr.contains("[possible values: on, off]"),
        "{stderr}"
    );
    let (code, _, stderr) = view(":0", &["--screenshot", "shot.png"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("the following required arguments were not provided")
            && stderr.contains("--frames <N>"),
        "{stderr}"
    );
}

#[test]
fn view_without_a_display_is_a_one_line_error() {
    // A display number no X server listens on.
    let display = (200..300)
        .find(|n| !Path::new(&format!("/tmp/.X11-unix/X{n}")).exists())
        .expect("a free display number");
    let (code, stdout, stderr) = view(&format!(":{display}"), &["--frames", "1"]);
    assert!(
        matches!(code, Some(c) if c != 0),
        "must fail: {stdout}{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    let lines: Vec<_> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "one line expected: {stderr}");
    assert!(
        lines[0].starts_with("error: cannot open a window: ") && lines[0].contains("Xvfb"),
        "{stderr}"
    );
    assert!(stdout.is_empty(), "{stdout}");
}

/// A scripted run (`--camera-path`) with `--screenshot`: the PNG, copied from the
/// presented swapchain image, holds exactly what the headless renderer makes of the same
/// scene, camera and size — both are the same output pass with the same exact sRGB
/// encoding, into B8G8R8A8_UNORM and R8G8B8A8_UNORM, so byte equality is expected (a
/// FLIP threshold would only hide a difference).
#[test]
fn screenshot_of_a_scripted_run_equals_the_headless_render() {
    let xvfb = Xvfb::start();
    let display = format!(":{}", xvfb.display);
    scripted_screenshot_equals_headless("x11", |args| view(&display, args));
}

/// The same on Wayland (a headless Weston): the window, its surface and swapchain come
/// from the Wayland backend of winit and ash-window.
#[test]
fn screenshot_on_wayland_equals_the_headless_render() {
    let weston = Weston::start();
    scripted_screenshot_equals_headless("wayland", |args| view_on_wayland(&weston, args));
}

/// A scripted run: `combustion view SCENE` at `size` for `frames` frames along the camera
/// path `path_text`, with `--screenshot` and `extra` arguments, started by `run`. The
/// screenshot's pixels, and the scene with its camera at the last frame.
fn scripted_screenshot(
    name: &str,
    run: impl FnOnce(&[&str]) -> (Option<i32>, String, String),
    scene: &str,
    size: (u32, u32),
    frames: u32,
    path_text: &str,
    extra: &[&str],
) -> (Vec<[u8; 4]>, combustion::scene::Scene) {
    use combustion::viewer::camera::CameraPath;
    use combustion::viewer::PATH_FRAMES_PER_SECOND;

    let dir = std::env::temp_dir().join(format!("combustion-view-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path_file = dir.join("path.txt");
    std::fs::write(&path_file, path_text).unwrap();
    let shot = dir.join("shot.png");
    let (width, height, frame_count) = (size.0.to_string(), size.1.to_string(), frames.to_string());
    let mut args = vec![
        scene,
        "--width",
        &width,
        "--height",
        &height,
        "--frames",
        &frame_count,
        "--camera-path",
        path_file.to_str().unwrap(),
        "--screenshot",
        shot.to_str().unwrap(),
        "--validate",
    ];
    args.extend_from_slice(extra);
    let (code, stdout, stderr) = run(&args);
    assert_eq!(code, Some(0), "stdout: {stdout}\nstderr: {stderr}");
    assert!(stdout.contains("; screenshot "), "{stdout}");
    let (w, h, pixels) = common::read_png(&shot);
    assert_eq!((w, h), size);
    std::fs::remove_dir_all(dir).unwrap();
    // The last frame (frames − 1) is shown at (frames − 1)/30 s on the path.
    let mut scene = combustion::scene::builtin_scene(scene.trim_start_matches("builtin:")).unwrap();
    let path = CameraPath::parse(path_text).unwrap();
    scene.camera = path.at((frames - 1) as f32 / PATH_FRAMES_PER_SECOND, &scene.camera);
    (pixels, scene)
}

/// The headless render of `scene` at `width`×`height` as the viewer shows it by default:
/// the default settings with bloom on (the window's default) and FXAA (the viewer's
/// default anti-aliasing), metered by `auto_exposure` if given.
fn headless_as_viewed(
    scene: &combustion::scene::Scene,
    width: u32,
    height: u32,
    auto_exposure: Option<combustion::renderer::AutoExposure>,
) -> combustion::renderer::Frame {
    use combustion::renderer::{AntiAliasing, FrameInputs, Readback, RendererSettings};
    let mut settings = RendererSettings::default();
    let bloom = combustion::renderer::optional_pass("bloom").unwrap();
    settings.shading.optional_passes = settings.shading.optional_passes.with(bloom, true);
    let mut headless = common::lavapipe(settings);
    let frame = {
        let renderer = headless.renderer();
        let gpu = renderer.upload(scene).expect("upload");
        let inputs = FrameInputs {
            anti_aliasing: AntiAliasing::Fxaa,
            auto_exposure,
            ..FrameInputs::of_scene(&gpu, settings.exposure)
        };
        let readback = Readback::IMAGES;
        renderer
            .render_with(&gpu, &inputs, width, height, readback)
            .expect("render")
    };
    common::finish(headless);
    frame
}

/// Runs a scripted view with `run` and compares its screenshot with the headless
/// render of the same scene, camera and size (with bloom and FXAA, as the viewer by
/// default).
fn scripted_screenshot_equals_headless(
    name: &str,
    run: impl FnOnce(&[&str]) -> (Option<i32>, String, String),
) {
    let path_text = "# time eye target\n0  0 1 6  0 0 0\n1  3 1 5  0 0 0\n";
    let (pixels, scene) = scripted_screenshot(
        &format!("shot-{name}"),
        run,
        "builtin:spheres",
        (160, 120),
        7,
        path_text,
        &["--overlay", "off"],
    );
    let reference = headless_as_viewed(&scene, 160, 120, None);
    let lit = pixels.iter().filter(|p| p[..3] != [0, 0, 0]).count();
    assert!(
        lit > pixels.len() / 10,
        "the spheres are in view: {lit} lit pixels"
    );
    let differing = pixels
        .iter()
        .zip(&reference.ldr)
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differing, 0,
        "{differing} pixels differ from the headless render"
    );
}

/// How many of a screenshot's `pixels` differ from `frame`'s display image.
fn pixels_differing(pixels: &[[u8; 4]], frame: &combustion::renderer::Frame) -> usize {
    pixels
        .iter()
        .zip(&frame.ldr)
        .filter(|(a, b)| a != b)
        .count()
}

/// Auto exposure in the viewer (`--auto-exposure on`): a scripted run whose camera holds
/// still meters each frame's own radiance, so after its first frame (taken at once) every
/// frame stays at that target, and the screenshot is, byte for byte, the headless render
/// metered at once (with bloom and FXAA, as the viewer by default).
#[test]
fn the_viewer_meters_as_the_headless_render_does() {
    use combustion::renderer::AutoExposure;
    let xvfb = Xvfb::start();
    let display = format!(":{}", xvfb.display);
    let still = "# time eye target\n0  0 1 6  0 0 0\n1  0 1 6  0 0 0\n";
    let (pixels, scene) = scripted_screenshot(
        "auto-exposure",
        |args| view(&display, args),
        "builtin:spheres",
        (160, 120),
        5,
        still,
        &["--overlay", "off", "--auto-exposure", "on"],
    );
    let reference = headless_as_viewed(&scene, 160, 120, Some(AutoExposure::default()));
    let plain = headless_as_viewed(&scene, 160, 120, None);
    let differing = |other: &combustion::renderer::Frame| pixels_differing(&pixels, other);
    assert_eq!(differing(&reference), 0, "the metered headless render");
    // The metering changed the picture (it is not exposure 1's).
    assert!(differing(&plain) > 1000, "{}", differing(&plain));
}

/// `view --environment` lights the scene in place of the environment it comes with:
/// builtin:spheres-studio (the studio environment beside its lights) viewed with
/// `--environment none` is, byte for byte, the headless render of the scene without an
/// environment — and differs from the scene as it comes.
#[test]
fn the_viewer_lights_by_the_environment_asked_for() {
    let xvfb = Xvfb::start();
    let display = format!(":{}", xvfb.display);
    let still = "# time eye target\n0  0 1 6  0 0 0\n1  0 1 6  0 0 0\n";
    let (pixels, scene) = scripted_screenshot(
        "environment",
        |args| view(&display, args),
        "builtin:spheres-studio",
        (160, 120),
        3,
        still,
        &["--overlay", "off", "--environment", "none"],
    );
    assert!(scene.environment.is_some(), "the scene comes with one");
    let unlit = combustion::scene::Scene {
        environment: None,
        ..scene.clone()
    };
    let differing = |other: &combustion::renderer::Frame| pixels_differing(&pixels, other);
    let reference = headless_as_viewed(&unlit, 160, 120, None);
    assert_eq!(
        differing(&reference),
        0,
        "the render without an environment"
    );
    let as_it_comes = headless_as_viewed(&scene, 160, 120, None);
    assert!(
        differing(&as_it_comes) > 1000,
        "{}",
        differing(&as_it_comes)
    );
}

/// The viewer's renderer settings with the optional passes `passes` on, frames of
/// path tracing averaged on the GPU as the viewer's are (`accumulate_paths`).
fn viewer_settings(passes: &[&str]) -> combustion::renderer::RendererSettings {
    let mut settings = combustion::renderer::RendererSettings {
        accumulate_paths: true,
        ..Default::default()
    };
    for name in passes {
        let pass = combustion::renderer::optional_pass(name).unwrap();
        settings.shading.optional_passes = settings.shading.optional_passes.with(pass, true);
    }
    settings
}

/// `count` successive frames of `scene` (its own camera, exposure 1) rendered headless
/// with `settings` at `size`, the scene's inputs changed by `inputs`, each read back.
fn headless_frames(
    scene: &combustion::scene::Scene,
    settings: combustion::renderer::RendererSettings,
    (width, height): (u32, u32),
    count: u32,
    inputs: impl Fn(combustion::renderer::FrameInputs<'_>) -> combustion::renderer::FrameInputs<'_>,
) -> Vec<combustion::renderer::Frame> {
    let mut headless = common::lavapipe(settings);
    let frames = {
        let renderer = headless.renderer();
        let gpu = renderer.upload(scene).expect("upload");
        let inputs = inputs(combustion::renderer::FrameInputs::of_scene(
            &gpu,
            settings.exposure,
        ));
        (0..count)
            .map(|_| {
                renderer
                    .render_with(
                        &gpu,
                        &inputs,
                        width,
                        height,
                        combustion::renderer::Readback::IMAGES,
                    )
                    .expect("render")
            })
            .collect()
    };
    common::finish(headless);
    frames
}

/// A scripted run of builtin:spheres whose camera holds still for `frames` frames, with
/// `--OPTION on` (the optional pass `option`), shows byte for byte the last of as many
/// frames rendered headless with the viewer's settings (bloom and FXAA, as the viewer by
/// default, and the pass on), which differs from the first.
fn assert_a_still_run_shows_the_headless_frame(option: &str, frames: u32) {
    use combustion::renderer::{AntiAliasing, FrameInputs};
    let xvfb = Xvfb::start();
    let display = format!(":{}", xvfb.display);
    let still = "# time eye target\n0  0 1 6  0 0 0\n1  0 1 6  0 0 0\n";
    let flag = format!("--{option}");
    let (pixels, scene) = scripted_screenshot(
        option,
        |args| view(&display, args),
        "builtin:spheres",
        (160, 120),
        frames,
        still,
        &["--overlay", "off", &flag, "on"],
    );
    let shown = headless_frames(
        &scene,
        viewer_settings(&["bloom", option]),
        (160, 120),
        frames,
        |inputs| FrameInputs {
            anti_aliasing: AntiAliasing::Fxaa,
            ..inputs
        },
    );
    let differing = |other: &combustion::renderer::Frame| pixels_differing(&pixels, other);
    assert_eq!(differing(&shown[frames as usize - 1]), 0, "the last frame");
    assert!(differing(&shown[0]) > 100, "{}", differing(&shown[0]));
}

/// Temporal anti-aliasing in the viewer (`--temporal-anti-aliasing on`): a scripted run
/// whose camera holds still for 20 frames shows, byte for byte, the 20th frame of the
/// same sequence rendered headless (its jitter and history frame for frame; with bloom
/// and FXAA, as the viewer by default), which differs from one frame's.
#[test]
fn the_viewer_accumulates_as_the_headless_frames_do() {
    assert_a_still_run_shows_the_headless_frame("temporal-anti-aliasing", 20);
}

/// Path tracing in the viewer (`--path-trace on`) converges while the camera rests: a
/// scripted run holding still for 8 frames shows, byte for byte, the 8th frame of a
/// headless renderer that averages path-traced frames on the GPU
/// (`RendererSettings::accumulate_paths`; with bloom and FXAA, as the viewer by default),
/// which differs from one frame's paths alone.
#[test]
fn the_viewer_converges_a_path_traced_view_while_it_rests() {
    assert_a_still_run_shows_the_headless_frame("path-trace", 8);
}

/// The error view of a path-traced view (`--error-view --path-trace on`): once the mean
/// holds 64 paths a pixel, the screenshot is, byte for byte, the heat map of the
/// real-time frame's relative error against it — the real-time frame rendered headless
/// with the same inputs, the mean the 17th frame of a headless renderer that averages
/// path-traced frames on the GPU (the 16 the viewer showed, and the one the measurement
/// reads back) — and the map shows the real-time frame missing light that bounces.
#[test]
fn the_error_view_of_a_path_traced_view_is_the_real_time_frame_against_its_mean() {
    use combustion::renderer::reference::heat_map_color_in;
    use combustion::renderer::FrameInputs;
    use combustion::viewer::inspect::{transport_errors, TRANSPORT_HEAT_MAP_RANGE};
    let xvfb = Xvfb::start();
    let display = format!(":{}", xvfb.display);
    let (w, h) = (96, 72);
    let (pixels, scene) = scripted_screenshot(
        "transport",
        |args| view(&display, args),
        "builtin:cornell-box",
        (w, h),
        20,
        "0  0 1 0.95  0 0.85 -1\n1  0 1 0.95  0 0.85 -1\n",
        &["--overlay", "off", "--error-view", "--path-trace", "on"],
    );
    drop(xvfb);
    // Radiance without bloom's share, as the error view measures it.
    let last = |passes: &[&str], count: u32| {
        let frames = headless_frames(&scene, viewer_settings(passes), (w, h), count, |inputs| {
            FrameInputs {
                bloom_intensity: 0.0,
                ..inputs
            }
        });
        frames.into_iter().last().expect("a frame").hdr
    };
    let realtime = last(&["bloom"], 1);
    let traced = last(&["bloom", "path-trace"], 17);
    let (errors, summary) = transport_errors(&realtime, &traced, 68);
    let expected: Vec<[u8; 4]> = errors
        .iter()
        .map(|&e| heat_map_color_in(e, TRANSPORT_HEAT_MAP_RANGE))
        .collect();
    let differing = pixels.iter().zip(&expected).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "{differing} pixels differ from the heat map");
    // The real-time frame misses the box's emitter and every bounce: darker, and far
    // from the mean over most of the lit pixels.
    assert!(summary.compared > 3000, "{summary:?}");
    assert!(summary.brightness < -0.3, "{summary:?}");
    assert!(summary.mean_relative > 0.3, "{summary:?}");
}

/// The error view (`--error-view`, as the X key): the screenshot of a scripted run is,
/// byte for byte, the heat map of the f64 reference's relative error for the headless
/// render of the same scene, camera and size — the viewer shows the very error map the
/// library computes (`reference::error_map`), nothing else.
#[test]
fn the_error_view_shows_the_reference_error_map() {
    assert_error_view_is_the_reference_map("builtin:hard-cases");
}

/// The error view of an environment-lit scene (spheres-studio): the same, against the
/// reference that integrates the environment (one pixel in 4×4, 500 samples of each
/// strategy, the rest grey), as the viewer measures it.
#[test]
fn the_error_view_of_an_environment_lit_scene_is_the_reference_map() {
    assert_error_view_is_the_reference_map("builtin:spheres-studio");
}

/// A scripted `--error-view` run of `scene_name` at 192×128: its screenshot equals the
/// heat map of the library's error map for the headless frame, pixel for pixel.
fn assert_error_view_is_the_reference_map(scene_name: &str) {
    use combustion::renderer::reference::{
        error_map, heat_map_color, EnvironmentSampling, ReferenceShading,
    };
    use combustion::renderer::{Readback, RendererSettings};

    let xvfb = Xvfb::start();
    let display = format!(":{}", xvfb.display);
    let (pixels, scene) = scripted_screenshot(
        "error",
        |args| view(&display, args),
        scene_name,
        (192, 128),
        4,
        "0  1 1.5 6  0 0.2 0\n1  1 1.5 6  0 0.2 0\n",
        &["--overlay", "off", "--error-view"],
    );
    drop(xvfb);
    let frame = common::render(&scene, 192, 128, RendererSettings::default(), Readback::ALL);
    let inputs = common::frame_inputs(&scene, &scene.lights);
    let mut reference = ReferenceShading::new(&scene, &inputs, 192, 128);
    if let Some(environment) = &scene.environment {
        reference = reference.with_environment(
            environment.clone(),
            EnvironmentSampling {
                iterations: 500,
                stride: 4,
            },
        );
    }
    let map = error_map(&frame, &reference, 2);
    assert!(map.lit_pixels > 500, "{} pixels compared", map.lit_pixels);
    let expected: Vec<[u8; 4]> = map.relative.iter().map(|&e| heat_map_color(e)).collect();
    let differing = pixels.iter().zip(&expected).filter(|(a, b)| a != b).count();
    assert_eq!(
        differing, 0,
        "{scene_name}: {differing} pixels differ from the reference's heat map"
    );
    // The map is not uniform: errors span several colours.
    let mut colours: Vec<[u8; 4]> = expected.clone();
    colours.sort();
    colours.dedup();
    assert!(colours.len() > 20, "{} distinct colours", colours.len());
}

/// The statistics panel (on by default) is drawn over the frame in the top-left corner
/// and changes nothing else: the screenshot equals the headless render below the panel.
#[test]
fn the_statistics_panel_covers_only_its_corner() {
    let (width, height) = (480, 270);
    let xvfb = Xvfb::start();
    let display = format!(":{}", xvfb.display);
    // A camera held still: the same camera in both renders.
    let (pixels, scene) = scripted_screenshot(
        "panel",
        |args| view(&display, args),
        "builtin:spheres",
        (width, height),
        4,
        "0  0 1 6  0 0 0\n1  0 1 6  0 0 0\n",
        &[],
    );
    drop(xvfb);
    let reference = headless_as_viewed(&scene, width, height, None);
    let differing: Vec<(u32, u32)> = (0..width * height)
        .filter(|&i| pixels[i as usize] != reference.ldr[i as usize])
        .map(|i| (i % width, i / width))
        .collect();
    // Four lines of 15 px text (18 px apart) with padding and margin: under 100 px.
    assert!(differing.len() > 1000, "{} pixels differ", differing.len());
    let lowest = differing.iter().map(|&(_, y)| y).max().unwrap();
    assert!(lowest < 100, "a pixel at y = {lowest} differs");
    assert!(
        differing.iter().all(|&(x, _)| x >= 8),
        "the panel keeps its margin"
    );
}

#[test]
fn a_bad_camera_path_is_a_one_line_error_naming_file_and_line() {
    let dir = std::env::temp_dir().join(format!("combustion-view-path-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path_file = dir.join("bad.txt");
    std::fs::write(&path_file, "0 0 1 6 0 0 0\n0 1 1 6 0 0 0\n").unwrap();
    let (code, _, stderr) = view(":0", &["--camera-path", path_file.to_str().unwrap()]);
    // A bad input file, not bad usage: exit status 1.
    assert_eq!(code, Some(1), "{stderr}");
    let lines: Vec<_> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{stderr}");
    assert!(
        lines[0].contains("bad.txt:2: times must increase"),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// docs/usage.md's key table lists every key the viewer handles, with the same text.
#[test]
fn the_usage_page_lists_every_key() {
    let usage =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/usage.md")).unwrap();
    for (key, does) in combustion::viewer::KEYS {
        let row = format!("| {key} | {does} |");
        assert!(usage.contains(&row), "docs/usage.md lacks `{row}`");
    }
}

/// Runs `xdotool ARGS` on `display`; its output.
/// A viewer run under a test's X display with its log (info level) collected as it comes,
/// so that a test can wait for what the viewer says it handled.
struct LoggedViewer {
    child: std::process::Child,
    lines: std::sync::Arc<std::sync::Mutex<Vec<String>>>,
    reader: std::thread::JoinHandle<()>,
    display: String,
    /// The window's X id (xdotool's).
    window: String,
}

impl LoggedViewer {
    /// Runs `combustion view ARGS` in `dir` on `display` and waits (30 s at most) until
    /// it has made its swapchain; finds its window.
    fn start(display: &str, dir: &Path, args: &[&str]) -> LoggedViewer {
        let mut child = Command::new(env!("CARGO_BIN_EXE_combustion"))
            .arg("view")
            .args(args)
            .current_dir(dir)
            .env("DISPLAY", display)
            .env_remove("WAYLAND_DISPLAY")
            .env("COMBUSTION_DEVICE", "llvmpipe")
            // The viewer logs its swapchain at info level: the sign that its window is
            // up, so xdotool need not poll for it.
            .env("COMBUSTION_LOG", "info")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("run combustion");
        let lines = std::sync::Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
        let reader = {
            use std::io::BufRead;
            let stderr = child.stderr.take().unwrap();
            let lines = lines.clone();
            std::thread::spawn(move || {
                for line in std::io::BufReader::new(stderr)
                    .lines()
                    .map_while(Result::ok)
                {
                    lines.lock().unwrap().push(line);
                }
            })
        };
        let deadline = Instant::now() + Duration::from_secs(30);
        while !lines
            .lock()
            .unwrap()
            .iter()
            .any(|l| l.contains("swapchain:"))
        {
            assert!(
                Instant::now() < deadline,
                "the viewer never made its swapchain"
            );
            if child.try_wait().unwrap().is_some() {
                panic!(
                    "the viewer exited early: {}",
                    lines.lock().unwrap().join("\n")
                );
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let found = xdotool(display, &["search", "--name", "^combustion"]);
        let window = found
            .lines()
            .next()
            .expect("the viewer's window")
            .to_owned();
        LoggedViewer {
            child,
            lines,
            reader,
            display: display.to_owned(),
            window,
        }
    }

    /// Lines of the log containing `said`.
    fn logged(&self, said: &str) -> usize {
        self.lines
            .lock()
            .unwrap()
            .iter()
            .filter(|l| l.contains(said))
            .count()
    }

    /// Waits (10 s at most) until the log has more lines containing `said` than
    /// `before`: the viewer has handled the event that says it.
    fn await_log(&self, said: &str, before: usize, after_what: &str) {
        let deadline = Instant::now() + Duration::from_secs(10);
        while self.logged(said) <= before {
            assert!(
                Instant::now() < deadline,
                "after {after_what} the log never said `{said}`: {}",
                self.lines.lock().unwrap().join("\n")
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Presses Escape and waits (30 s at most, then kills it) for the viewer to exit:
    /// its exit code, standard output and log.
    fn quit(mut self) -> (Option<i32>, String, String) {
        xdotool(&self.display, &["key", "Escape"]);
        let deadline = Instant::now() + Duration::from_secs(30);
        while self.child.try_wait().unwrap().is_none() {
            if Instant::now() > deadline {
                let _ = self.child.kill();
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let out = self.child.wait_with_output().unwrap();
        self.reader.join().unwrap();
        let stderr = self.lines.lock().unwrap().join("\n");
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr,
        )
    }
}

/// F5 loads the scene again, and a scene file that changes on disk is reloaded (the
/// viewer looks once a second); a change that breaks the file is a logged error and the
/// scene shown stays; the file mended, it is loaded again. Drag and drop opens files
/// through the same `load` (`WindowEvent::DroppedFile`); Xvfb has no drag source to
/// test it with.
#[test]
fn f5_and_a_changed_file_reload_the_scene() {
    let xvfb = Xvfb::start();
    let display = format!(":{}", xvfb.display);
    let dir = std::env::temp_dir().join(format!("combustion-view-reload-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The project's optics scene with its buffer and its measured-metal table.
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/optics");
    for entry in std::fs::read_dir(&source).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, dir.join(path.file_name().unwrap())).unwrap();
    }
    let scene = dir.join("optics.gltf");
    let text = std::fs::read_to_string(&scene).unwrap();
    let viewer = LoggedViewer::start(
        &display,
        &dir,
        &[
            scene.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
            "--validate",
        ],
    );
    let loaded = "optics.gltf: loaded";
    let changed = "changed on disk, reloading";
    xdotool(&display, &["windowfocus", &viewer.window]);
    viewer.await_log("window focused", 0, "focusing the window");
    let before = viewer.logged(loaded);
    xdotool(&display, &["key", "F5"]);
    viewer.await_log(loaded, before, "F5");
    // A newer modification time: reloaded within about a second.
    let touch = |seconds: u64| {
        let file = std::fs::File::options().write(true).open(&scene).unwrap();
        file.set_modified(std::time::SystemTime::now() + Duration::from_secs(seconds))
            .unwrap();
    };
    let (before_change, before_load) = (viewer.logged(changed), viewer.logged(loaded));
    touch(10);
    viewer.await_log(changed, before_change, "touching the file");
    viewer.await_log(loaded, before_load, "touching the file");
    // Broken: an error, and the viewer goes on with the scene it shows.
    std::fs::write(&scene, "{ not glTF").unwrap();
    touch(20);
    let errors = viewer.logged("error: ");
    viewer.await_log("error: ", errors, "breaking the file");
    let before_load = viewer.logged(loaded);
    std::fs::write(&scene, &text).unwrap();
    touch(30);
    viewer.await_log(loaded, before_load, "mending the file");
    let (code, stdout, stderr) = viewer.quit();
    drop(xvfb);
    assert_eq!(code, Some(0), "stdout: {stdout}\nstderr: {stderr}");
    // The one error is the broken file's, naming it.
    let error_lines: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("error: "))
        .collect();
    assert_eq!(error_lines.len(), 1, "{stderr}");
    assert!(error_lines[0].contains("optics.gltf"), "{}", error_lines[0]);
    std::fs::remove_dir_all(dir).unwrap();
}

fn xdotool(display: &str, args: &[&str]) -> String {
    let out = Command::new("xdotool")
        .args(args)
        .env("DISPLAY", display)
        .output()
        .expect("run xdotool (install xdotool: bash scripts/dev.sh test does)");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Keys and the mouse, typed into the window by xdotool (real X input events): a
/// built-in scene switched in, the Fresnel, diffuse and medium toggles, exposure, frame
/// and reset, every debug view, an orbit drag, zoom, a resize of the window, a
/// screenshot key, and Escape.
/// The run ends cleanly with no validation message (synchronization included), and the
/// screenshot is written.
#[test]
fn keys_and_mouse_drive_the_viewer() {
    let xvfb = Xvfb::start();
    let display = format!(":{}", xvfb.display);
    let dir = std::env::temp_dir().join(format!("combustion-view-keys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let viewer = LoggedViewer::start(
        &display,
        &dir,
        &[
            "builtin:spheres",
            "--width",
            "160",
            "--height",
            "120",
            "--validate",
        ],
    );
    let window = viewer.window.clone();
    let logged = |said: &str| viewer.logged(said);
    let await_log =
        |said: &str, before: usize, after_what: &str| viewer.await_log(said, before, after_what);
    xdotool(&display, &["windowfocus", &window]);
    // Focused once at least (it may have been before this asked for it).
    await_log("window focused", 0, "focusing the window");
    xdotool(&display, &["mousemove", "--window", &window, "80", "60"]);
    // Each key, and what the window's title must say after it (it names the scene, the
    // debug view and every toggle).
    let mut keys = vec![
        ("2", "builtin:hard-cases"),
        ("g", "Schlick (comparison)"),
        ("m", "diffuse Lambert"),
        ("o", "medium air"),
        ("plus", "exposure 1.41"),
        ("f", "exposure 1.41"),
        ("r", "exposure 1.41"),
        ("m", "diffuse Oren–Nayar qualitative"),
        ("o", "medium η 1.33"),
        ("g", "F82 (comparison)"),
        ("g", "full Fresnel"),
        ("minus", "exposure 1.00"),
        ("1", "builtin:spheres"),
    ];
    // Every debug view once, and back to radiance.
    for view in combustion::renderer::DebugView::ALL
        .iter()
        .skip(1)
        .chain([&combustion::renderer::DebugView::None])
    {
        keys.push(("v", view.name()));
    }
    keys.extend([
        // The error view: measured (the frame re-shaded in f64), then off again.
        ("x", "error view max"),
        ("x", "radiance"),
        // A typed outside medium.
        ("i", "typing η _"),
        ("1", "typing η 1_"),
        ("period", "typing η 1._"),
        ("5", "typing η 1.5_"),
        ("Return", "medium η 1.5"),
    ]);
    for (key, expected) in keys {
        xdotool(&display, &["key", key]);
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            let title = xdotool(&display, &["getwindowname", &window]);
            // Each state's words; the error view's only while it is on.
            let error_view_ok = expected.contains("error view") || !title.contains("error view");
            if title.contains(expected) && error_view_ok {
                break;
            }
            assert!(
                Instant::now() < deadline,
                "after `{key}` the title is `{}`, not naming `{expected}`",
                title.trim()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }
    // Help, statistics panel, next camera: they leave the title alone and say what they
    // did in the log (info level).
    for (key, said) in [
        ("h", "help panel shown"),
        ("Tab", "statistics panel hidden"),
        ("Tab", "statistics panel shown"),
        ("c", "camera 1 of 1"),
    ] {
        let before = logged(said);
        xdotool(&display, &["key", key]);
        await_log(said, before, &format!("`{key}`"));
    }
    xdotool(&display, &["mousedown", "1"]);
    xdotool(&display, &["mousemove", "--window", &window, "120", "70"]);
    xdotool(&display, &["mouseup", "1"]);
    xdotool(&display, &["click", "4"]);
    xdotool(&display, &["windowsize", &window, "200", "150"]);
    await_log("images of 200x150", 0, "resizing to 200x150");
    // Minimised and restored as a window manager does it (Xvfb has none to ask): the
    // window marked _NET_WM_STATE_HIDDEN and unmapped, then the mark removed and the
    // window mapped and focused. The viewer stops drawing while minimised and draws
    // again afterwards.
    let xprop = |args: &[&str]| {
        let status = Command::new("xprop")
            .args(["-id", &window])
            .args(args)
            .env("DISPLAY", &display)
            .status()
            .expect("run xprop");
        assert!(status.success(), "xprop {args:?}");
    };
    let paused = logged("drawing paused (window hidden)");
    xprop(&[
        "-f",
        "_NET_WM_STATE",
        "32a",
        "-set",
        "_NET_WM_STATE",
        "_NET_WM_STATE_HIDDEN",
    ]);
    xdotool(&display, &["windowunmap", &window]);
    await_log(
        "drawing paused (window hidden)",
        paused,
        "minimising the window",
    );
    let resumed = logged("drawing resumed");
    xprop(&["-remove", "_NET_WM_STATE"]);
    let shown = logged("window shown");
    xdotool(&display, &["windowmap", &window]);
    await_log("window shown", shown, "mapping the window again");
    let focused = logged("window focused");
    xdotool(&display, &["windowfocus", &window]);
    await_log("window focused", focused, "focusing the window again");
    await_log("drawing resumed", resumed, "restoring the window");
    xdotool(&display, &["key", "p"]);
    await_log("screenshot written", 0, "`p`");
    let (code, stdout, stderr) = viewer.quit();
    drop(xvfb);
    // Info lines are expected (the swapchain's); warnings and errors are not.
    assert_eq!(code, Some(0), "stdout: {stdout}\nstderr: {stderr}");
    assert_quiet(&stderr);
    assert!(
        stdout.contains("; screenshot combustion-0001.png"),
        "{stdout}"
    );
    let (width, height, _) = common::read_png(&dir.join("combustion-0001.png"));
    assert_eq!(
        (width, height),
        (200, 150),
        "the screenshot has the resized window's size"
    );
    std::fs::remove_dir_all(dir).unwrap();
}
