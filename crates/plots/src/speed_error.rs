//! Speed against error: one point per measured variant set (frame time against its
//! relative error to the f64 reference, log scale), with the Pareto front — the sets no
//! other set beats on both — drawn as a line through its points.

use crate::canvas::{render, title_block, Scale, INK, MUTED};
use crate::{PlotError, Png};
use plotters::prelude::*;

/// One measured variant set.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeedErrorPoint {
    /// Its name, written beside the point.
    pub label: String,
    /// Frame (or pass) time in milliseconds, > 0.
    pub ms: f64,
    /// Relative error against the reference, ≥ 0 (drawn at 1e-9 or above on the log axis).
    pub error: f64,
}

/// Errors within this fraction of each other count as equal for the front: variant sets
/// that differ only by f32 rounding (e.g. a specialised and a general pipeline) are not
/// told apart by noise in the last digits.
pub const PARETO_ERROR_TOLERANCE: f64 = 0.01;

/// The indices of the points on the Pareto front, fastest first: each is less wrong, by
/// more than [`PARETO_ERROR_TOLERANCE`], than the front's previous (faster) point, and
/// so than every faster point on the front (of equal times, the less wrong comes
/// first).
pub fn pareto_front(points: &[SpeedErrorPoint]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        points[a]
            .ms
            .total_cmp(&points[b].ms)
            .then(points[a].error.total_cmp(&points[b].error))
    });
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for i in order {
        if points[i].error < best * (1.0 - PARETO_ERROR_TOLERANCE) {
            best = points[i].error;
            front.push(i);
        }
    }
    front
}

/// Smallest error the log axis shows.
const ERROR_FLOOR: f64 = 1e-9;

/// The y axis of the variant sets' plot: the error [`plot_speed_vs_error`] shows.
pub const RELATIVE_ERROR_AXIS: &str = "mean relative error against the f64 reference";

/// The plot of `points` (at least one; every time finite and positive, every error
/// finite and not negative) at `width`×`height`, the x axis described by `x_desc` and
/// the (logarithmic) error axis by `y_desc` (e.g. [`RELATIVE_ERROR_AXIS`]).
pub fn plot_speed_vs_error(
    title: &str,
    subtitle: &str,
    x_desc: &str,
    y_desc: &str,
    points: &[SpeedErrorPoint],
    width: u32,
    height: u32,
) -> Result<Png, PlotError> {
    if points.is_empty() {
        return Err(PlotError::NoPoints);
    }
    for p in points {
        let reason = if !(p.ms.is_finite() && p.ms > 0.0) {
            format!("time {} ms is not a finite time above 0", p.ms)
        } else if !(p.error.is_finite() && p.error >= 0.0) {
            format!(
                "error {} is not a finite relative error of at least 0",
                p.error
            )
        } else {
            continue;
        };
        return Err(PlotError::InvalidPoint {
            label: p.label.clone(),
            reason,
        });
    }
    let front = pareto_front(points);
    render(width, height, |root, s: Scale| {
        let area = title_block(root, s, title, subtitle)?;
        let ms_max = points.iter().map(|p| p.ms).fold(0.0, f64::max);
        let ms_min = points.iter().map(|p| p.ms).fold(f64::INFINITY, f64::min);
        let errors = points.iter().map(|p| p.error.max(ERROR_FLOOR));
        let e_max = errors.clone().fold(0.0, f64::max);
        let e_min = errors.fold(f64::INFINITY, f64::min);
        let pad = 0.08 * (ms_max - ms_min).max(0.1 * ms_max);
        let x_range = (ms_min - pad).max(0.0)..(ms_max + pad);
        let y_range = (e_min / 3.0)..(e_max * 3.0);
        let mut chart = ChartBuilder::on(&area)
            .margin_left(s.px(6.0))
            // Room for the labels of the slowest points, written to their right.
            .margin_right(s.px(120.0))
            .margin_top(s.px(6.0))
            .margin_bottom(s.px(8.0))
            .x_label_area_size(s.px(48.0))
            .y_label_area_size(s.px(70.0))
            .build_cartesian_2d(x_range, y_range.log_scale())?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .axis_desc_style(s.font(15.0, &INK))
            .label_style(s.font(13.0, &INK))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .x_label_formatter(&|v| format!("{v:.0}"))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()?;
        let front_points: Vec<(f64, f64)> = front
            .iter()
            .map(|&i| (points[i].ms, points[i].error.max(ERROR_FLOOR)))
            .collect();
        let front_colour = RGBColor(214, 39, 40);
        chart.draw_series(LineSeries::new(
            front_points.clone(),
            ShapeStyle::from(&front_colour).stroke_width(s.stroke(1.6)),
        ))?;
        for (i, p) in points.iter().enumerate() {
            let on_front = front.contains(&i);
            let colour = if on_front { front_colour } else { MUTED };
            let at = (p.ms, p.error.max(ERROR_FLOOR));
            chart.draw_series(std::iter::once(Circle::new(
                at,
                s.px(if on_front { 5.0 } else { 4.0 }),
                ShapeStyle::from(&colour).filled(),
            )))?;
            chart.draw_series(std::iter::once(Text::new(
                p.label.clone(),
                at,
                s.font(12.0, &colour)
                    .pos(plotters::style::text_anchor::Pos::new(
                        plotters::style::text_anchor::HPos::Left,
                        plotters::style::text_anchor::VPos::Bottom,
                    )),
            )))?;
        }
        Ok(())
    })
    .map(|(png, ())| png)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(label: &str, ms: f64, error: f64) -> SpeedErrorPoint {
        SpeedErrorPoint {
            label: label.into(),
            ms,
            error,
        }
    }

    #[test]
    fn the_front_keeps_only_undominated_sets() {
        let points = [
            point("slow exact", 40.0, 1e-6),
            point("fast rough", 30.0, 1e-2),
            point("dominated", 41.0, 1e-5),
            point("middle", 35.0, 1e-4),
            point("tie slower", 35.0, 1e-3),
            point("rounding apart", 50.0, 0.999e-6),
        ];
        assert_eq!(pareto_front(&points), vec![1, 3, 0]);
    }

    #[test]
    fn plots_and_refuses_bad_points() {
        let points = [point("a", 40.0, 1e-6), point("b", 30.0, 0.0)];
        let png =
            plot_speed_vs_error("t", "s", "ms", RELATIVE_ERROR_AXIS, &points, 400, 250).unwrap();
        assert_eq!((png.width, png.height), (400, 250));
        assert!(plot_speed_vs_error("t", "s", "ms", RELATIVE_ERROR_AXIS, &[], 400, 250).is_err());
        let bad = [point("nan", f64::NAN, 1e-3)];
        assert!(plot_speed_vs_error("t", "s", "ms", RELATIVE_ERROR_AXIS, &bad, 400, 250).is_err());
        let negative = [point("neg", 10.0, -1.0)];
        assert!(
            plot_speed_vs_error("t", "s", "ms", RELATIVE_ERROR_AXIS, &negative, 400, 250).is_err()
        );
    }
}
