//! Thin-film interference (KHR_materials_iridescence): a clear dielectric film of index
//! η₂ and thickness d over the surface's base (a dielectric η₃ or a conductor η₃ + ik₃),
//! under the outside medium η₁.
//!
//! **The model** (Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for
//! the Modeling of Varying Iridescence", the Airy summation in Fourier form). At one
//! wavelength λ the film reflects, per polarisation, the Airy amplitude
//! r = (r₁₂ + r₂₃ e^{iδ}) / (1 + r₁₂ r₂₃ e^{iδ}), δ = 2π·OPD/λ, OPD = 2 η₂ d cos θ₂,
//! with r₁₂ the real amplitude of the top interface and r₂₃ = ρ₂₃ e^{iφ₂₃} the complex
//! amplitude of the film–base interface (the exact Fresnel amplitude of η₃ + ik₃, its
//! phase shift included; total internal reflection at the base has |r₂₃| = 1 and a
//! phase too). Its power |r|² is, with R₁₂ = r₁₂², R₂₃ = ρ₂₃², T = 1 − R₁₂ and the
//! Poisson kernel's expansion in harmonics of ψ = δ + φ₂₃:
//!
//! |r|² = C₀ + Σ_{m≥1} 2 C_m cos(m(δ + Φ)),
//! C₀ = 1 − T(1 − R₂₃)/(1 − R₁₂R₂₃), C_m = −T(1 − R₂₃)/(1 − R₁₂R₂₃) · (|r₁₂| ρ₂₃)^m,
//! Φ = φ₂₃ (+ π where r₁₂ > 0).
//!
//! The amplitudes do not depend on λ (the indices are taken per RGB channel), so the
//! colour of the spectrum is C₀ + Σ 2 C_m S(m·OPD, m·Φ), S the colour of cos(2πD/λ + φ):
//! S_c(D, φ) = Σ_g W_cg cos(k_g D + φ) e^{−a_g D²}, the four Gaussians Belcour & Barla
//! fitted to the Fourier transforms of the CIE 1931 x̄, ȳ, z̄ ([`SENSITIVITY_GAUSSIANS`]),
//! taken to linear sRGB (Rec. 709, D65) and normalised per channel so that a flat
//! spectrum keeps its value: S_c(0, 0) = 1 ([`sensitivity_weights`]). The series is cut
//! after [`FILM_HARMONICS`] terms.
//!
//! **Limits, measured** (`tests/thin_film.rs`, against the spectral f64 oracle
//! `combustion_spectra::thin_film_colour`, which sums the exact Airy reflectance over
//! the CIE tables at 5 nm under D65): stated there.
//!
//! **Identities, exact here**: a film index-matched to the outside medium is no film
//! (the base's Fresnel reflectance, bit for bit in C₀ and no harmonic); a film
//! index-matched to a dielectric base reflects as that medium's bulk; a zero thickness
//! is no film (the caller uses the base's Fresnel, as KHR_materials_iridescence says);
//! past the critical angle of the top interface (a film of lower index than the outside
//! medium, e.g. η₂ 1.2 under water) the film reflects everything (frustrated total
//! reflection through a film thinner than a wavelength is not modelled).
//!
//! GLSL mirror: `thin_film_reflectance` in `shaders/include/thin_film.glsl`.

use crate::fresnel::Polarised;
use crate::real::Real;
use crate::{ETA_MAX, ETA_MIN};

/// A thin dielectric film over a surface (KHR_materials_iridescence).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinFilm<T> {
    /// How much of the surface's Fresnel is the film's: 0 none … 1 all
    /// (iridescenceFactor × the iridescence texture's R), clamped to [0, 1].
    pub weight: T,
    /// The film's real IOR η₂ (iridescenceIor, 1.3 by default).
    pub eta: T,
    /// Its thickness d in nanometres; 0 (or less, or NaN) is no film.
    pub thickness_nm: T,
}

impl<T: Real> ThinFilm<T> {
    /// Whether the film changes anything: a positive weight and a positive thickness.
    pub fn is_present(&self) -> bool {
        self.weight.is_positive() && self.thickness_nm.is_positive()
    }
}

/// The harmonics m = 1 … FILM_HARMONICS of the Airy series that are summed. The m-th is
/// weighted by (|r₁₂| ρ₂₃)^m: for a film of η 1.3–2 over a metal (ρ₂₃ ≈ 0.95) that is
/// at most ≈ 0.3^m, so the first left out weighs ≤ 1 % of the first kept.
pub const FILM_HARMONICS: usize = 4;

/// Thicknesses are clamped to [0, FILM_THICKNESS_MAX_NM]: from about 20 µm on the
/// interference averages out over the visible (the sensitivity's envelope is below
/// e⁻⁶⁸ at 20 µm), so a thicker film reflects as this one.
pub const FILM_THICKNESS_MAX_NM: f64 = 1.0e5;

/// Belcour & Barla's Gaussian fit of the CIE 1931 colour matching functions' Fourier
/// transforms: per Gaussian the XYZ component it belongs to (0 x, 1 y, 2 z), its
/// amplitude, position (1/m) and variance (1/m²); x has two. Their sum, normalised by
/// 1.0685e-7, is the XYZ colour of cos(2π·OPD/λ + φ) under an equal-energy light.
pub const SENSITIVITY_GAUSSIANS: [(usize, f64, f64, f64); 4] = [
    (0, 5.4856e-13, 1.6810e+06, 4.3278e+09),
    (1, 4.4201e-13, 1.7953e+06, 9.3046e+09),
    (2, 5.2481e-13, 2.2084e+06, 6.6121e+09),
    (0, 9.7470e-14, 2.2399e+06, 4.5282e+09),
];

/// The XYZ → linear sRGB matrix (IEC 61966-2-1, Rec. 709 primaries, D65 white).
pub const XYZ_TO_LINEAR_SRGB: [[f64; 3]; 3] = [
    [3.2404542, -1.5371385, -0.4985314],
    [-0.9692660, 1.8760108, 0.0415560],
    [0.0556434, -0.2040259, 1.0572252],
];

/// The sensitivity S_c(D, φ) = Σ_g W_cg cos(k_g D + φ) e^{−a_g D²} (D in nm) as three
/// arrays: W (3 channels × 4 Gaussians, each row summing to 1), k (rad/nm) and a
/// (1/nm²), derived from [`SENSITIVITY_GAUSSIANS`] and [`XYZ_TO_LINEAR_SRGB`].
pub fn sensitivity_weights() -> ([[f64; 4]; 3], [f64; 4], [f64; 4]) {
    let to_rad_per_nm = 2.0 * std::f64::consts::PI * 1e-9;
    let amplitude = SENSITIVITY_GAUSSIANS
        .map(|(_, val, _, var)| val * (2.0 * std::f64::consts::PI * var).sqrt() / 1.0685e-7);
    let mut w = [[0.0; 4]; 3];
    for (c, row) in w.iter_mut().enumerate() {
        for (g, &(component, ..)) in SENSITIVITY_GAUSSIANS.iter().enumerate() {
            row[g] = XYZ_TO_LINEAR_SRGB[c][component] * amplitude[g];
        }
        let sum: f64 = row.iter().sum();
        for x in row.iter_mut() {
            *x /= sum;
        }
    }
    let k = SENSITIVITY_GAUSSIANS.map(|(_, _, pos, _)| to_rad_per_nm * pos);
    let a = SENSITIVITY_GAUSSIANS.map(|(_, _, _, var)| to_rad_per_nm * to_rad_per_nm * var);
    (w, k, a)
}

/// S(D, ·) split as cos φ · `cos_part` − sin φ · `sin_part`, per channel.
struct Sensitivity<T> {
    cos_part: [T; 3],
    sin_part: [T; 3],
}

fn sensitivity<T: Real>(opd_nm: T) -> Sensitivity<T> {
    // Derived once: the f64 reference evaluates this per harmonic of every film lookup.
    type Weights = ([[f64; 4]; 3], [f64; 4], [f64; 4]);
    static WEIGHTS: std::sync::OnceLock<Weights> = std::sync::OnceLock::new();
    let (w, k, a) = *WEIGHTS.get_or_init(sensitivity_weights);
    let mut cos_part = [T::ZERO; 3];
    let mut sin_part = [T::ZERO; 3];
    for g in 0..4 {
        let phase = T::from_f64(k[g]) * opd_nm;
        let envelope = (-(T::from_f64(a[g]) * opd_nm * opd_nm)).exp();
        let (cg, sg) = (phase.cos() * envelope, phase.sin() * envelope);
        for c in 0..3 {
            cos_part[c] += T::from_f64(w[c][g]) * cg;
            sin_part[c] += T::from_f64(w[c][g]) * sg;
        }
    }
    Sensitivity { cos_part, sin_part }
}

/// A complex number, for the film–base amplitude.
#[derive(Clone, Copy)]
struct Complex<T> {
    re: T,
    im: T,
}

impl<T: Real> Complex<T> {
    fn mul(self, o: Self) -> Self {
        Complex {
            re: self.re * o.re - self.im * o.im,
            im: self.re * o.im + self.im * o.re,
        }
    }
    fn scale(self, s: T) -> Self {
        Complex {
            re: self.re * s,
            im: self.im * s,
        }
    }
    fn add_real(self, x: T) -> Self {
        Complex {
            re: self.re + x,
            im: self.im,
        }
    }
    fn norm_sq(self) -> T {
        self.re * self.re + self.im * self.im
    }
    /// (a − b)/(a + b); 1 where a + b = 0.
    fn ratio_of_difference(a: Self, b: Self) -> Self {
        let num = Complex {
            re: a.re - b.re,
            im: a.im - b.im,
        };
        let den = Complex {
            re: a.re + b.re,
            im: a.im + b.im,
        };
        let d = den.norm_sq();
        if !d.is_positive() {
            return Complex {
                re: T::ONE,
                im: T::ZERO,
            };
        }
        Complex {
            re: (num.re * den.re + num.im * den.im) / d,
            im: (num.im * den.re - num.re * den.im) / d,
        }
    }
    /// The principal square root (Im ≥ 0 for Im(self) ≥ 0): the decaying wave.
    fn sqrt(self) -> Self {
        let r = self.norm_sq().sqrt();
        let re = (T::HALF * (r + self.re)).max(T::ZERO).sqrt();
        let im = (T::HALF * (r - self.re)).max(T::ZERO).sqrt();
        Complex {
            re,
            im: if self.im.is_positive() || self.im == T::ZERO {
                im
            } else {
                -im
            },
        }
    }
}

/// One polarisation's Airy series: |r|² = c0 + Σ 2 c_m cos(m(δ + phase)),
/// c_m = amplitude · ratio^m.
#[derive(Clone, Copy)]
struct AirySeries<T> {
    c0: T,
    amplitude: T,
    ratio: T,
    phase: T,
}

/// The series of a top amplitude `r12` (real) and a base amplitude `r23` (module
/// documentation).
fn airy_series<T: Real>(r12: T, r23: Complex<T>) -> AirySeries<T> {
    let big_r12 = r12 * r12;
    let big_r23 = r23.norm_sq().min(T::ONE);
    let transmitted = T::ONE - big_r12;
    let denominator = T::ONE - big_r12 * big_r23;
    if !denominator.is_positive() {
        return AirySeries {
            c0: T::ONE,
            amplitude: T::ZERO,
            ratio: T::ZERO,
            phase: T::ZERO,
        };
    }
    let amplitude = -(transmitted * (T::ONE - big_r23)) / denominator;
    let phase_23 = if big_r23.is_positive() {
        r23.im.atan2(r23.re)
    } else {
        T::ZERO
    };
    AirySeries {
        c0: T::ONE + amplitude,
        amplitude,
        ratio: r12.abs() * big_r23.sqrt(),
        phase: if r12.is_positive() {
            phase_23 + T::PI
        } else {
            phase_23
        },
    }
}

/// The film's top interface at the incidence cosine `cos_theta` from the outside medium
/// (indices clamped): Snell into the film and the real amplitudes r₁₂.
struct TopInterface<T> {
    /// The film's index η₂.
    eta2: T,
    /// sin²θ₂ = (η₁/η₂)² sin²θ₁.
    sin2_2: T,
    /// cos θ₂.
    c2: T,
    /// r₁₂ for s and p.
    r12: (T, T),
}

/// The top interface, or `None` past its critical angle (the film reflects everything).
fn top_interface<T: Real>(cos_theta: T, outside_eta: T, film_eta: T) -> Option<TopInterface<T>> {
    let (eta_min, eta_max) = (T::from_f64(ETA_MIN), T::from_f64(ETA_MAX));
    let c1 = cos_theta.saturate();
    let eta1 = outside_eta.clamp_to(eta_min, eta_max);
    let eta2 = film_eta.clamp_to(eta_min, eta_max);
    let ratio = eta1 / eta2;
    let sin2_2 = ratio * ratio * ((T::ONE - c1) * (T::ONE + c1));
    if sin2_2 >= T::ONE {
        return None;
    }
    let c2 = ((T::ONE - sin2_2).max(T::ZERO)).sqrt();
    Some(TopInterface {
        eta2,
        sin2_2,
        c2,
        r12: (
            (eta1 * c1 - eta2 * c2) / (eta1 * c1 + eta2 * c2),
            (eta2 * c1 - eta1 * c2) / (eta2 * c1 + eta1 * c2),
        ),
    })
}

/// The base's complex amplitudes r₂₃ (s, p) under the film, for a base η₃ + ik₃:
/// N₃ cos θ₃ = √(N₃² − η₂² sin²θ₂), the root of the decaying wave.
fn base_amplitudes<T: Real>(
    top: &TopInterface<T>,
    base_eta: T,
    base_k: T,
) -> (Complex<T>, Complex<T>) {
    let eta_max = T::from_f64(ETA_MAX);
    let n3 = base_eta.clamp_to(T::from_f64(ETA_MIN), eta_max);
    let k3 = base_k.abs().clamp_to(T::ZERO, eta_max);
    let n3_sq = Complex {
        re: (n3 - k3) * (n3 + k3),
        im: T::TWO * n3 * k3,
    };
    let w = n3_sq.add_real(-(top.eta2 * top.eta2 * top.sin2_2)).sqrt();
    let film_side = Complex {
        re: top.eta2 * top.c2,
        im: T::ZERO,
    };
    (
        Complex::ratio_of_difference(film_side, w),
        Complex::ratio_of_difference(n3_sq.scale(top.c2), w.scale(top.eta2)),
    )
}

/// The film's reflectance R_s, R_p per RGB channel at the cosine `cos_theta` of the
/// incident direction to the (micro)surface normal in the outside medium of index
/// `outside_eta`, over a base η₃ + ik₃ per channel (`base_eta`, `base_k`; k = 0 for a
/// dielectric). The film's weight is not applied (see [`ThinFilm::weight`]); a film of
/// zero thickness is evaluated as a vanishingly thin one (the series' truncation then
/// shows: use the base's Fresnel there, as [`crate::brdf`] does).
///
/// Each value is clamped to [0, 1] (the fitted sensitivity can take a saturated
/// spectrum slightly outside the sRGB gamut).
pub fn thin_film_reflectance<T: Real>(
    cos_theta: T,
    outside_eta: T,
    film: &ThinFilm<T>,
    base_eta: [T; 3],
    base_k: [T; 3],
) -> Polarised<[T; 3]> {
    let Some(top) = top_interface(cos_theta, outside_eta, film.eta) else {
        return Polarised {
            s: [T::ONE; 3],
            p: [T::ONE; 3],
        };
    };
    let d = film
        .thickness_nm
        .clamp_to(T::ZERO, T::from_f64(FILM_THICKNESS_MAX_NM));
    let opd = T::TWO * top.eta2 * d * top.c2;
    let sensitivities: [Sensitivity<T>; FILM_HARMONICS] =
        std::array::from_fn(|m| sensitivity(T::from_f64((m + 1) as f64) * opd));
    let mut out = Polarised {
        s: [T::ZERO; 3],
        p: [T::ZERO; 3],
    };
    for c in 0..3 {
        let (r23_s, r23_p) = base_amplitudes(&top, base_eta[c], base_k[c]);
        let (r12_s, r12_p) = top.r12;
        for (r12, r23, slot) in [(r12_s, r23_s, &mut out.s[c]), (r12_p, r23_p, &mut out.p[c])] {
            let series = airy_series(r12, r23);
            let mut value = series.c0;
            let mut c_m = series.amplitude;
            for (m, s) in sensitivities.iter().enumerate() {
                c_m *= series.ratio;
                let phase = T::from_f64((m + 1) as f64) * series.phase;
                let s_c = phase.cos() * s.cos_part[c] - phase.sin() * s.sin_part[c];
                value += T::TWO * c_m * s_c;
            }
            *slot = value.saturate();
        }
    }
    out
}

/// The transmittance T_s, T_p per RGB channel of one crossing of a dielectric interface
/// from index `eta_from` into `eta_to` at the cosine `cos_theta` (on the `eta_from`
/// side), under `film` where it is present: the film absorbs nothing, so of the light it
/// does not reflect all crosses, T + w ((1 − R_film) − T) with w the film's weight
/// (clamped to [0, 1]) and R_film its reflectance over a base of index `eta_to` —
/// the BRDF's mixing of the film's Fresnel, for light that passes through. Without a
/// film (None, or no weight or thickness) it is the interface's own transmittance, the
/// same in every channel. Light crossing from inside a filmed object out meets the film
/// from its other side: `eta_from` the object's index, `eta_to` the outside medium's.
pub fn film_crossing_transmittance<T: Real>(
    cos_theta: T,
    eta_from: T,
    eta_to: T,
    film: Option<&ThinFilm<T>>,
) -> Polarised<[T; 3]> {
    let t = crate::fresnel::fresnel_dielectric_transmittance(cos_theta, eta_from, eta_to);
    let plain = Polarised {
        s: [t.s; 3],
        p: [t.p; 3],
    };
    let Some(film) = film.filter(|f| f.is_present()) else {
        return plain;
    };
    let r = thin_film_reflectance(cos_theta, eta_from, film, [eta_to; 3], [T::ZERO; 3]);
    let w = film.weight.min(T::ONE);
    Polarised {
        s: std::array::from_fn(|c| t.s + w * ((T::ONE - r.s[c]) - t.s)),
        p: std::array::from_fn(|c| t.p + w * ((T::ONE - r.p[c]) - t.p)),
    }
}

/// The exact Airy reflectance of the film at one wavelength (nm), per polarisation, over
/// a base η₃ + ik₃ at that wavelength: the spectral truth the Fourier form integrates,
/// for the f64 oracle (`combustion_spectra::thin_film_colour`) and tests.
pub fn thin_film_reflectance_at(
    cos_theta: f64,
    outside_eta: f64,
    film_eta: f64,
    thickness_nm: f64,
    base_eta: f64,
    base_k: f64,
    wavelength_nm: f64,
) -> Polarised<f64> {
    let Some(top) = top_interface(cos_theta, outside_eta, film_eta) else {
        return Polarised { s: 1.0, p: 1.0 };
    };
    let (r23_s, r23_p) = base_amplitudes(&top, base_eta, base_k);
    let ((r12_s, r12_p), eta2, c2) = (top.r12, top.eta2, top.c2);
    let d = if thickness_nm > 0.0 {
        thickness_nm.min(FILM_THICKNESS_MAX_NM)
    } else {
        0.0
    };
    let delta = 2.0 * std::f64::consts::PI * 2.0 * eta2 * d * c2 / wavelength_nm;
    let turn = Complex {
        re: delta.cos(),
        im: delta.sin(),
    };
    let airy = |r12: f64, r23: Complex<f64>| {
        let x = r23.mul(turn);
        let num = x.add_real(r12);
        let den = x.scale(r12).add_real(1.0);
        (num.norm_sq() / den.norm_sq()).clamp(0.0, 1.0)
    };
    Polarised {
        s: airy(r12_s, r23_s),
        p: airy(r12_p, r23_p),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fresnel::{fresnel_conductor, fresnel_dielectric};

    #[test]
    fn each_channel_keeps_a_flat_spectrum() {
        let (w, _, _) = sensitivity_weights();
        for row in w {
            assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        }
        let s = sensitivity::<f64>(0.0);
        assert!(s.cos_part.iter().all(|&x| (x - 1.0).abs() < 1e-15));
        assert!(s.sin_part.iter().all(|&x| x == 0.0));
    }

    #[test]
    fn a_film_matched_to_the_outside_is_the_base() {
        for (eta_i, base_eta, base_k) in [(1.0, 1.5, 0.0), (1.33, 0.2, 3.4), (1.0, 1.1, 2.6)] {
            let film = ThinFilm {
                weight: 1.0,
                eta: eta_i,
                thickness_nm: 400.0,
            };
            for i in 0..=20 {
                let c = i as f64 / 20.0;
                let f = thin_film_reflectance(c, eta_i, &film, [base_eta; 3], [base_k; 3]);
                let exact = fresnel_conductor(c, eta_i, base_eta, base_k);
                for ch in 0..3 {
                    assert!(
                        (f.s[ch] - exact.s).abs() < 1e-12,
                        "{c}: {} {}",
                        f.s[ch],
                        exact.s
                    );
                    assert!(
                        (f.p[ch] - exact.p).abs() < 1e-12,
                        "{c}: {} {}",
                        f.p[ch],
                        exact.p
                    );
                }
            }
        }
    }

    #[test]
    fn a_film_matched_to_a_dielectric_base_is_its_bulk() {
        let film = ThinFilm {
            weight: 1.0,
            eta: 1.5,
            thickness_nm: 300.0,
        };
        for eta_i in [1.0, 1.33] {
            for i in 0..=20 {
                let c = i as f64 / 20.0;
                let f = thin_film_reflectance(c, eta_i, &film, [1.5; 3], [0.0; 3]);
                let bulk = fresnel_dielectric(c, eta_i, 1.5);
                assert!((f.s[1] - bulk.s).abs() < 1e-12);
                assert!((f.p[1] - bulk.p).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn the_exact_airy_reflectance_of_a_vanishing_film_is_the_base() {
        for (base_eta, base_k) in [(1.5, 0.0), (0.2, 3.4), (2.4, 0.0)] {
            for i in 0..=10 {
                let c = i as f64 / 10.0;
                let r = thin_film_reflectance_at(c, 1.0, 1.8, 0.0, base_eta, base_k, 550.0);
                let exact = fresnel_conductor(c, 1.0, base_eta, base_k);
                assert!((r.s - exact.s).abs() < 1e-12, "{c} {} {}", r.s, exact.s);
                assert!((r.p - exact.p).abs() < 1e-12, "{c} {} {}", r.p, exact.p);
            }
        }
    }

    #[test]
    fn a_thick_film_reflects_the_incoherent_sum() {
        // 20 µm: the interference averages out over the visible, leaving
        // C₀ = (R₁₂ + R₂₃ − 2R₁₂R₂₃)/(1 − R₁₂R₂₃) per polarisation
        let film = ThinFilm {
            weight: 1.0,
            eta: 1.4,
            thickness_nm: 20_000.0,
        };
        for (eta, k) in [(1.5, 0.0), (0.4, 2.4), (1.2, 0.0)] {
            for cos in [1.0, 0.6, 0.3, 0.05] {
                let fast = thin_film_reflectance(cos, 1.0, &film, [eta; 3], [k; 3]);
                let r12 = fresnel_dielectric(cos, 1.0, 1.4);
                let sin2_2 = (1.0 - cos * cos) / (1.4 * 1.4);
                let r23 = fresnel_conductor((1.0 - sin2_2).sqrt(), 1.4, eta, k);
                let sum = |a: f64, b: f64| (a + b - 2.0 * a * b) / (1.0 - a * b);
                for c in 0..3 {
                    assert!((fast.s[c] - sum(r12.s, r23.s)).abs() < 1e-12, "{eta} {cos}");
                    assert!((fast.p[c] - sum(r12.p, r23.p)).abs() < 1e-12, "{eta} {cos}");
                }
            }
        }
    }

    #[test]
    fn a_film_of_lower_index_under_water_reflects_everything_past_its_critical_angle() {
        let film = ThinFilm {
            weight: 1.0,
            eta: 1.2,
            thickness_nm: 300.0,
        };
        // critical angle of 1.33 → 1.2: sin θ = 0.902, cos θ = 0.431
        let past = thin_film_reflectance(0.4, 1.33, &film, [1.5; 3], [0.0; 3]);
        assert_eq!(past.s, [1.0; 3]);
        let before = thin_film_reflectance(0.5, 1.33, &film, [1.5; 3], [0.0; 3]);
        assert!(before.s[1] < 1.0);
    }

    #[test]
    fn bad_inputs_stay_in_range() {
        for x in [f64::NAN, f64::INFINITY, -1.0, 0.0, 1e300, -1e300] {
            let film = ThinFilm {
                weight: x,
                eta: x,
                thickness_nm: x,
            };
            for r in [
                thin_film_reflectance(x, x, &film, [x; 3], [x; 3]),
                thin_film_reflectance(0.5, 1.0, &film, [1.5; 3], [0.0; 3]),
            ] {
                for v in r.s.iter().chain(&r.p) {
                    assert!((0.0..=1.0).contains(v), "{x}: {v}");
                }
            }
        }
    }
}
