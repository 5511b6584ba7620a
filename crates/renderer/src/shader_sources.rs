//! The embedded GLSL sources (see build.rs) and the generated binding headers.
use combustion_vk::ShaderSources;

include!(concat!(env!("OUT_DIR"), "/shader_files.rs"));

/// The embedded sources and the binding headers generated from [`crate::bindings`].
pub(crate) fn sources() -> ShaderSources {
    crate::bindings::ALL.iter().fold(
        ShaderSources::new(SHADER_FILES.iter().copied()),
        |sources, set| sources.with_generated(set.header_path(), set.glsl()),
    )
}
