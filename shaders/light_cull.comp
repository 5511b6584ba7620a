#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Tiled light culling: one workgroup per 16×16-pixel tile. The tile's depth range (of
// the pixels where something was drawn) and its pixel rectangle bound every position the
// lighting pass reconstructs there; the 8 corners of that slab, unprojected, give a
// world-space box. A light is listed for the tile unless it has a range whose sphere
// misses the box (directional lights and lights without range are always listed). The
// list keeps the lights in index order, so the lighting pass sums the same terms in the
// same order as without culling: a light left out contributes exactly 0 there.
#include "gpu_types.glsl"
#include "bindings/light_cull.glsl"  // set 0: see combustion_renderer::bindings::LIGHT_CULL

#define TILE_SIZE 16u
#define MAX_CULLED_LIGHTS 1024u  // combustion_renderer: MAX_CULLED_LIGHTS

layout(local_size_x = 16, local_size_y = 16) in;

layout(push_constant) uniform CullPush {
    mat4 inverse_view_projection;
    uvec4 counts;  // x: lights; y: tiles across; z: list stride (1 + lights)
} push;

shared uint depth_min_bits;
shared uint depth_max_bits;
shared uint light_mask[MAX_CULLED_LIGHTS / 32u];

void main() {
    uint local = gl_LocalInvocationIndex;
    if (local == 0u) {
        depth_min_bits = floatBitsToUint(1.0);
        depth_max_bits = 0u;
    }
    for (uint i = local; i < MAX_CULLED_LIGHTS / 32u; i += TILE_SIZE * TILE_SIZE) {
        light_mask[i] = 0u;
    }
    barrier();

    ivec2 size = textureSize(gbuffer_depth, 0);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x < size.x && pixel.y < size.y) {
        float depth = texelFetch(gbuffer_depth, pixel, 0).r;
        if (depth < 1.0) {
            // Depths in [0, 1): their bit patterns order as the values do.
            atomicMin(depth_min_bits, floatBitsToUint(depth));
            atomicMax(depth_max_bits, floatBitsToUint(depth));
        }
    }
    barrier();

    uint tile = gl_WorkGroupID.y * push.counts.y + gl_WorkGroupID.x;
    uint base = tile * push.counts.z;
    if (depth_min_bits == floatBitsToUint(1.0)) {
        // Nothing drawn in this tile: the lighting pass shades none of its pixels.
        if (local == 0u) {
            tile_lights[base] = 0u;
        }
        return;
    }
    float z0 = uintBitsToFloat(depth_min_bits);
    float z1 = uintBitsToFloat(depth_max_bits);
    // The tile's rectangle in the lighting pass's NDC (uv · 2 − 1, uv = pixel / size).
    vec2 first = vec2(gl_WorkGroupID.xy * TILE_SIZE);
    vec2 last = min(first + vec2(TILE_SIZE), vec2(size));
    vec2 ndc0 = first / vec2(size) * 2.0 - 1.0;
    vec2 ndc1 = last / vec2(size) * 2.0 - 1.0;
    vec3 lo = vec3(3.0e38);
    vec3 hi = vec3(-3.0e38);
    for (uint c = 0u; c < 8u; ++c) {
        vec4 corner = vec4((c & 1u) != 0u ? ndc1.x : ndc0.x,
                           (c & 2u) != 0u ? ndc1.y : ndc0.y,
                           (c & 4u) != 0u ? z1 : z0,
                           1.0);
        vec4 world = push.inverse_view_projection * corner;
        vec3 p = world.xyz / world.w;
        lo = min(lo, p);
        hi = max(hi, p);
    }
    // Room for the f32 rounding of the lighting pass's own reconstruction.
    vec3 pad = vec3(1e-4 * max(max(abs(lo.x), abs(hi.x)), max(max(abs(lo.y), abs(hi.y)), max(abs(lo.z), abs(hi.z)))) + 1e-6);
    lo -= pad;
    hi += pad;

    for (uint i = local; i < push.counts.x; i += TILE_SIZE * TILE_SIZE) {
        GpuLight light = lights[i];
        bool listed = true;
        float inverse_r2 = light.spot_cone.z;
        if (light.power_kind.a != LIGHT_KIND_DIRECTIONAL && inverse_r2 > 0.0) {
            vec3 centre = light.position_or_direction.xyz;
            vec3 nearest = clamp(centre, lo, hi);
            vec3 gap = centre - nearest;
            // Within the range (with 0.1 % to spare): the window may be above 0 here.
            listed = dot(gap, gap) * inverse_r2 <= 1.002;
        }
        if (listed) {
            atomicOr(light_mask[i >> 5u], 1u << (i & 31u));
        }
    }
    barrier();
    if (local == 0u) {
        uint n = 0u;
        uint words = (push.counts.x + 31u) / 32u;
        for (uint w = 0u; w < words; ++w) {
            uint bits = light_mask[w];
            while (bits != 0u) {
                uint b = uint(findLSB(bits));
                tile_lights[base + 1u + n] = w * 32u + b;
                n += 1u;
                bits &= bits - 1u;
            }
        }
        tile_lights[base] = n;
    }
}
