#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Bloom's chain (combustion_renderer's passes/bloom.rs; Jimenez, "Next generation post
// processing in Call of Duty: Advanced Warfare", 2014), one level per dispatch into an
// atlas of levels, each half the size of the one before:
// - DOWN from the HDR image (push.mode 0) or the level before (1): the 13-tap filter, five
//   2×2 boxes around the target texel's footprint (the centre one weighted 1/2, the four
//   corner ones 1/8 each); from the HDR image each box is weighted by 1 / (1 + its
//   luminance) (Karis's average), so a lone bright pixel does not become a square;
// - UP (2): the level becomes itself plus the 3×3 tent of the next smaller level (16
//   texels by their summed weights), so the smallest level's glow reaches the largest.
// The energy pass then scales the result so that it holds exactly the frame's radiance.
#include "bindings/bloom_chain.glsl"  // set 0: hdr_image, levels
#include "push/bloom_chain.glsl"

#define BLOOM_TEXEL(p) imageLoad(levels, p)
#include "bloom.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// The source's texel p: the HDR image's (edge repeated), or the source level's.
vec3 source_texel(ivec2 p) {
    if (push.mode == 0u) {
        ivec2 size = textureSize(hdr_image, 0);
        return texelFetch(hdr_image, clamp(p, ivec2(0), size - 1), 0).rgb;
    }
    return bloom_texel(push.source, p);
}

float luminance(vec3 c) {
    return dot(c, vec3(0.2126, 0.7152, 0.0722));
}

// The 6×6 source texels the 13-tap filter of one target texel reads (from 2t − 2), each
// read once. (A group's 20×20 texels shared through shared memory cost twice as much on
// lavapipe: 31.9 against 17.2 ms for the three passes at 1280×720.)
vec3 footprint[6][6];

// The mean of the 2×2 footprint texels from (i, j): the box of a bilinear tap at their
// shared corner.
vec3 box(ivec2 at) {
    return 0.25 * (footprint[at.y][at.x] + footprint[at.y][at.x + 1]
        + footprint[at.y + 1][at.x] + footprint[at.y + 1][at.x + 1]);
}

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    bool inside = all(lessThan(texel, ivec2(push.target.zw)));
    ivec2 target = ivec2(push.target.xy) + texel;
    if (push.mode == 2u) {
        if (inside) {
            vec3 own = imageLoad(levels, target).rgb;
            imageStore(levels, target, vec4(own + bloom_tent(push.source, texel), 1.0));
        }
        return;
    }
    if (!inside) {
        return;
    }
    // The target texel covers source texels 2t, 2t + 1; the taps lie at the corners
    // 2t + 1 + o, o from −2 to 2, each the box of the texels 2t + o and 2t + o + 1:
    // the box from footprint texel o + 2.
    ivec2 first = 2 * texel - 2;
    for (int j = 0; j < 6; ++j) {
        for (int i = 0; i < 6; ++i) {
            footprint[j][i] = source_texel(first + ivec2(i, j));
        }
    }
    ivec2 c = ivec2(2);
    vec3 centre = box(c);
    vec3 inner = 0.25 * (box(c + ivec2(-1, -1)) + box(c + ivec2(1, -1)) + box(c + ivec2(-1, 1))
        + box(c + ivec2(1, 1)));
    vec3 corners[4];
    int k = 0;
    for (int sy = -1; sy <= 1; sy += 2) {
        for (int sx = -1; sx <= 1; sx += 2) {
            corners[k++] = 0.25 * (centre + box(c + ivec2(2 * sx, 0)) + box(c + ivec2(0, 2 * sy))
                + box(c + 2 * ivec2(sx, sy)));
        }
    }
    vec3 result;
    if (push.mode == 0u) {
        // Karis's average: each group by 1 / (1 + its luminance), normalised.
        float w = 0.5 / (1.0 + luminance(inner));
        vec3 sum = w * inner;
        float total = w;
        for (int g = 0; g < 4; ++g) {
            float wg = 0.125 / (1.0 + luminance(corners[g]));
            sum += wg * corners[g];
            total += wg;
        }
        result = sum / total;
    } else {
        result = 0.5 * inner + 0.125 * (corners[0] + corners[1] + corners[2] + corners[3]);
    }
    imageStore(levels, target, vec4(result, 1.0));
}
