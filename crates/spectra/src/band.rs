//! The RGB wavelength bands of the rendering notes (section 4) and the Gaussian-weighted
//! band mean.
//!
//! For a band [w_min, w_max] and t = (λ − w_min)/(w_max − w_min) ∈ [0, 1], the weight is
//! p(t) = exp(−(t − ½)²) and the band value of a function f is the weighted **mean**
//!
//! ```text
//! V = ∫₀¹ f(t) p(t) dt / ∫₀¹ p(t) dt
//! ```
//!
//! (seed-notes 6: the denominator is taken over the normalised t, so a constant f comes
//! back unchanged).

use crate::spectrum::interpolate;
use crate::{Spectrum, SpectrumError};
use std::fmt;

/// One of Combustion's three RGB wavelength bands (rendering notes §4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RgbBand {
    /// 620–740 nm.
    Red,
    /// 495–570 nm.
    Green,
    /// 450–495 nm.
    Blue,
}

impl RgbBand {
    /// Red band, (min, max) in nm.
    pub const RED_NM: (f64, f64) = (620.0, 740.0);
    /// Green band, (min, max) in nm.
    pub const GREEN_NM: (f64, f64) = (495.0, 570.0);
    /// Blue band, (min, max) in nm.
    pub const BLUE_NM: (f64, f64) = (450.0, 495.0);
    /// Shortest wavelength a table must reach (the Blue band's lower edge), nm.
    pub const COVERAGE_MIN_NM: f64 = Self::BLUE_NM.0;
    /// Longest wavelength a table must reach (the Red band's upper edge), nm.
    pub const COVERAGE_MAX_NM: f64 = Self::RED_NM.1;

    /// The bands in RGB channel order: `[Red, Green, Blue]`, index = [`RgbBand::index`].
    pub const ALL: [RgbBand; 3] = [RgbBand::Red, RgbBand::Green, RgbBand::Blue];
    /// The bands by increasing wavelength: `[Blue, Green, Red]`.
    pub const ALL_BY_WAVELENGTH: [RgbBand; 3] = [RgbBand::Blue, RgbBand::Green, RgbBand::Red];

    /// `(min, max)` wavelength of the band in nm.
    pub const fn range_nm(self) -> (f64, f64) {
        match self {
            RgbBand::Red => Self::RED_NM,
            RgbBand::Green => Self::GREEN_NM,
            RgbBand::Blue => Self::BLUE_NM,
        }
    }

    /// Channel index in an `[R, G, B]` array.
    pub const fn index(self) -> usize {
        match self {
            RgbBand::Red => 0,
            RgbBand::Green => 1,
            RgbBand::Blue => 2,
        }
    }

    /// `"Red"`, `"Green"` or `"Blue"`.
    pub const fn name(self) -> &'static str {
        match self {
            RgbBand::Red => "Red",
            RgbBand::Green => "Green",
            RgbBand::Blue => "Blue",
        }
    }
}

impl fmt::Display for RgbBand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The band weight p(t) = exp(−(t − ½)²), t the normalised wavelength in [0, 1].
pub fn band_weight(t: f64) -> f64 {
    let x = t - 0.5;
    (-x * x).exp()
}

/// 8-point Gauss–Legendre rule on [−1, 1]: (node, weight). Exact for polynomials of
/// degree ≤ 15.
const GAUSS_LEGENDRE_8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
];

/// The pieces of `band` between consecutive breakpoints (band edges and the samples
/// strictly inside the band): `(λ_a, λ_b, sample_a, sample_b)` where the table interval
/// `[sample_a, sample_b]` contains `[λ_a, λ_b]`.
type Piece = (f64, f64, (f64, f64, f64), (f64, f64, f64));

fn band_pieces(spectrum: &Spectrum, band: RgbBand) -> Result<Vec<Piece>, SpectrumError> {
    let (lo, hi) = band.range_nm();
    let s = spectrum.samples();
    let (first, last) = spectrum.range_nm();
    if s.len() < 2 || first > lo || last < hi {
        let (end, line_nm) = if s.is_empty() || first > lo {
            ("first", first)
        } else {
            ("last", last)
        };
        return Err(SpectrumError::BandNotCovered {
            line: 0,
            band,
            end,
            table_nm: line_nm,
            band_min_nm: lo,
            band_max_nm: hi,
        });
    }
    let mut pieces = Vec::new();
    for pair in s.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let from = a.0.max(lo);
        let to = b.0.min(hi);
        if to > from {
            pieces.push((from, to, a, b));
        }
    }
    Ok(pieces)
}

/// The p-weighted mean of `f(λ, n(λ), k(λ))` over `band` (rendering notes §4, seed-notes 6).
///
/// n and k are interpolated linearly in wavelength between the tabulated samples. The
/// integrals are evaluated with an 8-point Gauss–Legendre rule on every piece between
/// consecutive breakpoints (band edges and samples inside the band), numerator and
/// denominator with the same nodes, so a constant `f` is returned unchanged up to
/// rounding and the kinks of the interpolant never fall inside a quadrature cell. For `f`
/// linear in n and k the rule is exact to rounding (the integrand is a polynomial times
/// a Gaussian that varies by less than 25 % over a band); for smooth non-linear `f` such
/// as a Fresnel reflectance it agrees with much finer quadrature to ~1e-15.
///
/// Errors: [`SpectrumError::BandNotCovered`] if the table does not span the band (cannot
/// happen for a validated [`Spectrum`]; the line is reported as 0), and
/// [`SpectrumError::NonFiniteIntegrand`] if `f` returns NaN or ±∞.
pub fn band_weighted_mean(
    spectrum: &Spectrum,
    band: RgbBand,
    f: impl Fn(f64, f64, f64) -> f64,
) -> Result<f64, SpectrumError> {
    let (lo, hi) = band.range_nm();
    let width = hi - lo;
    let mut numerator = 0.0;
    let mut denominator = 0.0;
    for (from, to, a, b) in band_pieces(spectrum, band)? {
        let half = 0.5 * (to - from);
        let mid = 0.5 * (to + from);
        for (node, weight) in GAUSS_LEGENDRE_8 {
            let wavelength_nm = mid + half * node;
            let (n, k) = interpolate(a, b, wavelength_nm);
            let value = f(wavelength_nm, n, k);
            if !value.is_finite() {
                return Err(SpectrumError::NonFiniteIntegrand {
                    band,
                    wavelength_nm,
                    value,
                });
            }
            let w = weight * half * band_weight((wavelength_nm - lo) / width);
            numerator += w * value;
            denominator += w;
        }
    }
    Ok(numerator / denominator)
}

/// erf(x) for |x| ≤ 1 by its Maclaurin series (relative error ~1e-16 there).
fn erf_small(x: f64) -> f64 {
    debug_assert!(x.abs() <= 1.0);
    // erf(x) = 2/√π Σ (−1)^n x^(2n+1) / (n! (2n+1))
    let x2 = x * x;
    let mut power = x; // (−1)^n x^(2n+1) / n!
    let mut sum = x;
    for n in 1..40 {
        power *= -x2 / n as f64;
        let term = power / (2 * n + 1) as f64;
        sum += term;
        if term.abs() < 1e-18 * sum.abs() {
            break;
        }
    }
    sum * std::f64::consts::FRAC_2_SQRT_PI
}

/// ∫_{x0}^{x1} e^{−x²} dx for x0, x1 ∈ [−½, ½].
fn gauss_integral(x0: f64, x1: f64) -> f64 {
    0.5 * std::f64::consts::PI.sqrt() * (erf_small(x1) - erf_small(x0))
}

/// The p-weighted band mean of a quantity that is itself piecewise linear in wavelength
/// (n or k, chosen by `select`), integrated in closed form with erf: exact up to rounding.
///
/// On a piece [t0, t1] with g(t) = g0 + β (t − t0), x = t − ½:
/// ∫ g p dt = g0 ∫ e^{−x²} dx + β ∫ (x − x0) e^{−x²} dx, with ∫ x e^{−x²} dx = −½ e^{−x²}.
pub(crate) fn band_mean_of_linear(
    spectrum: &Spectrum,
    band: RgbBand,
    select: impl Fn(f64, f64) -> f64,
) -> Result<f64, SpectrumError> {
    let (lo, hi) = band.range_nm();
    let width = hi - lo;
    let mut numerator = 0.0;
    for (from, to, a, b) in band_pieces(spectrum, band)? {
        let (n0, k0) = interpolate(a, b, from);
        let (n1, k1) = interpolate(a, b, to);
        let (g0, g1) = (select(n0, k0), select(n1, k1));
        let x0 = (from - lo) / width - 0.5;
        let x1 = (to - lo) / width - 0.5;
        let beta = (g1 - g0) / (x1 - x0);
        let i0 = gauss_integral(x0, x1);
        let i1 = 0.5 * ((-x0 * x0).exp() - (-x1 * x1).exp());
        numerator += g0 * i0 + beta * (i1 - x0 * i0);
    }
    Ok(numerator / gauss_integral(-0.5, 0.5))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_rule_is_exact_to_degree_15() {
        let total: f64 = GAUSS_LEGENDRE_8.iter().map(|&(_, w)| w).sum();
        assert!((total - 2.0).abs() < 1e-15);
        for degree in 0..=15 {
            let q: f64 = GAUSS_LEGENDRE_8
                .iter()
                .map(|&(x, w)| w * f64::powi(x, degree))
                .sum();
            let exact = if degree % 2 == 1 {
                0.0
            } else {
                2.0 / (degree as f64 + 1.0)
            };
            assert!((q - exact).abs() < 1e-15, "degree {degree}: {q} vs {exact}");
        }
    }

    #[test]
    fn erf_series_matches_reference_values() {
        // Reference values of erf (Abramowitz & Stegun table 7.1).
        for (x, want) in [
            (0.1, 0.112_462_916_018_284_9),
            (0.25, 0.276_326_390_168_236_9),
            (0.5, 0.520_499_877_813_046_5),
            (1.0, 0.842_700_792_949_714_9),
        ] {
            assert!((erf_small(x) - want).abs() < 2e-16, "erf({x})");
            assert!((erf_small(-x) + want).abs() < 2e-16, "erf(-{x})");
        }
    }

    #[test]
    fn band_ranges_are_those_of_the_notes() {
        assert_eq!(RgbBand::Red.range_nm(), (620.0, 740.0));
        assert_eq!(RgbBand::Green.range_nm(), (495.0, 570.0));
        assert_eq!(RgbBand::Blue.range_nm(), (450.0, 495.0));
        for band in RgbBand::ALL {
            assert_eq!(RgbBand::ALL[band.index()], band);
        }
    }
}
