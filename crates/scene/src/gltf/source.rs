#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! The container (GLB or JSON), URIs (`data:`, relative files, and what is refused) and
//! buffers.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::rc::Rc;

use gltf::json;

use super::ImportProblem;

/// A parsed container: the JSON text and the GLB binary chunk, if any.
pub(crate) struct Container<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
    pub is_glb: bool,
}

pub(crate) fn split_container<'a>(
    bytes: &'a [u8],
    warnings: &mut Vec<String>,
) -> Result<Container<'a>, ImportProblem> {
    if !bytes.starts_with(b"glTF") {
        let json = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        if json.len() != bytes.len() {
            warnings
                .push("the JSON starts with a byte-order mark, which glTF forbids; ignored".into());
        }
        return Ok(Container {
            json,
            bin: None,
            is_glb: false,
        });
    }
    let glb = |m: String| ImportProblem::Glb(m);
    let u32_at = |at: usize| -> Option<u32> {
        let word: [u8; 4] = bytes.get(at..at.checked_add(4)?)?.try_into().ok()?;
        Some(u32::from_le_bytes(word))
    };
    let (Some(version), Some(length)) = (u32_at(4), u32_at(8)) else {
        return Err(glb(format!(
            "truncated: {} bytes, but the GLB header alone is 12",
            bytes.len()
        )));
    };
    if version != 2 {
        return Err(glb(format!(
            "version {version}; only GLB version 2 (glTF 2.0) is supported"
        )));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(glb(format!(
            "truncated: the header declares {length} bytes but the file has {}",
            bytes.len()
        )));
    }
    if length < bytes.len() {
        warnings.push(format!(
            "GLB: ignoring {} bytes after the declared length of {length}",
            bytes.len().saturating_sub(length)
        ));
    }
    // Within the file: checked above.
    let data = bytes.get(..length).unwrap_or(bytes);
    let mut offset: usize = 12;
    let mut json = None;
    let mut bin = None;
    let mut index: usize = 0;
    while offset < data.len() {
        // Offsets stay within the file (at most isize::MAX bytes): the sums below do not
        // overflow, saturating if they did.
        let start = offset.saturating_add(8);
        let header: [u8; 8] = data
            .get(offset..start)
            .and_then(|h| h.try_into().ok())
            .ok_or_else(|| {
                glb(format!(
                    "truncated: chunk {index} at byte {offset} has no complete 8-byte header"
                ))
            })?;
        let [l0, l1, l2, l3, k0, k1, k2, k3] = header;
        let chunk_length = u32::from_le_bytes([l0, l1, l2, l3]) as usize;
        let kind = [k0, k1, k2, k3];
        let body = data
            .get(start..)
            .and_then(|rest| rest.get(..chunk_length))
            .ok_or_else(|| {
                glb(format!(
                    "truncated: chunk {index} ({}) at byte {offset} declares {chunk_length} bytes but only {} remain",
                    chunk_name(kind),
                    data.len().saturating_sub(start)
                ))
            })?;
        match &kind {
            b"JSON" if index == 0 => json = Some(body),
            b"JSON" => return Err(glb(format!("a second JSON chunk (chunk {index})"))),
            b"BIN\0" if index == 1 => bin = Some(body),
            b"BIN\0" => {
                return Err(glb(format!(
                    "BIN chunk at position {index}; it must directly follow the JSON chunk"
                )))
            }
            _ if index == 0 => {
                return Err(glb(format!(
                    "the first chunk is {}, not JSON",
                    chunk_name(kind)
                )))
            }
            _ => warnings.push(format!(
                "GLB: ignoring chunk {index} of unknown type {}",
                chunk_name(kind)
            )),
        }
        // Chunks are padded to 4 bytes; tolerate a missing final padding. A chunk before
        // another whose length is not padded leaves the next header at an unknown place
        // (read at the rounded offset, it would be garbage: "truncated chunk").
        let end = start.saturating_add(chunk_length);
        if chunk_length % 4 != 0 && end < data.len() {
            return Err(glb(format!(
                "chunk {index} ({}) is {chunk_length} bytes, not a multiple of 4: the GLB \
                 format pads every chunk to 4 bytes, so the chunk after it cannot be found",
                chunk_name(kind)
            )));
        }
        offset = end.saturating_add(3) & !3;
        index = index.saturating_add(1);
    }
    let json = json.ok_or_else(|| glb("no JSON chunk".into()))?;
    // Pad bytes of the JSON chunk are spaces; some writers use NULs.
    let end = json
        .iter()
        .rposition(|&b| !matches!(b, b' ' | b'\0' | b'\n' | b'\r' | b'\t'))
        .map_or(0, |i| i.saturating_add(1));
    Ok(Container {
        json: json.get(..end).unwrap_or(json),
        bin,
        is_glb: true,
    })
}

fn chunk_name(kind: [u8; 4]) -> String {
    if kind.iter().all(|b| b.is_ascii_graphic()) {
        format!("`{}`", String::from_utf8_lossy(&kind))
    } else {
        format!("0x{:08X}", u32::from_le_bytes(kind))
    }
}

/// Where an URI's bytes come from.
pub(crate) enum Resolved {
    Data {
        mime: Option<String>,
        bytes: Vec<u8>,
    },
    File(PathBuf),
}

/// Resolves `uri` against `base` (the scene's folder; `None` when loaded from memory),
/// refusing what `allow_external` does not allow.
pub(crate) fn resolve_uri(
    uri: &str,
    base: Option<&Path>,
    allow_external: bool,
) -> Result<Resolved, ImportProblem> {
    let refuse = |reason: String| ImportProblem::UriRefused {
        uri: truncate(uri),
        reason,
    };
    if let Some(rest) = strip_prefix_ignore_case(uri, "data:") {
        let (header, payload) = rest
            .split_once(',')
            .ok_or_else(|| refuse("data URI without a `,`".into()))?;
        let Some(mime) = strip_suffix_ignore_case(header, ";base64") else {
            return Err(refuse(
                "only base64 data URIs (`data:...;base64,...`) are supported".into(),
            ));
        };
        let bytes = decode_base64(payload)
            .map_err(|e| refuse(format!("invalid base64 in the data URI: {e}")))?;
        let mime = (!mime.is_empty()).then(|| mime.to_ascii_lowercase());
        return Ok(Resolved::Data { mime, bytes });
    }
    if let Some(scheme) = uri_scheme(uri) {
        if scheme.len() == 1 {
            // `C:/...`: a Windows absolute path.
            if !allow_external {
                return Err(refuse(
                    "absolute paths are refused: a scene's files lie in its folder".into(),
                ));
            }
            return Ok(Resolved::File(PathBuf::from(percent_decode(uri)?)));
        }
        if scheme.eq_ignore_ascii_case("file") {
            if !allow_external {
                return Err(refuse(
                    "`file:` URIs are refused: a scene's files lie in its folder".into(),
                ));
            }
            let path = &uri[5..];
            let path = path
                .strip_prefix("//localhost")
                .or_else(|| path.strip_prefix("//"))
                .unwrap_or(path);
            return Ok(Resolved::File(PathBuf::from(percent_decode(path)?)));
        }
        return Err(refuse(format!(
            "the `{scheme}:` scheme is not supported; Combustion reads local files and data URIs only"
        )));
    }
    let decoded = percent_decode(uri)?;
    if decoded.contains('\0') {
        return Err(refuse("the path contains a NUL character".into()));
    }
    let relative = Path::new(&decoded);
    let absolute = decoded.starts_with('/') || decoded.starts_with('\\') || relative.is_absolute();
    if absolute {
        if !allow_external {
            return Err(refuse(
                "absolute paths are refused: a scene's files lie in its folder".into(),
            ));
        }
        return Ok(Resolved::File(relative.to_path_buf()));
    }
    // Lexically: does the path climb above the scene's folder?
    let mut depth: i64 = 0;
    for part in decoded.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => depth = depth.saturating_sub(1),
            _ => depth = depth.saturating_add(1),
        }
        if depth < 0 && !allow_external {
            return Err(refuse(
                "it leaves the scene's folder (`..`): a scene's files lie in its folder".into(),
            ));
        }
    }
    let Some(base) = base else {
        return Err(refuse(
            "relative URIs cannot be resolved when the glTF is loaded from memory".into(),
        ));
    };
    let mut path = base.to_path_buf();
    for component in relative.components() {
        match component {
            Component::Normal(part) => path.push(part),
            Component::ParentDir => path.push(".."),
            _ => {}
        }
    }
    Ok(Resolved::File(path))
}

pub(crate) fn truncate(uri: &str) -> String {
    const MAX: usize = 80;
    if uri.len() <= MAX {
        uri.to_owned()
    } else {
        // The last character boundary at or before MAX (0 is one).
        let end = (0..=MAX)
            .rev()
            .find(|&i| uri.is_char_boundary(i))
            .unwrap_or(0);
        format!("{}…", uri.get(..end).unwrap_or_default())
    }
}

fn strip_prefix_ignore_case<'a>(s: &'a str, prefix: &str) -> Option<&'a str> {
    let head = s.get(..prefix.len())?;
    head.eq_ignore_ascii_case(prefix)
        .then(|| s.get(prefix.len()..))
        .flatten()
}

fn strip_suffix_ignore_case<'a>(s: &'a str, suffix: &str) -> Option<&'a str> {
    let at = s.len().checked_sub(suffix.len())?;
    let tail = s.get(at..)?;
    tail.eq_ignore_ascii_case(suffix)
        .then(|| s.get(..at))
        .flatten()
}

/// The scheme of an absolute URI (RFC 3986: ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":").
fn uri_scheme(uri: &str) -> Option<&str> {
    let (scheme, _) = uri.split_once(':')?;
    let mut chars = scheme.chars();
    let first = chars.next()?;
    (first.is_ascii_alphabetic()
        && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.')))
    .then_some(scheme)
}

fn percent_decode(s: &str) -> Result<String, ImportProblem> {
    if !s.contains('%') {
        return Ok(s.to_owned());
    }
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i: usize = 0;
    while let Some(&byte) = bytes.get(i) {
        if byte == b'%' {
            let hex = bytes
                .get(i.saturating_add(1)..i.saturating_add(3))
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok());
            match hex {
                Some(b) => {
                    out.push(b);
                    i = i.saturating_add(3);
                    continue;
                }
                None => {
                    return Err(ImportProblem::UriRefused {
                        uri: truncate(s),
                        reason: format!("invalid percent escape at byte {i}"),
                    })
                }
            }
        }
        out.push(byte);
        i = i.saturating_add(1);
    }
    String::from_utf8(out).map_err(|_| ImportProblem::UriRefused {
        uri: truncate(s),
        reason: "percent escapes do not decode to UTF-8".into(),
    })
}

/// Standard base64 (RFC 4648 §4), padding optional, ASCII whitespace ignored.
pub(crate) fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    // 3 bytes for every 4 characters (the quotient of a usize by 4 times 3 cannot
    // overflow; saturating all the same).
    let mut out = Vec::with_capacity((text.len() / 4).saturating_mul(3).saturating_add(3));
    let mut acc: u32 = 0;
    let mut bits: u32 = 0;
    let mut padding: usize = 0;
    for (i, c) in text.bytes().enumerate() {
        // Each arm's subtraction is from within its range (c ≥ its start).
        let value = match c {
            b'A'..=b'Z' => c.wrapping_sub(b'A'),
            b'a'..=b'z' => c.wrapping_sub(b'a').wrapping_add(26),
            b'0'..=b'9' => c.wrapping_sub(b'0').wrapping_add(52),
            b'+' => 62,
            b'/' => 63,
            b'=' => {
                padding = padding.saturating_add(1);
                continue;
            }
            b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return Err(format!("unexpected character at offset {i}")),
        };
        if padding > 0 {
            return Err(format!("data after `=` padding at offset {i}"));
        }
        // At most 13 bits are held (7 left over and 6 new): the shifts stay in the word.
        acc = (acc << 6) | u32::from(value);
        bits = bits.saturating_add(6);
        if bits >= 8 {
            bits = bits.saturating_sub(8);
            out.push((acc >> bits) as u8);
            acc &= (1u32 << bits).wrapping_sub(1);
        }
    }
    if bits >= 6 || padding > 2 {
        return Err("truncated base64 data".into());
    }
    Ok(out)
}

#[cfg(test)]
#[allow(clippy::arithmetic_side_effects, clippy::indexing_slicing)] // the tests' encoder
pub(crate) fn encode_base64(bytes: &[u8]) -> String {
    const TABLE: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(TABLE[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Reads `path` if it is a regular file (after symlinks) of at most `limit` bytes, both
/// checked before reading: a device, FIFO or socket is refused without being opened
/// (so `/dev/zero` is not read without end and a FIFO does not block), and the read
/// itself stops past `limit` in case the file grows meanwhile. `what` says in words what
/// the file is (`"a scene file"`), for the message when it exceeds the limit (the limit's
/// option or constant is named in the caller's documentation, not to the user).
pub fn read_regular_file(path: &Path, limit: u64, what: &str) -> std::io::Result<Vec<u8>> {
    use std::io::Read as _;
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file (a folder, device, FIFO or socket)",
        ));
    }
    let too_large = |size: u64| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("{size} bytes is more than the {limit} bytes {what} may have"),
        )
    };
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)?
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// Reads `path` as UTF-8 text under [`read_regular_file`]'s rule; `what` says what the
/// file is (`"a camera path"`), for the message when it passes `limit`. The error is the
/// message alone (the caller names the file and what it was for).
pub fn read_text(path: &Path, limit: u64, what: &str) -> Result<String, String> {
    let bytes = read_regular_file(path, limit, what).map_err(|e| e.to_string())?;
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
    })
}

/// What every file an import reads is called when it passes
/// [`ImportOptions::max_file_bytes`](super::ImportOptions::max_file_bytes).
pub(crate) const SCENE_FILE: &str = "a scene's file";

/// Reads a resolved URI's bytes (a file within `limit` bytes, as [`read_regular_file`];
/// `limit` is [`ImportOptions::max_file_bytes`](super::ImportOptions::max_file_bytes)).
pub(crate) fn read_resolved(
    uri: &str,
    resolved: Resolved,
    limit: u64,
) -> Result<(Option<String>, Vec<u8>), ImportProblem> {
    match resolved {
        Resolved::Data { mime, bytes } => Ok((mime, bytes)),
        Resolved::File(path) => match read_regular_file(&path, limit, SCENE_FILE) {
            Ok(bytes) => Ok((None, bytes)),
            Err(source) => Err(ImportProblem::ExternalIo {
                uri: truncate(uri),
                path,
                source,
            }),
        },
    }
}

/// A buffer view: its buffer, the view's byte range in it, and its byte stride.
pub(crate) type ViewBytes = (Rc<[u8]>, std::ops::Range<usize>, Option<usize>);

/// The glTF buffers, loaded on first use.
pub(crate) struct Buffers<'a> {
    root: &'a json::Root,
    bin: Option<&'a [u8]>,
    is_glb: bool,
    base: Option<&'a Path>,
    allow_external: bool,
    max_file_bytes: u64,
    /// Per buffer: the bytes it reads from (shared) and its byteLength.
    loaded: Vec<Option<(Rc<[u8]>, usize)>>,
    /// Each file read for a buffer, once however many `buffers` entries name it.
    files: HashMap<PathBuf, Rc<[u8]>>,
    /// Bytes of the files read for buffers (a data URI or a GLB's binary chunk is part of
    /// the glTF file itself, which the importer counts).
    bytes_read: u64,
    /// Elements read so far from accessors without a buffer view (zeros that no byte of
    /// the file holds), against `accessor::MAX_UNBACKED_ELEMENTS`.
    pub unbacked_elements: u64,
}

impl<'a> Buffers<'a> {
    pub fn new(
        root: &'a json::Root,
        container: &Container<'a>,
        base: Option<&'a Path>,
        allow_external: bool,
        max_file_bytes: u64,
    ) -> Self {
        Self {
            root,
            bin: container.bin,
            is_glb: container.is_glb,
            max_file_bytes,
            base,
            allow_external,
            loaded: vec![None; root.buffers.len()],
            files: HashMap::new(),
            bytes_read: 0,
            unbacked_elements: 0,
        }
    }

    /// Buffer `index`: the bytes it reads from and its byteLength (checked to be there).
    pub fn get(&mut self, index: usize) -> Result<(Rc<[u8]>, usize), ImportProblem> {
        if let Some(Some(loaded)) = self.loaded.get(index) {
            return Ok(loaded.clone());
        }
        let buffer = self
            .root
            .buffers
            .get(index)
            .ok_or_else(|| ImportProblem::Buffer {
                index,
                message: format!("does not exist ({} buffers)", self.root.buffers.len()),
            })?;
        let err = |message: String| ImportProblem::Buffer { index, message };
        let declared = buffer.byte_length.0;
        let data: Rc<[u8]> = match &buffer.uri {
            None if self.is_glb && index == 0 => match self.bin {
                // Part of the file itself, which the caller counts.
                Some(bin) => Rc::from(bin),
                None => {
                    return Err(err(
                        "has no URI, so it is the GLB's binary chunk, but the file has none".into(),
                    ))
                }
            },
            None if self.is_glb => {
                return Err(err(
                    "has no URI; only buffer 0 of a .glb may (it is the binary chunk)".into(),
                ))
            }
            None => {
                return Err(err(
                    "has no URI (only a .glb's first buffer may omit it)".into()
                ))
            }
            Some(uri) => match resolve_uri(uri, self.base, self.allow_external)? {
                // In the file's own text: decoded per entry, bounded by the file.
                Resolved::Data { bytes, .. } => Rc::from(bytes),
                // A file outside: read once however many entries name it (as the
                // system names it, so `a.bin` and `d/../a.bin` are one file).
                Resolved::File(path) => {
                    let key = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
                    match self.files.get(&key) {
                        Some(bytes) => bytes.clone(),
                        None => {
                            let bytes: Rc<[u8]> = Rc::from(
                                read_resolved(uri, Resolved::File(path), self.max_file_bytes)?.1,
                            );
                            self.bytes_read = self.bytes_read.saturating_add(bytes.len() as u64);
                            self.files.insert(key, bytes.clone());
                            bytes
                        }
                    }
                }
            },
        };
        if (data.len() as u64) < declared {
            return Err(err(format!(
                "is short: byteLength is {declared} bytes but only {} are available",
                data.len()
            )));
        }
        let loaded = (data, declared as usize);
        if let Some(slot) = self.loaded.get_mut(index) {
            *slot = Some(loaded.clone());
        }
        Ok(loaded)
    }

    /// Bytes of the files read for buffers so far, each file once.
    pub fn bytes_read(&self) -> u64 {
        self.bytes_read
    }

    /// The bytes of buffer view `index`.
    pub fn view(&mut self, index: usize) -> Result<ViewBytes, String> {
        let view = self
            .root
            .buffer_views
            .get(index)
            .ok_or_else(|| format!("buffer view {index} does not exist"))?;
        let buffer = view.buffer.value();
        let (data, buffer_length) = self.get(buffer).map_err(|e| e.to_string())?;
        let offset = view.byte_offset.map_or(0, |o| o.0);
        let length = view.byte_length.0;
        let end = offset.checked_add(length).filter(|&end| end <= buffer_length as u64).ok_or_else(|| {
            format!(
                "buffer view {index} (bytes {offset}..{offset}+{length}) exceeds buffer {buffer} ({buffer_length} bytes)"
            )
        })?;
        let stride = view.byte_stride.map(|s| s.0);
        Ok((data, offset as usize..end as usize, stride))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips() {
        for n in 0..20 {
            let bytes: Vec<u8> = (0..n).map(|i| (i * 37 + 11) as u8).collect();
            assert_eq!(decode_base64(&encode_base64(&bytes)).unwrap(), bytes);
        }
        assert!(decode_base64("QQ=A").is_err());
        assert!(decode_base64("Q").is_err());
        assert!(decode_base64("Q*==").is_err());
    }

    #[test]
    fn uris_leaving_the_folder_are_refused() {
        let base = Path::new("/scenes");
        let ok = |uri: &str| resolve_uri(uri, Some(base), false).is_ok();
        assert!(ok("a.bin"));
        assert!(ok("sub/../a.bin"));
        assert!(ok("a%20b.bin"));
        assert!(!ok("../a.bin"));
        assert!(!ok("sub/../../a.bin"));
        assert!(!ok("/etc/passwd"));
        assert!(!ok("C:/x.bin"));
        assert!(!ok("file:///etc/passwd"));
        assert!(!ok("http://example.com/a.bin"));
        assert!(resolve_uri("../a.bin", Some(base), true).is_ok());
        assert!(resolve_uri("https://example.com/a.bin", Some(base), true).is_err());
        assert!(resolve_uri("a.bin", None, true).is_err());
        assert!(ok("data:application/octet-stream;base64,AAAA"));
    }
}
