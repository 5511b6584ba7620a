//! The command-line tool: a render produces a PNG and an EXR; bad input gets a one-line
//! error and a non-zero exit, never a panic, and leaves no file behind.

use std::process::Command;

fn combustion(args: &[&str]) -> (i32, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_combustion"))
        .args(args)
        .env("COMBUSTION_DEVICE", "llvmpipe")
        .output()
        .expect("run combustion");
    (
        output.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("combustion-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A failed run: non-zero exit, exactly one `error:` line naming `expected`, no panic.
fn assert_clear_error(args: &[&str], expected: &str) {
    let (code, _stdout, stderr) = combustion(args);
    assert_ne!(code, 0, "{args:?} must fail");
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    let errors: Vec<_> = stderr
        .lines()
        .filter(|l| l.starts_with("error: "))
        .collect();
    assert_eq!(
        errors.len(),
        1,
        "{args:?}: one error line expected, got {stderr}"
    );
    assert!(
        errors[0].contains(expected),
        "{args:?}: `{}` should mention `{expected}`",
        errors[0]
    );
}

#[test]
fn render_writes_png_and_exr() {
    let dir = scratch("render");
    let png = dir.join("spheres.png");
    let exr = dir.join("spheres.exr");
    let (code, stdout, stderr) = combustion(&[
        "render",
        "--scene",
        "builtin:spheres",
        "--width",
        "96",
        "--height",
        "64",
        "-o",
        png.to_str().unwrap(),
        "--hdr",
        exr.to_str().unwrap(),
        "--validate",
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let png_bytes = std::fs::read(&png).unwrap();
    assert_eq!(&png_bytes[..8], b"\x89PNG\r\n\x1a\n");
    let exr_bytes = std::fs::read(&exr).unwrap();
    assert_eq!(&exr_bytes[..4], &[0x76, 0x2f, 0x31, 0x01]);
    // Header, 64 offsets, 64 scanlines of 8 + 3·4·96 bytes.
    assert!(exr_bytes.len() > 64 * 8 + 64 * (8 + 3 * 4 * 96));
    // Nothing but the two outputs is left in the folder (no partial files).
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert_eq!(names, ["spheres.exr", "spheres.png"]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn unknown_scene() {
    assert_clear_error(
        &["render", "--scene", "builtin:teapot"],
        "unknown built-in scene `teapot`",
    );
}

#[test]
fn scene_files_are_refused_clearly_until_supported() {
    assert_clear_error(&["render", "--scene", "scene.gltf"], "scene.gltf");
}

#[test]
fn zero_size() {
    assert_clear_error(&["render", "--width", "0"], "at least 1");
}

#[test]
fn absurd_size() {
    let dir = scratch("absurd");
    let out = dir.join("x.png");
    assert_clear_error(
        &[
            "render",
            "--width",
            "1000000",
            "--height",
            "8",
            "-o",
            out.to_str().unwrap(),
        ],
        "between 1 and",
    );
    assert!(!out.exists());
}

#[test]
fn not_a_number() {
    assert_clear_error(&["render", "--height", "tall"], "--height");
}

#[test]
fn unwritable_output() {
    assert_clear_error(
        &["render", "-o", "/nonexistent-folder/out.png"],
        "/nonexistent-folder",
    );
}

#[test]
fn output_is_a_folder() {
    let dir = scratch("folder");
    assert_clear_error(&["render", "-o", dir.to_str().unwrap()], "folder");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn unknown_device() {
    assert_clear_error(
        &["render", "--device", "no-such-gpu"],
        "no Vulkan device matches `no-such-gpu`",
    );
    assert_clear_error(&["render", "--device", "7"], "no Vulkan device matches `7`");
}

#[test]
fn no_vulkan_driver() {
    // Point the loader at no driver at all: the same path a machine without
    // mesa-vulkan-drivers takes.
    let output = Command::new(env!("CARGO_BIN_EXE_combustion"))
        .args(["render", "-o", "/tmp/never-written.png"])
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(!stderr.contains("panicked"), "{stderr}");
    let error = stderr
        .lines()
        .find(|l| l.starts_with("error: "))
        .expect("an error line");
    assert!(
        error.contains("mesa-vulkan-drivers"),
        "must say what to install: {error}"
    );
}

#[test]
fn unknown_command_and_flag() {
    assert_clear_error(&["paint"], "unknown command `paint`");
    assert_clear_error(
        &["render", "--colour", "red"],
        "unknown argument `--colour`",
    );
}

#[test]
fn devices_lists_lavapipe() {
    let (code, stdout, stderr) = combustion(&["devices"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("llvmpipe"), "{stdout}");
}

#[test]
fn eval_prints_json_for_a_term() {
    // Gold at normal incidence with the RGB constants of assets/spectra/README.md: the
    // reflectance ((η−1)² + k²)/((η+1)² + k²) computed by hand for the red channel is
    // ((0.1132−1)² + 4.0955²)/((1.1132)² + 4.0955²) = 17.5596/18.0124 = 0.97486.
    let (code, stdout, stderr) = combustion(&[
        "eval",
        "fresnel-conductor",
        "--theta-v",
        "0",
        "--theta-l",
        "0",
        "--eta",
        "0.1132",
        "--k",
        "4.0955",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let r = stdout
        .split("\"r\": [")
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap();
    let r: f64 = r.trim().parse().unwrap();
    assert!((r - 0.974_86).abs() < 1e-5, "{stdout}");
    assert!(stdout.trim_start().starts_with('{') && stdout.trim_end().ends_with('}'));
}

#[test]
fn eval_total_internal_reflection_is_exactly_one() {
    // An air bubble under water (ηi = 1.33 > η = 1) past the critical angle (48.75°).
    let (code, stdout, _) = combustion(&[
        "eval",
        "fresnel-dielectric",
        "--theta-v",
        "60",
        "--theta-l",
        "60",
        "--phi-l",
        "180",
        "--eta",
        "1.0",
        "--eta-i",
        "1.33",
    ]);
    assert_eq!(code, 0);
    assert!(
        stdout.contains("\"r\": 1.0,") && stdout.contains("\"rs\": 1.0"),
        "{stdout}"
    );
}

#[test]
fn eval_bad_input() {
    assert_clear_error(
        &[
            "eval",
            "d-ggx",
            "--theta-v",
            "0",
            "--theta-l",
            "0",
            "--alpha",
            "-1",
        ],
        "outside",
    );
    assert_clear_error(&["eval", "d-gx"], "unknown term `d-gx`");
    assert_clear_error(
        &["eval", "fresnel-conductor", "--eta", "1,2"],
        "takes 1 or 3 value(s)",
    );
    assert_clear_error(
        &[
            "eval", "d-ggx", "--v", "0,0,1", "--l", "0,0,-1", "--alpha", "0.5",
        ],
        "opposite",
    );
    assert_clear_error(&["eval", "lambert", "--rho", "NaN"], "not finite");
    assert_clear_error(&["eval", "d-ggx", "--theta-v", "10"], "needs m");
}
