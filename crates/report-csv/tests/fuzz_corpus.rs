//! The committed report-CSV fuzz corpus (fuzz/seeds/report_csv: the target's corpus after
//! its run, minimised with libFuzzer's `-merge=1`) replayed through the code the fuzz
//! target runs (fuzz/common/report_csv.rs): no input may panic `bench --against`'s reader
//! or break the quoting's round trip.

#[path = "../../../fuzz/common/report_csv.rs"]
mod fuzz_target;
#[path = "../../../fuzz/common/replay.rs"]
mod replay;

#[test]
fn the_report_csv_corpus_replays_without_a_panic() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/report_csv");
    let files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .collect();
    let (inputs, panicked) = replay::replay(&files, fuzz_target::parse_and_round_trip);
    assert!(panicked.is_empty(), "{panicked:?} panicked");
    assert!(inputs >= 5, "{inputs} inputs");
}
