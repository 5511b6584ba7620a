//! The criteria fuzz target's corpus (fuzz/seeds/criteria/: hand-made seeds and what the
//! fuzzer kept) replayed through the code the target runs (fuzz/common/criteria.rs): no
//! input may panic the parser, fail its echo's round trip or the check.

#[path = "../../../fuzz/common/criteria.rs"]
mod criteria_target;
#[path = "../../../fuzz/common/replay.rs"]
mod replay;

#[test]
fn the_criteria_corpus_replays_without_a_panic() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/criteria");
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .collect();
    files.sort();
    let (inputs, panicked) = replay::replay(&files, criteria_target::parse_and_check);
    assert!(panicked.is_empty(), "{panicked:?} of {inputs} panicked");
    assert!(inputs >= 7, "{inputs} inputs");
}
