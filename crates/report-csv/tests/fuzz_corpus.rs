//! The committed report-CSV fuzz corpora replayed through the code the fuzz target runs
//! (fuzz/common/report_csv.rs): no input may panic `bench --against`'s reader or break
//! the quoting's round trip. `fuzz/seeds/report_csv/` holds inputs written by hand (the
//! two stored reports among them); `fuzz/seeds/report_csv.tar.xz` the target's corpus
//! after an hour's run, minimised with libFuzzer's `-merge=1`.

#[path = "../../../fuzz/common/report_csv.rs"]
mod fuzz_target;
#[path = "../../../fuzz/common/replay.rs"]
mod replay;

#[test]
fn the_report_csv_seeds_replay_without_a_panic() {
    let inputs = replay::replay_seeds("report_csv", fuzz_target::parse_and_round_trip);
    assert!(inputs >= 7, "{inputs} inputs");
}

#[test]
fn the_report_csv_corpus_replays_without_a_panic() {
    let inputs = replay::replay_archive("report_csv", fuzz_target::parse_and_round_trip);
    assert!(inputs >= 300, "{inputs} inputs");
}
