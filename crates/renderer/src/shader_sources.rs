//! The embedded GLSL sources (see build.rs).
use combustion_vk::ShaderSources;

include!(concat!(env!("OUT_DIR"), "/shader_files.rs"));

pub(crate) fn sources() -> ShaderSources {
    ShaderSources::new(SHADER_FILES.iter().copied())
}
