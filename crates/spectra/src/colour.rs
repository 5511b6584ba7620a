//! Colorimetry: the colour a viewer sees of a spectral reflectance, and the metals' RGB
//! constants chosen to give it.
//!
//! * Tables: the CIE 1931 2° standard observer x̄, ȳ, z̄ ([`CIE_1931_2DEG`]) and CIE
//!   standard illuminant D65 ([`D65`]), both at 5 nm from 380 to 780 nm, as CIE 015:2018
//!   *Colorimetry* tabulates them (the observer: CIE 018:2019 data set
//!   doi:10.25039/CIE.DS.xvudnb9b, every fifth value; D65: ISO/CIE 11664-2:2022,
//!   doi:10.25039/CIE.DS.hjfjmt59). Their tests check them against the chromaticities
//!   they must give and D65 against its own definition from the daylight components.
//! * [`reflectance_colour`]: XYZ = Σ R(λ)·(x̄, ȳ, z̄)(λ)·D65(λ) / Σ ȳ(λ)·D65(λ) (the CIE's
//!   5 nm summation), then linear sRGB by [`xyz_to_linear_srgb`] (Rec. 709 primaries,
//!   white the tables' own D65, so a perfect reflector is (1, 1, 1)). A colour outside
//!   the sRGB gamut keeps its negative or above-1 components: nothing is clipped here.
//! * [`colorimetric_reflectance`]: the per-wavelength Fresnel reflectance of a measured
//!   n(λ) + ik(λ) under an outside medium, seen so (Filament's specular-colour procedure).
//! * [`colorimetric_optical_constants`]: an RGB η, k per channel whose Fresnel curves
//!   match the colorimetric reflectance over every angle, in air and in water (least
//!   squares), with the residual stated: the real-time form the renderer shades with.

use crate::rgb::RgbOpticalConstants;
use crate::{Spectrum, SpectrumError};

/// First wavelength of the colorimetric tables, nm.
pub const CIE_FIRST_NM: f64 = 380.0;
/// Step of the colorimetric tables, nm.
pub const CIE_STEP_NM: f64 = 5.0;
/// Last wavelength of the colorimetric tables, nm.
pub const CIE_LAST_NM: f64 = 780.0;

/// The CIE 1931 2° standard colorimetric observer: (x̄, ȳ, z̄) at 380, 385, …, 780 nm.
pub const CIE_1931_2DEG: [[f64; 3]; 81] = [
    [0.001368, 0.000039, 0.006450],
    [0.002236, 0.000064, 0.010550],
    [0.004243, 0.000120, 0.020050],
    [0.007650, 0.000217, 0.036210],
    [0.014310, 0.000396, 0.067850],
    [0.023190, 0.000640, 0.110200],
    [0.043510, 0.001210, 0.207400],
    [0.077630, 0.002180, 0.371300],
    [0.134380, 0.004000, 0.645600],
    [0.214770, 0.007300, 1.039050],
    [0.283900, 0.011600, 1.385600],
    [0.328500, 0.016840, 1.622960],
    [0.348280, 0.023000, 1.747060],
    [0.348060, 0.029800, 1.782600],
    [0.336200, 0.038000, 1.772110],
    [0.318700, 0.048000, 1.744100],
    [0.290800, 0.060000, 1.669200],
    [0.251100, 0.073900, 1.528100],
    [0.195360, 0.090980, 1.287640],
    [0.142100, 0.112600, 1.041900],
    [0.095640, 0.139020, 0.812950],
    [0.057950, 0.169300, 0.616200],
    [0.032010, 0.208020, 0.465180],
    [0.014700, 0.258600, 0.353300],
    [0.004900, 0.323000, 0.272000],
    [0.002400, 0.407300, 0.212300],
    [0.009300, 0.503000, 0.158200],
    [0.029100, 0.608200, 0.111700],
    [0.063270, 0.710000, 0.078250],
    [0.109600, 0.793200, 0.057250],
    [0.165500, 0.862000, 0.042160],
    [0.225750, 0.914850, 0.029840],
    [0.290400, 0.954000, 0.020300],
    [0.359700, 0.980300, 0.013400],
    [0.433450, 0.994950, 0.008750],
    [0.512050, 1.000000, 0.005750],
    [0.594500, 0.995000, 0.003900],
    [0.678400, 0.978600, 0.002750],
    [0.762100, 0.952000, 0.002100],
    [0.842500, 0.915400, 0.001800],
    [0.916300, 0.870000, 0.001650],
    [0.978600, 0.816300, 0.001400],
    [1.026300, 0.757000, 0.001100],
    [1.056700, 0.694900, 0.001000],
    [1.062200, 0.631000, 0.000800],
    [1.045600, 0.566800, 0.000600],
    [1.002600, 0.503000, 0.000340],
    [0.938400, 0.441200, 0.000240],
    [0.854450, 0.381000, 0.000190],
    [0.751400, 0.321000, 0.000100],
    [0.642400, 0.265000, 0.000050],
    [0.541900, 0.217000, 0.000030],
    [0.447900, 0.175000, 0.000020],
    [0.360800, 0.138200, 0.000010],
    [0.283500, 0.107000, 0.0],
    [0.218700, 0.081600, 0.0],
    [0.164900, 0.061000, 0.0],
    [0.121200, 0.044580, 0.0],
    [0.087400, 0.032000, 0.0],
    [0.063600, 0.023200, 0.0],
    [0.046770, 0.017000, 0.0],
    [0.032900, 0.011920, 0.0],
    [0.022700, 0.008210, 0.0],
    [0.015840, 0.005723, 0.0],
    [0.011359, 0.004102, 0.0],
    [0.008111, 0.002929, 0.0],
    [0.005790, 0.002091, 0.0],
    [0.004109, 0.001484, 0.0],
    [0.002899, 0.001047, 0.0],
    [0.002049, 0.000740, 0.0],
    [0.001440, 0.000520, 0.0],
    [0.001000, 0.000361, 0.0],
    [0.000690, 0.000249, 0.0],
    [0.000476, 0.000172, 0.0],
    [0.000332, 0.000120, 0.0],
    [0.000235, 0.000085, 0.0],
    [0.000166, 0.000060, 0.0],
    [0.000117, 0.000042, 0.0],
    [0.000083, 0.000030, 0.0],
    [0.000059, 0.000021, 0.0],
    [0.000042, 0.000015, 0.0],
];

/// CIE standard illuminant D65, relative spectral power (100 at 560 nm), at 380, 385,
/// …, 780 nm.
pub const D65: [f64; 81] = [
    49.9755, 52.3118, 54.6482, 68.7015, 82.7549, 87.1204, 91.486, 92.4589, 93.4318, 90.057,
    86.6823, 95.7736, 104.865, 110.936, 117.008, 117.41, 117.812, 116.336, 114.861, 115.392,
    115.923, 112.367, 108.811, 109.082, 109.354, 108.578, 107.802, 106.296, 104.79, 106.239,
    107.689, 106.047, 104.405, 104.225, 104.046, 102.023, 100.0, 98.1671, 96.3342, 96.0611, 95.788,
    92.2368, 88.6856, 89.3459, 90.0062, 89.8026, 89.5991, 88.6489, 87.6987, 85.4936, 83.2886,
    83.4939, 83.6992, 81.863, 80.0268, 80.1207, 80.2146, 81.2462, 82.2778, 80.281, 78.2842,
    74.0027, 69.7213, 70.6652, 71.6091, 72.979, 74.349, 67.9765, 61.604, 65.7448, 69.8856, 72.4863,
    75.087, 69.3398, 63.5927, 55.0054, 46.4182, 56.6118, 66.8054, 65.0941, 63.3828,
];

/// The wavelength of row `i` of the tables, nm.
pub fn cie_wavelength(i: usize) -> f64 {
    CIE_FIRST_NM + CIE_STEP_NM * i as f64
}

/// Rec. 709 / sRGB primaries' chromaticities (x, y): red, green, blue.
pub const REC709_PRIMARIES: [[f64; 2]; 3] = [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]];

/// CIE XYZ of the tables' D65 white (a perfect reflector), Y = 1.
pub fn d65_white_xyz() -> [f64; 3] {
    xyz_of(|_| 1.0)
}

/// The matrix from CIE XYZ to linear sRGB: Rec. 709 primaries, and as white the tables'
/// own D65 ([`d65_white_xyz`], chromaticity (0.31272, 0.32903) against the sRGB
/// standard's rounded (0.3127, 0.3290)), so a perfect reflector is (1, 1, 1) exactly.
pub fn xyz_to_linear_srgb() -> [[f64; 3]; 3] {
    static MATRIX: std::sync::OnceLock<[[f64; 3]; 3]> = std::sync::OnceLock::new();
    *MATRIX.get_or_init(|| inverse(linear_srgb_to_xyz()))
}

/// The inverse of [`xyz_to_linear_srgb`]: each primary's XYZ (columns) scaled so that
/// they sum to the tables' white.
fn linear_srgb_to_xyz() -> [[f64; 3]; 3] {
    static MATRIX: std::sync::OnceLock<[[f64; 3]; 3]> = std::sync::OnceLock::new();
    *MATRIX.get_or_init(|| {
        // Columns: each primary's XYZ at Y = 1, scaled so that they sum to the white.
        let primary = |[x, y]: [f64; 2]| [x / y, 1.0, (1.0 - x - y) / y];
        let p = REC709_PRIMARIES.map(primary);
        let columns = [
            [p[0][0], p[1][0], p[2][0]],
            [p[0][1], p[1][1], p[2][1]],
            [p[0][2], p[1][2], p[2][2]],
        ];
        let scale = solve(columns, d65_white_xyz());
        columns.map(|row| [row[0] * scale[0], row[1] * scale[1], row[2] * scale[2]])
    })
}

/// CIE XYZ (Y = 1 for a perfect reflector) of the reflectance `reflectance(λ)` under D65.
pub fn xyz_of(reflectance: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    let mut norm = 0.0;
    for (i, (cmf, power)) in CIE_1931_2DEG.iter().zip(D65).enumerate() {
        let r = reflectance(cie_wavelength(i));
        for c in 0..3 {
            xyz[c] += r * cmf[c] * power;
        }
        norm += cmf[1] * power;
    }
    xyz.map(|v| v / norm)
}

/// Linear sRGB of CIE XYZ.
pub fn linear_srgb_of_xyz(xyz: [f64; 3]) -> [f64; 3] {
    let m = xyz_to_linear_srgb();
    m.map(|row| row[0] * xyz[0] + row[1] * xyz[1] + row[2] * xyz[2])
}

/// The linear sRGB colour of the reflectance spectrum `reflectance(λ)` (λ in nm, 380 to
/// 780) under D65, seen by the 1931 2° observer: a perfect reflector is (1, 1, 1).
pub fn reflectance_colour(reflectance: impl Fn(f64) -> f64) -> [f64; 3] {
    linear_srgb_of_xyz(xyz_of(reflectance))
}

/// CIELAB (L*, a*, b*) of linear sRGB, white the tables' D65.
pub fn lab_of_linear_srgb(rgb: [f64; 3]) -> [f64; 3] {
    let xyz = linear_srgb_to_xyz().map(|row| row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2]);
    let white = d65_white_xyz();
    let f = |t: f64| {
        const DELTA: f64 = 6.0 / 29.0;
        if t > DELTA.powi(3) {
            t.cbrt()
        } else {
            t / (3.0 * DELTA * DELTA) + 4.0 / 29.0
        }
    };
    let [fx, fy, fz] = [0, 1, 2].map(|c| f(xyz[c] / white[c]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// CIE 1976 colour difference ΔE*ab between two linear sRGB colours.
pub fn delta_e_76(a: [f64; 3], b: [f64; 3]) -> f64 {
    let (a, b) = (lab_of_linear_srgb(a), lab_of_linear_srgb(b));
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The colorimetric reflectance of the interface between an outside medium of real
/// index `outside_eta` and the tabulated conductor, at `cos_theta`, polarisation weight
/// `polarisation_weight` (0 = s, 1 = p, ½ = unpolarised): the Fresnel reflectance per
/// wavelength (`combustion-optics`), n and k interpolated linearly in the table, seen
/// as [`reflectance_colour`] says. The table must span 380–780 nm.
pub fn colorimetric_reflectance(
    spectrum: &Spectrum,
    cos_theta: f64,
    outside_eta: f64,
    polarisation_weight: f64,
) -> Result<[f64; 3], SpectrumError> {
    crate::rgb::check_reflectance_arguments(cos_theta, outside_eta, polarisation_weight)?;
    check_visible(spectrum)?;
    Ok(reflectance_colour(|nm| {
        let (n, k) = spectrum
            .n_k_at(nm)
            .expect("the table spans 380-780 nm (checked)");
        crate::fresnel::conductor_reflectance(cos_theta, outside_eta, n, k, polarisation_weight)
    }))
}

/// The linear sRGB colour of a thin film's exact reflectance: the Airy reflectance of
/// the film per wavelength (`combustion_optics::thin_film::thin_film_reflectance_at`)
/// over a base whose index is `base(λ)` = (n, k), polarisation-weighted
/// (0 = s, 1 = p, ½ = unpolarised), seen as [`reflectance_colour`] says. The f64 oracle
/// of the renderer's thin film (`combustion_optics::thin_film`), which takes the base's
/// index per RGB channel and the colour matching functions as Gaussians.
pub fn thin_film_colour(
    cos_theta: f64,
    outside_eta: f64,
    film_eta: f64,
    thickness_nm: f64,
    base: impl Fn(f64) -> (f64, f64),
    polarisation_weight: f64,
) -> [f64; 3] {
    reflectance_colour(|nm| {
        let (n, k) = base(nm);
        combustion_optics::thin_film::thin_film_reflectance_at(
            cos_theta,
            outside_eta,
            film_eta,
            thickness_nm,
            n,
            k,
            nm,
        )
        .weighted(polarisation_weight)
    })
}

/// Refuses a table that does not span the colorimetric tables' 380–780 nm.
fn check_visible(spectrum: &Spectrum) -> Result<(), SpectrumError> {
    let (first, last) = spectrum.range_nm();
    if first > CIE_FIRST_NM || last < CIE_LAST_NM {
        return Err(SpectrumError::VisibleNotCovered {
            first_nm: first,
            last_nm: last,
        });
    }
    Ok(())
}

/// Outside media the colorimetric constants are fitted in: air and water.
pub const FIT_OUTSIDE_ETAS: [f64; 2] = [1.0, 1.33];

/// Angles of incidence (degrees) the fit samples: 0 to 88° in steps of 4°.
pub fn fit_angles_deg() -> impl Iterator<Item = f64> {
    (0..=22).map(|i| f64::from(i) * 4.0)
}

/// RGB constants fitted to the colorimetric reflectance, and how well they fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorimetricFit {
    /// η and k per channel.
    pub constants: RgbOpticalConstants,
    /// Per channel, the root mean square of (RGB Fresnel − colorimetric reflectance) over
    /// [`fit_angles_deg`] in each medium of [`FIT_OUTSIDE_ETAS`] (unpolarised).
    pub rms_residual: [f64; 3],
    /// Per channel, the largest such difference.
    pub max_residual: [f64; 3],
}

/// An RGB η, k per channel whose unpolarised Fresnel reflectance matches the colorimetric
/// reflectance ([`colorimetric_reflectance`]) in the least-squares sense over every angle
/// of [`fit_angles_deg`] in air and in water ([`FIT_OUTSIDE_ETAS`]): Nelder–Mead on
/// (ln η, ln k) per channel within [`FIT_BOUNDS`], from the band method's constants.
/// The table must span 380–780 nm.
///
/// Out of gamut: where the colorimetric colour has a channel above 1 (gold's and
/// copper's red, 1.05: redder than sRGB's red primary shows at that brightness), no
/// reflectance reaches it; the channel fits a mirror (R ≈ 1), the nearest a Fresnel
/// reflectance comes, and the residual states the rest.
pub fn colorimetric_optical_constants(
    spectrum: &Spectrum,
) -> Result<ColorimetricFit, SpectrumError> {
    check_visible(spectrum)?;
    let start = crate::rgb_optical_constants(spectrum)?;
    let mut targets = Vec::new();
    for outside_eta in FIT_OUTSIDE_ETAS {
        for angle in fit_angles_deg() {
            let cos_theta = angle.to_radians().cos();
            let colour = colorimetric_reflectance(spectrum, cos_theta, outside_eta, 0.5)?;
            targets.push((cos_theta, outside_eta, colour));
        }
    }
    let mut fit = ColorimetricFit {
        constants: start,
        rms_residual: [0.0; 3],
        max_residual: [0.0; 3],
    };
    for c in 0..3 {
        let residuals = |[ln_eta, ln_k]: [f64; 2]| {
            targets
                .iter()
                .map(move |&(cos_theta, outside_eta, colour)| {
                    let r = crate::fresnel::conductor_reflectance(
                        cos_theta,
                        outside_eta,
                        ln_eta.exp(),
                        ln_k.exp(),
                        0.5,
                    );
                    r - colour[c]
                })
        };
        let cost = |p: [f64; 2]| residuals(within_bounds(p)).map(|d| d * d).sum::<f64>();
        let best = within_bounds(nelder_mead(cost, [start.eta[c].ln(), start.k[c].ln()]));
        fit.constants.eta[c] = best[0].exp();
        fit.constants.k[c] = best[1].exp();
        let n = targets.len() as f64;
        fit.rms_residual[c] = (cost(best) / n).sqrt();
        fit.max_residual[c] = residuals(best).map(f64::abs).fold(0.0, f64::max);
    }
    Ok(fit)
}

/// The range of the fitted η and k: 1e-3 to 100 (an out-of-gamut channel, whose target
/// a reflectance cannot reach, would otherwise run to η → 0, k → ∞: the box stops it
/// at η = 1e-3, k = 100, a mirror to 4e-7).
pub const FIT_BOUNDS: (f64, f64) = (1e-3, 100.0);

/// `p` = (ln η, ln k) brought into [`FIT_BOUNDS`].
fn within_bounds(p: [f64; 2]) -> [f64; 2] {
    p.map(|x| x.clamp(FIT_BOUNDS.0.ln(), FIT_BOUNDS.1.ln()))
}

/// Minimises `f` over the plane from `start` (Nelder–Mead, standard coefficients),
/// until the simplex's values agree to 1e-15 or after 2,000 steps.
fn nelder_mead(f: impl Fn([f64; 2]) -> f64, start: [f64; 2]) -> [f64; 2] {
    let mut simplex = [
        start,
        [start[0] + 0.1, start[1]],
        [start[0], start[1] + 0.1],
    ]
    .map(|p| (p, f(p)));
    let at =
        |a: [f64; 2], b: [f64; 2], t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    for _ in 0..2000 {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        if (simplex[2].1 - simplex[0].1).abs() <= 1e-15 * (1.0 + simplex[0].1.abs()) {
            break;
        }
        let centroid = at(simplex[0].0, simplex[1].0, 0.5);
        let worst = simplex[2];
        let reflected = at(centroid, worst.0, -1.0);
        let fr = f(reflected);
        if fr < simplex[0].1 {
            let expanded = at(centroid, worst.0, -2.0);
            let fe = f(expanded);
            simplex[2] = if fe < fr {
                (expanded, fe)
            } else {
                (reflected, fr)
            };
        } else if fr < simplex[1].1 {
            simplex[2] = (reflected, fr);
        } else {
            let contracted = if fr < worst.1 {
                at(centroid, reflected, 0.5)
            } else {
                at(centroid, worst.0, 0.5)
            };
            let fc = f(contracted);
            if fc < worst.1.min(fr) {
                simplex[2] = (contracted, fc);
            } else {
                let best = simplex[0].0;
                for vertex in &mut simplex[1..] {
                    let p = at(best, vertex.0, 0.5);
                    *vertex = (p, f(p));
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex[0].0
}

/// How a metal's RGB η, k are derived from its measured spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum MetalColour {
    /// The rendering notes' method: Gaussian-weighted means of η and k over three bands
    /// ([`crate::rgb_optical_constants`]).
    #[default]
    Bands,
    /// Fitted to the colorimetric reflectance ([`colorimetric_optical_constants`]).
    Colorimetric,
}

impl MetalColour {
    /// Both, the default first.
    pub const ALL: [MetalColour; 2] = [MetalColour::Bands, MetalColour::Colorimetric];

    /// `bands` or `colorimetric`.
    pub const fn name(self) -> &'static str {
        match self {
            MetalColour::Bands => "bands",
            MetalColour::Colorimetric => "colorimetric",
        }
    }

    /// The constants of `spectrum` by this method.
    pub fn constants(self, spectrum: &Spectrum) -> Result<RgbOpticalConstants, SpectrumError> {
        match self {
            MetalColour::Bands => crate::rgb_optical_constants(spectrum),
            MetalColour::Colorimetric => Ok(colorimetric_optical_constants(spectrum)?.constants),
        }
    }
}

impl crate::BuiltinMetal {
    /// This metal's RGB constants by `colour` ([`MetalColour::constants`] of its table),
    /// each built-in metal's colorimetric fit made once per process (scenes name a metal
    /// once per material: the gold-copper grid eight times).
    pub fn constants(self, colour: MetalColour) -> RgbOpticalConstants {
        static FITS: std::sync::OnceLock<Vec<RgbOpticalConstants>> = std::sync::OnceLock::new();
        let fits = || {
            crate::BuiltinMetal::ALL
                .iter()
                .map(|m| {
                    let fit = MetalColour::Colorimetric.constants(m.spectrum());
                    fit.expect("built-in tables span 380-780 nm (tested)")
                })
                .collect()
        };
        match colour {
            MetalColour::Bands => crate::rgb_optical_constants(self.spectrum())
                .expect("built-in tables cover the RGB bands (tested)"),
            MetalColour::Colorimetric => {
                let i = crate::BuiltinMetal::ALL.iter().position(|&m| m == self);
                FITS.get_or_init(fits)[i.expect("every metal is in ALL")]
            }
        }
    }
}

/// `a x = b` for a 3×3 `a` (Cramer's rule).
fn solve(a: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let inv = inverse(a);
    inv.map(|row| row[0] * b[0] + row[1] * b[1] + row[2] * b[2])
}

/// The inverse of a 3×3 matrix (rows), by its adjugate.
fn inverse(m: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let cofactor = |r: usize, c: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
        m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]
    };
    let det = m[0][0] * cofactor(0, 0) + m[0][1] * cofactor(0, 1) + m[0][2] * cofactor(0, 2);
    let mut out = [[0.0; 3]; 3];
    for (r, row) in out.iter_mut().enumerate() {
        for (c, value) in row.iter_mut().enumerate() {
            *value = cofactor(c, r) / det;
        }
    }
    out
}

/// The built-in metals' colours by both methods, as a Markdown table (docs/metal-colours.md, the speed-against-error report): per metal at normal incidence in air, the
/// band method's RGB reflectance and the colorimetric colour, their difference per
/// channel and as CIE ΔE*ab, the fitted constants, the colour they give, its ΔE to the
/// colorimetric colour, and the fit's largest residual over angles in air and water.
pub fn metal_colour_table() -> Result<String, SpectrumError> {
    let rgb = |c: [f64; 3]| format!("{:.3}, {:.3}, {:.3}", c[0], c[1], c[2]);
    let mut table = String::from(
        "| metal | data | bands RGB | colorimetric RGB | bands − colorimetric | ΔE*ab bands | fitted η | fitted k | fitted RGB | ΔE*ab fitted | fit residual (max) |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for metal in crate::BuiltinMetal::ALL {
        let spectrum = metal.spectrum();
        let bands = crate::rgb_optical_constants(spectrum)?.reflectance(1.0, 1.0, 0.5)?;
        let target = colorimetric_reflectance(spectrum, 1.0, 1.0, 0.5)?;
        let fit = colorimetric_optical_constants(spectrum)?;
        let fitted = fit.constants.reflectance(1.0, 1.0, 0.5)?;
        let relative = [0, 1, 2].map(|c| (bands[c] / target[c] - 1.0) * 100.0);
        table += &format!(
            "| {} | {} | {} | {} | {:+.1} %, {:+.1} %, {:+.1} % | {:.2} | {:.3}, {:.3}, {:.3} | {:.3}, {:.3}, {:.3} | {} | {:.2} | {:.1e} |\n",
            metal.name(),
            metal.dataset(),
            rgb(bands),
            rgb(target),
            relative[0],
            relative[1],
            relative[2],
            delta_e_76(bands, target),
            fit.constants.eta[0],
            fit.constants.eta[1],
            fit.constants.eta[2],
            fit.constants.k[0],
            fit.constants.k[1],
            fit.constants.k[2],
            rgb(fitted),
            delta_e_76(fitted, target),
            fit.max_residual.iter().copied().fold(0.0, f64::max),
        );
    }
    Ok(table)
}
