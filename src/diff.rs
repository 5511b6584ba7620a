//! `combustion diff A B` and batch goldens: the comparison itself is the
//! combustion-diff crate, re-exported here whole (a crate of its own so that its image
//! readers are fuzzed without the renderer); the heat map's legend, lettered with the
//! overlay's font, is drawn here.

pub use combustion_diff::*;

/// Rows of the heat map's legend ([`heat_map_with_legend`]): the colour bar, then the
/// band its labels stand in.
pub const LEGEND_BAR_ROWS: u32 = 16;
/// See [`LEGEND_BAR_ROWS`].
pub const LEGEND_LABEL_ROWS: u32 = 46;

/// [`heat_map`] with a legend below it: a bar of the colour map from FLIP 0 at the left
/// to 1 at the right ([`LEGEND_BAR_ROWS`] rows, the map's colour at each column's
/// centre), and under it, on black, its ends' labels ([`LEGEND_LABEL_ROWS`] rows, the
/// overlay's font; shortened to `FLIP 0` and `1` below 300 pixels of width). Returns the image's height and its RGBA pixels, `comparison.width`
/// wide.
pub fn heat_map_with_legend(comparison: &Comparison) -> Result<(u32, Vec<[u8; 4]>), String> {
    use crate::renderer::overlay::OverlayFont;
    use crate::renderer::{Corner, OverlayPanel};
    let width = comparison.width;
    let mut pixels = heat_map(comparison);
    let lut = nv_flip::magma_lut().to_vec();
    let colour_at = |x: u32| {
        let t = (f64::from(x) + 0.5) / f64::from(width.max(1));
        let i = ((t * 255.0).round() as usize).min(255);
        [lut[3 * i], lut[3 * i + 1], lut[3 * i + 2], 255]
    };
    for _ in 0..LEGEND_BAR_ROWS {
        pixels.extend((0..width).map(colour_at));
    }
    let font = OverlayFont::new().map_err(|e| e.to_string())?;
    // Short labels where the long ones would not fit side by side.
    let (low, high) = if width >= 300 {
        ("FLIP 0: the same", "1: most different")
    } else {
        ("FLIP 0", "1")
    };
    let panels = [
        OverlayPanel {
            text: low,
            corner: Corner::BottomLeft,
        },
        OverlayPanel {
            text: high,
            corner: Corner::BottomRight,
        },
    ];
    let quads = font.layout(&panels, [width, LEGEND_LABEL_ROWS], None);
    for y in 0..LEGEND_LABEL_ROWS {
        for x in 0..width {
            let rgba = font.composite_unorm8(&quads, None, x, y, [0, 0, 0, 255]);
            pixels.push(rgba.map(|c| (c * 255.0).round() as u8));
        }
    }
    Ok((
        comparison.height + LEGEND_BAR_ROWS + LEGEND_LABEL_ROWS,
        pixels,
    ))
}
