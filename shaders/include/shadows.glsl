// Shadows of directional lights (SHADOWS variant; combustion_renderer::shadows and
// docs/shadows.md): each shadowed light has SHADOW_CASCADES layers in shadow_maps, placed
// by shadow_cascades; a lookup takes the first cascade whose map holds the point, fading
// into the next one over the outer CASCADE_BLEND_BAND of the map.
#ifndef COMBUSTION_SHADOWS_GLSL
#define COMBUSTION_SHADOWS_GLSL

// Interleaved gradient noise (Jimenez 2014): a per-pixel rotation of the PCF disk.
float interleaved_gradient_noise(vec2 pixel) {
    return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}

// The lit fraction of layer `layer` at map coordinates uv for a receiver at map depth z.
float shadow_filter(uint layer, vec2 uv, float z, vec2 pixel) {
#if SHADOW_TAPS == 1
    return texture(shadow_maps, vec4(uv, float(layer), z));
#else
    vec2 texel = 1.0 / vec2(textureSize(shadow_maps, 0).xy);
    float rotation = 6.28318531 * interleaved_gradient_noise(pixel);
    float lit = 0.0;
    for (int i = 0; i < SHADOW_TAPS; ++i) {
        // A Vogel disk: radii √((i + ½)/N), angles i times the golden angle.
        float r = sqrt((float(i) + 0.5) / float(SHADOW_TAPS)) * SHADOW_PCF_RADIUS_TEXELS;
        float a = float(i) * 2.39996323 + rotation;
        vec2 offset = r * vec2(cos(a), sin(a)) * texel;
        lit += texture(shadow_maps, vec4(uv + offset, float(layer), z));
    }
    return lit / float(SHADOW_TAPS);
#endif
}

// Where a receiver at `position` (unit shading normal n, unit direction l to the light)
// falls in cascade `layer`: map uv, and the reference depth. The receiver is offset
// along n by (kernel radius + 1.5) texels × sin θ (θ: n's angle to l), which keeps every
// tap of a flat receiver in front of its own surface up to grazing light
// (docs/shadows.md), plus half a texel of depth.
vec3 shadow_lookup(uint layer, vec3 position, vec3 n, float sin_theta) {
    GpuShadowCascade cascade = shadow_cascades[layer];
    float texel = cascade.texel_world_depth_range.x;
    vec3 p = position + n * (texel * (SHADOW_PCF_RADIUS_TEXELS + 1.5) * sin_theta);
    vec4 clip = cascade.world_to_clip * vec4(p, 1.0);
    float bias = 0.5 * texel / cascade.texel_world_depth_range.y;
    return vec3(clip.xy * 0.5 + 0.5, clip.z - bias);
}

// How far inside its map a lookup is, as a share of the map (negative: outside).
float shadow_inside(vec3 lookup) {
    vec2 edge = min(lookup.xy, 1.0 - lookup.xy);
    return min(edge.x, edge.y);
}

// The lit fraction of the light whose cascades start at layer `first`, at `position`.
// Points beyond every cascade (past the shadow distance) are lit.
float shadow_visibility(uint first, vec3 position, vec3 n, vec3 l, vec2 pixel) {
    float cos_theta = clamp(dot(n, l), 0.0, 1.0);
    float sin_theta = sqrt(1.0 - cos_theta * cos_theta);
    float margin = (SHADOW_PCF_RADIUS_TEXELS + 1.0) / float(textureSize(shadow_maps, 0).x);
    for (uint c = 0u; c < uint(SHADOW_CASCADES); ++c) {
        vec3 lookup = shadow_lookup(first + c, position, n, sin_theta);
        float inside = shadow_inside(lookup) - margin;
        if (inside < 0.0 || lookup.z > 1.0) {
            continue;
        }
        float lit = shadow_filter(first + c, lookup.xy, lookup.z, pixel);
        if (inside < SHADOW_CASCADE_BLEND_BAND && c + 1u < uint(SHADOW_CASCADES)) {
            vec3 next = shadow_lookup(first + c + 1u, position, n, sin_theta);
            if (shadow_inside(next) - margin >= 0.0 && next.z <= 1.0) {
                float next_lit = shadow_filter(first + c + 1u, next.xy, next.z, pixel);
                lit = mix(next_lit, lit, inside / SHADOW_CASCADE_BLEND_BAND);
            }
        }
        return lit;
    }
    return 1.0;
}

// The cascade a lookup of the light starting at `first` uses (SHADOW_CASCADES: none),
// for the cascade debug view.
uint shadow_cascade_of(uint first, vec3 position, vec3 n, vec3 l) {
    float cos_theta = clamp(dot(n, l), 0.0, 1.0);
    float sin_theta = sqrt(1.0 - cos_theta * cos_theta);
    float margin = (SHADOW_PCF_RADIUS_TEXELS + 1.0) / float(textureSize(shadow_maps, 0).x);
    for (uint c = 0u; c < uint(SHADOW_CASCADES); ++c) {
        vec3 lookup = shadow_lookup(first + c, position, n, sin_theta);
        if (shadow_inside(lookup) - margin >= 0.0 && lookup.z <= 1.0) {
            return c;
        }
    }
    return uint(SHADOW_CASCADES);
}

#endif
