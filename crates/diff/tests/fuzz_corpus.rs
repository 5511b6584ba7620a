//! The diff_images fuzz target's corpora — fuzz/seeds/diff_images/ (seeds made from
//! small renders: PNG and OpenEXR pairs, of one size and of two, and a PNG against an
//! OpenEXR file) and diff_images.tar.xz (a run's corpus, minimised) — replayed through
//! the code the target runs (fuzz/common/diff.rs): no input may panic the readers or
//! the comparison, decode to another size than its header's, or differ from itself.

#[path = "../../../fuzz/common/diff.rs"]
mod diff_target;
#[path = "../../../fuzz/common/replay.rs"]
mod replay;

#[test]
fn the_diff_images_corpus_replays_without_a_panic() {
    let run = diff_target::read_and_compare;
    let inputs = replay::replay_seeds("diff_images", run);
    assert!(inputs >= 5, "{inputs} inputs");
    // And the corpus of a 60-minute run, minimised (fuzz/seeds/diff_images.tar.xz).
    let inputs = replay::replay_archive("diff_images", run);
    assert!(inputs > 3000, "{inputs} inputs");
}
