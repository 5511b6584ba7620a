//! The public API: every plot function makes a decodable PNG of the requested size with
//! content, and bad parameters are errors, never panics.

use combustion_plots::{
    plot_dielectric_family, plot_reflectance, plot_spectrum, BuiltinMetal, PlotError, PlotMaterial,
    Png, ReflectancePlot, Spectrum, FIGURE_12_ETAS, MAX_FAMILY, MAX_SIZE,
};
use combustion_spectra::BuiltinDielectric;

struct Image {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
}

impl Image {
    fn pixel(&self, x: usize, y: usize) -> [u8; 3] {
        let i = (y * self.width + x) * 3;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Pixels that are not the white background.
    fn ink(&self) -> usize {
        self.rgb
            .chunks_exact(3)
            .filter(|p| p.iter().any(|&c| c < 235))
            .count()
    }

    /// Pixels within `tolerance` of `colour` in every channel.
    fn count_colour(&self, colour: [u8; 3], tolerance: u8) -> usize {
        self.rgb
            .chunks_exact(3)
            .filter(|p| {
                p.iter()
                    .zip(colour)
                    .all(|(&a, b)| a.abs_diff(b) <= tolerance)
            })
            .count()
    }

    /// Dark (text-like) pixels in rows `rows`.
    fn dark_in_rows(&self, rows: std::ops::Range<usize>) -> usize {
        rows.flat_map(|y| (0..self.width).map(move |x| (x, y)))
            .filter(|&(x, y)| self.pixel(x, y).iter().all(|&c| c < 120))
            .count()
    }
}

/// Decodes with the `png` crate and checks the declared and requested size.
fn decode(png: &Png, width: u32, height: u32) -> Image {
    assert_eq!((png.width, png.height), (width, height));
    assert_eq!(&png.bytes[..8], b"\x89PNG\r\n\x1a\n");
    let decoder = png::Decoder::new(png.bytes.as_slice());
    let mut reader = decoder.read_info().expect("PNG header decodes");
    let mut rgb = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut rgb).expect("PNG data decodes");
    assert_eq!((info.width, info.height), (width, height));
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    rgb.truncate(info.buffer_size());
    Image {
        width: width as usize,
        height: height as usize,
        rgb,
    }
}

/// Not blank: a few percent of the pixels carry ink, and the title strip has text.
fn assert_has_content(image: &Image) {
    let total = image.width * image.height;
    let ink = image.ink();
    assert!(
        ink * 50 > total && ink * 2 < total,
        "{ink} of {total} pixels are not background"
    );
    let title = image.dark_in_rows(0..image.height * 7 / 100);
    assert!(title > 150, "title strip has only {title} dark pixels");
}

const RED: [u8; 3] = [214, 39, 40];
const GREEN: [u8; 3] = [44, 160, 44];
const BLUE: [u8; 3] = [31, 119, 180];

fn plot(
    material: PlotMaterial,
    outside_eta: f64,
    w: f64,
    width: u32,
    height: u32,
) -> ReflectancePlot {
    ReflectancePlot {
        material,
        outside_eta,
        polarisation_weight: w,
        width,
        height,
    }
}

#[test]
fn gold_reflectance_is_an_800x500_png_with_red_green_and_blue_curves() {
    let png = plot_reflectance(&ReflectancePlot::new(PlotMaterial::Metal(
        BuiltinMetal::Gold,
    )))
    .unwrap();
    let image = decode(&png, 800, 500);
    assert_has_content(&image);
    for (name, colour) in [("red", RED), ("green", GREEN), ("blue", BLUE)] {
        let n = image.count_colour(colour, 30);
        assert!(n > 500, "{n} pixels of the {name} channel's colour");
    }
}

#[test]
fn every_builtin_metal_plots_from_air_and_from_water() {
    for metal in BuiltinMetal::ALL {
        for outside_eta in [1.0, 1.33] {
            let p = plot(PlotMaterial::Metal(metal), outside_eta, 0.5, 400, 250);
            let png = plot_reflectance(&p).unwrap_or_else(|e| panic!("{metal:?}: {e}"));
            assert_has_content(&decode(&png, 400, 250));
        }
    }
}

#[test]
fn dielectric_with_total_internal_reflection_plots() {
    // Light inside water meeting air: θc = asin(1/1.33) = 48.8°.
    let p = plot(PlotMaterial::Dielectric { eta: 1.0 }, 1.33, 0.5, 800, 500);
    let image = decode(&plot_reflectance(&p).unwrap(), 800, 500);
    assert_has_content(&image);
    // A dielectric is drawn once, in near-black: no channel colours.
    assert!(image.count_colour(RED, 30) < 20);
    assert!(image.count_colour(BLUE, 30) < 20);
}

#[test]
fn glass_from_water_and_from_air_differ() {
    let glass = PlotMaterial::Dielectric { eta: 1.5 };
    let air = plot_reflectance(&plot(glass.clone(), 1.0, 0.5, 800, 500)).unwrap();
    let water = plot_reflectance(&plot(glass, 1.33, 0.5, 800, 500)).unwrap();
    assert_has_content(&decode(&air, 800, 500));
    assert_has_content(&decode(&water, 800, 500));
    assert_ne!(air.bytes, water.bytes);
}

#[test]
fn user_conductor_plots_at_an_odd_size_and_weight_changes_the_plot() {
    let material = PlotMaterial::Conductor {
        eta: [0.2, 0.9, 1.1],
        k: [3.9, 2.6, 2.5],
    };
    let s = plot_reflectance(&plot(material.clone(), 1.0, 0.0, 641, 333)).unwrap();
    let p = plot_reflectance(&plot(material.clone(), 1.0, 1.0, 641, 333)).unwrap();
    assert_has_content(&decode(&s, 641, 333));
    assert_has_content(&decode(&p, 641, 333));
    assert_ne!(s.bytes, p.bytes);
    // k = 0 on a channel with η < ηi: a dielectric channel with a critical angle.
    let tir = PlotMaterial::Conductor {
        eta: [1.2, 1.25, 1.3],
        k: [0.0, 0.0, 0.0],
    };
    assert_has_content(&decode(
        &plot_reflectance(&plot(tir, 1.33, 0.5, 800, 500)).unwrap(),
        800,
        500,
    ));
}

/// A user's table in the project's CSV format, spanning the RGB bands.
const USER_CSV: &str = "# a made-up metal\nwavelength_nm,n,k\n\
400,1.2,2.0\n450,1.1,2.2\n475,1.0,2.4\n500,0.9,2.6\n530,0.7,2.9\n570,0.5,3.1\n\
620,0.3,3.4\n680,0.25,3.7\n740,0.2,4.0\n800,0.2,4.3\n";

#[test]
fn user_spectral_csv_plots_as_reflectance_and_spectrum() {
    let spectrum = Spectrum::from_csv(USER_CSV).unwrap();
    let material = PlotMaterial::Spectral {
        name: "made-up metal".to_owned(),
        spectrum: spectrum.clone(),
    };
    let png = plot_reflectance(&plot(material, 1.0, 0.5, 800, 500)).unwrap();
    assert_has_content(&decode(&png, 800, 500));
    let png = plot_spectrum("made-up metal", &spectrum, 800, 500).unwrap();
    assert_has_content(&decode(&png, 800, 500));
}

#[test]
fn dielectric_family_is_a_png_of_the_requested_size() {
    let png = plot_dielectric_family(&FIGURE_12_ETAS, 1.0, 800, 500).unwrap();
    assert_has_content(&decode(&png, 800, 500));
    // From water: two of the four have a critical angle.
    let png = plot_dielectric_family(&[1.0, 1.2, 1.5, 2.0], 1.33, 1000, 620).unwrap();
    assert_has_content(&decode(&png, 1000, 620));
    // One curve, and the most curves allowed.
    let many: Vec<f64> = (0..MAX_FAMILY).map(|i| 1.1 + 0.2 * i as f64).collect();
    for etas in [&[2.0][..], &many[..]] {
        let png = plot_dielectric_family(etas, 1.0, 800, 500).unwrap();
        assert_has_content(&decode(&png, 800, 500));
    }
}

#[test]
fn spectrum_plot_shows_gold_with_its_three_bands() {
    let png = plot_spectrum(
        "gold (Au, McPeak et al. 2015)",
        BuiltinMetal::Gold.spectrum(),
        800,
        500,
    )
    .unwrap();
    let image = decode(&png, 800, 500);
    assert_has_content(&image);
    // The band-mean bars are drawn in the band colours.
    for (name, colour) in [("red", RED), ("green", GREEN), ("blue", BLUE)] {
        let n = image.count_colour(colour, 30);
        assert!(n > 300, "{n} pixels of the {name} band's colour");
    }
}

#[test]
fn spectrum_plot_handles_every_builtin_table() {
    for metal in BuiltinMetal::ALL {
        let png = plot_spectrum(metal.name(), metal.spectrum(), 400, 250).unwrap();
        assert_has_content(&decode(&png, 400, 250));
    }
    // Dielectrics: k is tiny (water ~1e-9) or zero-ish; the axis still works.
    for dielectric in BuiltinDielectric::ALL {
        let png = plot_spectrum(dielectric.name(), dielectric.spectrum(), 800, 500).unwrap();
        assert_has_content(&decode(&png, 800, 500));
    }
}

#[test]
fn plots_are_deterministic() {
    let a = plot_dielectric_family(&FIGURE_12_ETAS, 1.0, 300, 200).unwrap();
    let b = plot_dielectric_family(&FIGURE_12_ETAS, 1.0, 300, 200).unwrap();
    assert_eq!(a, b);
}

#[test]
fn tiny_and_extreme_sizes_never_panic() {
    let gold = PlotMaterial::Metal(BuiltinMetal::Gold);
    for (w, h) in [
        (1, 1),
        (2, 3),
        (17, 9),
        (60, 40),
        (MAX_SIZE, 2),
        (2, MAX_SIZE),
    ] {
        let png = plot_reflectance(&plot(gold.clone(), 1.0, 0.5, w, h)).unwrap();
        decode(&png, w, h);
        let png = plot_dielectric_family(&FIGURE_12_ETAS, 1.33, w, h).unwrap();
        decode(&png, w, h);
        let png = plot_spectrum("gold", BuiltinMetal::Gold.spectrum(), w, h).unwrap();
        decode(&png, w, h);
    }
}

fn assert_invalid_size(result: Result<Png, PlotError>, width: u32, height: u32) {
    match result {
        Err(PlotError::InvalidSize {
            width: w,
            height: h,
        }) => assert_eq!((w, h), (width, height)),
        other => panic!("{width}×{height}: expected InvalidSize, got {other:?}"),
    }
}

#[test]
fn sizes_of_zero_or_above_the_maximum_are_errors() {
    let gold = PlotMaterial::Metal(BuiltinMetal::Gold);
    for (w, h) in [
        (0, 500),
        (800, 0),
        (0, 0),
        (MAX_SIZE + 1, 500),
        (800, MAX_SIZE + 1),
        (u32::MAX, u32::MAX),
    ] {
        assert_invalid_size(plot_reflectance(&plot(gold.clone(), 1.0, 0.5, w, h)), w, h);
        assert_invalid_size(plot_dielectric_family(&FIGURE_12_ETAS, 1.0, w, h), w, h);
        assert_invalid_size(
            plot_spectrum("gold", BuiltinMetal::Gold.spectrum(), w, h),
            w,
            h,
        );
    }
}

fn assert_invalid_parameter(result: Result<Png, PlotError>, name: &str) {
    match result {
        Err(PlotError::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
        other => panic!("expected InvalidParameter {name}, got {other:?}"),
    }
}

const BAD_ETAS: [f64; 7] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -1.5,
    1e-9,
    1e9,
];

#[test]
fn bad_eta_k_outside_eta_and_weight_are_errors() {
    for bad in BAD_ETAS {
        let p = plot(PlotMaterial::Dielectric { eta: bad }, 1.0, 0.5, 800, 500);
        assert_invalid_parameter(plot_reflectance(&p), "η");
        let p = plot(PlotMaterial::Dielectric { eta: 1.5 }, bad, 0.5, 800, 500);
        assert_invalid_parameter(plot_reflectance(&p), "outside IOR");
        let p = plot(PlotMaterial::Metal(BuiltinMetal::Gold), bad, 0.5, 800, 500);
        assert_invalid_parameter(plot_reflectance(&p), "outside IOR");
        let conductor = PlotMaterial::Conductor {
            eta: [0.2, bad, 1.1],
            k: [3.9, 2.6, 2.5],
        };
        assert_invalid_parameter(
            plot_reflectance(&plot(conductor, 1.0, 0.5, 800, 500)),
            "η of the green band",
        );
    }
    for bad in [f64::NAN, f64::INFINITY, -0.1, -1e-300, 1e5] {
        let conductor = PlotMaterial::Conductor {
            eta: [0.2, 0.9, 1.1],
            k: [3.9, 2.6, bad],
        };
        assert_invalid_parameter(
            plot_reflectance(&plot(conductor, 1.0, 0.5, 800, 500)),
            "k of the blue band",
        );
    }
    for bad in [f64::NAN, -0.01, 1.01, f64::INFINITY] {
        let p = plot(PlotMaterial::Metal(BuiltinMetal::Gold), 1.0, bad, 800, 500);
        assert_invalid_parameter(plot_reflectance(&p), "polarisation weight");
    }
    // The edges of the ranges are accepted.
    for w in [0.0, 1.0] {
        plot_reflectance(&plot(
            PlotMaterial::Dielectric { eta: 1e4 },
            1e-4,
            w,
            200,
            100,
        ))
        .unwrap();
        plot_reflectance(&plot(
            PlotMaterial::Dielectric { eta: 1e-4 },
            1e4,
            w,
            200,
            100,
        ))
        .unwrap();
    }
}

#[test]
fn bad_dielectric_family_lists_are_errors() {
    assert!(matches!(
        plot_dielectric_family(&[], 1.0, 800, 500),
        Err(PlotError::EmptyEtaList)
    ));
    let too_many = vec![1.5; MAX_FAMILY + 1];
    assert!(matches!(
        plot_dielectric_family(&too_many, 1.0, 800, 500),
        Err(PlotError::TooManyCurves { count, max }) if count == MAX_FAMILY + 1 && max == MAX_FAMILY
    ));
    for bad in BAD_ETAS {
        assert_invalid_parameter(
            plot_dielectric_family(&[1.33, bad], 1.0, 800, 500),
            "η number 2",
        );
        assert_invalid_parameter(
            plot_dielectric_family(&[1.33], bad, 800, 500),
            "outside IOR",
        );
    }
}

#[test]
fn error_messages_name_the_problem() {
    let e = plot_dielectric_family(&[1.5], -1.0, 800, 500).unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid outside IOR -1: an index of refraction must be finite and > 0"
    );
    // A value far out of range is shown short, not as its 301 digits.
    let e = plot_dielectric_family(&[1e300], 1.0, 800, 500).unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid η number 1 1e300: an index of refraction must lie in [1e-4, 1e4], the range \
         the optics reference evaluates"
    );
    let e = plot_spectrum("gold", BuiltinMetal::Gold.spectrum(), 0, 10).unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid plot size 0×10: width and height must be 1–8192 pixels"
    );
}
