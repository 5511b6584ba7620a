//! The committed spectral-table fuzz corpus (fuzz/seeds/spectrum_csv: the target's corpus
//! after an hour's run, minimised with libFuzzer's `-merge=1`) replayed through the code
//! the fuzz target runs (fuzz/common/spectrum.rs): no input may panic the parser or the
//! band means.

#[path = "../../../fuzz/common/spectrum.rs"]
mod fuzz_target;
#[path = "../../../fuzz/common/replay.rs"]
mod replay;

#[test]
fn the_spectrum_corpus_replays_without_a_panic() {
    let dir =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/spectrum_csv");
    let files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .collect();
    let (inputs, panicked) = replay::replay(&files, fuzz_target::parse_and_reduce);
    assert!(panicked.is_empty(), "{panicked:?} panicked");
    assert!(inputs > 300, "{inputs} inputs");
}
