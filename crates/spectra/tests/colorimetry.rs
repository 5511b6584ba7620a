//! Colorimetry of the measured spectra: the shipped CIE tables checked against what they
//! must give, the colour of a reflectance against identities, the metals' colorimetric
//! reflectance against an independent integration written here (its own complex Fresnel
//! equations, 1 nm steps between the 5 nm table values, the sRGB standard's published
//! matrix), and the fitted RGB constants against the colour they are fitted to.

use combustion_spectra::{
    colorimetric_optical_constants, colorimetric_reflectance, d65_white_xyz, delta_e_76,
    reflectance_colour, rgb_optical_constants, xyz_to_linear_srgb, BuiltinMetal, MetalColour,
    SpectrumError, CIE_1931_2DEG, D65,
};

/// The D65 white of the tables is the illuminant's chromaticity, (0.31272, 0.32903)
/// (CIE 015:2018, 2° observer); the equal-energy white is (1/3, 1/3) to the tables'
/// rounding: a mistyped value of the observer or the illuminant shows here.
#[test]
fn the_tables_give_the_white_points() {
    let w = d65_white_xyz();
    let sum = w[0] + w[1] + w[2];
    assert!((w[0] / sum - 0.31272).abs() < 5e-6, "x {}", w[0] / sum);
    assert!((w[1] / sum - 0.32903).abs() < 5e-6, "y {}", w[1] / sum);
    assert!((w[1] - 1.0).abs() < 1e-15);
    let e = CIE_1931_2DEG
        .iter()
        .fold([0.0; 3], |a, c| [a[0] + c[0], a[1] + c[1], a[2] + c[2]]);
    let sum = e[0] + e[1] + e[2];
    assert!((e[0] / sum - 1.0 / 3.0).abs() < 1e-5 && (e[1] / sum - 1.0 / 3.0).abs() < 1e-5);
    // The observer peaks where it must: ȳ = 1 at 555 nm, x̄ at 600 nm, z̄ at 445 nm.
    let peak = |c: usize| {
        (0..81)
            .max_by(|&a, &b| CIE_1931_2DEG[a][c].total_cmp(&CIE_1931_2DEG[b][c]))
            .unwrap()
    };
    assert_eq!([peak(0), peak(1), peak(2)], [44, 35, 13]);
    assert_eq!(CIE_1931_2DEG[35][1], 1.0);
}

/// D65 is a CIE daylight: at every 10 nm it is S0 + M1·S1 + M2·S2 of the daylight
/// components (CIE 015:2018 §4.1, tabulated at 10 nm, written here) for one M1, M2 —
/// those of the daylight locus at 6504 K to the third decimal (the table predates the
/// locus formula's current constants) — and the 5 nm values between are the linear
/// interpolations. The shipped table is that to its six significant figures: a mistyped
/// value breaks the fit.
#[test]
fn d65_is_the_daylight_of_6504_kelvin() {
    const S0: [f64; 41] = [
        63.4, 65.8, 94.8, 104.8, 105.9, 96.8, 113.9, 125.6, 125.5, 121.3, 121.3, 113.5, 113.1,
        110.8, 106.5, 108.8, 105.3, 104.4, 100.0, 96.0, 95.1, 89.1, 90.5, 90.3, 88.4, 84.0, 85.1,
        81.9, 82.6, 84.9, 81.3, 71.9, 74.3, 76.4, 63.3, 71.7, 77.0, 65.2, 47.7, 68.6, 65.0,
    ];
    const S1: [f64; 41] = [
        38.5, 35.0, 43.4, 46.3, 43.9, 37.1, 36.7, 35.9, 32.6, 27.9, 24.3, 20.1, 16.2, 13.2, 8.6,
        6.1, 4.2, 1.9, 0.0, -1.6, -3.5, -3.5, -5.8, -7.2, -8.6, -9.5, -10.9, -10.7, -12.0, -14.0,
        -13.6, -12.0, -13.3, -12.9, -10.6, -11.6, -12.2, -10.2, -7.8, -11.2, -10.4,
    ];
    const S2: [f64; 41] = [
        3.0, 1.2, -1.1, -0.5, -0.7, -1.2, -2.6, -2.9, -2.8, -2.6, -2.6, -1.8, -1.5, -1.3, -1.2,
        -1.0, -0.5, -0.3, 0.0, 0.2, 0.5, 2.1, 3.2, 4.1, 4.7, 5.1, 6.7, 7.3, 8.6, 9.8, 10.2, 8.3,
        9.6, 8.5, 7.0, 7.6, 8.0, 6.7, 5.2, 7.4, 6.8,
    ];
    // The daylight locus at 6504 K (the 1.4388/1.4380 change of c2 is why D65 is 6504 K).
    let t = 6504.0f64;
    let x = -4.6070e9 / t.powi(3) + 2.9678e6 / t.powi(2) + 0.09911e3 / t + 0.244063;
    let y = -3.000 * x * x + 2.870 * x - 0.275;
    let m = 0.0241 + 0.2562 * x - 0.7341 * y;
    let round3 = |v: f64| (v * 1000.0).round() / 1000.0;
    let locus = [
        round3((-1.3515 - 1.7703 * x + 5.9114 * y) / m),
        round3((0.0300 - 31.4424 * x + 30.0717 * y) / m),
    ];
    // M1, M2 by least squares from the table's 10 nm values.
    let (mut a, mut b) = ([[0.0; 2]; 2], [0.0; 2]);
    for i in 0..41 {
        let (u, v, r) = (S1[i], S2[i], D65[2 * i] - S0[i]);
        a[0][0] += u * u;
        a[0][1] += u * v;
        a[1][1] += v * v;
        b[0] += u * r;
        b[1] += v * r;
    }
    let det = a[0][0] * a[1][1] - a[0][1] * a[0][1];
    let m1 = (b[0] * a[1][1] - b[1] * a[0][1]) / det;
    let m2 = (a[0][0] * b[1] - a[0][1] * b[0]) / det;
    assert!(
        (m1 - locus[0]).abs() < 2e-3 && (m2 - locus[1]).abs() < 2e-3,
        "M1 {m1}, M2 {m2} against the locus's {locus:?}"
    );
    let daylight: Vec<f64> = (0..41).map(|i| S0[i] + m1 * S1[i] + m2 * S2[i]).collect();
    for (i, &value) in D65.iter().enumerate() {
        let expected = if i % 2 == 0 {
            daylight[i / 2]
        } else {
            (daylight[i / 2] + daylight[i / 2 + 1]) / 2.0
        };
        assert!(
            (value - expected).abs() <= 2e-4 * expected,
            "{} nm: table {value}, daylight {expected} (M1 {m1}, M2 {m2})",
            380 + 5 * i
        );
    }
}

/// The matrix to linear sRGB is IEC 61966-2-1's (published to four decimals, for the
/// white (0.3127, 0.3290)) to the difference of the two whites; a perfect reflector
/// is (1, 1, 1) and any constant reflectance its grey.
#[test]
fn a_constant_reflectance_is_its_grey() {
    const IEC: [[f64; 3]; 3] = [
        [3.2406, -1.5372, -0.4986],
        [-0.9689, 1.8758, 0.0415],
        [0.0557, -0.2040, 1.0570],
    ];
    let m = xyz_to_linear_srgb();
    for (row, iec) in m.iter().zip(IEC) {
        for (a, b) in row.iter().zip(iec) {
            assert!((a - b).abs() < 5e-4, "{m:?}");
        }
    }
    for c in reflectance_colour(|_| 1.0) {
        assert!((c - 1.0).abs() < 1e-12);
    }
    for c in reflectance_colour(|_| 0.37) {
        assert!((c - 0.37).abs() < 1e-12);
    }
}

/// A complex number, for the Fresnel equations written here apart from the optics
/// crate's.
#[derive(Clone, Copy)]
struct C(f64, f64);

impl C {
    fn add(self, o: C) -> C {
        C(self.0 + o.0, self.1 + o.1)
    }
    fn sub(self, o: C) -> C {
        C(self.0 - o.0, self.1 - o.1)
    }
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn div(self, o: C) -> C {
        let d = o.0 * o.0 + o.1 * o.1;
        C(
            (self.0 * o.0 + self.1 * o.1) / d,
            (self.1 * o.0 - self.0 * o.1) / d,
        )
    }
    fn sqrt(self) -> C {
        let r = (self.0 * self.0 + self.1 * self.1).sqrt();
        let re = ((r + self.0) / 2.0).sqrt();
        let im = ((r - self.0) / 2.0).sqrt().copysign(self.1);
        C(re, im)
    }
    fn norm2(self) -> f64 {
        self.0 * self.0 + self.1 * self.1
    }
}

/// Unpolarised reflectance from a medium of index `ni` into n + ik at angle θ: the
/// amplitude coefficients with the complex cosine of refraction.
fn fresnel(cos_i: f64, ni: f64, n: f64, k: f64) -> f64 {
    let nt = C(n, k);
    let ni_c = C(ni, 0.0);
    let sin2 = 1.0 - cos_i * cos_i;
    // cos θt = sqrt(1 − (ni sinθi / nt)²)
    let ratio = ni_c.div(nt);
    let cos_t = C(1.0, 0.0).sub(ratio.mul(ratio).mul(C(sin2, 0.0))).sqrt();
    let ci = C(cos_i, 0.0);
    let rs = ni_c
        .mul(ci)
        .sub(nt.mul(cos_t))
        .div(ni_c.mul(ci).add(nt.mul(cos_t)));
    let rp = nt
        .mul(ci)
        .sub(ni_c.mul(cos_t))
        .div(nt.mul(ci).add(ni_c.mul(cos_t)));
    (rs.norm2() + rp.norm2()) / 2.0
}

/// Linear interpolation in a 5 nm table from 380 nm.
fn at(table: impl Fn(usize) -> f64, nm: f64) -> f64 {
    let t = (nm - 380.0) / 5.0;
    let i = (t.floor() as usize).min(79);
    let f = t - i as f64;
    table(i) * (1.0 - f) + table(i + 1) * f
}

/// The colour of `metal` at `cos_i` under a medium `ni`, integrated here: 1 nm steps,
/// trapezoids, the tables interpolated, n and k interpolated in the metal's own rows,
/// the published sRGB matrix.
fn independent_colour(metal: BuiltinMetal, cos_i: f64, ni: f64) -> [f64; 3] {
    let rows = metal.spectrum().samples();
    let n_k = |nm: f64| {
        let j = rows.partition_point(|r| r.0 <= nm).clamp(1, rows.len() - 1);
        let (a, b) = (rows[j - 1], rows[j]);
        let s = (nm - a.0) / (b.0 - a.0);
        (a.1 + s * (b.1 - a.1), a.2 + s * (b.2 - a.2))
    };
    let mut xyz = [0.0; 3];
    let mut norm = 0.0;
    for step in 0..=400 {
        let nm = 380.0 + f64::from(step);
        let weight = if step == 0 || step == 400 { 0.5 } else { 1.0 };
        let d65 = at(|i| D65[i], nm);
        let (n, k) = n_k(nm);
        let r = fresnel(cos_i, ni, n, k);
        for (c, v) in xyz.iter_mut().enumerate() {
            *v += weight * r * at(|i| CIE_1931_2DEG[i][c], nm) * d65;
        }
        norm += weight * at(|i| CIE_1931_2DEG[i][1], nm) * d65;
    }
    let xyz = xyz.map(|v| v / norm);
    const IEC: [[f64; 3]; 3] = [
        [3.2406, -1.5372, -0.4986],
        [-0.9689, 1.8758, 0.0415],
        [0.0557, -0.2040, 1.0570],
    ];
    IEC.map(|row| row[0] * xyz[0] + row[1] * xyz[1] + row[2] * xyz[2])
}

/// Gold and copper (and the other built-in metals) at normal incidence and at 60°, in
/// air and in water: the colorimetric reflectance agrees with the independent
/// integration within 1e-3 per channel.
#[test]
fn colorimetric_metals_agree_with_an_independent_integration() {
    for metal in BuiltinMetal::ALL {
        for cos_i in [1.0, 0.5] {
            for ni in [1.0, 1.33] {
                let ours = colorimetric_reflectance(metal.spectrum(), cos_i, ni, 0.5).unwrap();
                let theirs = independent_colour(metal, cos_i, ni);
                for c in 0..3 {
                    assert!(
                        (ours[c] - theirs[c]).abs() < 1e-3,
                        "{} cos {cos_i} ηi {ni}: {ours:?} against {theirs:?}",
                        metal.name()
                    );
                }
            }
        }
    }
}

/// Under water a metal reflects less (its contrast with the medium is smaller) and its
/// colour shifts as the per-wavelength Fresnel reflectance says: gold's blue falls by
/// more than its red, relatively, so it looks more saturated.
#[test]
fn in_water_the_colour_shifts_as_the_spectral_fresnel_says() {
    let gold = BuiltinMetal::Gold.spectrum();
    let air = colorimetric_reflectance(gold, 1.0, 1.0, 0.5).unwrap();
    let water = colorimetric_reflectance(gold, 1.0, 1.33, 0.5).unwrap();
    for c in 0..3 {
        assert!(water[c] < air[c], "{water:?} {air:?}");
    }
    assert!(
        water[2] / air[2] < water[0] / air[0] - 0.1,
        "{water:?} {air:?}"
    );
    assert!(delta_e_76(air, water) > 2.0);
}

/// The band method, measured against the colour the spectrum shows: gold's red too
/// dark by 7 %, its blue too bright by 15 % at normal incidence (the figures the issue
/// quotes within a point or two, on the McPeak data); silver within 1 %. The fitted
/// constants come back to the colour: within 0.3 % in every channel a reflectance can
/// reach (gold's and copper's red lie outside sRGB and fit a mirror, below 6 %), and
/// their ΔE to the colorimetric colour is below 0.05 within the gamut and under half the
/// band method's outside it.
#[test]
fn the_fitted_constants_give_the_colorimetric_colour() {
    for metal in BuiltinMetal::ALL {
        let spectrum = metal.spectrum();
        let target = colorimetric_reflectance(spectrum, 1.0, 1.0, 0.5).unwrap();
        let bands = rgb_optical_constants(spectrum)
            .unwrap()
            .reflectance(1.0, 1.0, 0.5)
            .unwrap();
        let fit = colorimetric_optical_constants(spectrum).unwrap();
        let fitted = fit.constants.reflectance(1.0, 1.0, 0.5).unwrap();
        for c in 0..3 {
            let bound = if target[c] > 1.0 { 0.06 } else { 3e-3 };
            assert!(
                fit.max_residual[c] < bound && (fitted[c] - target[c].min(1.0)).abs() < bound,
                "{}: channel {c}: fitted {fitted:?} target {target:?} residual {:?}",
                metal.name(),
                fit.max_residual
            );
        }
        let (e_bands, e_fit) = (delta_e_76(bands, target), delta_e_76(fitted, target));
        let in_gamut = target.iter().all(|&c| c <= 1.0);
        let bound = if in_gamut { 0.05 } else { e_bands / 2.0 };
        assert!(
            e_fit < bound,
            "{}: ΔE {e_fit} against {e_bands}",
            metal.name()
        );
        assert_eq!(
            MetalColour::Colorimetric.constants(spectrum).unwrap(),
            fit.constants
        );
        if metal == BuiltinMetal::Gold {
            assert!(
                (bands[0] / target[0] - 1.0 + 0.074).abs() < 0.01,
                "{bands:?} {target:?}"
            );
            assert!(
                (bands[2] / target[2] - 1.0 - 0.15).abs() < 0.01,
                "{bands:?} {target:?}"
            );
        }
    }
}

/// A table that does not reach 380 or 780 nm cannot be seen whole: refused in one line.
#[test]
fn a_table_short_of_the_visible_range_is_refused() {
    let csv = "wavelength_nm,n,k\n440,0.5,2\n500,0.5,2.5\n600,0.2,3\n750,0.2,4\n";
    let spectrum = combustion_spectra::Spectrum::from_csv(csv).unwrap();
    let e = colorimetric_reflectance(&spectrum, 1.0, 1.0, 0.5).unwrap_err();
    assert!(matches!(e, SpectrumError::VisibleNotCovered { .. }), "{e}");
    assert_eq!(
        e.to_string(),
        "the table spans 440–750 nm; its colour (CIE 1931 observer, D65) needs 380–780 nm"
    );
    assert!(MetalColour::Colorimetric.constants(&spectrum).is_err());
    assert!(MetalColour::Bands.constants(&spectrum).is_ok());
}

/// docs/metal-colours.md's table of metal colours is the one this crate computes.
#[test]
fn the_metal_colours_page_shows_the_table() {
    let page = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/metal-colours.md"
    ))
    .unwrap();
    let table = combustion_spectra::metal_colour_table().unwrap();
    assert!(
        page.contains(&table),
        "docs/metal-colours.md's table differs from metal_colour_table():\n{table}"
    );
}
