//! Light arriving from infinitely far away in every direction: the environment a scene
//! is lit by besides its lights. Radiance L(ω) in W·sr⁻¹·m⁻² per RGB channel, ω the
//! direction the light comes *from* (world space, y up).
//!
//! The radiance functions here are the definition: the renderer's cube-map bake
//! evaluates the same formula in GLSL (`shaders/include/environment.glsl`), and the f64
//! environment oracle (`combustion_renderer::reference`) integrates against these.

use std::path::Path;
use std::sync::Arc;

use crate::SceneError;

/// The most bytes an environment file may have (checked before reading).
pub const MAX_ENVIRONMENT_FILE_BYTES: u64 = 1 << 30;
/// The most texels an environment image may decode to (8192 × 4096 × 2).
pub const MAX_ENVIRONMENT_TEXELS: u64 = 1 << 26;

/// An equirectangular (latitude–longitude) radiance image, W·sr⁻¹·m⁻² per RGB channel,
/// row 0 at the zenith (+y). Its radiance is the image bilinearly interpolated, wrapping
/// around in u and clamped at the poles, at
/// u = ½ + atan2(ω_x, −ω_z)/2π, v = acos(ω_y)/π
/// (the image's centre column looks along −z, the default camera's view).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentImage {
    /// The file it came from (for messages).
    pub name: String,
    /// Texels per row (the full 360° of longitude), at least 1.
    pub width: u32,
    /// Rows (zenith to nadir, 180° of latitude), at least 1.
    pub height: u32,
    /// `width × height` texels of radiance (linear RGB, W·sr⁻¹·m⁻², between 0 and
    /// [`crate::MAX_RADIANCE`]),
    /// row-major from the top-left.
    pub texels: Vec<[f32; 3]>,
}

/// The file formats of an environment image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnvironmentFormat {
    /// Radiance RGBE (`.hdr`), flat or run-length encoded.
    RadianceHdr,
    /// OpenEXR (`.exr`): its first layer with R, G and B channels, at its largest
    /// resolution level.
    OpenExr,
}

impl EnvironmentImage {
    /// Reads a Radiance `.hdr` (RGBE) or OpenEXR `.exr` file: a regular file of at most
    /// [`MAX_ENVIRONMENT_FILE_BYTES`], decoding to at most [`MAX_ENVIRONMENT_TEXELS`]
    /// texels, every value between 0 and [`crate::MAX_RADIANCE`].
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let fail = |reason: String| SceneError::EnvironmentImage {
            path: path.display().to_string(),
            reason,
        };
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let bytes = crate::gltf::read_regular_file(
            path,
            MAX_ENVIRONMENT_FILE_BYTES,
            "an environment image",
        )
        .map_err(|e| fail(e.to_string()))?;
        let format = match extension.as_deref() {
            Some("hdr") => EnvironmentFormat::RadianceHdr,
            Some("exr") => EnvironmentFormat::OpenExr,
            _ => return Err(fail("not a .hdr or .exr file".into())),
        };
        Self::from_bytes(&bytes, format, &path.display().to_string())
    }

    /// Decodes a Radiance `.hdr` or OpenEXR image from `bytes` (the file's contents) by
    /// [`EnvironmentImage::load`]'s rules, after the file rule: at most
    /// [`MAX_ENVIRONMENT_TEXELS`] texels, every value between 0 and
    /// [`crate::MAX_RADIANCE`]. `name` names it in messages.
    pub fn from_bytes(
        bytes: &[u8],
        format: EnvironmentFormat,
        name: &str,
    ) -> Result<Self, SceneError> {
        let image = match format {
            EnvironmentFormat::RadianceHdr => decode_radiance_hdr(bytes),
            EnvironmentFormat::OpenExr => decode_exr(bytes),
        }
        .map_err(|reason| SceneError::EnvironmentImage {
            path: name.to_owned(),
            reason,
        })?;
        let image = Self {
            name: name.to_owned(),
            ..image
        };
        image.validate()?;
        Ok(image)
    }

    /// The image's own checks: a size that fits, texels for every pixel, values between
    /// 0 and [`crate::MAX_RADIANCE`].
    pub fn validate(&self) -> Result<(), SceneError> {
        let fail = |reason: String| {
            Err(SceneError::EnvironmentImage {
                path: self.name.clone(),
                reason,
            })
        };
        let count = u64::from(self.width) * u64::from(self.height);
        if self.width == 0 || self.height == 0 || count != self.texels.len() as u64 {
            return fail(format!(
                "{}×{} with {} texels",
                self.width,
                self.height,
                self.texels.len()
            ));
        }
        if let Some(i) = self
            .texels
            .iter()
            .position(|t| !t.iter().all(|&c| (0.0..=crate::MAX_RADIANCE).contains(&c)))
        {
            let [r, g, b] = self.texels[i].map(crate::error::readable);
            return fail(format!(
                "texel ({}, {}) is {r} {g} {b}: radiance must be between 0 and {:e} W·sr⁻¹·m⁻²",
                i as u32 % self.width,
                i as u32 / self.width,
                crate::MAX_RADIANCE
            ));
        }
        Ok(())
    }

    /// The bilinearly interpolated radiance towards `direction` (unit length).
    pub fn radiance(&self, d: [f64; 3]) -> [f64; 3] {
        let (u, v) = equirect_coordinates(d);
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let x = u * w - 0.5;
        let y = (v * h - 0.5).clamp(0.0, h - 1.0);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let column = |i: f64| (i as i64).rem_euclid(i64::from(self.width)) as usize;
        let row = |j: f64| (j as i64).clamp(0, i64::from(self.height) - 1) as usize;
        let at = |i: f64, j: f64| self.texels[row(j) * self.width as usize + column(i)];
        let (a, b, c, e) = (
            at(x0, y0),
            at(x0 + 1.0, y0),
            at(x0, y0 + 1.0),
            at(x0 + 1.0, y0 + 1.0),
        );
        let mut out = [0.0; 3];
        for (k, o) in out.iter_mut().enumerate() {
            let top = f64::from(a[k]) * (1.0 - fx) + f64::from(b[k]) * fx;
            let bottom = f64::from(c[k]) * (1.0 - fx) + f64::from(e[k]) * fx;
            *o = top * (1.0 - fy) + bottom * fy;
        }
        out
    }
}

/// (u, v) of a unit direction on an equirectangular image ([`EnvironmentImage`]).
pub fn equirect_coordinates(d: [f64; 3]) -> (f64, f64) {
    let u = 0.5 + d[0].atan2(-d[2]) / (2.0 * std::f64::consts::PI);
    let v = d[1].clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
    (u, v)
}

fn check_size(width: usize, height: usize) -> Result<(u32, u32), String> {
    let count = (width as u64).saturating_mul(height as u64);
    if width == 0 || height == 0 || count > MAX_ENVIRONMENT_TEXELS {
        return Err(format!(
            "{width}×{height} is outside the 1 to {MAX_ENVIRONMENT_TEXELS} texels an environment image may have"
        ));
    }
    Ok((width as u32, height as u32))
}

fn decode_radiance_hdr(bytes: &[u8]) -> Result<EnvironmentImage, String> {
    use image::ImageDecoder as _;
    let decoder =
        image::codecs::hdr::HdrDecoder::new(std::io::Cursor::new(bytes)).map_err(hdr_error)?;
    let (w, h) = decoder.dimensions();
    let (width, height) = check_size(w as usize, h as usize)?;
    // Decoded straight into the texels (the codec writes RGB f32s, which is their
    // layout): the decoded image is held once, not once as floats and again as texels.
    let mut texels = vec![[0f32; 3]; width as usize * height as usize];
    if std::mem::size_of_val(texels.as_slice()) as u64 != decoder.total_bytes() {
        return Err("the decoder's output is not RGB f32".into());
    }
    decoder
        .read_image(bytemuck::cast_slice_mut(&mut texels))
        .map_err(hdr_error)?;
    Ok(EnvironmentImage {
        name: String::new(),
        width,
        height,
        texels,
    })
}

/// What a file that ends before its texels do is told (the codecs say "failed to fill
/// whole buffer" or "reference to missing bytes").
const TRUNCATED: &str = "the file ends before its pixels do (truncated or damaged)";

/// The Radiance decoder's error in words.
fn hdr_error(e: image::ImageError) -> String {
    match e {
        image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            TRUNCATED.to_owned()
        }
        e => format!(
            "not a Radiance .hdr file this reader takes: {}",
            crate::error::shortened(&e.to_string())
        ),
    }
}

/// The OpenEXR decoder's error in words.
fn exr_error(e: exr::error::Error) -> String {
    use exr::error::Error;
    let shortened = |m: &str| crate::error::shortened(m);
    match e {
        Error::Invalid(m) if m.contains("missing bytes") => TRUNCATED.to_owned(),
        Error::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => TRUNCATED.to_owned(),
        Error::Invalid(m) if m.contains("no layer") => {
            "no layer of the file has R, G and B channels (an RGB or RGBA image is needed)"
                .to_owned()
        }
        Error::Invalid(m) => format!("not a valid OpenEXR file ({})", shortened(&m)),
        Error::NotSupported(m) => format!(
            "it uses an OpenEXR feature this reader does not support ({})",
            shortened(&m)
        ),
        Error::Io(io) => format!("cannot read it: {io}"),
        Error::Aborted => "reading it was cancelled".to_owned(),
    }
}

/// The most bytes one layer (or tile) of an OpenEXR file may decode to, over all its
/// channels: [`MAX_ENVIRONMENT_TEXELS`] × 16 (four 32-bit channels), 1 GiB.
pub const MAX_EXR_LAYER_BYTES: u64 = MAX_ENVIRONMENT_TEXELS * 16;

/// Refuses, from the headers alone and before any pixel is decompressed, a file whose
/// layers or tiles would decode to more than [`MAX_EXR_LAYER_BYTES`], or a layer whose
/// size `size_ok` refuses. The decoder sizes each block's output from the header
/// (a 779-byte file asked for 53 GB, and its pixels were decompressed even when the
/// size check below refused the layer: found by the `environment_image` fuzz target).
fn check_exr_headers(
    bytes: &[u8],
    size_ok: &impl Fn(usize, usize) -> Result<(u32, u32), String>,
) -> Result<(), String> {
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(exr_error)?;
    for (index, header) in meta.headers.iter().enumerate() {
        let bytes_per_texel: u64 = header
            .channels
            .list
            .iter()
            .map(|c| c.sample_type.bytes_per_sample() as u64)
            .sum();
        let (width, height) = (header.layer_size.width(), header.layer_size.height());
        let mut areas = vec![(format!("layer {index}"), width as u64 * height as u64)];
        if let exr::meta::BlockDescription::Tiles(tiles) = &header.blocks {
            let tile = tiles.tile_size;
            areas.push((
                format!("a tile of layer {index}"),
                tile.width() as u64 * tile.height() as u64,
            ));
        }
        for (what, area) in areas {
            let decoded = area.saturating_mul(bytes_per_texel);
            if decoded > MAX_EXR_LAYER_BYTES {
                return Err(format!(
                    "{what} would decode to {decoded} bytes ({} channels), more than the \
                     {MAX_EXR_LAYER_BYTES} an environment image may have",
                    header.channels.list.len()
                ));
            }
        }
        size_ok(width, height)?;
    }
    Ok(())
}

fn decode_exr(bytes: &[u8]) -> Result<EnvironmentImage, String> {
    let (width, height, texels) = decode_exr_rgb(bytes, check_size)?;
    Ok(EnvironmentImage {
        name: String::new(),
        width,
        height,
        texels,
    })
}

/// An OpenEXR file's first valid layer (its largest resolution level) as row-major RGB
/// from the top-left, alpha dropped, when `size_ok` takes its width and height (checked
/// before the texels are allocated: a refused size allocates nothing).
pub fn decode_exr_rgb(
    bytes: &[u8],
    size_ok: impl Fn(usize, usize) -> Result<(u32, u32), String>,
) -> Result<(u32, u32, Vec<[f32; 3]>), String> {
    use exr::prelude::*;
    check_exr_headers(bytes, &size_ok)?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |resolution, _| {
                let (w, h) = (resolution.width(), resolution.height());
                let ok = size_ok(w, h).is_ok();
                // Refused sizes allocate nothing; the size is checked again below.
                (vec![[0.0f32; 3]; if ok { w * h } else { 0 }], w, ok)
            },
            |(texels, width, ok), position, (r, g, b, _a): (f32, f32, f32, f32)| {
                if *ok {
                    texels[position.y() * *width + position.x()] = [r, g, b];
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(exr_error)?;
    let size = image.layer_data.size;
    let (width, height) = size_ok(size.width(), size.height())?;
    let (texels, _, _) = image.layer_data.channel_data.pixels;
    Ok((width, height, texels))
}

/// The studio environment's sky colour at the zenith (W·sr⁻¹·m⁻²).
pub const STUDIO_SKY: [f64; 3] = [0.60, 0.70, 0.85];
/// The studio environment's ground colour at the nadir.
pub const STUDIO_GROUND: [f64; 3] = [0.25, 0.22, 0.20];
/// The studio's soft boxes: (direction towards the box, peak radiance, exponent p of
/// the max(0, ω·k)^p falloff). A key above front left, a cooler rim behind right.
pub const STUDIO_BOXES: [([f64; 3], [f64; 3], f64); 2] = [
    ([-0.5, 0.8, 0.6], [6.0, 5.6, 5.0], 24.0),
    ([0.7, 0.3, -0.6], [2.0, 2.4, 3.0], 12.0),
];

/// Where an environment's radiance comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// The same radiance from every direction (a "white furnace" when 1, 1, 1).
    Uniform([f32; 3]),
    /// The built-in studio, an analytic radiance ([`Environment::radiance`]): a sky-to-
    /// ground gradient linear in ω_y plus two soft boxes,
    /// L(ω) = G + (S − G)(1 + ω_y)/2 + Σ_i B_i max(0, ω·k_i)^p_i
    /// with S = [`STUDIO_SKY`], G = [`STUDIO_GROUND`], (k_i, B_i, p_i) = [`STUDIO_BOXES`]
    /// (k_i normalised). Smooth everywhere, so a cube map of it has no aliasing to hide.
    Studio,
    /// An equirectangular radiance image ([`EnvironmentImage`]; `--environment FILE`).
    Image(Arc<EnvironmentImage>),
}

impl Environment {
    /// L(ω) in f64 for `direction` (need not be unit length; zero gives the gradient's
    /// middle).
    pub fn radiance(&self, direction: [f64; 3]) -> [f64; 3] {
        match self {
            Environment::Uniform(l) => l.map(f64::from),
            Environment::Studio => studio_radiance(direction),
            Environment::Image(image) => image.radiance(unit(direction)),
        }
    }

    /// Every radiance between 0 and [`crate::MAX_RADIANCE`].
    pub fn validate(&self) -> Result<(), SceneError> {
        match self {
            Environment::Uniform(l)
                if !l.iter().all(|&x| (0.0..=crate::MAX_RADIANCE).contains(&x)) =>
            {
                let [r, g, b] = l.map(crate::error::readable);
                Err(SceneError::Invalid(format!(
                    "uniform environment radiance {r} {g} {b} must be between 0 and {:e} W·sr⁻¹·m⁻²",
                    crate::MAX_RADIANCE
                )))
            }
            Environment::Image(image) => image.validate(),
            _ => Ok(()),
        }
    }

    /// A short name for logs and panels.
    pub fn name(&self) -> String {
        match self {
            Environment::Uniform(l) => format!("uniform {},{},{}", l[0], l[1], l[2]),
            Environment::Studio => "studio".into(),
            Environment::Image(image) => {
                format!("{} ({}×{})", image.name, image.width, image.height)
            }
        }
    }
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if len > 0.0 {
        v.map(|c| c / len)
    } else {
        [0.0; 3]
    }
}

/// The studio's radiance ([`Environment::Studio`]).
pub fn studio_radiance(direction: [f64; 3]) -> [f64; 3] {
    let d = unit(direction);
    let up = 0.5 * (1.0 + d[1]);
    let mut l = [0.0; 3];
    for (c, out) in l.iter_mut().enumerate() {
        *out = STUDIO_GROUND[c] + (STUDIO_SKY[c] - STUDIO_GROUND[c]) * up;
    }
    for (towards, peak, exponent) in STUDIO_BOXES {
        let k = unit(towards);
        let cos = d[0] * k[0] + d[1] * k[1] + d[2] * k[2];
        if cos > 0.0 {
            let w = cos.powf(exponent);
            for c in 0..3 {
                l[c] += peak[c] * w;
            }
        }
    }
    l
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn studio_is_the_gradient_away_from_the_boxes_and_peaks_at_them() {
        // Straight down: the ground; no box reaches below the horizon there.
        assert_eq!(studio_radiance([0.0, -1.0, 0.0]), STUDIO_GROUND);
        let k = unit(STUDIO_BOXES[0].0);
        let at_key = studio_radiance(k);
        let up = 0.5 * (1.0 + k[1]);
        let other = {
            let k2 = unit(STUDIO_BOXES[1].0);
            (k[0] * k2[0] + k[1] * k2[1] + k[2] * k2[2]).max(0.0)
        };
        for c in 0..3 {
            let gradient = STUDIO_GROUND[c] + (STUDIO_SKY[c] - STUDIO_GROUND[c]) * up;
            let expected =
                gradient + STUDIO_BOXES[0].1[c] + STUDIO_BOXES[1].1[c] * other.powf(12.0);
            assert!((at_key[c] - expected).abs() < 1e-12);
        }
    }

    /// A test's own folder in the temporary folder, removed when the test is done with
    /// it (tests of one process run side by side: each has its own).
    struct Scratch(std::path::PathBuf);

    impl Scratch {
        fn new(test: &str) -> Self {
            let dir =
                std::env::temp_dir().join(format!("combustion-env-{}-{test}", std::process::id()));
            std::fs::create_dir_all(&dir).unwrap();
            Self(dir)
        }

        fn file(&self, name: &str) -> std::path::PathBuf {
            self.0.join(name)
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// A smooth test pattern with values from 0.01 to above f16's range.
    fn pattern(x: usize, y: usize) -> [f32; 3] {
        [
            0.01 + x as f32 * 0.5,
            1.0 + y as f32 * 0.25,
            7.0e4 * (x % 2) as f32,
        ]
    }

    #[test]
    fn exr_images_read_back_exactly() {
        let scratch = Scratch::new("exr_images_read_back_exactly");
        let path = scratch.file("pattern.exr");
        exr::prelude::write_rgb_file(&path, 8, 4, |x, y| {
            let [r, g, b] = pattern(x, y);
            (r, g, b)
        })
        .unwrap();
        let image = EnvironmentImage::load(&path).unwrap();
        assert_eq!((image.width, image.height), (8, 4));
        for y in 0..4 {
            for x in 0..8 {
                assert_eq!(image.texels[y * 8 + x], pattern(x, y));
            }
        }
    }

    #[test]
    fn radiance_hdr_images_read_back_within_rgbe_precision() {
        let scratch = Scratch::new("radiance_hdr_images_read_back_within_rgbe_precision");
        use image::ImageEncoder as _;
        let path = scratch.file("pattern.hdr");
        let texels: Vec<[f32; 3]> = (0..4)
            .flat_map(|y| (0..8).map(move |x| pattern(x, y)))
            .collect();
        let file = std::fs::File::create(&path).unwrap();
        image::codecs::hdr::HdrEncoder::new(file)
            .write_image(
                bytemuck::cast_slice(&texels),
                8,
                4,
                image::ExtendedColorType::Rgb32F,
            )
            .unwrap();
        let image = EnvironmentImage::load(&path).unwrap();
        assert_eq!((image.width, image.height), (8, 4));
        for (read, written) in image.texels.iter().zip(&texels) {
            // RGBE: an 8-bit mantissa per channel under the largest channel's exponent.
            let largest = written.iter().copied().fold(0.0f32, f32::max);
            for c in 0..3 {
                assert!(
                    (read[c] - written[c]).abs() <= largest / 128.0,
                    "{read:?} against {written:?}"
                );
            }
        }
    }

    #[test]
    fn bad_environment_files_are_refused_with_the_reason() {
        let scratch = Scratch::new("bad_environment_files_are_refused_with_the_reason");
        let text = scratch.file("not-an-image.hdr");
        std::fs::write(&text, b"hello").unwrap();
        let wrong = scratch.file("image.png");
        std::fs::write(&wrong, b"\x89PNG").unwrap();
        let negative = scratch.file("negative.exr");
        exr::prelude::write_rgb_file(&negative, 2, 2, |x, _| (x as f32 - 1.0, 0.0, 0.0)).unwrap();
        // A well-formed RGBE texel of the largest exponent: 255 · 2^(255 − 136) ≈ 1.7e38,
        // and an EXR texel of 3e38 (issue 28, defect 3: each made every lit pixel NaN).
        let rgbe_max = scratch.file("largest.hdr");
        let mut bytes = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 1\n".to_vec();
        bytes.extend([255, 255, 255, 255]);
        std::fs::write(&rgbe_max, bytes).unwrap();
        let huge = scratch.file("huge.exr");
        exr::prelude::write_rgb_file(&huge, 8, 4, |x, y| {
            (if (x, y) == (3, 2) { 3e38 } else { 1.0 }, 1.0, 1.0)
        })
        .unwrap();
        // Files cut short: the decoders' own words ("failed to fill whole buffer",
        // "reference to missing bytes") replaced by what happened.
        let truncated_exr = scratch.file("truncated.exr");
        exr::prelude::write_rgb_file(&truncated_exr, 8, 4, |x, y| {
            let [r, g, b] = pattern(x, y);
            (r, g, b)
        })
        .unwrap();
        let whole = std::fs::read(&truncated_exr).unwrap();
        std::fs::write(&truncated_exr, &whole[..whole.len() * 2 / 3]).unwrap();
        let truncated_hdr = scratch.file("truncated.hdr");
        let mut hdr = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n".to_vec();
        hdr.extend([128u8, 128, 128, 129].repeat(8 * 4 - 5));
        std::fs::write(&truncated_hdr, hdr).unwrap();
        // A 779-byte file whose header declares a layer of 53 GB of samples (found by the
        // fuzzer: the decoder allocated it, and the process aborted).
        let bomb = scratch.file("bomb.exr");
        let seed = include_bytes!("../../../fuzz/seeds/environment_image/exr-decompression-bomb");
        std::fs::write(&bomb, &seed[1..]).unwrap();
        for (path, expected) in [
            (
                bomb,
                "layer 0 would decode to 53150221824 bytes (3 channels), more than the 1073741824",
            ),
            (
                truncated_exr,
                "the file ends before its pixels do (truncated or damaged)",
            ),
            (
                truncated_hdr,
                "the file ends before its pixels do (truncated or damaged)",
            ),
            (text, "environment image"),
            (wrong, "not a .hdr or .exr file"),
            (negative, "radiance must be between 0 and 1e30"),
            (rgbe_max, "radiance must be between 0 and 1e30"),
            (
                huge,
                "texel (3, 2) is 3e38 1 1: radiance must be between 0 and 1e30",
            ),
            (scratch.file("missing.exr"), "No such file"),
            (std::env::temp_dir(), "not a regular file"),
        ] {
            let message = EnvironmentImage::load(&path).unwrap_err().to_string();
            assert!(message.contains(expected), "{}: {message}", path.display());
        }
    }

    #[test]
    fn equirect_radiance_is_bilinear_and_wraps_around() {
        // 4×2 texels: columns 0…3 with radiance 0, 1, 2, 3 on both rows.
        let image = EnvironmentImage {
            name: "ramp".into(),
            width: 4,
            height: 2,
            texels: (0..8).map(|i| [(i % 4) as f32; 3]).collect(),
        };
        let along = |u: f64| {
            let phi = 2.0 * std::f64::consts::PI * (u - 0.5);
            image.radiance([phi.sin(), 0.0, -phi.cos()])[0]
        };
        // Texel centres at u = 1/8, 3/8, …; half-way between column 3 and column 0
        // (wrapping round) is 1.5; the image's centre column looks along −z.
        assert!((along(3.0 / 8.0) - 1.0).abs() < 1e-12);
        assert!((along(0.5) - 1.5).abs() < 1e-12);
        assert!((along(0.999_999_999) - 1.5).abs() < 1e-6);
        assert!((along(0.0) - 1.5).abs() < 1e-12);
        let (u, v) = equirect_coordinates([0.0, 0.0, -1.0]);
        assert!((u - 0.5).abs() < 1e-15 && (v - 0.5).abs() < 1e-15);
    }

    #[test]
    fn negative_or_nan_uniform_radiance_is_refused() {
        assert!(Environment::Uniform([1.0, -1.0, 0.0]).validate().is_err());
        assert!(Environment::Uniform([f32::NAN, 1.0, 0.0])
            .validate()
            .is_err());
        assert!(Environment::Uniform([0.0, 2.0, 1.0]).validate().is_ok());
        assert!(Environment::Studio.validate().is_ok());
    }

    /// The file-size limit is the fixed [`MAX_ENVIRONMENT_FILE_BYTES`], and the message
    /// says so in words (not by a Rust name, nor as a glTF import's limit).
    #[test]
    fn an_oversized_environment_file_names_its_limit() {
        let scratch = Scratch::new("an_oversized_environment_file_names_its_limit");
        let path = scratch.file("huge.hdr");
        // Sparse: the size is checked from the metadata, before anything is read.
        std::fs::File::create(&path)
            .unwrap()
            .set_len(MAX_ENVIRONMENT_FILE_BYTES + 1)
            .unwrap();
        let message = EnvironmentImage::load(&path).unwrap_err().to_string();
        std::fs::remove_file(&path).unwrap();
        assert!(
            message.contains(&format!(
                "is more than the {MAX_ENVIRONMENT_FILE_BYTES} bytes an environment image may have"
            )) && !message.contains("::"),
            "{message}"
        );
    }
}
