// Bloom's levels (combustion_renderer's passes/bloom.rs): one image holds the chain as
// an atlas, level k at the rectangle (x, y, width, height) in texels; a reader defines
// BLOOM_TEXEL(p) (imageLoad in the chain, texelFetch after it) before including this.
#ifndef COMBUSTION_BLOOM_GLSL
#define COMBUSTION_BLOOM_GLSL

// Texel `p` of the level at `rect`, its coordinates clamped into it (the edge repeated).
vec3 bloom_texel(uvec4 rect, ivec2 p) {
    ivec2 clamped = clamp(p, ivec2(0), ivec2(rect.zw) - 1);
    return BLOOM_TEXEL(ivec2(rect.xy) + clamped).rgb;
}

// The weights of the four texels from floor(g) − 1 along one axis that a 3-tap tent
// (1/4, 1/2, 1/4), one texel apart, of bilinear samples centred at g (texel units, less
// a half) gives: each tap's two texels by (1 − f, f).
vec4 bloom_tent_weights(float f) {
    return vec4(0.25 * (1.0 - f), 0.25 * f + 0.5 * (1.0 - f), 0.5 * f + 0.25 * (1.0 - f),
        0.25 * f);
}

// The 3×3 tent (weights 1 2 1 by 1 2 1, over 16) of bilinear samples of the coarser
// level at `rect`, one of its texels apart, at the centre of pixel `pixel` of the level
// twice its size: 16 texels, each by its summed weight.
vec3 bloom_tent(uvec4 rect, ivec2 pixel) {
    vec2 g = (vec2(pixel) + 0.5) * 0.5 - 0.5;
    ivec2 base = ivec2(floor(g));
    vec2 f = g - vec2(base);
    vec4 wx = bloom_tent_weights(f.x);
    vec4 wy = bloom_tent_weights(f.y);
    vec3 sum = vec3(0.0);
    for (int j = 0; j < 4; ++j) {
        vec3 row = vec3(0.0);
        for (int i = 0; i < 4; ++i) {
            row += wx[i] * bloom_texel(rect, base + ivec2(i - 1, j - 1));
        }
        sum += wy[j] * row;
    }
    return sum;
}

// The level at `rect` sampled bilinearly (edge repeated) at the centre of pixel `pixel`
// of the image twice its size: the glow at a pixel of the frame from the largest level.
vec3 bloom_upsampled(uvec4 rect, ivec2 pixel) {
    vec2 g = (vec2(pixel) + 0.5) * 0.5 - 0.5;
    ivec2 base = ivec2(floor(g));
    vec2 f = g - vec2(base);
    vec3 a = bloom_texel(rect, base);
    vec3 b = bloom_texel(rect, base + ivec2(1, 0));
    vec3 c = bloom_texel(rect, base + ivec2(0, 1));
    vec3 d = bloom_texel(rect, base + ivec2(1, 1));
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

// What texel `t` of a level `count` texels long weighs, summed over every pixel of the
// image `fine` pixels long that bloom_upsampled draws from it: 2 (0.25 + 0.75 + 0.75 +
// 0.25, the edge's repeats included), but 1 for the last texel of an odd length (it
// covers one pixel and a half beyond the image).
float bloom_upsampled_weight(int t, int count, int fine) {
    return (t == count - 1 && (fine & 1) == 1) ? 1.0 : 2.0;
}

#endif
