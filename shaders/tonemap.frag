#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Tonemap pass: HDR radiance → display. The attachment is RGBA8_UNORM holding
// sRGB-encoded values; the encoding is done here with the exact formula rather than by
// the driver's approximate conversion on write.
#include "tonemap.glsl"
#include "srgb.glsl"

layout(set = 0, binding = 0) uniform texture2D hdr_image;

layout(push_constant) uniform TonemapPush {
    float exposure;
} push;

layout(location = 0) out vec4 out_color;

void main() {
    vec3 radiance = texelFetch(hdr_image, ivec2(gl_FragCoord.xy), 0).rgb;
    out_color = vec4(srgb_encode(tonemap_exponential(radiance * push.exposure)), 1.0);
}
