//! `combustion view` under a virtual X server (Xvfb): frames are rendered, presented and
//! everything torn down with the validation layer silent; without a display the command
//! fails with one line.

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// An Xvfb server on a display of its own, killed when dropped.
struct Xvfb {
    child: Child,
    display: u32,
    /// The socket appeared: this server made it (and its lock file).
    ready: bool,
}

impl Xvfb {
    /// Starts Xvfb on the first free display of :90..:99 and waits (bounded) for its socket.
    fn start() -> Xvfb {
        for display in 90..100 {
            if Path::new(&format!("/tmp/.X11-unix/X{display}")).exists()
                || Path::new(&format!("/tmp/.X{display}-lock")).exists()
            {
                continue;
            }
            let child = Command::new("Xvfb")
                .args([
                    &format!(":{display}"),
                    "-screen",
                    "0",
                    "1024x768x24",
                    "-nolisten",
                    "tcp",
                ])
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("start Xvfb (install xvfb and xauth: bash scripts/dev.sh test does)");
            let mut server = Xvfb {
                child,
                display,
                ready: false,
            };
            let socket = format!("/tmp/.X11-unix/X{display}");
            let deadline = Instant::now() + Duration::from_secs(10);
            while Instant::now() < deadline {
                if Path::new(&socket).exists() {
                    server.ready = true;
                    return server;
                }
                // Exited early: the display was taken meanwhile; try the next one.
                if server.child.try_wait().expect("poll Xvfb").is_some() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
            drop(server);
        }
        panic!("could not start Xvfb on any display of :90..:99");
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        // SIGTERM lets Xvfb remove its socket and lock file; SIGKILL only if it lingers.
        let _ = Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status();
        let deadline = Instant::now() + Duration::from_secs(3);
        while matches!(self.child.try_wait(), Ok(None)) && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
        // After a SIGKILL the server leaves both behind; they were free when it started.
        if !self.ready {
            return;
        }
        let _ = std::fs::remove_file(format!("/tmp/.X11-unix/X{}", self.display));
        let _ = std::fs::remove_file(format!("/tmp/.X{}-lock", self.display));
    }
}

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
    let (code, stdout, stderr) = view(
        &format!(":{}", xvfb.display),
        &[
            "builtin:spheres",
            "--width",
            "160",
            "--height",
            "120",
            "--frames",
            "5",
            "--validate",
        ],
    );
    drop(xvfb);
    assert_eq!(code, Some(0), "stdout: {stdout}\nstderr: {stderr}");
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
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
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
