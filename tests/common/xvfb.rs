//! A virtual X server for the tests that open windows (`combustion view`, the example
//! host in a window).

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// An Xvfb server on a display of its own, killed when dropped.
pub struct Xvfb {
    child: Child,
    pub display: u32,
    /// The server reported its display: it made that display's socket and lock file.
    ready: bool,
}

impl Xvfb {
    /// Starts Xvfb on a display it picks itself (`-displayfd`: the server takes the first
    /// free display atomically and writes its number once it accepts connections), so
    /// tests starting servers at the same time never share or remove each other's.
    pub fn start() -> Xvfb {
        use std::io::Read;
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start Xvfb (install xvfb and xauth: bash scripts/dev.sh test does)");
        // The number arrives as one line when the server is ready; EOF if it failed.
        let mut stdout = child.stdout.take().expect("piped");
        let (sender, receiver) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut text = String::new();
            let mut byte = [0u8; 1];
            while stdout.read(&mut byte).is_ok_and(|n| n == 1) && byte[0] != b'\n' {
                text.push(byte[0] as char);
            }
            let _ = sender.send(text);
        });
        let display = receiver
            .recv_timeout(Duration::from_secs(20))
            .ok()
            .and_then(|text| text.trim().parse::<u32>().ok());
        let mut server = Xvfb {
            child,
            display: display.unwrap_or(0),
            ready: display.is_some(),
        };
        if !server.ready {
            let _ = server.child.kill();
            panic!("Xvfb did not start (no display number within 20 s)");
        }
        server
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
        let exited = matches!(self.child.try_wait(), Ok(Some(_)));
        let _ = self.child.kill();
        let _ = self.child.wait();
        // Only after a SIGKILL does the server leave its socket and lock file behind
        // (after SIGTERM it removed them, and another server may own that number now).
        if exited || !self.ready {
            return;
        }
        let _ = std::fs::remove_file(format!("/tmp/.X11-unix/X{}", self.display));
        let _ = std::fs::remove_file(format!("/tmp/.X{}-lock", self.display));
    }
}
