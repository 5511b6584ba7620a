// Shadows (SHADOWS variant; combustion_renderer::shadows and docs/shadows.md): each
// shadowed directional light has SHADOW_CASCADES entries in shadow_cascades, whose maps
// are layers of shadow_maps; a lookup takes the cascade whose slice of the view holds
// the point, fading into the next one over the last CASCADE_BLEND_BAND of the slice. A
// spot light has one entry, a point light six (a cube), their maps in local_shadow_maps.
// Each entry names its layer in its array (view_forward.w). The variant compiles only
// the kinds of shadow the scene's lights cast (ShadowShader): SHADOW_CASCADED
// (directional lights), SHADOW_LOCAL (spot and point lights), SHADOW_SOFT (lights with
// a size) — a GPU that runs both sides of a branch pays for none it cannot take.
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
#if defined(SHADOW_CASCADED) && defined(SHADOW_LOCAL)
    return local ? texture(local_shadow_maps, c) : texture(shadow_maps, c);
#elif defined(SHADOW_LOCAL)
    return texture(local_shadow_maps, c);
#else
    return texture(shadow_maps, c);
#endif
}

// A texel's side in map coordinates, in the cascades' maps or the local lights'.
vec2 shadow_texel_uv(bool local) {
#if defined(SHADOW_CASCADED) && defined(SHADOW_LOCAL)
    return 1.0 / vec2(local ? textureSize(local_shadow_maps, 0).xy
                            : textureSize(shadow_maps, 0).xy);
#elif defined(SHADOW_LOCAL)
    return 1.0 / vec2(textureSize(local_shadow_maps, 0).xy);
#else
    return 1.0 / vec2(textureSize(shadow_maps, 0).xy);
#endif
}

// The lit fraction of the map of table entry `entry` at uv for a receiver at map depth
// z over `taps` bilinear comparisons on a Vogel disk of `radius` texels (radii
// √((i + ½)/N)·radius, angles i times the golden angle) turned per pixel; one
// comparison when taps is 1.
float shadow_pcf(uint entry, vec2 uv, float z, float radius, int taps, vec2 pixel) {
    GpuShadowCascade map = shadow_cascades[entry];
    bool local = map.texel_depth_slice.w != 0.0;
    float layer = map.view_forward.w;
    if (taps == 1) {
        return shadow_compare(local, layer, vec3(uv, z));
    }
    vec2 texel = shadow_texel_uv(local);
    float rotation = 6.28318531 * interleaved_gradient_noise(pixel);
    float lit = 0.0;
    for (int i = 0; i < taps; ++i) {
        float r = sqrt((float(i) + 0.5) / float(taps)) * radius;
        float a = float(i) * 2.39996323 + rotation;
        lit += shadow_compare(local, layer, vec3(uv + r * vec2(cos(a), sin(a)) * texel, z));
    }
    return lit / float(taps);
}

// Where a receiver falls in the map of entry `entry`.
struct ShadowLookup {
    vec2 uv;         // map coordinates
    float z;         // reference depth (biased)
    float texel;     // a texel's side at the receiver, metres
    float receiver;  // the receiver's distance: from the map's near plane along the light
                     // (cascade), or its depth along the layer's axis (local light)
    bool inside;     // the receiver is on the map
};

// The receiver at `position` (unit shading normal n, sin θ of its angle to the light),
// offset along n by (SHADOW_PCF_RADIUS_TEXELS + 1.5) texels × sin θ, which keeps every
// tap of the filter on a flat receiver in front of its own surface up to grazing light
// (docs/shadows.md), and biased by half a texel of depth; a wider kernel of `radius`
// texels (a light with a size) adds the depth its extra reach can span on a plane tilted
// by θ, (radius − SHADOW_PCF_RADIUS_TEXELS) texels × tan θ (θ at most 85°), as depth
// bias rather than a longer offset, which would shift the shadow sideways. A local
// light's texel is taken at the point's distance from `light_position`.
ShadowLookup shadow_locate(uint entry, vec3 position, vec3 n, float sin_theta, float radius,
                           vec3 light_position) {
    GpuShadowCascade map = shadow_cascades[entry];
    ShadowLookup at;
    at.inside = true;
    bool local = map.texel_depth_slice.w != 0.0;
    float texel = local ? map.texel_depth_slice.x * length(position - light_position)
                        : map.texel_depth_slice.x;
    vec3 p = position + n * (texel * (SHADOW_PCF_RADIUS_TEXELS + 1.5) * sin_theta);
    float cos_theta = sqrt(max(1.0 - sin_theta * sin_theta, 0.0));
    float tan_theta = min(sin_theta / max(cos_theta, 1e-6), 11.43);
    // World distance along the light the comparison is biased by.
    float bias = texel * (0.5 + max(radius - SHADOW_PCF_RADIUS_TEXELS, 0.0) * tan_theta);
    vec4 clip = map.world_to_clip * vec4(p, 1.0);
    at.texel = texel;
#ifdef SHADOW_CASCADED
    if (!local) {
        at.uv = clip.xy * 0.5 + 0.5;
        at.z = clip.z - bias / map.texel_depth_slice.y;
        at.receiver = clip.z * map.texel_depth_slice.y;
        return at;
    }
#endif
#ifdef SHADOW_LOCAL
    if (clip.w <= 0.0) {
        at.inside = false;
        return at;
    }
    vec3 ndc = clip.xyz / clip.w;
    at.uv = ndc.xy * 0.5 + 0.5;
    at.inside = all(greaterThanEqual(at.uv, vec2(0.0))) && all(lessThanEqual(at.uv, vec2(1.0)));
    // Map depth is near·far/(far − near)·(1/near − 1/w) at depth w along the layer's
    // axis: a world distance b there is b·near·far/((far − near)·w²) of it.
    float near_plane = map.texel_depth_slice.y;
    float far_plane = map.texel_depth_slice.z;
    at.z = ndc.z - bias * near_plane * far_plane / ((far_plane - near_plane) * clip.w * clip.w);
    at.receiver = clip.w;
#endif
    return at;
}

#ifdef SHADOW_SOFT
// The raw depth of the map of entry `entry` at the texel holding uv.
float shadow_depth(uint entry, vec2 uv) {
    GpuShadowCascade map = shadow_cascades[entry];
    int layer = int(map.view_forward.w);
#ifdef SHADOW_LOCAL
    if (map.texel_depth_slice.w != 0.0) {
        ivec2 size = textureSize(local_shadow_depths, 0).xy;
        ivec2 t = clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1);
        return texelFetch(local_shadow_depths, ivec3(t, layer), 0).r;
    }
#endif
#ifdef SHADOW_CASCADED
    ivec2 size = textureSize(shadow_depths, 0).xy;
    ivec2 t = clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1);
    return texelFetch(shadow_depths, ivec3(t, layer), 0).r;
#else
    return 1.0;
#endif
}

// Contact-hardening softness (PCSS, Fernando 2005) for a light of size `size` (the
// radius of a local light, tan of half a sun's angular diameter): the average depth of
// the blockers SHADOW_SOFT_TAPS depth reads find around the receiver, within the
// region the light's size can shadow it from (capped at SHADOW_SOFT_MAX_RADIUS_TEXELS),
// gives the penumbra's width at the receiver; its half, in texels, is the PCF radius
// (at least SHADOW_PCF_RADIUS_TEXELS, at most the cap). Negative: no blocker, lit.
float shadow_soft_radius(uint entry, ShadowLookup at, float size, vec2 pixel) {
    GpuShadowCascade map = shadow_cascades[entry];
    bool local = map.texel_depth_slice.w != 0.0;
    float near_plane = map.texel_depth_slice.y;
    float far_plane = map.texel_depth_slice.z;
    // How far from the receiver, in texels, a blocker can shadow it (one on the map's
    // near plane): a sun's cone over the receiver's distance from the near plane; a local
    // light's disc seen from the receiver, projected onto the near plane (the usual
    // PCSS search width).
    float search = local
        ? size * (at.receiver - near_plane) / (at.receiver * near_plane * map.texel_depth_slice.x)
        : size * at.receiver / at.texel;
    search = clamp(search, SHADOW_PCF_RADIUS_TEXELS, SHADOW_SOFT_MAX_RADIUS_TEXELS);
    vec2 texel = shadow_texel_uv(local);
    float rotation = 6.28318531 * interleaved_gradient_noise(pixel.yx);
    float sum = 0.0;
    float blockers = 0.0;
    for (int i = 0; i < SHADOW_SOFT_TAPS; ++i) {
        float r = sqrt((float(i) + 0.5) / float(SHADOW_SOFT_TAPS)) * search;
        float a = float(i) * 2.39996323 + rotation;
        float d = shadow_depth(entry, at.uv + r * vec2(cos(a), sin(a)) * texel);
        if (d < at.z) {
            sum += d;
            blockers += 1.0;
        }
    }
    if (blockers == 0.0) {
        return -1.0;
    }
    float blocker = sum / blockers;
    float penumbra;
    if (local) {
        // Similar triangles from the light's disc: w = 2 r (d_receiver − d_blocker) / d_blocker.
        float distance = near_plane * far_plane / (far_plane - blocker * (far_plane - near_plane));
        penumbra = 2.0 * size * max(at.receiver - distance, 0.0) / distance;
    } else {
        penumbra = 2.0 * size * max(at.z - blocker, 0.0) * map.texel_depth_slice.y;
    }
    return clamp(0.5 * penumbra / at.texel, SHADOW_PCF_RADIUS_TEXELS, SHADOW_SOFT_MAX_RADIUS_TEXELS);
}

#endif

// The lit fraction of the map of entry `entry` at `position`: the frame's filter, or for
// a light with a size (`size` > 0) contact-hardening PCF over the penumbra it casts.
// Points off the map are lit.
float shadow_filtered(uint entry, vec3 position, vec3 n, float sin_theta, vec3 light_position,
                      float size, vec2 pixel) {
    ShadowLookup at = shadow_locate(entry, position, n, sin_theta, SHADOW_PCF_RADIUS_TEXELS,
                                    light_position);
    if (!at.inside) {
        return 1.0;
    }
#ifdef SHADOW_SOFT
    if (size <= 0.0) {
        return shadow_pcf(entry, at.uv, at.z, SHADOW_PCF_RADIUS_TEXELS, SHADOW_TAPS, pixel);
    }
    float radius = shadow_soft_radius(entry, at, size, pixel);
    if (radius < 0.0) {
        return 1.0;
    }
    // Offset again for the wider kernel.
    at = shadow_locate(entry, position, n, sin_theta, radius, light_position);
    if (!at.inside) {
        return 1.0;
    }
    return shadow_pcf(entry, at.uv, at.z, radius, SHADOW_SOFT_TAPS, pixel);
#else
    return shadow_pcf(entry, at.uv, at.z, SHADOW_PCF_RADIUS_TEXELS, SHADOW_TAPS, pixel);
#endif
}

// The cascade of the light whose cascades start at entry `first` that covers a point
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

// The lit fraction of `light` (its entries starting at `first`) at `position` seen from
// `eye`, whatever its kind. A directional light's cascade is chosen by the point's view
// distance (the cascades' maps hold their slices of the view frustum whole), and the
// last part of each slice fades into the next cascade; points beyond the shadow
// distance are lit. A spot light has one entry; a point light (or a wide spot) six, the
// cube's faces +X, −X, +Y, −Y, +Z, −Z, the one of the major axis of the direction from
// the light taken.
float shadow_visibility_of(GpuLight light, uint first, vec3 position, vec3 eye, vec3 n, vec3 l,
                           vec2 pixel) {
    float cos_theta = clamp(dot(n, l), 0.0, 1.0);
    float sin_theta = sqrt(1.0 - cos_theta * cos_theta);
    float size = light.spot_axis.w;
    vec3 light_position = light.position_or_direction.xyz;
#ifdef SHADOW_CASCADED
    if (light.power_kind.a == LIGHT_KIND_DIRECTIONAL) {
        float blend;
        uint c = shadow_cascade(first, shadow_view_distance(first, position, eye), blend);
        if (c >= uint(SHADOW_CASCADES)) {
            return 1.0;
        }
        float lit = shadow_filtered(first + c, position, n, sin_theta, light_position, size,
                                    pixel);
        if (blend > 0.0 && c + 1u < uint(SHADOW_CASCADES)) {
            lit = mix(lit, shadow_filtered(first + c + 1u, position, n, sin_theta,
                                           light_position, size, pixel), blend);
        }
        return lit;
    }
#endif
#ifdef SHADOW_LOCAL
    uint entry = first;
    if (shadow_cascades[first].texel_depth_slice.w == SHADOW_LAYER_CUBE_FACE) {
        vec3 from_light = position - light_position;
        vec3 a = abs(from_light);
        if (a.x >= a.y && a.x >= a.z) {
            entry += from_light.x > 0.0 ? 0u : 1u;
        } else if (a.y >= a.z) {
            entry += from_light.y > 0.0 ? 2u : 3u;
        } else {
            entry += from_light.z > 0.0 ? 4u : 5u;
        }
    }
    return shadow_filtered(entry, position, n, sin_theta, light_position, size, pixel);
#else
    return 1.0;
#endif
}

#endif
