//! The promises about failure and about the hot path, tested by injecting faults into
//! the device (`combustion::vk::Device::fail_submission`, `fail_allocation`) and
//! counting what it is asked to do (`Device::counters`, `Renderer::stats`):
//! - a failed submission is a typed `DeviceLost` / `OutOfMemory`, nothing waits for
//!   the frame that was never submitted, and the next frames render as before;
//! - a failed allocation anywhere in an upload is a typed `OutOfMemory` and leaves
//!   nothing behind (the validation layer reports any object not destroyed);
//! - a run of frames compiles no shader, builds no pipeline, allocates nothing, reads
//!   nothing back, never waits for the device to be idle, and waits for one fence per
//!   frame at most (the slot the ring reuses).
//!
//! Each test runs under a watchdog: a hang is a failure, not a stuck CI job.

use crate::common;

use std::sync::mpsc;
use std::time::Duration;

use combustion::renderer::{Readback, RenderError};
use combustion::scene::builtin_scene;
use combustion::vk::{InjectedFault, VkError};

/// Runs `body` on its own thread and fails if it does not finish within `seconds`.
fn within(seconds: u64, body: impl FnOnce() + Send + 'static) {
    let (done, finished) = mpsc::channel();
    let thread = std::thread::spawn(move || {
        body();
        let _ = done.send(());
    });
    match finished.recv_timeout(Duration::from_secs(seconds)) {
        Ok(()) => thread.join().unwrap(),
        // The body panicked: its panic is the failure.
        Err(mpsc::RecvTimeoutError::Disconnected) => {
            if let Err(panic) = thread.join() {
                std::panic::resume_unwind(panic);
            }
        }
        Err(mpsc::RecvTimeoutError::Timeout) => panic!("hung for {seconds} s"),
    }
}

const IMAGES: Readback = Readback::IMAGES;

fn is_fault(error: &RenderError, fault: InjectedFault) -> bool {
    matches!(
        (fault, error),
        (
            InjectedFault::DeviceLost,
            RenderError::Vulkan(VkError::DeviceLost { .. })
        ) | (
            InjectedFault::OutOfMemory,
            RenderError::Vulkan(VkError::OutOfMemory { .. })
        )
    )
}

#[test]
fn a_failed_submission_is_a_typed_error_and_the_next_frame_renders() {
    within(120, || {
        let mut headless = common::lavapipe(common::exact_f32());
        let renderer = headless.renderer();
        let scene = renderer.upload(&builtin_scene("spheres").unwrap()).unwrap();
        let before = renderer.render(&scene, 64, 48, IMAGES).unwrap();
        for fault in [InjectedFault::DeviceLost, InjectedFault::OutOfMemory] {
            renderer.device().fail_submission(0, fault);
            let error = renderer.render(&scene, 64, 48, IMAGES).unwrap_err();
            assert!(is_fault(&error, fault), "{fault:?}: {error}");
            let after = renderer.render(&scene, 64, 48, IMAGES).unwrap();
            assert_eq!(after.ldr, before.ldr, "after {fault:?}");
        }
        // Frames in flight: the second of five submissions fails; the others are
        // submitted and completed, and finishing waits for none that was not.
        for frame in 0..5 {
            if frame == 1 {
                renderer
                    .device()
                    .fail_submission(0, InjectedFault::DeviceLost);
                let error = renderer.submit_offscreen(&scene, 64, 48).unwrap_err();
                assert!(is_fault(&error, InjectedFault::DeviceLost), "{error}");
            } else {
                renderer.submit_offscreen(&scene, 64, 48).unwrap();
            }
        }
        renderer.finish_offscreen().unwrap();
        assert_eq!(
            renderer.render(&scene, 64, 48, IMAGES).unwrap().ldr,
            before.ldr
        );
        drop(scene);
        common::finish(headless);
    });
}

#[test]
fn a_failed_allocation_anywhere_in_an_upload_is_out_of_memory_and_leaves_nothing() {
    within(300, || {
        let mut headless = common::lavapipe(common::exact_f32());
        let renderer = headless.renderer();
        let scene = builtin_scene("hard-cases").unwrap();
        let reference = {
            let gpu = renderer.upload(&scene).unwrap();
            renderer.render(&gpu, 48, 32, IMAGES).unwrap()
        };
        // Fail the first allocation of the upload, then the second, and so on, until an
        // upload makes fewer allocations than the one armed to fail.
        let mut failures = 0;
        for n in 0.. {
            let device = renderer.device().clone();
            let allocations = device.counters().allocations;
            device.fail_allocation(n);
            let result = renderer.upload(&scene);
            let made = device.counters().allocations - allocations;
            device.clear_faults();
            match result {
                Err(error) => {
                    assert!(is_fault(&error, InjectedFault::OutOfMemory), "{n}: {error}");
                    failures += 1;
                }
                Ok(gpu) => {
                    assert!(made <= n, "allocation {n} failed unseen");
                    let frame = renderer.render(&gpu, 48, 32, IMAGES).unwrap();
                    assert_eq!(frame.ldr, reference.ldr);
                    break;
                }
            }
        }
        eprintln!("an upload of hard-cases failed cleanly at each of its {failures} allocations");
        assert!(failures >= 3, "{failures}");
        common::finish(headless);
    });
}

#[test]
fn a_run_of_frames_compiles_builds_allocates_and_reads_back_nothing() {
    within(120, || {
        let mut headless = common::lavapipe(common::exact_f32());
        let renderer = headless.renderer();
        let spheres = renderer.upload(&builtin_scene("spheres").unwrap()).unwrap();
        let hard = renderer
            .upload(&builtin_scene("hard-cases").unwrap())
            .unwrap();
        // Warm-up: each scene and size once.
        for scene in [&spheres, &hard] {
            renderer.submit_offscreen(scene, 64, 48).unwrap();
        }
        renderer.finish_offscreen().unwrap();
        let device = renderer.device().clone();
        let (counters, stats) = (device.counters(), renderer.stats());
        const FRAMES: u64 = 40;
        for frame in 0..FRAMES {
            let scene = if frame % 2 == 0 { &spheres } else { &hard };
            renderer.submit_offscreen(scene, 64, 48).unwrap();
        }
        renderer.finish_offscreen().unwrap();
        let run = device.counters().since(&counters);
        let after = renderer.stats();
        eprintln!("{FRAMES} frames: {run:?}");
        assert_eq!(after.frames - stats.frames, FRAMES);
        assert_eq!(after.shaders_compiled, stats.shaders_compiled, "compiled");
        assert_eq!(after.pipelines_built, stats.pipelines_built, "pipelines");
        assert_eq!(after.readbacks, stats.readbacks, "read back");
        assert_eq!(run.allocations, 0, "allocated");
        assert_eq!(run.idle_waits, 0, "waited idle");
        assert_eq!(run.submissions, FRAMES);
        // One fence per frame: the slot each frame reuses; and finishing waits for the
        // frames still in flight (one per slot).
        let in_flight = common::exact_f32().frames_in_flight as u64;
        assert!(run.fence_waits <= FRAMES + in_flight, "{run:?}");
        drop((spheres, hard));
        common::finish(headless);
    });
}
