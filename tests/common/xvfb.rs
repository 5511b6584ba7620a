//! A virtual X server for the tests that open windows (`combustion view`, the example
//! host in a window).

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// An Xvfb server on a display of its own, killed when dropped.
pub struct Xvfb {
    child: Child,
    pub display: u32,
    /// The socket appeared: this server made it (and its lock file).
    ready: bool,
}

impl Xvfb {
    /// Starts Xvfb on the first free display of :90..:99 and waits (bounded) for its socket.
    pub fn start() -> Xvfb {
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
