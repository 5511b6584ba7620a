// Rays against the scene's acceleration structure with its cut-outs tested where a ray
// meets them (crates/renderer/src/accel.rs, TracedCutouts; passes/traced.rs binds them):
// the bindings `scene`, `cutouts`, `cutout_corners` and `cutout_alphas` are declared first
// (a set with passes/traced.rs's bindings), and GL_EXT_ray_query is enabled.
//
// A cut-out's instance is not opaque: its candidate hits come back to the loop in
// scene_blocks, which confirms one only where the material's alpha — its factor × the
// base colour texture's alpha at level 0, filtered by the sampler's magnification filter
// × the vertex colour's alpha — reaches the cutoff, as the f64 reference's ray casts
// (combustion_reference, cutout.rs). Every other instance is opaque: no test, no cost.
#ifndef COMBUSTION_TRACED_SCENE_GLSL
#define COMBUSTION_TRACED_SCENE_GLSL

// TRACE_MASK_OCCLUDES: generated from crate::accel's instance masks.
#include "bindings/constants.glsl"

// The f64 reference's step off a surface at `p` (combustion_reference::visibility::
// surface_offset): 1e-4 · max(1, |p|∞).
float surface_offset(vec3 p) {
    vec3 a = abs(p);
    return 1e-4 * max(1.0, max(a.x, max(a.y, a.z)));
}

// Alpha byte `i` of the cut-outs' textures, in [0, 1].
float cutout_alpha_byte(uint i) {
    return float((cutout_alphas[i >> 2] >> ((i & 3u) * 8u)) & 0xffu) / 255.0;
}

// Texel index `i` wrapped into [0, n) by `mode` (0 repeat, 1 mirrored repeat, 2 clamp).
int texel_wrap(int i, int n, uint mode) {
    if (mode == 2u) {
        return clamp(i, 0, n - 1);
    }
    if (mode == 1u) {
        int m = ((i % (2 * n)) + 2 * n) % (2 * n);
        return m < n ? m : 2 * n - 1 - m;
    }
    return ((i % n) + n) % n;
}

// The texture's alpha at `uv` (entry halves `size`: first texel, width, height; `flags`).
float cutout_texture_alpha(uvec4 size, uint flags, vec2 uv) {
    int w = int(size.z);
    int h = int(size.w);
    uint wrap_u = flags & 3u;
    uint wrap_v = (flags >> 2) & 3u;
    vec2 texel = uv * vec2(w, h);
    if ((flags & 16u) == 0u) {
        int x = texel_wrap(int(floor(texel.x)), w, wrap_u);
        int y = texel_wrap(int(floor(texel.y)), h, wrap_v);
        return cutout_alpha_byte(size.y + uint(y * w + x));
    }
    vec2 p = texel - 0.5;
    vec2 p0 = floor(p);
    vec2 f = p - p0;
    int x0 = texel_wrap(int(p0.x), w, wrap_u);
    int x1 = texel_wrap(int(p0.x) + 1, w, wrap_u);
    int y0 = texel_wrap(int(p0.y), h, wrap_v);
    int y1 = texel_wrap(int(p0.y) + 1, h, wrap_v);
    float a00 = cutout_alpha_byte(size.y + uint(y0 * w + x0));
    float a10 = cutout_alpha_byte(size.y + uint(y0 * w + x1));
    float a01 = cutout_alpha_byte(size.y + uint(y1 * w + x0));
    float a11 = cutout_alpha_byte(size.y + uint(y1 * w + x1));
    return mix(mix(a00, a10, f.x), mix(a01, a11, f.x), f.y);
}

// Whether cut-out `entry`'s triangle `primitive` is present at barycentrics `b`.
bool cutout_present(uint entry, uint primitive, vec2 b) {
    uvec4 size = cutouts[2u * entry];
    uvec4 rule = cutouts[2u * entry + 1u];
    uint corner = size.x + 3u * primitive;
    vec3 weights = vec3(1.0 - b.x - b.y, b.x, b.y);
    vec4 c = cutout_corners[corner] * weights.x + cutout_corners[corner + 1u] * weights.y
             + cutout_corners[corner + 2u] * weights.z;
    float alpha = uintBitsToFloat(rule.y) * c.z;
    if ((rule.x & 32u) != 0u) {
        alpha *= cutout_texture_alpha(size, rule.x, c.xy);
    }
    return alpha >= uintBitsToFloat(rule.z);
}

// Runs `query` to its end, a candidate hit on a cut-out confirmed only where its alpha
// reaches the cutoff (the other instances are opaque: their hits need no test).
void proceed_past_cutout_holes(rayQueryEXT query) {
    while (rayQueryProceedEXT(query)) {
        if (rayQueryGetIntersectionTypeEXT(query, false) == gl_RayQueryCandidateIntersectionTriangleEXT
            && cutout_present(uint(rayQueryGetIntersectionInstanceCustomIndexEXT(query, false)),
                              uint(rayQueryGetIntersectionPrimitiveIndexEXT(query, false)),
                              rayQueryGetIntersectionBarycentricsEXT(query, false))) {
            rayQueryConfirmIntersectionEXT(query);
        }
    }
}

// Whether anything of the scene that blocks light (instance mask TRACE_MASK_OCCLUDES:
// not what only paths see) lies on the segment from `origin` along the unit `direction`
// up to `reach`.
bool scene_blocks(vec3 origin, vec3 direction, float reach) {
    rayQueryEXT query;
    rayQueryInitializeEXT(query, scene, gl_RayFlagsTerminateOnFirstHitEXT, TRACE_MASK_OCCLUDES,
                          origin, 0.0, direction, reach);
    proceed_past_cutout_holes(query);
    return rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionNoneEXT;
}

#endif
