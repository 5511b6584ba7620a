use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use crate::device::Device;
use crate::disk_cache::Digest;
use crate::error::{VkError, VkResultExt};
use crate::spirv_cache::{SpirvCache, COMPILER_IDENTITY};

/// GLSL sources by path relative to the shader root (e.g. `lighting.frag`,
/// `include/brdf.glsl`). Renderers embed theirs at build time, so no file is read at
/// run time; `#include "x.glsl"` resolves against `include/` and the including file's folder.
#[derive(Clone, Debug, Default)]
pub struct ShaderSources {
    files: HashMap<String, Cow<'static, str>>,
}

impl ShaderSources {
    /// Sources from `(path, text)` pairs, e.g. files embedded with `include_str!`.
    pub fn new(files: impl IntoIterator<Item = (&'static str, &'static str)>) -> Self {
        Self {
            files: files
                .into_iter()
                .map(|(path, text)| (path.to_owned(), Cow::Borrowed(text)))
                .collect(),
        }
    }

    /// Adds (or replaces) a file made at run time, e.g. a header generated from the
    /// renderer's binding declarations.
    pub fn with_generated(mut self, path: impl Into<String>, text: String) -> Self {
        self.files.insert(path.into(), Cow::Owned(text));
        self
    }

    /// The text of `path`, if there is such a source.
    pub fn get(&self, path: &str) -> Option<&str> {
        self.files.get(path).map(|text| &**text)
    }

    fn resolve(&self, requested: &str, requesting: &str) -> Option<(String, &str)> {
        let folder = requesting.rsplit_once('/').map(|(dir, _)| dir);
        let candidates = [
            folder.map(|dir| format!("{dir}/{requested}")),
            Some(requested.to_owned()),
            Some(format!("include/{requested}")),
        ];
        candidates
            .into_iter()
            .flatten()
            .find_map(|path| self.get(&path).map(|text| (path, text)))
    }
}

/// The pipeline stage a shader is compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderStage {
    /// A vertex shader.
    Vertex,
    /// A fragment shader.
    Fragment,
    /// A compute shader.
    Compute,
}

impl ShaderStage {
    fn kind(self) -> shaderc::ShaderKind {
        match self {
            Self::Vertex => shaderc::ShaderKind::Vertex,
            Self::Fragment => shaderc::ShaderKind::Fragment,
            Self::Compute => shaderc::ShaderKind::Compute,
        }
    }
    /// The stage as Vulkan shader stage flags (for layouts and push constants).
    pub fn flags(self) -> vk::ShaderStageFlags {
        match self {
            Self::Vertex => vk::ShaderStageFlags::VERTEX,
            Self::Fragment => vk::ShaderStageFlags::FRAGMENT,
            Self::Compute => vk::ShaderStageFlags::COMPUTE,
        }
    }
}

/// Compiles GLSL to SPIR-V (Vulkan 1.3 target) with shaderc.
pub struct ShaderCompiler {
    compiler: shaderc::Compiler,
    sources: ShaderSources,
    /// Compilations attempted ([`ShaderCompiler::compilations`]).
    compilations: std::sync::atomic::AtomicU64,
    /// Wall time spent in [`ShaderCompiler::compile`], in nanoseconds
    /// ([`ShaderCompiler::compile_time`]).
    compile_nanos: std::sync::atomic::AtomicU64,
    /// Where compiled SPIR-V is kept between processes, if anywhere.
    cache: Option<SpirvCache>,
    /// Compilations answered from `cache` ([`ShaderCompiler::cache_hits`]).
    cache_hits: std::sync::atomic::AtomicU64,
    /// The compiler's identity and every source, the start of each compilation's key.
    sources_digest: Digest,
}

impl ShaderCompiler {
    /// A compiler of `sources`.
    ///
    /// # Errors
    /// [`VkError::Shader`] when shaderc cannot be started.
    pub fn new(sources: ShaderSources) -> Result<Self, VkError> {
        let compiler = shaderc::Compiler::new()
            .map_err(|e| VkError::Shader(format!("cannot start the shader compiler: {e}")))?;
        let mut paths: Vec<&String> = sources.files.keys().collect();
        paths.sort();
        let sources_digest = paths.into_iter().fold(
            Digest::new().part(COMPILER_IDENTITY.as_bytes()),
            |digest, path| {
                digest
                    .part(path.as_bytes())
                    .part(sources.files[path].as_bytes())
            },
        );
        Ok(Self {
            compiler,
            sources,
            compilations: Default::default(),
            compile_nanos: Default::default(),
            cache: None,
            cache_hits: Default::default(),
            sources_digest,
        })
    }

    /// Keeps compiled SPIR-V in `dir` (created when first written) and looks each
    /// compilation up there first; `None` compiles every time.
    /// [`default_spirv_cache_dir`](crate::default_spirv_cache_dir) is the usual choice.
    /// A folder that cannot be used only costs the time it would have saved.
    pub fn with_spirv_cache(mut self, dir: Option<std::path::PathBuf>) -> Self {
        self.cache = dir.map(SpirvCache::new);
        self
    }

    /// How many of [`ShaderCompiler::compilations`] were answered from the SPIR-V cache.
    pub fn cache_hits(&self) -> u64 {
        self.cache_hits.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// How many compilations were asked of this compiler (failed ones included).
    pub fn compilations(&self) -> u64 {
        self.compilations.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// The wall time spent compiling so far (every [`ShaderCompiler::compile`] call's,
    /// failed ones and cache lookups included).
    pub fn compile_time(&self) -> std::time::Duration {
        std::time::Duration::from_nanos(
            self.compile_nanos
                .load(std::sync::atomic::Ordering::Relaxed),
        )
    }

    /// Compiles `path` with `defines` (`NAME` or `NAME=value`). Errors carry
    /// `file:line: message` as reported by glslang. Returns SPIR-V words for
    /// [`ShaderModule::new`]; warnings are errors, and entry points are `main`.
    ///
    /// # Errors
    /// [`VkError::Shader`] when `path` or an include is not among the sources, or when
    /// compilation fails (the diagnostics joined on one line with ` | `).
    pub fn compile(
        &self,
        path: &str,
        stage: ShaderStage,
        defines: &[(&str, Option<&str>)],
    ) -> Result<Vec<u32>, VkError> {
        self.compilations
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let started = std::time::Instant::now();
        let compiled = self.compile_or_load(path, stage, defines);
        let nanos = u64::try_from(started.elapsed().as_nanos()).unwrap_or(u64::MAX);
        self.compile_nanos
            .fetch_add(nanos, std::sync::atomic::Ordering::Relaxed);
        compiled
    }

    fn compile_or_load(
        &self,
        path: &str,
        stage: ShaderStage,
        defines: &[(&str, Option<&str>)],
    ) -> Result<Vec<u32>, VkError> {
        let key = defines.iter().fold(
            self.sources_digest
                .part(path.as_bytes())
                .part(format!("{stage:?}").as_bytes()),
            |digest, (name, value)| {
                digest
                    .part(name.as_bytes())
                    .part(value.map_or(&[0xff][..], str::as_bytes))
            },
        );
        if let Some(words) = self.cache.as_ref().and_then(|cache| cache.load(key)) {
            self.cache_hits
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            return Ok(words);
        }
        let words = self.run_shaderc(path, stage, defines)?;
        if let Some(cache) = &self.cache {
            cache.store(key, &words);
        }
        Ok(words)
    }

    fn run_shaderc(
        &self,
        path: &str,
        stage: ShaderStage,
        defines: &[(&str, Option<&str>)],
    ) -> Result<Vec<u32>, VkError> {
        let source = self
            .sources
            .get(path)
            .ok_or_else(|| VkError::Shader(format!("no shader source named {path}")))?;
        let mut options = shaderc::CompileOptions::new()
            .map_err(|e| VkError::Shader(format!("cannot create compile options: {e}")))?;
        options.set_target_env(
            shaderc::TargetEnv::Vulkan,
            shaderc::EnvVersion::Vulkan1_3 as u32,
        );
        options.set_source_language(shaderc::SourceLanguage::GLSL);
        options.set_optimization_level(shaderc::OptimizationLevel::Performance);
        options.set_warnings_as_errors();
        for (name, value) in defines {
            options.add_macro_definition(name, *value);
        }
        let sources = self.sources.clone();
        options.set_include_callback(move |requested, _kind, requesting, _depth| {
            sources
                .resolve(requested, requesting)
                .map(|(resolved_name, content)| shaderc::ResolvedInclude {
                    resolved_name,
                    content: content.to_owned(),
                })
                .ok_or_else(|| format!("cannot find include file {requested}"))
        });
        let artifact = self
            .compiler
            .compile_into_spirv(source, stage.kind(), path, "main", Some(&options))
            .map_err(|e| {
                // glslang reports one `file:line: error: ...` per line; keep them on one line.
                let messages: Vec<_> = e
                    .to_string()
                    .lines()
                    .map(str::trim)
                    .filter(|l| !l.is_empty())
                    .map(str::to_owned)
                    .collect();
                VkError::Shader(format!("compiling {path}: {}", messages.join(" | ")))
            })?;
        Ok(artifact.as_binary().to_vec())
    }
}

/// A `VkShaderModule`, destroyed when dropped.
pub struct ShaderModule {
    device: Arc<Device>,
    raw: vk::ShaderModule,
    stage: ShaderStage,
}

impl ShaderModule {
    /// A module of `spirv` (as [`ShaderCompiler::compile`] returns it) for `stage`.
    ///
    /// # Errors
    /// [`VkError`] when `vkCreateShaderModule` fails.
    pub fn new(device: &Arc<Device>, spirv: &[u32], stage: ShaderStage) -> Result<Self, VkError> {
        let info = vk::ShaderModuleCreateInfo::default().code(spirv);
        // SAFETY: SPIR-V comes from shaderc.
        let raw = unsafe { device.raw().create_shader_module(&info, None) }
            .what("vkCreateShaderModule")?;
        Ok(Self {
            device: device.clone(),
            raw,
            stage,
        })
    }
    /// The Vulkan shader module, valid while `self` lives.
    pub fn raw(&self) -> vk::ShaderModule {
        self.raw
    }
    /// The stage the module was made for.
    pub fn stage(&self) -> ShaderStage {
        self.stage
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        // SAFETY: modules are only needed during pipeline creation.
        unsafe { self.device.raw().destroy_shader_module(self.raw, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHADER: &str = "#version 460\nlayout(location = 0) out vec4 colour;\nvoid main() { colour = vec4(SHADE); }\n";

    fn compiler(cache: &std::path::Path, generated: &str) -> ShaderCompiler {
        ShaderCompiler::new(
            ShaderSources::new([
                ("plain.frag", SHADER),
                ("broken.frag", "#version 460\nvoid main() { x; }\n"),
            ])
            .with_generated("include/generated.glsl", generated.to_owned()),
        )
        .unwrap()
        .with_spirv_cache(Some(cache.to_owned()))
    }

    /// The SPIR-V cache answers only the same request on the same sources, and never
    /// stores a failure.
    #[test]
    fn the_spirv_cache_answers_only_the_same_compilation() {
        let cache =
            std::env::temp_dir().join(format!("combustion-spirv-cache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&cache);
        let stage = ShaderStage::Fragment;
        let first = compiler(&cache, "// one");
        let half = first
            .compile("plain.frag", stage, &[("SHADE", Some("0.5"))])
            .unwrap();
        assert_eq!(first.cache_hits(), 0);
        let again = first
            .compile("plain.frag", stage, &[("SHADE", Some("0.5"))])
            .unwrap();
        assert_eq!(
            (first.cache_hits(), &again),
            (1, &half),
            "the same request is a hit"
        );
        let quarter = first
            .compile("plain.frag", stage, &[("SHADE", Some("0.25"))])
            .unwrap();
        assert_eq!(first.cache_hits(), 1, "another define's value is a miss");
        assert_ne!(quarter, half);
        assert!(first.compile("broken.frag", stage, &[]).is_err());
        assert!(first.compile("broken.frag", stage, &[]).is_err());
        assert_eq!(first.cache_hits(), 1, "a failure is never stored");
        // Another process with the same sources finds both; with any source changed
        // (here a generated header no shader includes) none.
        let same = compiler(&cache, "// one");
        same.compile("plain.frag", stage, &[("SHADE", Some("0.25"))])
            .unwrap();
        assert_eq!(same.cache_hits(), 1);
        let edited = compiler(&cache, "// two");
        edited
            .compile("plain.frag", stage, &[("SHADE", Some("0.5"))])
            .unwrap();
        assert_eq!(edited.cache_hits(), 0);
        assert_eq!(
            std::fs::read_dir(&cache).unwrap().count(),
            3,
            "three entries, no temporaries"
        );
        std::fs::remove_dir_all(&cache).unwrap();
    }
}
