// Shadows (SHADOWS variant; combustion_renderer::shadows and docs/shadows.md): each
// shadowed directional light has SHADOW_CASCADES entries in shadow_cascades, whose maps
// are layers of shadow_maps; a lookup takes the cascade whose slice of the view holds
// the point, fading into the next one over the last CASCADE_BLEND_BAND of the slice. A
// spot light has one entry, a point light six (a cube), their maps in local_shadow_maps.
// Each entry names its layer in its array (view_forward.w).
#ifndef COMBUSTION_SHADOWS_GLSL
#define COMBUSTION_SHADOWS_GLSL

// Interleaved gradient noise (Jimenez 2014): a per-pixel rotation of the PCF disk.
float interleaved_gradient_noise(vec2 pixel) {
    return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}

// One depth comparison in layer `layer` of the cascades' maps, or of the local lights'
// (`local`), at coord.xy with reference depth coord.z (bilinearly weighted over 2×2).
float shadow_compare(bool local, float layer, vec3 coord) {
    vec4 c = vec4(coord.xy, layer, coord.z);
    return local ? texture(local_shadow_maps, c) : texture(shadow_maps, c);
}

// The lit fraction of the map of table entry `entry` at uv for a receiver at map depth
// z: one bilinear comparison, or the average of SHADOW_TAPS on a Vogel disk (radii
// √((i + ½)/N)·SHADOW_PCF_RADIUS_TEXELS, angles i times the golden angle) turned per
// pixel.
float shadow_filter(uint entry, vec2 uv, float z, vec2 pixel) {
    GpuShadowCascade map = shadow_cascades[entry];
    bool local = map.texel_depth_slice.w != 0.0;
    float layer = map.view_forward.w;
#if SHADOW_TAPS == 1
    return shadow_compare(local, layer, vec3(uv, z));
#else
    vec2 texel = 1.0 / vec2(local ? textureSize(local_shadow_maps, 0).xy
                                  : textureSize(shadow_maps, 0).xy);
    float rotation = 6.28318531 * interleaved_gradient_noise(pixel);
    float lit = 0.0;
    for (int i = 0; i < SHADOW_TAPS; ++i) {
        float r = sqrt((float(i) + 0.5) / float(SHADOW_TAPS)) * SHADOW_PCF_RADIUS_TEXELS;
        float a = float(i) * 2.39996323 + rotation;
        lit += shadow_compare(local, layer, vec3(uv + r * vec2(cos(a), sin(a)) * texel, z));
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
    float texel = cascade.texel_depth_slice.x;
    vec3 p = position + n * (texel * (SHADOW_PCF_RADIUS_TEXELS + 1.5) * sin_theta);
    vec4 clip = cascade.world_to_clip * vec4(p, 1.0);
    float bias = 0.5 * texel / cascade.texel_depth_slice.y;
    return vec3(clip.xy * 0.5 + 0.5, clip.z - bias);
}

// The cascade of the light whose cascades start at layer `first` that covers a point
// `distance` metres in front of the eye (SHADOW_CASCADES beyond the shadow distance),
// and how far into its slice's last CASCADE_BLEND_BAND the point is (0 before it, 1 at
// the slice's end).
uint shadow_cascade(uint first, float distance, out float blend) {
    float slice_start = 0.0;
    for (uint c = 0u; c < uint(SHADOW_CASCADES); ++c) {
        float slice_end = shadow_cascades[first + c].texel_depth_slice.z;
        if (distance <= slice_end) {
            float band = SHADOW_CASCADE_BLEND_BAND * (slice_end - slice_start);
            blend = clamp((distance - (slice_end - band)) / band, 0.0, 1.0);
            return c;
        }
        slice_start = slice_end;
    }
    blend = 0.0;
    return uint(SHADOW_CASCADES);
}

// The distance of `position` in front of the eye at `eye`, along the view direction.
float shadow_view_distance(uint first, vec3 position, vec3 eye) {
    return dot(position - eye, shadow_cascades[first].view_forward.xyz);
}

// The lit fraction of the light whose cascades start at layer `first`, at `position`
// seen from `eye`: the cascade is chosen by the point's view distance (the cascades'
// maps hold their slices of the view frustum whole), and the last part of each slice
// fades into the next cascade. Points beyond the shadow distance are lit.
float shadow_visibility(uint first, vec3 position, vec3 eye, vec3 n, vec3 l, vec2 pixel) {
    float blend;
    uint c = shadow_cascade(first, shadow_view_distance(first, position, eye), blend);
    if (c >= uint(SHADOW_CASCADES)) {
        return 1.0;
    }
    float cos_theta = clamp(dot(n, l), 0.0, 1.0);
    float sin_theta = sqrt(1.0 - cos_theta * cos_theta);
    vec3 lookup = shadow_lookup(first + c, position, n, sin_theta);
    float lit = shadow_filter(first + c, lookup.xy, lookup.z, pixel);
    if (blend > 0.0 && c + 1u < uint(SHADOW_CASCADES)) {
        vec3 next = shadow_lookup(first + c + 1u, position, n, sin_theta);
        lit = mix(lit, shadow_filter(first + c + 1u, next.xy, next.z, pixel), blend);
    }
    return lit;
}

// The lit fraction of a spot or point light at `light_position` whose layers start at
// `first` (`cube`: six faces +X, −X, +Y, −Y, +Z, −Z, chosen by the major axis of the
// direction from the light; else one layer), at `position`. The normal offset and the
// half-texel depth bias are those of a cascade, with the texel's side at the point's
// distance (a perspective layer's texel grows with depth). Points outside the layer
// are lit.
float shadow_visibility_local(uint first, bool cube, vec3 light_position, vec3 position,
                              vec3 n, vec3 l, vec2 pixel) {
    vec3 from_light = position - light_position;
    uint layer = first;
    if (cube) {
        vec3 a = abs(from_light);
        if (a.x >= a.y && a.x >= a.z) {
            layer += from_light.x > 0.0 ? 0u : 1u;
        } else if (a.y >= a.z) {
            layer += from_light.y > 0.0 ? 2u : 3u;
        } else {
            layer += from_light.z > 0.0 ? 4u : 5u;
        }
    }
    GpuShadowCascade map = shadow_cascades[layer];
    float texel = map.texel_depth_slice.x * length(from_light);
    float cos_theta = clamp(dot(n, l), 0.0, 1.0);
    float sin_theta = sqrt(1.0 - cos_theta * cos_theta);
    vec3 p = position + n * (texel * (SHADOW_PCF_RADIUS_TEXELS + 1.5) * sin_theta);
    vec4 clip = map.world_to_clip * vec4(p, 1.0);
    if (clip.w <= 0.0) {
        return 1.0;
    }
    vec3 ndc = clip.xyz / clip.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
        return 1.0;
    }
    // Map depth is near·far/(far − near)·(1/near − 1/w) at depth w along the layer's
    // axis: half a texel of world distance there is this much of it.
    float near_plane = map.texel_depth_slice.y;
    float far_plane = map.texel_depth_slice.z;
    float bias = 0.5 * texel * near_plane * far_plane
               / ((far_plane - near_plane) * clip.w * clip.w);
    return shadow_filter(layer, uv, ndc.z - bias, pixel);
}

// The lit fraction of `light` (its layers starting at `first`) at `position` seen from
// `eye`, whatever its kind.
float shadow_visibility_of(GpuLight light, uint first, vec3 position, vec3 eye, vec3 n, vec3 l,
                           vec2 pixel) {
    if (light.power_kind.a == LIGHT_KIND_DIRECTIONAL) {
        return shadow_visibility(first, position, eye, n, l, pixel);
    }
    bool cube = shadow_cascades[first].texel_depth_slice.w == SHADOW_LAYER_CUBE_FACE;
    return shadow_visibility_local(first, cube, light.position_or_direction.xyz, position, n, l,
                                   pixel);
}

#endif
