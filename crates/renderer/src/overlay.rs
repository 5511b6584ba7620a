//! Text drawn over a frame by the renderer: panels of lines in the corners of the target
//! (statistics, help), blended onto the output in the output pass.
//!
//! The font is DejaVu Sans (`assets/fonts/`, embedded), rasterised once into a coverage
//! atlas with `ab_glyph` when the renderer is made. A frame's panels are laid out on the
//! CPU into quads (a background rectangle per panel, one quad per glyph, on whole pixels)
//! written to the frame slot's quad buffer; `overlay.vert`/`overlay.frag` draw them with
//! one instanced draw, reading the atlas with exact texel lookups (no filtering, so a
//! glyph's pixels are its rasterised coverage, blended with its colour's alpha).

use std::collections::HashMap;
use std::sync::Arc;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use combustion_vk::{
    vk, DescriptorSetLayout, Device, Pipeline, PipelineCache, PipelineLayout, ShaderCompiler,
};

use crate::error::RenderError;

/// DejaVu Sans 2.37 (see `assets/fonts/README.md` for its source and licence).
static FONT_BYTES: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// The text size in pixels (ascent to descent).
pub const OVERLAY_TEXT_PX: f32 = 15.0;

/// Characters the atlas holds besides printable ASCII; any other is drawn as `?`.
const EXTRA_CHARACTERS: &str = "×·µ±–—…≤≥°ηκσαθλ²³⁻¹";

/// Atlas width in texels (rows of glyphs; the height follows).
const ATLAS_WIDTH: u32 = 512;

/// Space between a panel's edge and its text, and between a panel and the target's edge.
const PANEL_PADDING: f32 = 6.0;
const PANEL_MARGIN: f32 = 8.0;
/// Space between columns of a tab-separated panel.
const COLUMN_GAP: f32 = 14.0;

/// The corner of the target a panel is placed in. Panels in one corner are stacked
/// away from it in the order given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corner {
    /// The target's top-left corner.
    TopLeft,
    /// The target's top-right corner.
    TopRight,
    /// The target's bottom-left corner.
    BottomLeft,
    /// The target's bottom-right corner.
    BottomRight,
}

/// A block of text over a translucent dark background. Lines are separated by `\n`;
/// within a line, `\t` separates columns, aligned across the panel's lines (for tables
/// such as a list of keys).
#[derive(Clone, Copy, Debug)]
pub struct OverlayPanel<'a> {
    /// The panel's text (`\n` between lines, `\t` between columns).
    pub text: &'a str,
    /// The corner it is placed in.
    pub corner: Corner,
}

/// One quad of the overlay, as `overlay.glsl` declares it (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct OverlayQuad {
    /// Target pixels: x0, y0, x1, y1 (whole pixels; y down).
    pub rect: [f32; 4],
    /// The atlas texel at the quad's top-left corner (x, y), and 0 for a glyph, 1 for a
    /// solid quad (no lookup), 2 for the overlay image (x, y its texel there).
    pub atlas: [f32; 4],
    /// Colour (sRGB-encoded, as displayed) and opacity.
    pub color: [f32; 4],
}

/// The colour of text and of panel backgrounds.
const TEXT_COLOR: [f32; 4] = [1.0, 1.0, 1.0, 1.0];
const PANEL_COLOR: [f32; 4] = [0.0, 0.0, 0.0, 0.68];

#[derive(Clone, Copy, Debug)]
struct Glyph {
    /// Top-left texel in the atlas.
    atlas: [u32; 2],
    size: [u32; 2],
    /// From the pen position on the baseline to the bitmap's top-left corner.
    offset: [i32; 2],
    advance: f32,
}

/// The rasterised font: a coverage atlas (one byte per texel) and each glyph's place.
pub struct OverlayFont {
    atlas: Vec<u8>,
    height: u32,
    glyphs: HashMap<char, Glyph>,
    ascent: f32,
    line_height: f32,
}

impl OverlayFont {
    /// Rasterises printable ASCII and a few symbols at [`OVERLAY_TEXT_PX`].
    pub fn new() -> Result<Self, RenderError> {
        let font = FontRef::try_from_slice(FONT_BYTES)
            .map_err(|e| RenderError::Overlay(format!("the embedded font: {e}")))?;
        let scale = PxScale::from(OVERLAY_TEXT_PX);
        let scaled = font.as_scaled(scale);
        let characters: Vec<char> = (' '..='~').chain(EXTRA_CHARACTERS.chars()).collect();
        let mut glyphs = HashMap::new();
        let mut bitmaps = Vec::new();
        let (mut x, mut y, mut row_height) = (0u32, 0u32, 0u32);
        for c in characters {
            let id = font.glyph_id(c);
            let advance = scaled.h_advance(id);
            let outlined = font.outline_glyph(id.with_scale_and_position(scale, (0.0, 0.0)));
            let (size, offset, coverage) = match outlined {
                Some(outlined) => {
                    let bounds = outlined.px_bounds();
                    let size = [bounds.width() as u32, bounds.height() as u32];
                    let mut coverage = vec![0u8; (size[0] * size[1]) as usize];
                    outlined.draw(|gx, gy, c| {
                        if gx < size[0] && gy < size[1] {
                            coverage[(gy * size[0] + gx) as usize] =
                                (c.clamp(0.0, 1.0) * 255.0).round() as u8;
                        }
                    });
                    (size, [bounds.min.x as i32, bounds.min.y as i32], coverage)
                }
                // Spaces have an advance and no outline.
                None => ([0, 0], [0, 0], Vec::new()),
            };
            if x + size[0] + 1 > ATLAS_WIDTH {
                (x, y, row_height) = (0, y + row_height + 1, 0);
            }
            glyphs.insert(
                c,
                Glyph {
                    atlas: [x, y],
                    size,
                    offset,
                    advance,
                },
            );
            bitmaps.push(([x, y], size, coverage));
            x += size[0] + 1;
            row_height = row_height.max(size[1]);
        }
        let height = y + row_height + 1;
        let mut atlas = vec![0u8; (ATLAS_WIDTH * height) as usize];
        for ([x0, y0], [w, h], coverage) in bitmaps {
            for row in 0..h {
                let start = ((y0 + row) * ATLAS_WIDTH + x0) as usize;
                atlas[start..start + w as usize]
                    .copy_from_slice(&coverage[(row * w) as usize..((row + 1) * w) as usize]);
            }
        }
        Ok(Self {
            atlas,
            height,
            glyphs,
            ascent: scaled.ascent(),
            line_height: (scaled.ascent() - scaled.descent() + scaled.line_gap()).ceil(),
        })
    }

    /// The atlas's texels, one byte each, rows of [`OverlayFont::atlas_width`].
    pub fn atlas(&self) -> &[u8] {
        &self.atlas
    }

    /// The atlas's width in texels.
    pub fn atlas_width(&self) -> u32 {
        ATLAS_WIDTH
    }

    /// The atlas's height in texels (rows).
    pub fn atlas_height(&self) -> u32 {
        self.height
    }

    fn glyph(&self, c: char) -> Glyph {
        self.glyphs
            .get(&c)
            .or_else(|| self.glyphs.get(&'?'))
            .copied()
            .expect("the atlas holds '?'")
    }

    fn text_width(&self, text: &str) -> f32 {
        text.chars().map(|c| self.glyph(c).advance).sum()
    }

    /// The quads of `panels` on a target of `extent` pixels: the overlay image of
    /// `image` texels first (at the top-left, one texel a pixel), then per panel its
    /// background and its glyphs.
    pub fn layout(
        &self,
        panels: &[OverlayPanel<'_>],
        extent: [u32; 2],
        image: Option<[u32; 2]>,
    ) -> Vec<OverlayQuad> {
        let mut quads = Vec::new();
        if let Some([w, h]) = image {
            quads.push(OverlayQuad {
                rect: [0.0, 0.0, w as f32, h as f32],
                atlas: [0.0, 0.0, 2.0, 0.0],
                color: [1.0; 4],
            });
        }
        // How far each corner's stack of panels reaches from its edge.
        let mut stacked = [0.0f32; 4];
        for panel in panels {
            let lines: Vec<Vec<&str>> = panel
                .text
                .lines()
                .map(|line| line.split('\t').collect())
                .collect();
            let columns = lines.iter().map(Vec::len).max().unwrap_or(0);
            let mut column_widths = vec![0.0f32; columns];
            for line in &lines {
                for (i, cell) in line.iter().enumerate() {
                    column_widths[i] = column_widths[i].max(self.text_width(cell).ceil());
                }
            }
            let text_width =
                column_widths.iter().sum::<f32>() + COLUMN_GAP * columns.saturating_sub(1) as f32;
            let width = text_width + 2.0 * PANEL_PADDING;
            let height = self.line_height * lines.len() as f32 + 2.0 * PANEL_PADDING;
            let corner = panel.corner as usize;
            let (w, h) = (extent[0] as f32, extent[1] as f32);
            let x0 = match panel.corner {
                Corner::TopLeft | Corner::BottomLeft => PANEL_MARGIN,
                Corner::TopRight | Corner::BottomRight => w - PANEL_MARGIN - width,
            };
            let y0 = match panel.corner {
                Corner::TopLeft | Corner::TopRight => PANEL_MARGIN + stacked[corner],
                Corner::BottomLeft | Corner::BottomRight => {
                    h - PANEL_MARGIN - stacked[corner] - height
                }
            };
            stacked[corner] += height + PANEL_MARGIN;
            let (x0, y0) = (x0.round(), y0.round());
            quads.push(OverlayQuad {
                rect: [x0, y0, x0 + width, y0 + height],
                atlas: [0.0, 0.0, 1.0, 0.0],
                color: PANEL_COLOR,
            });
            for (row, line) in lines.iter().enumerate() {
                let baseline =
                    (y0 + PANEL_PADDING + self.line_height * row as f32 + self.ascent).round();
                let mut column_x = x0 + PANEL_PADDING;
                for (cell, column_width) in line.iter().zip(&column_widths) {
                    let mut pen = column_x;
                    for c in cell.chars() {
                        let g = self.glyph(c);
                        if g.size[0] > 0 {
                            let gx = pen.round() + g.offset[0] as f32;
                            let gy = baseline + g.offset[1] as f32;
                            quads.push(OverlayQuad {
                                rect: [gx, gy, gx + g.size[0] as f32, gy + g.size[1] as f32],
                                atlas: [g.atlas[0] as f32, g.atlas[1] as f32, 0.0, 0.0],
                                color: TEXT_COLOR,
                            });
                        }
                        pen += g.advance;
                    }
                    column_x += column_width + COLUMN_GAP;
                }
            }
        }
        quads
    }

    /// What the overlay's blend gives for one pixel of an 8-bit target holding
    /// `below` (sRGB-encoded values of a UNORM target), for tests: each quad covering
    /// the pixel's centre in order, `src·α + dst·(1 − α)`, the target holding the
    /// result rounded to 8 bits between quads; `image` is the overlay image, if shown.
    pub fn composite_unorm8(
        &self,
        quads: &[OverlayQuad],
        image: Option<&OverlayImage>,
        x: u32,
        y: u32,
        below: [u8; 4],
    ) -> [f64; 4] {
        let mut rgba = below.map(|c| f64::from(c) / 255.0);
        let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
        for q in quads {
            let [x0, y0, x1, y1] = q.rect;
            if px < x0 || px >= x1 || py < y0 || py >= y1 {
                continue;
            }
            let mut color = q.color;
            let coverage = if q.atlas[2] == 2.0 {
                let texel = image.map_or([0; 4], |i| i.rgba[(y * i.width + x) as usize]);
                for (c, v) in color.iter_mut().zip(texel) {
                    *c = f32::from(v) / 255.0;
                }
                1.0
            } else if q.atlas[2] == 1.0 {
                1.0
            } else {
                let ax = q.atlas[0] as u32 + (px - x0) as u32;
                let ay = q.atlas[1] as u32 + (py - y0) as u32;
                f64::from(self.atlas[(ay * ATLAS_WIDTH + ax) as usize]) / 255.0
            };
            let alpha = f64::from(color[3]) * coverage;
            for (value, color) in rgba.iter_mut().zip(color).take(3) {
                let blended = f64::from(color) * alpha + *value * (1.0 - alpha);
                *value = (blended * 255.0).round() / 255.0;
            }
        }
        rgba
    }
}

/// The push constants of `overlay.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct OverlayPush {
    target_size: [f32; 2],
    atlas_width: u32,
    image_width: u32,
}

/// The overlay's pipeline for one target format (blending over the output pass's
/// pixels, inside its rendering).
pub(crate) struct OverlayPass {
    layout: PipelineLayout,
    pipeline: Pipeline,
}

impl OverlayPass {
    pub fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        set_layout: &DescriptorSetLayout,
        defines: &[(&str, Option<&str>)],
        format: vk::Format,
    ) -> Result<Self, RenderError> {
        let (layout, pipeline) = crate::fullscreen::screen_pipeline(
            device,
            compiler,
            cache,
            &crate::fullscreen::ScreenPipelineDesc {
                vertex_shader: "overlay.vert",
                fragment_shader: "overlay.frag",
                defines,
                set_layout,
                push_stages: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                push_size: std::mem::size_of::<OverlayPush>() as u32,
                format,
                blend: combustion_vk::ColorBlend::OverKeepingAlpha,
                depth_test: None,
            },
        )?;
        Ok(Self { layout, pipeline })
    }

    /// Draws `quads` quads inside the output pass's rendering (viewport and scissor set).
    pub fn record(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        extent: vk::Extent2D,
        set: vk::DescriptorSet,
        quads: u32,
        image_width: u32,
    ) {
        let push = OverlayPush {
            target_size: [extent.width as f32, extent.height as f32],
            atlas_width: ATLAS_WIDTH,
            image_width,
        };
        let raw = device.raw();
        crate::commands::bind_pass(
            raw,
            cmd,
            vk::PipelineBindPoint::GRAPHICS,
            &self.pipeline,
            &self.layout,
            set,
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            bytemuck::bytes_of(&push),
        );
        // SAFETY: inside a rendering instance of a command buffer in the recording state.
        unsafe { raw.cmd_draw(cmd, 6, quads, 0, 0) };
    }
}

/// An sRGB-encoded RGBA8 image shown over the frame, under the text panels, at the
/// target's top-left corner, one texel a pixel, blended with its alpha (e.g. the
/// viewer's error heat map, opaque).
#[derive(Clone, Debug, PartialEq)]
pub struct OverlayImage {
    /// Width in texels (= pixels of the target).
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Row-major from the top-left; `width · height` texels.
    pub rgba: Vec<[u8; 4]>,
}

/// The atlas packed four texels to a `uint` (little-endian), as the shader reads it.
pub(crate) fn atlas_words(font: &OverlayFont) -> Vec<u32> {
    font.atlas
        .chunks(4)
        .map(|c| {
            let mut b = [0u8; 4];
            b[..c.len()].copy_from_slice(c);
            u32::from_le_bytes(b)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_printable_character_has_a_distinct_glyph() {
        let font = OverlayFont::new().unwrap();
        let mut seen = std::collections::HashSet::new();
        for c in ('!'..='~').chain(EXTRA_CHARACTERS.chars()) {
            let g = font.glyphs[&c];
            assert!(g.size[0] > 0 && g.size[1] > 0, "{c:?} has no bitmap");
            let mut bitmap = Vec::new();
            for row in 0..g.size[1] {
                let start = ((g.atlas[1] + row) * ATLAS_WIDTH + g.atlas[0]) as usize;
                bitmap.extend_from_slice(&font.atlas[start..start + g.size[0] as usize]);
            }
            // Thin strokes ('"', '|') are anti-aliased over two texels at this size.
            assert!(bitmap.iter().any(|&v| v > 128), "{c:?} has no inked texel");
            // Glyphs that differ only in offset (e.g. ',' and '\'') are told apart by it.
            assert!(
                seen.insert((bitmap, g.offset)),
                "{c:?} repeats another glyph"
            );
        }
        assert!(font.glyphs[&' '].advance > 0.0);
    }

    #[test]
    fn panels_stack_in_their_corner_and_columns_align() {
        let font = OverlayFont::new().unwrap();
        let panels = [
            OverlayPanel {
                text: "a\tb\nlong key\tc",
                corner: Corner::TopRight,
            },
            OverlayPanel {
                text: "x",
                corner: Corner::TopRight,
            },
        ];
        let quads = font.layout(&panels, [640, 480], None);
        let backgrounds: Vec<_> = quads.iter().filter(|q| q.atlas[2] == 1.0).collect();
        assert_eq!(backgrounds.len(), 2);
        assert_eq!(backgrounds[0].rect[2], 640.0 - PANEL_MARGIN);
        assert!(backgrounds[1].rect[1] >= backgrounds[0].rect[3] + PANEL_MARGIN);
        // 'b' and 'c' start in one column: their pens are equal (offsets differ by glyph).
        let glyph_x = |c: char, nth: usize| {
            let g = font.glyph(c);
            quads
                .iter()
                .filter(|q| q.atlas[..2] == [g.atlas[0] as f32, g.atlas[1] as f32])
                .nth(nth)
                .map(|q| q.rect[0] - g.offset[0] as f32)
                .unwrap()
        };
        assert_eq!(glyph_x('b', 0), glyph_x('c', 0));
        assert!(quads
            .iter()
            .all(|q| q.rect.iter().all(|v| v.fract() == 0.0)));
    }
}
