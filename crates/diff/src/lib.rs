//! `combustion diff A B`: two images compared as a user's CI compares a render with its
//! golden — per-pixel channel differences, FLIP, and criteria with stated tolerances.
//!
//! - **PNG** (8-bit display images, sRGB as written): each pixel's largest channel
//!   difference in 8-bit steps (out of 255), and FLIP (Andersson et al. 2020, `nv-flip`,
//!   67 pixels per degree: the implementation the speed-against-error report uses).
//! - **OpenEXR** (linear radiance): each pixel's largest channel difference relative to
//!   the larger of the two values (at least 1e-4, the report's floor), and FLIP of the
//!   two display images the render would write from them (exposure 1, 1 − e^−x, exact
//!   sRGB, 8 bits).
//! - **Criteria** ([`Criteria::parse`]): terms joined by `and` and `or` (`and` binds
//!   tighter): `max-channel-diff N/255 on at most P% of pixels` (PNG),
//!   `max-relative-diff X on at most P% of pixels` (EXR), `mean-flip <= X`,
//!   `max-flip <= X`. A term that fails says by how much.
//!
//! Inputs are read by the rule of every input file (a regular file within a size limit,
//! checked before a byte is read).

use std::path::Path;

pub use combustion_criteria::{Criteria, Criterion, Measured};

/// The largest image file read: 1 GiB.
pub const MAX_IMAGE_BYTES: u64 = 1 << 30;

/// The largest side of an image compared (the renderer's largest).
pub const MAX_SIDE: u32 = 65536;

/// An image's pixels, as its format stores them.
#[derive(Clone, Debug, PartialEq)]
pub enum Pixels {
    /// 8-bit sRGB display values (PNG), alpha dropped.
    Display(Vec<[u8; 3]>),
    /// Linear radiance (OpenEXR), alpha dropped.
    Radiance(Vec<[f32; 3]>),
}

/// One image to compare.
#[derive(Clone, Debug, PartialEq)]
pub struct DiffImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major from the top-left.
    pub pixels: Pixels,
}

/// The most pixels an image compared may have: 16,777,216 (4096 × 4096, or 7680 × 2160),
/// checked from its header before it is decoded. Comparing two takes about 100 bytes a
/// pixel (FLIP's images among them): some 1.7 GB at this size.
pub const MAX_PIXELS: u64 = 1 << 24;

/// An image file read but not decoded: its bytes, its kind and its size from its header
/// (within [`MAX_SIDE`] and [`MAX_PIXELS`]).
pub struct ImageFile {
    bytes: Vec<u8>,
    /// OpenEXR (radiance) rather than PNG (display values).
    pub radiance: bool,
    /// Width in pixels, from the header.
    pub width: u32,
    /// Height in pixels, from the header.
    pub height: u32,
}

/// Reads a PNG or an OpenEXR file (by its extension) and its header: its size is known,
/// and checked, before a pixel is decoded ([`ImageFile::decode`]).
pub fn open_image(path: &Path) -> Result<ImageFile, String> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let radiance = match extension.as_deref() {
        Some("png") => false,
        Some("exr") => true,
        _ => return Err("not a .png or .exr file".into()),
    };
    let bytes = combustion_scene::read_regular_file(path, MAX_IMAGE_BYTES, "an image to compare")
        .map_err(|e| e.to_string())?;
    ImageFile::from_bytes(bytes, radiance)
}

impl ImageFile {
    /// A PNG's (`radiance` false) or an OpenEXR file's bytes with their header read: its
    /// size is known, and checked, before a pixel is decoded ([`ImageFile::decode`]).
    pub fn from_bytes(bytes: Vec<u8>, radiance: bool) -> Result<Self, String> {
        let (width, height) = if radiance {
            let meta =
                exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(&bytes[..]), false)
                    .map_err(|e| format!("OpenEXR: {e}"))?;
            let header = meta
                .headers
                .first()
                .ok_or_else(|| "OpenEXR: no layer".to_owned())?;
            let size = header.layer_size;
            checked_size(size.width(), size.height())?
        } else {
            let decoder = png::Decoder::new(std::io::Cursor::new(&bytes[..]));
            let reader = decoder
                .read_info()
                .map_err(|e| format!("PNG: {}", combustion_scene::png_error_message(&e)))?;
            let info = reader.info();
            checked_size(info.width as usize, info.height as usize)?
        };
        Ok(ImageFile {
            bytes,
            radiance,
            width,
            height,
        })
    }
}

impl ImageFile {
    /// Its pixels, decoded.
    pub fn decode(&self) -> Result<DiffImage, String> {
        if self.radiance {
            read_exr(&self.bytes)
        } else {
            read_png(&self.bytes)
        }
    }
}

/// Reads a PNG (8-bit or 16-bit, grey or RGB, with or without alpha; 16-bit is rounded
/// to 8) or an OpenEXR file's first RGB(A) layer, by its extension.
pub fn read_image(path: &Path) -> Result<DiffImage, String> {
    open_image(path)?.decode()
}

fn checked_size(width: usize, height: usize) -> Result<(u32, u32), String> {
    let side = |s: usize| {
        u32::try_from(s)
            .ok()
            .filter(|&s| (1..=MAX_SIDE).contains(&s))
    };
    match (side(width), side(height)) {
        (Some(w), Some(h)) if u64::from(w) * u64::from(h) <= MAX_PIXELS => Ok((w, h)),
        (Some(_), Some(_)) => Err(format!(
            "{width}x{height}: more than {MAX_PIXELS} pixels, the most an image compared may have"
        )),
        _ => Err(format!(
            "{width}x{height}: each side must be between 1 and {MAX_SIDE}"
        )),
    }
}

fn read_png(bytes: &[u8]) -> Result<DiffImage, String> {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    // 16-bit samples are kept and rounded to 8 bits below (STRIP_16 would truncate).
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder
        .read_info()
        .map_err(|e| format!("PNG: {}", combustion_scene::png_error_message(&e)))?;
    let (width, height) = {
        let info = reader.info();
        checked_size(info.width as usize, info.height as usize)?
    };
    let mut buffer = vec![0; reader.output_buffer_size()];
    let frame = reader
        .next_frame(&mut buffer)
        .map_err(|e| format!("PNG: {}", combustion_scene::png_error_message(&e)))?;
    let channels = frame.color_type.samples();
    let data = &buffer[..frame.buffer_size()];
    let data: std::borrow::Cow<'_, [u8]> = match frame.bit_depth {
        // Big-endian 16-bit samples, each rounded to the nearest 8-bit code.
        png::BitDepth::Sixteen => data
            .chunks_exact(2)
            .map(|s| {
                let v = u32::from(u16::from_be_bytes([s[0], s[1]]));
                ((v * 255 + 32_767) / 65_535) as u8
            })
            .collect::<Vec<u8>>()
            .into(),
        _ => data.into(),
    };
    let pixels = data
        .chunks_exact(channels)
        .map(|p| match channels {
            1 | 2 => [p[0]; 3],
            _ => [p[0], p[1], p[2]],
        })
        .collect::<Vec<_>>();
    if pixels.len() != (width * height) as usize {
        return Err("PNG: its pixel data does not match its size".into());
    }
    Ok(DiffImage {
        width,
        height,
        pixels: Pixels::Display(pixels),
    })
}

fn read_exr(bytes: &[u8]) -> Result<DiffImage, String> {
    let (width, height, pixels) = combustion_scene::decode_exr_rgb(bytes, checked_size)
        .map_err(|e| format!("OpenEXR: {e}"))?;
    Ok(DiffImage {
        width,
        height,
        pixels: Pixels::Radiance(pixels),
    })
}

/// Two images compared.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Whether the images are radiance (OpenEXR) rather than display values (PNG).
    pub radiance: bool,
    /// Per pixel, the largest channel difference: in 8-bit steps (display), or relative
    /// to the larger value, at least 1e-4 (radiance).
    pub channel_diff: Vec<f64>,
    /// Per pixel FLIP, in [0, 1].
    pub flip: Vec<f32>,
    /// `flip` sorted, made once on the first quantile asked (criteria with many
    /// `max-flip` terms sorted it once per term).
    sorted_flip: std::sync::OnceLock<Vec<f32>>,
}

impl Comparison {
    /// The largest per-pixel channel difference.
    pub fn max_channel_diff(&self) -> f64 {
        self.channel_diff.iter().copied().fold(0.0, f64::max)
    }

    /// The share of pixels (0 to 1) whose channel difference is above `tolerance`.
    pub fn share_above(&self, tolerance: f64) -> f64 {
        let over = self.channel_diff.iter().filter(|&&d| d > tolerance).count();
        over as f64 / self.channel_diff.len().max(1) as f64
    }

    /// Mean FLIP.
    pub fn mean_flip(&self) -> f64 {
        self.flip.iter().map(|&f| f64::from(f)).sum::<f64>() / self.flip.len().max(1) as f64
    }

    /// The FLIP value the share `q` of the pixels does not exceed.
    pub fn flip_quantile(&self, q: f64) -> f64 {
        let sorted = self.sorted_flip.get_or_init(|| {
            let mut sorted = self.flip.clone();
            sorted.sort_by(f32::total_cmp);
            sorted
        });
        let i = ((sorted.len().max(1) - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize;
        sorted.get(i).map_or(0.0, |&f| f64::from(f))
    }
}

/// What the criteria read of a comparison.
impl Measured for Comparison {
    fn radiance(&self) -> bool {
        self.radiance
    }

    fn share_above(&self, tolerance: f64) -> f64 {
        Comparison::share_above(self, tolerance)
    }

    fn max_channel_diff(&self) -> f64 {
        Comparison::max_channel_diff(self)
    }

    fn mean_flip(&self) -> f64 {
        Comparison::mean_flip(self)
    }

    fn max_flip(&self) -> f64 {
        self.flip_quantile(1.0)
    }
}

/// The display image the render writes from radiance: exposure 1, 1 − e^−x, exact sRGB,
/// rounded to 8 bits.
fn displayed(radiance: &[[f32; 3]]) -> Vec<[u8; 3]> {
    radiance
        .iter()
        .map(|p| {
            p.map(|c| {
                let display = combustion_optics::display::tonemap_exponential(f64::from(c));
                (combustion_optics::display::linear_to_srgb(display).clamp(0.0, 1.0) * 255.0)
                    .round() as u8
            })
        })
        .collect()
}

/// Compares `a` with `b` (same size and kind, else the error says what differs).
pub fn compare(a: &DiffImage, b: &DiffImage) -> Result<Comparison, String> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(format!(
            "the images differ in size: {}x{} and {}x{}",
            a.width, a.height, b.width, b.height
        ));
    }
    let (channel_diff, display_a, display_b, radiance) = match (&a.pixels, &b.pixels) {
        (Pixels::Display(pa), Pixels::Display(pb)) => {
            let diff = pa
                .iter()
                .zip(pb)
                .map(|(p, q)| {
                    (0..3)
                        .map(|c| f64::from(p[c].abs_diff(q[c])))
                        .fold(0.0, f64::max)
                })
                .collect();
            (diff, pa.clone(), pb.clone(), false)
        }
        (Pixels::Radiance(pa), Pixels::Radiance(pb)) => {
            let diff = pa
                .iter()
                .zip(pb)
                .map(|(p, q)| {
                    (0..3)
                        .map(|c| {
                            let (x, y) = (f64::from(p[c]), f64::from(q[c]));
                            // Equal values (infinities included) and two NaNs do not
                            // differ; a NaN or infinity against anything else does.
                            if x == y || (x.is_nan() && y.is_nan()) {
                                return 0.0;
                            }
                            let d = (x - y).abs() / x.abs().max(y.abs()).max(1e-4);
                            if d.is_nan() {
                                f64::INFINITY
                            } else {
                                d
                            }
                        })
                        .fold(0.0, f64::max)
                })
                .collect();
            (diff, displayed(pa), displayed(pb), true)
        }
        _ => {
            return Err(
                "one image is a PNG (display values) and the other an OpenEXR (radiance): compare like with like"
                    .into(),
            )
        }
    };
    let flat = |p: &[[u8; 3]]| p.iter().flatten().copied().collect::<Vec<u8>>();
    let (fa, fb) = (flat(&display_a), flat(&display_b));
    let flip = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(a.width, a.height, &fa),
        nv_flip::FlipImageRgb8::with_data(a.width, a.height, &fb),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    // Row-major from the top-left, as the inputs.
    let flip_values = flip.to_vec();
    Ok(Comparison {
        width: a.width,
        height: a.height,
        radiance,
        channel_diff,
        flip: flip_values,
        sorted_flip: std::sync::OnceLock::new(),
    })
}

/// The FLIP heat map of `comparison` (the magma colour map from 0, black, to 1, light
/// yellow, as FLIP's own tool draws it), as RGBA for a PNG.
pub fn heat_map(comparison: &Comparison) -> Vec<[u8; 4]> {
    let flip =
        nv_flip::FlipImageFloat::with_data(comparison.width, comparison.height, &comparison.flip);
    flip.apply_color_lut(&nv_flip::magma_lut())
        .to_vec()
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2], 255])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FLIP's quantiles come from one sort, kept: every `max-flip` term of a long
    /// criterion reads the same values the first did (each term sorted the image again).
    #[test]
    fn flip_quantiles_are_sorted_once() {
        let image = |v: u8| DiffImage {
            width: 4,
            height: 4,
            pixels: Pixels::Display((0..16u8).map(|i| [i * v, 0, 255 - i * v]).collect()),
        };
        let comparison = compare(&image(3), &image(13)).unwrap();
        let max = comparison.flip.iter().copied().fold(0.0f32, f32::max);
        let min = comparison.flip.iter().copied().fold(1.0f32, f32::min);
        assert_eq!(comparison.flip_quantile(1.0), f64::from(max));
        assert_eq!(comparison.flip_quantile(0.0), f64::from(min));
        let terms = vec!["max-flip <= 1"; 2000].join(" and ");
        let criteria = Criteria::parse(&terms).unwrap();
        assert_eq!(criteria.check(&comparison), Ok(()));
        assert_eq!(comparison.sorted_flip.get().map(Vec::len), Some(16));
    }

    /// A 16-bit PNG's samples are rounded to 8 bits, as the documentation says: 0x00FF
    /// (0.992 of an 8-bit step) is 1 and 0xFF00 (254.0) is 254, where STRIP_16 took the
    /// high byte (0 and 255).
    #[test]
    fn sixteen_bit_pngs_are_rounded() {
        let mut bytes = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut bytes, 2, 1);
            encoder.set_color(png::ColorType::Grayscale);
            encoder.set_depth(png::BitDepth::Sixteen);
            let mut writer = encoder.write_header().unwrap();
            writer.write_image_data(&[0x00, 0xFF, 0xFF, 0x00]).unwrap();
        }
        let image = read_png(&bytes).unwrap();
        let Pixels::Display(pixels) = image.pixels else {
            panic!("a PNG is display values")
        };
        assert_eq!(pixels, vec![[1; 3], [254; 3]]);
    }

    /// An EXR does not differ from itself where it holds NaN or infinity (a NaN pixel
    /// made it "differ"); a NaN or infinity against a number still differs.
    #[test]
    fn non_finite_radiance_equals_itself() {
        let image = |v: f32| DiffImage {
            width: 2,
            height: 1,
            pixels: Pixels::Radiance(vec![[v, 1.0, 2.0], [0.5; 3]]),
        };
        for v in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 3.0] {
            let same = compare(&image(v), &image(v)).unwrap();
            assert_eq!(same.max_channel_diff(), 0.0, "{v}");
            assert_eq!(same.mean_flip(), 0.0, "{v}");
        }
        for v in [f32::NAN, f32::INFINITY] {
            let other = compare(&image(v), &image(3.0)).unwrap();
            assert_eq!(other.max_channel_diff(), f64::INFINITY, "{v}");
        }
    }

    fn display(width: u32, height: u32, f: impl Fn(u32, u32) -> [u8; 3]) -> DiffImage {
        DiffImage {
            width,
            height,
            pixels: Pixels::Display(
                (0..height)
                    .flat_map(|y| (0..width).map(move |x| (x, y)))
                    .map(|(x, y)| f(x, y))
                    .collect(),
            ),
        }
    }

    /// An image against itself: no difference, FLIP 0, every criterion met; one pixel
    /// changed by 6 steps: the share and the largest difference are exact, the criteria
    /// that allow it pass and the others say by how much they fail.
    #[test]
    fn differences_and_criteria_are_exact() {
        let a = display(20, 10, |x, y| [(x * 10) as u8, (y * 20) as u8, 128]);
        let same = compare(&a, &a).unwrap();
        assert_eq!((same.max_channel_diff(), same.mean_flip()), (0.0, 0.0));
        let mut b = a.clone();
        if let Pixels::Display(p) = &mut b.pixels {
            p[7][1] += 6;
        }
        let c = compare(&a, &b).unwrap();
        assert_eq!(c.max_channel_diff(), 6.0);
        assert_eq!(c.share_above(5.0), 1.0 / 200.0);
        assert!(c.mean_flip() > 0.0);
        let pass = Criteria::parse("max-channel-diff 5/255 on at most 0.5% of pixels").unwrap();
        assert_eq!(pass.check(&c), Ok(()));
        let fail = Criteria::parse("max-channel-diff 5/255 on at most 0.1% of pixels").unwrap();
        let why = fail.check(&c).unwrap_err();
        assert!(
            why.contains("0.5000% of pixels are above it (largest difference 6/255)"),
            "{why}"
        );
        let either = Criteria::parse(
            "max-channel-diff 5/255 on at most 0.1% of pixels or max-channel-diff 6/255 on at most 0% of pixels and mean-flip <= 1",
        )
        .unwrap();
        assert_eq!(either.0.len(), 2);
        assert_eq!(
            Criteria::parse("mean-flip<=0.5").unwrap(),
            Criteria(vec![vec![Criterion::MeanFlip(0.5)]])
        );
        assert_eq!(either.check(&c), Ok(()));
    }

    #[test]
    fn bad_criteria_and_mismatched_images_are_named() {
        for (text, expected) in [
            ("max-channel-diff 5 on at most 1% of pixels", "as N/255"),
            (
                "max-channel-diff 5/255 on at most 1 of pixels",
                "in percent",
            ),
            ("mean-flip <= -1", "at least 0"),
            (
                "max-channel-diff 5/255 on at most 101% of pixels",
                "at most 100%",
            ),
            ("psnr >= 30", "not one of"),
        ] {
            let error = Criteria::parse(text).unwrap_err();
            assert!(error.contains(expected), "{text}: {error}");
        }
        let a = display(4, 4, |_, _| [0; 3]);
        let b = display(4, 5, |_, _| [0; 3]);
        assert!(compare(&a, &b).unwrap_err().contains("4x4 and 4x5"));
        let r = DiffImage {
            width: 4,
            height: 4,
            pixels: Pixels::Radiance(vec![[0.0; 3]; 16]),
        };
        assert!(compare(&a, &r).unwrap_err().contains("like with like"));
    }
}
