#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Tiled light culling: one invocation per 16×16-pixel tile (no shared memory, atomics or
// barriers: on a CPU driver those cost more than the work). The tile's depth range (of
// the pixels where something was drawn) and its pixel rectangle bound every position the
// lighting pass reconstructs there; the 8 corners of that slab, unprojected, give a
// world-space box. A light is listed for the tile unless it has a range whose sphere
// misses the box (directional lights and lights without range are always listed). The
// list keeps the lights in index order, so the lighting pass sums the same terms in the
// same order as without culling: a light left out contributes exactly 0 there.
#include "gpu_types.glsl"
#include "bindings/light_cull.glsl"  // set 0: see combustion_renderer::bindings::LIGHT_CULL

#include "bindings/constants.glsl"  // TILE_SIZE: combustion_renderer::TILE_SIZE

layout(local_size_x = 64) in;

// push.inverse_view_projection; push.counts: x lights, y tiles across, z list stride
// (1 + lights), w tiles (combustion_renderer's CullPush, passes/light_cull.rs).
#include "push/light_cull.glsl"

void main() {
    uint tile = gl_GlobalInvocationID.x;
    if (tile >= push.counts.w) {
        return;
    }
    uint base = tile * push.counts.z;
    ivec2 size = textureSize(gbuffer_depth, 0);
    ivec2 first = ivec2(int(tile % push.counts.y), int(tile / push.counts.y)) * TILE_SIZE;
    ivec2 last = min(first + ivec2(TILE_SIZE), size);
    float z0 = 1.0;
    float z1 = 0.0;
    for (int y = first.y; y < last.y; ++y) {
        for (int x = first.x; x < last.x; ++x) {
            float depth = texelFetch(gbuffer_depth, ivec2(x, y), 0).r;
            if (depth < 1.0) {
                z0 = min(z0, depth);
                z1 = max(z1, depth);
            }
        }
    }
    if (z0 == 1.0) {
        // Nothing drawn in this tile: the lighting pass shades none of its pixels.
        tile_lights[base] = 0u;
        return;
    }
    // The tile's rectangle in the lighting pass's NDC (uv · 2 − 1, uv = pixel / size).
    vec2 ndc0 = vec2(first) / vec2(size) * 2.0 - 1.0;
    vec2 ndc1 = vec2(last) / vec2(size) * 2.0 - 1.0;
    mat4 m = push.inverse_view_projection;
    mat4 magnitude = mat4(abs(m[0]), abs(m[1]), abs(m[2]), abs(m[3]));
    vec3 lo = vec3(3.0e38);
    vec3 hi = vec3(-3.0e38);
    float error = 0.0;
    for (uint c = 0u; c < 8u; ++c) {
        vec4 corner = vec4((c & 1u) != 0u ? ndc1.x : ndc0.x,
                           (c & 2u) != 0u ? ndc1.y : ndc0.y,
                           (c & 4u) != 0u ? z1 : z0,
                           1.0);
        vec4 world = m * corner;
        vec3 p = world.xyz / world.w;
        lo = min(lo, p);
        hi = max(hi, p);
        // How far the lighting pass's f32 reconstruction (the same product, with its
        // own rounding of uv) can land from p: each component of m·c is off by at most
        // a few ulps of Σ|m_ij c_j| (its cancellation, e.g. in w near the far plane with
        // a small near plane, is what makes it large), and the division adds w's error.
        vec4 sums = magnitude * abs(corner);
        float w_relative = sums.w / abs(world.w);
        vec3 p_error = sums.xyz / abs(world.w) + abs(p) * w_relative;
        error = max(error, max(p_error.x, max(p_error.y, p_error.z)));
    }
    // 16 ulps of slack on that bound, and a floor for coordinates near 0.
    vec3 pad = vec3(16.0 * 1.1920929e-7 * error + 1e-6);
    lo -= pad;
    hi += pad;

    uint n = 0u;
    for (uint i = 0u; i < push.counts.x; ++i) {
        GpuLight light = lights[i];
        bool listed = true;
        float inverse_r2 = light.spot_cone.z;
        if (light.power_kind.a != LIGHT_KIND_DIRECTIONAL && inverse_r2 > 0.0) {
            vec3 centre = light.position_or_direction.xyz;
            vec3 gap = centre - clamp(centre, lo, hi);
            // Within the range (with 0.1 % to spare): the window may be above 0 here.
            listed = dot(gap, gap) * inverse_r2 <= 1.002;
        }
        if (listed) {
            tile_lights[base + 1u + n] = i;
            n += 1u;
        }
    }
    tile_lights[base] = n;
}
