//! What rendering on a CPU device (lavapipe) costs the process besides the frames'
//! work: the heap it keeps (combustion_vk::HeapTrim).

use crate::common;

use combustion::renderer::{Readback, RendererSettings};
use combustion::scene::builtin_scene;

/// Set in the child process that measures alone (the test binary run again for one test).
const CHILD: &str = "COMBUSTION_CPU_DEVICE_CHILD";

/// The minor page faults of the whole process so far (memory faulted in, zeroed by the
/// kernel when fresh).
fn minor_faults() -> i64 {
    let mut usage = std::mem::MaybeUninit::<libc::rusage>::zeroed();
    // SAFETY: getrusage writes the struct it is given.
    let status = unsafe { libc::getrusage(libc::RUSAGE_SELF, usage.as_mut_ptr()) };
    assert_eq!(status, 0, "getrusage");
    // SAFETY: written by the successful call above.
    unsafe { usage.assume_init() }.ru_minflt
}

/// lavapipe bins each frame's triangles in memory of the process's heap and frees it when
/// the frame is drawn; given back to the system each time (glibc's thresholds where a
/// process starts, as some processes keep them), every frame faults it in anew — about
/// 5,800 pages a frame on builtin:grid-7x7 at 1280×720, a quarter of its G-buffer pass
/// (docs/performance.md). With the heap kept (the default on a CPU device), a warm frame
/// faults in nearly nothing: the frames here, after three of warm-up, average at most 100
/// minor faults (0.4 MB); with the system's behaviour they took 3,400–8,500 a frame.
///
/// Measured in a process of its own (the faults are the whole process's), whose
/// environment sets no threshold of glibc's allocator (the test command sets them for
/// the test processes: an environment's setting is kept, so the renderer's own would
/// not be tested there).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[test]
fn frames_on_a_cpu_device_fault_in_no_memory_anew() {
    let test = "cpu_device::frames_on_a_cpu_device_fault_in_no_memory_anew";
    if std::env::var_os(CHILD).is_none() {
        let output = std::process::Command::new(std::env::current_exe().unwrap())
            .args([test, "--exact", "--nocapture", "--test-threads", "1"])
            .env(CHILD, "1")
            .env_remove("GLIBC_TUNABLES")
            .env_remove("MALLOC_TRIM_THRESHOLD_")
            .env_remove("MALLOC_MMAP_THRESHOLD_")
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&output.stdout);
        let stderr = String::from_utf8_lossy(&output.stderr);
        eprintln!("{stdout}{stderr}");
        assert!(output.status.success(), "{test} in its own process failed");
        assert!(
            stderr.contains("minor page faults per warm frame"),
            "{test}: the child measured nothing"
        );
        return;
    }
    let mut headless = common::lavapipe(RendererSettings::default());
    {
        let renderer = headless.renderer();
        let scene = builtin_scene("grid-7x7").unwrap();
        let gpu_scene = renderer.upload(&scene).expect("upload");
        let render = |renderer: &mut combustion::renderer::Renderer| {
            renderer
                .render(&gpu_scene, 640, 360, Readback::default())
                .expect("render");
        };
        for _ in 0..3 {
            render(renderer);
        }
        let frames = 12;
        let before = minor_faults();
        for _ in 0..frames {
            render(renderer);
        }
        let per_frame = (minor_faults() - before) as f64 / f64::from(frames);
        eprintln!("minor page faults per warm frame: {per_frame:.0}");
        assert!(
            per_frame <= 100.0,
            "{per_frame:.0} minor page faults per frame: the memory the device frees each \
             frame is given back to the system and faulted in again"
        );
    }
    common::finish(headless);
}
