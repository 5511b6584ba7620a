//! Unit tests that need the crate's internals (the chart's coordinate mapping).

use super::*;
use crate::canvas::supersampling;
use crate::reflectance::{render_dielectric_family, FAMILY_COLOURS};
use combustion_optics::fresnel::fresnel_dielectric;
use plotters::coord::CoordTranslate;

#[test]
fn values_are_formatted_with_four_significant_digits() {
    assert_eq!(fmt_value(1.0), "1");
    assert_eq!(fmt_value(1.33), "1.33");
    assert_eq!(fmt_value(0.113_17), "0.1132");
    assert_eq!(fmt_value(4.0955), "4.096");
    assert_eq!(fmt_value(850.0), "850");
    assert_eq!(fmt_value(1.5e-9), "1.50e-9");
    assert_eq!(fmt_value(0.0), "0");
}

fn decode(png: &Png) -> (usize, usize, Vec<u8>) {
    let decoder = png::Decoder::new(png.bytes.as_slice());
    let mut reader = decoder.read_info().expect("PNG header");
    let mut rgb = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut rgb).expect("PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    (info.width as usize, info.height as usize, rgb)
}

/// In Figure 12 (ηi = 1), the η = 1.5 curve passes through R = 0.04 at 0° and through
/// the Fresnel values at 30°, 60° and 80°: the pixel column of each angle has a pixel of
/// that curve's colour within 2 rows of the row the chart's coordinate mapping gives for
/// R, and none of that colour farther than 4 rows away.
#[test]
fn figure_12_curve_for_glass_passes_through_its_fresnel_values() {
    let etas = FIGURE_12_ETAS;
    let index = etas.iter().position(|&e| e == 1.5).unwrap();
    let colour = FAMILY_COLOURS[index];
    let (width, height) = (800, 500);
    let (png, coords) = render_dielectric_family(&etas, 1.0, width, height).unwrap();
    let factor = supersampling(width, height) as i32;
    let (w, h, rgb) = decode(&png);
    assert_eq!((w, h), (800, 500));
    let is_curve = |x: usize, y: usize| {
        let p = &rgb[(y * w + x) * 3..(y * w + x) * 3 + 3];
        let target = [colour.0, colour.1, colour.2];
        p.iter().zip(target).all(|(&a, b)| a.abs_diff(b) <= 40)
    };
    for theta in [0.0_f64, 30.0, 60.0, 80.0] {
        let r = fresnel_dielectric(theta.to_radians().cos(), 1.0, 1.5).unpolarised();
        if theta == 0.0 {
            assert!((r - 0.04).abs() < 1e-12, "R(0°) = {r}");
        }
        let (sx, sy) = coords.translate(&(theta, r));
        // Supersampled pixel → output pixel (2×2 box filter).
        let (x, y) = ((sx / factor) as usize, (sy / factor) as usize);
        let rows: Vec<usize> = (0..h).filter(|&row| is_curve(x, row)).collect();
        assert!(
            rows.iter().any(|&row| row.abs_diff(y) <= 2),
            "θ = {theta}°: no curve pixel near row {y} (R = {r:.4}) in column {x}; curve rows {rows:?}"
        );
        assert!(
            rows.iter().all(|&row| row.abs_diff(y) <= 4),
            "θ = {theta}°: curve pixels far from row {y} in column {x}: {rows:?}"
        );
    }
}

/// The mapping the test above relies on: 0° is the left edge of the plotting area, R = 0
/// its bottom, and R grows upwards.
#[test]
fn figure_12_coordinate_mapping_is_oriented_as_drawn() {
    let (_, coords) = render_dielectric_family(&[1.5], 1.0, 800, 500).unwrap();
    let (x0, y0) = coords.translate(&(0.0, 0.0));
    let (x1, y1) = coords.translate(&(90.0, 1.0));
    let factor = supersampling(800, 500) as i32;
    assert!(x1 > x0 && y1 < y0, "({x0}, {y0}) → ({x1}, {y1})");
    assert!(x0 > 0 && x1 < 800 * factor && y1 > 0 && y0 < 500 * factor);
}
