//! Replays a corpus through what a fuzz target does with one input (the tests in
//! crates/scene/tests/fuzz_corpus.rs and crates/spectra/tests/fuzz_corpus.rs).

use std::path::PathBuf;

/// Runs every file of `files` through `run`; returns how many there were and the names
/// of those that panicked.
pub fn replay(files: &[PathBuf], run: fn(&[u8])) -> (usize, Vec<String>) {
    let mut panicked = Vec::new();
    for file in files {
        let data = std::fs::read(file).unwrap();
        if std::panic::catch_unwind(|| run(&data)).is_err() {
            panicked.push(file.file_name().unwrap().to_string_lossy().into_owned());
        }
    }
    (files.len(), panicked)
}
