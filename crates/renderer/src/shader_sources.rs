//! The embedded GLSL sources (see build.rs), the binding headers generated from
//! [`crate::bindings`], and the constants header generated from the Rust constants the
//! shaders share ([`CONSTANTS_HEADER`]): no number the two sides must agree on is
//! written twice by hand.
use combustion_vk::ShaderSources;

use crate::environment::{CODES, CODE_TABLE_SIZE, ENERGY_TABLE_SIZE, TABLE_SIZE};
use crate::gpu_types::{
    LIGHT_KIND_DIRECTIONAL, LIGHT_KIND_POINT, LIGHT_KIND_SPOT,
    MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR, MATERIAL_FLAG_UNLIT,
};
use crate::light_cull::TILE_SIZE;
use crate::options::DebugView;
use crate::shadows::{
    CASCADE_BLEND_BAND, LAYER_CUBE_FACE, PCF_RADIUS_TEXELS, SOFT_MAX_RADIUS_TEXELS, SOFT_TAPS,
};

include!(concat!(env!("OUT_DIR"), "/shader_files.rs"));

/// The path shaders include the generated constants by.
pub(crate) const CONSTANTS_HEADER: &str = "bindings/constants.glsl";

/// The value of a shared constant, as GLSL spells it.
#[derive(Clone, Copy, Debug, PartialEq)]
enum GlslValue {
    /// An `int` literal (`16`).
    Int(i64),
    /// A `uint` literal (`16u`).
    Uint(u32),
    /// A `float` literal (`1.0`), written with the digits that give back the f32.
    Float(f32),
}

impl std::fmt::Display for GlslValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Int(v) => write!(f, "{v}"),
            Self::Uint(v) => write!(f, "{v}u"),
            Self::Float(v) => write!(f, "{v:?}"),
        }
    }
}

/// One shared constant: its GLSL name, value, and the Rust item it comes from.
struct SharedConstant {
    name: String,
    value: GlslValue,
    source: &'static str,
}

/// Every constant the shaders share with the Rust code.
fn shared_constants() -> Vec<SharedConstant> {
    let constant = |name: &str, value, source| SharedConstant {
        name: name.to_owned(),
        value,
        source,
    };
    let mut all = vec![
        // An int: light_cull.comp multiplies ivec2 tile coordinates by it.
        constant(
            "TILE_SIZE",
            GlslValue::Int(i64::from(TILE_SIZE)),
            "light_cull::TILE_SIZE",
        ),
        constant(
            "ENERGY_TABLE_SIZE",
            GlslValue::Uint(ENERGY_TABLE_SIZE),
            "environment::ENERGY_TABLE_SIZE",
        ),
        constant(
            "SHEEN_TABLE_SIZE",
            GlslValue::Uint(combustion_optics::sheen::SHEEN_TABLE_SIZE as u32),
            "combustion_optics::sheen::SHEEN_TABLE_SIZE",
        ),
        constant(
            "TABLE_MU_MIN",
            GlslValue::Float(combustion_optics::environment::TABLE_MU_MIN as f32),
            "combustion_optics::environment::TABLE_MU_MIN",
        ),
        constant(
            "ENVIRONMENT_TABLE_SIZE",
            GlslValue::Uint(TABLE_SIZE),
            "environment::TABLE_SIZE",
        ),
        constant(
            "ENVIRONMENT_CODE_TABLE_SIZE",
            GlslValue::Uint(CODE_TABLE_SIZE),
            "environment::CODE_TABLE_SIZE",
        ),
        constant(
            "ENVIRONMENT_CODES",
            GlslValue::Uint(CODES),
            "environment::CODES",
        ),
        constant(
            "MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR",
            GlslValue::Uint(MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR),
            "gpu_types::MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR",
        ),
        constant(
            "MATERIAL_FLAG_UNLIT",
            GlslValue::Uint(MATERIAL_FLAG_UNLIT),
            "gpu_types::MATERIAL_FLAG_UNLIT",
        ),
        constant(
            "LIGHT_KIND_DIRECTIONAL",
            GlslValue::Float(LIGHT_KIND_DIRECTIONAL),
            "gpu_types::LIGHT_KIND_DIRECTIONAL",
        ),
        constant(
            "LIGHT_KIND_POINT",
            GlslValue::Float(LIGHT_KIND_POINT),
            "gpu_types::LIGHT_KIND_POINT",
        ),
        constant(
            "LIGHT_KIND_SPOT",
            GlslValue::Float(LIGHT_KIND_SPOT),
            "gpu_types::LIGHT_KIND_SPOT",
        ),
        constant(
            "SHADOW_PCF_RADIUS_TEXELS",
            GlslValue::Float(PCF_RADIUS_TEXELS),
            "shadows::PCF_RADIUS_TEXELS",
        ),
        constant(
            "SHADOW_CASCADE_BLEND_BAND",
            GlslValue::Float(CASCADE_BLEND_BAND),
            "shadows::CASCADE_BLEND_BAND",
        ),
        constant(
            "SHADOW_SOFT_TAPS",
            GlslValue::Int(i64::from(SOFT_TAPS)),
            "shadows::SOFT_TAPS",
        ),
        constant(
            "SHADOW_SOFT_MAX_RADIUS_TEXELS",
            GlslValue::Float(SOFT_MAX_RADIUS_TEXELS),
            "shadows::SOFT_MAX_RADIUS_TEXELS",
        ),
        constant(
            "SHADOW_LAYER_CUBE_FACE",
            GlslValue::Float(LAYER_CUBE_FACE),
            "shadows::LAYER_CUBE_FACE",
        ),
        constant(
            "ENVIRONMENT_RAY_OFFSET",
            GlslValue::Float(crate::accel::ENVIRONMENT_RAY_OFFSET as f32),
            "accel::ENVIRONMENT_RAY_OFFSET",
        ),
        constant(
            "TRACE_MASK_OCCLUDES",
            GlslValue::Uint(u32::from(crate::accel::OCCLUDES)),
            "accel::OCCLUDES",
        ),
        constant(
            "TRACE_MASK_SEEN_ONLY",
            GlslValue::Uint(u32::from(crate::accel::SEEN_ONLY)),
            "accel::SEEN_ONLY",
        ),
    ];
    for view in DebugView::ALL {
        if view != DebugView::None {
            all.push(SharedConstant {
                name: format!("DEBUG_VIEW_{}", upper_snake(&format!("{view:?}"))),
                value: GlslValue::Uint(view as u32),
                source: "DebugView",
            });
        }
    }
    all
}

/// `BaseColor` → `BASE_COLOR`.
fn upper_snake(camel: &str) -> String {
    let mut out = String::new();
    for (i, c) in camel.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            out.push('_');
        }
        out.push(c.to_ascii_uppercase());
    }
    out
}

/// The text of [`CONSTANTS_HEADER`]: a `#define` per shared constant.
pub(crate) fn constants_glsl() -> String {
    let mut out = String::from(
        "// Generated from the renderer's Rust constants (shader_sources.rs); do not edit.\n#ifndef COMBUSTION_BINDINGS_CONSTANTS_GLSL\n#define COMBUSTION_BINDINGS_CONSTANTS_GLSL\n",
    );
    for c in shared_constants() {
        out += &format!(
            "#define {} {}  // combustion_renderer::{}\n",
            c.name, c.value, c.source
        );
    }
    out += "#endif\n";
    out
}

/// The embedded sources, `headers` generated for them (each declared set's bindings, each
/// pass's push block: `passes::generated_headers`, by path and text) and the constants
/// header.
pub(crate) fn sources(headers: Vec<(String, String)>) -> ShaderSources {
    headers
        .into_iter()
        .fold(
            ShaderSources::new(SHADER_FILES.iter().copied()),
            |sources, (path, text)| sources.with_generated(path, text),
        )
        .with_generated(CONSTANTS_HEADER, constants_glsl())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_header_defines_each_constant_with_its_rust_value() {
        let glsl = constants_glsl();
        let defines: Vec<&str> = glsl
            .lines()
            .filter_map(|line| line.strip_prefix("#define "))
            .map(|line| line.split("  //").next().unwrap())
            .collect();
        let mut expected = vec![
            format!("TILE_SIZE {TILE_SIZE}"),
            format!("ENERGY_TABLE_SIZE {ENERGY_TABLE_SIZE}u"),
            format!(
                "SHEEN_TABLE_SIZE {}u",
                combustion_optics::sheen::SHEEN_TABLE_SIZE
            ),
            format!("TABLE_MU_MIN {:?}", combustion_optics::environment::TABLE_MU_MIN as f32),
            format!("ENVIRONMENT_TABLE_SIZE {TABLE_SIZE}u"),
            format!("ENVIRONMENT_CODE_TABLE_SIZE {CODE_TABLE_SIZE}u"),
            format!("ENVIRONMENT_CODES {CODES}u"),
            format!("MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR {MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR}u"),
            format!("MATERIAL_FLAG_UNLIT {MATERIAL_FLAG_UNLIT}u"),
            format!("LIGHT_KIND_DIRECTIONAL {LIGHT_KIND_DIRECTIONAL:.1}"),
            format!("LIGHT_KIND_POINT {LIGHT_KIND_POINT:.1}"),
            format!("LIGHT_KIND_SPOT {LIGHT_KIND_SPOT:.1}"),
            format!("SHADOW_PCF_RADIUS_TEXELS {PCF_RADIUS_TEXELS:?}"),
            format!("SHADOW_CASCADE_BLEND_BAND {CASCADE_BLEND_BAND:?}"),
            format!("SHADOW_SOFT_TAPS {SOFT_TAPS}"),
            format!("SHADOW_SOFT_MAX_RADIUS_TEXELS {SOFT_MAX_RADIUS_TEXELS:?}"),
            format!("SHADOW_LAYER_CUBE_FACE {LAYER_CUBE_FACE:?}"),
            format!(
                "ENVIRONMENT_RAY_OFFSET {:?}",
                crate::accel::ENVIRONMENT_RAY_OFFSET as f32
            ),
            format!("TRACE_MASK_OCCLUDES {}u", crate::accel::OCCLUDES),
            format!("TRACE_MASK_SEEN_ONLY {}u", crate::accel::SEEN_ONLY),
        ];
        for (name, view) in [
            ("BASE_COLOR", DebugView::BaseColor),
            ("NORMAL", DebugView::Normal),
            ("ROUGHNESS", DebugView::Roughness),
            ("ANISOTROPY_STRENGTH", DebugView::AnisotropyStrength),
            ("ANISOTROPY_DIRECTION", DebugView::AnisotropyDirection),
            ("METALNESS", DebugView::Metalness),
            ("MATERIAL_INDEX", DebugView::MaterialIndex),
            ("DEPTH", DebugView::Depth),
            ("DISTRIBUTION", DebugView::Distribution),
            ("SMITH", DebugView::Smith),
            ("FRESNEL", DebugView::Fresnel),
            ("DIFFUSE", DebugView::Diffuse),
            ("LIGHTS_PER_TILE", DebugView::LightsPerTile),
            ("SHADOW_FACTOR", DebugView::ShadowFactor),
            ("SHADOW_CASCADE", DebugView::ShadowCascade),
        ] {
            expected.push(format!("DEBUG_VIEW_{name} {}u", view as u32));
        }
        // The guard, then one define per constant.
        assert_eq!(defines[0], "COMBUSTION_BINDINGS_CONSTANTS_GLSL");
        assert_eq!(defines[1..], expected);
        // Spelled as the shaders had them by hand before.
        assert!(glsl.contains("#define TILE_SIZE 16  //"));
        assert!(glsl.contains("#define ENVIRONMENT_TABLE_SIZE 32u  //"));
        assert!(glsl.contains("#define LIGHT_KIND_SPOT 2.0  //"));
        assert!(glsl.contains("#define DEBUG_VIEW_LIGHTS_PER_TILE 13u  //"));
    }

    #[test]
    fn shaders_include_the_constants_header_and_copy_none_of_them() {
        let sources = sources(crate::passes::generated_headers());
        assert_eq!(
            sources.get(CONSTANTS_HEADER),
            Some(constants_glsl().as_str())
        );
        for (path, text) in SHADER_FILES {
            for c in shared_constants() {
                assert!(
                    !text.contains(&format!("#define {} ", c.name)),
                    "{path} defines {} by hand",
                    c.name
                );
            }
        }
    }
}
