//! The batch_manifest fuzz target's corpora — fuzz/seeds/batch_manifest/ (hand-made
//! seeds, and its finds) and batch_manifest.tar.xz (its runs' corpus, minimised) — replayed
//! through the code the target runs (fuzz/common/batch_manifest.rs): no manifest or
//! shard's results may panic the parser, the split or the merge, or break their rules.

#[path = "../fuzz/common/batch_manifest.rs"]
mod batch_manifest_target;
#[path = "../fuzz/common/replay.rs"]
mod replay;

#[test]
fn the_batch_manifest_corpus_replays_without_a_panic() {
    let run = batch_manifest_target::parse_and_merge;
    let inputs = replay::replay_seeds("batch_manifest", run);
    assert!(inputs >= 8, "{inputs} inputs");
    // And the corpus of its runs, minimised (fuzz/seeds/batch_manifest.tar.xz).
    let inputs = replay::replay_archive("batch_manifest", run);
    assert!(inputs > 2000, "{inputs} inputs");
}
