//! The committed fuzz corpora (fuzz/seeds/gltf_import.tar.xz and
//! gltf_import_validate.tar.xz: each target's corpus after an hour's run, minimised with
//! libFuzzer's `-merge=1`) replayed through the code each fuzz target runs
//! (fuzz/common/gltf.rs): no input may panic the importer or `Scene::validate`. A change
//! that breaks an input the fuzzer had reached fails here, in the ordinary test run, with
//! the input's name.

#[path = "../../../fuzz/common/animation.rs"]
mod animation_target;
#[path = "../../../fuzz/common/camera_path.rs"]
mod camera_path_target;
#[path = "../../../fuzz/common/environment.rs"]
mod environment_target;
#[path = "../../../fuzz/common/gltf.rs"]
mod gltf;
#[path = "../../../fuzz/common/replay.rs"]
mod replay;

#[test]
fn the_importer_corpus_replays_without_a_panic() {
    let inputs = replay::replay_archive("gltf_import", gltf::import_both_ways);
    // The archive holds the minimised corpus, not a stub.
    assert!(inputs > 10_000, "{inputs} inputs");
}

#[test]
fn the_import_and_validate_corpus_replays_without_a_panic() {
    let inputs = replay::replay_archive("gltf_import_validate", gltf::import_and_validate);
    assert!(inputs > 10_000, "{inputs} inputs");
}

/// The importer turns its own panics into `ImportProblem::Internal` errors; the replay
/// (and the fuzzer, which runs the same code) counts such an error as the crash it is.
#[test]
#[should_panic(expected = "the importer panicked: index out of bounds")]
fn an_internal_error_of_the_importer_is_a_crash_to_the_replay() {
    use combustion_scene::gltf::{ImportError, ImportProblem};
    gltf::imported(Err(ImportError {
        file: "<memory>".into(),
        problem: ImportProblem::Internal("index out of bounds".into()),
    }));
}

/// The animation sampling corpus (fuzz/seeds/animation_sampling/: the hand-made seeds
/// its generate.py writes — each kind of channel and interpolation, morph weights, a
/// skin, rotation keys from q to -q and all zero, times of NaN, infinity and 1e30 — and
/// animation_sampling.tar.xz, an hour's run minimised) through the sampling and posing, as
/// the `animation_sampling` target runs them.
#[test]
fn the_animation_sampling_corpus_replays_without_a_panic() {
    let inputs = replay::replay_seeds("animation_sampling", animation_target::sample_animations);
    assert!(inputs >= 12, "{inputs} inputs");
    // And the corpus of an hour's run, minimised (fuzz/seeds/animation_sampling.tar.xz).
    let archived =
        replay::replay_archive("animation_sampling", animation_target::sample_animations);
    assert!(archived > 13_000, "{archived} inputs");
    // The hand-made seeds reach the sampling — each imports, with an animation — but
    // the two the importer refuses: keys that are not unit quaternions, and a scale of
    // 3e38 whose scene spans more than f32 holds (its numbers written short).
    let options = combustion_scene::gltf::ImportOptions::default();
    let mut refused = Vec::new();
    for file in replay::seed_folder("animation_sampling") {
        if file.extension().is_some_and(|e| e == "seed") {
            let data = std::fs::read(&file).unwrap();
            match combustion_scene::gltf::import_slice(&data[8..], &options) {
                Ok((scene, _)) => {
                    assert!(!scene.motion.animations.is_empty(), "{}", file.display())
                }
                Err(e) => refused.push(e.to_string()),
            }
        }
    }
    assert!(
        refused.len() == 2
            && refused[0].contains("not a unit quaternion")
            && refused[1].contains("to (3e38, 3e38, 0): more than f32 can hold"),
        "{refused:?}"
    );
}

/// The camera paths' corpus (fuzz/seeds/camera_path/) through the parser and the
/// cameras of every path it accepts, as the `camera_path` target runs them.
#[test]
fn the_camera_path_corpus_replays_without_a_panic() {
    let inputs = replay::replay_seeds("camera_path", camera_path_target::parse_and_follow);
    assert!(inputs >= 5, "{inputs} inputs");
}

/// The environment images' corpora (fuzz/seeds/environment_image/, written by hand and
/// the fuzzer's first find, as files; environment_image.tar.xz, an hour's run minimised:
/// the first byte of an input picks .hdr or .exr) through the readers, as the
/// `environment_image` target runs them.
#[test]
fn the_environment_image_corpus_replays_without_a_panic() {
    let inputs = replay::replay_seeds("environment_image", environment_target::decode);
    // And the corpus of an hour's run, minimised (fuzz/seeds/environment_image.tar.xz).
    let archived = replay::replay_archive("environment_image", environment_target::decode);
    assert!(archived > 4_000, "{archived} inputs");
    // Both formats, accepted and refused, are in it (not a stub).
    assert!(inputs >= 6, "{inputs} inputs");
}
