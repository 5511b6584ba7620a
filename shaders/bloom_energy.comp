#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Bloom's energy (combustion_renderer's passes/bloom.rs): the frame's radiance summed per
// channel, and the glow's (the largest level upsampled to each pixel as the composite
// draws it, summed from the level's texels by their weights); the glow is then scaled by
// their ratio, so that blending it in at any intensity
// moves radiance without adding or losing any (Karis's average and the chain's sums of
// levels change its total; the edges repeat texels).
// push.stage 0: 256 groups each sum a share of the pixels into partial sums;
// push.stage 1: one group sums the partial sums and writes the scale (0 where the glow
// holds nothing).
#include "bindings/bloom_energy.glsl"  // set 0: hdr_image, levels, sums
#include "push/bloom_energy.glsl"

#define BLOOM_TEXEL(p) texelFetch(levels, p, 0)
#include "bloom.glsl"

layout(local_size_x = 256) in;

// Partial sums per group: radiance (xyz) and glow (xyz), 8 floats each; the scale after
// them (at 8 · PARTIALS).
const uint PARTIALS = 256u;

shared vec3 radiance_sums[256];
shared vec3 glow_sums[256];

void reduce(uint i) {
    for (uint half_size = 128u; half_size > 0u; half_size >>= 1u) {
        barrier();
        if (i < half_size) {
            radiance_sums[i] += radiance_sums[i + half_size];
            glow_sums[i] += glow_sums[i + half_size];
        }
    }
    barrier();
}

void main() {
    uint i = gl_LocalInvocationIndex;
    vec3 radiance = vec3(0.0);
    vec3 glow = vec3(0.0);
    if (push.stage == 0u) {
        // Group g sums rows g, g + 256, …: of the frame, and of the largest level, each
        // texel by what it weighs summed over the frame's pixels the composite draws.
        ivec2 size = textureSize(hdr_image, 0);
        for (int y = int(gl_WorkGroupID.x); y < size.y; y += int(PARTIALS)) {
            for (int x = int(i); x < size.x; x += 256) {
                radiance += texelFetch(hdr_image, ivec2(x, y), 0).rgb;
            }
        }
        ivec2 count = ivec2(push.largest.zw);
        for (int y = int(gl_WorkGroupID.x); y < count.y; y += int(PARTIALS)) {
            float wy = bloom_upsampled_weight(y, count.y, size.y);
            for (int x = int(i); x < count.x; x += 256) {
                float w = wy * bloom_upsampled_weight(x, count.x, size.x);
                glow += w * bloom_texel(push.largest, ivec2(x, y));
            }
        }
    } else {
        uint g = 8u * i;
        radiance = vec3(sums[g], sums[g + 1u], sums[g + 2u]);
        glow = vec3(sums[g + 4u], sums[g + 5u], sums[g + 6u]);
    }
    radiance_sums[i] = radiance;
    glow_sums[i] = glow;
    reduce(i);
    if (i != 0u) {
        return;
    }
    radiance = radiance_sums[0];
    glow = glow_sums[0];
    if (push.stage == 0u) {
        uint g = 8u * gl_WorkGroupID.x;
        sums[g] = radiance.x;
        sums[g + 1u] = radiance.y;
        sums[g + 2u] = radiance.z;
        sums[g + 4u] = glow.x;
        sums[g + 5u] = glow.y;
        sums[g + 6u] = glow.z;
    } else {
        uint s = 8u * PARTIALS;
        for (int c = 0; c < 3; ++c) {
            sums[s + uint(c)] = glow[c] > 0.0 ? radiance[c] / glow[c] : 0.0;
        }
        // The totals, for the host's and the tests' eyes (read back with the state).
        sums[s + 4u] = radiance.x + radiance.y + radiance.z;
        sums[s + 5u] = glow.x + glow.y + glow.z;
    }
}
