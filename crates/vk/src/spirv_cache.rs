//! SPIR-V compiled once and kept on disk ([`crate::disk_cache`]):
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

use std::path::PathBuf;

use crate::disk_cache::{default_cache_dir, Digest, DiskCache};

/// What, besides the sources, decides the SPIR-V: the shaderc version the workspace
/// builds and the options [`crate::ShaderCompiler::compile`] sets. Change it when
/// either changes.
pub const COMPILER_IDENTITY: &str =
    "shaderc 0.10.1 (v2025.3); glsl; vulkan 1.3; optimisation performance; warnings as errors";

/// The entry file's magic and format version.
const MAGIC: [u8; 8] = *b"CMBSPV01";

/// The folder [`crate::ShaderCompiler::with_spirv_cache`] is given by default:
/// `$COMBUSTION_SPIRV_CACHE` when set (`off` or empty: none), else
/// `$XDG_CACHE_HOME/combustion/spirv`, else `$HOME/.cache/combustion/spirv`, else none.
pub fn default_spirv_cache_dir() -> Option<PathBuf> {
    default_cache_dir("COMBUSTION_SPIRV_CACHE", "spirv")
}

/// A folder of compiled shaders.
#[derive(Clone, Debug)]
pub(crate) struct SpirvCache {
    entries: DiskCache,
}

impl SpirvCache {
    pub(crate) fn new(dir: PathBuf) -> Self {
        Self {
            entries: DiskCache::new(dir, MAGIC, "spv"),
        }
    }

    /// The SPIR-V stored under `key`, if an intact entry is there.
    pub(crate) fn load(&self, key: Digest) -> Option<Vec<u32>> {
        crate::disk_cache::bodies::spirv_words(&self.entries.load(key)?)
    }

    /// Stores `words` under `key`; a failure only loses the entry.
    pub(crate) fn store(&self, key: Digest, words: &[u32]) {
        let body: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        self.entries.store(key, &body);
    }
}
