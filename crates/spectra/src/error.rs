//! The one error type of the crate.

use combustion_optics::{readable, shortened};

use crate::RgbBand;

/// Everything that can go wrong when reading a spectral table or reducing it to RGB.
///
/// The variants produced by [`Spectrum::from_csv`](crate::Spectrum::from_csv) carry the
/// 1-based line number of the CSV text they refer to, and their messages start with it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SpectrumError {
    /// A data row does not have exactly three comma-separated fields.
    #[error("line {line}: expected 3 comma-separated fields `wavelength_nm,n,k`, found {found}")]
    WrongFieldCount {
        /// 1-based line number.
        line: usize,
        /// Number of fields found on the line.
        found: usize,
    },
    /// A field is not a number.
    #[error("line {line}: cannot parse the {column} field `{}` as a number", shortened(.text))]
    UnparsableNumber {
        /// 1-based line number.
        line: usize,
        /// `"wavelength_nm"`, `"n"` or `"k"`.
        column: &'static str,
        /// The offending field, trimmed.
        text: String,
    },
    /// A field parses as a number but is infinite or NaN.
    #[error("line {line}: the {column} field `{}` is not a finite number", shortened(.text))]
    NonFinite {
        /// 1-based line number.
        line: usize,
        /// `"wavelength_nm"`, `"n"` or `"k"`.
        column: &'static str,
        /// The offending field, trimmed.
        text: String,
    },
    /// A wavelength is zero or negative.
    #[error("line {line}: wavelength must be positive, found {} nm", readable(*.wavelength_nm))]
    NonPositiveWavelength {
        /// 1-based line number.
        line: usize,
        /// The wavelength read.
        wavelength_nm: f64,
    },
    /// n or k is negative.
    #[error("line {line}: {column} must not be negative, found {}", readable(*.value))]
    NegativeConstant {
        /// 1-based line number.
        line: usize,
        /// `"n"` or `"k"`.
        column: &'static str,
        /// The value read.
        value: f64,
    },
    /// n or k is above [`crate::MAX_OPTICAL_CONSTANT`].
    #[error(
        "line {line}: {column} {} is above {}, beyond any material's optical constants",
        readable(*.value),
        readable(*.max)
    )]
    ConstantTooLarge {
        /// 1-based line number.
        line: usize,
        /// `"n"` or `"k"`.
        column: &'static str,
        /// The value read.
        value: f64,
        /// The bound, [`crate::MAX_OPTICAL_CONSTANT`].
        max: f64,
    },
    /// A wavelength equals the one on the previous data row.
    #[error(
        "line {line}: duplicate wavelength {} nm (already on line {previous_line})",
        readable(*.wavelength_nm)
    )]
    DuplicateWavelength {
        /// 1-based line number.
        line: usize,
        /// The repeated wavelength.
        wavelength_nm: f64,
        /// Line of the previous data row.
        previous_line: usize,
    },
    /// A wavelength is smaller than the one on the previous data row.
    #[error(
        "line {line}: wavelength {} nm is below {} nm on line {previous_line}; rows must be \
         sorted by increasing wavelength",
        readable(*.wavelength_nm),
        readable(*.previous_nm)
    )]
    UnsortedWavelength {
        /// 1-based line number.
        line: usize,
        /// The wavelength read.
        wavelength_nm: f64,
        /// Line of the previous data row.
        previous_line: usize,
        /// Wavelength of the previous data row.
        previous_nm: f64,
    },
    /// The text has no data rows at all.
    #[error("{}", no_data(*.line))]
    NoData {
        /// Number of lines read (the line at which the input ended).
        line: usize,
    },
    /// The table does not span a whole RGB band (tables must span 450–740 nm).
    #[error(
        "line {line}: the table's {end} sample is at {table_nm} nm, so the {band} band \
         ({band_min_nm}–{band_max_nm} nm) is not covered; a table must span at least \
         450–740 nm"
    )]
    BandNotCovered {
        /// Line of the table's first or last data row.
        line: usize,
        /// The band that is not covered.
        band: RgbBand,
        /// `"first"` or `"last"`.
        end: &'static str,
        /// Wavelength of that first or last row.
        table_nm: f64,
        /// Lower edge of the band.
        band_min_nm: f64,
        /// Upper edge of the band.
        band_max_nm: f64,
    },
    /// A band is covered but resolved by fewer than 2 samples.
    ///
    /// The samples counted are those inside the band plus the nearest sample beyond each
    /// edge if it lies within half the band's width of that edge (see
    /// [`Spectrum`](crate::Spectrum) for the rule).
    #[error(
        "line {line}: the {band} band ({band_min_nm}–{band_max_nm} nm) is resolved by only \
         {count} sample(s) (this row, at {line_nm} nm, is the last one at or below the band's lower edge); at \
         least 2 must lie inside the band or bracket it within {tolerance_nm} nm of its edges"
    )]
    TooSparse {
        /// Line of the last sample below (or at) the band's lower edge.
        line: usize,
        /// Wavelength on that line.
        line_nm: f64,
        /// The band.
        band: RgbBand,
        /// Number of samples counted.
        count: usize,
        /// Lower edge of the band.
        band_min_nm: f64,
        /// Upper edge of the band.
        band_max_nm: f64,
        /// Half the band's width.
        tolerance_nm: f64,
    },
    /// A function integrated over a band returned a non-finite value.
    #[error("the function averaged over the {band} band returned {value} at {wavelength_nm} nm")]
    NonFiniteIntegrand {
        /// The band.
        band: RgbBand,
        /// Where it happened.
        wavelength_nm: f64,
        /// The value returned.
        value: f64,
    },
    /// A colorimetric reduction needs the table to span the colour-matching functions'
    /// 380–780 nm.
    #[error(
        "the table spans {first_nm}–{last_nm} nm; its colour (CIE 1931 observer, D65) needs \
         380–780 nm"
    )]
    VisibleNotCovered {
        /// The table's first wavelength.
        first_nm: f64,
        /// The table's last wavelength.
        last_nm: f64,
    },
    /// An argument of a reflectance function is out of its domain.
    #[error("invalid argument: {name} = {value} ({expected})")]
    InvalidArgument {
        /// Argument name.
        name: &'static str,
        /// Value passed.
        value: f64,
        /// What was expected.
        expected: &'static str,
    },
}

/// [`SpectrumError::NoData`]'s message: an empty file is called empty (not "line 0").
fn no_data(lines: usize) -> String {
    match lines {
        0 => "the file is empty: no `wavelength_nm,n,k` data row".to_owned(),
        n => format!("line {n}: end of input without any `wavelength_nm,n,k` data row"),
    }
}
