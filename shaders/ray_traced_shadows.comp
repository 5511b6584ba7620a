#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_ray_query : require
// Ray-traced shadows (the optional pass `ray-traced-shadows`, passes/ray_traced_shadows.rs):
// per pixel, for each of the first push.lights lights whose bit is set in push.casting, one
// ray from the surface towards the light, any hit against the scene's acceleration
// structure; bit i of the pixel's word is set where light i reaches it (and for lights
// that cast no shadow). The offset rule is the f64 reference's
// (combustion_reference::shadow_ray_origin): the ray starts 1e-4 · max(1, |p|∞) along the
// normal the lighting pass shades with, and a segment to a point or spot light ends
// 1e-4 · max(1, |light|∞) short of it.
#include "gbuffer_encoding.glsl"
#include "gpu_types.glsl"
#include "brdf.glsl"
#include "bindings/ray_traced_shadows.glsl"
#include "bindings/constants.glsl"
#include "push/ray_traced_shadows.glsl"
#include "traced_scene.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// The world position at `coordinate` (pixels, from the image's corner) and `depth`.
vec3 world_at(vec2 coordinate, float depth, vec2 size) {
    vec4 world = push.inverse_view_projection * vec4(coordinate / size * 2.0 - 1.0, depth, 1.0);
    return world.xyz / world.w;
}

// The reference's step off a surface at `p`: 1e-4 · max(1, |p|∞).
float surface_offset(vec3 p) {
    vec3 a = abs(p);
    return 1e-4 * max(1.0, max(a.x, max(a.y, a.z)));
}

void main() {
    ivec2 size = imageSize(light_bits);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, size))) {
        return;
    }
    float depth = texelFetch(gbuffer_depth, pixel, 0).r;
    if (isnan(depth) || depth >= 1.0) {
        imageStore(light_bits, pixel, uvec4(0xffffffffu));
        return;
    }
    vec3 p = world_at(vec2(pixel) + 0.5, depth, vec2(size));
    vec3 v = normalize(push.camera_position.xyz - p);
    vec3 n = facing_view(octahedral_decode(texelFetch(gbuffer_normal_roughness_anisotropy, pixel, 0).xy), v);
    vec3 origin = p + n * surface_offset(p);
    uint bits = ~push.casting;
    for (uint i = 0u; i < push.lights; ++i) {
        if ((push.casting & (1u << i)) == 0u) {
            continue;
        }
        GpuLight light = lights[i];
        vec3 direction;
        float reach;
        if (light.power_kind.a != LIGHT_KIND_DIRECTIONAL) {
            vec3 to_light = light.position_or_direction.xyz - origin;
            float distance = length(to_light);
            if (distance == 0.0) {
                bits |= 1u << i;
                continue;
            }
            direction = to_light / distance;
            reach = distance - surface_offset(light.position_or_direction.xyz);
        } else {
            direction = -light.position_or_direction.xyz;
            reach = 1e30;
        }
        if (reach <= 0.0) {
            bits |= 1u << i;
            continue;
        }
        if (!scene_blocks(origin, direction, reach)) {
            bits |= 1u << i;
        }
    }
    imageStore(light_bits, pixel, uvec4(bits));
}
