//! The RGB canvas every plot is drawn on, PNG encoding, size-dependent styling, and the
//! pieces shared by the plots: title block, legend, and the choice of a free corner for it.

use crate::{font, PlotError, Png, MAX_SIZE};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The drawing area of a whole image.
pub(crate) type Root<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// Background colour of every plot.
pub(crate) const BACKGROUND: RGBColor = WHITE;
/// Colour of text and axes.
pub(crate) const INK: RGBColor = RGBColor(25, 25, 25);
/// Colours of the RGB bands and channels, `[R, G, B]` (index = `RgbBand::index`).
pub(crate) const BAND_COLOURS: [RGBColor; 3] = [
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(31, 119, 180),
];
/// Colour of secondary text (subtitles, annotations).
pub(crate) const MUTED: RGBColor = RGBColor(90, 90, 90);

/// Checks a requested image size.
pub(crate) fn check_size(width: u32, height: u32) -> Result<(), PlotError> {
    if width == 0 || height == 0 || width > MAX_SIZE || height > MAX_SIZE {
        return Err(PlotError::InvalidSize { width, height });
    }
    Ok(())
}

/// Supersampling factor for an image of `width`×`height` pixels: plots are drawn at
/// twice the size and averaged down 2×2 (anti-aliased curves), up to 4 megapixels;
/// larger images are drawn directly.
pub(crate) fn supersampling(width: u32, height: u32) -> u32 {
    if u64::from(width) * u64::from(height) <= 4 * 1024 * 1024 {
        2
    } else {
        1
    }
}

/// Draws with `draw` on a white `width`×`height` RGB buffer (supersampled, see
/// [`supersampling`]) and encodes the result as PNG. Returns the PNG and whatever `draw`
/// returned; pixel coordinates seen by `draw` are supersampled ones.
pub(crate) fn render<T>(
    width: u32,
    height: u32,
    draw: impl FnOnce(&Root<'_>, Scale) -> Result<T, PlotError>,
) -> Result<(Png, T), PlotError> {
    check_size(width, height)?;
    font::ensure_registered()?;
    let factor = supersampling(width, height);
    let (big_w, big_h) = (width * factor, height * factor);
    let mut buffer = vec![0u8; big_w as usize * big_h as usize * 3];
    let value = {
        let root = BitMapBackend::with_buffer(&mut buffer, (big_w, big_h)).into_drawing_area();
        root.fill(&BACKGROUND)?;
        let scale = Scale::for_size(width, height);
        let value = draw(&root, Scale(scale.0 * f64::from(factor)))?;
        root.present()?;
        value
    };
    let rgb = downsample(&buffer, big_w as usize, big_h as usize, factor as usize);
    let bytes = encode_png(width, height, &rgb)?;
    Ok((
        Png {
            width,
            height,
            bytes,
        },
        value,
    ))
}

/// Box-filters an RGB image down by `factor` in each direction.
fn downsample(rgb: &[u8], width: usize, height: usize, factor: usize) -> Vec<u8> {
    if factor == 1 {
        return rgb.to_vec();
    }
    let (w, h) = (width / factor, height / factor);
    let n = (factor * factor) as u32;
    let mut out = vec![0u8; w * h * 3];
    for y in 0..h {
        for x in 0..w {
            for c in 0..3 {
                let mut sum = 0u32;
                for dy in 0..factor {
                    let row = (y * factor + dy) * width;
                    for dx in 0..factor {
                        sum += u32::from(rgb[(row + x * factor + dx) * 3 + c]);
                    }
                }
                out[(y * w + x) * 3 + c] = ((sum + n / 2) / n) as u8;
            }
        }
    }
    out
}

fn encode_png(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, PlotError> {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(rgb)?;
        writer.finish()?;
    }
    Ok(bytes)
}

/// Size-dependent lengths: the plots are designed at 800×500 and scaled from there.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scale(f64);

impl Scale {
    fn for_size(width: u32, height: u32) -> Scale {
        Scale((f64::from(width) / 800.0).min(f64::from(height) / 500.0))
    }

    /// A length of `design` pixels at 800×500, at least 1.
    pub(crate) fn px(self, design: f64) -> i32 {
        (design * self.0).round().max(1.0) as i32
    }

    /// Like [`Scale::px`], as `u32`.
    pub(crate) fn upx(self, design: f64) -> u32 {
        self.px(design) as u32
    }

    /// A font of about `design` pixels at 800×500, never below 8 pixels (legibility).
    ///
    /// The size is rounded to an even number of pixels: plotters' ab_glyph text drawing
    /// places each glyph at `size/2 + top` truncated to an integer, so an odd size puts
    /// short glyphs (`.`, `,`) one pixel above the baseline of tall ones.
    pub(crate) fn font(self, design: f64, colour: &RGBColor) -> TextStyle<'static> {
        let size = (2.0 * (design * self.0 / 2.0).round()).max(8.0);
        (font::FAMILY, size).into_font().color(colour)
    }

    /// A stroke width of `design` pixels at 800×500, at least 1.
    pub(crate) fn stroke(self, design: f64) -> u32 {
        self.upx(design)
    }
}

/// Title and subtitle centred in the top strip of `root`; returns the rest of the image.
pub(crate) fn title_block<'a>(
    root: &Root<'a>,
    scale: Scale,
    title: &str,
    subtitle: &str,
) -> Result<Root<'a>, PlotError> {
    let (width, _) = root.dim_in_pixel();
    let title_style = scale
        .font(22.0, &INK)
        .pos(Pos::new(HPos::Center, VPos::Top));
    let subtitle_style = scale
        .font(14.0, &MUTED)
        .pos(Pos::new(HPos::Center, VPos::Top));
    let centre = width as i32 / 2;
    root.draw(&Text::new(
        title.to_owned(),
        (centre, scale.px(8.0)),
        title_style,
    ))?;
    root.draw(&Text::new(
        subtitle.to_owned(),
        (centre, scale.px(36.0)),
        subtitle_style,
    ))?;
    let (_, rest) = root.split_vertically(scale.upx(58.0));
    Ok(rest)
}

/// How a legend entry's sample is drawn.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Glyph {
    /// Solid line of the given width (design pixels).
    Line(RGBColor, f64),
    /// Dashed line.
    Dashed(RGBColor, f64),
    /// Dotted line.
    Dotted(RGBColor, f64),
    /// Round markers only.
    Markers(RGBColor),
    /// Three short thick segments in the band colours (band means).
    BandSegments,
}

/// One line of a legend.
#[derive(Debug, Clone)]
pub(crate) struct LegendEntry {
    pub(crate) glyph: Glyph,
    pub(crate) label: String,
}

impl LegendEntry {
    pub(crate) fn new(glyph: Glyph, label: impl Into<String>) -> LegendEntry {
        LegendEntry {
            glyph,
            label: label.into(),
        }
    }
}

/// A legend laid out for drawing: entries, fonts and its size in pixels.
pub(crate) struct Legend {
    entries: Vec<LegendEntry>,
    scale: Scale,
    font_px: f64,
    width: i32,
    height: i32,
    row: i32,
    sample: i32,
    pad: i32,
}

impl Legend {
    pub(crate) fn new(root: &Root<'_>, scale: Scale, entries: Vec<LegendEntry>) -> Legend {
        let font_px = 14.0;
        let style = scale.font(font_px, &INK);
        let text_width = entries
            .iter()
            .map(|e| {
                root.estimate_text_size(&e.label, &style)
                    .map_or(0, |(w, _)| w as i32)
            })
            .max()
            .unwrap_or(0);
        let pad = scale.px(7.0);
        let sample = scale.px(34.0);
        let row = scale.px(19.0);
        let width = pad + sample + pad + text_width + pad;
        let height = pad + row * entries.len() as i32 + pad / 2;
        Legend {
            entries,
            scale,
            font_px,
            width,
            height,
            row,
            sample,
            pad,
        }
    }

    /// Size in pixels.
    pub(crate) fn size(&self) -> (i32, i32) {
        (self.width, self.height)
    }

    /// Draws the legend with its top-left corner at `at` (absolute pixels).
    pub(crate) fn draw(&self, root: &Root<'_>, at: (i32, i32)) -> Result<(), PlotError> {
        let (x0, y0) = at;
        let s = self.scale;
        root.draw(&Rectangle::new(
            [(x0, y0), (x0 + self.width, y0 + self.height)],
            BACKGROUND.mix(0.88).filled(),
        ))?;
        root.draw(&Rectangle::new(
            [(x0, y0), (x0 + self.width, y0 + self.height)],
            RGBColor(170, 170, 170).stroke_width(1),
        ))?;
        let text_style = s
            .font(self.font_px, &INK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        for (i, entry) in self.entries.iter().enumerate() {
            let y = y0 + self.pad + self.row * i as i32 + self.row / 2;
            let xa = x0 + self.pad;
            let xb = xa + self.sample;
            draw_glyph(root, s, entry.glyph, (xa, xb), y)?;
            root.draw(&Text::new(
                entry.label.clone(),
                (xb + self.pad, y),
                text_style.clone(),
            ))?;
        }
        Ok(())
    }
}

fn draw_glyph(
    root: &Root<'_>,
    s: Scale,
    glyph: Glyph,
    (xa, xb): (i32, i32),
    y: i32,
) -> Result<(), PlotError> {
    match glyph {
        Glyph::Line(colour, width) => {
            root.draw(&PathElement::new(
                vec![(xa, y), (xb, y)],
                colour.stroke_width(s.stroke(width)),
            ))?;
        }
        Glyph::Dashed(colour, width) => {
            // Whole dashes only: end on a dash, not on a sliver of one.
            let (dash, gap) = (s.px(DASH), s.px(DASH_GAP));
            let count = ((xb - xa + gap) / (dash + gap)).max(1);
            let xb = xa + count * (dash + gap) - gap;
            root.draw(&DashedPathElement::new(
                vec![(xa, y), (xb, y)],
                s.px(DASH),
                s.px(DASH_GAP),
                colour.stroke_width(s.stroke(width)),
            ))?;
        }
        Glyph::Dotted(colour, width) => {
            let spacing = s.px(DOT_SPACING);
            let mut x = xa + s.px(1.0);
            while x <= xb {
                root.draw(&Circle::new((x, y), dot_radius(s, width), colour.filled()))?;
                x += spacing;
            }
        }
        Glyph::Markers(colour) => {
            for x in [xa + s.px(5.0), (xa + xb) / 2, xb - s.px(5.0)] {
                root.draw(&Circle::new((x, y), s.px(2.6), colour.filled()))?;
            }
        }
        Glyph::BandSegments => {
            let third = (xb - xa) / 3;
            for (i, colour) in BAND_COLOURS.iter().rev().enumerate() {
                let x = xa + third * i as i32;
                root.draw(&PathElement::new(
                    vec![(x + s.px(1.0), y), (x + third - s.px(1.0), y)],
                    colour.stroke_width(s.stroke(3.0)),
                ))?;
            }
        }
    }
    Ok(())
}

/// Dash length of dashed curves, design pixels.
pub(crate) const DASH: f64 = 7.0;
/// Gap between dashes, design pixels.
pub(crate) const DASH_GAP: f64 = 4.0;
/// Distance between dots of dotted curves, design pixels.
pub(crate) const DOT_SPACING: f64 = 5.0;

/// Radius of the dots of a dotted curve of the given design width.
pub(crate) fn dot_radius(s: Scale, width: f64) -> i32 {
    ((width * 0.75) * s.0).round().max(1.0) as i32
}

/// Top-left corner for a box of `size` inside the rectangle `area` (absolute pixels,
/// `(left, top, right, bottom)`) that covers the fewest of `obstacles` (absolute pixels),
/// trying the corners first, then the edge middles; ties go to the earlier candidate.
pub(crate) fn free_spot(
    area: (i32, i32, i32, i32),
    size: (i32, i32),
    margin: i32,
    obstacles: &[(i32, i32)],
) -> (i32, i32) {
    let (left, top, right, bottom) = area;
    let (w, h) = size;
    let xs = [left + margin, right - margin - w, (left + right - w) / 2];
    let ys = [top + margin, bottom - margin - h, (top + bottom - h) / 2];
    let mut candidates = vec![
        (xs[0], ys[0]),
        (xs[1], ys[1]),
        (xs[0], ys[1]),
        (xs[1], ys[0]),
        (xs[2], ys[0]),
        (xs[2], ys[1]),
        (xs[0], ys[2]),
        (xs[1], ys[2]),
        (xs[2], ys[2]),
    ];
    // Then a grid of in-between positions, those nearest an edge first.
    const STEPS: i32 = 16;
    let mut grid: Vec<(i32, i32)> = (0..=STEPS)
        .flat_map(|i| {
            (0..=STEPS).map(move |j| {
                (
                    xs[0] + (xs[1] - xs[0]) * i / STEPS,
                    ys[0] + (ys[1] - ys[0]) * j / STEPS,
                )
            })
        })
        .collect();
    let edge_distance =
        |&(x, y): &(i32, i32)| (x - xs[0]).min(xs[1] - x).min(y - ys[0]).min(ys[1] - y);
    grid.sort_by_key(edge_distance);
    candidates.extend(grid);
    let pad = margin.max(2);
    let mut best = candidates[0];
    let mut best_count = usize::MAX;
    for (x, y) in candidates {
        let count = obstacles
            .iter()
            .filter(|&&(px, py)| {
                px >= x - pad && px <= x + w + pad && py >= y - pad && py <= y + h + pad
            })
            .count();
        if count < best_count {
            best = (x, y);
            best_count = count;
        }
    }
    best
}

/// Places and draws legends one after the other, each in the free spot of the plotting
/// area `area` that covers the fewest obstacles (curves, labels, legends placed before).
pub(crate) fn place_legends(
    root: &Root<'_>,
    s: Scale,
    area: (i32, i32, i32, i32),
    legends: Vec<Vec<LegendEntry>>,
    obstacles: &mut Vec<(i32, i32)>,
) -> Result<(), PlotError> {
    for entries in legends.into_iter().filter(|e| !e.is_empty()) {
        let legend = Legend::new(root, s, entries);
        let (w, h) = legend.size();
        let (x, y) = free_spot(area, (w, h), s.px(8.0), obstacles);
        legend.draw(root, (x, y))?;
        let step = s.px(4.0) as usize;
        for py in (y..=y + h).step_by(step) {
            obstacles.extend((x..=x + w).step_by(step).map(|px| (px, py)));
        }
    }
    Ok(())
}

/// The pixels along a polyline, at most `step` pixels apart (obstacles for
/// [`free_spot`]).
pub(crate) fn densify(points: &[(i32, i32)], step: i32, out: &mut Vec<(i32, i32)>) {
    let step = step.max(1);
    for pair in points.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let n = (dx.abs().max(dy.abs()) / step).max(1);
        for i in 0..n {
            out.push((a.0 + dx * i / n, a.1 + dy * i / n));
        }
    }
    if let Some(&last) = points.last() {
        out.push(last);
    }
}
