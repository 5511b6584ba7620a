//! Reflectance against angle of incidence: one material's Rs, Rp and R per RGB channel
//! ([`plot_reflectance`]), and unpolarised R for a family of dielectrics
//! ([`plot_dielectric_family`], the rendering notes' Figure 12).

use crate::canvas::{
    densify, dot_radius, place_legends, render, title_block, Glyph, LegendEntry, Root, Scale,
    BAND_COLOURS, DASH, DASH_GAP, DOT_SPACING, INK, MUTED,
};
use crate::{check_eta, check_k, check_size, check_weight, fmt_value, PlotError, Png};
use combustion_optics::fresnel::{fresnel_conductor, fresnel_dielectric, Polarised};
use combustion_spectra::{rgb_optical_constants, BuiltinMetal, RgbBand, Spectrum};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The material whose reflectance is plotted.
#[derive(Debug, Clone, PartialEq)]
pub enum PlotMaterial {
    /// A built-in metal: its RGB η, k are the band means of its measured spectrum
    /// ([`rgb_optical_constants`], method (a), what the renderer uses).
    Metal(BuiltinMetal),
    /// A dielectric of real index η (k = 0): total internal reflection past the critical
    /// angle when the outside index ηi exceeds η.
    Dielectric {
        /// Index of refraction ηt, finite and in [1e-4, 1e4].
        eta: f64,
    },
    /// A conductor given per RGB channel (`[R, G, B]`): η in [1e-4, 1e4], k in [0, 1e4].
    Conductor {
        /// Real part η per channel.
        eta: [f64; 3],
        /// Extinction coefficient k per channel.
        k: [f64; 3],
    },
    /// A tabulated spectrum (e.g. read with [`Spectrum::from_csv`]), reduced to RGB band
    /// means of η and k like a built-in metal.
    Spectral {
        /// Name printed in the title.
        name: String,
        /// The spectrum.
        spectrum: Spectrum,
    },
}

/// A reflectance-against-angle plot of one material.
#[derive(Debug, Clone, PartialEq)]
pub struct ReflectancePlot {
    /// The material seen through the outside medium.
    pub material: PlotMaterial,
    /// Real index ηi of the outside medium (1 for air or vacuum, 1.33 for water); > 0.
    pub outside_eta: f64,
    /// Polarisation weight w of the solid curve R = (1 − w) Rs + w Rp: 0 = s
    /// (perpendicular), 1 = p (parallel), ½ = unpolarised; in [0, 1].
    pub polarisation_weight: f64,
    /// Image width in pixels, 1–8192.
    pub width: u32,
    /// Image height in pixels, 1–8192.
    pub height: u32,
}

impl ReflectancePlot {
    /// An 800×500 plot of `material` seen from air (ηi = 1) with unpolarised light (w = ½).
    pub fn new(material: PlotMaterial) -> ReflectancePlot {
        ReflectancePlot {
            material,
            outside_eta: 1.0,
            polarisation_weight: 0.5,
            width: 800,
            height: 500,
        }
    }
}

/// Most curves [`plot_dielectric_family`] draws (one colour each).
pub const MAX_FAMILY: usize = 10;

/// Curve colours of the RGB channels, `[R, G, B]`.
const CHANNEL_COLOURS: [RGBColor; 3] = BAND_COLOURS;

/// Curve colour of a single-channel (dielectric) material.
const SINGLE_COLOUR: RGBColor = RGBColor(40, 40, 40);

/// Curve colours of [`plot_dielectric_family`], in the order of the η given.
pub(crate) const FAMILY_COLOURS: [RGBColor; MAX_FAMILY] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Width of the solid R curves, design pixels.
const R_WIDTH: f64 = 2.4;
/// Width of the dashed Rs and dotted Rp curves, design pixels.
const SP_WIDTH: f64 = 1.5;

/// The chart type every reflectance plot uses: θ in degrees × R.
pub(crate) type AngleCoords = Cartesian2d<RangedCoordf64, RangedCoordf64>;

/// One curve family to draw: a channel of a material.
struct Channel {
    colour: RGBColor,
    label: String,
    eta: f64,
    k: f64,
}

/// Rs and Rp of the interface from `outside_eta` into `eta + ik` at `cos_theta`.
fn polarised(cos_theta: f64, outside_eta: f64, eta: f64, k: f64) -> Polarised<f64> {
    if k == 0.0 {
        fresnel_dielectric(cos_theta, outside_eta, eta)
    } else {
        fresnel_conductor(cos_theta, outside_eta, eta, k)
    }
}

/// Critical angle (degrees) of total internal reflection, for a dielectric (k = 0) with
/// η < ηi.
fn critical_angle_deg(outside_eta: f64, eta: f64, k: f64) -> Option<f64> {
    (k == 0.0 && eta < outside_eta).then(|| (eta / outside_eta).asin().to_degrees())
}

/// Brewster's angle (degrees), where Rp = 0, for a dielectric (k = 0) with η ≠ ηi.
fn brewster_angle_deg(outside_eta: f64, eta: f64, k: f64) -> Option<f64> {
    (k == 0.0 && eta != outside_eta).then(|| (eta / outside_eta).atan().to_degrees())
}

/// Angles 0°, 0.1°, ..., 90° plus `extra` (kinks: critical angles), sorted.
fn angle_grid(extra: &[f64]) -> Vec<f64> {
    let mut angles: Vec<f64> = (0..=900).map(|i| f64::from(i) * 0.1).collect();
    angles.extend(extra.iter().copied().filter(|a| (0.0..=90.0).contains(a)));
    angles.sort_by(f64::total_cmp);
    angles.dedup();
    angles
}

/// (θ, Rs, Rp) along `angles`.
fn sweep(angles: &[f64], outside_eta: f64, eta: f64, k: f64) -> Vec<(f64, Polarised<f64>)> {
    angles
        .iter()
        .map(|&theta| {
            let cos = theta.to_radians().cos().clamp(0.0, 1.0);
            (theta, polarised(cos, outside_eta, eta, k))
        })
        .collect()
}

fn band_label(band: RgbBand) -> String {
    let (lo, hi) = band.range_nm();
    format!("{} {lo:.0}–{hi:.0} nm", band.name())
}

fn rgb_channels(eta: [f64; 3], k: [f64; 3]) -> Vec<Channel> {
    RgbBand::ALL
        .into_iter()
        .map(|band| {
            let c = band.index();
            Channel {
                colour: CHANNEL_COLOURS[c],
                label: format!(
                    "{}: η = {}, k = {}",
                    band_label(band),
                    fmt_value(eta[c]),
                    fmt_value(k[c])
                ),
                eta: eta[c],
                k: k[c],
            }
        })
        .collect()
}

/// Title, subtitle and channels of a material (validated).
fn describe(
    material: &PlotMaterial,
    outside_eta: f64,
) -> Result<(String, String, Vec<Channel>), PlotError> {
    let medium = format!("outside medium ηi = {}", fmt_value(outside_eta));
    Ok(match material {
        PlotMaterial::Metal(metal) => {
            let constants =
                rgb_optical_constants(metal.spectrum()).map_err(|source| PlotError::Spectrum {
                    name: metal.name().to_owned(),
                    source,
                })?;
            (
                format!(
                    "Fresnel reflectance of {} ({})",
                    metal.name(),
                    metal.symbol()
                ),
                format!(
                    "{medium};  η, k: band means of {} (method (a))",
                    metal.dataset()
                ),
                rgb_channels(constants.eta, constants.k),
            )
        }
        PlotMaterial::Dielectric { eta } => {
            check_eta("η".to_owned(), *eta)?;
            (
                format!(
                    "Fresnel reflectance of a dielectric, ηt = {}",
                    fmt_value(*eta)
                ),
                format!(
                    "{medium};  relative index ηt/ηi = {}",
                    fmt_value(eta / outside_eta)
                ),
                vec![Channel {
                    colour: SINGLE_COLOUR,
                    label: String::new(),
                    eta: *eta,
                    k: 0.0,
                }],
            )
        }
        PlotMaterial::Conductor { eta, k } => {
            for band in RgbBand::ALL {
                let c = band.index();
                check_eta(
                    format!("η of the {} band", band.to_string().to_lowercase()),
                    eta[c],
                )?;
                check_k(
                    format!("k of the {} band", band.to_string().to_lowercase()),
                    k[c],
                )?;
            }
            (
                "Fresnel reflectance of a conductor η + ik".to_owned(),
                format!("{medium};  η, k given per RGB channel"),
                rgb_channels(*eta, *k),
            )
        }
        PlotMaterial::Spectral { name, spectrum } => {
            let constants =
                rgb_optical_constants(spectrum).map_err(|source| PlotError::Spectrum {
                    name: name.clone(),
                    source,
                })?;
            (
                format!("Fresnel reflectance of {name}"),
                format!("{medium};  η, k: band means of the tabulated spectrum (method (a))"),
                rgb_channels(constants.eta, constants.k),
            )
        }
    })
}

/// A marked special angle: a vertical line and a label beside it.
struct AngleMark {
    theta: f64,
    colour: RGBColor,
    label: String,
    /// Label to the right of the line (else to the left).
    right: bool,
    /// Height of the label, in reflectance units.
    at_r: f64,
}

/// Builds the θ × R chart with its mesh and axis labels in `area`.
fn angle_chart<'a, 'b>(
    area: &'a Root<'b>,
    s: Scale,
) -> Result<ChartContext<'a, BitMapBackend<'b>, AngleCoords>, PlotError> {
    let mut chart = ChartBuilder::on(area)
        .margin_left(s.px(6.0))
        .margin_right(s.px(22.0))
        .margin_top(s.px(6.0))
        .margin_bottom(s.px(8.0))
        .x_label_area_size(s.px(48.0))
        .y_label_area_size(s.px(62.0))
        .build_cartesian_2d(0.0..90.0, 0.0..1.0)?;
    chart
        .configure_mesh()
        .x_desc("angle of incidence θ (degrees)")
        .y_desc("reflectance R")
        .x_labels(10)
        .y_labels(11)
        .x_label_formatter(&|x| format!("{x:.0}°"))
        .y_label_formatter(&|y| format!("{y:.1}"))
        .label_style(s.font(14.0, &INK))
        .axis_desc_style(s.font(16.0, &INK))
        .bold_line_style(RGBColor(218, 218, 218))
        .light_line_style(RGBColor(242, 242, 242))
        .max_light_lines(1)
        .axis_style(INK.stroke_width(1))
        .set_all_tick_mark_size(s.px(4.0))
        .draw()?;
    Ok(chart)
}

/// Pixel rectangle `(left, top, right, bottom)` of a chart's plotting area.
fn plot_rect(chart: &ChartContext<'_, BitMapBackend<'_>, AngleCoords>) -> (i32, i32, i32, i32) {
    let (x, y) = chart.plotting_area().get_pixel_range();
    (x.start, y.start, x.end, y.end)
}

/// A text label placed in absolute pixels, drawn after the curves on a light halo.
struct Label {
    text: String,
    colour: RGBColor,
    left_centre: (i32, i32),
    size: (i32, i32),
}

impl Label {
    fn draw(&self, root: &Root<'_>, s: Scale) -> Result<(), PlotError> {
        let (x, y) = self.left_centre;
        let (w, h) = self.size;
        let pad = s.px(2.0);
        root.draw(&Rectangle::new(
            [(x - pad, y - h / 2 - pad), (x + w + pad, y + h / 2 + pad)],
            WHITE.mix(0.7).filled(),
        ))?;
        root.draw(&Text::new(
            self.text.clone(),
            (x, y),
            s.font(14.0, &self.colour)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        Ok(())
    }

    /// Points covering the label, obstacles for the legends.
    fn obstacles(&self, out: &mut Vec<(i32, i32)>) {
        let (x, y) = self.left_centre;
        let (w, h) = self.size;
        for fx in 0..=6 {
            for fy in 0..=2 {
                out.push((x + w * fx / 6, y - h / 2 + h * fy / 2));
            }
        }
    }
}

/// Draws the marks' lines; returns their labels, to be drawn after the curves.
fn draw_angle_marks(
    root: &Root<'_>,
    chart: &mut ChartContext<'_, BitMapBackend<'_>, AngleCoords>,
    s: Scale,
    marks: &[AngleMark],
) -> Result<Vec<Label>, PlotError> {
    let mut labels = Vec::new();
    for mark in marks {
        chart.draw_series(DashedLineSeries::new(
            [(mark.theta, 0.0), (mark.theta, 1.0)],
            s.px(5.0),
            s.px(4.0),
            mark.colour.mix(0.8).stroke_width(s.stroke(1.0)),
        ))?;
        let (x, y) = chart.backend_coord(&(mark.theta, mark.at_r));
        let style = s.font(14.0, &mark.colour);
        let (w, h) = root
            .estimate_text_size(&mark.label, &style)
            .map_or((0, 0), |(w, h)| (w as i32, h as i32));
        let gap = s.px(5.0);
        let left = if mark.right { x + gap } else { x - gap - w };
        labels.push(Label {
            text: mark.label.clone(),
            colour: mark.colour,
            left_centre: (left, y),
            size: (w, h),
        });
    }
    Ok(labels)
}

/// "total internal reflection" over the region past the critical angle, if it fits.
fn tir_region_label(
    root: &Root<'_>,
    chart: &ChartContext<'_, BitMapBackend<'_>, AngleCoords>,
    s: Scale,
    critical_deg: f64,
) -> Option<Label> {
    let text = "total internal reflection";
    let style = s.font(14.0, &MUTED);
    let (w, h) = root
        .estimate_text_size(text, &style)
        .map_or((0, 0), |(w, h)| (w as i32, h as i32));
    let (xa, y) = chart.backend_coord(&(critical_deg, 1.0));
    let (xb, _) = chart.backend_coord(&(90.0, 1.0));
    (xb - xa >= w + s.px(12.0)).then(|| Label {
        text: text.to_owned(),
        colour: MUTED,
        left_centre: ((xa + xb - w) / 2, y + s.px(8.0) + h / 2),
        size: (w, h),
    })
}

/// Plots Rs (dashed), Rp (dotted) and R = (1 − w) Rs + w Rp (solid) against the angle of
/// incidence, 0–90°, per RGB channel (one curve colour per channel) for a metal,
/// conductor or spectrum, or once for a dielectric, seen from an outside medium of index
/// `outside_eta`. A dielectric's Brewster angle is marked, and so is its critical angle
/// when `outside_eta` > η (total internal reflection past it).
///
/// Errors: size 0 or above 8192 pixels, η outside [1e-4, 1e4] or not finite, k negative,
/// above 1e4 or not finite, ηi likewise, weight outside [0, 1].
pub fn plot_reflectance(plot: &ReflectancePlot) -> Result<Png, PlotError> {
    check_size(plot.width, plot.height)?;
    check_eta("outside IOR".to_owned(), plot.outside_eta)?;
    check_weight(plot.polarisation_weight)?;
    let (title, subtitle, channels) = describe(&plot.material, plot.outside_eta)?;
    render(plot.width, plot.height, |root, s| {
        draw_reflectance(root, s, plot, &title, &subtitle, &channels)
    })
    .map(|(png, ())| png)
}

fn weighted_label(w: f64) -> String {
    if w == 0.5 {
        "R = ½(Rₛ + Rₚ), unpolarised".to_owned()
    } else if w == 0.0 {
        "R = Rₛ (s-polarised light)".to_owned()
    } else if w == 1.0 {
        "R = Rₚ (p-polarised light)".to_owned()
    } else {
        format!("R = {:.2}·Rₛ + {:.2}·Rₚ", 1.0 - w, w)
    }
}

fn draw_reflectance(
    root: &Root<'_>,
    s: Scale,
    plot: &ReflectancePlot,
    title: &str,
    subtitle: &str,
    channels: &[Channel],
) -> Result<(), PlotError> {
    let outside = plot.outside_eta;
    let w = plot.polarisation_weight;
    let area = title_block(root, s, title, subtitle)?;
    let mut chart = angle_chart(&area, s)?;

    // Special angles of the dielectric channels, one mark per distinct angle.
    let mut marks: Vec<AngleMark> = Vec::new();
    let mut critical: Vec<f64> = Vec::new();
    let single = channels.len() == 1;
    for channel in channels {
        let colour = if single { MUTED } else { channel.colour };
        if let Some(theta) = critical_angle_deg(outside, channel.eta, channel.k) {
            if !critical.iter().any(|&c| (c - theta).abs() < 1e-9) {
                critical.push(theta);
                marks.push(AngleMark {
                    theta,
                    colour,
                    label: format!("θc = {theta:.1}°"),
                    right: true,
                    at_r: 0.55 - 0.08 * (critical.len() - 1) as f64,
                });
            }
        }
    }
    let mut brewster_count = 0;
    for channel in channels {
        let colour = if single { MUTED } else { channel.colour };
        if let Some(theta) = brewster_angle_deg(outside, channel.eta, channel.k) {
            if !marks.iter().any(|m| (m.theta - theta).abs() < 1e-9) {
                brewster_count += 1;
                marks.push(AngleMark {
                    theta,
                    colour,
                    label: format!("θB = {theta:.1}° (Rₚ = 0)"),
                    right: false,
                    at_r: 0.45 - 0.08 * (brewster_count - 1) as f64,
                });
            }
        }
    }
    let mut labels = draw_angle_marks(root, &mut chart, s, &marks)?;
    if let [theta] = critical[..] {
        labels.extend(tir_region_label(root, &chart, s, theta));
    }
    let mut obstacles = Vec::new();

    let angles = angle_grid(&critical);
    let radius = dot_radius(s, SP_WIDTH);
    for channel in channels {
        let data = sweep(&angles, outside, channel.eta, channel.k);
        let colour = channel.colour;
        chart.draw_series(DashedLineSeries::new(
            data.iter().map(|(t, r)| (*t, r.s)),
            s.px(DASH),
            s.px(DASH_GAP),
            colour.stroke_width(s.stroke(SP_WIDTH)),
        ))?;
        chart.draw_series(DottedLineSeries::new(
            data.iter().map(|(t, r)| (*t, r.p)).collect::<Vec<_>>(),
            0,
            s.px(DOT_SPACING),
            move |c| Circle::new(c, radius, colour.filled()),
        ))?;
        chart.draw_series(LineSeries::new(
            data.iter().map(|(t, r)| (*t, r.weighted(w))),
            colour.stroke_width(s.stroke(R_WIDTH)),
        ))?;
        for select in [
            |r: &Polarised<f64>, _| r.s,
            |r: &Polarised<f64>, _| r.p,
            |r: &Polarised<f64>, w| r.weighted(w),
        ] {
            let px: Vec<(i32, i32)> = data
                .iter()
                .map(|(t, r)| chart.backend_coord(&(*t, select(r, w))))
                .collect();
            densify(&px, s.px(3.0), &mut obstacles);
        }
    }

    for label in &labels {
        label.draw(root, s)?;
        label.obstacles(&mut obstacles);
    }
    let style_colour = if single { SINGLE_COLOUR } else { INK };
    let channel_entries: Vec<LegendEntry> = channels
        .iter()
        .filter(|c| !c.label.is_empty())
        .map(|c| LegendEntry::new(Glyph::Line(c.colour, R_WIDTH), c.label.clone()))
        .collect();
    let style_entries = vec![
        LegendEntry::new(Glyph::Line(style_colour, R_WIDTH), weighted_label(w)),
        LegendEntry::new(
            Glyph::Dashed(style_colour, SP_WIDTH),
            "Rₛ: s-polarised (perpendicular)",
        ),
        LegendEntry::new(
            Glyph::Dotted(style_colour, SP_WIDTH),
            "Rₚ: p-polarised (parallel)",
        ),
    ];
    place_legends(
        root,
        s,
        plot_rect(&chart),
        vec![channel_entries, style_entries],
        &mut obstacles,
    )
}

/// Plots the unpolarised reflectance R = ½(Rs + Rp) against the angle of incidence for
/// dielectrics of index ηt = each of `etas` seen from an outside medium of index
/// `outside_eta` (the rendering notes' Figure 12 with `etas` = 1.1, 1.33, 1.5, 1.8, 2.4,
/// 3.0 and ηi = 1). A critical angle (ηt < ηi) is marked in its curve's colour.
///
/// Errors: empty `etas` or more than [`MAX_FAMILY`], an η or ηi outside [1e-4, 1e4] or
/// not finite, size 0 or above 8192 pixels.
pub fn plot_dielectric_family(
    etas: &[f64],
    outside_eta: f64,
    width: u32,
    height: u32,
) -> Result<Png, PlotError> {
    render_dielectric_family(etas, outside_eta, width, height).map(|(png, _)| png)
}

/// [`plot_dielectric_family`], also returning the chart's coordinate mapping (data →
/// absolute pixel), for tests.
pub(crate) fn render_dielectric_family(
    etas: &[f64],
    outside_eta: f64,
    width: u32,
    height: u32,
) -> Result<(Png, AngleCoords), PlotError> {
    check_size(width, height)?;
    check_eta("outside IOR".to_owned(), outside_eta)?;
    if etas.is_empty() {
        return Err(PlotError::EmptyEtaList);
    }
    if etas.len() > MAX_FAMILY {
        return Err(PlotError::TooManyCurves {
            count: etas.len(),
            max: MAX_FAMILY,
        });
    }
    for (i, &eta) in etas.iter().enumerate() {
        check_eta(format!("η number {}", i + 1), eta)?;
    }
    render(width, height, |root, s| {
        draw_family(root, s, etas, outside_eta)
    })
}

fn draw_family(
    root: &Root<'_>,
    s: Scale,
    etas: &[f64],
    outside: f64,
) -> Result<AngleCoords, PlotError> {
    let area = title_block(
        root,
        s,
        "Dielectric Fresnel reflectance for various ηt",
        &format!(
            "unpolarised light, R = ½(Rₛ + Rₚ);  outside medium ηi = {}",
            fmt_value(outside)
        ),
    )?;
    let mut chart = angle_chart(&area, s)?;
    let critical: Vec<f64> = etas
        .iter()
        .filter_map(|&eta| critical_angle_deg(outside, eta, 0.0))
        .collect();
    let mut marks = Vec::new();
    for (i, &eta) in etas.iter().enumerate() {
        if let Some(theta) = critical_angle_deg(outside, eta, 0.0) {
            marks.push(AngleMark {
                theta,
                colour: FAMILY_COLOURS[i],
                label: format!("θc = {theta:.1}°"),
                right: true,
                at_r: 0.55 - 0.07 * marks.len() as f64,
            });
        }
    }
    let labels = draw_angle_marks(root, &mut chart, s, &marks)?;
    let mut obstacles = Vec::new();
    let angles = angle_grid(&critical);
    let mut entries = Vec::new();
    for (i, &eta) in etas.iter().enumerate() {
        let colour = FAMILY_COLOURS[i];
        let data: Vec<(f64, f64)> = sweep(&angles, outside, eta, 0.0)
            .into_iter()
            .map(|(t, r)| (t, r.unpolarised()))
            .collect();
        chart.draw_series(LineSeries::new(
            data.iter().copied(),
            colour.stroke_width(s.stroke(R_WIDTH)),
        ))?;
        let px: Vec<(i32, i32)> = data.iter().map(|p| chart.backend_coord(p)).collect();
        densify(&px, s.px(3.0), &mut obstacles);
        let r0 = data.first().map_or(f64::NAN, |p| p.1);
        let mut label = format!("ηt = {}: R(0°) = {r0:.3}", fmt_value(eta));
        if let Some(theta) = brewster_angle_deg(outside, eta, 0.0) {
            label.push_str(&format!(", θB = {theta:.1}°"));
        }
        if let Some(theta) = critical_angle_deg(outside, eta, 0.0) {
            label.push_str(&format!(", θc = {theta:.1}°"));
        }
        entries.push(LegendEntry::new(Glyph::Line(colour, R_WIDTH), label));
    }
    for label in &labels {
        label.draw(root, s)?;
        label.obstacles(&mut obstacles);
    }
    place_legends(root, s, plot_rect(&chart), vec![entries], &mut obstacles)?;
    Ok(chart.as_coord_spec().clone())
}
