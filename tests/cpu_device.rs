//! What rendering on a CPU device (lavapipe) costs the process besides the frames'
//! work: the heap it keeps (combustion_vk::HeapTrim).

use crate::common;

use combustion::renderer::{Readback, RendererSettings};
use combustion::scene::builtin_scene;

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
/// the frame is drawn; given back to the system each time (glibc's trim threshold at its
/// starting value, as some processes have it), every frame faults it in anew — about
/// 5,800 pages a frame on builtin:grid-7x7 at 1280×720, a quarter of its G-buffer pass
/// (docs/performance.md). With the heap kept (the default on a CPU device), a warm frame
/// faults in nearly nothing: the frames here, after three of warm-up, average at most 100
/// minor faults (0.4 MB); with the system's behaviour they took 3,400–4,000 a frame.
#[test]
fn frames_on_a_cpu_device_fault_in_no_memory_anew() {
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
