//! Replays a corpus through what a fuzz target does with one input (the tests named
//! fuzz_corpus.rs in crates/scene, spectra, report-csv, criteria, disk-cache and diff, and
//! the root package's tests/fuzz_corpus.rs), and finds the
//! committed corpora: `fuzz/seeds/NAME/` (inputs written by hand, and small corpora, as
//! files) and `fuzz/seeds/NAME.tar.xz` (a target's corpus after a run, minimised with
//! libFuzzer's `-merge=1`).

#![allow(dead_code)] // each replay test uses some of these

use std::path::{Path, PathBuf};
use std::process::Command;

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

/// `fuzz/seeds`, from the including crate's folder (crates/NAME, or the root package).
pub fn seeds() -> PathBuf {
    let package = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = package.join("fuzz/seeds");
    if root.is_dir() {
        root
    } else {
        package.join("../../fuzz/seeds")
    }
}

/// The files of `dir`, sorted.
pub fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .collect();
    files.sort();
    files
}

/// The files of `fuzz/seeds/NAME/`, sorted.
pub fn seed_folder(name: &str) -> Vec<PathBuf> {
    files_in(&seeds().join(name))
}

/// `fuzz/seeds/NAME.tar.xz` unpacked into a fresh folder: the folder (to remove once
/// replayed) and its files, sorted.
pub fn unpacked_archive(name: &str) -> (PathBuf, Vec<PathBuf>) {
    let archive = seeds().join(format!("{name}.tar.xz"));
    let dir = std::env::temp_dir().join(format!("combustion-corpus-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let status = Command::new("tar")
        .arg("-xJf")
        .arg(&archive)
        .arg("-C")
        .arg(&dir)
        .status()
        .expect("tar (with xz) unpacks the corpus: scripts/dev.sh installs xz-utils");
    assert!(status.success(), "tar -xJf {}", archive.display());
    let files = files_in(&dir);
    (dir, files)
}

/// Every input of `fuzz/seeds/NAME/` through `run`, none of which may panic (the names
/// of those that did fail the test); how many there were.
pub fn replay_seeds(name: &str, run: fn(&[u8])) -> usize {
    assert_none_panicked(
        &format!("fuzz/seeds/{name}/"),
        replay(&seed_folder(name), run),
    )
}

/// Every input of `fuzz/seeds/NAME.tar.xz` through `run`, as [`replay_seeds`].
pub fn replay_archive(name: &str, run: fn(&[u8])) -> usize {
    let (dir, files) = unpacked_archive(name);
    let replayed = replay(&files, run);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_none_panicked(&format!("fuzz/seeds/{name}.tar.xz"), replayed)
}

fn assert_none_panicked(corpus: &str, (inputs, panicked): (usize, Vec<String>)) -> usize {
    assert!(
        panicked.is_empty(),
        "{} of {inputs} inputs of {corpus} panicked: {panicked:?}",
        panicked.len()
    );
    inputs
}
