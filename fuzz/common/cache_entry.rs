//! What the `cache_entry` fuzz target does with one input (shared with the test that
//! replays its corpus, crates/disk-cache/tests/fuzz_corpus.rs): the disk caches' reader
//! (`combustion_disk_cache::DiskCache::load`) and the checks of each kind's body
//! (`bodies::spirv_words`, `bodies::is_radiance`).
//!
//! The first byte picks how the rest becomes an entry file, and a size limit:
//! - mode 0: the bytes are the file as found on disk (any header, any length);
//! - mode 1: the bytes are a body under a header that passes the cache's own checks (a
//!   forged or foreign entry: what the body checks must catch);
//! - mode 2: the body stored through the cache, then loaded.
//!
//! A load is `None` or exactly the body its file holds after an intact header, never
//! more than the size limit; a stored body loads back as itself; a body a check takes
//! is what its kind says (whole SPIR-V words from the magic; radiance texels finite,
//! within the bound).

#![allow(dead_code)] // the replay test and the target use parts of it

use combustion_disk_cache::bodies::{is_radiance, spirv_words, SPIRV_MAGIC};
use combustion_disk_cache::{Digest, DiskCache};
use std::path::PathBuf;

/// The kind's magic of the entries made here.
pub const MAGIC: [u8; 8] = *b"FUZZCA01";

/// The radiance bound the checks are given (the scene crate's `MAX_RADIANCE`).
pub const MAX_RADIANCE: f32 = 1.0e30;

/// A folder of this process's own for the entry files.
fn folder() -> &'static PathBuf {
    static FOLDER: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    FOLDER.get_or_init(|| {
        let dir =
            std::env::temp_dir().join(format!("combustion-fuzz-cache-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        dir
    })
}

/// The header an intact entry of `key` has before `body`.
pub fn header(key: Digest, body: &[u8]) -> Vec<u8> {
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&key.to_bytes());
    let checksum = Digest::new().part(body).to_bytes();
    bytes.extend_from_slice(&checksum[..8]);
    bytes
}

/// Runs one input.
pub fn load_and_check(data: &[u8]) {
    let _ = loaded(data);
}

/// Runs one input: what the cache loaded of it (checked).
pub fn loaded(data: &[u8]) -> Option<Vec<u8>> {
    let (&mode, rest) = data.split_first()?;
    // A size limit from none (the reader's ceiling) to small ones the entry may pass.
    let limit = match mode >> 2 {
        0 => None,
        n => Some(u64::from(n) * 8),
    };
    let mut cache = DiskCache::new(folder().clone(), MAGIC, "entry");
    if let Some(limit) = limit {
        cache = cache.keeping_at_most(limit);
    }
    let key = Digest::new().part(b"fuzz").part(&[mode]);
    let file = cache.entry(key);
    let loaded = match mode & 3 {
        0 => {
            std::fs::write(&file, rest).expect("the entry written");
            cache.load(key)
        }
        1 => {
            let mut bytes = header(key, rest);
            bytes.extend_from_slice(rest);
            std::fs::write(&file, &bytes).expect("the entry written");
            let loaded = cache.load(key);
            let fits = limit.is_none_or(|limit| bytes.len() as u64 <= limit);
            if fits {
                assert_eq!(loaded.as_deref(), Some(rest), "an intact entry loads whole");
            }
            loaded
        }
        _ => {
            cache.store(key, rest);
            let loaded = cache.load(key);
            // A store past the size limit may be removed at once; one kept loads whole.
            if limit.is_none() {
                assert_eq!(loaded.as_deref(), Some(rest), "a stored body loads back");
            }
            loaded
        }
    };
    if let Some(body) = &loaded {
        let on_disk = std::fs::read(&file).unwrap_or_default();
        if let Some(limit) = limit {
            assert!(on_disk.len() as u64 <= limit, "read past the size limit");
        }
        assert!(
            on_disk.len() >= 32
                && on_disk[32..] == body[..]
                && on_disk[..32] == header(key, body)[..],
            "a load is the body after an intact header"
        );
        check_bodies(body);
    }
    let _ = std::fs::remove_file(&file);
    loaded
}

/// The body checks on `body`: what they take is what its kind says.
pub fn check_bodies(body: &[u8]) {
    if let Some(words) = spirv_words(body) {
        assert_eq!(words.len() * 4, body.len());
        assert_eq!(words[0], SPIRV_MAGIC);
    }
    if is_radiance(body, body.len() as u64, MAX_RADIANCE) {
        for texel in body.chunks_exact(16) {
            for (c, value) in texel.chunks_exact(4).enumerate() {
                let v = f32::from_le_bytes([value[0], value[1], value[2], value[3]]);
                assert!(v.is_finite());
                if c < 3 {
                    assert!((0.0..=MAX_RADIANCE).contains(&v));
                }
            }
        }
    }
}
