#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Tonemap pass: HDR radiance → display. The attachment is RGBA8_SRGB, so the hardware
// applies the sRGB encoding on write.
#include "tonemap.glsl"

layout(set = 0, binding = 0) uniform texture2D hdr_image;

layout(push_constant) uniform TonemapPush {
    float exposure;
} push;

layout(location = 0) out vec4 out_color;

void main() {
    vec3 radiance = texelFetch(hdr_image, ivec2(gl_FragCoord.xy), 0).rgb;
    out_color = vec4(tonemap_exponential(radiance * push.exposure), 1.0);
}
