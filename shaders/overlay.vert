#version 460
#extension GL_GOOGLE_include_directive : require
// Text overlay: one instance per quad (a panel's background or a glyph), six vertices.
#include "overlay.glsl"
#include "bindings/overlay.glsl"  // set 0: see combustion_renderer::bindings::OVERLAY

layout(location = 0) out vec2 atlas_texel;
layout(location = 1) flat out vec4 color;
layout(location = 2) flat out float solid;

const vec2 CORNERS[6] = vec2[](
    vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(0.0, 1.0),
    vec2(0.0, 1.0), vec2(1.0, 0.0), vec2(1.0, 1.0));

void main() {
    OverlayQuad quad = overlay_quads[gl_InstanceIndex];
    vec2 corner = CORNERS[gl_VertexIndex];
    vec2 pixel = mix(quad.rect.xy, quad.rect.zw, corner);
    gl_Position = vec4(pixel / push.target_size * 2.0 - 1.0, 0.0, 1.0);
    // At a pixel's centre this is the atlas texel's centre: floor() finds it exactly.
    atlas_texel = quad.atlas.xy + corner * (quad.rect.zw - quad.rect.xy);
    color = quad.color;
    solid = quad.atlas.z;
}
