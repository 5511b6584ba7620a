//! A spectrum's n(λ) and k(λ) with the RGB bands and their band means (the rendering
//! notes' Figures 8 and 9 for gold).

use crate::canvas::{
    densify, place_legends, render, title_block, Glyph, LegendEntry, Root, Scale, BAND_COLOURS, INK,
};
use crate::{check_size, fmt_value, PlotError, Png};
use combustion_spectra::{rgb_optical_constants, RgbBand, Spectrum};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

type SpectrumCoords = Cartesian2d<RangedCoordf64, RangedCoordf64>;
type SpectrumChart<'a, 'b> = ChartContext<'a, BitMapBackend<'b>, SpectrumCoords>;

/// Colour of the measured samples and their interpolation.
const DATA_COLOUR: RGBColor = RGBColor(45, 45, 45);

/// Plots a tabulated spectrum's n (top panel) and k (bottom panel) against vacuum
/// wavelength: the measured samples as markers, the piecewise-linear interpolation the
/// renderer's band integrals use as a line, the RGB bands (Blue 450–495, Green 495–570,
/// Red 620–740 nm) as shaded spans, and the Gaussian-weighted band means of n and k
/// ([`rgb_optical_constants`], method (a)) as horizontal bars over each band with their
/// values. `name` goes into the title, e.g. `"gold (Au, McPeak et al. 2015)"`.
///
/// Errors: size 0 or above 8192 pixels.
pub fn plot_spectrum(
    name: &str,
    spectrum: &Spectrum,
    width: u32,
    height: u32,
) -> Result<Png, PlotError> {
    check_size(width, height)?;
    let constants = rgb_optical_constants(spectrum).map_err(|source| PlotError::Spectrum {
        name: name.to_owned(),
        source,
    })?;
    render(width, height, |root, s| {
        let samples = spectrum.samples();
        let (first, last) = spectrum.range_nm();
        let title = if name.trim().is_empty() {
            "Spectral optical constants n(λ) and k(λ)".to_owned()
        } else {
            format!("Spectral optical constants of {name}")
        };
        let subtitle = format!(
            "{} tabulated samples, {}–{} nm;  shaded: RGB bands;  bars: Gaussian-weighted band means",
            samples.len(),
            fmt_value(first),
            fmt_value(last)
        );
        let area = title_block(root, s, &title, &subtitle)?;
        let (_, height) = area.dim_in_pixel();
        let (top, bottom) = area.split_vertically(height * 46 / 100);
        let n: Vec<(f64, f64)> = samples.iter().map(|&(l, n, _)| (l, n)).collect();
        let k: Vec<(f64, f64)> = samples.iter().map(|&(l, _, k)| (l, k)).collect();
        let panel_n = Panel {
            values: &n,
            means: constants.eta,
            y_desc: "refractive index n",
            bottom: false,
        };
        let panel_k = Panel {
            values: &k,
            means: constants.k,
            y_desc: "extinction coeff. k",
            bottom: true,
        };
        let (chart_n, mut obstacles) = draw_panel(root, &top, s, (first, last), &panel_n)?;
        draw_panel(root, &bottom, s, (first, last), &panel_k)?;
        let entries = vec![
            LegendEntry::new(Glyph::Markers(DATA_COLOUR), "measured samples"),
            LegendEntry::new(Glyph::Line(DATA_COLOUR, 1.2), "linear interpolation"),
            LegendEntry::new(Glyph::BandSegments, "band mean (Gaussian-weighted)"),
        ];
        let (x, y) = chart_n.plotting_area().get_pixel_range();
        // Keep the legend clear of the band labels along the top.
        obstacles.extend((x.start..x.end).step_by(4).map(|px| (px, y.start + s.px(10.0))));
        place_legends(
            root,
            s,
            (x.start, y.start, x.end, y.end),
            vec![entries],
            &mut obstacles,
        )
    })
    .map(|(png, ())| png)
}

struct Panel<'v> {
    values: &'v [(f64, f64)],
    means: [f64; 3],
    y_desc: &'static str,
    bottom: bool,
}

fn tick_label(value: f64, span: f64) -> String {
    if span < 0.01 {
        if value == 0.0 {
            "0".to_owned()
        } else {
            format!("{value:.1e}")
        }
    } else if span < 0.1 {
        format!("{value:.3}")
    } else if span < 1.0 {
        format!("{value:.2}")
    } else {
        format!("{value:.1}")
    }
}

/// Draws one panel; returns its chart and obstacle pixels (curve, bars, value labels).
fn draw_panel<'a, 'b>(
    root: &Root<'b>,
    area: &'a Root<'b>,
    s: Scale,
    (first, last): (f64, f64),
    panel: &Panel<'_>,
) -> Result<(SpectrumChart<'a, 'b>, Vec<(i32, i32)>), PlotError> {
    let pad = 0.015 * (last - first);
    let x_range = (first - pad)..(last + pad);
    let max = panel
        .values
        .iter()
        .map(|p| p.1)
        .chain(panel.means)
        .fold(0.0, f64::max);
    let y_max = if max > 0.0 { max * 1.16 } else { 1.0 };
    let mut chart = ChartBuilder::on(area)
        .margin_left(s.px(6.0))
        .margin_right(s.px(22.0))
        .margin_top(s.px(4.0))
        .margin_bottom(s.px(if panel.bottom { 8.0 } else { 2.0 }))
        .x_label_area_size(s.px(if panel.bottom { 48.0 } else { 24.0 }))
        .y_label_area_size(s.px(62.0))
        .build_cartesian_2d(x_range, 0.0..y_max)?;

    // Shaded bands first, under the grid and the data.
    for band in RgbBand::ALL {
        let (lo, hi) = band.range_nm();
        chart.draw_series(std::iter::once(Rectangle::new(
            [(lo, 0.0), (hi, y_max)],
            BAND_COLOURS[band.index()].mix(0.11).filled(),
        )))?;
    }
    let y_formatter = |y: &f64| tick_label(*y, y_max);
    let mut mesh = chart.configure_mesh();
    mesh.y_desc(panel.y_desc)
        .x_labels(12)
        .y_labels(6)
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_label_formatter(&y_formatter)
        .label_style(s.font(14.0, &INK))
        .axis_desc_style(s.font(15.0, &INK))
        .bold_line_style(RGBColor(218, 218, 218).mix(0.8))
        .light_line_style(RGBColor(240, 240, 240).mix(0.6))
        .max_light_lines(1)
        .axis_style(INK.stroke_width(1))
        .set_all_tick_mark_size(s.px(4.0));
    if panel.bottom {
        mesh.x_desc("vacuum wavelength λ (nm)");
    }
    mesh.draw()?;

    // Band names along the top of the upper panel.
    if !panel.bottom {
        for band in RgbBand::ALL {
            let (lo, hi) = band.range_nm();
            let (x, y) = chart.backend_coord(&(0.5 * (lo + hi), y_max));
            root.draw(&Text::new(
                band.name(),
                (x, y + s.px(3.0)),
                s.font(14.0, &BAND_COLOURS[band.index()])
                    .pos(Pos::new(HPos::Center, VPos::Top)),
            ))?;
        }
    }

    let mut obstacles = Vec::new();
    // Samples: line, then markers sized to the sample spacing.
    chart.draw_series(LineSeries::new(
        panel.values.iter().copied(),
        DATA_COLOUR.stroke_width(s.stroke(1.2)),
    ))?;
    let px: Vec<(i32, i32)> = panel
        .values
        .iter()
        .map(|p| chart.backend_coord(p))
        .collect();
    let mut curve = Vec::new();
    densify(&px, s.px(2.0), &mut curve);
    obstacles.extend_from_slice(&curve);
    let spacing = px
        .windows(2)
        .map(|w| (w[1].0 - w[0].0).abs())
        .min()
        .unwrap_or(i32::MAX);
    // Dense tables (Pt: ~1.7 nm) get overlapping dots rather than invisible ones.
    let radius = (spacing * 2 / 5).clamp(s.px(1.6), s.px(3.0));
    chart.draw_series(
        panel
            .values
            .iter()
            .map(|&p| Circle::new(p, radius, DATA_COLOUR.filled())),
    )?;

    // Band means: a bar over each band and its value above it.
    for band in RgbBand::ALL {
        let (lo, hi) = band.range_nm();
        let mean = panel.means[band.index()];
        let colour = BAND_COLOURS[band.index()];
        chart.draw_series(LineSeries::new(
            [(lo, mean), (hi, mean)],
            colour.stroke_width(s.stroke(3.0)),
        ))?;
        let a = chart.backend_coord(&(lo, mean));
        let b = chart.backend_coord(&(hi, mean));
        densify(&[a, b], s.px(3.0), &mut obstacles);
        let text = fmt_value(mean);
        let style = s.font(14.0, &colour);
        let (w, h) = root
            .estimate_text_size(&text, &style)
            .map_or((0, 0), |(w, h)| (w as i32, h as i32));
        // Above or below the bar, centred or towards an end, wherever it hides the least
        // of the curve; never outside the panel.
        let (_, y_px) = chart.plotting_area().get_pixel_range();
        let gap = s.px(4.0);
        let half = w / 2 + s.px(2.0);
        let xs = [(a.0 + b.0) / 2, a.0 + half, b.0 - half];
        let ys = [a.1 - gap - h, a.1 + gap + s.px(1.0)];
        let mut best = (usize::MAX, xs[0], ys[0]);
        for y in ys {
            for x in xs {
                let inside_panel = y - s.px(1.0) > y_px.start && y + h + s.px(1.0) < y_px.end;
                let hidden = curve
                    .iter()
                    .filter(|&&(px, py)| {
                        px >= x - half && px <= x + half && py >= y - gap && py <= y + h + gap
                    })
                    .count();
                let score = if inside_panel { hidden } else { usize::MAX - 1 };
                if score < best.0 {
                    best = (score, x, y);
                }
            }
        }
        let (_, centre_x, top) = best;
        let rect = [
            (centre_x - half, top - s.px(1.0)),
            (centre_x + half, top + h + s.px(1.0)),
        ];
        root.draw(&Rectangle::new(rect, WHITE.mix(0.75).filled()))?;
        root.draw(&Text::new(
            text,
            (centre_x, top),
            style.pos(Pos::new(HPos::Center, VPos::Top)),
        ))?;
        densify(
            &[rect[0], (rect[1].0, rect[0].1)],
            s.px(3.0),
            &mut obstacles,
        );
        densify(
            &[(rect[0].0, rect[1].1), rect[1]],
            s.px(3.0),
            &mut obstacles,
        );
    }
    Ok((chart, obstacles))
}
