//! Reduction of a spectrum to RGB: method (a) "average η and k, then Fresnel" and
//! method (b) "average the reflectance" (seed-notes 7), and their comparison.

use crate::band::band_mean_of_linear;
use crate::{band_weighted_mean, BuiltinMetal, RgbBand, Spectrum, SpectrumError};

/// Per-channel complex index of refraction η + ik, channels in `[R, G, B]` order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RgbOpticalConstants {
    /// Real part η (n) per channel.
    pub eta: [f64; 3],
    /// Extinction coefficient k per channel.
    pub k: [f64; 3],
}

impl RgbOpticalConstants {
    /// Reflectance per channel of a surface with these constants, seen from a medium of
    /// real index `outside_eta` at `cos_theta` = cos of the angle of incidence, with
    /// polarisation weight `polarisation_weight` (0 = s / perpendicular, 1 = p / parallel,
    /// ½ = unpolarised): R = (1 − w)·Rs + w·Rp. This is method (a) once the constants came
    /// from [`rgb_optical_constants`]. Uses the Fresnel equations of `combustion-optics`.
    pub fn reflectance(
        &self,
        cos_theta: f64,
        outside_eta: f64,
        polarisation_weight: f64,
    ) -> Result<[f64; 3], SpectrumError> {
        check_reflectance_arguments(cos_theta, outside_eta, polarisation_weight)?;
        let mut out = [0.0; 3];
        for (c, value) in out.iter_mut().enumerate() {
            *value = crate::fresnel::conductor_reflectance(
                cos_theta,
                outside_eta,
                self.eta[c],
                self.k[c],
                polarisation_weight,
            );
        }
        Ok(out)
    }
}

/// Method (a): the p-weighted band means of η and k, per RGB channel.
///
/// η and k are piecewise linear in wavelength, so their band means are computed in closed
/// form (erf), exactly up to rounding; they agree with [`band_weighted_mean`] to ~1e-14.
pub fn rgb_optical_constants(spectrum: &Spectrum) -> Result<RgbOpticalConstants, SpectrumError> {
    let mut constants = RgbOpticalConstants {
        eta: [0.0; 3],
        k: [0.0; 3],
    };
    for band in RgbBand::ALL {
        let c = band.index();
        constants.eta[c] = band_mean_of_linear(spectrum, band, |n, _| n)?;
        constants.k[c] = band_mean_of_linear(spectrum, band, |_, k| k)?;
    }
    Ok(constants)
}

pub(crate) fn check_reflectance_arguments(
    cos_theta: f64,
    outside_eta: f64,
    polarisation_weight: f64,
) -> Result<(), SpectrumError> {
    if !(0.0..=1.0).contains(&cos_theta) {
        return Err(SpectrumError::InvalidArgument {
            name: "cos_theta",
            value: cos_theta,
            expected: "in [0, 1]",
        });
    }
    if !(outside_eta.is_finite() && outside_eta > 0.0) {
        return Err(SpectrumError::InvalidArgument {
            name: "outside_eta",
            value: outside_eta,
            expected: "finite and > 0",
        });
    }
    if !(0.0..=1.0).contains(&polarisation_weight) {
        return Err(SpectrumError::InvalidArgument {
            name: "polarisation_weight",
            value: polarisation_weight,
            expected: "in [0, 1]",
        });
    }
    Ok(())
}

/// Method (b): the p-weighted band mean of the Fresnel reflectance R(λ), per channel.
///
/// R(λ) is the reflectance of the interface between an outside medium of real index
/// `outside_eta` and the tabulated material n(λ) + ik(λ), at `cos_theta` (cosine of the
/// angle of incidence, in [0, 1]), with polarisation weight `polarisation_weight`
/// (0 = s, 1 = p, ½ = unpolarised). The Fresnel equations are those of
/// `combustion-optics`; the band integral is [`band_weighted_mean`].
pub fn rgb_band_averaged_reflectance(
    spectrum: &Spectrum,
    cos_theta: f64,
    outside_eta: f64,
    polarisation_weight: f64,
) -> Result<[f64; 3], SpectrumError> {
    check_reflectance_arguments(cos_theta, outside_eta, polarisation_weight)?;
    let mut out = [0.0; 3];
    for band in RgbBand::ALL {
        out[band.index()] = band_weighted_mean(spectrum, band, |_, n, k| {
            crate::fresnel::conductor_reflectance(cos_theta, outside_eta, n, k, polarisation_weight)
        })?;
    }
    Ok(out)
}

/// Angles of incidence (degrees) at which the two averaging methods are compared.
pub const COMPARISON_ANGLES_DEG: [f64; 5] = [0.0, 30.0, 60.0, 75.0, 85.0];
/// Outside-medium indices at which the two averaging methods are compared (air, water).
pub const COMPARISON_OUTSIDE_ETAS: [f64; 2] = [1.0, 1.33];

/// Method (a) versus method (b) for one outside medium and one angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AveragingComparison {
    /// Outside-medium index ηi.
    pub outside_eta: f64,
    /// Angle of incidence in degrees.
    pub theta_deg: f64,
    /// Method (a): Fresnel reflectance of the band-averaged η, k, `[R, G, B]`.
    pub averaged_constants: [f64; 3],
    /// Method (b): band-averaged Fresnel reflectance, `[R, G, B]`.
    pub averaged_reflectance: [f64; 3],
}

impl AveragingComparison {
    /// (a) − (b) per channel.
    pub fn difference(&self) -> [f64; 3] {
        std::array::from_fn(|c| self.averaged_constants[c] - self.averaged_reflectance[c])
    }

    /// max over channels of |(a) − (b)|.
    pub fn max_abs_difference(&self) -> f64 {
        self.difference().iter().fold(0.0, |m, d| m.max(d.abs()))
    }
}

/// Compares method (a) ([`rgb_optical_constants`] then Fresnel) with method (b)
/// ([`rgb_band_averaged_reflectance`]) for every `outside_etas` × `angles_deg` pair
/// (outer loop over `outside_etas`), at polarisation weight `polarisation_weight`.
pub fn compare_averaging_methods(
    spectrum: &Spectrum,
    angles_deg: &[f64],
    outside_etas: &[f64],
    polarisation_weight: f64,
) -> Result<Vec<AveragingComparison>, SpectrumError> {
    let constants = rgb_optical_constants(spectrum)?;
    let mut out = Vec::with_capacity(angles_deg.len() * outside_etas.len());
    for &outside_eta in outside_etas {
        for &theta_deg in angles_deg {
            // Clamp the rounding of cos(90°) ≈ 6e-17 and friends into [0, 1].
            let cos_theta = theta_deg.to_radians().cos().clamp(0.0, 1.0);
            out.push(AveragingComparison {
                outside_eta,
                theta_deg,
                averaged_constants: constants.reflectance(
                    cos_theta,
                    outside_eta,
                    polarisation_weight,
                )?,
                averaged_reflectance: rgb_band_averaged_reflectance(
                    spectrum,
                    cos_theta,
                    outside_eta,
                    polarisation_weight,
                )?,
            });
        }
    }
    Ok(out)
}

/// [`compare_averaging_methods`] for every [`BuiltinMetal`] at
/// [`COMPARISON_ANGLES_DEG`] × [`COMPARISON_OUTSIDE_ETAS`], unpolarised light (w = ½).
pub fn compare_builtin_metals(
) -> Result<Vec<(BuiltinMetal, Vec<AveragingComparison>)>, SpectrumError> {
    BuiltinMetal::ALL
        .into_iter()
        .map(|metal| {
            compare_averaging_methods(
                metal.spectrum(),
                &COMPARISON_ANGLES_DEG,
                &COMPARISON_OUTSIDE_ETAS,
                0.5,
            )
            .map(|rows| (metal, rows))
        })
        .collect()
}
