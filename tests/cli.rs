//! The command-line tool: a render produces a PNG and an EXR; bad input gets a one-line
//! error and a non-zero exit, never a panic, and leaves no file behind.

use crate::common;

use std::process::Command;

use common::combustion;

fn scratch(name: &str) -> common::Scratch {
    common::Scratch::new("cli", name)
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

/// A command line refused as bad usage (clap's message, or a check after parsing): exit
/// status 2, one `error:` line, no panic, and every one of `expected` in what it printed
/// (clap adds the possible values, a tip and the usage on the lines after).
fn assert_refused(args: &[&str], expected: &[&str]) {
    assert_clear_error(args, "");
    let (code, _stdout, stderr) = combustion(args);
    assert_eq!(code, 2, "{args:?} is a usage error: {stderr}");
    for part in expected {
        assert!(
            stderr.contains(part),
            "{args:?}: `{stderr}` should mention `{part}`"
        );
    }
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
    // 96×64 RGB f32 radiance, ZIP-compressed: it reads back as such (exr crate).
    let image = exr::prelude::read_first_rgba_layer_from_file(
        &exr,
        |resolution, _| (resolution.width(), resolution.height()),
        |_: &mut (usize, usize), _, _: (f32, f32, f32, f32)| {},
    )
    .unwrap();
    assert_eq!(image.layer_data.channel_data.pixels, (96, 64));
    assert!(
        exr_bytes.len() < 96 * 64 * 12,
        "compressed: {} bytes",
        exr_bytes.len()
    );
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
    assert_refused(
        &["render", "--width", "0"],
        &["invalid value '0' for '--width <N>': is 0; it must be at least 1"],
    );
}

/// A side the command line takes (at most 65536) but no device does (they take at most
/// 32768): the device's limit, named, and nothing written.
#[test]
fn absurd_size() {
    let dir = scratch("absurd");
    let out = dir.join("x.png");
    assert_clear_error(
        &[
            "render",
            "--width",
            "65536",
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
fn unknown_fresnel_model_or_hdr_format() {
    assert_refused(
        &["render", "--fresnel", "fast"],
        &[
            "invalid value 'fast' for '--fresnel <MODEL>'",
            "[possible values: full, schlick, f82]",
        ],
    );
    assert_refused(
        &["bench", "--hdr-format", "f8"],
        &[
            "invalid value 'f8' for '--hdr-format <FORMAT>'",
            "[possible values: f16, f32]",
        ],
    );
}

/// One option chooses how the scene blocks the environment: a way it does not have is a
/// one-line error listing those it has; each way it has runs its pass (its timing printed)
/// and none runs neither; asked of a scene lit by no environment, it says there is
/// nothing to block, in one warning line, and runs nothing.
#[test]
fn environment_occlusion_is_one_option_of_named_ways() {
    assert_refused(
        &["render", "--environment-occlusion", "ssao"],
        &[
            "invalid value 'ssao' for '--environment-occlusion <WAY>'",
            "[possible values: none, gtao, ray-traced]",
        ],
    );
    assert_refused(
        &["render", "--ambient-occlusion", "on"],
        &["unexpected argument '--ambient-occlusion'"],
    );
    let dir = scratch("environment-occlusion");
    // A 32×24 render of `scene` with `way`: (exit status, standard output, error).
    let render = |scene: &str, way: &str| {
        let out = dir.join(format!("{way}.png"));
        combustion(&[
            "render",
            scene,
            "--width",
            "32",
            "--height",
            "24",
            "--environment-occlusion",
            way,
            "-o",
            out.to_str().unwrap(),
        ])
    };
    for (way, pass) in [
        ("none", None),
        ("gtao", Some("ambient occlusion")),
        ("ray-traced", Some("ray-traced occlusion")),
    ] {
        let (code, stdout, stderr) = render("builtin:resting", way);
        assert_eq!(code, 0, "{way}: {stderr}");
        let timings = stdout
            .lines()
            .find(|l| l.starts_with("GPU time:"))
            .unwrap_or_default();
        for name in ["ambient occlusion", "ray-traced occlusion"] {
            assert_eq!(
                timings.contains(&format!("{name} ")),
                pass == Some(name),
                "{way}: {timings}"
            );
        }
        assert!(!stderr.contains("nothing to block"), "{way}: {stderr}");
    }
    let (code, stdout, stderr) = render("builtin:spheres", "gtao");
    assert_eq!(code, 0, "{stderr}");
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains("nothing to block"))
        .collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(
        warnings[0].contains(
            "builtin:spheres: --environment-occlusion gtao: the scene is lit by no environment"
        ),
        "{}",
        warnings[0]
    );
    assert!(!stdout.contains("ambient occlusion "), "{stdout}");
}

#[test]
fn bad_environments_are_one_line_errors() {
    assert_refused(
        &["render", "--environment", "sunset"],
        &["invalid value 'sunset' for '--environment <ENVIRONMENT>': is not studio, none, uniform:R,G,B or an .hdr or .exr file"],
    );
    assert_refused(
        &["render", "--environment", "uniform:1,2"],
        &["is not uniform:L or uniform:R,G,B"],
    );
    assert_refused(
        &["render", "--environment", "uniform:1,x,3"],
        &["invalid value 'uniform:1,x,3'", "`x` is not a number"],
    );
    // Finite as an f64 but not as the f32 the renderer keeps; finite as an f32 but
    // beyond what the shading's products keep finite (issue 28, defect 3).
    for big in ["1e39", "3e38", "5e36"] {
        assert_refused(
            &["render", "--environment", &format!("uniform:{big}")],
            &[&format!("`{big}` must be between 0 and 1e30 (a radiance")],
        );
    }
    assert_clear_error(
        &[
            "render",
            "--environment",
            "uniform:1,-2,3",
            "--width",
            "8",
            "--height",
            "8",
        ],
        "must be between 0 and 1e30",
    );
    let dir = scratch("environment");
    let missing = dir.join("missing.hdr");
    assert_clear_error(
        &["render", "--environment", missing.to_str().unwrap()],
        "missing.hdr",
    );
    let out = dir.join("out.png");
    let (code, _, stderr) = combustion(&[
        "render",
        "--environment",
        "uniform:0.5",
        "--width",
        "16",
        "--height",
        "16",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(out.exists());
}

#[test]
fn not_a_number() {
    assert_refused(
        &["render", "--height", "tall"],
        &["invalid value 'tall' for '--height <N>': is not a valid number"],
    );
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

/// A file where a folder is needed is named as such: as the folder of `-o` (it said the
/// folder did not exist), as `--report`'s folder or a parent of it (it said "File exists
/// (os error 17)"); and `-o /dev/stdout` into a pipe is refused as not a regular file (it
/// said "No such file or directory": the link ends in `pipe:[N]`).
#[test]
fn a_file_where_a_folder_is_needed_is_named() {
    let dir = scratch("file-in-the-way");
    let file = dir.join("afile");
    std::fs::write(&file, b"mine").unwrap();
    let file = file.to_str().unwrap();
    assert_clear_error(
        &["render", "-o", &format!("{file}/x.png")],
        &format!("{file} is a file, not a folder"),
    );
    for report in [file.to_owned(), format!("{file}/sub")] {
        assert_clear_error(
            &[
                "bench",
                "builtin:spheres",
                "--frames",
                "2",
                "--report",
                &report,
            ],
            &format!("cannot write {report}: {file} is a file, not a folder"),
        );
    }
    assert_eq!(std::fs::read(file).unwrap(), b"mine");
    // The test's own stdout is a pipe.
    assert_clear_error(
        &[
            "render",
            "-o",
            "/dev/stdout",
            "--width",
            "8",
            "--height",
            "8",
        ],
        "cannot write /dev/stdout: it is not a regular file",
    );
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
    assert_refused(&["paint"], &["unrecognized subcommand 'paint'"]);
    assert_refused(
        &["render", "--colour", "red"],
        &["unexpected argument '--colour' found"],
    );
}

#[test]
fn devices_lists_lavapipe() {
    let (code, stdout, stderr) = combustion(&["devices"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("llvmpipe"), "{stdout}");
    // The device type in words, not Vulkan's enum.
    assert!(stdout.contains("(CPU, Vulkan "), "{stdout}");
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
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let r = json["result"]["r"][0].as_f64().unwrap();
    assert!((r - 0.974_86).abs() < 1e-5, "{stdout}");
    assert_eq!(json["term"], "fresnel-conductor");
    assert_eq!(json["input"]["eta"], 0.1132);
}

/// Issue 9, `eval` output: one key for the input as given, one for what was evaluated,
/// one for the result (a vector input no longer repeats `v`, `l`, `m`); α = 0 says the
/// clamped α it was evaluated at; a direction given as angles at θ = 90° equals the same
/// direction given as a vector (n·l exactly 0, not 6e-17).
#[test]
fn eval_json_has_one_key_each_and_says_what_it_evaluated() {
    let run = |args: &[&str]| -> serde_json::Value {
        let (code, stdout, stderr) = combustion(args);
        assert_eq!(code, 0, "{stderr}");
        // serde_json refuses nothing here, but a repeated key would show in the text.
        for key in ["\"v\":", "\"l\":", "\"m\":"] {
            assert!(stdout.matches(key).count() <= 2, "{key} repeated: {stdout}");
        }
        serde_json::from_str(&stdout).unwrap()
    };
    let json = run(&[
        "eval", "d-ggx", "--v", "0.3,0,1", "--l", "-0.3,0,1", "--alpha", "0",
    ]);
    assert_eq!(json["input"]["alpha"], 0.0);
    assert_eq!(json["used"]["alpha_x"], combustion::optics::ALPHA_MIN);
    assert_eq!(json["input"]["v"], serde_json::json!([0.3, 0.0, 1.0]));
    let used_v = json["used"]["v"][2].as_f64().unwrap();
    assert!((used_v - 1.0 / 1.09f64.sqrt()).abs() < 1e-15, "{json}");

    let angles = run(&[
        "eval",
        "brdf",
        "--theta-v",
        "30",
        "--theta-l",
        "90",
        "--alpha",
        "0.5",
    ]);
    let vector = run(&[
        "eval",
        "brdf",
        "--theta-v",
        "30",
        "--l",
        "1,0,0",
        "--alpha",
        "0.5",
    ]);
    assert_eq!(angles["used"]["l"][2], 0.0);
    assert_eq!(angles["result"], vector["result"], "{angles} {vector}");
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
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(json["result"]["r"], 1.0, "{stdout}");
    assert_eq!(json["result"]["rs"], 1.0, "{stdout}");
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
    assert_refused(
        &["eval", "d-gx"],
        &[
            "invalid value 'd-gx' for '[TERM]'",
            "a similar value exists: 'd-ggx'",
        ],
    );
    assert_refused(
        &["eval", "fresnel-conductor", "--eta", "1,2"],
        &["invalid value '1,2' for '--eta <X|R,G,B>': takes 1 or 3 value(s), got 2"],
    );
    assert_refused(
        &["eval"],
        &[
            "the following required arguments were not provided",
            "<TERM>",
        ],
    );
    assert_clear_error(
        &[
            "eval", "d-ggx", "--v", "0,0,1", "--l", "0,0,-1", "--alpha", "0.5",
        ],
        "opposite",
    );
    assert_clear_error(&["eval", "lambert", "--rho", "NaN"], "not finite");
    assert_clear_error(&["eval", "d-ggx", "--theta-v", "10"], "needs m");
    // Issue 28, defect 9: two ways of saying one thing are refused, not resolved silently.
    assert_clear_error(
        &[
            "eval",
            "lambda-ggx",
            "--v",
            "0,0,1",
            "--theta-v",
            "10",
            "--alpha",
            "0.5",
        ],
        "give --v or --theta-v, not both",
    );
    assert_clear_error(
        &[
            "eval",
            "d-ggx",
            "--m",
            "0,0,1",
            "--alpha",
            "0.2",
            "--roughness",
            "0.3",
        ],
        "give --alpha or --roughness, not both",
    );
    // Two ways of giving one quantity: one took the other's place without a word.
    assert_clear_error(
        &[
            "eval",
            "lambda-ggx",
            "--theta-v",
            "30",
            "--alpha",
            "0.3",
            "--alpha-x",
            "0.2",
            "--alpha-y",
            "0.4",
        ],
        "give --alpha (or --roughness), or --alpha-x and --alpha-y, not both",
    );
    assert_clear_error(
        &[
            "eval",
            "fresnel-schlick",
            "--theta-v",
            "30",
            "--theta-l",
            "30",
            "--f0",
            "0.04",
            "--eta",
            "1.5",
        ],
        "give --f0 or --eta (F0 from η and ηi), not both",
    );
}

/// Issue 28, defect 9: a direction is normalised by its largest component first, so a
/// huge one is not lost to overflow (1e200: its square is infinite) nor a tiny one to
/// underflow (1e-200): both are the direction they point in.
#[test]
fn eval_directions_of_any_magnitude_are_normalised() {
    for v in ["1e200,0,0", "1e-200,0,1e-200"] {
        let out = Command::new(env!("CARGO_BIN_EXE_combustion"))
            .args(["eval", "lambda-ggx", "--v", v, "--alpha", "0.5"])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{v}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let used = &json["used"]["v"];
        let expected: [f64; 3] = if v.starts_with("1e200") {
            [1.0, 0.0, 0.0]
        } else {
            [
                std::f64::consts::FRAC_1_SQRT_2,
                0.0,
                std::f64::consts::FRAC_1_SQRT_2,
            ]
        };
        for (c, e) in expected.iter().enumerate() {
            let got = used[c].as_f64().unwrap_or(f64::NAN);
            assert!((got - e).abs() < 1e-15, "{v}: {json}");
        }
        assert!(json["result"]["value"].as_f64().is_some(), "{v}: {json}");
    }
}

/// Width and height from a PNG's IHDR chunk, after checking the signature.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR", "first chunk is IHDR");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

fn repo_file(path: &str) -> String {
    format!("{}/{path}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn plot_writes_pngs_of_the_requested_size() {
    let dir = scratch("plot");
    let out = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    let copper = repo_file("assets/scenes/optics/copper.csv");
    let runs: [(&[&str], &str, (u32, u32)); 6] = [
        (
            &[
                "reflectance",
                "--metal",
                "gold",
                "--width",
                "320",
                "--height",
                "200",
            ],
            "gold.png",
            (320, 200),
        ),
        (
            &[
                "reflectance",
                "--dielectric",
                "1.0",
                "--outside-ior",
                "1.33",
                "--polarisation",
                "0",
            ],
            "bubble.png",
            (800, 500),
        ),
        (
            &["reflectance", "--eta", "0.2,0.9,1.1", "--k", "3.9,2.6,2.5"],
            "eta-k.png",
            (800, 500),
        ),
        (&["reflectance", "--csv", &copper], "copper.png", (800, 500)),
        (
            &[
                "spectrum", "--metal", "Au", "--width", "400", "--height", "300",
            ],
            "gold-nk.png",
            (400, 300),
        ),
        (
            &["dielectrics", "--etas", "1.1,1.5,2.4"],
            "fig12.png",
            (800, 500),
        ),
    ];
    let mut expected_files = Vec::new();
    for (args, name, size) in runs {
        let path = out(name);
        let mut full = vec!["plot"];
        full.extend_from_slice(args);
        full.extend_from_slice(&["-o", &path]);
        let (code, stdout, stderr) = combustion(&full);
        assert_eq!(code, 0, "{full:?}: {stdout}{stderr}");
        assert!(stdout.contains("wrote"), "{stdout}");
        assert_eq!(png_size(&std::fs::read(&path).unwrap()), size, "{name}");
        expected_files.push(name.to_owned());
    }
    // Nothing but the plots is left in the folder (no partial files).
    expected_files.sort();
    assert_eq!(common::listing(&dir), expected_files);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn plot_spectrum_of_a_csv_and_the_default_output_name() {
    let dir = scratch("plot-default");
    let output = Command::new(env!("CARGO_BIN_EXE_combustion"))
        .args([
            "plot",
            "spectrum",
            "--csv",
            &repo_file("assets/scenes/optics/copper.csv"),
        ])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(output.status.success(), "{output:?}");
    let bytes = std::fs::read(dir.join("spectrum.png")).unwrap();
    assert_eq!(png_size(&bytes), (800, 600));
    std::fs::remove_dir_all(dir).unwrap();
}

/// Exit status 2 (bad usage) and a one-line error mentioning `expected`.
fn assert_usage_error(args: &[&str], expected: &str) {
    assert_refused(args, &[expected]);
}

/// Issue 28, defect 9: a spectral table `render` refuses (n = 1e300: its RGB constants
/// overflow) was drawn by `plot`; both read it through one rule and refuse it.
#[test]
fn plot_refuses_a_table_render_refuses() {
    let dir = scratch("plot-huge-n");
    let csv = dir.join("huge.csv");
    let mut table = String::from("wavelength_nm,n,k\n");
    for nm in (400..=760).step_by(10) {
        let n = if nm == 550 { "1e300" } else { "1.5" };
        table.push_str(&format!("{nm},{n},1\n"));
    }
    std::fs::write(&csv, table).unwrap();
    let out = dir.join("never.png");
    for kind in ["spectrum", "reflectance"] {
        assert_clear_error(
            &[
                "plot",
                kind,
                "--csv",
                csv.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ],
            "line 17: n 1e300 is above 1e6, beyond any material's optical constants",
        );
        assert!(!out.exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn plot_bad_input() {
    let dir = scratch("plot-bad");
    let out = dir.join("never.png");
    let o = out.to_str().unwrap();
    assert_usage_error(
        &["plot", "reflectance", "--metal", "unobtainium", "-o", o],
        "invalid value 'unobtainium' for '--metal <NAME>': not a built-in metal; built-in metals: gold, silver",
    );
    assert_usage_error(
        &["plot", "spectrum", "--metal", "kryptonite", "-o", o],
        "invalid value 'kryptonite' for '--metal <NAME>'",
    );
    assert_usage_error(
        &["plot", "dielectrics", "--etas", "1.1,glass,2.4", "-o", o],
        "for '--etas <E,E,...>': `glass` is not a number",
    );
    assert_usage_error(
        &["plot", "dielectrics", "--etas", "1.1,-1.5", "-o", o],
        "η number 2 -1.5",
    );
    assert_usage_error(
        &[
            "plot",
            "dielectrics",
            "--etas",
            "1,2,3,4,5,6,7,8,9,10,11",
            "-o",
            o,
        ],
        "at most 10",
    );
    assert_usage_error(
        &["plot", "reflectance", "--eta", "1,2", "-o", o],
        "invalid value '1,2' for '--eta <E|R,G,B>': takes 1 or 3 value(s), got 2",
    );
    assert_usage_error(
        &[
            "plot",
            "reflectance",
            "--metal",
            "gold",
            "--dielectric",
            "1.5",
            "-o",
            o,
        ],
        "the argument '--metal <NAME>' cannot be used with '--dielectric <ETA>'",
    );
    assert_usage_error(
        &[
            "plot",
            "reflectance",
            "--metal",
            "gold",
            "--polarisation",
            "2",
            "-o",
            o,
        ],
        "polarisation",
    );
    assert_usage_error(
        &[
            "plot",
            "reflectance",
            "--metal",
            "gold",
            "--width",
            "0",
            "-o",
            o,
        ],
        "size",
    );
    assert_usage_error(
        &["plot", "reflectance", "-o", o],
        "<--metal <NAME>|--dielectric <ETA>|--eta <E|R,G,B>|--csv <FILE>>",
    );
    assert_usage_error(&["plot", "reflectance", "--k", "2", "-o", o], "--eta");
    // --k belongs to --eta: with another material it is refused, not ignored.
    assert_usage_error(
        &[
            "plot",
            "reflectance",
            "--metal",
            "gold",
            "--k",
            "1",
            "-o",
            o,
        ],
        "the argument '--metal <NAME>' cannot be used with '--k <K|R,G,B>'",
    );
    // A negative value reaches the plot's own check (clap takes it for a value).
    assert_usage_error(
        &["plot", "reflectance", "--eta", "-1", "-o", o],
        "η of the red band -1: an index of refraction must be finite and > 0",
    );
    assert_usage_error(
        &["plot", "histogram"],
        "unrecognized subcommand 'histogram'",
    );
    // A bad spectral table: the file, the line and the problem, exit status 1.
    let csv = dir.join("my-metal.csv");
    std::fs::write(&csv, "wavelength_nm,n,k\n450,1.0,2.0\n500,abc,2.1\n").unwrap();
    let csv = csv.to_str().unwrap();
    for kind in ["reflectance", "spectrum"] {
        assert_clear_error(
            &["plot", kind, "--csv", csv, "-o", o],
            &format!("{csv}: line 3: cannot parse the n field `abc` as a number"),
        );
    }
    let sparse = dir.join("sparse.csv");
    std::fs::write(&sparse, "400,1,2\n800,1,3\n").unwrap();
    assert_clear_error(
        &[
            "plot",
            "reflectance",
            "--csv",
            sparse.to_str().unwrap(),
            "-o",
            o,
        ],
        "resolved by only 0 sample(s)",
    );
    assert_clear_error(
        &[
            "plot",
            "reflectance",
            "--csv",
            "/nonexistent/metal.csv",
            "-o",
            o,
        ],
        "cannot read /nonexistent/metal.csv",
    );
    // The destination is checked before any work.
    assert_clear_error(
        &["plot", "dielectrics", "-o", "/nonexistent-folder/fig12.png"],
        "/nonexistent-folder",
    );
    assert!(!out.exists());
    assert_eq!(common::listing(&dir), ["my-metal.csv", "sparse.csv"]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn info_describes_builtin_scenes() {
    let (code, stdout, stderr) = combustion(&["info", "builtin:underwater"]);
    assert_eq!(code, 0, "{stderr}");
    for expected in [
        "scene: builtin:underwater",
        "outside medium IOR: 1.33",
        "air bubble: dielectric η 1",
        "renderer features needed:",
        "outside IOR ≠ 1: yes",
        "conductors (given η+ik): 1",
        "lights: 0 point, 0 spot, 2 directional",
    ] {
        assert!(
            stdout.contains(expected),
            "missing `{expected}` in:\n{stdout}"
        );
    }
    let (code, stdout, _) = combustion(&["info", "builtin:diffuse-models"]);
    assert_eq!(code, 0);
    assert!(
        stdout.contains("diffuse models: lambert, oren-nayar-qualitative, oren-nayar-full"),
        "{stdout}"
    );
    assert_clear_error(
        &["info", "builtin:teapot"],
        "unknown built-in scene `teapot`",
    );
    assert_refused(
        &["info"],
        &[
            "the following required arguments were not provided",
            "<SCENE>",
        ],
    );
}

#[test]
fn info_describes_gltf_files() {
    let optics = repo_file("assets/scenes/optics/optics.gltf");
    let (code, stdout, stderr) = combustion(&["info", &optics]);
    assert_eq!(code, 0, "{stderr}");
    for expected in [
        "file: ",
        "extensions used: COMBUSTION_materials_optics",
        "renderer features needed:",
        "diffuse models: lambert, oren-nayar-qualitative, oren-nayar-full",
        "conductors from base colour: 1",
        "outside IOR ≠ 1: yes",
    ] {
        assert!(
            stdout.contains(expected),
            "missing `{expected}` in:\n{stdout}"
        );
    }
    let textured = repo_file("assets/scenes/textured/textured.gltf");
    let (code, stdout, stderr) = combustion(&["info", &textured]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("textured materials: base colour"),
        "{stdout}"
    );
    assert!(
        stdout.contains("lights: 1 point, 1 spot, 1 directional"),
        "{stdout}"
    );
}

/// `--hdr-format f16` does not clamp radiance silently: a frame whose radiance passes
/// f16's largest value (a uniform environment of 1e5) is refused and nothing written,
/// whether the driver wrote infinity or clamped to 65504 (lavapipe clamps: it rendered
/// and exited 0); the same frame in f32 renders.
#[test]
fn a_16_bit_frame_that_overflows_is_refused() {
    let dir = scratch("f16-overflow");
    let png = dir.join("f16.png");
    let args = |format: &'static str, png: &std::path::Path| -> Vec<String> {
        [
            "render",
            "builtin:spheres-studio",
            "--environment",
            "uniform:1e5",
            "--width",
            "16",
            "--height",
            "16",
            "--hdr-format",
            format,
            "-o",
        ]
        .iter()
        .map(|s| s.to_string())
        .chain([png.to_str().unwrap().to_owned()])
        .collect()
    };
    let f16 = args("f16", &png);
    let f16: Vec<&str> = f16.iter().map(String::as_str).collect();
    assert_clear_error(&f16, "overflowed (NaN, infinite, or f16's largest, 65504");
    assert!(!png.exists(), "nothing is written");
    let f32_png = dir.join("f32.png");
    let f32 = args("f32", &f32_png);
    let f32: Vec<&str> = f32.iter().map(String::as_str).collect();
    let (code, _, stderr) = combustion(&f32);
    assert_eq!(code, 0, "{stderr}");
}

/// No output is written over what the run reads: `render S.gltf -o S.gltf` (and through a
/// hard link), `render --environment E.exr --hdr E.exr`, `diff A B --heatmap B` are
/// refused in one line naming the output and the input, before any work, and the input is
/// left as it was (each wrote over it and exited 0); `batch -o D --goldens D` without
/// `--update-goldens` is refused (it replaced every golden and passed it against itself).
#[test]
fn no_output_is_written_over_an_input() {
    let text = |path: &std::path::Path| path.to_str().unwrap().to_owned();
    let dir = scratch("over-inputs");
    let scene = dir.join("scene.gltf");
    let gltf = std::fs::read(repo_file("assets/scenes/optics/optics.gltf")).unwrap();
    std::fs::write(&scene, &gltf).unwrap();
    let linked = dir.join("linked.png");
    std::fs::hard_link(&scene, &linked).unwrap();
    for output in [&scene, &linked] {
        assert_clear_error(
            &["render", &text(&scene), "-o", &text(output)],
            "it is the scene file this run reads",
        );
    }
    assert_eq!(
        std::fs::read(&scene).unwrap(),
        gltf,
        "the scene was written over"
    );

    let sky = dir.join("sky.exr");
    let (code, _, stderr) = combustion(&[
        "render",
        "builtin:spheres",
        "--width",
        "16",
        "--height",
        "8",
        "--hdr",
        &text(&sky),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let sky_bytes = std::fs::read(&sky).unwrap();
    assert_clear_error(
        &[
            "render",
            "builtin:spheres",
            "--environment",
            &text(&sky),
            "--hdr",
            &text(&sky),
        ],
        "it is the environment image this run reads",
    );
    assert_eq!(std::fs::read(&sky).unwrap(), sky_bytes);

    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    for path in [&a, &b] {
        let (code, _, stderr) = combustion(&[
            "render",
            "builtin:spheres",
            "--width",
            "16",
            "--height",
            "8",
            "-o",
            &text(path),
        ]);
        assert_eq!(code, 0, "{stderr}");
    }
    let b_bytes = std::fs::read(&b).unwrap();
    assert_clear_error(
        &["diff", &text(&a), &text(&b), "--heatmap", &text(&b)],
        "it is the second image this run reads",
    );
    assert_eq!(std::fs::read(&b).unwrap(), b_bytes);

    let manifest = dir.join("one.json");
    std::fs::write(
        &manifest,
        r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "width": 16, "height": 8}]}"#,
    )
    .unwrap();
    let goldens = dir.join("goldens");
    std::fs::create_dir(&goldens).unwrap();
    assert_clear_error(
        &[
            "batch",
            &text(&manifest),
            "-o",
            &text(&goldens),
            "--goldens",
            &text(&goldens),
        ],
        "are one folder: the renders would replace the goldens",
    );
}

/// `render` smooths edges with FXAA by default: its PNG is byte for byte the one
/// `--anti-aliasing fxaa` writes and differs from `--anti-aliasing none`'s, while the EXR
/// (radiance) is the same in all three; `--supersample 2` alone needs no
/// `--anti-aliasing none` (supersampling replaces the default) and still refuses an
/// explicit `fxaa`.
#[test]
fn render_smooths_edges_by_default() {
    let dir = scratch("fxaa-default");
    let render = |name: &str, extra: &[&str]| {
        let png = dir.join(format!("{name}.png"));
        let exr = dir.join(format!("{name}.exr"));
        let mut args = vec![
            "render",
            "builtin:spheres",
            "--width",
            "96",
            "--height",
            "64",
            "-o",
            png.to_str().unwrap(),
            "--hdr",
            exr.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, _, stderr) = combustion(&args);
        assert_eq!(code, 0, "{name}: {stderr}");
        (std::fs::read(png).unwrap(), std::fs::read(exr).unwrap())
    };
    let default = render("default", &[]);
    let fxaa = render("fxaa", &["--anti-aliasing", "fxaa"]);
    let none = render("none", &["--anti-aliasing", "none"]);
    assert!(default.0 == fxaa.0, "the default PNG is not FXAA's");
    assert!(default.0 != none.0, "FXAA changed nothing");
    assert!(
        default.1 == none.1 && fxaa.1 == none.1,
        "the EXR was smoothed"
    );
    let png = dir.join("supersampled.png");
    let (code, _, stderr) = combustion(&[
        "render",
        "builtin:spheres",
        "--width",
        "48",
        "--height",
        "32",
        "--supersample",
        "2",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert_clear_error(
        &[
            "render",
            "builtin:spheres",
            "--supersample",
            "2",
            "--anti-aliasing",
            "fxaa",
        ],
        "--supersample 2 and --anti-aliasing fxaa",
    );
}

/// A shadow map side below 64 is bad usage (exit 2, before the device starts; it was a
/// device error after it, exit 1), and shadow options without `--shadows on` are said to
/// do nothing, naming the ones given.
#[test]
fn shadow_options_are_checked_and_said_to_need_shadows() {
    assert_refused(
        &[
            "render",
            "builtin:grid-sun",
            "--shadows",
            "on",
            "--shadow-map-size",
            "63",
        ],
        &["--shadow-map-size", "a shadow map's side is at least 64"],
    );
    render_warns(
        "shadow-options-unused",
        &[
            "builtin:grid-sun",
            "--width",
            "16",
            "--height",
            "16",
            "--shadow-filter",
            "pcf16",
            "--shadow-cascades",
            "2",
        ],
        "--shadow-cascades, --shadow-filter do nothing without --shadows on",
    );
}

/// An `--accumulate-until` that 1 024 frames cannot meet says so (it ran them and
/// exited 0 without a word); the image, their mean, is still written.
#[test]
fn an_accumulation_target_not_reached_is_said() {
    let scene = repo_file("assets/scenes/textured/textured.gltf");
    render_warns(
        "accumulate-unmet",
        &[
            &scene,
            "--environment-samples",
            "1",
            "--accumulate-until",
            "1e-9",
            "--width",
            "8",
            "--height",
            "8",
        ],
        "--accumulate-until 1e-9: not reached in 1024 frames",
    );
}

/// `combustion render ARGS… -o SCRATCH/out.png`, which must render (exit 0, the PNG
/// written) and warn with `expected` on stderr.
fn render_warns(name: &str, args: &[&str], expected: &str) {
    let dir = scratch(name);
    let png = dir.join("out.png");
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend(["-o", png.to_str().unwrap()]);
    let (code, _, stderr) = combustion(&all);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains(expected), "{stderr}");
    assert!(png.exists(), "the image is written");
}

/// `--shadows on` on a scene whose lights cast none (here: no lights, the studio alone)
/// says that it does nothing, and renders.
#[test]
fn shadows_without_a_casting_light_are_said_to_do_nothing() {
    render_warns(
        "shadows-nothing",
        &[
            "builtin:spheres-studio",
            "--width",
            "32",
            "--height",
            "24",
            "--shadows",
            "on",
        ],
        "--shadows on does nothing here: it has no lights",
    );
}

/// A glTF file with lights is lit by its lights and the studio environment by default,
/// and light adds up: on the textured scene (a point, a spot and a directional light,
/// and an emissive material), each pixel of the default frame plus the frame with
/// neither (`--scene-lights off --environment none`: the emission alone) equals the
/// frame of the lights alone (`--environment none`) plus the frame of the studio alone
/// (`--scene-lights off`), to f32 rounding; the studio adds light to the frame, and
/// `info` states the rule.
#[test]
fn a_file_is_lit_by_its_lights_and_the_studio() {
    let dir = scratch("scene-lights");
    let textured = repo_file("assets/scenes/textured/textured.gltf");
    let render = |name: &str, extra: &[&str]| {
        let exr = dir.join(format!("{name}.exr"));
        let png = dir.join(format!("{name}.png"));
        let mut args = vec![
            "render",
            "--scene",
            &textured,
            "--width",
            "64",
            "--height",
            "48",
            "-o",
            png.to_str().unwrap(),
            "--hdr",
            exr.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, _, stderr) = combustion(&args);
        assert_eq!(code, 0, "{name}: {stderr}");
        read_exr(&exr).2
    };
    let both = render("both", &[]);
    let lights = render("lights", &["--environment", "none"]);
    let studio = render("studio", &["--scene-lights", "off"]);
    let neither = render(
        "neither",
        &["--scene-lights", "off", "--environment", "none"],
    );
    let mut worst = 0.0f64;
    for i in 0..both.len() {
        for c in 0..3 {
            let left = f64::from(both[i][c]) + f64::from(neither[i][c]);
            let right = f64::from(lights[i][c]) + f64::from(studio[i][c]);
            worst = worst.max((left - right).abs() / right.abs().max(1e-4));
        }
    }
    let sum = |frame: &[[f32; 3]]| {
        frame
            .iter()
            .map(|p| f64::from(p[0] + p[1] + p[2]))
            .sum::<f64>()
    };
    eprintln!(
        "radiance summed: both {:.3}, lights {:.3}, studio {:.3}, neither {:.3}; superposition worst {worst:.2e}",
        sum(&both),
        sum(&lights),
        sum(&studio),
        sum(&neither)
    );
    assert!(worst < 1e-4, "superposition off by {worst:.2e}");
    assert!(sum(&studio) > sum(&neither) && sum(&lights) > sum(&neither));
    let (code, stdout, stderr) = combustion(&["info", &textured]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("render lights the file with its 3 lights and the studio environment"),
        "{stdout}"
    );
}

/// Every file of the bad-glTF corpus gives the importer's error on one line, naming the
/// file, exit status 1. (`image-over-limit.gltf` is bad only under a lower image limit than
/// the default, so it is skipped.)
#[test]
fn info_on_bad_gltf_files_gives_one_line_errors() {
    let dir = std::path::PathBuf::from(repo_file("tests/bad-gltf"));
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !(name.ends_with(".gltf") || name.ends_with(".glb")) || name == "image-over-limit.gltf" {
            continue;
        }
        let path = path.to_str().unwrap().to_owned();
        assert_clear_error(&["info", &path], &path);
        let (code, stdout, stderr) = combustion(&["info", &path]);
        assert_eq!(code, 1, "{name}");
        assert!(stdout.is_empty(), "{name}: printed {stdout}");
        assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
        checked += 1;
    }
    assert!(checked >= 30, "only {checked} bad files found");
}

#[test]
fn closed_stdout_ends_quietly() {
    // `combustion eval --list | head -1`: the tool must not panic when the reader goes.
    use std::io::Read;
    let mut child = Command::new(env!("CARGO_BIN_EXE_combustion"))
        .args(["eval", "--list"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // close the pipe before the tool writes
    let status = child.wait().unwrap();
    let mut stderr = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(status.success(), "{status:?} {stderr}");
}

#[test]
fn device_chosen_by_index_name_or_environment() {
    let dir = scratch("device");
    for (args, env) in [
        (vec!["--device", "0"], None),
        (vec!["--device", "LLVMPIPE"], None),
        (vec![], Some("llvmpipe")),
    ] {
        let out = dir.join("d.png");
        let mut command = Command::new(env!("CARGO_BIN_EXE_combustion"));
        command
            .args([
                "render",
                "--width",
                "16",
                "--height",
                "16",
                "-o",
                out.to_str().unwrap(),
            ])
            .args(&args)
            .env_remove("COMBUSTION_DEVICE");
        if let Some(value) = env {
            command.env("COMBUSTION_DEVICE", value);
        }
        let output = command.output().unwrap();
        assert!(
            output.status.success(),
            "{args:?} {env:?}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        assert!(out.exists());
        std::fs::remove_file(&out).unwrap();
    }
    // Issue 28, defect 9: a COMBUSTION_DEVICE that is not UTF-8 is refused in one line
    // (exit 1), not ignored for the automatic choice.
    use std::os::unix::ffi::OsStrExt;
    let out = dir.join("d.png");
    let output = Command::new(env!("CARGO_BIN_EXE_combustion"))
        .args(["render", "--width", "16", "--height", "16", "-o"])
        .arg(&out)
        .env(
            "COMBUSTION_DEVICE",
            std::ffi::OsStr::from_bytes(b"llvm\xffpipe"),
        )
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("COMBUSTION_DEVICE is not valid UTF-8 text") && stderr.lines().count() == 1,
        "{stderr}"
    );
    assert!(!out.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

/// More lights than a frame can cull: `--culling always` (and auto) say that the frame is
/// not culled, rather than silently looping every pixel over every light; within the
/// limit nothing is said. (Before: no word, only the shading loop's line.)
#[test]
fn bench_says_when_a_frame_has_more_lights_than_culling_takes() {
    let max = combustion::renderer::MAX_CULLED_LIGHTS;
    for (extra, says) in [(max + 10, true), (max - 10, false)] {
        let extra = extra.to_string();
        let (code, stdout, stderr) = combustion(&[
            "bench",
            "--width",
            "32",
            "--height",
            "32",
            "--frames",
            "1",
            "--extra-lights",
            &extra,
            "--culling",
            "always",
        ]);
        assert_eq!(code, 0, "{stderr}");
        let warned =
            stderr.contains("a frame can cull into tile lists, so --culling always does not cull");
        assert_eq!(warned, says, "{extra} extra lights: {stderr}");
        let looped = stdout.contains("every pixel loops over every light");
        assert_eq!(looped, says, "{extra} extra lights: {stdout}");
    }
}

#[test]
fn bench_reports_gpu_and_wall_clock_time_with_frames_in_flight() {
    let (code, stdout, stderr) = combustion(&[
        "bench",
        "--width",
        "64",
        "--height",
        "48",
        "--frames",
        "4",
        "--frames-in-flight",
        "3",
        "--device",
        "llvmpipe",
        "--validate",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("3 in flight"), "{stdout}");
    for row in ["gbuffer", "lighting", "total", "wall"] {
        assert!(
            stdout.lines().any(|l| l.starts_with(row)),
            "no `{row}` row: {stdout}"
        );
    }
    // The output's work is folded into the lighting pass, and said so; --fold-output
    // off times the two passes apart.
    assert!(
        stdout.contains("output: folded into the lighting pass") && !stdout.contains("\noutput "),
        "{stdout}"
    );
    let (code, apart, stderr) = combustion(&[
        "bench",
        "--width",
        "64",
        "--height",
        "48",
        "--frames",
        "2",
        "--fold-output",
        "off",
        "--device",
        "llvmpipe",
        "--validate",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        apart.lines().any(|l| l.starts_with("output ")) && !apart.contains("folded"),
        "{apart}"
    );
    assert!(stdout.contains("wall clock:"), "{stdout}");
    // Every measured frame's timings are collected, also the last ones in flight.
    assert!(stdout.contains("n=4 frames (4 timed)"), "{stdout}");
    assert_refused(
        &["bench", "--frames-in-flight", "0"],
        &["invalid value '0' for '--frames-in-flight <N>': is not between 1 and 3"],
    );
    assert_refused(
        &["bench", "--against", "old"],
        &[
            "the following required arguments were not provided",
            "--report <DIR>",
        ],
    );
    assert_clear_error(
        &["bench", "--report", "new", "--against", "no-such-dir"],
        "previous report `no-such-dir/report.csv`",
    );
    assert_refused(
        &["bench", "--report", "new", "--diffuse", "lambert"],
        &["the argument '--report <DIR>' cannot be used with '--diffuse <MODEL>'"],
    );
    // Sections that cannot be measured as asked, refused before the device starts.
    assert_clear_error(
        &[
            "bench",
            "--report",
            "new",
            "--report-sections",
            "light-transport",
        ],
        "--report-sections light-transport needs --path-traced-frames N",
    );
    assert_clear_error(
        &[
            "bench",
            "--report",
            "new",
            "--report-sections",
            "variants",
            "--path-traced-frames",
            "4",
        ],
        "--path-traced-frames measures the light-transport section, which --report-sections leaves out",
    );
    assert_clear_error(
        &[
            "bench",
            "--report",
            "new",
            "--report-sections",
            "floors,shadows",
        ],
        "--report-sections floors needs variants too",
    );
    assert_refused(
        &[
            "bench",
            "--report",
            "new",
            "--report-sections",
            "variants,bounces",
        ],
        &["invalid value 'bounces' for '--report-sections <LIST>'"],
    );
    assert_refused(
        &["bench", "--report-sections", "variants"],
        &["--report <DIR>"],
    );
    // The report sets its own lighting too: an environment would be ignored.
    assert_refused(
        &["bench", "--report", "new", "--environment", "studio"],
        &["the argument '--report <DIR>' cannot be used with '--environment <ENVIRONMENT>'"],
    );
    assert_refused(
        &["render", "--distribution", "phong"],
        &[
            "invalid value 'phong' for '--distribution <KIND>'",
            "[possible values: ggx, beckmann]",
        ],
    );
    assert_refused(
        &["render", "--diffuse", "minnaert"],
        &["[possible values: material, lambert, oren-nayar-qualitative, oren-nayar-full]"],
    );
    assert_refused(
        &["render", "--frames-in-flight", "2"],
        &["unexpected argument '--frames-in-flight' found"],
    );
    assert_refused(
        &["view", "--screenshot", "last.png"],
        &[
            "the following required arguments were not provided",
            "--frames <N>",
        ],
    );
}

/// The accuracy budget: `render --max-error E` renders with the fastest variant set
/// whose mean relative error against the f64 reference is within E (measured on the
/// scene first); a budget no set meets, or a budget that is no number above 0, is a
/// one-line error; `info --max-error` lists every set with its time and errors at the
/// size asked (`--width`, `--height`, which need the budget), and the one it marks
/// chosen is the fastest of those within the budget.
#[test]
fn an_accuracy_budget_picks_a_variant_set_or_says_why_not() {
    let dir = scratch("budget");
    let png = dir.join("out.png");
    let (code, stdout, stderr) = combustion(&[
        "render",
        "builtin:underwater",
        "--width",
        "64",
        "--height",
        "48",
        "--max-error",
        "1e-3",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    // Schlick's mean error under water is of order 1: it cannot be the choice.
    let chosen = stdout
        .lines()
        .find(|l| l.starts_with("variant set "))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(chosen.starts_with("variant set full/"), "{chosen}");
    assert!(png.exists());
    assert_clear_error(
        &[
            "render",
            "builtin:underwater",
            "--width",
            "64",
            "--height",
            "48",
            "--max-error",
            "1e-12",
            "-o",
            png.to_str().unwrap(),
        ],
        "no variant set is within it",
    );
    // The options a variant set chooses are not taken beside a budget (they were
    // dropped without a word).
    for (flag, value) in [
        ("--diffuse", "lambert"),
        ("--distribution", "beckmann"),
        ("--fresnel", "schlick"),
        ("--hdr-format", "f16"),
    ] {
        assert_refused(
            &["render", "--max-error", "1e-3", flag, value],
            &["cannot be used with", flag],
        );
    }
    for bad in ["0", "-1", "x", "inf"] {
        assert_refused(
            &["render", "--max-error", bad],
            &[&format!(
                "invalid value '{bad}' for '--max-error <E>': is not a relative error above 0"
            )],
        );
    }
    assert_refused(
        &["info", "builtin:dielectrics", "--width", "160"],
        &["--max-error"],
    );
    // A side beyond the device's limit, before anything is measured.
    assert_clear_error(
        &[
            "info",
            "builtin:dielectrics",
            "--max-error",
            "1e-2",
            "--width",
            "60000",
        ],
        "is not allowed",
    );
    let (code, stdout, stderr) = combustion(&[
        "info",
        "builtin:dielectrics",
        "--max-error",
        "1e-2",
        "--width",
        "160",
        "--height",
        "90",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("variant sets measured at 160x90 (10 frames each)"),
        "{stdout}"
    );
    let listed = stdout.lines().filter(|l| l.contains(" ms  mean ")).count();
    assert_eq!(
        listed,
        combustion::report::VariantSet::all().len(),
        "{stdout}"
    );
    assert_eq!(
        stdout
            .matches("chosen: the fastest within the budget")
            .count(),
        1
    );
    // The rule itself, on the listed measurements: the chosen set is within the budget
    // and no faster set is; every set within it is as slow or slower.
    let sets: Vec<(f64, f64, &str)> = stdout
        .lines()
        .filter_map(|l| {
            let (left, right) = l.split_once(" ms  mean ")?;
            let ms: f64 = left.split_whitespace().last()?.parse().ok()?;
            let mean: f64 = right.split_whitespace().next()?.parse().ok()?;
            Some((ms, mean, l))
        })
        .collect();
    let budget = 1e-2;
    let &(chosen_ms, chosen_mean, _) = sets
        .iter()
        .find(|(_, _, l)| l.ends_with("chosen: the fastest within the budget"))
        .unwrap();
    assert!(chosen_mean <= budget);
    for &(ms, mean, line) in &sets {
        if mean <= budget {
            assert!(ms >= chosen_ms, "faster and within the budget: {line}");
        }
        assert_eq!(
            line.ends_with("over the budget"),
            mean > budget,
            "verdict of {line}"
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// Issue 9, output paths: outputs are regular files written atomically; a symlink is
/// followed to its target (the link stays); special files (a FIFO here, /dev/full in the
/// report) and read-only files are refused, not replaced; two outputs may not name one
/// file; an empty or folder-like name is refused before any rendering; a write error on
/// standard output is reported, and a closed pipe ends the program quietly.
#[test]
fn output_paths_are_regular_files_and_every_write_error_is_reported() {
    use std::os::unix::fs::{FileTypeExt, PermissionsExt};
    let dir = scratch("output-paths");
    let at = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    let small = ["--width", "16", "--height", "16"];
    let render = |extra: &[&str]| {
        let mut args = vec!["render", "builtin:spheres"];
        args.extend_from_slice(&small);
        args.extend_from_slice(extra);
        combustion(&args)
    };

    // A FIFO is refused and stays a FIFO.
    let fifo = at("pipe.png");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    assert_clear_error(
        &["render", "builtin:spheres", "-o", &fifo],
        "is not a regular file",
    );
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());

    // A symlink is followed: the target is written, the link stays a link.
    let target = at("real.png");
    let link = at("link.png");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let (code, _, stderr) = render(&["-o", &link]);
    assert_eq!(code, 0, "{stderr}");
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::read(&target).unwrap().starts_with(b"\x89PNG"));

    // A read-only file is not replaced.
    let locked = at("locked.png");
    std::fs::write(&locked, b"keep").unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o444)).unwrap();
    assert_clear_error(
        &["render", "builtin:spheres", "-o", &locked],
        "is read-only",
    );
    assert_eq!(std::fs::read(&locked).unwrap(), b"keep");

    // Two outputs naming one file, directly or through the link.
    let same = at("same"); // no extension: either option takes it
    assert_clear_error(
        &["render", "builtin:spheres", "-o", &same, "--hdr", &same],
        "name the same file",
    );
    // (A link without an extension: `--hdr` refuses a name that says PNG.)
    let bare_link = at("link-to-real");
    std::os::unix::fs::symlink(&target, &bare_link).unwrap();
    assert_clear_error(
        &[
            "render",
            "builtin:spheres",
            "-o",
            &target,
            "--hdr",
            &bare_link,
        ],
        "name the same file",
    );
    assert!(!std::path::Path::new(&same).exists());

    // Names that cannot be a file, refused before rendering.
    assert_refused(
        &["render", "builtin:spheres", "-o", ""],
        &["a value is required for '--output <OUT.png>' but none was supplied"],
    );
    let folder_like = format!("{}/", at("newdir"));
    assert_clear_error(
        &["render", "builtin:spheres", "-o", &folder_like],
        "names a folder",
    );
    // A name ending in `.` or `..` names a folder too, whether it exists, is missing or
    // is a file (the path reads as the name before it; this failed only at the write,
    // after the render).
    for folder_like in [
        format!("{}/.", at("newdir")),
        format!("{target}/."),
        format!("{}/..", at("newdir")),
    ] {
        assert_clear_error(
            &["render", "builtin:spheres", "-o", &folder_like],
            "names a folder",
        );
    }

    // Standard output: a write error is an error; a closed pipe is a quiet end.
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_combustion"))
        .args(["eval", "--list"])
        .stdout(full)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("cannot write to standard output"),
        "{stderr}"
    );
    for args in [&["info", "builtin:spheres"][..], &["eval", "--list"]] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_combustion"))
            .args(args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take()); // the reader goes away at once, as `| head -0` would
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert_eq!(out.status.code(), Some(0), "{args:?}: {stderr}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// Issue 9, arguments (on clap): a path that is not UTF-8 is taken as the path it is
/// (the error names the missing file), text that is not UTF-8 is refused (exit 2); every
/// command answers --help and -h with its usage; numbers are refused with why (negative,
/// out of range) and without echoing hundreds of digits.
#[test]
fn arguments_are_refused_with_why_and_every_command_has_help() {
    use std::os::unix::ffi::OsStrExt;
    let bad = std::ffi::OsStr::from_bytes(b"scene-\xff.gltf");
    let run = |args: &[&std::ffi::OsStr]| {
        let out = Command::new(env!("CARGO_BIN_EXE_combustion"))
            .args(args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!stderr.contains("panicked"), "{stderr}");
        (out.status.code(), stderr)
    };
    let (code, stderr) = run(&["info".as_ref(), bad]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.starts_with("error: scene-\u{fffd}.gltf: ") && stderr.contains("No such file"),
        "{stderr}"
    );
    let (code, stderr) = run(&["render".as_ref(), "--fresnel".as_ref(), bad]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("invalid UTF-8"), "{stderr}");

    const COMMANDS: [&str; 8] = [
        "render",
        "bench",
        "view",
        "eval",
        "plot",
        "info",
        "devices",
        "completions",
    ];
    let plot_kinds = ["plot reflectance", "plot spectrum", "plot dielectrics"];
    for command in COMMANDS.into_iter().chain(plot_kinds) {
        for flag in ["--help", "-h"] {
            let mut args: Vec<&str> = command.split(' ').collect();
            args.push(flag);
            let (code, stdout, stderr) = combustion(&args);
            assert_eq!(code, 0, "{command} {flag}: {stderr}");
            assert!(
                stdout.contains(&format!("Usage: combustion {command}")),
                "{command} {flag}: {stdout}"
            );
        }
    }
    // `help COMMAND` is `COMMAND --help`; the overview lists every command.
    let (code, stdout, _) = combustion(&["help", "bench"]);
    assert_eq!(code, 0);
    assert!(stdout.contains("--report <DIR>"), "{stdout}");
    let (code, stdout, _) = combustion(&["--help"]);
    assert_eq!(code, 0);
    for command in COMMANDS {
        assert!(
            stdout.contains(&format!("\n  {command} ")),
            "{command}: {stdout}"
        );
    }
    let (code, stdout, _) = combustion(&["--version"]);
    assert_eq!(
        (code, stdout.trim()),
        (0, concat!("combustion ", env!("CARGO_PKG_VERSION")))
    );

    assert_refused(
        &["render", "--width", "-5"],
        &["invalid value '-5' for '--width <N>': is negative"],
    );
    let digits = "9".repeat(300);
    let (code, _, stderr) = combustion(&["render", "--width", &digits]);
    assert_eq!(code, 2);
    assert!(stderr.contains("is out of range"), "{stderr}");
    assert!(
        stderr.len() < 200,
        "the message echoes the whole number: {stderr}"
    );
}

/// Issue 9, shell completions from the command line's declaration: bash loads the script
/// and completes subcommands and options from it; zsh and fish scripts name the options.
#[test]
fn completions_are_generated_for_each_shell() {
    let (code, script, stderr) = combustion(&["completions", "bash"]);
    assert_eq!(code, 0, "{stderr}");
    let dir = scratch("completions");
    let file = dir.join("combustion.bash");
    std::fs::write(&file, &script).unwrap();
    // What bash offers after `combustion re` and `combustion render --energy`.
    let complete = |words: &str| -> String {
        let line = format!(
            "source {}; COMP_WORDS=({words}); COMP_CWORD=$((${{#COMP_WORDS[@]}} - 1)); \
             COMP_LINE=\"{words}\"; COMP_POINT=${{#COMP_LINE}}; _combustion combustion \"${{COMP_WORDS[COMP_CWORD]}}\" \
             \"${{COMP_WORDS[COMP_CWORD-1]}}\"; \
             printf '%s\\n' \"${{COMPREPLY[@]}}\"",
            file.display()
        );
        let out = Command::new("bash").args(["-c", &line]).output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let commands = complete("combustion re");
    assert_eq!(commands.trim(), "render", "{commands}");
    let options = complete("combustion render --energy");
    assert_eq!(options.trim(), "--energy-compensation", "{options}");
    let values = complete("combustion render --fresnel ''");
    assert_eq!(
        values.split_whitespace().collect::<Vec<_>>(),
        ["full", "schlick", "f82"],
        "{values}"
    );
    for shell in ["zsh", "fish", "elvish", "powershell"] {
        let (code, script, stderr) = combustion(&["completions", shell]);
        assert_eq!(code, 0, "{shell}: {stderr}");
        assert!(script.contains("energy-compensation"), "{shell}: {script}");
    }
    assert_refused(
        &["completions", "tcsh"],
        &[
            "invalid value 'tcsh' for '<SHELL>'",
            "[possible values: bash, elvish, fish, powershell, zsh]",
        ],
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// Issue 9, OpenEXR through the `exr` crate: `--hdr` files are ZIP-compressed and read
/// back bit for bit (radiance from 0 through 1e-30-small to above f16's range).
#[test]
fn exr_output_reads_back_bit_for_bit() {
    use exr::prelude::*;
    let dir = scratch("exr");
    let (width, height) = (37u32, 23u32);
    let pixels: Vec<[f32; 4]> = (0..width * height)
        .map(|i| {
            let x = i as f32;
            [x * 0.013, 1e-30 * x, 70000.0 + x, 1.0]
        })
        .collect();
    let path = dir.join("radiance.exr");
    combustion::output::write_exr(&path, width, height, &pixels).unwrap();
    let w = width as usize;
    let image = read_first_rgba_layer_from_file(
        &path,
        |resolution, _| vec![[0.0f32; 3]; resolution.width() * resolution.height()],
        move |out: &mut Vec<[f32; 3]>, at: Vec2<usize>, (r, g, b, _a): (f32, f32, f32, f32)| {
            out[at.y() * w + at.x()] = [r, g, b];
        },
    )
    .unwrap();
    assert_eq!(image.layer_data.encoding.compression, Compression::ZIP16);
    let read = &image.layer_data.channel_data.pixels;
    assert_eq!(read.len(), pixels.len());
    for (a, b) in pixels.iter().zip(read) {
        assert_eq!(
            a[..3].iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            b.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// `view --screenshot` follows `render -o`'s output rule, checked before a window opens
/// or the scene loads: a missing folder, a folder and a FIFO are one-line errors with a
/// failing exit status. (Before: the viewer ran, logged the failed write and exited 0.)
/// No display is reached here, so an error from the window would fail the test too.
#[test]
fn view_checks_its_screenshot_before_opening_a_window() {
    let dir = scratch("view-screenshot");
    let fifo = dir.join("pipe.png");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    std::fs::create_dir_all(dir.join("folder.png")).unwrap();
    let s = |p: std::path::PathBuf| p.to_str().unwrap().to_owned();
    for (shot, expected) in [
        (s(dir.join("missing/shot.png")), "does not exist"),
        (s(dir.join("folder.png")), "it names a folder, not a file"),
        (s(fifo), "it is not a regular file"),
    ] {
        let args = [
            "view",
            "--frames",
            "1",
            "--screenshot",
            &shot,
            "--scene",
            "builtin:spheres",
        ];
        assert_clear_error(&args, expected);
    }
    assert_eq!(common::listing(&dir), ["folder.png", "pipe.png"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 28, defect 1: the command line's readers keep the importer's rule for input
/// files — a regular file within a limit, checked before reading — so a FIFO does not
/// block and a link to /dev/zero is not read without end: `plot --csv`, `bench
/// --against` (its report.csv) and `view --camera-path` each refuse both at once with
/// one error line. (Before: each blocked, or grew by gigabytes; the runs are bounded
/// by `timeout` so a regression fails instead of hanging.)
#[test]
fn every_reader_refuses_fifos_and_devices_before_reading() {
    let dir = scratch("special-inputs");
    let fifo = dir.join("pipe.csv");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let zero = dir.join("zero.csv");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    // `bench --against DIR` reads DIR/report.csv.
    let against_fifo = dir.join("against-fifo");
    std::fs::create_dir_all(&against_fifo).unwrap();
    assert!(Command::new("mkfifo")
        .arg(against_fifo.join("report.csv"))
        .status()
        .unwrap()
        .success());
    let against_zero = dir.join("against-zero");
    std::fs::create_dir_all(&against_zero).unwrap();
    std::os::unix::fs::symlink("/dev/zero", against_zero.join("report.csv")).unwrap();
    let report = dir.join("report");
    let s = |p: &std::path::Path| p.to_str().unwrap().to_owned();
    let cases: Vec<Vec<String>> = vec![
        vec![
            "plot".into(),
            "reflectance".into(),
            "--csv".into(),
            s(&fifo),
        ],
        vec!["plot".into(), "spectrum".into(), "--csv".into(), s(&zero)],
        vec![
            "bench".into(),
            "--report".into(),
            s(&report),
            "--against".into(),
            s(&against_fifo),
        ],
        vec![
            "bench".into(),
            "--report".into(),
            s(&report),
            "--against".into(),
            s(&against_zero),
        ],
        vec![
            "view".into(),
            "builtin:spheres".into(),
            "--camera-path".into(),
            s(&fifo),
        ],
        vec![
            "view".into(),
            "builtin:spheres".into(),
            "--camera-path".into(),
            s(&zero),
        ],
    ];
    for args in cases {
        let output = Command::new("timeout")
            .arg("20")
            .arg(env!("CARGO_BIN_EXE_combustion"))
            .args(&args)
            .env("COMBUSTION_DEVICE", "llvmpipe")
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_ne!(
            output.status.code(),
            Some(124),
            "{args:?} blocked or read without end"
        );
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        let errors: Vec<_> = stderr
            .lines()
            .filter(|l| l.starts_with("error: "))
            .collect();
        assert_eq!(errors.len(), 1, "{args:?}: {stderr}");
        assert!(
            errors[0].contains("not a regular file"),
            "{args:?}: {stderr}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 28, defect 6: `bench --report` checked only report.md before measuring, so a
/// folder named floors.csv, a read-only scaling.csv or a FIFO report.csv failed after
/// the whole measurement, leaving new files beside old ones. Every file the report may
/// write is checked first: each case fails at once (well inside the 20 s the test
/// allows; the measurement takes minutes), names the file, and writes nothing.
#[test]
fn a_report_folder_that_cannot_take_every_file_is_refused_before_measuring() {
    let dir = scratch("report-outputs");
    let s = |p: &std::path::Path| p.to_str().unwrap().to_owned();
    let folder = dir.join("folder");
    std::fs::create_dir_all(folder.join("floors.csv")).unwrap();
    let read_only = dir.join("read-only");
    std::fs::create_dir_all(&read_only).unwrap();
    std::fs::write(read_only.join("scaling.csv"), "old").unwrap();
    let mut permissions = std::fs::metadata(read_only.join("scaling.csv"))
        .unwrap()
        .permissions();
    permissions.set_readonly(true);
    std::fs::set_permissions(read_only.join("scaling.csv"), permissions).unwrap();
    let fifo = dir.join("fifo");
    std::fs::create_dir_all(&fifo).unwrap();
    assert!(Command::new("mkfifo")
        .arg(fifo.join("report.csv"))
        .status()
        .unwrap()
        .success());
    for (report, file) in [
        (&folder, "floors.csv"),
        (&read_only, "scaling.csv"),
        (&fifo, "report.csv"),
    ] {
        let output = Command::new("timeout")
            .arg("20")
            .arg(env!("CARGO_BIN_EXE_combustion"))
            .args(["bench", "--report", &s(report), "--frames", "1"])
            .env("COMBUSTION_DEVICE", "llvmpipe")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{file}: {stderr}");
        let errors: Vec<_> = stderr
            .lines()
            .filter(|l| l.starts_with("error: "))
            .collect();
        assert_eq!(errors.len(), 1, "{file}: {stderr}");
        assert!(errors[0].contains(file), "{file}: {stderr}");
        assert!(!report.join("report.md").exists(), "{file}");
    }
    assert_eq!(
        std::fs::read_to_string(read_only.join("scaling.csv")).unwrap(),
        "old"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 28, defect 6: a bad `--device`, or a side beyond the device's limit, was
/// reported only after the scene and its environment were loaded (an environment image
/// can take gigabytes to decode). They are checked first: with an environment file that
/// cannot be read at all, the device's error is the one reported.
#[test]
fn the_device_and_the_size_are_checked_before_anything_is_loaded() {
    let dir = scratch("preflight");
    let garbage = dir.join("sky.hdr");
    std::fs::write(&garbage, b"not a radiance file").unwrap();
    let sky = garbage.to_str().unwrap();
    for command in ["render", "bench"] {
        assert_clear_error(
            &[
                command,
                "builtin:spheres",
                "--environment",
                sky,
                "--device",
                "9",
            ],
            "no Vulkan device matches",
        );
        assert_clear_error(
            &[
                command,
                "builtin:spheres",
                "--environment",
                sky,
                "--width",
                "65536",
            ],
            "each side must be between 1 and",
        );
    }
    // The environment's own error, once the device and size are fine.
    assert_clear_error(
        &["render", "builtin:spheres", "--environment", sky],
        "sky.hdr",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 28, defect 2: `view --width 65536` (or a height above 65535) panicked inside
/// winit under X11 (its sizes are 16-bit); it is refused as bad usage before anything is
/// loaded or any display is asked for.
#[test]
fn a_window_side_beyond_the_window_system_is_refused_before_any_window() {
    assert_refused(
        &["view", "builtin:spheres", "--width", "65536"],
        &["at most 65535 pixels per side"],
    );
    assert_refused(
        &["view", "builtin:spheres", "--height", "65536"],
        &["at most 65535 pixels per side"],
    );
}

/// Issue 28, defect 9: `--width 100000` was an error of the device (exit 1, "must be
/// between 1 and 16384 on this device") where `--width 0` was bad usage (exit 2). A side
/// beyond what any Vulkan device takes is bad usage for every command, whatever the
/// device; within it, the device's own limit stays a runtime error.
#[test]
fn an_image_side_beyond_any_device_is_bad_usage() {
    for args in [
        ["render", "builtin:spheres", "--width", "100000"],
        ["bench", "builtin:spheres", "--height", "70000"],
        ["view", "builtin:spheres", "--height", "70000"],
        ["render", "builtin:spheres", "--shadow-map-size", "65537"],
    ] {
        assert_refused(
            &args,
            &["more pixels per side than any Vulkan device takes"],
        );
    }
}

/// Reads an OpenEXR file's RGB channels (row-major from the top-left).
fn read_exr(path: &std::path::Path) -> (usize, usize, Vec<[f32; 3]>) {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| {
            (
                resolution.width(),
                vec![[0.0f32; 3]; resolution.width() * resolution.height()],
            )
        },
        |(w, out): &mut (usize, Vec<[f32; 3]>),
         at: Vec2<usize>,
         (r, g, b, _a): (f32, f32, f32, f32)| {
            out[at.y() * *w + at.x()] = [r, g, b];
        },
    )
    .unwrap();
    let (w, pixels) = image.layer_data.channel_data.pixels;
    let h = pixels.len() / w;
    (w, h, pixels)
}

/// `--hdr` holds the frame's linear radiance, and `--exposure` scales what the PNG
/// shows, not the radiance: on spot-box (a spot light with a range over a Lambert floor)
/// the EXR is bit for bit the HDR image of the library's render of the scene (the frame
/// tests/end_to_end.rs holds per pixel to the scene's f64 reference) whatever the
/// exposure, and each PNG is that radiance × the exposure through the exponential tone
/// curve and the sRGB encoding, to within one 8-bit code (f32 on the GPU, f64 here).
/// Shown to fail: with the command line's exposure dropped (the settings' exposure left
/// at 1), the exposure-4 PNG is codes away from what its radiance makes.
#[test]
fn the_hdr_file_is_the_frames_radiance_and_exposure_changes_only_the_image() {
    use combustion::renderer::{linear_to_srgb, tonemap_exponential};
    let dir = scratch("exposure");
    let (width, height) = (64u32, 48u32);
    let mut outputs = Vec::new();
    for exposure in ["1", "4"] {
        let png = dir.join(format!("x{exposure}.png"));
        let exr = dir.join(format!("x{exposure}.exr"));
        let (code, stdout, stderr) = combustion(&[
            "render",
            "builtin:spot-box",
            "--width",
            &width.to_string(),
            "--height",
            &height.to_string(),
            "--exposure",
            exposure,
            // The tone curve of each pixel's own radiance (no FXAA across edges).
            "--anti-aliasing",
            "none",
            "-o",
            png.to_str().unwrap(),
            "--hdr",
            exr.to_str().unwrap(),
            "--validate",
        ]);
        assert_eq!(code, 0, "{stdout}{stderr}");
        outputs.push((exposure.parse::<f64>().unwrap(), png, exr));
    }
    let scene = combustion::scene::builtin_scene("spot-box").unwrap();
    let frame = common::render_images(&scene, width, height, common::exact_f32());
    let mut pngs = Vec::new();
    for (exposure, png, exr) in &outputs {
        let (w, h, radiance) = read_exr(exr);
        assert_eq!((w, h), (width as usize, height as usize));
        let bits = |p: &[f32]| p.iter().map(|c| c.to_bits()).collect::<Vec<_>>();
        for (i, (file, gpu)) in radiance.iter().zip(&frame.hdr).enumerate() {
            assert_eq!(
                bits(file),
                bits(&gpu[..3]),
                "pixel {i}, exposure {exposure}"
            );
        }
        // Linear radiance, not a display value: the spot's pool is brighter than 1.
        assert!(radiance.iter().flatten().any(|&c| c > 1.0));
        let (pw, ph, codes) = common::read_png(png);
        assert_eq!((pw, ph), (width, height));
        let mut worst = 0i32;
        for (rgb, code) in radiance.iter().zip(&codes) {
            for c in 0..3 {
                let display = linear_to_srgb(tonemap_exponential(exposure * f64::from(rgb[c])));
                let expected = (display * 255.0).round() as i32;
                worst = worst.max((expected - i32::from(code[c])).abs());
            }
        }
        assert!(worst <= 1, "exposure {exposure}: a code {worst} off");
        pngs.push(codes);
    }
    // Every pixel the spot lights (neither black nor white at exposure 1) is brighter
    // at exposure 4.
    let lit: Vec<(u8, u8)> = pngs[0]
        .iter()
        .zip(&pngs[1])
        .map(|(a, b)| (a[1], b[1]))
        .filter(|(a, _)| (1..=250).contains(a))
        .collect();
    let brighter = lit.iter().filter(|(a, b)| b > a).count();
    assert!(lit.len() > 500, "{} lit pixels", lit.len());
    assert_eq!(
        brighter,
        lit.len(),
        "{brighter} of {} lit pixels brighter",
        lit.len()
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--validate` turns any message of the validation layer into a failed run: one error
/// line, a non-zero exit and no output written. The layer is asked for its
/// best-practices checks through its own environment variable (`VK_LAYER_ENABLES`),
/// which warn about choices Combustion makes on purpose (debug utils, resettable
/// command buffers); without `--validate` the same run succeeds.
#[test]
fn validate_fails_the_run_on_any_validation_message() {
    let dir = scratch("validate");
    let png = dir.join("out.png");
    let run = |validate: bool| {
        let mut args = vec![
            "render",
            "builtin:spheres",
            "--width",
            "32",
            "--height",
            "24",
            "-o",
            png.to_str().unwrap(),
        ];
        if validate {
            args.push("--validate");
        }
        Command::new(env!("CARGO_BIN_EXE_combustion"))
            .args(&args)
            .env("COMBUSTION_DEVICE", "llvmpipe")
            .env(
                "VK_LAYER_ENABLES",
                "VK_VALIDATION_FEATURE_ENABLE_BEST_PRACTICES_EXT",
            )
            .output()
            .expect("run combustion")
    };
    let failed = run(true);
    let stderr = String::from_utf8_lossy(&failed.stderr);
    assert_eq!(failed.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let errors: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("error: "))
        .collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(
        errors[0].contains("the Vulkan validation layer reported")
            && errors[0].contains("BestPractices"),
        "{}",
        errors[0]
    );
    assert!(!png.exists(), "a failed run wrote its image");
    let passed = run(false);
    assert_eq!(
        passed.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&passed.stderr)
    );
    assert!(png.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--background`: `R,G,B` puts that radiance where no surface is (in the EXR, exactly);
/// a scene lit by an environment shows it by default, `none` leaves it black; a value
/// that is not a radiance is a usage error naming the option.
#[test]
fn the_background_is_what_the_option_says() {
    let dir = scratch("background");
    let (width, height) = (64u32, 48u32);
    let render = |scene: &str, background: Option<&str>, name: &str| {
        let exr = dir.join(format!("{name}.exr"));
        let mut args = vec![
            "render".to_owned(),
            scene.to_owned(),
            "--width".into(),
            width.to_string(),
            "--height".into(),
            height.to_string(),
            "--hdr".into(),
            exr.to_str().unwrap().to_owned(),
            "--validate".into(),
        ];
        if let Some(b) = background {
            args.extend(["--background".to_owned(), b.to_owned()]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, stdout, stderr) = combustion(&args);
        assert_eq!(code, 0, "{stdout}{stderr}");
        read_exr(&exr).2
    };
    // The corner pixel of builtin:spheres and spheres-studio shows no surface.
    let corner = 0;
    let coloured = render("builtin:spheres", Some("0.5,0.25,2"), "coloured");
    assert_eq!(coloured[corner], [0.5, 0.25, 2.0]);
    let black = render("builtin:spheres", None, "plain");
    assert_eq!(black[corner], [0.0; 3]);
    let studio = render("builtin:spheres-studio", None, "studio");
    assert!(
        studio[corner].iter().all(|&c| c > 0.01),
        "{:?}",
        studio[corner]
    );
    let studio_none = render("builtin:spheres-studio", Some("none"), "studio-none");
    assert_eq!(studio_none[corner], [0.0; 3]);
    for bad in ["1,2", "red", "1,2,nan", "0,0,3e38", "-1,0,0"] {
        let (code, _, stderr) = combustion(&["render", "--background", bad]);
        assert_eq!(code, 2, "{bad}: {stderr}");
        assert!(stderr.contains("--background"), "{bad}: {stderr}");
    }
}

/// A glTF file without lights is lit by the studio environment, and `render` says so
/// once — not when `--environment` or `--light-rig` lights it otherwise, and once under
/// `--max-error` (which loads the scene again to measure it). `bench` names the scene,
/// the lighting pipeline's parts and the culling as the options spell them, with no
/// Rust debug text.
#[test]
fn the_studio_default_is_announced_only_when_it_is_kept() {
    let dir = scratch("lightless");
    // Coarse spheres: the test is of the notice, and --max-error renders every variant
    // set six times.
    let mut scene =
        common::with_coarse_grid_spheres(combustion::scene::builtin_scene("spheres").unwrap());
    scene.lights.clear();
    let file = dir.join("lightless.gltf");
    combustion::scene::gltf::save_gltf(&scene, &file).unwrap();
    let file = file.to_str().unwrap();
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let notice = "lighting it with the studio environment";
    for (extra, times) in [
        (&[][..], 1),
        (&["--environment", "none"][..], 0),
        (&["--environment", "uniform:0.5"][..], 0),
        (&["--light-rig"][..], 0),
        (&["--max-error", "1"][..], 1),
    ] {
        let mut args = vec!["render", file, "--width", "32", "--height", "24", "-o", out];
        args.extend_from_slice(extra);
        let (code, stdout, stderr) = combustion(&args);
        assert_eq!(code, 0, "{extra:?}: {stdout}{stderr}");
        assert_eq!(stderr.matches(notice).count(), times, "{extra:?}: {stderr}");
    }
    let (code, stdout, stderr) =
        combustion(&["bench", "--frames", "2", "--width", "32", "--height", "24"]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(
        stdout.contains("scene builtin:spheres at 32x24"),
        "{stdout}"
    );
    assert!(
        stdout.contains("specialised to anisotropy, conductors, dielectrics, Lambert"),
        "{stdout}"
    );
    assert!(stdout.contains("light culling: auto"), "{stdout}");
    for debug_text in ["Builtin(", "LightingFeatures {", "Auto ("] {
        assert!(!stdout.contains(debug_text), "{debug_text} in {stdout}");
    }
}

/// Saves `scene` as DIR/NAME.gltf and renders it at 32×24 into DIR/NAME.png with the
/// `extra` options: the exit code, standard output and error, and the PNG's path.
fn render_saved_scene(
    dir: &std::path::Path,
    name: &str,
    scene: &combustion::scene::Scene,
    extra: &[&str],
) -> (i32, String, String, std::path::PathBuf) {
    let file = dir.join(format!("{name}.gltf"));
    combustion::scene::gltf::save_gltf(scene, &file).unwrap();
    let out = dir.join(format!("{name}.png"));
    let mut args = vec![
        "render",
        file.to_str().unwrap(),
        "--width",
        "32",
        "--height",
        "24",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, stdout, stderr) = combustion(&args);
    (code, stdout, stderr, out)
}

/// A scene with nothing to draw renders its background with a warning saying so, and an
/// accuracy budget on it says that no pixel was compared and keeps the default variant
/// set (before, an empty scene met any budget and picked the fastest set).
#[test]
fn an_empty_scene_says_so_and_meets_no_budget() {
    let dir = scratch("empty");
    let mut scene = combustion::scene::builtin_scene("spheres").unwrap();
    scene.objects.clear();
    let (code, stdout, stderr, out) =
        render_saved_scene(&dir, "empty", &scene, &["--max-error", "0.5"]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stderr.contains("nothing to draw"), "{stderr}");
    assert!(
        stderr.contains("no pixel of this scene was compared"),
        "{stderr}"
    );
    assert!(!stdout.contains("variant set"), "{stdout}");
    assert!(out.exists());
}

/// A frame that would show nothing, or not what the scene holds, says why before it is
/// rendered: a camera with a field of view of 1e-20 radians aimed beside the objects, and
/// an object moved 1e8 m out (where 32-bit positions are 8 m apart) framed by the
/// camera. (Before: both rendered the background alone with exit 0 and no word.)
#[test]
fn a_frame_that_cannot_show_the_scene_says_why() {
    use combustion::scene::{builtin_scene, Camera};
    let dir = scratch("view-warnings");
    let spheres = builtin_scene("spheres").unwrap();
    let (lo, hi) = spheres.world_bounds().unwrap();
    let framed = Camera::framing(Some((lo, hi)));
    let right = (framed.target - framed.position)
        .cross(framed.up)
        .normalize();
    let mut pinhole = spheres.clone();
    pinhole.camera = Camera {
        target: framed.target + right * 1.5 * (hi - lo).length() / 2.0,
        vertical_fov: 1e-20,
        ..framed
    };
    let mut far = spheres.clone();
    far.objects[0].transform =
        glam::Mat4::from_translation(glam::Vec3::new(1e8, 0.0, 0.0)) * far.objects[0].transform;
    far.camera = Camera::framing(far.world_bounds());
    // Renders `scene` saved as a file (it must succeed): its stderr.
    let render = |name: &str, scene: &combustion::scene::Scene| {
        let (code, stdout, stderr, out) = render_saved_scene(&dir, name, scene, &[]);
        assert_eq!(code, 0, "{name}: {stdout}{stderr}");
        assert!(out.exists(), "{name}");
        stderr
    };
    for (name, scene, expected) in [
        ("pinhole", pinhole, "objects is in the camera's view"),
        ("far", far, "where 32-bit positions are"),
    ] {
        let stderr = render(name, &scene);
        assert!(stderr.contains(expected), "{name}: {stderr}");
    }
    // The scene as framed says nothing.
    let stderr = render("framed", &spheres);
    assert!(
        !stderr.contains("camera's view") && !stderr.contains("32-bit"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An output name whose extension names another image format is refused before any
/// work (exit 2, the option and the format named): `-o a.jpg` used to get PNG bytes and
/// `--hdr h.png` OpenEXR ones without a word. Case does not matter, and no extension is
/// fine. An unknown COMBUSTION_LOG level is said to be one, once, instead of ignored.
#[test]
fn output_names_say_the_format_they_get() {
    let dir = scratch("extensions");
    for (option, name, format) in [
        ("-o", "a.jpg", "PNG"),
        ("-o", "a.EXR", "PNG"),
        ("--hdr", "h.png", "OpenEXR"),
        ("--hdr", "h.hdr", "OpenEXR"),
    ] {
        let path = dir.join(name);
        let (code, _, stderr) = combustion(&["render", option, path.to_str().unwrap()]);
        assert_eq!(code, 2, "{option} {name}: {stderr}");
        assert!(
            stderr.contains(option) && stderr.contains(format) && stderr.lines().count() == 1,
            "{option} {name}: {stderr}"
        );
        assert!(!path.exists(), "{name} written");
    }
    for name in ["upper.PNG", "bare"] {
        let path = dir.join(name);
        let (code, stdout, stderr) = combustion(&[
            "render",
            "--width",
            "8",
            "--height",
            "8",
            "-o",
            path.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{name}: {stdout}{stderr}");
        assert!(path.exists(), "{name}");
    }
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_combustion"))
        .args(["devices"])
        .env("COMBUSTION_LOG", "garbage")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(
        stderr.matches("COMBUSTION_LOG=`garbage`").count(),
        1,
        "{stderr}"
    );
}

/// `--ev N` is `--exposure 2^N`: the same PNG, byte for byte, as `--exposure 4` for
/// `--ev 2` (2² is exact in f32); the two together, or stops beyond ±64, are usage errors.
#[test]
fn exposure_in_stops_is_the_factor_two_to_the_stops() {
    let dir = scratch("ev");
    let render = |flag: &str, value: &str, name: &str| {
        let png = dir.join(name);
        let (code, stdout, stderr) = combustion(&[
            "render",
            "builtin:spot-box",
            "--width",
            "48",
            "--height",
            "32",
            flag,
            value,
            "-o",
            png.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{stdout}{stderr}");
        std::fs::read(png).unwrap()
    };
    assert_eq!(
        render("--ev", "2", "ev.png"),
        render("--exposure", "4", "x.png")
    );
    for args in [
        &["render", "--ev", "1", "--exposure", "2"][..],
        &["render", "--ev", "65"][..],
        &["render", "--ev", "nan"][..],
    ] {
        let (code, _, stderr) = combustion(args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains("--ev"), "{args:?}: {stderr}");
    }
}

/// Issue 25, item 1 (and item 3 for one driver): `diff` compares a render with another.
/// The same job run twice writes byte-equal PNG and EXR files, which `diff` finds equal
/// under the strictest criterion (exit 0); a render 10 % brighter differs by up to 6
/// steps, which `max-channel-diff 5/255 on at most 0.1% of pixels` refuses (exit 1, one
/// line naming the criterion and the share measured) and a looser criterion, or an `or`
/// with one, accepts; the JSON says the same; the heat map has the images' size.
#[test]
fn diff_compares_renders_by_stated_criteria() {
    let dir = scratch("diff");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    for (name, exposure) in [("a", "1"), ("b", "1"), ("c", "1.1")] {
        let (code, _, stderr) = combustion(&[
            "render",
            "builtin:spheres",
            "--width",
            "96",
            "--height",
            "64",
            "--exposure",
            exposure,
            // Each pixel's own radiance (no FXAA across edges): the steps stated above.
            "--anti-aliasing",
            "none",
            "-o",
            &path(&format!("{name}.png")),
            "--hdr",
            &path(&format!("{name}.exr")),
        ]);
        assert_eq!(code, 0, "{stderr}");
    }
    for ext in ["png", "exr"] {
        assert_eq!(
            std::fs::read(path(&format!("a.{ext}"))).unwrap(),
            std::fs::read(path(&format!("b.{ext}"))).unwrap(),
            "the same job gives the same {ext} bytes"
        );
    }
    let strict = "max-channel-diff 0/255 on at most 0% of pixels and max-flip <= 0";
    let (code, stdout, stderr) =
        combustion(&["diff", &path("a.png"), &path("b.png"), "--criteria", strict]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("largest channel difference 0/255"),
        "{stdout}"
    );
    let (code, _, stderr) = combustion(&[
        "diff",
        &path("a.exr"),
        &path("b.exr"),
        "--criteria",
        "max-relative-diff 0 on at most 0% of pixels",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let tight = "max-channel-diff 5/255 on at most 0.1% of pixels";
    assert_clear_error(
        &["diff", &path("a.png"), &path("c.png"), "--criteria", tight],
        "the images differ beyond the criteria: max-channel-diff 5/255 on at most 0.1% of pixels: ",
    );
    let (code, stdout, _) = combustion(&[
        "diff",
        &path("a.png"),
        &path("c.png"),
        "--criteria",
        tight,
        "--json",
    ]);
    assert_eq!(code, 1);
    let json: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(json["pass"], false);
    assert_eq!(json["max_channel_diff"], 6.0);
    let loose = format!("{tight} or max-channel-diff 6/255 on at most 0% of pixels");
    let (code, _, stderr) = combustion(&[
        "diff",
        &path("a.png"),
        &path("c.png"),
        "--criteria",
        &loose,
        "--heatmap",
        &path("heat.png"),
    ]);
    assert_eq!(code, 0, "{stderr}");
    // The heat map, then its legend: the colour bar from FLIP 0 (magma's black) to 1
    // (its light yellow), and the ends' labels, white on black.
    let decoder = png::Decoder::new(std::fs::File::open(path("heat.png")).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let (width, height) = (reader.info().width, reader.info().height);
    use combustion::diff::{LEGEND_BAR_ROWS, LEGEND_LABEL_ROWS};
    assert_eq!(
        (width, height),
        (96, 64 + LEGEND_BAR_ROWS + LEGEND_LABEL_ROWS)
    );
    let mut buffer = vec![0; reader.output_buffer_size()];
    let frame = reader.next_frame(&mut buffer).unwrap();
    let channels = frame.color_type.samples();
    let at = |x: u32, y: u32| {
        let i = (y * width + x) as usize * channels;
        [buffer[i], buffer[i + 1], buffer[i + 2]]
    };
    let bar = 64 + LEGEND_BAR_ROWS / 2;
    let (left, right) = (at(0, bar), at(width - 1, bar));
    assert!(left.iter().all(|&c| c < 16), "FLIP 0 is dark: {left:?}");
    assert!(
        right[0] > 240 && right[1] > 240 && right[2] > 150,
        "FLIP 1 is light: {right:?}"
    );
    // Text at both ends (`FLIP 0` at the left, `1` at the right at this width).
    let white = |xs: std::ops::Range<u32>| {
        (64 + LEGEND_BAR_ROWS..height)
            .flat_map(|y| xs.clone().map(move |x| (x, y)))
            .filter(|&(x, y)| at(x, y).iter().all(|&c| c > 200))
            .count()
    };
    let (left, right) = (white(0..width / 2), white(width / 2..width));
    assert!(
        left > 10 && right > 3,
        "the labels' text: {left}, {right} white pixels"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 25, item 1: `diff`'s bad input — criteria it cannot read are bad usage (exit
/// 2, the term named); images of different sizes or kinds, or a file that is no image,
/// are one-line errors (exit 1).
#[test]
fn diff_refuses_what_it_cannot_compare() {
    let dir = scratch("diff-bad");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    for (name, width) in [("a", "16"), ("b", "17")] {
        let (code, _, stderr) = combustion(&[
            "render",
            "builtin:spheres",
            "--width",
            width,
            "--height",
            "8",
            "-o",
            &path(&format!("{name}.png")),
            "--hdr",
            &path(&format!("{name}.exr")),
        ]);
        assert_eq!(code, 0, "{stderr}");
    }
    assert_refused(
        &[
            "diff",
            &path("a.png"),
            &path("a.png"),
            "--criteria",
            "psnr >= 30",
        ],
        &["criterion `psnr >= 30`: not one of"],
    );
    assert_clear_error(
        &["diff", &path("a.png"), &path("b.png")],
        "the images differ in size: 16x8 and 17x8",
    );
    // A PNG against an OpenEXR, and a criterion of the other kind (alone or after `or`):
    // bad usage, said before any image is compared (they failed as image differences,
    // exit 1, or the second was dropped without a word).
    assert_refused(
        &["diff", &path("a.png"), &path("a.exr")],
        &["is a PNG and", "is an OpenEXR: compare a PNG with a PNG"],
    );
    for criteria in [
        "max-relative-diff 0.1 on at most 1% of pixels",
        "mean-flip <= 0.5 or max-relative-diff 0.1 on at most 1% of pixels",
    ] {
        assert_refused(
            &["diff", &path("a.png"), &path("a.png"), "--criteria", criteria],
            &["criterion `max-relative-diff 0.1 on at most 1% of pixels` does not apply to PNG images"],
        );
    }
    assert_refused(
        &[
            "diff",
            &path("a.exr"),
            &path("a.exr"),
            "--criteria",
            "max-channel-diff 2/255 on at most 1% of pixels",
        ],
        &["does not apply to OpenEXR images (radiance): use max-relative-diff"],
    );
    // Criteria from a file: comments and line breaks; a term it cannot read is bad
    // usage naming the file; a file that holds none too.
    std::fs::write(
        dir.join("criteria.txt"),
        "# goldens of this project\nmax-channel-diff 0/255 on at most 0% of pixels # exact\nand mean-flip <= 0\n",
    )
    .unwrap();
    let (code, _, stderr) = combustion(&[
        "diff",
        &path("a.png"),
        &path("a.png"),
        "--criteria-file",
        &path("criteria.txt"),
    ]);
    assert_eq!(code, 0, "{stderr}");
    std::fs::write(dir.join("bad.txt"), "mean-flip <= 0\nor psnr >= 30\n").unwrap();
    assert_refused(
        &[
            "diff",
            &path("a.png"),
            &path("a.png"),
            "--criteria-file",
            &path("bad.txt"),
        ],
        &["--criteria-file", "criterion `psnr >= 30`: not one of"],
    );
    std::fs::write(dir.join("empty.txt"), "# nothing\n").unwrap();
    assert_refused(
        &[
            "diff",
            &path("a.png"),
            &path("a.png"),
            "--criteria-file",
            &path("empty.txt"),
        ],
        &["no criterion in it"],
    );
    std::fs::write(dir.join("x.png"), b"not a png").unwrap();
    assert_clear_error(&["diff", &path("x.png"), &path("a.png")], "x.png: PNG:");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A number too large for its option says so, not that it is not finite (`--time 1e308`
/// was "not a finite number"), and an orbit too near to leave the target is refused with
/// the option named (`orbit:0,0,1e-30` failed later: "its position and target
/// coincide").
#[test]
fn numbers_out_of_an_options_range_are_named_as_such() {
    assert_refused(
        &[
            "render",
            "builtin:spheres",
            "--time",
            "1e308",
            "-o",
            "/tmp/x.png",
        ],
        &[
            "--time",
            "is beyond the largest value this option takes (3.40282e38)",
        ],
    );
    assert_refused(
        &[
            "render",
            "builtin:spheres",
            "--camera",
            "orbit:0,0,1e-30",
            "-o",
            "/tmp/x.png",
        ],
        &["--camera", "distance 1e-30 is not within 1e-3 and 1e6"],
    );
}

/// `render --time T [--animation NAME|INDEX]` shows the scene at that time of its
/// animation: BoxAnimated (a sample model) at 0 s and at 1.8 s gives two different
/// images, and `bench --time` plays it while measuring; an animation the scene lacks, a
/// scene without animations and a time that is not a finite number are one-line errors.
#[test]
fn render_shows_the_scene_at_a_time_of_its_animation() {
    assert_refused(
        &[
            "render",
            "builtin:spheres",
            "--time",
            "nan",
            "-o",
            "/tmp/x.png",
        ],
        &["is not a finite number"],
    );
    assert_clear_error(
        &[
            "render",
            "builtin:spheres",
            "--time",
            "1",
            "-o",
            "/tmp/x.png",
        ],
        "the scene has no animations",
    );
    let Some(samples) = common::shared_gltf_samples() else {
        return;
    };
    let model = samples.join("BoxAnimated/glTF-Binary/BoxAnimated.glb");
    let model = model.to_str().unwrap();
    assert_clear_error(
        &["render", model, "--animation", "walk", "-o", "/tmp/x.png"],
        "--animation walk: the scene has no such animation (it has 0)",
    );
    let dir = scratch("time");
    let images: Vec<Vec<[u8; 4]>> = ["0", "1.8"]
        .iter()
        .map(|time| {
            let out = dir.join(format!("box-{time}.png"));
            let (code, stdout, stderr) = combustion(&[
                "render",
                model,
                "--time",
                time,
                "--animation",
                "0",
                "--width",
                "64",
                "--height",
                "48",
                "-o",
                out.to_str().unwrap(),
            ]);
            assert_eq!(code, 0, "{stdout}{stderr}");
            common::read_png(&out).2
        })
        .collect();
    // bench plays the animation through its measured frames (validation on).
    let (code, stdout, stderr) = combustion(&[
        "bench",
        model,
        "--time",
        "0.5",
        "--frames",
        "3",
        "--width",
        "32",
        "--height",
        "24",
        "--validate",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("animation 0 playing (3.71 s long, 1/30 s per frame)"),
        "{stdout}"
    );
    let differing = images[0]
        .iter()
        .zip(&images[1])
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        differing > 50,
        "the box at 1.8 s differs from 0 s in {differing} pixels"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--camera`: framing and orbits render from where they say (a different image from the
/// scene's own camera; orbits at opposite azimuths of a symmetric view differ), and a
/// camera that cannot be is refused in one line: an elevation beyond ±89°, a camera
/// index on a built-in scene (which has one camera), text that is no view.
#[test]
fn render_takes_the_camera_asked_for() {
    let dir = scratch("camera");
    let png = |name: &str| dir.join(format!("{name}.png")).to_str().unwrap().to_owned();
    for (name, camera) in [
        ("own", "scene"),
        ("framing", "framing"),
        ("left", "orbit:-60,20"),
        ("right", "orbit:60,20"),
    ] {
        let (code, _, stderr) = combustion(&[
            "render",
            "builtin:spheres",
            "--width",
            "64",
            "--height",
            "48",
            "--camera",
            camera,
            "-o",
            &png(name),
        ]);
        assert_eq!(code, 0, "{camera}: {stderr}");
    }
    let bytes = |name: &str| std::fs::read(png(name)).unwrap();
    assert_ne!(bytes("own"), bytes("framing"));
    assert_ne!(bytes("left"), bytes("right"));
    assert_refused(
        &["render", "--camera", "orbit:0,95"],
        &["elevation 95° is not within ±89°"],
    );
    assert_refused(
        &["render", "--camera", "orbit:0"],
        &["takes 2 or 3 value(s)"],
    );
    assert_refused(&["render", "--camera", "top"], &["is not scene, framing"]);
    assert_refused(
        &[
            "render",
            "builtin:spheres",
            "--camera",
            "1",
            "-o",
            &png("none"),
        ],
        &["--camera 1: builtin:spheres has one camera"],
    );
    assert!(!dir.join("none.png").exists());
}

/// SIGTERM while an output is being written (its temporary `.NAME.partial-PID-N` on
/// disk) removes the temporary file and ends the process by that signal: nothing is left
/// but what was there before (here, nothing). SIGINT the same.
#[test]
fn a_terminated_write_leaves_no_partial_file() {
    use std::os::unix::process::ExitStatusExt;
    for signal in ["TERM", "INT"] {
        let dir = scratch(&format!("terminated-{signal}"));
        let exr = dir.join("big.exr");
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_combustion"))
            .args([
                "render",
                "builtin:spheres",
                "--width",
                "3072",
                "--height",
                "3072",
                "--hdr",
            ])
            .arg(&exr)
            .env("COMBUSTION_DEVICE", "llvmpipe")
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let partial = || {
            std::fs::read_dir(&dir).unwrap().any(|e| {
                e.unwrap()
                    .file_name()
                    .to_string_lossy()
                    .starts_with(".big.exr.partial-")
            })
        };
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
        while !partial() {
            assert!(
                std::time::Instant::now() < deadline,
                "no partial file appeared"
            );
            assert!(
                matches!(child.try_wait(), Ok(None)),
                "the render ended before writing"
            );
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        let pid = child.id().to_string();
        assert!(Command::new("kill")
            .args([&format!("-{signal}"), &pid])
            .status()
            .unwrap()
            .success());
        let status = child.wait().unwrap();
        let number = if signal == "TERM" { 15 } else { 2 };
        assert_eq!(status.signal(), Some(number), "{status:?}");
        let left = common::listing(&dir);
        assert!(left.is_empty(), "{signal}: left {left:?}");
    }
}

/// A file replaced keeps its mode, and its owner where the process may give it: root
/// rendering over a user's 0600 PNG leaves the user's 0600 PNG (not a root-owned file
/// the user can no longer read). Not root: only the mode is checked.
#[test]
fn a_replaced_output_keeps_its_owner_and_mode() {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let dir = scratch("owner");
    let png = dir.join("theirs.png");
    std::fs::write(&png, b"old").unwrap();
    std::fs::set_permissions(&png, std::fs::Permissions::from_mode(0o600)).unwrap();
    let root = std::fs::metadata(&dir).unwrap().uid() == 0
        && Command::new("id").arg("-u").output().unwrap().stdout == b"0\n";
    // nobody:nogroup, as a user's file would be.
    let owner = (65534, 65534);
    if root {
        std::os::unix::fs::chown(&png, Some(owner.0), Some(owner.1)).unwrap();
    }
    let (code, _, stderr) = combustion(&[
        "render",
        "builtin:spheres",
        "--width",
        "32",
        "--height",
        "24",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let meta = std::fs::metadata(&png).unwrap();
    assert_ne!(std::fs::read(&png).unwrap(), b"old");
    assert_eq!(meta.permissions().mode() & 0o777, 0o600);
    if root {
        assert_eq!((meta.uid(), meta.gid()), owner);
    } else {
        eprintln!("not root: the owner is this user's; only the mode was checked");
    }
}

/// `--metal-colour colorimetric` renders the built-in metals with constants fitted to
/// their colorimetric colour (another image than the band method's); another value is
/// bad usage.
#[test]
fn render_takes_the_metal_colour_asked_for() {
    let dir = scratch("metal-colour");
    let png = |name: &str| dir.join(format!("{name}.png")).to_str().unwrap().to_owned();
    for colour in ["bands", "colorimetric"] {
        let (code, _, stderr) = combustion(&[
            "render",
            "builtin:gold-copper",
            "--width",
            "64",
            "--height",
            "32",
            "--metal-colour",
            colour,
            "-o",
            &png(colour),
        ]);
        assert_eq!(code, 0, "{colour}: {stderr}");
    }
    assert_ne!(
        std::fs::read(png("bands")).unwrap(),
        std::fs::read(png("colorimetric")).unwrap()
    );
    assert_refused(
        &["render", "--metal-colour", "spectral"],
        &["possible values: bands, colorimetric"],
    );
}

/// `--environment-samples N --accumulate-until E` renders frames of successive sample
/// sets until their mean's relative standard error is at most E, says how many it took
/// and what it reached, and writes the mean; without samples there is nothing to
/// accumulate (bad usage), as with a sample count the renderer has no pipeline for.
#[test]
fn render_accumulates_sampled_environment_light_to_a_stated_error() {
    let dir = scratch("accumulate");
    let png = dir.join("mean.png");
    let (code, stdout, stderr) = combustion(&[
        "render",
        "builtin:spheres-studio",
        "--width",
        "64",
        "--height",
        "40",
        "--environment-samples",
        "4",
        "--accumulate-until",
        "0.02",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let line = stdout
        .lines()
        .find(|l| l.starts_with("accumulated "))
        .unwrap_or_else(|| panic!("{stdout}"));
    let frames: u32 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    let reached: f64 = line
        .split("relative standard error ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .unwrap()
        .parse()
        .unwrap();
    assert!((4..1024).contains(&frames) && reached <= 0.02, "{line}");
    assert!(png.is_file());
    assert_refused(
        &["render", "--accumulate-until", "0.01"],
        &["--accumulate-until needs --environment-samples N, --environment-occlusion ray-traced or --path-trace on"],
    );
    assert_refused(
        &["render", "--environment-samples", "3"],
        &["power of two from 1 to 1024"],
    );
    for depth in ["0", "65", "-1", "x"] {
        assert_refused(&["render", "--path-depth", depth], &["--path-depth"]);
    }
    for frames in ["0", "1", "1025"] {
        assert_refused(
            &[
                "bench",
                "--report",
                "unused-dir",
                "--path-traced-frames",
                frames,
            ],
            &["--path-traced-frames"],
        );
    }
    assert_refused(&["bench", "--path-traced-frames", "8"], &["--report"]);
}

/// `render`'s start-up line: (shaders, of them from the SPIR-V cache).
/// `combustion render ARGS` then each (option, file) of `files`, with
/// COMBUSTION_DEVICE=llvmpipe and `variable` set to `cache`; it must succeed: its
/// standard output.
fn render_with_cache(
    args: &[&str],
    files: &[(&str, &std::path::Path)],
    variable: &str,
    cache: &std::path::Path,
) -> String {
    let mut command = Command::new(env!("CARGO_BIN_EXE_combustion"));
    command.arg("render").args(args);
    for (option, file) in files {
        command.arg(option).arg(file);
    }
    let output = command
        .env("COMBUSTION_DEVICE", "llvmpipe")
        .env(variable, cache)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

fn start_up_shaders(stdout: &str) -> (u32, u32) {
    let start_up = stdout
        .lines()
        .find_map(|line| line.strip_prefix("start-up: "))
        .unwrap_or_else(|| panic!("no start-up line: {stdout}"));
    let words: Vec<&str> = start_up.split(' ').collect();
    (
        words[0].parse().unwrap(),
        words[2].trim_start_matches('(').parse().unwrap(),
    )
}

/// Issue 27, item 3: compiled SPIR-V is kept on disk. A first run into an empty cache
/// compiles every shader with shaderc and stores it; a second process reads every one
/// back and renders the same bytes; a damaged entry is compiled again, not used.
#[test]
fn a_second_process_reads_its_spirv_from_the_cache_and_renders_the_same_image() {
    let dir = scratch("spirv-cache");
    let cache = dir.join("spirv");
    let run = |name: &str| {
        let png = dir.join(name);
        let args = [
            "--scene",
            "builtin:glass",
            "--width",
            "64",
            "--height",
            "48",
        ];
        let args = [&args[..], &["--validate"]].concat();
        let stdout = render_with_cache(&args, &[("-o", &png)], "COMBUSTION_SPIRV_CACHE", &cache);
        (start_up_shaders(&stdout), std::fs::read(png).unwrap())
    };
    let ((compiled, cached), first) = run("first.png");
    // The cache was empty: only a shader asked for again in the same process (the
    // full-screen vertex shader of several passes) is found.
    assert!(compiled > 0 && cached < compiled, "{compiled} {cached}");
    let entries = std::fs::read_dir(&cache).unwrap().count() as u32;
    assert_eq!(
        entries,
        compiled - cached,
        "one entry per compilation, no temporary left"
    );
    let ((again, cached), second) = run("second.png");
    assert_eq!(
        (again, cached),
        (compiled, compiled),
        "every shader from the cache"
    );
    assert!(first == second, "the cached SPIR-V renders the same bytes");
    // One entry damaged (a word flipped): it is compiled again and rewritten.
    let entry = std::fs::read_dir(&cache)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let mut bytes = std::fs::read(&entry).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 0x40;
    std::fs::write(&entry, &bytes).unwrap();
    let ((_, cached), third) = run("third.png");
    assert_eq!(cached, compiled - 1, "the damaged entry was not used");
    assert!(third == first);
    assert_ne!(
        std::fs::read(&entry).unwrap(),
        bytes,
        "the damaged entry was replaced"
    );
}

/// Issue 27: an environment bake keeps its cubes (the prefiltered specular cube and the
/// irradiance cube, which depend on the environment alone) on disk. A first run into an
/// empty cache computes them and stores one entry; a second process copies them from it
/// and renders the same bytes (PNG and the EXR's radiance); a damaged entry is not used:
/// the cubes are computed again, the same image comes out, and the entry is rewritten as
/// it was; so is a forged one (a NaN texel under a checksum that matches); another
/// environment is another entry. Under validation throughout.
#[test]
fn a_second_process_copies_its_environment_cubes_from_the_cache_and_renders_the_same_image() {
    let dir = scratch("environment-cache");
    let cache = dir.join("environment");
    let run = |name: &str, environment: &str| {
        let (png, exr) = (
            dir.join(format!("{name}.png")),
            dir.join(format!("{name}.exr")),
        );
        let args = [
            "--scene",
            "builtin:spheres",
            "--width",
            "64",
            "--height",
            "48",
        ];
        let args = [&args[..], &["--validate", "--environment", environment]].concat();
        let files = [("-o", png.as_path()), ("--hdr", exr.as_path())];
        let stdout = render_with_cache(&args, &files, "COMBUSTION_ENVIRONMENT_CACHE", &cache);
        let from_cache =
            if stdout.contains("1 environment bake (with its cubes from the bake cache)") {
                true
            } else {
                assert!(
                    stdout.contains("1 environment bake (without its cubes from the bake cache)"),
                    "{stdout}"
                );
                false
            };
        let images = (std::fs::read(png).unwrap(), std::fs::read(exr).unwrap());
        (from_cache, images)
    };
    let entries = || -> Vec<std::path::PathBuf> {
        let mut entries: Vec<_> = std::fs::read_dir(&cache)
            .unwrap()
            .map(|entry| entry.unwrap().path())
            .collect();
        entries.sort();
        entries
    };
    let (from_cache, first) = run("first", "studio");
    assert!(!from_cache, "the cache was empty");
    let stored = entries();
    assert_eq!(stored.len(), 1, "one entry, no temporary left: {stored:?}");
    let entry = std::fs::read(&stored[0]).unwrap();
    let (from_cache, second) = run("second", "studio");
    assert!(from_cache, "the second process found the first one's cubes");
    assert!(
        first == second,
        "cubes from the cache render the same bytes"
    );
    // The entry damaged (a byte of the texels flipped): computed again and rewritten.
    let mut damaged = entry.clone();
    let middle = damaged.len() / 2;
    damaged[middle] ^= 0x40;
    std::fs::write(&stored[0], &damaged).unwrap();
    let (from_cache, third) = run("third", "studio");
    assert!(!from_cache, "the damaged entry was not used");
    assert!(third == first);
    assert!(
        std::fs::read(&stored[0]).unwrap() == entry,
        "the damaged entry was rewritten with the same cubes"
    );
    // A forged entry: a texel's radiance NaN, the checksum made to match (the cache's
    // own checks pass): not radiance, so computed again and rewritten, never lit with.
    let header = 32;
    let mut forged = entry.clone();
    forged[header + 16..header + 20].copy_from_slice(&f32::NAN.to_le_bytes());
    let checksum = combustion_vk::Digest::new()
        .part(&forged[header..])
        .to_bytes();
    forged[24..32].copy_from_slice(&checksum[..8]);
    std::fs::write(&stored[0], &forged).unwrap();
    let (from_cache, fourth) = run("fourth", "studio");
    assert!(!from_cache, "the forged entry was not used");
    assert!(fourth == first);
    assert!(
        std::fs::read(&stored[0]).unwrap() == entry,
        "the forged entry was rewritten with the same cubes"
    );
    let (from_cache, _) = run("uniform", "uniform:0.5");
    assert!(!from_cache, "another environment has cubes of its own");
    assert_eq!(entries().len(), 2);
}

/// `--supersample N` writes an image of the asked size (the frame rendered N times as
/// large and resolved); 0 and 5 are refused, as is `--supersample` with
/// `--anti-aliasing fxaa` or with `--accumulate-until`: each a usage error naming the
/// option. `--anti-aliasing fxaa` renders.
#[test]
fn supersampling_and_anti_aliasing_on_the_command_line() {
    let dir = scratch("supersample");
    for (name, extra) in [
        ("ss.png", &["--supersample", "3"][..]),
        ("fxaa.png", &["--anti-aliasing", "fxaa"][..]),
    ] {
        let png = dir.join(name);
        let mut args = vec![
            "render",
            "builtin:spheres",
            "--width",
            "40",
            "--height",
            "30",
        ];
        args.extend_from_slice(extra);
        args.extend(["-o", png.to_str().unwrap()]);
        let (code, stdout, stderr) = combustion(&args);
        assert_eq!(code, 0, "{stdout}{stderr}");
        let bytes = std::fs::read(&png).unwrap();
        // PNG IHDR: width and height, big-endian, at bytes 16..24.
        assert_eq!(&bytes[16..24], &[0, 0, 0, 40, 0, 0, 0, 30], "{name}");
    }
    for (args, named) in [
        (&["render", "--supersample", "0"][..], "--supersample"),
        (&["render", "--supersample", "5"][..], "--supersample"),
        (
            &["render", "--supersample", "2", "--anti-aliasing", "fxaa"][..],
            "--supersample",
        ),
        (
            &["render", "--supersample", "2", "--accumulate-until", "0.01"][..],
            "--supersample",
        ),
        (
            &["render", "--anti-aliasing", "msaa"][..],
            "--anti-aliasing",
        ),
    ] {
        let (code, _, stderr) = combustion(args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(named), "{args:?}: {stderr}");
    }
}

/// `--samples N` with `--path-trace on`: N paths a pixel, the mean of N/4 frames of
/// successive seeds — four is the one frame `--path-trace on` renders alone (the same
/// radiance, bit for bit), eight the same image on every run; a count that is not whole
/// frames, one without path tracing, and one beside `--accumulate-until` are refused in
/// one line naming the option.
#[test]
fn samples_set_the_paths_a_pixel_averages() {
    assert_refused(
        &["render", "--path-trace", "on", "--samples", "6"],
        &["invalid value '6' for '--samples <N>'", "a multiple of 4"],
    );
    assert_refused(
        &["render", "--path-trace", "on", "--samples", "131072"],
        &["invalid value '131072' for '--samples <N>'", "65,536"],
    );
    assert_refused(
        &["render", "builtin:spheres", "--samples", "8"],
        &["--samples needs --path-trace on"],
    );
    assert_refused(
        &[
            "render",
            "--path-trace",
            "on",
            "--samples",
            "8",
            "--accumulate-until",
            "0.1",
        ],
        &["'--samples <N>' cannot be used with '--accumulate-until <E>'"],
    );
    let dir = scratch("samples");
    let render = |name: &str, extra: &[&str]| {
        let exr = dir.join(format!("{name}.exr"));
        let mut args = vec![
            "render",
            "builtin:cornell-box",
            "--path-trace",
            "on",
            "--width",
            "16",
            "--height",
            "12",
            "--hdr",
            exr.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, stdout, stderr) = combustion(&args);
        assert_eq!(code, 0, "{stderr}");
        (std::fs::read(&exr).unwrap(), stdout)
    };
    let (alone, _) = render("alone", &[]);
    let (four, stdout) = render("four", &["--samples", "4"]);
    assert!(
        stdout.contains("path traced 4 paths per pixel (1 frame of 4): relative standard error not measured (one frame)"),
        "{stdout}"
    );
    assert_eq!(alone, four, "four paths are the one frame");
    let (eight, stdout) = render("eight", &["--samples", "8"]);
    assert!(
        stdout.contains("path traced 8 paths per pixel (2 frames of 4): relative standard error"),
        "{stdout}"
    );
    let (again, _) = render("again", &["--samples", "8"]);
    assert_eq!(eight, again, "the same image for the same count");
    assert_ne!(eight, four);
}

/// Warnings read as the command line's own messages: `warning: …`, one line, no Rust
/// module path (they printed `[WARN combustion::cli::args] …`); the verb agrees with the
/// options it names.
#[test]
fn warnings_name_no_rust_module() {
    let dir = scratch("warnings");
    let png = dir.join("out.png");
    for (args, expected) in [
        (
            vec!["builtin:spheres", "--shadow-map-size", "1024"],
            "warning: --shadow-map-size does nothing without --shadows on",
        ),
        (
            vec!["builtin:spheres", "--shadow-map-size", "1024", "--shadow-filter", "pcf8"],
            "warning: --shadow-map-size, --shadow-filter do nothing without --shadows on",
        ),
        (
            vec!["builtin:spheres", "--ray-traced-reflections", "on"],
            "warning: builtin:spheres: --ray-traced-reflections on: the scene is lit by no environment",
        ),
    ] {
        let mut all = vec!["render"];
        all.extend(args.iter().copied());
        all.extend(["--width", "8", "--height", "8", "-o", png.to_str().unwrap()]);
        let (code, _, stderr) = combustion(&all);
        assert_eq!(code, 0, "{stderr}");
        assert!(stderr.lines().any(|l| l.starts_with(expected)), "{stderr}");
        for line in stderr.lines() {
            assert!(
                !line.contains("[WARN") && !line.contains("combustion::") && !line.contains("combustion_"),
                "a Rust path in `{line}`"
            );
        }
    }
}

/// A supersampled frame past the device's size is said in the options given (it named
/// a size the user never gave: "image size 16388x2880 is not allowed").
#[test]
fn a_supersampled_frame_too_large_names_the_options() {
    let dir = scratch("supersample-size");
    let png = dir.join("out.png");
    let (code, _, stderr) = combustion(&[
        "render",
        "builtin:spheres",
        "--supersample",
        "4",
        "--width",
        "4097",
        "--height",
        "720",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("--supersample 4 with --width 4097 --height 720: the frame is rendered 4 times as wide and high, 16388×2880 pixels"),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(!png.exists(), "nothing written");
}

/// `--shadows on` with more shadow-casting lights than the maps hold: the lights left
/// without a shadow are said, by index (they cast none without a word) — a sun and seven
/// point lights: four cascades and four cubes fill 28 of the 32 layers, the last three
/// point lights cast none.
#[test]
fn lights_past_the_shadow_layers_are_said() {
    let dir = scratch("shadow-layers");
    let source = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/optics");
    let mut gltf: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(source.join("optics.gltf")).unwrap())
            .unwrap();
    for file in ["optics.bin", "optics_0.png", "copper.csv"] {
        std::fs::copy(source.join(file), dir.join(file)).unwrap();
    }
    for k in 0..7 {
        let light = gltf["extensions"]["KHR_lights_punctual"]["lights"]
            .as_array_mut()
            .unwrap();
        light.push(serde_json::json!({"type": "point", "intensity": 2.0}));
        let index = light.len() - 1;
        let nodes = gltf["nodes"].as_array_mut().unwrap();
        nodes.push(serde_json::json!({
            "name": format!("point {k}"),
            "translation": [k as f64 - 3.0, 2.0, 1.0],
            "extensions": {"KHR_lights_punctual": {"light": index}}
        }));
        let node = nodes.len() - 1;
        gltf["scenes"][0]["nodes"]
            .as_array_mut()
            .unwrap()
            .push(node.into());
    }
    let scene = dir.join("lights.gltf");
    std::fs::write(&scene, gltf.to_string()).unwrap();
    let png = dir.join("out.png");
    let (code, _, stderr) = combustion(&[
        "render",
        scene.to_str().unwrap(),
        "--shadows",
        "on",
        "--width",
        "16",
        "--height",
        "16",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("--shadows on: 3 of its 8 lights that cast shadows cast none (lights 5, 6, 7): the maps hold 32 layers"),
        "{stderr}"
    );
}

/// `diff` reads both headers before it decodes either image: an image past the pixel
/// budget (16,777,216) is refused from its header, and sizes that differ are said before
/// anything is decoded (two 65 KB 8192² PNGs took 6.5 GB and 79 s).
#[test]
fn diff_checks_sizes_before_it_decodes() {
    let dir = scratch("diff-budget");
    let write = |name: &str, side: u32| {
        let path = dir.join(name);
        let file = std::fs::File::create(&path).unwrap();
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), side, side);
        encoder.set_color(png::ColorType::Grayscale);
        encoder.set_depth(png::BitDepth::One);
        let mut writer = encoder.write_header().unwrap();
        writer
            .write_image_data(&vec![0; (side.div_ceil(8) * side) as usize])
            .unwrap();
        writer.finish().unwrap();
        path
    };
    let big = write("big.png", 4097);
    let small = write("small.png", 32);
    let (code, _, stderr) = combustion(&["diff", big.to_str().unwrap(), small.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr
            .contains("4097x4097: more than 16777216 pixels, the most an image compared may have"),
        "{stderr}"
    );
    let other = write("other.png", 31);
    let (code, _, stderr) = combustion(&["diff", small.to_str().unwrap(), other.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("the images differ in size: 32x32 and 31x31"),
        "{stderr}"
    );
}

/// An output whose file name is past 255 bytes is refused before anything renders: the
/// PNG beside it is not written (it was, and then the EXR's write failed).
#[test]
fn a_file_name_too_long_is_refused_before_the_render() {
    let dir = scratch("long-name");
    let png = dir.join("out.png");
    let exr = dir.join(format!("{}.exr", "a".repeat(252)));
    let (code, _, stderr) = combustion(&[
        "render",
        "builtin:spheres",
        "--width",
        "8",
        "--height",
        "8",
        "-o",
        png.to_str().unwrap(),
        "--hdr",
        exr.to_str().unwrap(),
    ]);
    assert_ne!(code, 0, "{stderr}");
    assert!(
        stderr.contains("its file name is 256 bytes long, past the 255 a file name may have"),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(!png.exists(), "nothing written");
}

/// Exposure on the command line: a physical camera's PNG is, byte for byte, the PNG of
/// `--exposure` at its factor (f/4, 1/60 s, ISO 100: EV100 log2(960), the factor
/// 1/(1.2 · 960)); `--auto-exposure on` meters the frame (said on stdout) and its
/// compensation moves the EV100 by the stops given; an exposure set by hand beside the
/// metered one, metering settings without it, and values out of range are refused in one
/// line naming the option.
#[test]
fn exposure_by_camera_by_hand_and_metered() {
    let dir = scratch("exposure");
    let frame = ["--width", "48", "--height", "27"];
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec!["render", "builtin:grid-7x7", "-o", out.to_str().unwrap()];
        args.extend_from_slice(&frame);
        args.extend_from_slice(extra);
        let (code, stdout, stderr) = combustion(&args);
        assert_eq!(code, 0, "{args:?}: {stderr}");
        (std::fs::read(&out).unwrap(), stdout)
    };
    let factor = 1.0 / (1.2 * 960.0f64);
    let (camera, _) = render(
        "camera.png",
        &[
            "--aperture",
            "4",
            "--shutter",
            "0.016666667",
            "--iso",
            "100",
        ],
    );
    let (by_hand, _) = render("hand.png", &["--exposure", &format!("{factor}")]);
    assert_eq!(camera, by_hand, "the physical camera's PNG is --exposure's");
    let ev100 = |stdout: &str| -> f64 {
        let line = stdout
            .lines()
            .find(|l| l.starts_with("auto exposure: EV100 "))
            .unwrap_or_else(|| panic!("no auto exposure line in {stdout}"));
        line["auto exposure: EV100 ".len()..]
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let (_, metered) = render("auto.png", &["--auto-exposure", "on"]);
    let (_, brighter) = render(
        "auto-plus-2.png",
        &["--auto-exposure", "on", "--exposure-compensation", "2"],
    );
    assert!(
        (ev100(&metered) - ev100(&brighter) - 2.0).abs() < 0.011,
        "{metered}{brighter}"
    );
    assert_refused(
        &["render", "--auto-exposure", "on", "--ev", "1"],
        &["--auto-exposure on", "--ev"],
    );
    assert_refused(
        &["render", "--exposure-compensation", "1"],
        &["--exposure-compensation needs --auto-exposure on"],
    );
    assert_refused(
        &[
            "render",
            "--auto-exposure",
            "on",
            "--metering-window",
            "90,10",
        ],
        &["--metering-window", "low percentile 90"],
    );
    assert_refused(
        &[
            "render",
            "--aperture",
            "0.1",
            "--shutter",
            "1",
            "--iso",
            "100",
        ],
        &["--aperture", "between 0.5 and 128"],
    );
    assert_refused(&["render", "--aperture", "4"], &["--shutter", "--iso"]);
    assert_refused(
        &[
            "render",
            "--aperture",
            "4",
            "--shutter",
            "1",
            "--iso",
            "100",
            "--exposure",
            "2",
        ],
        &["--aperture", "--exposure"],
    );
    assert_refused(
        &[
            "render",
            "--iso",
            "nan",
            "--aperture",
            "4",
            "--shutter",
            "1",
        ],
        &["--iso", "not a finite number"],
    );
    assert_refused(
        &["view", "--adaptation-speed", "1,3"],
        &["--adaptation-speed needs --auto-exposure on"],
    );
    assert_refused(
        &["view", "--auto-exposure", "on", "--adaptation-speed", "0,3"],
        &["--adaptation-speed", "between 0.01 and 1000"],
    );
}

/// Bloom on the command line: `--bloom on` renders (validation on) and changes the
/// picture; its intensity without bloom, or out of 0 to 1, is refused in one line naming
/// the option.
#[test]
fn bloom_on_the_command_line() {
    let dir = scratch("bloom");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render",
            "builtin:grid-7x7",
            "--width",
            "64",
            "--height",
            "36",
            "--validate",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, stdout, stderr) = combustion(&args);
        assert_eq!(code, 0, "{args:?}: {stderr}");
        assert!(stdout.contains("bloom "), "bloom is timed: {stdout}");
        std::fs::read(&out).unwrap()
    };
    let plain = {
        let out = dir.join("plain.png");
        let (code, _, stderr) = combustion(&[
            "render",
            "builtin:grid-7x7",
            "--width",
            "64",
            "--height",
            "36",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{stderr}");
        std::fs::read(&out).unwrap()
    };
    let glow = render("bloom.png", &["--bloom", "on", "--bloom-intensity", "0.3"]);
    assert_ne!(glow, plain);
    assert_refused(
        &["render", "--bloom-intensity", "0.1"],
        &["--bloom-intensity needs bloom"],
    );
    assert_refused(
        &["render", "--bloom", "on", "--bloom-intensity", "2"],
        &["--bloom-intensity", "between 0 and 1"],
    );
    assert_refused(
        &["view", "--bloom", "off", "--bloom-intensity", "0.1"],
        &["--bloom-intensity needs bloom"],
    );
}

/// A conductor given by a spectral table whose n is 1e-300 (a band's mean rounds to 0 in
/// 32-bit floats) is refused in one line naming the table and the bands' means — before,
/// the scene's own check refused η ≤ 0 with "the imported scene is invalid: invalid
/// scene: …", naming neither table nor value. A scene invalid for another reason says
/// "invalid" once.
#[test]
fn a_spectral_table_beyond_32_bit_numbers_is_named() {
    let dir = scratch("spectral-underflow");
    let mut scene =
        common::with_coarse_grid_spheres(combustion::scene::builtin_scene("spheres").unwrap());
    scene.objects.truncate(1);
    let file = dir.join("underflow.gltf");
    combustion::scene::gltf::save_gltf(&scene, &file).unwrap();
    let mut root: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    let material = root["meshes"][0]["primitives"][0]["material"]
        .as_u64()
        .unwrap_or(0) as usize;
    root["materials"][material]["extensions"]["COMBUSTION_materials_optics"] =
        serde_json::json!({ "conductor": { "spectrum": "tiny.csv" } });
    root["materials"][material]["pbrMetallicRoughness"]["metallicFactor"] = serde_json::json!(1.0);
    let used = root["extensionsUsed"]
        .as_array_mut()
        .expect("extensions used");
    if !used.iter().any(|e| e == "COMBUSTION_materials_optics") {
        used.push(serde_json::json!("COMBUSTION_materials_optics"));
    }
    std::fs::write(&file, serde_json::to_string(&root).unwrap()).unwrap();
    let rows: Vec<String> = (440..=760)
        .step_by(10)
        .map(|nm| format!("{nm},1e-300,{}", 1.0 + f64::from(nm) / 1000.0))
        .collect();
    std::fs::write(
        dir.join("tiny.csv"),
        format!("wavelength_nm,n,k\n{}\n", rows.join("\n")),
    )
    .unwrap();
    let out = dir.join("x.png");
    let args = [
        "render",
        file.to_str().unwrap(),
        "--width",
        "16",
        "--height",
        "16",
        "-o",
        out.to_str().unwrap(),
    ];
    assert_clear_error(
        &args,
        "spectral table `tiny.csv`: its bands' η (1.000e-300, 1.000e-300, 1.000e-300) are not positive 32-bit numbers",
    );
    assert!(!out.exists());
}

/// `diff --criteria` echoes its criteria's numbers short in its verdict: `mean-flip <=
/// 1e-300`, not 300 digits (and `1e-12/255`, not `0.000000000001/255`).
#[test]
fn diff_criteria_are_echoed_short() {
    let dir = scratch("criteria-short");
    let [a, b] = ["a.png", "b.png"].map(|n| dir.join(n));
    for (file, exposure) in [(&a, "1"), (&b, "2")] {
        let (code, _, stderr) = combustion(&[
            "render",
            "--width",
            "16",
            "--height",
            "16",
            "--exposure",
            exposure,
            "-o",
            file.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{stderr}");
    }
    for (criteria, echoed) in [
        ("mean-flip <= 1e-300", "mean-flip <= 1e-300: mean FLIP is"),
        (
            "max-channel-diff 0.000000000001/255 on at most 0.0000000000001% of pixels",
            "max-channel-diff 1e-12/255 on at most 1e-13% of pixels:",
        ),
    ] {
        let (code, _, stderr) = combustion(&[
            "diff",
            a.to_str().unwrap(),
            b.to_str().unwrap(),
            "--criteria",
            criteria,
        ]);
        assert_eq!(code, 1, "{stderr}");
        assert!(stderr.contains(echoed), "{stderr}");
    }
}

/// A file name holding a terminal's escape sequence is shown with the sequence as an
/// escape (`\u{1b}`) in the one error line, never written to the terminal raw.
#[test]
fn a_file_name_holding_an_escape_sequence_is_shown_escaped() {
    let (code, _stdout, stderr) = combustion(&["render", "--scene", "\u{1b}[2Jscene.gltf"]);
    assert_ne!(code, 0, "{stderr}");
    assert!(!stderr.contains('\u{1b}'), "{stderr:?}");
    assert!(stderr.contains("\\u{1b}[2Jscene.gltf"), "{stderr:?}");
}
