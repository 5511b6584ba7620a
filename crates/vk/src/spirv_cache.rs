//! SPIR-V compiled once and kept on disk:
//! [`ShaderCompiler::with_spirv_cache`](crate::ShaderCompiler::with_spirv_cache) looks a compilation up by a key of everything that decides
//! its result before it runs shaderc.
//!
//! The key is a 128-bit digest (two FNV-1a 64 hashes with different offsets) of the
//! compiler's identity ([`COMPILER_IDENTITY`], the fixed compile options), the shader's
//! path, stage and defines, and every source the compiler holds (so any edit to any
//! shader, or a generated header, makes every entry stale: simple, and never wrong).
//! An entry is written to a temporary file and renamed into place, so processes sharing
//! the folder never read half an entry; one that fails its checks (magic, key, length,
//! checksum, SPIR-V's magic number) is compiled again and replaced. The cache never
//! makes a compilation fail: a folder that cannot be read or written only costs the
//! compilation it would have saved. Failed compilations are never stored.

use std::io::Write;
use std::path::{Path, PathBuf};

/// What, besides the sources, decides the SPIR-V: the shaderc version the workspace
/// builds and the options [`crate::ShaderCompiler::compile`] sets. Change it when
/// either changes.
pub const COMPILER_IDENTITY: &str =
    "shaderc 0.10.1 (v2025.3); glsl; vulkan 1.3; optimisation performance; warnings as errors";

/// The entry file's magic and format version.
const MAGIC: &[u8; 8] = b"CMBSPV01";
/// SPIR-V's magic number, the first word of every module.
const SPIRV_MAGIC: u32 = 0x0723_0203;

/// The folder [`crate::ShaderCompiler::with_spirv_cache`] is given by default:
/// `$COMBUSTION_SPIRV_CACHE` when set (`off` or empty: none), else
/// `$XDG_CACHE_HOME/combustion/spirv`, else `$HOME/.cache/combustion/spirv`, else none.
pub fn default_spirv_cache_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("COMBUSTION_SPIRV_CACHE") {
        return (!dir.is_empty() && dir != "off").then(|| PathBuf::from(dir));
    }
    let base = std::env::var_os("XDG_CACHE_HOME")
        .filter(|dir| !dir.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|dir| !dir.is_empty())
                .map(|home| PathBuf::from(home).join(".cache"))
        })?;
    Some(base.join("combustion").join("spirv"))
}

/// A 128-bit digest built up from parts (each part's length is hashed before it, so
/// `("ab", "c")` and `("a", "bc")` differ).
#[derive(Clone, Copy)]
pub(crate) struct Digest {
    low: u64,
    high: u64,
}

impl Digest {
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    pub(crate) fn new() -> Self {
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

    pub(crate) fn part(mut self, bytes: &[u8]) -> Self {
        self.bytes(&(bytes.len() as u64).to_le_bytes());
        self.bytes(bytes);
        self
    }

    fn to_bytes(self) -> [u8; 16] {
        let mut out = [0; 16];
        out[..8].copy_from_slice(&self.low.to_le_bytes());
        out[8..].copy_from_slice(&self.high.to_le_bytes());
        out
    }

    fn hex(self) -> String {
        self.to_bytes().iter().map(|b| format!("{b:02x}")).collect()
    }
}

/// A folder of compiled shaders.
#[derive(Clone, Debug)]
pub(crate) struct SpirvCache {
    dir: PathBuf,
}

impl SpirvCache {
    pub(crate) fn new(dir: PathBuf) -> Self {
        Self { dir }
    }

    fn entry(&self, key: Digest) -> PathBuf {
        self.dir.join(format!("{}.spv", key.hex()))
    }

    /// The SPIR-V stored under `key`, if an intact entry is there.
    pub(crate) fn load(&self, key: Digest) -> Option<Vec<u32>> {
        let bytes = std::fs::read(self.entry(key)).ok()?;
        let header = MAGIC.len() + 16 + 8;
        if bytes.len() < header + 4 || &bytes[..8] != MAGIC || bytes[8..24] != key.to_bytes() {
            return None;
        }
        let checksum = u64::from_le_bytes(bytes[24..32].try_into().ok()?);
        let body = &bytes[header..];
        if body.len() % 4 != 0 || Digest::new().part(body).low != checksum {
            return None;
        }
        let words: Vec<u32> = body
            .chunks_exact(4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
            .collect();
        (words[0] == SPIRV_MAGIC).then_some(words)
    }

    /// Stores `words` under `key`; a failure only loses the entry.
    pub(crate) fn store(&self, key: Digest, words: &[u32]) {
        let body: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        let mut bytes = Vec::with_capacity(32 + body.len());
        bytes.extend_from_slice(MAGIC);
        bytes.extend_from_slice(&key.to_bytes());
        bytes.extend_from_slice(&Digest::new().part(&body).low.to_le_bytes());
        bytes.extend_from_slice(&body);
        let _ = self.write_atomically(&self.entry(key), &bytes);
    }

    fn write_atomically(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
        std::fs::create_dir_all(&self.dir)?;
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let temporary = path.with_extension(format!(
            "{}-{}.tmp",
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
