#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Bloom's composite (combustion_renderer's passes/bloom.rs): the glow at each pixel (the
// largest level sampled bilinearly, scaled by the energy pass so that it holds exactly the frame's
// radiance) blended over the HDR image at alpha = the intensity: radiance becomes
// (1 − i) · radiance + i · glow, the fraction i of the frame's light redistributed.
#include "bindings/bloom_composite.glsl"  // set 0: levels, sums
#include "push/bloom_composite.glsl"

#define BLOOM_TEXEL(p) texelFetch(levels, p, 0)
#include "bloom.glsl"

layout(location = 0) out vec4 out_color;

void main() {
    uint s = 8u * 256u;
    vec3 scale = vec3(sums[s], sums[s + 1u], sums[s + 2u]);
    vec3 glow = scale * bloom_upsampled(push.largest, ivec2(gl_FragCoord.xy));
    out_color = vec4(glow, push.intensity);
}
