//! A headless Wayland compositor (Weston's headless backend) for the tests that open
//! windows on Wayland.

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A Weston compositor with a runtime folder and socket of its own, killed (and its
/// folder removed) when dropped.
pub struct Weston {
    child: Child,
    /// `XDG_RUNTIME_DIR` of the compositor and its clients.
    pub runtime_dir: PathBuf,
    /// `WAYLAND_DISPLAY`: the socket's name in `runtime_dir`.
    pub socket: String,
}

impl Weston {
    /// Starts Weston (headless backend, no idle blanking) and waits (bounded) until its
    /// socket accepts connections.
    pub fn start() -> Weston {
        use std::os::unix::fs::PermissionsExt;
        static STARTED: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = STARTED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let runtime_dir =
            std::env::temp_dir().join(format!("combustion-weston-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&runtime_dir);
        std::fs::create_dir_all(&runtime_dir).expect("the compositor's runtime folder");
        std::fs::set_permissions(&runtime_dir, std::fs::Permissions::from_mode(0o700))
            .expect("runtime folder permissions");
        let socket = "wayland-combustion".to_owned();
        let child = Command::new("weston")
            .args([
                "--backend=headless-backend.so",
                &format!("--socket={socket}"),
                "--width=1024",
                "--height=768",
                "--idle-time=0",
            ])
            .env("XDG_RUNTIME_DIR", &runtime_dir)
            .env_remove("WAYLAND_DISPLAY")
            .env_remove("DISPLAY")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start weston (install weston: bash scripts/dev.sh test does)");
        let mut weston = Weston {
            child,
            runtime_dir,
            socket,
        };
        let path = weston.runtime_dir.join(&weston.socket);
        let deadline = Instant::now() + Duration::from_secs(20);
        while std::os::unix::net::UnixStream::connect(&path).is_err() {
            if let Ok(Some(status)) = weston.child.try_wait() {
                panic!("weston exited before listening: {status}");
            }
            assert!(
                Instant::now() < deadline,
                "weston did not listen within 20 s"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        weston
    }
}

impl Drop for Weston {
    fn drop(&mut self) {
        super::xvfb::terminate(&mut self.child);
        let _ = std::fs::remove_dir_all(&self.runtime_dir);
    }
}
