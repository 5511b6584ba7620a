//! Results kept on disk under a key of everything that decides them: the SPIR-V cache
//! (combustion-vk's `ShaderCompiler::with_spirv_cache`) and the renderer's environment
//! bakes use it. A crate of its own so that its reader is fuzzed without the renderer
//! (fuzz/fuzz_targets/cache_entry.rs).
//!
//! The key is a 128-bit [`Digest`] (two FNV-1a 64 hashes with different offsets) of
//! what decides the result. An entry is the kind's magic, the key, a checksum of the
//! body and the body; it is written to a temporary file and renamed into place, so
//! processes sharing the folder never read half an entry. One that fails its checks
//! (magic, key, checksum) is not used: the caller computes the result again and
//! replaces it. The cache never makes anything fail: a folder that cannot be read or
//! written only costs the work it would have saved.

use std::io::Write;
use std::path::{Path, PathBuf};

pub mod bodies;

/// The folder a cache of one kind is given by default: `$variable` when set (`off`, in
/// any case, or empty: none), else `$XDG_CACHE_HOME/combustion/<folder>` when that is an
/// absolute path (the XDG rule: a relative one is ignored), else
/// `$HOME/.cache/combustion/<folder>`, else none.
pub fn default_cache_dir(variable: &str, folder: &str) -> Option<PathBuf> {
    cache_dir_from(
        std::env::var_os(variable),
        std::env::var_os("XDG_CACHE_HOME"),
        std::env::var_os("HOME"),
        folder,
    )
}

/// [`default_cache_dir`] from the variables' values.
fn cache_dir_from(
    chosen: Option<std::ffi::OsString>,
    xdg_cache_home: Option<std::ffi::OsString>,
    home: Option<std::ffi::OsString>,
    folder: &str,
) -> Option<PathBuf> {
    if let Some(dir) = chosen {
        let off = dir.is_empty() || dir.to_str().is_some_and(|d| d.eq_ignore_ascii_case("off"));
        return (!off).then(|| PathBuf::from(dir));
    }
    let base = xdg_cache_home
        .map(PathBuf::from)
        .filter(|dir| dir.is_absolute())
        .or_else(|| {
            home.filter(|dir| !dir.is_empty())
                .map(|home| PathBuf::from(home).join(".cache"))
        })?;
    Some(base.join("combustion").join(folder))
}

/// A 128-bit digest built up from parts (each part's length is hashed before it, so
/// `("ab", "c")` and `("a", "bc")` differ).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Digest {
    low: u64,
    high: u64,
}

impl Default for Digest {
    fn default() -> Self {
        Self::new()
    }
}

impl Digest {
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    /// The digest of nothing.
    pub fn new() -> Self {
        Self {
            low: 0xcbf2_9ce4_8422_2325,
            high: 0x6c62_272e_07bb_0142,
        }
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.low = (self.low ^ u64::from(byte)).wrapping_mul(Self::PRIME);
            self.high = (self.high ^ u64::from(byte.rotate_left(3))).wrapping_mul(Self::PRIME);
        }
    }

    /// The digest with `bytes` (and their length) added.
    #[must_use]
    pub fn part(mut self, bytes: &[u8]) -> Self {
        self.bytes(&(bytes.len() as u64).to_le_bytes());
        self.bytes(bytes);
        self
    }

    /// The digest with `bytes` (and their length) added eight bytes at a step, several
    /// times as fast as [`Digest::part`] for large inputs (an environment image's
    /// texels, up to 768 MB); a different digest from `part` of the same bytes.
    #[must_use]
    pub fn part_in_words(mut self, bytes: &[u8]) -> Self {
        self.bytes(&(bytes.len() as u64).to_le_bytes());
        let mut words = bytes.chunks_exact(8);
        for word in &mut words {
            let word = u64::from_le_bytes(word.try_into().expect("8 bytes"));
            self.low = (self.low ^ word).wrapping_mul(Self::PRIME).rotate_left(29);
            self.high = (self.high ^ word.rotate_left(32))
                .wrapping_mul(Self::PRIME)
                .rotate_left(17);
        }
        self.bytes(words.remainder());
        self
    }

    /// Its 16 bytes.
    pub fn to_bytes(self) -> [u8; 16] {
        let mut out = [0; 16];
        out[..8].copy_from_slice(&self.low.to_le_bytes());
        out[8..].copy_from_slice(&self.high.to_le_bytes());
        out
    }

    /// Its 16 bytes in hexadecimal.
    pub fn hex(self) -> String {
        self.to_bytes().iter().map(|b| format!("{b:02x}")).collect()
    }

    /// The checksum an entry keeps of its body.
    fn checksum(body: &[u8]) -> u64 {
        Self::new().part(body).low
    }
}

/// The largest entry a cache reads (and its size limit's ceiling): an entry's file
/// larger than this, or larger than the cache's size limit, is a miss, never read.
pub const MAX_ENTRY_BYTES: u64 = 256 << 20;

/// The bytes of the entry file `path` if it is a regular file (after links) of at most
/// `limit` bytes, read whole; else `None` (a miss) before a byte is read: a FIFO never
/// blocks, `/dev/zero` or a sparse giant is never read.
fn read_entry(path: &Path, limit: u64) -> Option<Vec<u8>> {
    use std::io::Read;
    let metadata = std::fs::metadata(path).ok()?;
    if !metadata.is_file() || metadata.len() > limit {
        return None;
    }
    let file = std::fs::File::open(path).ok()?;
    // The file may have grown since: read no more than the limit allows.
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.take(limit + 1).read_to_end(&mut bytes).ok()?;
    (bytes.len() as u64 <= limit).then_some(bytes)
}

/// A folder of entries of one kind (its magic and file extension), optionally kept
/// within a size ([`DiskCache::keeping_at_most`]).
#[derive(Clone, Debug)]
pub struct DiskCache {
    dir: PathBuf,
    magic: [u8; 8],
    extension: &'static str,
    capacity: Option<u64>,
}

impl DiskCache {
    /// Entries in `dir`, each starting with `magic` (the kind and its format's version:
    /// change it when the body's layout changes), named `<key>.<extension>`.
    pub fn new(dir: PathBuf, magic: [u8; 8], extension: &'static str) -> Self {
        Self {
            dir,
            magic,
            extension,
            capacity: None,
        }
    }

    /// The same cache, which after each store removes its least recently used entries
    /// (by modification time: a store or a load sets it) until the rest take at most
    /// `bytes`.
    #[must_use]
    pub fn keeping_at_most(self, bytes: u64) -> Self {
        Self {
            capacity: Some(bytes),
            ..self
        }
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The file of `key`'s entry.
    pub fn entry(&self, key: Digest) -> PathBuf {
        self.dir.join(format!("{}.{}", key.hex(), self.extension))
    }

    /// The body stored under `key`, if an intact entry is there.
    pub fn load(&self, key: Digest) -> Option<Vec<u8>> {
        let limit = self
            .capacity
            .unwrap_or(MAX_ENTRY_BYTES)
            .min(MAX_ENTRY_BYTES);
        let mut bytes = read_entry(&self.entry(key), limit)?;
        let header = self.magic.len() + 16 + 8;
        if bytes.len() < header || bytes[..8] != self.magic || bytes[8..24] != key.to_bytes() {
            return None;
        }
        let checksum = u64::from_le_bytes(bytes[24..32].try_into().ok()?);
        if Digest::checksum(&bytes[header..]) != checksum {
            return None;
        }
        bytes.drain(..header);
        if self.capacity.is_some() {
            // Used now: the last entry a size limit removes.
            let _ = std::fs::File::options()
                .append(true)
                .open(self.entry(key))
                .and_then(|file| file.set_modified(std::time::SystemTime::now()));
        }
        Some(bytes)
    }

    /// Stores `body` under `key`; a failure only loses the entry.
    pub fn store(&self, key: Digest, body: &[u8]) {
        let mut bytes = Vec::with_capacity(32 + body.len());
        bytes.extend_from_slice(&self.magic);
        bytes.extend_from_slice(&key.to_bytes());
        bytes.extend_from_slice(&Digest::checksum(body).to_le_bytes());
        bytes.extend_from_slice(body);
        let entry = self.entry(key);
        if self.write_atomically(&entry, &bytes).is_ok() {
            if let Some(capacity) = self.capacity {
                self.shrink_to(capacity, &entry);
            }
        }
    }

    /// Removes the least recently used entries but `keep` (the one just stored: on a
    /// file system with coarse times its time may tie with older ones) until the rest
    /// take at most `capacity` bytes, and temporaries over an hour old (left by a process
    /// that died while writing). Files of other kinds are left alone.
    fn shrink_to(&self, capacity: u64, keep: &Path) {
        let Ok(folder) = std::fs::read_dir(&self.dir) else {
            return;
        };
        let an_hour_ago = std::time::SystemTime::now()
            .checked_sub(std::time::Duration::from_secs(3600))
            .unwrap_or(std::time::UNIX_EPOCH);
        let mut total = 0;
        let mut entries: Vec<(std::time::SystemTime, u64, PathBuf)> = folder
            .filter_map(|entry| {
                let path = entry.ok()?.path();
                let metadata = std::fs::metadata(&path).ok()?;
                let modified = metadata.modified().ok()?;
                let name = path.file_name()?.to_str()?;
                if name.ends_with(".tmp") && name.contains(&format!(".{}.", self.extension)) {
                    if modified < an_hour_ago {
                        let _ = std::fs::remove_file(&path);
                    }
                    return None;
                }
                if path.extension()? != self.extension {
                    return None;
                }
                total += metadata.len();
                (path != keep).then_some((modified, metadata.len(), path))
            })
            .collect();
        entries.sort();
        for (_, len, path) in entries {
            if total <= capacity {
                break;
            }
            if std::fs::remove_file(&path).is_ok() {
                total -= len;
            }
        }
    }

    fn write_atomically(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
        std::fs::create_dir_all(&self.dir)?;
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let temporary = path.with_extension(format!(
            "{}.{}-{}.tmp",
            self.extension,
            std::process::id(),
            NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
        ));
        let written = std::fs::File::create(&temporary)
            .and_then(|mut file| file.write_all(bytes))
            .and_then(|()| std::fs::rename(&temporary, path));
        if written.is_err() {
            let _ = std::fs::remove_file(&temporary);
        }
        written
    }
}

#[cfg(test)]
mod tests {
    /// `off` in any case or an empty value turns a cache off; a relative
    /// `XDG_CACHE_HOME` is ignored (the XDG rule), falling back to `$HOME/.cache`.
    #[test]
    fn the_default_folder_follows_the_variables() {
        let os = |s: &str| Some(std::ffi::OsString::from(s));
        for off in ["off", "OFF", "Off", ""] {
            assert_eq!(
                cache_dir_from(os(off), os("/x"), os("/h"), "k"),
                None,
                "{off:?}"
            );
        }
        assert_eq!(
            cache_dir_from(os("here"), None, None, "k"),
            Some(PathBuf::from("here"))
        );
        assert_eq!(
            cache_dir_from(None, os("/x"), os("/h"), "k"),
            Some(PathBuf::from("/x/combustion/k"))
        );
        for relative in ["rel", "./rel", ""] {
            assert_eq!(
                cache_dir_from(None, os(relative), os("/h"), "k"),
                Some(PathBuf::from("/h/.cache/combustion/k")),
                "{relative:?}"
            );
        }
        assert_eq!(cache_dir_from(None, os("rel"), None, "k"), None);
    }

    use super::*;

    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "combustion-disk-cache-{name}-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn an_entry_reads_back_as_stored_and_a_damaged_one_not_at_all() {
        let dir = folder("damage");
        let cache = DiskCache::new(dir.clone(), *b"TESTCA01", "entry");
        let key = Digest::new().part(b"key");
        assert_eq!(cache.load(key), None);
        cache.store(key, b"the body");
        assert_eq!(cache.load(key).as_deref(), Some(&b"the body"[..]));
        assert_eq!(cache.load(Digest::new().part(b"another key")), None);
        let other_kind = DiskCache::new(dir.clone(), *b"TESTCA02", "entry");
        assert_eq!(other_kind.load(key), None, "another magic");
        let mut bytes = std::fs::read(cache.entry(key)).unwrap();
        let last = bytes.len() - 1;
        bytes[last] ^= 1;
        std::fs::write(cache.entry(key), &bytes).unwrap();
        assert_eq!(cache.load(key), None, "checksum");
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// An entry that is not a regular file, or larger than the cache may hold, is a
    /// miss before a byte is read: a FIFO does not block, a link to /dev/zero is not
    /// read without end, a sparse file beyond the limit is not read whole.
    #[cfg(unix)]
    #[test]
    fn an_entry_that_is_no_regular_file_or_too_large_is_a_miss() {
        let dir = folder("special");
        let cache = DiskCache::new(dir.clone(), *b"TESTCA01", "entry").keeping_at_most(1 << 20);
        let key = Digest::new().part(b"key");
        cache.store(key, b"the body");
        let entry = cache.entry(key);
        std::fs::remove_file(&entry).unwrap();
        let made = std::process::Command::new("mkfifo")
            .arg(&entry)
            .status()
            .unwrap();
        assert!(made.success());
        assert_eq!(cache.load(key), None, "FIFO");
        std::fs::remove_file(&entry).unwrap();
        std::os::unix::fs::symlink("/dev/zero", &entry).unwrap();
        assert_eq!(cache.load(key), None, "/dev/zero");
        std::fs::remove_file(&entry).unwrap();
        let sparse = std::fs::File::create(&entry).unwrap();
        sparse.set_len(3 << 30).unwrap();
        assert_eq!(cache.load(key), None, "3 GiB sparse");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn a_part_in_words_tells_every_single_bit_apart() {
        // 1 000 bytes (125 words): flipping any one bit, or dropping the last byte,
        // changes the digest; so does moving the same bytes between parts.
        let bytes: Vec<u8> = (0..1000u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect();
        let digest = Digest::new().part_in_words(&bytes);
        let mut seen = std::collections::HashSet::new();
        seen.insert(digest.to_bytes());
        for bit in 0..bytes.len() * 8 {
            let mut flipped = bytes.clone();
            flipped[bit / 8] ^= 1 << (bit % 8);
            assert!(
                seen.insert(Digest::new().part_in_words(&flipped).to_bytes()),
                "bit {bit}"
            );
        }
        assert_ne!(Digest::new().part_in_words(&bytes[..999]), digest);
        assert_ne!(
            Digest::new()
                .part_in_words(&bytes[..8])
                .part_in_words(&bytes[8..]),
            digest.part_in_words(&[])
        );
        assert_eq!(Digest::new().part_in_words(&bytes), digest, "deterministic");
    }

    #[test]
    fn a_size_limit_removes_the_least_recently_used_entries() {
        let dir = folder("limit");
        // Three entries of 32 + 100 bytes fit in 400, a fourth does not.
        let cache = DiskCache::new(dir.clone(), *b"TESTCA01", "entry").keeping_at_most(400);
        let keys: Vec<Digest> = (0..4u8).map(|i| Digest::new().part(&[i])).collect();
        let at = |seconds: u64| {
            std::time::SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(seconds)
        };
        let age = |key: Digest, seconds| {
            std::fs::File::options()
                .append(true)
                .open(cache.entry(key))
                .unwrap()
                .set_modified(at(seconds))
                .unwrap();
        };
        for (i, &key) in keys[..3].iter().enumerate() {
            cache.store(key, &[0; 100]);
            age(key, 1000 + i as u64);
        }
        // The oldest, used now, is kept over the second.
        assert!(cache.load(keys[0]).is_some());
        std::fs::write(dir.join("unrelated.txt"), [0; 1000]).unwrap();
        // Temporaries of dead writers: removed once over an hour old.
        let temporary = |name: &str| dir.join(format!("{}.entry.{name}.tmp", keys[0].hex()));
        std::fs::write(temporary("1-0"), [0; 50]).unwrap();
        std::fs::File::options()
            .append(true)
            .open(temporary("1-0"))
            .unwrap()
            .set_modified(at(1000))
            .unwrap();
        std::fs::write(temporary("2-0"), [0; 50]).unwrap();
        cache.store(keys[3], &[0; 100]);
        let present: Vec<bool> = keys.iter().map(|&k| cache.entry(k).exists()).collect();
        assert_eq!(present, [true, false, true, true]);
        assert!(
            dir.join("unrelated.txt").exists(),
            "other files are left alone"
        );
        assert!(!temporary("1-0").exists(), "an old temporary is removed");
        assert!(
            temporary("2-0").exists(),
            "a fresh one may be a writer's at work"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn the_entry_just_stored_is_kept_whatever_the_times_say() {
        // Room for one entry; the one there seems newer than the one stored (a clock
        // set back, or times too coarse to order them): the new one is kept.
        let dir = folder("keep");
        let cache = DiskCache::new(dir.clone(), *b"TESTCA01", "entry").keeping_at_most(200);
        let (first, second) = (Digest::new().part(b"1"), Digest::new().part(b"2"));
        cache.store(first, &[0; 100]);
        let later = std::time::SystemTime::now() + std::time::Duration::from_secs(3600);
        std::fs::File::options()
            .append(true)
            .open(cache.entry(first))
            .unwrap()
            .set_modified(later)
            .unwrap();
        cache.store(second, &[0; 100]);
        assert!(cache.entry(second).exists() && !cache.entry(first).exists());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
