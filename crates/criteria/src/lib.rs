//! `diff --criteria` and the batch manifests' criteria: what a comparison of two images
//! must meet — terms joined by `and` / `or` (`and` binds tighter), each a share of pixels
//! over a channel difference or a bound on FLIP — parsed from text and checked against
//! what a comparison measured ([`Measured`]). A crate of its own, without the renderer,
//! so that its parser can be fuzzed (fuzz/fuzz_targets/criteria.rs).

use combustion_optics::{finite_number, readable, shortened};

/// What a comparison of two images measured, as the criteria read it.
pub trait Measured {
    /// Whether the images are radiance (OpenEXR) rather than display values (PNG).
    fn radiance(&self) -> bool;
    /// The share of pixels (0 to 1) whose largest channel difference is above
    /// `tolerance` (8-bit steps, or relative for radiance).
    fn share_above(&self, tolerance: f64) -> f64;
    /// The largest channel difference of any pixel.
    fn max_channel_diff(&self) -> f64;
    /// The mean FLIP over the pixels.
    fn mean_flip(&self) -> f64;
    /// The largest per-pixel FLIP.
    fn max_flip(&self) -> f64;
}

/// One criterion.
#[derive(Clone, Debug, PartialEq)]
pub enum Criterion {
    /// No pixel's largest channel difference above `tolerance` (8-bit steps, or relative
    /// for radiance) on more than `share` (0 to 1) of the pixels.
    ChannelDiff {
        /// Whether the tolerance is relative (radiance) rather than in 8-bit steps.
        relative: bool,
        /// The tolerance.
        tolerance: f64,
        /// The share of pixels allowed above it.
        share: f64,
    },
    /// Mean FLIP at most this.
    MeanFlip(f64),
    /// Largest per-pixel FLIP at most this.
    MaxFlip(f64),
}

impl std::fmt::Display for Criterion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            // Numbers as messages write them (`1e-300`, not 300 digits).
            Criterion::ChannelDiff {
                relative: false,
                tolerance,
                share,
            } => write!(
                f,
                "max-channel-diff {}/255 on at most {}% of pixels",
                readable(*tolerance),
                readable(share * 100.0)
            ),
            Criterion::ChannelDiff {
                relative: true,
                tolerance,
                share,
            } => write!(
                f,
                "max-relative-diff {} on at most {}% of pixels",
                readable(*tolerance),
                readable(share * 100.0)
            ),
            Criterion::MeanFlip(x) => write!(f, "mean-flip <= {}", readable(*x)),
            Criterion::MaxFlip(x) => write!(f, "max-flip <= {}", readable(*x)),
        }
    }
}

impl Criterion {
    /// `None` when `comparison` meets it, else what was measured against what is allowed.
    pub fn failure(&self, comparison: &impl Measured) -> Result<(), String> {
        match *self {
            Criterion::ChannelDiff {
                relative,
                tolerance,
                share,
            } => {
                if relative != comparison.radiance() {
                    return Err(format!(
                        "{self}: applies to {} images, these are {}",
                        if relative { "OpenEXR" } else { "PNG" },
                        if comparison.radiance() {
                            "OpenEXR"
                        } else {
                            "PNG"
                        }
                    ));
                }
                let above = comparison.share_above(tolerance);
                if above > share {
                    return Err(format!(
                        "{self}: {:.4}% of pixels are above it (largest difference {})",
                        above * 100.0,
                        if relative {
                            format!("{:.3e}", comparison.max_channel_diff())
                        } else {
                            format!("{}/255", comparison.max_channel_diff())
                        }
                    ));
                }
                Ok(())
            }
            Criterion::MeanFlip(limit) => {
                let mean = comparison.mean_flip();
                (mean <= limit)
                    .then_some(())
                    .ok_or_else(|| format!("{self}: mean FLIP is {mean:.4e}"))
            }
            Criterion::MaxFlip(limit) => {
                let max = comparison.max_flip();
                (max <= limit)
                    .then_some(())
                    .ok_or_else(|| format!("{self}: largest FLIP is {max:.4e}"))
            }
        }
    }
}

/// Criteria: alternatives (`or`) of conjunctions (`and`).
#[derive(Clone, Debug, PartialEq)]
pub struct Criteria(pub Vec<Vec<Criterion>>);

impl Criteria {
    /// Parses `text`: terms joined by `and` / `or` (`and` binds tighter), each one of
    /// `max-channel-diff N/255 on at most P% of pixels`, `max-relative-diff X on at most
    /// P% of pixels`, `mean-flip <= X`, `max-flip <= X` (`≤` too). The error names the
    /// term that cannot be read.
    pub fn parse(text: &str) -> Result<Criteria, String> {
        // `mean-flip<=0.01` reads as `mean-flip <= 0.01`.
        let text = text.replace("<=", " <= ").replace('≤', " ≤ ");
        let alternatives = split_words(&text, "or")
            .into_iter()
            .map(|alternative| {
                split_words(&alternative, "and")
                    .into_iter()
                    .map(|term| parse_term(&term))
                    .collect::<Result<Vec<_>, _>>()
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Criteria(alternatives))
    }

    /// Parses a criteria file: [`Criteria::parse`] of its lines joined by spaces, each
    /// line's text from a `#` on left out.
    pub fn parse_file_text(text: &str) -> Result<Criteria, String> {
        let joined = text
            .lines()
            .map(|line| line.split('#').next().unwrap_or(""))
            .collect::<Vec<_>>()
            .join(" ");
        if joined.trim().is_empty() {
            return Err("no criterion in it".into());
        }
        Criteria::parse(&joined)
    }

    /// The first term that does not apply to images of this kind (`radiance`: OpenEXR),
    /// in any alternative: a channel difference in 8-bit steps for OpenEXR, or a
    /// relative one for PNG.
    pub fn wrong_kind(&self, radiance: bool) -> Option<&Criterion> {
        self.0
            .iter()
            .flatten()
            .find(|c| matches!(c, Criterion::ChannelDiff { relative, .. } if *relative != radiance))
    }

    /// `Ok` when some alternative's every term holds; else, for the closest alternative
    /// (the first), the first term that fails and by how much.
    pub fn check(&self, comparison: &impl Measured) -> Result<(), String> {
        let mut first_failure = None;
        for alternative in &self.0 {
            match alternative.iter().try_for_each(|c| c.failure(comparison)) {
                Ok(()) => return Ok(()),
                Err(why) => {
                    first_failure.get_or_insert(why);
                }
            }
        }
        Err(first_failure.unwrap_or_else(|| "no criterion given".into()))
    }
}

/// `text` split at the whole word `word` (surrounded by white space), trimmed.
fn split_words(text: &str, word: &str) -> Vec<String> {
    let mut parts = vec![Vec::new()];
    for token in text.split_whitespace() {
        if token == word {
            parts.push(Vec::new());
        } else {
            parts.last_mut().expect("one part at least").push(token);
        }
    }
    parts.into_iter().map(|p| p.join(" ")).collect()
}

fn parse_term(term: &str) -> Result<Criterion, String> {
    let bad = |why: &str| format!("criterion `{}`: {why}", shortened(term));
    let number = |text: &str| -> Result<f64, String> {
        finite_number(text)
            .ok()
            .filter(|x| *x >= 0.0)
            .ok_or_else(|| {
                bad(&format!(
                    "`{}` is not a number of at least 0",
                    shortened(text)
                ))
            })
    };
    let words: Vec<&str> = term.split_whitespace().collect();
    match words.as_slice() {
        [kind @ ("max-channel-diff" | "max-relative-diff"), tolerance, "on", "at", "most", share, "of", "pixels"] =>
        {
            let relative = *kind == "max-relative-diff";
            let tolerance = if relative {
                number(tolerance)?
            } else {
                let steps = tolerance.strip_suffix("/255").ok_or_else(|| {
                    bad("a channel difference is given in 8-bit steps, as N/255")
                })?;
                number(steps)?
            };
            let share = share
                .strip_suffix('%')
                .ok_or_else(|| bad("the share of pixels is given in percent, as P%"))?;
            let share = number(share)?;
            if share > 100.0 {
                return Err(bad("a share of pixels is at most 100%"));
            }
            Ok(Criterion::ChannelDiff {
                relative,
                tolerance,
                share: share / 100.0,
            })
        }
        [kind @ ("mean-flip" | "max-flip"), "<=" | "≤", value] => {
            let value = number(value)?;
            Ok(if *kind == "mean-flip" {
                Criterion::MeanFlip(value)
            } else {
                Criterion::MaxFlip(value)
            })
        }
        _ => Err(bad(
            "not one of `max-channel-diff N/255 on at most P% of pixels`, `max-relative-diff X on at most P% of pixels`, `mean-flip <= X`, `max-flip <= X`",
        )),
    }
}
