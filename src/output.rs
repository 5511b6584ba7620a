//! Writing frames to files: PNG (8-bit sRGB) and OpenEXR (32-bit float, ZIP-compressed).
//!
//! The rule for every output path: an output is a regular file, written to a temporary
//! name in its folder and renamed into place, so a failure never leaves a half-written
//! file behind. A symlink is followed to its target (the target is replaced, the link
//! stays); an existing special file (device, FIFO, socket) or read-only file is refused,
//! never replaced; an empty name or one ending in `/` is refused; the folder must exist
//! and take a new file, checked before any work is done ([`check_writable`]).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// A file-system operation failed (reading a link, creating, writing, syncing or
    /// renaming the file).
    #[error("cannot write {path}: {source}")]
    Io {
        /// The output path as given.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The folder the file would be written in does not exist.
    #[error("cannot write {path}: folder {folder} does not exist")]
    NoFolder {
        /// The output path as given.
        path: PathBuf,
        /// The missing folder.
        folder: PathBuf,
    },
    /// The output path is empty.
    #[error("cannot write to an empty file name")]
    EmptyName,
    /// The output path names a folder (or ends in `/`).
    #[error("cannot write {path}: it names a folder, not a file")]
    FolderName {
        /// The output path as given.
        path: PathBuf,
    },
    /// The output path is an existing special file (device, FIFO, socket), never
    /// replaced.
    #[error("cannot write {path}: it is not a regular file (a device, FIFO or socket); write to a regular file")]
    NotRegular {
        /// The output path as given.
        path: PathBuf,
    },
    /// The output path is an existing file this process may not write, left as it is.
    #[error("cannot write {path}: it is read-only; it is left as it is")]
    ReadOnly {
        /// The output path as given.
        path: PathBuf,
    },
    /// The output path starts a chain of more than 40 symlinks, or a circular one.
    #[error("cannot write {path}: the symlink chain is too long or circular")]
    SymlinkLoop {
        /// The output path as given.
        path: PathBuf,
    },
    /// The PNG encoder failed.
    #[error("cannot encode PNG {path}: {message}")]
    Png {
        /// The output path.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
    /// The OpenEXR encoder failed.
    #[error("cannot encode OpenEXR {path}: {message}")]
    Exr {
        /// The output path.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
    /// The pixels given are not `width · height`.
    #[error("{path}: {count} pixels given for a {width}x{height} image")]
    SizeMismatch {
        /// The output path.
        path: PathBuf,
        /// Pixels given.
        count: usize,
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
    },
}

/// A new file beside `path`, `.NAME.KIND-PID-N`, made with `create_new` (never following a
/// planted link or truncating a file already there: a name in use is skipped).
fn create_new_beside(path: &Path, kind: &str) -> std::io::Result<(PathBuf, File)> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut last = None;
    for n in 0..100 {
        let candidate = path.with_file_name(format!(".{name}.{kind}-{}-{n}", std::process::id()));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&candidate)
        {
            Ok(file) => return Ok((candidate, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| std::io::Error::other("no free temporary name")))
}

/// The folder `path` is in (`.` for a bare file name).
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Extensions of image formats the command line may be given by mistake.
const IMAGE_EXTENSIONS: [&str; 12] = [
    "png", "exr", "jpg", "jpeg", "hdr", "bmp", "tga", "tif", "tiff", "webp", "gif", "ppm",
];

/// Refuses `path` (given to `option`, which writes `format`) when its extension names
/// another image format than `expected` (compared without case): `-o a.jpg` would get
/// PNG bytes under a JPEG name. No extension, or one of no image format, is left alone.
pub fn check_extension(
    path: &Path,
    option: &str,
    format: &str,
    expected: &[&str],
) -> Result<(), crate::Error> {
    let Some(extension) = path.extension().and_then(|e| e.to_str()) else {
        return Ok(());
    };
    let extension = extension.to_ascii_lowercase();
    if IMAGE_EXTENSIONS.contains(&extension.as_str()) && !expected.contains(&extension.as_str()) {
        return Err(crate::Error::Usage(format!(
            "{option} {}: {option} writes {format}, but `.{extension}` names another format; name the file .{}",
            crate::shortened(&path.display().to_string()),
            expected[0]
        )));
    }
    Ok(())
}

/// Checks, before any work is done, that `path` can be written by the rule of this
/// module, and returns the file that will be written: `path` itself, or the end of
/// the symlink chain it starts.
pub fn check_writable(path: &Path) -> Result<PathBuf, OutputError> {
    let named = path.to_path_buf();
    if path.as_os_str().is_empty() {
        return Err(OutputError::EmptyName);
    }
    if path.as_os_str().as_encoded_bytes().ends_with(b"/") || path.file_name().is_none() {
        return Err(OutputError::FolderName { path: named });
    }
    // Follow symlinks to the file they name (up to 40 links, as the kernel does).
    let mut target = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&target) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let next = std::fs::read_link(&target).map_err(|source| OutputError::Io {
                    path: named.clone(),
                    source,
                })?;
                target = folder_of(&target).join(next);
            }
            Ok(meta) if meta.is_dir() => return Err(OutputError::FolderName { path: named }),
            Ok(meta) if !meta.is_file() => return Err(OutputError::NotRegular { path: named }),
            // Read-only by its mode bits (which root would override), or not writable by
            // this user (opened for writing without truncating: nothing changes).
            Ok(meta)
                if meta.permissions().readonly()
                    || std::fs::OpenOptions::new()
                        .write(true)
                        .open(&target)
                        .is_err() =>
            {
                return Err(OutputError::ReadOnly { path: named })
            }
            _ => {
                let folder = folder_of(&target);
                if !folder.is_dir() {
                    return Err(OutputError::NoFolder {
                        path: named,
                        folder,
                    });
                }
                // The folder takes a new file (the temporary one is made there).
                let (probe, _) =
                    create_new_beside(&target, "probe").map_err(|source| OutputError::Io {
                        path: named.clone(),
                        source,
                    })?;
                let _ = std::fs::remove_file(&probe);
                return Ok(target);
            }
        }
    }
    Err(OutputError::SymlinkLoop { path: named })
}

/// Whether two checked outputs ([`check_writable`]'s results) are one file: the same
/// name in the same folder, folders compared after resolving their own links.
pub fn same_file(a: &Path, b: &Path) -> bool {
    let canonical_folder = |p: &Path| std::fs::canonicalize(folder_of(p)).ok();
    a.file_name() == b.file_name()
        && canonical_folder(a).is_some()
        && canonical_folder(a) == canonical_folder(b)
}

fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
) -> Result<(), OutputError> {
    let target = check_writable(path)?;
    let path = target.as_path();
    let io = |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    let (temporary, file) = create_new_beside(path, "partial").map_err(io)?;
    let result = (|| {
        // The replaced file's permissions carry over (a new file gets the umask's).
        if let Ok(meta) = std::fs::metadata(path) {
            file.set_permissions(meta.permissions()).map_err(io)?;
        }
        let mut writer = BufWriter::new(file);
        write(&mut writer)?;
        writer.flush().map_err(io)?;
        let file = writer.into_inner().map_err(|e| io(e.into_error()))?;
        // On disk before it takes the name, so a crash leaves the old file or the new.
        file.sync_all().map_err(io)?;
        drop(file);
        std::fs::rename(&temporary, path).map_err(io)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// Writes `bytes` to `path` atomically: to a temporary file in the same folder, renamed into
/// place when complete (an encoded plot, say).
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    write_atomically(path, |writer| {
        writer.write_all(bytes).map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            source,
        })
    })
}

fn check_pixel_count(
    path: &Path,
    width: u32,
    height: u32,
    count: usize,
) -> Result<(), OutputError> {
    if count == width as usize * height as usize {
        Ok(())
    } else {
        Err(OutputError::SizeMismatch {
            path: path.to_path_buf(),
            count,
            width,
            height,
        })
    }
}

/// Writes 8-bit sRGB RGBA pixels as a PNG (sRGB chunk set).
pub fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    rgba: &[[u8; 4]],
) -> Result<(), OutputError> {
    check_pixel_count(path, width, height, rgba.len())?;
    write_atomically(path, |writer| {
        let png_error = |e: png::EncodingError| OutputError::Png {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        let mut encoder = png::Encoder::new(writer, width, height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut png_writer = encoder.write_header().map_err(png_error)?;
        png_writer
            .write_image_data(rgba.as_flattened())
            .map_err(png_error)?;
        png_writer.finish().map_err(png_error)
    })
}

/// Writes linear RGB radiance as an OpenEXR file with 32-bit float R, G, B channels
/// (alpha dropped), ZIP-compressed scan lines (lossless: the file reads back bit for bit),
/// through the `exr` crate.
pub fn write_exr(
    path: &Path,
    width: u32,
    height: u32,
    rgba: &[[f32; 4]],
) -> Result<(), OutputError> {
    use exr::prelude::*;
    check_pixel_count(path, width, height, rgba.len())?;
    let row = width as usize;
    let channels = SpecificChannels::rgb(|at: Vec2<usize>| {
        let [r, g, b, _] = rgba[at.y() * row + at.x()];
        (r, g, b)
    });
    let encoding = Encoding {
        compression: Compression::ZIP16,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let image = Image::from_encoded_channels((row, height as usize), encoding, channels);
    write_atomically(path, |writer| {
        image
            .write()
            .to_buffered(writer)
            .map_err(|e| OutputError::Exr {
                path: path.to_path_buf(),
                message: e.to_string(),
            })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_folder_is_a_clear_error_and_leaves_nothing() {
        let err = write_png(Path::new("/nonexistent-folder/out.png"), 1, 1, &[[0; 4]]).unwrap_err();
        assert!(err.to_string().contains("does not exist"), "{err}");
    }
}
