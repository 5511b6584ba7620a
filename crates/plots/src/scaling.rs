//! Scaling: measured times against one quantity (pixels, light count), one line per
//! series, points marked. The x axis is linear or log₂ (for counts that double).

use crate::canvas::{render, title_block, Scale, INK};
use crate::{PlotError, Png};
use plotters::prelude::*;

/// One measured line: its name (in the legend) and its (x, y) points in x order.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// The legend's text.
    pub label: String,
    /// (x, y) pairs; every value finite, y ≥ 0, x > 0 on a log axis.
    pub points: Vec<(f64, f64)>,
}

/// The x axis of [`plot_scaling`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum XAxis {
    /// Linear, from 0.
    Linear,
    /// Log₂ (ticks at powers of two).
    Log2,
}

/// Line colours, in series order (a series beyond the last reuses them).
const SERIES_COLOURS: [RGBColor; 5] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
];

/// The plot of `series` (at least one point in all) at `width`×`height`.
#[allow(clippy::too_many_arguments)]
pub fn plot_scaling(
    title: &str,
    subtitle: &str,
    x_desc: &str,
    y_desc: &str,
    x_axis: XAxis,
    series: &[Series],
    width: u32,
    height: u32,
) -> Result<Png, PlotError> {
    let all = || series.iter().flat_map(|s| s.points.iter().copied());
    if all().next().is_none() {
        return Err(PlotError::NoPoints);
    }
    for s in series {
        for &(x, y) in &s.points {
            let reason = if !(x.is_finite() && (x > 0.0 || x_axis == XAxis::Linear)) {
                format!("x = {x} cannot be drawn on this axis")
            } else if !(y.is_finite() && y >= 0.0) {
                format!("y = {y} is not a finite value of at least 0")
            } else {
                continue;
            };
            return Err(PlotError::InvalidPoint {
                label: s.label.clone(),
                reason,
            });
        }
    }
    let x_max = all().map(|p| p.0).fold(f64::MIN, f64::max);
    let x_min = all().map(|p| p.0).fold(f64::MAX, f64::min);
    let y_max = all().map(|p| p.1).fold(0.0, f64::max).max(1e-9) * 1.08;
    render(width, height, |root, s: Scale| {
        let area = title_block(root, s, title, subtitle)?;
        let mut builder = ChartBuilder::on(&area);
        builder
            .margin_left(s.px(6.0))
            .margin_right(s.px(24.0))
            .margin_top(s.px(6.0))
            .margin_bottom(s.px(8.0))
            .x_label_area_size(s.px(48.0))
            .y_label_area_size(s.px(70.0));
        let style = |colour: RGBColor| ShapeStyle::from(&colour).stroke_width(s.stroke(1.6));
        // The two axes differ in type; the drawing after them is the same.
        macro_rules! draw {
            ($chart:expr, $x_format:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(x_desc)
                    .y_desc(y_desc)
                    .axis_desc_style(s.font(15.0, &INK))
                    .label_style(s.font(13.0, &INK))
                    .x_label_formatter($x_format)
                    .y_label_formatter(&|v| format!("{v:.0}"))
                    .light_line_style(RGBColor(235, 235, 235))
                    .bold_line_style(RGBColor(215, 215, 215))
                    .draw()?;
                for (i, line) in series.iter().enumerate() {
                    let colour = SERIES_COLOURS[i % SERIES_COLOURS.len()];
                    chart
                        .draw_series(LineSeries::new(line.points.clone(), style(colour)))?
                        .label(line.label.clone())
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], style(colour))
                        });
                    chart.draw_series(
                        line.points.iter().map(|&p| {
                            Circle::new(p, s.px(3.5), ShapeStyle::from(&colour).filled())
                        }),
                    )?;
                }
                chart
                    .configure_series_labels()
                    .position(SeriesLabelPosition::UpperLeft)
                    .label_font(s.font(13.0, &INK))
                    .background_style(WHITE.mix(0.85))
                    .border_style(RGBColor(200, 200, 200))
                    .draw()?;
            }};
        }
        match x_axis {
            XAxis::Linear => draw!(
                builder.build_cartesian_2d(0.0..x_max * 1.05, 0.0..y_max)?,
                &|v: &f64| format!("{v:.2}")
            ),
            XAxis::Log2 => draw!(
                builder.build_cartesian_2d(
                    (x_min / 1.3..x_max * 1.3).log_scale().base(2.0),
                    0.0..y_max
                )?,
                &|v: &f64| format!("{v:.0}")
            ),
        }
        Ok(())
    })
    .map(|(png, ())| png)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plots_both_axes_and_refuses_bad_points() {
        let series = [
            Series {
                label: "culled".into(),
                points: vec![(1.0, 30.0), (4.0, 31.0), (256.0, 90.0)],
            },
            Series {
                label: "every light".into(),
                points: vec![(1.0, 30.0), (4.0, 35.0), (256.0, 500.0)],
            },
        ];
        for axis in [XAxis::Linear, XAxis::Log2] {
            let png = plot_scaling("t", "s", "x", "ms", axis, &series, 400, 250).unwrap();
            assert_eq!((png.width, png.height), (400, 250));
        }
        assert!(plot_scaling("t", "s", "x", "ms", XAxis::Linear, &[], 400, 250).is_err());
        let zero_x = [Series {
            label: "zero".into(),
            points: vec![(0.0, 1.0)],
        }];
        assert!(plot_scaling("t", "s", "x", "ms", XAxis::Log2, &zero_x, 400, 250).is_err());
        assert!(plot_scaling("t", "s", "x", "ms", XAxis::Linear, &zero_x, 400, 250).is_ok());
        let nan_y = [Series {
            label: "nan".into(),
            points: vec![(1.0, f64::NAN)],
        }];
        assert!(plot_scaling("t", "s", "x", "ms", XAxis::Linear, &nan_y, 400, 250).is_err());
    }
}
