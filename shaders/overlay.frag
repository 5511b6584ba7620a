#version 460
#extension GL_GOOGLE_include_directive : require
// Text overlay: the overlay image's texel (under the panels), or a glyph's coverage from the atlas (exact texel, no filtering) times the
// quad's opacity, blended over the output (src·α + dst·(1 − α)). Colours are given as
// displayed (sRGB-encoded); targets the driver encodes (_SRGB) or that hold linear values
// (float formats) get them decoded first (the OUTPUT_* defines of tonemap.frag).
#include "overlay.glsl"
#include "srgb.glsl"
#include "bindings/overlay.glsl"  // set 0: see combustion_renderer::bindings::OVERLAY

layout(location = 0) in vec2 atlas_texel;
layout(location = 1) flat in vec4 color;
layout(location = 2) flat in float solid;

layout(location = 0) out vec4 out_color;

void main() {
    float coverage = 1.0;
    vec3 rgb = color.rgb;
    uvec2 texel = uvec2(floor(atlas_texel));
    if (solid == 0.0) {
        uint index = texel.y * push.atlas_width + texel.x;
        uint word = overlay_atlas[index >> 2];
        coverage = float((word >> ((index & 3u) * 8u)) & 0xffu) / 255.0;
    } else if (solid == 2.0) {
        vec4 image = unpackUnorm4x8(overlay_image[texel.y * push.image_width + texel.x]);
        rgb = image.rgb;
        coverage = image.a;
    }
#if defined(OUTPUT_LINEAR) || defined(OUTPUT_HARDWARE_SRGB)
    rgb = srgb_decode_unorm8(rgb);
#endif
    out_color = vec4(rgb, color.a * coverage);
}
