//! The cache_entry fuzz target's corpus — fuzz/seeds/cache_entry/: hand-made seeds
//! (`generate.py` writes them, named for their cases) and a 60-minute run's corpus,
//! minimised (named by their hashes) —
//! replayed through the code the target runs (fuzz/common/cache_entry.rs): no input may
//! panic the reader, load what is not an intact entry's body within its size limit, or
//! pass a body check that its kind's rule refuses.

#[path = "../../../fuzz/common/cache_entry.rs"]
mod cache_entry_target;
#[path = "../../../fuzz/common/replay.rs"]
mod replay;

#[test]
fn the_cache_entry_corpus_replays_without_a_panic() {
    let seeds: Vec<_> = replay::seed_folder("cache_entry")
        .into_iter()
        .filter(|file| file.extension().is_none())
        .collect();
    let (inputs, panicked) = replay::replay(&seeds, cache_entry_target::load_and_check);
    assert!(panicked.is_empty(), "{panicked:?} of {inputs} panicked");
    assert!(inputs >= 40, "{inputs} inputs");
}

/// The hand-made seeds reach what they are named for: the intact entry loads, the
/// damaged and foreign ones do not, the forged radiance body fails its check.
#[test]
fn the_cache_entry_seeds_reach_their_cases() {
    use combustion_disk_cache::bodies::{is_radiance, spirv_words};
    let seed = |name: &str| std::fs::read(replay::seeds().join("cache_entry").join(name)).unwrap();
    let intact = cache_entry_target::loaded(&seed("intact-spirv")).expect("an intact entry loads");
    assert!(spirv_words(&intact).is_some());
    for name in [
        "damaged-spirv",
        "foreign-magic",
        "short-header",
        "spirv-body-past-a-limit",
    ] {
        assert_eq!(cache_entry_target::loaded(&seed(name)), None, "{name}");
    }
    let radiance = &seed("radiance-body")[1..];
    assert!(is_radiance(
        radiance,
        radiance.len() as u64,
        cache_entry_target::MAX_RADIANCE
    ));
    let forged = &seed("forged-radiance")[1..];
    assert!(!is_radiance(
        forged,
        forged.len() as u64,
        cache_entry_target::MAX_RADIANCE
    ));
}
