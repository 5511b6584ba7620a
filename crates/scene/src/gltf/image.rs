#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! PNG, JPEG and WebP decoding to RGBA8, with the size limit and the caller's budget
//! checked before any pixel buffer is allocated.

pub(crate) enum DecodeError {
    TooLarge { width: u32, height: u32 },
    Other(String),
}

pub(crate) struct Decoded {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

/// An image's size and the most memory its decoder holds at once, known from its header
/// before any pixel buffer is allocated; `decode` gives it to the caller's admission
/// check first.
pub(crate) struct Header {
    pub width: u32,
    pub height: u32,
    /// Bytes held at once while decoding, at least the RGBA8 pixels kept (4 a pixel):
    /// more for a decoder that works beside its output (a progressive JPEG holds every
    /// DCT coefficient until its last scan).
    pub peak_bytes: u64,
}

impl Header {
    fn new(width: u32, height: u32, bytes_per_pixel: u64) -> Header {
        let pixels = u64::from(width).saturating_mul(u64::from(height));
        Header {
            width,
            height,
            peak_bytes: pixels.saturating_mul(bytes_per_pixel.max(4)),
        }
    }
}

const PNG_MAGIC: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Whether `bytes` begin as a WebP file does (a RIFF container of form `WEBP`).
fn is_webp(bytes: &[u8]) -> bool {
    bytes.get(..4) == Some(b"RIFF".as_slice()) && bytes.get(8..12) == Some(b"WEBP".as_slice())
}

/// Decodes PNG, JPEG or WebP (told by the content; `mime` only improves the message for
/// other formats). `admit` is given the image's [`Header`] once its size is read and
/// within `max_dimension`, before any pixel buffer is allocated; its error refuses the
/// image undecoded.
pub(crate) fn decode(
    bytes: &[u8],
    mime: Option<&str>,
    max_dimension: u32,
    admit: impl FnOnce(&Header) -> Result<(), DecodeError>,
) -> Result<Decoded, DecodeError> {
    if bytes.starts_with(PNG_MAGIC) {
        decode_png(bytes, max_dimension, admit)
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        decode_jpeg(bytes, max_dimension, admit)
    } else if is_webp(bytes) {
        decode_webp(bytes, max_dimension, admit)
    } else {
        let head: Vec<String> = bytes.iter().take(8).map(|b| format!("{b:02X}")).collect();
        Err(DecodeError::Other(format!(
            "not a PNG, JPEG or WebP image{} (first bytes: {}); only PNG, JPEG and WebP are supported",
            mime.map(|m| format!(" (declared `{m}`)"))
                .unwrap_or_default(),
            if head.is_empty() {
                "none".into()
            } else {
                head.join(" ")
            }
        )))
    }
}

fn check_size(width: u32, height: u32, max: u32) -> Result<(), DecodeError> {
    if width == 0 || height == 0 {
        return Err(DecodeError::Other(format!(
            "the image is {width}×{height} pixels"
        )));
    }
    if width > max || height > max {
        return Err(DecodeError::TooLarge { width, height });
    }
    Ok(())
}

/// A PNG decoder's error in words: the png crate's own text embeds a chunk type's
/// `Debug` form (`ChunkType { type: ageg, critical: false, … }`), said here as
/// ``chunk `ageg` ``.
pub fn png_error_message(error: &png::DecodingError) -> String {
    const DEBUG: &str = "ChunkType { type: ";
    let text = error.to_string();
    let mut out = String::new();
    let mut rest = text.as_str();
    while let Some((before, after)) = rest.split_once(DEBUG) {
        out.push_str(before);
        // `find` gives a character boundary, where `split_at` splits.
        let (name, _) = after.split_at(after.find([',', ' ', '}']).unwrap_or(after.len()));
        out.push_str(&format!("chunk `{name}`"));
        rest = after.split_once('}').map_or("", |(_, rest)| rest);
    }
    out + rest
}

fn decode_png(
    bytes: &[u8],
    max: u32,
    admit: impl FnOnce(&Header) -> Result<(), DecodeError>,
) -> Result<Decoded, DecodeError> {
    let bad = |e: png::DecodingError| {
        DecodeError::Other(format!("undecodable PNG: {}", png_error_message(&e)))
    };
    // Room for the largest image allowed at 16 bits per channel, plus bookkeeping.
    let limit = u64::from(max)
        .saturating_mul(u64::from(max))
        .saturating_mul(8)
        .saturating_add(1 << 20)
        .min(usize::MAX as u64) as usize;
    let mut decoder =
        png::Decoder::new_with_limits(std::io::Cursor::new(bytes), png::Limits { bytes: limit });
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder.read_info().map_err(bad)?;
    let (width, height) = reader.info().size();
    check_size(width, height, max)?;
    // The decode itself, at most 4 bytes a pixel after `normalize_to_color8`, widened to
    // RGBA in its own buffer (the decoder's rows beside it are a few kilobytes).
    admit(&Header::new(
        width,
        height,
        (reader.output_buffer_size() as u64)
            .div_ceil(u64::from(width).saturating_mul(u64::from(height)).max(1)),
    ))?;
    let mut buffer = vec![0; reader.output_buffer_size()];
    let frame = reader.next_frame(&mut buffer).map_err(bad)?;
    if frame.bit_depth != png::BitDepth::Eight {
        return Err(DecodeError::Other(format!(
            "PNG decoded to {} bits per channel, expected 8",
            frame.bit_depth as u8
        )));
    }
    buffer.truncate(frame.buffer_size());
    let pixels = (width as usize).saturating_mul(height as usize);
    let rgba = match frame.color_type {
        // The decoder's own buffer, not a copy of it: an RGBA image is held once.
        png::ColorType::Rgba => buffer,
        png::ColorType::Rgb => expand(buffer, 3, pixels, |[r, g, b, _]| [r, g, b, 255]),
        png::ColorType::GrayscaleAlpha => expand(buffer, 2, pixels, |[l, a, _, _]| [l, l, l, a]),
        png::ColorType::Grayscale => expand(buffer, 1, pixels, |[l, _, _, _]| [l, l, l, 255]),
        png::ColorType::Indexed => {
            return Err(DecodeError::Other("indexed PNG was not expanded".into()))
        }
    };
    if Some(rgba.len()) != pixels.checked_mul(4) {
        return Err(DecodeError::Other(
            "PNG decoded to an unexpected size".into(),
        ));
    }
    Ok(Decoded {
        width,
        height,
        rgba,
    })
}

/// `data`'s first `pixels` pixels of `channels` bytes each (1 to 4; `f` is given each
/// pixel's bytes, zeros after them, and returns RGBA8) as RGBA8 by `f`, in
/// the decoder's own buffer: it is lengthened (glibc moves a large block's pages rather
/// than copying them) and filled from its last pixel back, so a pixel is written only
/// after every source at or before it was read; the decode and an RGBA copy of it are
/// never held at once. A buffer holding fewer than `pixels` pixels comes back short.
fn expand(
    mut data: Vec<u8>,
    channels: usize,
    pixels: usize,
    f: impl Fn([u8; 4]) -> [u8; 4],
) -> Vec<u8> {
    debug_assert!((1..=4).contains(&channels));
    let (Some(source_bytes), Some(rgba_bytes)) =
        (pixels.checked_mul(channels), pixels.checked_mul(4))
    else {
        return data;
    };
    if data.len() < source_bytes || !(1..=4).contains(&channels) {
        return data;
    }
    data.truncate(source_bytes);
    data.resize(rgba_bytes, 0);
    // i < pixels: every offset below is within `rgba_bytes`, which did not overflow.
    for i in (0..pixels).rev() {
        let mut source = [0; 4];
        let from = i.saturating_mul(channels);
        if let (Some(to), Some(bytes)) = (
            source.get_mut(..channels),
            data.get(from..from.saturating_add(channels)),
        ) {
            to.copy_from_slice(bytes);
        }
        let at = i.saturating_mul(4);
        if let Some(out) = data.get_mut(at..at.saturating_add(4)) {
            out.copy_from_slice(&f(source));
        }
    }
    data
}

/// The most a JPEG's decoder (jpeg-decoder, without rayon) holds at once, from its
/// header. The decoder does not tell its components' sampling, so each is taken at full
/// resolution, the size rounded up to the largest MCU (32 pixels). Per sample: the
/// component's plane (1 byte) and the DCT coefficients of rows queued to the decoder's
/// threads, up to every row if they lag (2); a progressive JPEG also holds every
/// coefficient until its last scan (2); a lossless JPEG its differences (4-byte values
/// in vectors grown by doubling, 8), its 16-bit planes and their interleaved copy (4).
/// Beside them the interleaved output; or, if more, the RGBA8 pixels the output is
/// widened to.
fn jpeg_peak(info: &jpeg_decoder::ImageInfo) -> Header {
    use jpeg_decoder::{CodingProcess, PixelFormat};
    let (width, height) = (u32::from(info.width), u32::from(info.height));
    let components: u64 = match info.pixel_format {
        PixelFormat::L8 | PixelFormat::L16 => 1,
        PixelFormat::RGB24 => 3,
        PixelFormat::CMYK32 => 4,
    };
    let sample_bytes: u64 = match info.coding_process {
        CodingProcess::DctSequential => 1 + 2,
        CodingProcess::DctProgressive => 1 + 2 + 2,
        CodingProcess::Lossless => 8 + 4,
    };
    let padded = |side: u16| u64::from(side).div_ceil(32).saturating_mul(32);
    let pixels = u64::from(width).saturating_mul(u64::from(height));
    let working = padded(info.width)
        .saturating_mul(padded(info.height))
        .saturating_mul(components.saturating_mul(sample_bytes))
        .saturating_add(pixels.saturating_mul(info.pixel_format.pixel_bytes() as u64));
    Header {
        width,
        height,
        peak_bytes: working.max(pixels.saturating_mul(4)),
    }
}

fn decode_jpeg(
    bytes: &[u8],
    max: u32,
    admit: impl FnOnce(&Header) -> Result<(), DecodeError>,
) -> Result<Decoded, DecodeError> {
    let bad = |e: jpeg_decoder::Error| DecodeError::Other(format!("undecodable JPEG: {e}"));
    let mut decoder = jpeg_decoder::Decoder::new(bytes);
    decoder.read_info().map_err(bad)?;
    let info = decoder
        .info()
        .ok_or_else(|| DecodeError::Other("undecodable JPEG: no frame header".into()))?;
    let (width, height) = (u32::from(info.width), u32::from(info.height));
    check_size(width, height, max)?;
    admit(&jpeg_peak(&info))?;
    decoder.set_max_decoding_buffer_size(
        u64::from(max)
            .saturating_mul(u64::from(max))
            .saturating_mul(4)
            .min(usize::MAX as u64) as usize,
    );
    let data = decoder.decode().map_err(bad)?;
    let decoded_bytes = data.len();
    let pixels = (width as usize).saturating_mul(height as usize);
    use jpeg_decoder::PixelFormat;
    let rgba = match info.pixel_format {
        PixelFormat::L8 => expand(data, 1, pixels, |[l, _, _, _]| [l, l, l, 255]),
        // Big-endian 16-bit: keep the high byte.
        PixelFormat::L16 => expand(data, 2, pixels, |[high, _, _, _]| [high, high, high, 255]),
        PixelFormat::RGB24 => expand(data, 3, pixels, |[r, g, b, _]| [r, g, b, 255]),
        PixelFormat::CMYK32 => expand(data, 4, pixels, |[c_, m, y, k]| {
            // (255 − x)(255 − k)/255, rounded: `!x` is 255 − x for a byte, and the
            // product is at most 255², so the sums fit in u16 and the result in a byte.
            let k = u16::from(!k);
            let c = |x: u8| (u16::from(!x).saturating_mul(k).saturating_add(127) / 255) as u8;
            [c(c_), c(m), c(y), 255]
        }),
    };
    if Some(rgba.len()) != pixels.checked_mul(4) {
        return Err(DecodeError::Other(format!(
            "undecodable JPEG: {decoded_bytes} bytes of pixels for {width}×{height}"
        )));
    }
    Ok(Decoded {
        width,
        height,
        rgba,
    })
}

/// WebP (EXT_texture_webp), lossy or lossless, with or without alpha; an animation's
/// first frame.
fn decode_webp(
    bytes: &[u8],
    max: u32,
    admit: impl FnOnce(&Header) -> Result<(), DecodeError>,
) -> Result<Decoded, DecodeError> {
    let bad = |e: image_webp::DecodingError| DecodeError::Other(format!("undecodable WebP: {e}"));
    let mut decoder = image_webp::WebPDecoder::new(std::io::Cursor::new(bytes)).map_err(bad)?;
    let (width, height) = decoder.dimensions();
    check_size(width, height, max)?;
    // The decoder's buffers at once, per pixel: its output (3 or 4 bytes) and, lossless,
    // an ARGB decode (4); lossy, the Y, U and V planes (1.5) and an alpha channel decoded
    // through an ARGB image (4 + 1); an animation's frame is decoded beside its canvas
    // (4 more). At most 12 bytes a pixel, 16 for an animation.
    admit(&Header::new(
        width,
        height,
        if decoder.is_animated() { 16 } else { 12 },
    ))?;
    // The largest image allowed, as RGBA, plus bookkeeping.
    decoder.set_memory_limit(
        u64::from(max)
            .saturating_mul(u64::from(max))
            .saturating_mul(4)
            .saturating_add(1 << 20)
            .min(usize::MAX as u64) as usize,
    );
    let size = decoder
        .output_buffer_size()
        .ok_or_else(|| DecodeError::Other("undecodable WebP: its size overflows".into()))?;
    let mut data = vec![0; size];
    decoder.read_image(&mut data).map_err(bad)?;
    let pixels = (width as usize).saturating_mul(height as usize);
    let rgba = if decoder.has_alpha() {
        data
    } else {
        expand(data, 3, pixels, |[r, g, b, _]| [r, g, b, 255])
    };
    if Some(rgba.len()) != pixels.checked_mul(4) {
        return Err(DecodeError::Other(format!(
            "undecodable WebP: {} bytes of pixels for {width}×{height}",
            rgba.len()
        )));
    }
    Ok(Decoded {
        width,
        height,
        rgba,
    })
}

/// Encodes RGBA8 as PNG.
pub(crate) fn encode_png(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
        writer.write_image_data(rgba).map_err(|e| e.to_string())?;
        writer.finish().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

#[cfg(test)]
#[allow(clippy::arithmetic_side_effects, clippy::indexing_slicing)] // the tests' own data
mod tests {
    use super::expand;

    /// Expanding in the decoder's buffer gives what a copy into a new buffer gives, for
    /// every channel count, and a short buffer comes back short (the callers refuse it).
    #[test]
    fn expanding_in_place_matches_a_copy() {
        let pixels = 1000;
        for channels in 1..=4 {
            let data: Vec<u8> = (0..pixels * channels)
                .map(|i| (i * 7 % 251) as u8)
                .collect();
            let f = move |p: [u8; 4]| {
                let mut out = [255; 4];
                out[..channels].copy_from_slice(&p[..channels]);
                out
            };
            let copied: Vec<u8> = data
                .chunks_exact(channels)
                .flat_map(|p| {
                    let mut source = [0; 4];
                    source[..channels].copy_from_slice(p);
                    f(source)
                })
                .collect();
            assert_eq!(
                expand(data.clone(), channels, pixels, f),
                copied,
                "{channels}"
            );
            // Extra bytes past the pixels are dropped; too few leave the buffer short.
            let mut longer = data.clone();
            longer.extend([9; 5]);
            assert_eq!(expand(longer, channels, pixels, f), copied, "{channels}");
            let short = expand(data[..data.len() - 1].to_vec(), channels, pixels, f);
            assert!(short.len() < pixels * 4, "{channels}");
        }
    }
}
