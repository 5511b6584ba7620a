//! `combustion view` under a virtual X server (Xvfb): frames are rendered, presented and
//! everything torn down with the validation layer silent; without a display the command
//! fails with one line.

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::xvfb::Xvfb;

/// Runs `combustion view ARGS` with `DISPLAY=display`, killing it after 60 s.
fn view(display: &str, args: &[&str]) -> (Option<i32>, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_combustion"))
        .arg("view")
        .args(args)
        .env("DISPLAY", display)
        .env_remove("WAYLAND_DISPLAY")
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
    (
        status.code(),
        String::from_utf8_lossy(&stdout).into_owned(),
        String::from_utf8_lossy(&stderr).into_owned(),
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
        assert!(
            !stderr.contains("error") && !stderr.contains("[WARN") && !stderr.contains("[ERROR"),
            "{stderr}"
        );
        assert!(
            stdout.starts_with("viewed 5 frames at 160x120 on llvmpipe"),
            "{stdout}"
        );
        assert!(stdout.contains("on-device presentation"), "{stdout}");
        assert_eq!(stdout.lines().count(), 1, "{stdout}");
    }
    drop(xvfb);
    let (code, _, stderr) = view(":0", &["--vsync", "sometimes"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("--vsync: `sometimes` is not on or off"),
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
