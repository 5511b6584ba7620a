//! What the `animation_sampling` fuzz target does with one input, shared with the test
//! that replays its corpus (crates/scene/tests/fuzz_corpus.rs).
//!
//! The input is two little-endian f32 times (any bits: NaN, infinities, negative, huge),
//! then a glTF file (JSON, or GLB by its magic). Every animation of a scene the importer
//! accepts (the first four) is sampled at those times and at its start, middle and end —
//! the pose must exist for every animation index, hold a transform and weights for every
//! object — and a pose whose every number is finite (what `render --time` and the viewer
//! go on with; the rest they refuse, naming the file, animation and time) is posed: the
//! still scene must validate or say why, and have bounds, never panic.

// The glTF targets' module (common/gltf.rs), declared beside this one by its includer.
use super::gltf;

use combustion_scene::gltf::{import_slice, ImportOptions};

/// `animation_sampling`.
pub fn sample_animations(data: &[u8]) {
    let Some((times, file)) = data.split_first_chunk::<8>() else {
        return;
    };
    let given = [
        f32::from_le_bytes([times[0], times[1], times[2], times[3]]),
        f32::from_le_bytes([times[4], times[5], times[6], times[7]]),
    ];
    let options = ImportOptions {
        max_image_dimension: 64,
        max_decoded_pixels: 1 << 16,
        ..ImportOptions::default()
    };
    let Some(scene) = gltf::imported(import_slice(file, &options)) else {
        return;
    };
    for (index, animation) in scene.motion.animations.iter().enumerate().take(4) {
        let duration = animation.duration();
        for time in given.into_iter().chain([0.0, 0.5 * duration, duration]) {
            let poses = scene
                .pose_at(index, time)
                .unwrap_or_else(|| panic!("animation {index} has no pose at {time}"));
            assert_eq!(poses.transforms.len(), scene.objects.len());
            assert_eq!(poses.weights.len(), scene.objects.len());
            let finite = poses.transforms.iter().all(|m| m.is_finite())
                && poses.weights.iter().flatten().all(|w| w.is_finite())
                && poses.joints.iter().flatten().all(|m| m.is_finite());
            if finite {
                let still = scene.posed(&poses);
                let _ = still.validate();
                let _ = still.world_bounds();
            }
        }
    }
}
