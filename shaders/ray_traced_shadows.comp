#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_ray_query : require
// Ray-traced shadows (the optional pass `ray-traced-shadows`, passes/ray_traced_shadows.rs):
// per pixel, for each of the first push.lights lights whose bit is set in push.casting,
// rays from the surface towards the light against the scene's acceleration structure —
// one for a light without a size, 15 towards stratified points of the disc it is seen
// as for a light with one (SIZED_RAYS) — and nibble i of the pixel's 128 bits set to how
// many of light i's reach it, of 15 (15 for lights that cast no shadow). The offset rule
// is the f64 reference's (combustion_reference::shadow_ray_origin): the ray starts
// 1e-4 · max(1, |p|∞) along the normal the lighting pass shades with, and a segment to a
// point of a point or spot light ends 1e-4 · max(1, |point|∞) short of it. The discs are
// the reference's (SceneBvh::disc_visibility, sun_visibility): a point or spot light's
// of its radius facing the surface point; a directional light's the directions
// axis + tan(θ/2)·d, d on the unit disc.
#include "gbuffer_encoding.glsl"
#include "gpu_types.glsl"
#include "brdf.glsl"
#include "bindings/ray_traced_shadows.glsl"
#include "bindings/constants.glsl"
#include "push/ray_traced_shadows.glsl"
#include "traced_scene.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// Rays towards a light with a size: 5 × 3 stratified points of its disc (SIZED_RAYS).
const uint SIZED_ACROSS = 5u;
const uint SIZED_DOWN = 3u;

// The world position at `coordinate` (pixels, from the image's corner) and `depth`.
vec3 world_at(vec2 coordinate, float depth, vec2 size) {
    vec4 world = push.inverse_view_projection * vec4(coordinate / size * 2.0 - 1.0, depth, 1.0);
    return world.xyz / world.w;
}

// A 32-bit integer hash (Wang's, as the occlusion pass's).
uint hash(uint x) {
    x = (x ^ 61u) ^ (x >> 16);
    x *= 9u;
    x ^= x >> 4;
    x *= 0x27d4eb2du;
    x ^= x >> 15;
    return x;
}

// Stratified point `k` of the unit disc (uniform by area), the pattern turned by `turn`.
vec2 disc_point(uint k, vec2 turn) {
    vec2 u = fract((vec2(float(k % SIZED_ACROSS), float(k / SIZED_ACROSS)) + 0.5)
                   / vec2(float(SIZED_ACROSS), float(SIZED_DOWN)) + turn);
    float r = sqrt(u.x);
    float phi = 2.0 * PI * u.y;
    return r * vec2(cos(phi), sin(phi));
}

// Whether the segment from `origin` to the light point `target` is clear, ending the
// reference's offset short of the point.
bool towards_point_clear(vec3 origin, vec3 target) {
    vec3 to_light = target - origin;
    float distance = length(to_light);
    float reach = distance - surface_offset(target);
    if (distance == 0.0 || reach <= 0.0) {
        return true;
    }
    return !scene_blocks(origin, to_light / distance, reach);
}

// How many of `light`'s rays from `origin` reach it, of 15, turned by `turn`.
uint light_reaching(GpuLight light, vec3 origin, vec3 p, vec2 turn) {
    float size = light.spot_axis.w;
    bool directional = light.power_kind.a == LIGHT_KIND_DIRECTIONAL;
    if (!(size > 0.0)) {
        if (directional) {
            return scene_blocks(origin, -light.position_or_direction.xyz, 1e30) ? 0u : 15u;
        }
        return towards_point_clear(origin, light.position_or_direction.xyz) ? 15u : 0u;
    }
    vec3 axis;
    if (directional) {
        axis = -light.position_or_direction.xyz;
    } else {
        vec3 facing = p - light.position_or_direction.xyz;
        axis = dot(facing, facing) > 0.0 ? normalize(facing) : vec3(0.0, 0.0, 1.0);
    }
    vec3 t;
    vec3 b;
    orthonormal_basis(axis, t, b);
    uint reaching = 0u;
    for (uint k = 0u; k < SIZED_ACROSS * SIZED_DOWN; ++k) {
        vec2 d = disc_point(k, turn) * size;
        bool clear = directional
            ? !scene_blocks(origin, normalize(axis + t * d.x + b * d.y), 1e30)
            : towards_point_clear(origin, light.position_or_direction.xyz + t * d.x + b * d.y);
        reaching += clear ? 1u : 0u;
    }
    return reaching;
}

void main() {
    ivec2 size = imageSize(light_bits);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, size))) {
        return;
    }
    float depth = texelFetch(gbuffer_depth, pixel, 0).r;
    if (isnan(depth) || depth >= 1.0) {
        imageStore(light_bits, pixel, uvec4(0xffffffffu));  // every nibble 15: all reach
        return;
    }
    vec3 p = world_at(vec2(pixel) + 0.5, depth, vec2(size));
    vec3 v = normalize(push.camera_position.xyz - p);
    vec3 n = facing_view(octahedral_decode(texelFetch(gbuffer_normal_roughness_anisotropy, pixel, 0).xy), v);
    vec3 origin = p + n * surface_offset(p);
    uint h = hash(uint(pixel.x) * 7919u + hash(uint(pixel.y)));
    uvec4 counts = uvec4(0u);
    for (uint i = 0u; i < push.lights; ++i) {
        uint reaching = 15u;
        if ((push.casting & (1u << i)) != 0u) {
            uint turn_bits = hash(h + i);
            vec2 turn = vec2(float(turn_bits & 0xffffu), float(turn_bits >> 16)) / 65536.0;
            reaching = light_reaching(lights[i], origin, p, turn);
        }
        counts[i >> 3] |= reaching << ((i & 7u) * 4u);
    }
    imageStore(light_bits, pixel, counts);
}
