//! Tabulated spectral optical constants and their CSV reader.

use crate::{RgbBand, SpectrumError};

/// The header line a CSV table may start with (after `#` comment lines).
pub const CSV_HEADER: &str = "wavelength_nm,n,k";

/// A tabulated complex refractive index n + ik as a function of vacuum wavelength.
///
/// Samples are `(wavelength_nm, n, k)`, strictly increasing in wavelength, all finite,
/// wavelength > 0, n ≥ 0, k ≥ 0. Between samples the constants are interpolated
/// linearly in wavelength; outside the table they are undefined.
///
/// A `Spectrum` is always usable for RGB reduction: construction checks that
///
/// * the table spans every [`RgbBand`] (at least 450–740 nm), and
/// * every band is resolved by at least 2 samples, counting the samples inside the band
///   (edges included) and the nearest sample beyond each edge **if** it lies within half
///   the band's width of that edge (Blue 22.5 nm, Green 37.5 nm, Red 60 nm). A band
///   bridged only by far-away samples (say 400 nm and 800 nm around the Green band) is
///   rejected as too sparse: its "spectrum" would be a straight line invented by the
///   interpolation.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    samples: Vec<(f64, f64, f64)>,
}

const COLUMNS: [&str; 3] = ["wavelength_nm", "n", "k"];

fn parse_field(line: usize, column: &'static str, text: &str) -> Result<f64, SpectrumError> {
    let text = text.trim();
    let value: f64 = text.parse().map_err(|_| SpectrumError::UnparsableNumber {
        line,
        column,
        text: text.to_owned(),
    })?;
    if !value.is_finite() {
        return Err(SpectrumError::NonFinite {
            line,
            column,
            text: text.to_owned(),
        });
    }
    Ok(value)
}

fn is_header(fields: &[String]) -> bool {
    fields.len() == 3
        && fields
            .iter()
            .zip(COLUMNS)
            .all(|(f, c)| f.trim().eq_ignore_ascii_case(c))
}

/// `text` with its comment lines (first non-blank character `#`) emptied, their line
/// breaks kept, so that the CSV reader skips them and every line keeps its number.
fn without_comments(text: &str) -> String {
    text.split_inclusive('\n')
        .map(|line| {
            if line.trim_start().starts_with('#') {
                if line.ends_with("\r\n") {
                    "\r\n"
                } else if line.ends_with('\n') {
                    "\n"
                } else {
                    ""
                }
            } else {
                line
            }
        })
        .collect()
}

impl Spectrum {
    /// Reads a table in the project's CSV format.
    ///
    /// * Lines whose first non-blank character is `#` are comments; blank lines are
    ///   skipped. Lines may end in `\r\n`. Records are read by the `csv` crate (a field
    ///   may be quoted).
    /// * The first non-comment line may be the header `wavelength_nm,n,k` (ASCII case and
    ///   spaces around fields are ignored); it is optional. A leading byte-order mark is
    ///   ignored.
    /// * Every other line is a data row `wavelength_nm,n,k`: wavelength in nm (vacuum),
    ///   then n and k. Numbers use Rust's `f64` syntax (`1.5`, `3.1474E-01`, ...).
    ///
    /// Errors name the 1-based line and the problem: wrong field count, unparsable or
    /// non-finite number, wavelength ≤ 0, negative n or k, n or k above
    /// [`crate::MAX_OPTICAL_CONSTANT`], duplicate or decreasing
    /// wavelength, no data, a band not covered (the table must span 450–740 nm), or a band
    /// too sparsely sampled (see [`Spectrum`]). The first problem in line order is
    /// reported; table-level checks (coverage, then sparsity, Blue → Red) come last.
    /// Never panics.
    pub fn from_csv(text: &str) -> Result<Spectrum, SpectrumError> {
        let mut samples: Vec<(f64, f64, f64)> = Vec::new();
        let mut lines_of_samples: Vec<usize> = Vec::new();
        // A leading byte-order mark (spreadsheet exports) is not part of the first field.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let line_count = text.lines().count();
        // Records through the `csv` crate (quoted fields, `\r\n`), each with its line.
        let uncommented = without_comments(text);
        for (index, (line, fields)) in combustion_report_csv::record_iter(&uncommented).enumerate()
        {
            if index == 0 && is_header(&fields) {
                continue;
            }
            if fields.len() != 3 {
                return Err(SpectrumError::WrongFieldCount {
                    line,
                    found: fields.len(),
                });
            }
            let wavelength_nm = parse_field(line, COLUMNS[0], &fields[0])?;
            let n = parse_field(line, COLUMNS[1], &fields[1])?;
            let k = parse_field(line, COLUMNS[2], &fields[2])?;
            if wavelength_nm <= 0.0 {
                return Err(SpectrumError::NonPositiveWavelength {
                    line,
                    wavelength_nm,
                });
            }
            for (column, value) in [(COLUMNS[1], n), (COLUMNS[2], k)] {
                if value < 0.0 {
                    return Err(SpectrumError::NegativeConstant {
                        line,
                        column,
                        value,
                    });
                }
                if value > crate::MAX_OPTICAL_CONSTANT {
                    return Err(SpectrumError::ConstantTooLarge {
                        line,
                        column,
                        value,
                        max: crate::MAX_OPTICAL_CONSTANT,
                    });
                }
            }
            if let (Some(&(previous_nm, _, _)), Some(&previous_line)) =
                (samples.last(), lines_of_samples.last())
            {
                if wavelength_nm == previous_nm {
                    return Err(SpectrumError::DuplicateWavelength {
                        line,
                        wavelength_nm,
                        previous_line,
                    });
                }
                if wavelength_nm < previous_nm {
                    return Err(SpectrumError::UnsortedWavelength {
                        line,
                        wavelength_nm,
                        previous_line,
                        previous_nm,
                    });
                }
            }
            samples.push((wavelength_nm, n, k));
            lines_of_samples.push(line);
        }
        if samples.is_empty() {
            return Err(SpectrumError::NoData { line: line_count });
        }
        check_coverage(&samples, &lines_of_samples)?;
        check_density(&samples, &lines_of_samples)?;
        Ok(Spectrum { samples })
    }

    /// Optical constants `(n, k)` at `wavelength_nm`, interpolated linearly between the
    /// two neighbouring samples. `None` outside the table (or for a non-finite argument).
    pub fn n_k_at(&self, wavelength_nm: f64) -> Option<(f64, f64)> {
        let first = self.samples.first()?;
        let last = self.samples.last()?;
        if !(wavelength_nm >= first.0 && wavelength_nm <= last.0) {
            return None;
        }
        // Index of the first sample with wavelength > λ; λ lies in [s[i-1], s[i]].
        let i = self.samples.partition_point(|s| s.0 <= wavelength_nm);
        if i == 0 {
            return None;
        }
        if i == self.samples.len() {
            return Some((last.1, last.2));
        }
        Some(interpolate(
            self.samples[i - 1],
            self.samples[i],
            wavelength_nm,
        ))
    }

    /// The samples `(wavelength_nm, n, k)`, strictly increasing in wavelength.
    pub fn samples(&self) -> &[(f64, f64, f64)] {
        &self.samples
    }

    /// Wavelength range `(first, last)` of the table, in nm.
    pub fn range_nm(&self) -> (f64, f64) {
        // A Spectrum always has at least 2 samples (checked in from_csv).
        let first = self.samples.first().map_or(f64::NAN, |s| s.0);
        let last = self.samples.last().map_or(f64::NAN, |s| s.0);
        (first, last)
    }
}

/// Linear interpolation of `(n, k)` between samples `a` and `b` at `wavelength_nm`.
pub(crate) fn interpolate(
    a: (f64, f64, f64),
    b: (f64, f64, f64),
    wavelength_nm: f64,
) -> (f64, f64) {
    let s = (wavelength_nm - a.0) / (b.0 - a.0);
    (a.1 + s * (b.1 - a.1), a.2 + s * (b.2 - a.2))
}

fn check_coverage(samples: &[(f64, f64, f64)], lines: &[usize]) -> Result<(), SpectrumError> {
    let (first, last) = (samples[0].0, samples[samples.len() - 1].0);
    for band in RgbBand::ALL_BY_WAVELENGTH {
        let (band_min_nm, band_max_nm) = band.range_nm();
        if first > band_min_nm {
            return Err(SpectrumError::BandNotCovered {
                line: lines[0],
                band,
                end: "first",
                table_nm: first,
                band_min_nm,
                band_max_nm,
            });
        }
        if last < band_max_nm {
            return Err(SpectrumError::BandNotCovered {
                line: lines[lines.len() - 1],
                band,
                end: "last",
                table_nm: last,
                band_min_nm,
                band_max_nm,
            });
        }
    }
    Ok(())
}

fn check_density(samples: &[(f64, f64, f64)], lines: &[usize]) -> Result<(), SpectrumError> {
    for band in RgbBand::ALL_BY_WAVELENGTH {
        let (lo, hi) = band.range_nm();
        let tolerance_nm = 0.5 * (hi - lo);
        let inside = samples.iter().filter(|s| s.0 >= lo && s.0 <= hi).count();
        // Nearest sample strictly below / above the band (coverage guarantees that a
        // sample ≤ lo and one ≥ hi exist; these may be absent when they sit on the edge).
        let below = samples.iter().rposition(|s| s.0 < lo);
        let above = samples.iter().position(|s| s.0 > hi);
        let near_below = below.is_some_and(|i| lo - samples[i].0 <= tolerance_nm);
        let near_above = above.is_some_and(|i| samples[i].0 - hi <= tolerance_nm);
        let count = inside + usize::from(near_below) + usize::from(near_above);
        if count < 2 {
            // Report the last sample at or below the band's lower edge.
            let at_or_below = samples.iter().rposition(|s| s.0 <= lo).unwrap_or(0);
            return Err(SpectrumError::TooSparse {
                line: lines[at_or_below],
                line_nm: samples[at_or_below].0,
                band,
                count,
                band_min_nm: lo,
                band_max_nm: hi,
                tolerance_nm,
            });
        }
    }
    Ok(())
}
