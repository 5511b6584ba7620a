//! The criteria fuzz target's corpora — fuzz/seeds/criteria/ (hand-made seeds and its
//! first find) and criteria.tar.xz (a run's corpus, minimised) — replayed through the
//! code the target runs (fuzz/common/criteria.rs): no input may panic the parser, fail
//! its echo's round trip or the check.

#[path = "../../../fuzz/common/criteria.rs"]
mod criteria_target;
#[path = "../../../fuzz/common/replay.rs"]
mod replay;

#[test]
fn the_criteria_corpus_replays_without_a_panic() {
    let run = criteria_target::parse_and_check;
    let inputs = replay::replay_seeds("criteria", run);
    assert!(inputs >= 8, "{inputs} inputs");
    // And the corpus of its hour (two runs of 30 minutes), minimised
    // (fuzz/seeds/criteria.tar.xz).
    let inputs = replay::replay_archive("criteria", run);
    assert!(inputs >= 550, "{inputs} inputs");
}
