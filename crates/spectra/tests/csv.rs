//! `Spectrum::from_csv`: accepted syntax, every error case, interpolation.

use combustion_spectra::{RgbBand, Spectrum, SpectrumError};

/// A valid table: 400–800 nm every 10 nm, constant n = 1.5, k = 2.
fn valid_rows() -> String {
    (0..=40)
        .map(|i| format!("{},1.5,2\n", 400 + 10 * i))
        .collect()
}

fn err(text: &str) -> SpectrumError {
    match Spectrum::from_csv(text) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

#[test]
fn accepts_header_comments_blank_lines_crlf_and_exponents() {
    let text = format!(
        "# a citation line\r\n  # indented comment\r\n\r\nWavelength_nm, n , K\r\n{}",
        valid_rows()
            .replace('\n', "\r\n")
            .replace("400,1.5,2", "4.0E+2,1.5E0,2.0e0")
    );
    let s = Spectrum::from_csv(&text).unwrap();
    assert_eq!(s.samples().len(), 41);
    assert_eq!(s.samples()[0], (400.0, 1.5, 2.0));
    assert_eq!(s.range_nm(), (400.0, 800.0));
    // Header is optional.
    assert_eq!(Spectrum::from_csv(&valid_rows()).unwrap(), s);
}

#[test]
fn n_k_at_interpolates_linearly_and_is_none_outside() {
    let s = Spectrum::from_csv(
        "wavelength_nm,n,k\n400,1,2\n450,2,4\n500,3,6\n600,5,4\n700,5,4\n800,5,4\n",
    )
    .unwrap();
    assert_eq!(s.n_k_at(400.0), Some((1.0, 2.0)));
    assert_eq!(s.n_k_at(450.0), Some((2.0, 4.0)));
    assert_eq!(s.n_k_at(500.0), Some((3.0, 6.0)));
    assert_eq!(s.n_k_at(525.0), Some((3.5, 5.5)));
    assert_eq!(s.n_k_at(800.0), Some((5.0, 4.0)));
    assert_eq!(s.n_k_at(399.999), None);
    assert_eq!(s.n_k_at(800.001), None);
    assert_eq!(s.n_k_at(f64::NAN), None);
    assert_eq!(s.n_k_at(f64::INFINITY), None);
}

#[test]
fn wrong_field_count() {
    let e = err("wavelength_nm,n,k\n450,1\n");
    assert_eq!(e, SpectrumError::WrongFieldCount { line: 2, found: 2 });
    assert!(e.to_string().starts_with("line 2:"), "{e}");
    let e = err("450,1,2,3\n");
    assert_eq!(e, SpectrumError::WrongFieldCount { line: 1, found: 4 });
}

#[test]
fn unparsable_number() {
    let e = err("# c\nwavelength_nm,n,k\n450,abc,1\n");
    assert_eq!(
        e,
        SpectrumError::UnparsableNumber {
            line: 3,
            column: "n",
            text: "abc".into()
        }
    );
    assert!(e.to_string().starts_with("line 3:"), "{e}");
    assert!(e.to_string().contains("abc"), "{e}");
    // A field of megabytes is named by its start and length, not echoed whole.
    let e = err(&format!("450,{},1\n", "x".repeat(10_000_000))).to_string();
    assert!(
        e.len() < 200 && e.contains("… (10000000 characters)"),
        "{}",
        &e[..200.min(e.len())]
    );
    // Empty field.
    assert!(matches!(
        err("450,1,\n"),
        SpectrumError::UnparsableNumber {
            line: 1,
            column: "k",
            ..
        }
    ));
    // A header anywhere but first is not a header.
    let text = format!("{}wavelength_nm,n,k\n", valid_rows());
    assert!(matches!(
        err(&text),
        SpectrumError::UnparsableNumber {
            line: 42,
            column: "wavelength_nm",
            ..
        }
    ));
}

#[test]
fn non_finite_numbers() {
    for bad in ["inf", "-inf", "NaN", "1e999"] {
        let e = err(&format!("wavelength_nm,n,k\n450,1,{bad}\n"));
        assert!(
            matches!(
                e,
                SpectrumError::NonFinite {
                    line: 2,
                    column: "k",
                    ..
                }
            ),
            "{bad}: {e:?}"
        );
        assert!(e.to_string().starts_with("line 2:"), "{e}");
    }
    assert!(matches!(
        err("nan,1,1\n"),
        SpectrumError::NonFinite {
            line: 1,
            column: "wavelength_nm",
            ..
        }
    ));
}

#[test]
fn zero_or_negative_wavelength() {
    for (text, wavelength_nm) in [("0,1,1\n", 0.0), ("-450,1,1\n", -450.0)] {
        let e = err(text);
        assert_eq!(
            e,
            SpectrumError::NonPositiveWavelength {
                line: 1,
                wavelength_nm
            }
        );
        assert!(e.to_string().starts_with("line 1:"), "{e}");
    }
}

#[test]
fn negative_n_or_k() {
    let e = err("400,1,1\n450,-0.1,1\n");
    assert_eq!(
        e,
        SpectrumError::NegativeConstant {
            line: 2,
            column: "n",
            value: -0.1
        }
    );
    assert!(e.to_string().starts_with("line 2:"), "{e}");
    assert_eq!(
        err("400,1,-2\n"),
        SpectrumError::NegativeConstant {
            line: 1,
            column: "k",
            value: -2.0
        }
    );
}

/// Issue 28, defect 9: a table with n = 1e300 was drawn by `plot` while `render` refused
/// it (its RGB constants overflow f32, then "conductor η must be positive"). The table
/// itself is refused, wherever it is read, with the bound named and the value short.
#[test]
fn n_or_k_beyond_any_material() {
    let e = err("400,1,1\n450,1e300,1\n");
    assert_eq!(
        e,
        SpectrumError::ConstantTooLarge {
            line: 2,
            column: "n",
            value: 1e300,
            max: combustion_spectra::MAX_OPTICAL_CONSTANT
        }
    );
    assert_eq!(
        e.to_string(),
        "line 2: n 1e300 is above 1e6, beyond any material's optical constants"
    );
    assert!(matches!(
        err("400,1,2e6\n"),
        SpectrumError::ConstantTooLarge { column: "k", .. }
    ));
    // The bound itself is taken.
    assert!(!matches!(
        err("400,1,1e6\n"),
        SpectrumError::ConstantTooLarge { .. }
    ));
}

#[test]
fn duplicate_wavelength() {
    let e = err("wavelength_nm,n,k\n400,1,1\n450,1,1\n450,1,1\n");
    assert_eq!(
        e,
        SpectrumError::DuplicateWavelength {
            line: 4,
            wavelength_nm: 450.0,
            previous_line: 3
        }
    );
    assert!(e.to_string().starts_with("line 4:"), "{e}");
}

#[test]
fn unsorted_wavelengths() {
    let e = err("400,1,1\n# comment\n500,1,1\n450,1,1\n");
    assert_eq!(
        e,
        SpectrumError::UnsortedWavelength {
            line: 4,
            wavelength_nm: 450.0,
            previous_line: 3,
            previous_nm: 500.0
        }
    );
    assert!(e.to_string().starts_with("line 4:"), "{e}");
}

#[test]
fn no_data() {
    assert_eq!(err(""), SpectrumError::NoData { line: 0 });
    assert_eq!(
        err("").to_string(),
        "the file is empty: no `wavelength_nm,n,k` data row"
    );
    let e = err("# only\nwavelength_nm,n,k\n\n");
    assert_eq!(e, SpectrumError::NoData { line: 3 });
    assert!(e.to_string().starts_with("line 3:"), "{e}");
}

#[test]
fn band_not_covered() {
    // Starts at 460 nm: Blue (450–495) not covered.
    let text: String = (0..=40)
        .map(|i| format!("{},1,1\n", 460 + 10 * i))
        .collect();
    let e = err(&text);
    assert_eq!(
        e,
        SpectrumError::BandNotCovered {
            line: 1,
            band: RgbBand::Blue,
            end: "first",
            table_nm: 460.0,
            band_min_nm: 450.0,
            band_max_nm: 495.0
        }
    );
    assert!(e.to_string().starts_with("line 1:"), "{e}");
    // Ends at 730 nm: Red (620–740) not covered.
    let text: String = (0..=33)
        .map(|i| format!("{},1,1\n", 400 + 10 * i))
        .collect();
    let e = err(&format!("wavelength_nm,n,k\n{text}"));
    assert!(
        matches!(
            e,
            SpectrumError::BandNotCovered {
                line: 35,
                band: RgbBand::Red,
                end: "last",
                ..
            }
        ),
        "{e:?}"
    );
    // Exactly 450–740 is enough.
    let text: String = (0..=29)
        .map(|i| format!("{},1,1\n", 450 + 10 * i))
        .collect();
    assert!(text.ends_with("740,1,1\n"));
    Spectrum::from_csv(&text).unwrap();
}

#[test]
fn too_sparse() {
    // Two samples far outside the bands: each band would be a straight line between them.
    let e = err("wavelength_nm,n,k\n400,1,1\n800,2,2\n");
    assert!(
        matches!(
            e,
            SpectrumError::TooSparse {
                line: 2,
                band: RgbBand::Blue,
                count: 0,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().starts_with("line 2:"), "{e}");
    // Blue and Green well resolved, Red bridged by 560 nm (60 nm below 620: counts) and
    // 900 nm (160 nm above 740: too far): only 1 sample.
    let e = err("440,1,1\n460,1,1\n480,1,1\n500,1,1\n530,1,1\n560,1,1\n900,1,1\n");
    assert!(
        matches!(
            e,
            SpectrumError::TooSparse {
                line: 6,
                band: RgbBand::Red,
                count: 1,
                ..
            }
        ),
        "{e:?}"
    );
    // One sample inside each band plus one near neighbour is enough.
    Spectrum::from_csv("440,1,1\n470,1,1\n530,1,1\n680,1,1\n790,1,1\n").unwrap();
}

#[test]
fn never_panics_on_garbage() {
    for text in [
        ",,",
        ",",
        "\u{feff}wavelength_nm,n,k",
        "1e308,1,1\n",
        "450,1,1\n450.0000000000001,1,1\n",
        "\0\0\0",
        "wavelength_nm,n,k\nwavelength_nm,n,k\n",
        "4,5,6\n4e-320,1,1",
    ] {
        assert!(Spectrum::from_csv(text).is_err(), "{text:?}");
    }
}
