#version 460
#extension GL_GOOGLE_include_directive : require
// Shadow-caster pass, fragment stage: depth only, nothing written here; the ALPHA_MASK
// pipeline discards where a cut-out material's surface is absent, so light passes
// through the holes (the same test as the G-buffer pass's).
#ifdef ALPHA_MASK
#include "gpu_types.glsl"
#include "bindings/shadow_casters.glsl"      // set 0: the object and material tables
#include "bindings/material_textures.glsl"   // set 1: the caster's material's textures
#include "alpha_mask.glsl"

layout(location = 0) in vec2 in_base_color_uv;
layout(location = 1) flat in uint in_material;
layout(location = 2) in float in_vertex_alpha;
#endif

void main() {
#ifdef ALPHA_MASK
    if (alpha_cut_away(materials[in_material], base_color_texture, in_base_color_uv,
                       in_vertex_alpha)) {
        discard;
    }
#endif
}
