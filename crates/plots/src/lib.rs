//! PNG plots of Combustion's optics, drawn with plotters into an RGB buffer and encoded
//! with the `png` crate:
//!
//! * [`plot_reflectance`]: Rs, Rp and R = (1 − w) Rs + w Rp against the angle of
//!   incidence (0–90°) for a material ([`PlotMaterial`]: a built-in metal, a dielectric,
//!   a conductor η + ik per RGB channel, or a tabulated spectrum) seen from an outside
//!   medium of index ηi, per RGB channel; a dielectric's Brewster and critical angles are
//!   marked (rendering notes Figures 10 and 11 for gold and copper).
//! * [`plot_dielectric_family`]: unpolarised R against angle for several dielectrics
//!   (rendering notes Figure 12).
//! * [`plot_spectrum`]: a spectrum's n(λ) and k(λ), samples and interpolation, with the RGB
//!   bands and their band means (rendering notes Figures 8 and 9).
//! * [`plot_speed_vs_error`]: measured variant sets, time against relative error, with
//!   their Pareto front ([`pareto_front`]).
//! * [`plot_scaling`]: measured times against pixels or light count, a line per series.
//!
//! The Fresnel equations are `combustion-optics`' ([`fresnel_conductor`] and
//! [`fresnel_dielectric`], f64); the band means are `combustion-spectra`'s
//! ([`rgb_optical_constants`]). Text is set in DejaVu Sans, embedded at compile time from
//! `assets/fonts/` (see the README there); no system font is read. Bad parameters are
//! reported as [`PlotError`]; nothing here panics on any input.
//!
//! [`fresnel_conductor`]: combustion_optics::fresnel::fresnel_conductor
//! [`fresnel_dielectric`]: combustion_optics::fresnel::fresnel_dielectric
//! [`rgb_optical_constants`]: combustion_spectra::rgb_optical_constants

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod canvas;
mod error;
mod font;
mod reflectance;
mod scaling;
mod spectral;
mod speed_error;

pub use combustion_spectra::{BuiltinMetal, Spectrum};
pub use error::PlotError;
pub use reflectance::{
    plot_dielectric_family, plot_reflectance, PlotMaterial, ReflectancePlot, MAX_FAMILY,
};
pub use scaling::{plot_scaling, Series, XAxis};
pub use spectral::plot_spectrum;
pub use speed_error::{
    pareto_front, plot_speed_vs_error, SpeedErrorPoint, PARETO_ERROR_TOLERANCE, RELATIVE_ERROR_AXIS,
};

use combustion_optics::{ETA_MAX, ETA_MIN};

pub(crate) use canvas::check_size;

/// Largest accepted width or height, in pixels.
pub const MAX_SIZE: u32 = 8192;

/// The η values of the rendering notes' Figure 12 ("Dielectric Fresnel effect for various
/// ηt"), for [`plot_dielectric_family`].
pub const FIGURE_12_ETAS: [f64; 6] = [1.1, 1.33, 1.5, 1.8, 2.4, 3.0];

/// An encoded PNG image (8-bit RGB).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Png {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The PNG file's bytes.
    pub bytes: Vec<u8>,
}

impl Png {
    /// Writes the PNG file to `path`.
    pub fn save(&self, path: impl AsRef<std::path::Path>) -> std::io::Result<()> {
        std::fs::write(path, &self.bytes)
    }
}

/// Checks an index of refraction (η of a material or ηi of the outside medium).
pub(crate) fn check_eta(name: String, value: f64) -> Result<(), PlotError> {
    if !(value.is_finite() && value > 0.0) {
        return Err(PlotError::InvalidParameter {
            name,
            value,
            expected: "an index of refraction must be finite and > 0",
        });
    }
    if !(ETA_MIN..=ETA_MAX).contains(&value) {
        return Err(PlotError::InvalidParameter {
            name,
            value,
            expected: "an index of refraction must lie in [1e-4, 1e4], the range the optics \
                       reference evaluates",
        });
    }
    Ok(())
}

/// Checks an extinction coefficient.
pub(crate) fn check_k(name: String, value: f64) -> Result<(), PlotError> {
    if !(value.is_finite() && (0.0..=ETA_MAX).contains(&value)) {
        return Err(PlotError::InvalidParameter {
            name,
            value,
            expected: "an extinction coefficient must be finite and in [0, 1e4]",
        });
    }
    Ok(())
}

/// Checks a polarisation weight.
pub(crate) fn check_weight(value: f64) -> Result<(), PlotError> {
    if !(0.0..=1.0).contains(&value) {
        return Err(PlotError::InvalidParameter {
            name: "polarisation weight".to_owned(),
            value,
            expected: "the polarisation weight must be in [0, 1] (0 = s, 1 = p, 0.5 = unpolarised)",
        });
    }
    Ok(())
}

/// A value with 4 significant digits, trailing zeros dropped (`1`, `1.33`, `0.1132`,
/// `4.096`); scientific notation for very small or large magnitudes.
pub(crate) fn fmt_value(value: f64) -> String {
    if value == 0.0 || !value.is_finite() {
        return format!("{value}");
    }
    let magnitude = value.abs();
    if !(1e-3..1e5).contains(&magnitude) {
        return format!("{value:.2e}");
    }
    let decimals = (3 - magnitude.log10().floor() as i32).clamp(0, 6) as usize;
    let text = format!("{value:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

#[cfg(test)]
mod tests;
