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
    /// A folder the output needs (its own folder, a report's folder, or one of their
    /// parents) is an existing file.
    #[error("cannot write {path}: {file} is a file, not a folder")]
    NotAFolder {
        /// The output path as given.
        path: PathBuf,
        /// The file in the way.
        file: PathBuf,
    },
    /// The output path is empty.
    #[error("cannot write to an empty file name")]
    EmptyName,
    /// The output's file name is longer than file systems take.
    #[error("cannot write {path}: its file name is {bytes} bytes long, past the {MAX_FILE_NAME_BYTES} a file name may have")]
    NameTooLong {
        /// The output path as given.
        path: PathBuf,
        /// Its file name's length in bytes.
        bytes: usize,
    },
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
    /// The output is one of the run's input files (the same file by any name: a link, a
    /// hard link), which writing would destroy.
    #[error("cannot write {path}: it is the {what} this run reads ({input}); name another output")]
    IsAnInput {
        /// The output path as given.
        path: PathBuf,
        /// What the input is to the run ("scene file", "environment image", …).
        what: &'static str,
        /// The input's path as given.
        input: PathBuf,
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

/// The longest file name, in bytes, the file systems the tool writes to take (Linux's
/// NAME_MAX).
const MAX_NAME_BYTES: usize = 255;

/// The name of the temporary file `.NAME.KIND-PID-N` beside a file named `name`, NAME cut
/// short (at a character) where the whole would pass [`MAX_NAME_BYTES`]: an output whose
/// own name fits must not be refused because its temporary name does not.
fn temporary_name(name: &str, kind: &str, n: u32) -> String {
    let suffix = format!(".{kind}-{}-{n}", std::process::id());
    let budget = MAX_NAME_BYTES.saturating_sub(1 + suffix.len());
    let mut end = name.len().min(budget);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    format!(".{}{suffix}", &name[..end])
}

/// The temporary files this process has made and not yet renamed or removed: what a
/// terminating signal removes ([`remove_partial_files_on_termination`]).
static TEMPORARY_FILES: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

fn temporary_files() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    // A panic while the list was held leaves it as it was: still the right list.
    TEMPORARY_FILES
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// `path`, a temporary file, is renamed into place or removed: no longer this process's
/// to clean up.
fn forget_temporary(path: &Path) {
    temporary_files().retain(|p| p != path);
}

/// Removes `path`, a temporary file, and forgets it.
fn remove_temporary(path: &Path) {
    let _ = std::fs::remove_file(path);
    forget_temporary(path);
}

/// From now on, SIGINT, SIGTERM and SIGHUP end the process only after removing the
/// temporary files of writes in progress (`.NAME.partial-PID-N`, `.NAME.probe-PID-N`),
/// so an interrupted command leaves every output as it was or complete, and nothing
/// else. The signals are blocked in every thread and taken by one thread of their own
/// (call this first in `main`, before other threads start: they inherit the mask); it
/// ends the process by the same signal, so the exit status says which. SIGKILL cannot
/// be caught: it leaves the temporary file of a write in progress behind.
#[cfg(unix)]
pub fn remove_partial_files_on_termination() {
    const SIGNALS: [libc::c_int; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];
    // SAFETY: the set is initialised by sigemptyset before use; pthread_sigmask and
    // sigwait take pointers to it and to a local integer only.
    unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        for signal in SIGNALS {
            libc::sigaddset(&mut set, signal);
        }
        if libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut()) != 0 {
            return;
        }
        let spawned = std::thread::Builder::new()
            .name("termination".into())
            .spawn(move || {
                let mut signal: libc::c_int = 0;
                while libc::sigwait(&set, &mut signal) != 0 {}
                for path in temporary_files().drain(..) {
                    let _ = std::fs::remove_file(path);
                }
                // End as the signal would have: its default action, delivered unblocked.
                libc::signal(signal, libc::SIG_DFL);
                libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
                libc::raise(signal);
                libc::_exit(128 + signal);
            });
        if spawned.is_err() {
            // No thread to take them: the signals keep their default action.
            libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
        }
    }
}

/// Elsewhere the signals keep their default action.
#[cfg(not(unix))]
pub fn remove_partial_files_on_termination() {}

/// A new file beside `path`, `.NAME.KIND-PID-N` ([`temporary_name`]), made with
/// `create_new` (never following a planted link or truncating a file already there: a
/// name in use is skipped); listed for removal by a terminating signal until
/// [`forget_temporary`].
fn create_new_beside(path: &Path, kind: &str) -> std::io::Result<(PathBuf, File)> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut last = None;
    for n in 0..100 {
        let candidate = path.with_file_name(temporary_name(&name, kind, n));
        // Made and listed under the list's lock, so a signal never finds it made and
        // not listed.
        let mut listed = temporary_files();
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&candidate)
        {
            Ok(file) => {
                listed.push(candidate.clone());
                return Ok((candidate, file));
            }
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

/// The longest file name an output may have, in bytes (NAME_MAX of Linux's file
/// systems; the name is refused before anything renders, not when it is written).
pub const MAX_FILE_NAME_BYTES: usize = 255;

/// Checks, before any work is done, that `path` can be written by the rule of this
/// module, and returns the file that will be written: `path` itself, or the end of
/// the symlink chain it starts.
pub fn check_writable(path: &Path) -> Result<PathBuf, OutputError> {
    let named = path.to_path_buf();
    if path.as_os_str().is_empty() {
        return Err(OutputError::EmptyName);
    }
    // A name ending in `/`, `.` or `..` names a folder (Rust's `Path` reads `a/.` as `a`,
    // which would pass the checks below for a file `a` and fail only at the write).
    let bytes = path.as_os_str().as_encoded_bytes();
    let last = bytes.rsplit(|&b| b == b'/').next().unwrap_or_default();
    if bytes.ends_with(b"/") || last == b"." || last == b".." || path.file_name().is_none() {
        return Err(OutputError::FolderName { path: named });
    }
    if last.len() > MAX_FILE_NAME_BYTES {
        return Err(OutputError::NameTooLong {
            path: named,
            bytes: last.len(),
        });
    }
    // What the whole chain names, as the kernel resolves it: a pipe or terminal behind
    // `/dev/stdout` or `/proc/self/fd/N` ends in a name (`pipe:[N]`) that is no file.
    if let Ok(meta) = std::fs::metadata(path) {
        if !meta.is_file() && !meta.is_dir() {
            return Err(OutputError::NotRegular { path: named });
        }
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
                    return Err(match file_in_the_way(&folder) {
                        Some(file) => OutputError::NotAFolder { path: named, file },
                        None => OutputError::NoFolder {
                            path: named,
                            folder,
                        },
                    });
                }
                // The folder takes a new file (the temporary one is made there).
                let (probe, _) =
                    create_new_beside(&target, "probe").map_err(|source| OutputError::Io {
                        path: named.clone(),
                        source,
                    })?;
                remove_temporary(&probe);
                return Ok(target);
            }
        }
    }
    Err(OutputError::SymlinkLoop { path: named })
}

/// The first of `folder` and its parents that exists as something other than a folder.
fn file_in_the_way(folder: &Path) -> Option<PathBuf> {
    folder
        .ancestors()
        .find(|a| !a.as_os_str().is_empty() && a.exists())
        .filter(|a| !a.is_dir())
        .map(Path::to_path_buf)
}

/// Makes the output folder `dir` and its parents (a report's or a batch's). A file in
/// the way is named as such (the system says only "File exists").
pub fn make_folder(dir: &Path) -> Result<(), OutputError> {
    if let Some(file) = file_in_the_way(dir) {
        return Err(OutputError::NotAFolder {
            path: dir.to_path_buf(),
            file,
        });
    }
    std::fs::create_dir_all(dir).map_err(|source| OutputError::Io {
        path: dir.to_path_buf(),
        source,
    })
}

/// Whether two checked outputs ([`check_writable`]'s results) are one file: the same
/// name in the same folder, folders compared after resolving their own links.
pub fn same_file(a: &Path, b: &Path) -> bool {
    let canonical_folder = |p: &Path| std::fs::canonicalize(folder_of(p)).ok();
    a.file_name() == b.file_name()
        && canonical_folder(a).is_some()
        && canonical_folder(a) == canonical_folder(b)
}

/// Refuses `output` (as given to its option) when it is one of the run's `inputs`
/// (what each is to the run, and its path): the same file by whatever name, a symbolic
/// or hard link included. An output that does not exist yet is no input.
pub fn check_not_an_input(
    output: &Path,
    inputs: &[(&'static str, &Path)],
) -> Result<(), OutputError> {
    for &(what, input) in inputs {
        if same_existing_file(output, input) {
            return Err(OutputError::IsAnInput {
                path: output.to_path_buf(),
                what,
                input: input.to_path_buf(),
            });
        }
    }
    Ok(())
}

/// Whether `a` and `b` both exist and are one file (after links; the same device and
/// inode on Unix, the same canonical path elsewhere).
pub fn same_existing_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!(
            (std::fs::canonicalize(a), std::fs::canonicalize(b)),
            (Ok(x), Ok(y)) if x == y
        )
    }
}

/// Gives `file` the owner and group of `replaced` when they differ from this process's
/// and it may (as root); otherwise the file stays this process's, as any new file.
#[cfg(unix)]
fn keep_owner(file: &File, replaced: &std::fs::Metadata) {
    use std::os::unix::fs::MetadataExt;
    let Ok(own) = file.metadata() else { return };
    if (own.uid(), own.gid()) != (replaced.uid(), replaced.gid()) {
        let _ = std::os::unix::fs::fchown(file, Some(replaced.uid()), Some(replaced.gid()));
    }
}

#[cfg(not(unix))]
fn keep_owner(_file: &File, _replaced: &std::fs::Metadata) {}

/// A file written in full beside the one it will replace, not yet renamed into place.
struct Staged {
    temporary: PathBuf,
    target: PathBuf,
}

impl Staged {
    /// Writes what `write` writes to a temporary file beside the file `path` names (by
    /// [`check_writable`]'s rule), on disk before it returns; removed again on failure.
    fn new(
        path: &Path,
        write: impl FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
    ) -> Result<Staged, OutputError> {
        let target = check_writable(path)?;
        let io = |source| OutputError::Io {
            path: target.clone(),
            source,
        };
        let (temporary, file) = create_new_beside(&target, "partial").map_err(io)?;
        let result = (|| {
            // The replaced file's permissions carry over (a new file gets the umask's),
            // and its owner where this process may give it (root replacing a user's
            // 0600 file must not leave a file the user can no longer read).
            if let Ok(meta) = std::fs::metadata(&target) {
                file.set_permissions(meta.permissions()).map_err(io)?;
                keep_owner(&file, &meta);
            }
            let mut writer = BufWriter::new(file);
            write(&mut writer)?;
            writer.flush().map_err(io)?;
            let file = writer.into_inner().map_err(|e| io(e.into_error()))?;
            // On disk before it takes the name, so a crash leaves the old file or the new.
            file.sync_all().map_err(io)
        })();
        match result {
            Ok(()) => Ok(Staged { temporary, target }),
            Err(e) => {
                remove_temporary(&temporary);
                Err(e)
            }
        }
    }

    /// Renames the file into place.
    fn commit(self) -> Result<(), OutputError> {
        let result =
            std::fs::rename(&self.temporary, &self.target).map_err(|source| OutputError::Io {
                path: self.target.clone(),
                source,
            });
        if result.is_err() {
            let _ = std::fs::remove_file(&self.temporary);
        }
        forget_temporary(&self.temporary);
        result
    }

    /// Removes the staged file, leaving the target as it was.
    fn discard(self) {
        remove_temporary(&self.temporary);
    }
}

fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
) -> Result<(), OutputError> {
    Staged::new(path, write)?.commit()
}

/// Writes every `(path, bytes)` as one set: each checked and written in full beside its
/// target first; only when all are on disk is each renamed into place. A file that
/// cannot be written leaves every target as it was (the renames that follow are the
/// only steps left to fail, each of one name in a folder already written to).
pub fn write_files_atomically(files: &[(PathBuf, Vec<u8>)]) -> Result<(), OutputError> {
    let mut staged = Vec::with_capacity(files.len());
    for (path, bytes) in files {
        let written = Staged::new(path, |writer| {
            writer.write_all(bytes).map_err(|source| OutputError::Io {
                path: path.clone(),
                source,
            })
        });
        match written {
            Ok(file) => staged.push(file),
            Err(e) => {
                staged.into_iter().for_each(Staged::discard);
                return Err(e);
            }
        }
    }
    let mut staged = staged.into_iter();
    for file in staged.by_ref() {
        if let Err(e) = file.commit() {
            staged.for_each(Staged::discard);
            return Err(e);
        }
    }
    Ok(())
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

    /// Issue 28, defect 6: an output name of 241–255 bytes was refused ("File name too
    /// long") because the temporary name beside it is longer; it now cuts the name short
    /// and the output is written, with nothing left beside it.
    #[test]
    fn an_output_name_near_the_limit_is_written() {
        let dir = std::env::temp_dir().join(format!("combustion-long-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let names = [
            format!("{}.png", "a".repeat(MAX_NAME_BYTES - 4)),
            format!("{}.png", "a".repeat(240)),
            format!("{}.png", "é".repeat((MAX_NAME_BYTES - 4) / 2)),
        ];
        for name in &names {
            assert!(name.len() <= MAX_NAME_BYTES);
            let temporary = temporary_name(name, "partial", 99);
            assert!(temporary.len() <= MAX_NAME_BYTES, "{}", temporary.len());
            let path = dir.join(name);
            write_png(&path, 1, 1, &[[0; 4]]).unwrap();
            assert!(path.is_file());
            std::fs::remove_file(&path).unwrap();
        }
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert!(left.is_empty(), "{left:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Issue 28, defect 6: files written as a set — when one cannot be written (here a
    /// folder stands where it would go), none is replaced and nothing is left beside
    /// them.
    #[test]
    fn a_set_of_files_is_written_whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("combustion-set-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("b.csv")).unwrap();
        std::fs::write(dir.join("a.csv"), "old").unwrap();
        let files = [
            (dir.join("a.csv"), b"new".to_vec()),
            (dir.join("b.csv"), b"new".to_vec()),
        ];
        let error = write_files_atomically(&files).unwrap_err().to_string();
        assert!(error.contains("b.csv"), "{error}");
        assert_eq!(std::fs::read_to_string(dir.join("a.csv")).unwrap(), "old");
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        assert_eq!(names, ["a.csv", "b.csv"]);
        std::fs::remove_dir(dir.join("b.csv")).unwrap();
        write_files_atomically(&files).unwrap();
        for name in ["a.csv", "b.csv"] {
            assert_eq!(std::fs::read_to_string(dir.join(name)).unwrap(), "new");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn missing_folder_is_a_clear_error_and_leaves_nothing() {
        let err = write_png(Path::new("/nonexistent-folder/out.png"), 1, 1, &[[0; 4]]).unwrap_err();
        assert!(err.to_string().contains("does not exist"), "{err}");
    }
}
