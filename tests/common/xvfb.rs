//! A virtual X server for the tests that open windows (`combustion view`, the example
//! host in a window).

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// An Xvfb server on a display of its own, killed when dropped.
pub struct Xvfb {
    child: Child,
    pub display: u32,
    /// The server reported its display.
    ready: bool,
}

impl Xvfb {
    /// Starts Xvfb on a display number of its own and waits (bounded) until it accepts
    /// connections (`-displayfd`: the server writes the number once it is listening).
    ///
    /// The number is drawn at random from :1000..:31000 rather than taking the first free
    /// one: tests in other processes start and stop servers at the same time, and a
    /// number freed by one server and taken at once by the next was seen to refuse
    /// clients (the old server's cleanup racing the new one's sockets). A number taken
    /// already makes the server exit, and another is drawn.
    pub fn start() -> Xvfb {
        use std::io::Read;
        let seed = std::process::id() as u64
            ^ std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_nanos() as u64);
        for attempt in 0..20u64 {
            let display = 1000
                + (seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(attempt * 1442695040888963407)
                    >> 33)
                    % 30000;
            let mut child = Command::new("Xvfb")
                .args([
                    &format!(":{display}"),
                    "-displayfd",
                    "1",
                    "-screen",
                    "0",
                    "1024x768x24",
                    "-nolisten",
                    "tcp",
                    // Without it, the server resets whenever its last client disconnects,
                    // and a client connecting during the reset is refused (seen with the
                    // probe below, and with xdotool's short-lived connections).
                    "-noreset",
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
            let reported = receiver
                .recv_timeout(Duration::from_secs(20))
                .ok()
                .and_then(|text| text.trim().parse::<u32>().ok());
            if let Some(display) = reported {
                // Wait (bounded) until its socket accepts a connection.
                let socket = format!("/tmp/.X11-unix/X{display}");
                let deadline = Instant::now() + Duration::from_secs(10);
                while std::os::unix::net::UnixStream::connect(&socket).is_err()
                    && Instant::now() < deadline
                {
                    std::thread::sleep(Duration::from_millis(10));
                }
                return Xvfb {
                    child,
                    display,
                    ready: true,
                };
            }
            let _ = child.kill();
            let _ = child.wait();
        }
        panic!("Xvfb did not start on any of 20 display numbers");
    }
}

/// Stops a server: SIGTERM (it removes its own socket and lock file), then SIGKILL if it
/// lingers past 10 s.
pub fn terminate(child: &mut Child) {
    let _ = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status();
    let deadline = Instant::now() + Duration::from_secs(10);
    while matches!(child.try_wait(), Ok(None)) && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(10));
    }
    let _ = child.kill();
    let _ = child.wait();
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        // Nothing is removed here: after a SIGKILL the next server finds the stale lock
        // (its process is gone) and takes the display over, whereas removing the files
        // here could delete those of a server that has just taken the number.
        terminate(&mut self.child);
    }
}
