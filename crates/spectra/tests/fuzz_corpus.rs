//! The committed spectral-table fuzz corpus (fuzz/seeds/spectrum_csv: the target's corpus
//! after an hour's run, minimised with libFuzzer's `-merge=1`) replayed through the code
//! the fuzz target runs (fuzz/common/spectrum.rs): no input may panic the parser or the
//! band means.

#[path = "../../../fuzz/common/spectrum.rs"]
mod fuzz_target;

#[test]
fn the_spectrum_corpus_replays_without_a_panic() {
    let dir =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/spectrum_csv");
    let mut panicked = Vec::new();
    let mut inputs = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let data = std::fs::read(&path).unwrap();
        inputs += 1;
        if std::panic::catch_unwind(|| fuzz_target::parse_and_reduce(&data)).is_err() {
            panicked.push(path.file_name().unwrap().to_string_lossy().into_owned());
        }
    }
    assert!(panicked.is_empty(), "{panicked:?} panicked");
    assert!(inputs > 300, "{inputs} inputs");
}
