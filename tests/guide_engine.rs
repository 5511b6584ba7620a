//! The engine written from docs/integration.md alone (examples/guide_engine.rs), run for
//! 40 frames under validation with synchronisation validation: every built-in scene,
//! the two sample glTF files when the shared data is present, scene edits by handle, a
//! resize, three frames in flight. No validation message and no error.

use crate::common;
#[allow(dead_code)]
#[path = "../examples/guide_engine.rs"]
mod engine;

use std::path::PathBuf;

#[test]
fn guide_engine_runs_40_frames_without_validation_messages() {
    let gltf: Vec<PathBuf> = common::shared_gltf_samples()
        .map(|root| {
            ["LightsPunctualLamp", "ClearCoatTest"]
                .iter()
                .map(|name| root.join(name))
                .collect()
        })
        .unwrap_or_default();
    let options = engine::Options {
        frames: 40,
        width: 96,
        height: 64,
        resized: (120, 80),
        gltf,
        switch_every: 3,
        edit_every: 2,
        verbose: false,
    };
    let report = engine::run(&options);
    assert_eq!(report.error, None, "the engine failed");
    assert_eq!(report.frames, 40);
    assert_eq!(
        report.validation_messages, 0,
        "validation messages (see stderr)"
    );
    assert!(report.edits >= 9, "{} edits", report.edits);
}
