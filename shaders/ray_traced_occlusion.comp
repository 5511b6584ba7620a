#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_ray_query : require
// Ray-traced occlusion (the optional pass `ray-traced-occlusion`,
// passes/ray_traced_occlusion.rs): per pixel, push.rays rays drawn from the cosine
// distribution about the normal (the one the lighting pass shades with), each tested
// against the scene's acceleration structure for any hit; the share that leave the scene
// is the visibility of the environment's diffuse light (1: nothing in the way). Each
// pixel turns a stratified set of directions by its own hash and the frame's seed: the
// same rays in every frame of one seed.
#include "gbuffer_encoding.glsl"
#include "brdf.glsl"
#include "bindings/ray_traced_occlusion.glsl"
#include "push/ray_traced_occlusion.glsl"
#include "traced_scene.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// The world position at `coordinate` (pixels, from the image's corner) and `depth`.
vec3 world_at(vec2 coordinate, float depth, vec2 size) {
    vec4 world = push.inverse_view_projection * vec4(coordinate / size * 2.0 - 1.0, depth, 1.0);
    return world.xyz / world.w;
}

// A 32-bit integer hash (Wang's, as in the shadows' rotation).
uint hash(uint x) {
    x = (x ^ 61u) ^ (x >> 16);
    x *= 9u;
    x ^= x >> 4;
    x *= 0x27d4eb2du;
    x ^= x >> 15;
    return x;
}

void main() {
    ivec2 size = imageSize(visibility);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, size))) {
        return;
    }
    float depth = texelFetch(gbuffer_depth, pixel, 0).r;
    if (isnan(depth) || depth >= 1.0) {
        imageStore(visibility, pixel, vec4(1.0));
        return;
    }
    vec3 p = world_at(vec2(pixel) + 0.5, depth, vec2(size));
    vec3 to_eye = push.camera_position.xyz - p;
    float eye_distance = length(to_eye);
    vec3 v = to_eye / eye_distance;
    vec3 n = facing_view(octahedral_decode(texelFetch(gbuffer_normal_roughness_anisotropy, pixel, 0).xy), v);
    vec3 t;
    vec3 b;
    orthonormal_basis(n, t, b);
    vec3 origin = p + n * (push.offset_per_distance * eye_distance);
    // The pixel's turn of the pattern: a hash of its coordinates, in [0, 1)².
    uint h = hash(uint(pixel.x) * 7919u + hash(uint(pixel.y) + hash(push.seed)));
    vec2 turn = vec2(float(h & 0xffffu), float(h >> 16)) / 65536.0;
    uint across = uint(round(sqrt(float(push.rays))));
    uint rays = across * across;
    uint open = 0u;
    for (uint i = 0u; i < rays; ++i) {
        // A stratified point of the unit square, turned, then the cosine distribution
        // (Malley's method: uniform on the disc, lifted to the hemisphere).
        vec2 u = fract((vec2(float(i % across), float(i / across)) + 0.5) / float(across) + turn);
        float r = sqrt(u.x);
        float phi = 2.0 * PI * u.y;
        vec3 direction = normalize(t * (r * cos(phi)) + b * (r * sin(phi))
                                   + n * sqrt(max(1.0 - u.x, 0.0)));
        if (!scene_blocks(origin, direction, push.reach)) {
            ++open;
        }
    }
    imageStore(visibility, pixel, vec4(float(open) / float(rays)));
}
