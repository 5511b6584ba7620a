//! Band weighting (rendering notes §4, seed-notes 6), methods (a) and (b) (seed-notes 7),
//! and the built-in tables.

use combustion_spectra::{
    band_weight, band_weighted_mean, compare_averaging_methods, compare_builtin_metals,
    rgb_band_averaged_reflectance, rgb_optical_constants, BuiltinDielectric, BuiltinMetal, RgbBand,
    Spectrum, SpectrumError, COMPARISON_ANGLES_DEG, COMPARISON_OUTSIDE_ETAS,
};

/// A table from `first` to `last` nm every `step` nm with n, k given by `f(λ)`.
fn table(first: f64, last: f64, step: f64, f: impl Fn(f64) -> (f64, f64)) -> Spectrum {
    let mut text = String::from("wavelength_nm,n,k\n");
    let mut wavelength = first;
    while wavelength <= last + 1e-9 {
        let (n, k) = f(wavelength);
        text.push_str(&format!("{wavelength},{n},{k}\n"));
        wavelength += step;
    }
    Spectrum::from_csv(&text).unwrap()
}

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    (a - b).abs() <= tolerance * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn constant_spectrum_is_returned_unchanged() {
    // Samples deliberately not aligned with the band edges.
    let s = table(403.7, 787.0, 13.3, |_| (0.37, 2.9));
    for band in RgbBand::ALL {
        let v = band_weighted_mean(&s, band, |_, _, _| 0.731).unwrap();
        assert!(close(v, 0.731, 1e-15), "{band}: {v}");
        let n = band_weighted_mean(&s, band, |_, n, _| n).unwrap();
        assert!(close(n, 0.37, 1e-15), "{band}: {n}");
    }
    // Method (a): the band means of a constant η, k are that η, k.
    let c = rgb_optical_constants(&s).unwrap();
    for ch in 0..3 {
        assert!(close(c.eta[ch], 0.37, 1e-14), "{c:?}");
        assert!(close(c.k[ch], 2.9, 1e-14), "{c:?}");
    }
}

#[test]
fn constant_spectrum_makes_both_methods_agree() {
    let s = table(403.7, 787.0, 13.3, |_| (0.37, 2.9));
    let c = rgb_optical_constants(&s).unwrap();
    for outside_eta in [1.0, 1.33] {
        for theta in COMPARISON_ANGLES_DEG {
            let cos_theta = theta.to_radians().cos();
            for w in [0.0, 0.5, 1.0] {
                let a = c.reflectance(cos_theta, outside_eta, w).unwrap();
                let b = rgb_band_averaged_reflectance(&s, cos_theta, outside_eta, w).unwrap();
                for ch in 0..3 {
                    assert!(
                        close(a[ch], b[ch], 1e-14),
                        "θ={theta} ηi={outside_eta}: {a:?} {b:?}"
                    );
                    assert!(a[ch] > 0.0 && a[ch] <= 1.0);
                }
                // And all three channels are the same.
                assert!(
                    close(b[0], b[1], 1e-14) && close(b[1], b[2], 1e-14),
                    "{b:?}"
                );
            }
        }
    }
}

#[test]
fn linear_spectrum_gives_its_value_at_the_band_centre() {
    // ∫₀¹ (t − ½) exp(−(t − ½)²) dt = [−½ exp(−(t − ½)²)]₀¹ = −½e^(−¼) + ½e^(−¼) = 0, so the
    // p-weighted mean of t is ½ and the mean of any linear function of λ is its value at
    // the band centre (w_min + w_max)/2.
    let n = |wavelength: f64| 0.2 + 0.003 * wavelength;
    let k = |wavelength: f64| 7.5 - 0.0041 * wavelength;
    let s = table(401.3, 798.0, 7.7, |w| (n(w), k(w)));
    let c = rgb_optical_constants(&s).unwrap();
    for band in RgbBand::ALL {
        let (lo, hi) = band.range_nm();
        let centre = 0.5 * (lo + hi);
        let quad_n = band_weighted_mean(&s, band, |_, n, _| n).unwrap();
        let quad_k = band_weighted_mean(&s, band, |_, _, k| k).unwrap();
        let quad_lambda = band_weighted_mean(&s, band, |wavelength, _, _| wavelength).unwrap();
        assert!(
            close(quad_n, n(centre), 1e-14),
            "{band}: {quad_n} vs {}",
            n(centre)
        );
        assert!(
            close(quad_k, k(centre), 1e-14),
            "{band}: {quad_k} vs {}",
            k(centre)
        );
        assert!(close(quad_lambda, centre, 1e-14), "{band}: {quad_lambda}");
        assert!(
            close(c.eta[band.index()], n(centre), 1e-14),
            "{band}: {c:?}"
        );
        assert!(close(c.k[band.index()], k(centre), 1e-14), "{band}: {c:?}");
    }
}

#[test]
fn quadratic_spectrum_matches_the_closed_form() {
    // Independent check of the weighting itself (not only its symmetry): for f(t) = (t − ½)²,
    // ∫₀¹ x² e^(−x²) over x ∈ [−½, ½] = ½∫e^(−x²) − ½[x e^(−x²)] ⇒
    // mean = ½ − ½ e^(−¼) / ∫_{−½}^{½} e^(−x²) dx, and ∫_{−½}^{½} e^(−x²) dx = √π erf(½).
    let erf_half = 0.520_499_877_813_046_5;
    let gauss = std::f64::consts::PI.sqrt() * erf_half;
    let expected = 0.5 - 0.5 * (-0.25f64).exp() / gauss;
    let s = table(400.0, 800.0, 10.0, |_| (1.0, 1.0));
    for band in RgbBand::ALL {
        let (lo, hi) = band.range_nm();
        let v = band_weighted_mean(&s, band, |wavelength, _, _| {
            let x = (wavelength - lo) / (hi - lo) - 0.5;
            x * x
        })
        .unwrap();
        assert!(close(v, expected, 1e-14), "{band}: {v} vs {expected}");
    }
    assert_eq!(band_weight(0.5), 1.0);
    assert!(close(band_weight(0.0), (-0.25f64).exp(), 1e-16));
    assert!(close(band_weight(1.0), (-0.25f64).exp(), 1e-16));
}

/// Composite Simpson on `steps` equal cells over the band, for cross-checking the
/// Gauss–Legendre integration on real (kinked) tables.
fn simpson_band_mean(s: &Spectrum, band: RgbBand, f: impl Fn(f64, f64, f64) -> f64) -> f64 {
    let (lo, hi) = band.range_nm();
    let steps = 200_000;
    let h = (hi - lo) / steps as f64;
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..=steps {
        let wavelength = lo + h * i as f64;
        let weight = if i == 0 || i == steps {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let (n, k) = s.n_k_at(wavelength).unwrap();
        let p = band_weight((wavelength - lo) / (hi - lo));
        num += weight * p * f(wavelength, n, k);
        den += weight * p;
    }
    num / den
}

#[test]
fn exact_and_quadrature_means_agree_on_every_builtin_table() {
    let spectra = BuiltinMetal::ALL
        .iter()
        .map(|m| (m.name(), m.spectrum()))
        .chain(
            BuiltinDielectric::ALL
                .iter()
                .map(|d| (d.name(), d.spectrum())),
        );
    for (name, s) in spectra {
        let c = rgb_optical_constants(s).unwrap();
        for band in RgbBand::ALL {
            let n = band_weighted_mean(s, band, |_, n, _| n).unwrap();
            let k = band_weighted_mean(s, band, |_, _, k| k).unwrap();
            assert!(
                close(n, c.eta[band.index()], 1e-13),
                "{name} {band}: {n} {c:?}"
            );
            assert!(
                close(k, c.k[band.index()], 1e-13),
                "{name} {band}: {k} {c:?}"
            );
            // A smooth non-linear function of n and k, against brute-force Simpson.
            let f =
                |_: f64, n: f64, k: f64| ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
            let gl = band_weighted_mean(s, band, f).unwrap();
            let simpson = simpson_band_mean(s, band, f);
            assert!(close(gl, simpson, 1e-9), "{name} {band}: {gl} vs {simpson}");
        }
    }
}

#[test]
fn non_finite_integrand_is_an_error() {
    let s = BuiltinMetal::Gold.spectrum();
    let e = band_weighted_mean(s, RgbBand::Green, |wavelength, _, _| {
        if wavelength > 530.0 {
            f64::NAN
        } else {
            1.0
        }
    })
    .unwrap_err();
    assert!(
        matches!(
            e,
            SpectrumError::NonFiniteIntegrand {
                band: RgbBand::Green,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn reflectance_arguments_are_checked() {
    let s = BuiltinMetal::Gold.spectrum();
    for (cos_theta, outside_eta, w) in [
        (-0.1, 1.0, 0.5),
        (1.1, 1.0, 0.5),
        (f64::NAN, 1.0, 0.5),
        (0.5, 0.0, 0.5),
        (0.5, f64::INFINITY, 0.5),
        (0.5, 1.0, -0.5),
        (0.5, 1.0, 1.5),
    ] {
        assert!(
            matches!(
                rgb_band_averaged_reflectance(s, cos_theta, outside_eta, w),
                Err(SpectrumError::InvalidArgument { .. })
            ),
            "{cos_theta} {outside_eta} {w}"
        );
    }
}

#[test]
fn builtin_tables_parse_and_carry_their_citation() {
    for metal in BuiltinMetal::ALL {
        let s = metal.spectrum();
        assert!(s.samples().len() >= 19, "{metal:?}");
        let header: String = metal
            .csv()
            .lines()
            .take_while(|l| l.starts_with('#'))
            .collect();
        let doi = metal
            .citation()
            .split("doi:")
            .nth(1)
            .unwrap()
            .split([';', ' '])
            .next()
            .unwrap();
        assert!(header.contains(doi), "{metal:?}: {doi} not in header");
        assert!(header.contains("CC0"), "{metal:?}");
        assert!(header.contains("database/data/main/"), "{metal:?}");
        assert_eq!(BuiltinMetal::from_name(metal.name()), Some(metal));
        assert_eq!(
            BuiltinMetal::from_name(&metal.name().to_uppercase()),
            Some(metal)
        );
        assert_eq!(BuiltinMetal::from_name(metal.symbol()), Some(metal));
        assert_eq!(
            BuiltinMetal::from_name(&metal.symbol().to_lowercase()),
            Some(metal)
        );
    }
    for dielectric in BuiltinDielectric::ALL {
        let s = dielectric.spectrum();
        assert!(s.samples().len() >= 21);
        let header: String = dielectric
            .csv()
            .lines()
            .take_while(|l| l.starts_with('#'))
            .collect();
        assert!(header.contains("CC0"));
        assert_eq!(
            BuiltinDielectric::from_name(dielectric.name()),
            Some(dielectric)
        );
        let c = rgb_optical_constants(s).unwrap();
        for ch in 0..3 {
            assert!(
                c.eta[ch] > 1.3 && c.eta[ch] < 1.53 && c.k[ch] < 1e-6,
                "{c:?}"
            );
        }
    }
    assert_eq!(BuiltinMetal::from_name(" Au "), Some(BuiltinMetal::Gold));
    assert_eq!(
        BuiltinMetal::from_name("aluminum"),
        Some(BuiltinMetal::Aluminium)
    );
    assert_eq!(BuiltinMetal::from_name("unobtainium"), None);
    assert_eq!(
        BuiltinDielectric::from_name("H2O"),
        Some(BuiltinDielectric::Water)
    );
    assert_eq!(
        BuiltinDielectric::from_name("N-BK7"),
        Some(BuiltinDielectric::Bk7Glass)
    );
    assert_eq!(BuiltinDielectric::from_name("glass"), None);
    // Dispersion: water and BK7 have normal dispersion, η(Blue) > η(Green) > η(Red).
    for d in BuiltinDielectric::ALL {
        let c = rgb_optical_constants(d.spectrum()).unwrap();
        assert!(c.eta[2] > c.eta[1] && c.eta[1] > c.eta[0], "{d:?}: {c:?}");
    }
}

fn normal_incidence(metal: BuiltinMetal) -> ([f64; 3], [f64; 3]) {
    let s = metal.spectrum();
    let a = rgb_optical_constants(s)
        .unwrap()
        .reflectance(1.0, 1.0, 0.5)
        .unwrap();
    let b = rgb_band_averaged_reflectance(s, 1.0, 1.0, 0.5).unwrap();
    (a, b)
}

#[test]
fn gold_is_yellow_copper_is_orange_silver_is_bright() {
    let (a, b) = normal_incidence(BuiltinMetal::Gold);
    for r in [a, b] {
        assert!(r[0] > r[1] && r[1] > r[2], "gold {r:?}");
    }
    let (a, b) = normal_incidence(BuiltinMetal::Copper);
    for r in [a, b] {
        assert!(r[0] > r[1] && r[1] >= r[2], "copper {r:?}");
    }
    let (a, b) = normal_incidence(BuiltinMetal::Silver);
    for r in [a, b] {
        assert!(r.iter().all(|&x| x > 0.9), "silver {r:?}");
    }
    // Aluminium is bright and nearly neutral.
    let (a, _) = normal_incidence(BuiltinMetal::Aluminium);
    assert!(a.iter().all(|&x| x > 0.85), "aluminium {a:?}");
}

#[test]
fn every_builtin_metal_reflects_sensibly_at_every_angle() {
    let report = compare_builtin_metals().unwrap();
    assert_eq!(report.len(), BuiltinMetal::ALL.len());
    for (metal, rows) in report {
        assert_eq!(
            rows.len(),
            COMPARISON_ANGLES_DEG.len() * COMPARISON_OUTSIDE_ETAS.len()
        );
        for row in rows {
            for r in row
                .averaged_constants
                .iter()
                .chain(&row.averaged_reflectance)
            {
                assert!(*r > 0.0 && *r <= 1.0, "{metal:?} {row:?}");
            }
            // Reflectance of metals: averaging η, k first is a good approximation.
            assert!(row.max_abs_difference() < 0.05, "{metal:?} {row:?}");
        }
    }
    // Entering from water lowers a metal's normal-incidence reflectance.
    let s = BuiltinMetal::Silver.spectrum();
    let rows = compare_averaging_methods(s, &[0.0], &[1.0, 1.33], 0.5).unwrap();
    for ch in 0..3 {
        assert!(rows[1].averaged_reflectance[ch] < rows[0].averaged_reflectance[ch]);
    }
}
