//! What the `criteria` fuzz target does with one input, shared with the test that
//! replays its corpus (crates/criteria/tests/fuzz_corpus.rs).
//!
//! The input is a flag byte and four little-endian f64 (what a comparison measured: any
//! bits), then the criteria's text. Text that `Criteria::parse` or `parse_file_text`
//! accepts has at least one term, and each term's own words (as a verdict echoes them)
//! are written for people — no run of more than 12 digits — and parse back to one term of
//! the same kind; checking the criteria against the measurement never panics.

use combustion_criteria::{Criteria, Criterion, Measured};

/// A comparison's measurements, as the input gives them.
struct Measurement {
    radiance: bool,
    values: [f64; 4],
}

impl Measured for Measurement {
    fn radiance(&self) -> bool {
        self.radiance
    }
    fn share_above(&self, tolerance: f64) -> f64 {
        if self.values[0] > tolerance {
            self.values[1]
        } else {
            0.0
        }
    }
    fn max_channel_diff(&self) -> f64 {
        self.values[0]
    }
    fn mean_flip(&self) -> f64 {
        self.values[2]
    }
    fn max_flip(&self) -> f64 {
        self.values[3]
    }
}

/// `criteria`.
pub fn parse_and_check(data: &[u8]) {
    let Some((head, text)) = data.split_first_chunk::<33>() else {
        return;
    };
    let value = |i: usize| {
        let mut bytes = [0u8; 8];
        bytes.copy_from_slice(&head[1 + 8 * i..9 + 8 * i]);
        f64::from_le_bytes(bytes)
    };
    let measurement = Measurement {
        radiance: head[0] & 1 == 1,
        values: [value(0), value(1), value(2), value(3)],
    };
    let Ok(text) = std::str::from_utf8(text) else {
        return;
    };
    for parsed in [Criteria::parse(text), Criteria::parse_file_text(text)] {
        let Ok(criteria) = parsed else { continue };
        assert!(criteria.0.iter().all(|a| !a.is_empty()), "{criteria:?}");
        for criterion in criteria.0.iter().flatten() {
            let echoed = criterion.to_string();
            let long = echoed
                .split(|c: char| !(c.is_ascii_digit() || c == '.'))
                .any(|run| run.chars().filter(char::is_ascii_digit).count() > 12);
            assert!(!long, "{echoed}");
            let again = Criteria::parse(&echoed)
                .unwrap_or_else(|e| panic!("`{echoed}`, a criterion's own words: {e}"));
            let [alternative] = again.0.as_slice() else {
                panic!("`{echoed}` parsed as {again:?}")
            };
            let [one] = alternative.as_slice() else {
                panic!("`{echoed}` parsed as {again:?}")
            };
            assert_eq!(kind(one), kind(criterion), "{echoed}");
        }
        let _ = criteria.check(&measurement);
        let _ = criteria.wrong_kind(measurement.radiance);
    }
}

/// A criterion's kind, without its numbers.
fn kind(c: &Criterion) -> &'static str {
    match c {
        Criterion::ChannelDiff {
            relative: false, ..
        } => "max-channel-diff",
        Criterion::ChannelDiff { relative: true, .. } => "max-relative-diff",
        Criterion::MeanFlip(_) => "mean-flip",
        Criterion::MaxFlip(_) => "max-flip",
    }
}
