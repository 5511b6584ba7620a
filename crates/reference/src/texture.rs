//! Texture sampling in f64, from the scene's decoded images alone: the image's values
//! decoded (the sRGB curve inverted exactly for colour images), a mip chain made by
//! the linear 2:1 reduction a graphics API's linear blit performs, wrapping and
//! nearest/bilinear/trilinear filtering as the Vulkan specification defines them
//! ("Texel Filtering", "Wrapping Operation", "Level-of-Detail Operation").
//!
//! What it leaves out, because the ideal is what it stands for: the 8-bit storage of
//! the reduced levels, and any fixed-point filter weights a driver may use. Both are
//! errors of the GPU measured against it.

use combustion_scene::{ColorSpace, Filter, Image, Sampler, TextureRef, WrapMode};

pub use combustion_scene::{srgb_decode, srgb_encode};

/// One level of a [`MipChain`]: RGBA values, row-major from the top-left.
#[derive(Clone, Debug)]
struct Level {
    width: usize,
    height: usize,
    texels: Texels,
}

/// A level's values: the reduced levels' in f64; level 0's as the image's 8-bit codes
/// with each channel's value per code, so a 2048² image is 16 MiB here instead of the
/// 128 MiB of its values (the same values, looked up when read).
#[derive(Clone, Debug)]
enum Texels {
    Values(Vec<[f64; 4]>),
    Codes {
        rgba: Vec<u8>,
        value_of_code: Box<[[f64; 256]; 4]>,
    },
}

impl Level {
    fn texel(&self, x: usize, y: usize) -> [f64; 4] {
        let i = y * self.width + x;
        match &self.texels {
            Texels::Values(values) => values[i],
            Texels::Codes {
                rgba,
                value_of_code,
            } => std::array::from_fn(|c| value_of_code[c][usize::from(rgba[4 * i + c])]),
        }
    }

    /// The bilinear filter at (`u`, `v`) in texel units (texel centres at + 0.5),
    /// each integer coordinate wrapped by `wrap`.
    fn bilinear(&self, u: f64, v: f64, wrap: (WrapMode, WrapMode)) -> [f64; 4] {
        let (x, y) = (u - 0.5, v - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let mut out = [0.0; 4];
        for (dy, wy) in [(0, 1.0 - fy), (1, fy)] {
            for (dx, wx) in [(0, 1.0 - fx), (1, fx)] {
                let t = self.texel(
                    wrap_index(x0 + dx, self.width, wrap.0),
                    wrap_index(y0 + dy, self.height, wrap.1),
                );
                for c in 0..4 {
                    out[c] += wx * wy * t[c];
                }
            }
        }
        out
    }

    /// The nearest texel to (`u`, `v`) in texel units.
    fn nearest(&self, u: f64, v: f64, wrap: (WrapMode, WrapMode)) -> [f64; 4] {
        self.texel(
            wrap_index(u.floor() as i64, self.width, wrap.0),
            wrap_index(v.floor() as i64, self.height, wrap.1),
        )
    }

    /// The largest difference, over channels, between the 2×2 texels around (`uv`) — the
    /// texels a bilinear filter blends there, and those a nearest filter may pick when
    /// the position is rounded — with `encode` applied to each value first.
    fn footprint_contrast(
        &self,
        uv: [f64; 2],
        wrap: (WrapMode, WrapMode),
        encode: impl Fn(f64, usize) -> f64,
    ) -> f64 {
        let (x, y) = (
            uv[0] * self.width as f64 - 0.5,
            uv[1] * self.height as f64 - 0.5,
        );
        let (x0, y0) = (x.floor() as i64, y.floor() as i64);
        let texels: Vec<[f64; 4]> = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .map(|&(dx, dy)| {
                self.texel(
                    wrap_index(x0 + dx, self.width, wrap.0),
                    wrap_index(y0 + dy, self.height, wrap.1),
                )
            })
            .collect();
        (0..4)
            .map(|c| {
                let values = texels.iter().map(|t| encode(t[c], c));
                let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                });
                hi - lo
            })
            .fold(0.0, f64::max)
    }

    fn filtered(&self, uv: [f64; 2], filter: Filter, wrap: (WrapMode, WrapMode)) -> [f64; 4] {
        let (u, v) = (uv[0] * self.width as f64, uv[1] * self.height as f64);
        match filter {
            Filter::Nearest => self.nearest(u, v, wrap),
            Filter::Linear => self.bilinear(u, v, wrap),
        }
    }
}

/// An integer texel coordinate wrapped into [0, `size`) (Vulkan's wrapping operation).
fn wrap_index(i: i64, size: usize, mode: WrapMode) -> usize {
    let n = size as i64;
    let wrapped = match mode {
        WrapMode::Repeat => i.rem_euclid(n),
        WrapMode::ClampToEdge => i.clamp(0, n - 1),
        WrapMode::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m < n {
                m
            } else {
                2 * n - 1 - m
            }
        }
    };
    wrapped as usize
}

/// An image's values in f64 with every level of its mip chain.
#[derive(Clone, Debug)]
pub struct MipChain {
    levels: Vec<Level>,
    color_space: ColorSpace,
}

impl MipChain {
    /// Decodes `image` (RGB through the exact sRGB curve when its colour space is sRGB;
    /// alpha and linear images as value/255) and reduces it level by level down to 1×1:
    /// each level ⌊w/2⌋ × ⌊h/2⌋ (at least 1), each texel the bilinear filter of the
    /// level above at its own centre, clamped at the edges (a linear blit's result: the
    /// mean of 2×2 texels where the size is even).
    pub fn new(image: &Image) -> MipChain {
        let mut levels = vec![decoded(image)];
        while let Some(above) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
            let (width, height) = ((above.width / 2).max(1), (above.height / 2).max(1));
            let (sx, sy) = (
                above.width as f64 / width as f64,
                above.height as f64 / height as f64,
            );
            let clamp = (WrapMode::ClampToEdge, WrapMode::ClampToEdge);
            let texels = (0..height)
                .flat_map(|y| (0..width).map(move |x| (x, y)))
                .map(|(x, y)| above.bilinear((x as f64 + 0.5) * sx, (y as f64 + 0.5) * sy, clamp))
                .collect();
            levels.push(Level {
                width,
                height,
                texels: Texels::Values(texels),
            });
        }
        MipChain {
            levels,
            color_space: image.color_space,
        }
    }

    /// Level 0 alone (what [`MipChain::sample`] reads at λ ≤ 0, and at every λ when
    /// there is no other level): the image's values at its own resolution, without
    /// reducing it.
    pub fn level_zero(image: &Image) -> MipChain {
        MipChain {
            levels: vec![decoded(image)],
            color_space: image.color_space,
        }
    }

    /// Level 0's width and height in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.levels[0].width, self.levels[0].height)
    }

    /// The number of levels (⌊log₂ max(w, h)⌋ + 1).
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// The filtered RGBA value at texture coordinates `uv` (0..1 across the image, v
    /// down) with level of detail `lod` (λ: log₂ of texels per pixel on level 0), as
    /// `sampler` says: λ ≤ 0 magnifies with `mag_filter` on level 0; above, `min_filter`
    /// within a level and `mipmap_filter` between levels (nearest: the level
    /// ⌈λ + ½⌉ − 1; linear: the two levels around λ, blended); without a mipmap filter,
    /// level 0 only.
    pub fn sample(&self, sampler: &Sampler, uv: [f64; 2], lod: f64) -> [f64; 4] {
        let wrap = (sampler.wrap_u, sampler.wrap_v);
        let mut out = [0.0; 4];
        for (level, weight, filter) in self.levels_sampled(sampler, lod) {
            let value = self.levels[level].filtered(uv, filter, wrap);
            for c in 0..4 {
                out[c] += weight * value[c];
            }
        }
        out
    }

    /// The largest difference between neighbouring texels that [`MipChain::sample`]
    /// blends (or may pick) at `uv` and `lod`, over channels and the levels it reads,
    /// in the image's stored units (the 8-bit code / 255, sRGB-encoded for colour): how
    /// much a filter's rounding of the sample position can move its result per texel.
    pub fn footprint_contrast(&self, sampler: &Sampler, uv: [f64; 2], lod: f64) -> f64 {
        let wrap = (sampler.wrap_u, sampler.wrap_v);
        let srgb = self.color_space == ColorSpace::Srgb;
        let encode = |v: f64, c: usize| if srgb && c < 3 { srgb_encode(v) } else { v };
        self.levels_sampled(sampler, lod)
            .into_iter()
            .map(|(level, _, _)| self.levels[level].footprint_contrast(uv, wrap, encode))
            .fold(0.0, f64::max)
    }

    /// The levels [`MipChain::sample`] reads at `lod`, with their weights and the
    /// filter within each (see there).
    fn levels_sampled(&self, sampler: &Sampler, lod: f64) -> Vec<(usize, f64, Filter)> {
        if lod <= 0.0 || !lod.is_finite() {
            return vec![(0, 1.0, sampler.mag_filter)];
        }
        let last = (self.levels.len() - 1) as f64;
        let lod = lod.min(last);
        let filter = sampler.min_filter;
        match sampler.mipmap_filter {
            None => vec![(0, 1.0, filter)],
            Some(Filter::Nearest) => {
                let level = ((lod + 0.5).ceil() - 1.0).clamp(0.0, last) as usize;
                vec![(level, 1.0, filter)]
            }
            Some(Filter::Linear) => {
                let lower = lod.floor().min(last) as usize;
                let upper = (lower + 1).min(self.levels.len() - 1);
                let f = lod - lower as f64;
                vec![(lower, 1.0 - f, filter), (upper, f, filter)]
            }
        }
    }
}

/// The level of detail λ = log₂ ρ_max of a texture `size` texels wide and high whose
/// coordinates change by `duv_dx` and `duv_dy` per pixel (Vulkan's scale factor
/// ρ = max over the two screen axes of the texel-space derivative's length).
pub fn level_of_detail(size: (usize, usize), duv_dx: [f64; 2], duv_dy: [f64; 2]) -> f64 {
    let (w, h) = (size.0 as f64, size.1 as f64);
    let rho = |d: [f64; 2]| ((d[0] * w).powi(2) + (d[1] * h).powi(2)).sqrt();
    rho(duv_dx).max(rho(duv_dy)).log2()
}

/// A texture slot's coordinates: KHR_texture_transform's map of `uv` in f64
/// (u' = s_u cos θ u + s_v sin θ v + o_u, v' = −s_u sin θ u + s_v cos θ v + o_v).
pub fn transformed_uv(texture: &TextureRef, uv: [f64; 2]) -> [f64; 2] {
    let t = &texture.transform;
    let (sin, cos) = f64::from(t.rotation).sin_cos();
    let (su, sv) = (f64::from(t.scale[0]), f64::from(t.scale[1]));
    let (ou, ov) = (f64::from(t.offset[0]), f64::from(t.offset[1]));
    [
        su * cos * uv[0] + sv * sin * uv[1] + ou,
        -su * sin * uv[0] + sv * cos * uv[1] + ov,
    ]
}

/// The linear part of [`transformed_uv`] applied to a derivative.
pub fn transformed_derivative(texture: &TextureRef, d: [f64; 2]) -> [f64; 2] {
    let origin = transformed_uv(texture, [0.0, 0.0]);
    let moved = transformed_uv(texture, d);
    [moved[0] - origin[0], moved[1] - origin[1]]
}

/// `image`'s texels decoded: RGB through the exact sRGB curve when its colour space is
/// sRGB, alpha and linear images as value/255. Each of the 256 codes is decoded once per
/// channel (the same f64 the curve gives, bit for bit) and looked up when a texel is
/// read: a sample model's 2048² textures are millions of texels, where the curve's
/// `powf` per texel took seconds and their f64 values 128 MiB each.
fn decoded(image: &Image) -> Level {
    let linear: [f64; 256] = std::array::from_fn(|byte| byte as f64 / 255.0);
    let srgb: [f64; 256] = linear.map(srgb_decode);
    let value_of_code = Box::new(std::array::from_fn(|channel| {
        if image.color_space == ColorSpace::Srgb && channel < 3 {
            srgb
        } else {
            linear
        }
    }));
    Level {
        width: image.width as usize,
        height: image.height as usize,
        texels: Texels::Codes {
            rgba: image.pixels.clone(),
            value_of_code,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn image(width: u32, height: u32, pixels: Vec<u8>, color_space: ColorSpace) -> Image {
        Image {
            name: "test".into(),
            width,
            height,
            color_space,
            pixels,
        }
    }

    const BILINEAR_REPEAT: Sampler = Sampler {
        mag_filter: Filter::Linear,
        min_filter: Filter::Linear,
        mipmap_filter: Some(Filter::Linear),
        wrap_u: WrapMode::Repeat,
        wrap_v: WrapMode::Repeat,
    };

    /// The sRGB curve's two pieces meet at 0.04045, 1 decodes to 1, and 0.5 to the
    /// standard's 0.214 (to four figures).
    #[test]
    fn srgb_decoding_follows_the_standard() {
        assert!((srgb_decode(0.04045) - 0.04045 / 12.92).abs() < 1e-12);
        assert!((srgb_decode(0.040451) - 0.04045 / 12.92).abs() < 1e-6);
        assert_eq!(srgb_decode(1.0), 1.0);
        assert!((srgb_decode(0.5) - 0.2140).abs() < 1e-4);
    }

    /// Level 0 keeps the image's codes and looks their values up: every code of every
    /// channel reads back as the curve (or value/255) computed on the spot, bit for bit,
    /// in an sRGB and in a linear image.
    #[test]
    fn level_zero_reads_each_code_as_the_curve_gives_it() {
        let pixels: Vec<u8> = (0..=255u8).flat_map(|v| [v, 255 - v, v / 2, v]).collect();
        for color_space in [ColorSpace::Srgb, ColorSpace::Linear] {
            let chain = MipChain::level_zero(&image(16, 16, pixels.clone(), color_space));
            for (i, texel) in pixels.chunks_exact(4).enumerate() {
                let read = chain.levels[0].texel(i % 16, i / 16);
                for c in 0..4 {
                    let value = f64::from(texel[c]) / 255.0;
                    let expected = if color_space == ColorSpace::Srgb && c < 3 {
                        srgb_decode(value)
                    } else {
                        value
                    };
                    assert_eq!(
                        read[c].to_bits(),
                        expected.to_bits(),
                        "{color_space:?} texel {i} channel {c}"
                    );
                }
            }
        }
    }

    /// A 2×2 checker: at texel centres the texel itself, between them the mean; the
    /// chain's second level is the mean of all four; repeat wrapping joins the edges.
    #[test]
    fn bilinear_filtering_and_reduction_by_hand() {
        let px = |v: u8| [v, v, v, 255];
        let pixels = [px(0), px(255), px(255), px(0)].concat();
        let chain = MipChain::new(&image(2, 2, pixels, ColorSpace::Linear));
        assert_eq!(chain.levels(), 2);
        assert_eq!(chain.sample(&BILINEAR_REPEAT, [0.25, 0.25], -1.0)[0], 0.0);
        assert_eq!(chain.sample(&BILINEAR_REPEAT, [0.75, 0.25], -1.0)[0], 1.0);
        assert!((chain.sample(&BILINEAR_REPEAT, [0.5, 0.25], -1.0)[0] - 0.5).abs() < 1e-15);
        // Between the right column and the left column's copy: the mean too.
        assert!((chain.sample(&BILINEAR_REPEAT, [1.0, 0.25], -1.0)[0] - 0.5).abs() < 1e-15);
        // Level 1 (λ = 1): the mean of the four everywhere.
        assert!((chain.sample(&BILINEAR_REPEAT, [0.1, 0.9], 1.0)[0] - 0.5).abs() < 1e-15);
        // Half-way between the levels at a texel centre: halfway between 0 and ½.
        assert!((chain.sample(&BILINEAR_REPEAT, [0.25, 0.25], 0.5)[0] - 0.25).abs() < 1e-15);
    }

    /// The footprint contrast: a 0/255 checker's neighbours differ by the whole range; a
    /// flat image's by nothing; an sRGB image's in encoded units (code / 255).
    #[test]
    fn footprint_contrast_in_stored_units() {
        let px = |v: u8| [v, v, v, 255];
        let checker = [px(0), px(255), px(255), px(0)].concat();
        let chain = MipChain::new(&image(2, 2, checker, ColorSpace::Srgb));
        let full = chain.footprint_contrast(&BILINEAR_REPEAT, [0.5, 0.5], -1.0);
        assert!((full - 1.0).abs() < 1e-12, "{full}");
        // Level 1 alone (λ = 1) is one grey texel.
        assert_eq!(
            chain.footprint_contrast(&BILINEAR_REPEAT, [0.5, 0.5], 1.0),
            0.0
        );
        let steps = [px(100), px(110), px(100), px(110)].concat();
        let chain = MipChain::new(&image(2, 2, steps, ColorSpace::Srgb));
        let contrast = chain.footprint_contrast(&BILINEAR_REPEAT, [0.5, 0.5], -1.0);
        assert!((contrast - 10.0 / 255.0).abs() < 1e-12, "{contrast}");
    }

    /// Wrapping by the specification's rules, and a 3×1 image reduced by the linear
    /// filter at the new texel's centre (texel coordinate 1.5: the middle texel's
    /// centre, so the middle texel alone), not the box mean of all three.
    #[test]
    fn wrapping_and_odd_sizes() {
        assert_eq!(wrap_index(-1, 4, WrapMode::Repeat), 3);
        assert_eq!(wrap_index(4, 4, WrapMode::ClampToEdge), 3);
        assert_eq!(wrap_index(-1, 4, WrapMode::MirroredRepeat), 0);
        assert_eq!(wrap_index(5, 4, WrapMode::MirroredRepeat), 2);
        let pixels = [[0, 0, 0, 255], [102, 0, 0, 255], [204, 0, 0, 255]].concat();
        let chain = MipChain::new(&image(3, 1, pixels, ColorSpace::Linear));
        assert_eq!(chain.levels(), 2);
        let sampler = Sampler {
            mipmap_filter: Some(Filter::Nearest),
            ..BILINEAR_REPEAT
        };
        let level1 = chain.sample(&sampler, [0.5, 0.5], 1.0)[0];
        assert!((level1 - 102.0 / 255.0).abs() < 1e-12, "{level1}");
    }

    /// The level of detail of a texture minified 4× along x and 2× along y is 2, and
    /// a KHR_texture_transform with an offset, a rotation and a scale maps coordinates
    /// as the scene's own f32 map does.
    #[test]
    fn level_of_detail_and_transform() {
        let lod = level_of_detail((256, 128), [4.0 / 256.0, 0.0], [0.0, 2.0 / 128.0]);
        assert!((lod - 2.0).abs() < 1e-12);
        let texture = TextureRef {
            texture: combustion_scene::Texture {
                image: Arc::new(image(1, 1, vec![0; 4], ColorSpace::Linear)),
                sampler: BILINEAR_REPEAT,
            },
            tex_coord: 0,
            transform: combustion_scene::UvTransform {
                offset: [0.5, -0.25],
                rotation: 1.25,
                scale: [2.0, 3.0],
            },
        };
        for uv in [[0.0f32, 0.0], [1.0, 0.0], [0.3, 0.7]] {
            let ours = transformed_uv(&texture, uv.map(f64::from));
            let scenes = texture.transform.apply(uv);
            for c in 0..2 {
                assert!((ours[c] - f64::from(scenes[c])).abs() < 1e-6, "{uv:?}");
            }
        }
    }
}
