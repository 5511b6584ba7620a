//! The crate's one error type.

use combustion_spectra::SpectrumError;
use plotters::drawing::DrawingAreaErrorKind;

/// Everything that can go wrong when making a plot. Bad parameters are reported here;
/// no input makes a plot function panic.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// Width or height is 0 or above [`MAX_SIZE`](crate::MAX_SIZE).
    #[error(
        "invalid plot size {width}×{height}: width and height must be 1–{max} pixels",
        max = crate::MAX_SIZE
    )]
    InvalidSize {
        /// Requested width in pixels.
        width: u32,
        /// Requested height in pixels.
        height: u32,
    },
    /// A numeric parameter is outside its domain (η, k, ηi, polarisation weight).
    #[error("invalid {name} {}: {expected}", combustion_optics::readable(*.value))]
    InvalidParameter {
        /// Which parameter, in words, e.g. `"outside IOR"` or `"η of the green band"`.
        name: String,
        /// The value passed.
        value: f64,
        /// What is accepted.
        expected: &'static str,
    },
    /// [`plot_speed_vs_error`](crate::plot_speed_vs_error) or
    /// [`plot_scaling`](crate::plot_scaling) was given no point.
    #[error("no point given: the plot needs at least one")]
    NoPoints,
    /// A point of [`plot_speed_vs_error`](crate::plot_speed_vs_error) has a time or an
    /// error that cannot be drawn.
    #[error("variant set `{label}`: {reason}")]
    InvalidPoint {
        /// The point's label.
        label: String,
        /// What is wrong with it.
        reason: String,
    },
    /// [`plot_dielectric_family`](crate::plot_dielectric_family) was given no η.
    #[error("no η given: the dielectric family plot needs at least one ηt")]
    EmptyEtaList,
    /// [`plot_dielectric_family`](crate::plot_dielectric_family) was given more η than it
    /// has distinct colours for.
    #[error("{count} η values given: the dielectric family plot draws at most {max}")]
    TooManyCurves {
        /// Number of η given.
        count: usize,
        /// The limit.
        max: usize,
    },
    /// Reducing a spectrum to RGB band means failed.
    #[error("spectrum `{name}`: {source}")]
    Spectrum {
        /// The material's name.
        name: String,
        /// What went wrong.
        #[source]
        source: SpectrumError,
    },
    /// The embedded font could not be parsed (cannot happen with the shipped file).
    #[error("the embedded DejaVu Sans font could not be loaded")]
    Font,
    /// Plotters reported an error while drawing.
    #[error("drawing the plot failed: {0}")]
    Draw(String),
    /// The PNG encoder reported an error.
    #[error("encoding the PNG failed: {0}")]
    Encode(#[from] png::EncodingError),
}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(error: DrawingAreaErrorKind<E>) -> Self {
        PlotError::Draw(error.to_string())
    }
}
