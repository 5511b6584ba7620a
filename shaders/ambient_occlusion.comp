#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Ambient occlusion (the optional pass `ambient-occlusion`, passes/ambient_occlusion.rs):
// per pixel, the cosine-weighted visibility of the hemisphere above the surface, found in
// the depth buffer by ground-truth ambient occlusion (Jimenez et al. 2016, "Practical
// Real-Time Strategies for Accurate Indirect Occlusion"). In each of push.slices planes
// through the eye and the pixel, the two horizons are the highest points of the depth
// buffer within push.radius of the surface; the visibility between them, weighted by the
// cosine to the normal projected into the plane, is integrated exactly; its sum over the
// slices, over the same sum with nothing in the way, is the visibility (1: nothing in the
// way). Geometry is taken where the camera sees
// it: what lies behind a visible surface counts as solid. Each pixel of a 4×4 block turns
// its slices by its own sixteenth of the angle between two, and the block's pixels on the
// same surface (nearly the same distance and normal) average their visibilities: 16 times
// the slices over the block, without the banding of the same few directions everywhere.
#include "gbuffer_encoding.glsl"
#include "brdf.glsl"
#include "bindings/ambient_occlusion.glsl"
#include "push/ambient_occlusion.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

const float HALF_PI = 1.57079632679489662;

// The world position at `coordinate` (pixels, from the image's corner) and `depth`.
vec3 world_at(vec2 coordinate, float depth, vec2 size) {
    vec4 world = push.inverse_view_projection * vec4(coordinate / size * 2.0 - 1.0, depth, 1.0);
    return world.xyz / world.w;
}

// The visibility at `pixel` (1 for the background), and the surface there: its normal
// and its distance from the eye (0 for the background).
float visibility_at(ivec2 pixel, vec2 size, out vec3 n, out float eye_distance) {
    n = vec3(0.0);
    eye_distance = 0.0;
    float depth = texelFetch(gbuffer_depth, pixel, 0).r;
    if (isnan(depth) || depth >= 1.0) {
        return 1.0;
    }
    vec2 centre = vec2(pixel) + 0.5;
    vec3 p = world_at(centre, depth, size);
    vec3 to_eye = push.camera_position.xyz - p;
    eye_distance = length(to_eye);
    vec3 v = to_eye / eye_distance;
    // The normal as the lighting pass shades with it (made to face the eye).
    n = facing_view(octahedral_decode(texelFetch(gbuffer_normal_roughness_anisotropy, pixel, 0).xy), v);
    float distance_along_view = max(dot(p - push.camera_position.xyz, push.camera_forward.xyz), 1e-6);
    float radius_pixels = min(push.radius * push.camera_forward.w / distance_along_view,
                              push.max_radius_pixels);
    if (radius_pixels < 1.0) {
        // The search radius is within the pixel: nothing the depth buffer holds can occlude.
        return 1.0;
    }
    // The pixel's turn of its slices within the 4×4 block (a Bayer order: neighbours far
    // apart in angle).
    const float BAYER[16] = float[16](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0,
                                      3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);
    float turn = (BAYER[(pixel.y & 3) * 4 + (pixel.x & 3)] + 0.5) / 16.0;
    float tolerance = push.flat_tolerance * eye_distance * eye_distance;
    float sum = 0.0;
    float unoccluded = 0.0;
    for (uint s = 0u; s < push.slices; ++s) {
        float phi = PI * (float(s) + turn) / float(push.slices);
        vec2 d = vec2(cos(phi), sin(phi));
        // The slice: the plane through the eye and the screen line through the pixel along
        // d. `ortho` is its direction across v towards +d, `axis` its normal.
        vec3 along = world_at(centre + d, depth, size) - p;
        vec3 ortho = normalize(along - v * dot(along, v));
        vec3 axis = cross(ortho, v);
        vec3 projected = n - axis * dot(n, axis);
        float projected_length = length(projected);
        if (projected_length < 1e-6) {
            continue;
        }
        float cos_n = clamp(dot(projected, v) / projected_length, -1.0, 1.0);
        float angle_n = (dot(projected, ortho) >= 0.0 ? 1.0 : -1.0) * acos(cos_n);
        // The horizons' cosines to v on the +d side (0) and the -d side (1), from the
        // tangent plane's (nothing in the way) up.
        float low0 = cos(angle_n + HALF_PI);
        float low1 = cos(angle_n - HALF_PI);
        float horizon0 = low0;
        float horizon1 = low1;
        for (uint j = 1u; j <= push.steps; ++j) {
            // Steps closer together near the pixel, where occluders subtend more.
            float t = float(j) / float(push.steps);
            float offset = max(t * t * radius_pixels, float(j));
            for (int side = 0; side < 2; ++side) {
                vec2 at = centre + (side == 0 ? d : -d) * offset;
                if (any(lessThan(at, vec2(0.0))) || any(greaterThanEqual(at, size))) {
                    continue;
                }
                ivec2 q = ivec2(at);
                float q_depth = texelFetch(gbuffer_depth, q, 0).r;
                if (isnan(q_depth) || q_depth >= 1.0) {
                    continue;
                }
                vec3 delta = world_at(vec2(q) + 0.5, q_depth, size) - p;
                // A point on or below the tangent plane hides nothing of the hemisphere
                // (within the depth's precision there: a plane does not occlude itself).
                if (dot(delta, n) <= tolerance) {
                    continue;
                }
                float dist = length(delta);
                if (dist <= 0.0) {
                    continue;
                }
                // Occluders fade out over the last quarter of the radius.
                float weight = clamp((push.radius - dist) / (0.25 * push.radius), 0.0, 1.0);
                float cos_h = dot(delta, v) / dist;
                if (side == 0) {
                    horizon0 = max(horizon0, mix(low0, cos_h, weight));
                } else {
                    horizon1 = max(horizon1, mix(low1, cos_h, weight));
                }
            }
        }
        // The horizon angles from v (positive towards +d), within the hemisphere of the
        // projected normal, and the cosine-weighted visible arc between them.
        float h0 = -acos(clamp(horizon1, -1.0, 1.0));
        float h1 = acos(clamp(horizon0, -1.0, 1.0));
        h0 = angle_n + max(h0 - angle_n, -HALF_PI);
        h1 = angle_n + min(h1 - angle_n, HALF_PI);
        float sin_n = sin(angle_n);
        float arc0 = cos_n + 2.0 * h0 * sin_n - cos(2.0 * h0 - angle_n);
        float arc1 = cos_n + 2.0 * h1 * sin_n - cos(2.0 * h1 - angle_n);
        sum += projected_length * 0.25 * (arc0 + arc1);
        // The same slice with nothing in the way (h0, h1 = n ∓ π/2).
        unoccluded += projected_length * (cos_n + angle_n * sin_n);
    }
    // The slices' visible share of the hemisphere's cosine-weighted measure, both summed
    // by the same quadrature (its error cancels: a plane is exactly unoccluded).
    return unoccluded > 0.0 ? clamp(sum / unoccluded, 0.0, 1.0) : 1.0;
}

shared vec4 block_surface[64];  // normal (xyz), distance from the eye (w)
shared float block_visibility[64];

void main() {
    ivec2 size = imageSize(visibility);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    uint here = gl_LocalInvocationIndex;
    vec3 n = vec3(0.0);
    float eye_distance = 0.0;
    float value = 1.0;
    if (all(lessThan(pixel, size))) {
        value = visibility_at(pixel, vec2(size), n, eye_distance);
    }
    block_surface[here] = vec4(n, eye_distance);
    block_visibility[here] = value;
    barrier();
    if (any(greaterThanEqual(pixel, size))) {
        return;
    }
    if (eye_distance > 0.0) {
        // The 4×4 block's pixels on the same surface: within 2 % in distance and 25° in
        // normal.
        uvec2 block = (gl_LocalInvocationID.xy / 4u) * 4u;
        float total = 0.0;
        float weight = 0.0;
        for (uint y = 0u; y < 4u; ++y) {
            for (uint x = 0u; x < 4u; ++x) {
                uint other = (block.y + y) * 8u + block.x + x;
                vec4 surface = block_surface[other];
                if (abs(surface.w - eye_distance) <= 0.02 * eye_distance
                        && dot(surface.xyz, n) >= 0.906) {
                    total += block_visibility[other];
                    weight += 1.0;
                }
            }
        }
        value = total / weight;
    }
    imageStore(visibility, pixel, vec4(value));
}
