//! Measured optical constants of Combustion's built-in metals and dielectrics, and their
//! reduction to the renderer's three RGB bands.
//!
//! * [`Spectrum`]: a tabulated n(λ) + ik(λ), read from the project's CSV format
//!   ([`Spectrum::from_csv`]); the built-in tables ([`BuiltinMetal`],
//!   [`BuiltinDielectric`]) are embedded from `assets/spectra/` at compile time, nothing is
//!   read at run time.
//! * [`RgbBand`]: Red 620–740 nm, Green 495–570 nm, Blue 450–495 nm (rendering notes §4).
//! * [`band_weighted_mean`]: the Gaussian-weighted band **mean**
//!   V = ∫₀¹ f(t) p(t) dt / ∫₀¹ p(t) dt with p(t) = exp(−(t − ½)²) and
//!   t = (λ − w_min)/(w_max − w_min).
//! * Method (a), [`rgb_optical_constants`]: band means of η and k, to be fed to the
//!   Fresnel equations per channel (what the renderer does at run time).
//! * Method (b), [`rgb_band_averaged_reflectance`]: band mean of the spectral Fresnel
//!   reflectance.
//! * [`compare_averaging_methods`] / [`compare_builtin_metals`]: (a) − (b) per channel,
//!   angle and outside medium (seed-notes 7).
//! * Colorimetry ([`reflectance_colour`], [`colorimetric_reflectance`]): the colour a
//!   viewer sees (CIE 1931 2° observer, D65, linear sRGB), and RGB constants fitted to it
//!   ([`colorimetric_optical_constants`]); [`MetalColour`] chooses between the band
//!   method and these.
//!
//! The Fresnel equations are not implemented here: they come from `combustion-optics`.

#![warn(missing_docs)]

mod band;
mod builtin;
mod colour;
mod error;
mod fresnel;
mod rgb;
mod spectrum;

pub use band::{band_weight, band_weighted_mean, RgbBand};
pub use builtin::{BuiltinDielectric, BuiltinMetal};
pub use colour::{
    cie_wavelength, colorimetric_optical_constants, colorimetric_reflectance, d65_white_xyz,
    delta_e_76, fit_angles_deg, lab_of_linear_srgb, linear_srgb_of_xyz, metal_colour_table,
    reflectance_colour, thin_film_colour, xyz_of, xyz_to_linear_srgb, ColorimetricFit, MetalColour,
    CIE_1931_2DEG, CIE_FIRST_NM, CIE_LAST_NM, CIE_STEP_NM, D65, FIT_BOUNDS, FIT_OUTSIDE_ETAS,
    REC709_PRIMARIES,
};
pub use error::SpectrumError;
pub use rgb::{
    compare_averaging_methods, compare_builtin_metals, rgb_band_averaged_reflectance,
    rgb_optical_constants, AveragingComparison, RgbOpticalConstants, COMPARISON_ANGLES_DEG,
    COMPARISON_OUTSIDE_ETAS,
};
pub use spectrum::{Spectrum, CSV_HEADER};

/// The largest n or k a spectral table may give. No material comes near it (metals' k
/// stays below 100 across 450–740 nm), and the renderer's f32 Fresnel evaluation, which
/// squares the constants twice, stays finite with room to spare; above it a table is
/// refused wherever it is read (`render`'s glTF extension and `plot` alike), rather than
/// drawn by one and turned infinite by the other.
pub const MAX_OPTICAL_CONSTANT: f64 = 1e6;
