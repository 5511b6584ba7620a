//! The committed report-CSV fuzz corpora replayed through the code the fuzz target runs
//! (fuzz/common/report_csv.rs): no input may panic `bench --against`'s reader or break
//! the quoting's round trip. `fuzz/seeds/report_csv/` holds inputs written by hand (the
//! two stored reports among them); `fuzz/seeds/report_csv.tar.xz` the target's corpus
//! after an hour's run, minimised with libFuzzer's `-merge=1`.

#[path = "../../../fuzz/common/report_csv.rs"]
mod fuzz_target;
#[path = "../../../fuzz/common/replay.rs"]
mod replay;

use std::path::PathBuf;

fn assert_replays(name: &str, files: &[PathBuf], at_least: usize) {
    let (inputs, panicked) = replay::replay(files, fuzz_target::parse_and_round_trip);
    assert!(
        panicked.is_empty(),
        "{name}: {panicked:?} of {inputs} panicked"
    );
    assert!(inputs >= at_least, "{name}: {inputs} inputs");
}

#[test]
fn the_report_csv_seeds_replay_without_a_panic() {
    assert_replays("seeds", &replay::seed_folder("report_csv"), 7);
}

#[test]
fn the_report_csv_corpus_replays_without_a_panic() {
    let (dir, files) = replay::unpacked_archive("report_csv");
    assert_replays("report_csv.tar.xz", &files, 300);
    std::fs::remove_dir_all(&dir).unwrap();
}
