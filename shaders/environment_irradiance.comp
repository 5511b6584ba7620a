#version 460
#extension GL_GOOGLE_include_directive : require
// The irradiance cube: per texel direction n, the cosine-weighted mean radiance
// E(n)/π = ∫ L(l) max(0, n·l) dl / ∫ max(0, n·l) dl, summed over every texel of one
// level of the radiance cube with its exact solid angle. Dividing by the discrete ∫ cos
// (not π) makes a uniform environment come out exactly uniform.
#include "environment_bake.glsl"

layout(push_constant) uniform EnvironmentIrradiancePush {
    uint size;          // the irradiance cube's texels per side
    uint source_level;  // the radiance cube's level summed over
    uint source_size;   // its texels per side
} push;

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    uint size = push.size;
    if (id.x >= size || id.y >= size) {
        return;
    }
    vec3 n = cube_texel_direction(id.z, id.xy, size);
    uint source_size = push.source_size;
    float level = float(push.source_level);
    // Compensated (Kahan) sums: thousands of terms, kept to a few ulps.
    precise vec3 sum = vec3(0.0);
    precise vec3 sum_error = vec3(0.0);
    precise float weight = 0.0;
    precise float weight_error = 0.0;
    for (uint face = 0u; face < 6u; ++face) {
        for (uint y = 0u; y < source_size; ++y) {
            for (uint x = 0u; x < source_size; ++x) {
                vec3 d = cube_texel_direction(face, uvec2(x, y), source_size);
                float c = dot(n, d);
                if (c <= 0.0) {
                    continue;
                }
                float w = c * cube_texel_solid_angle(uvec2(x, y), source_size);
                precise vec3 term = textureLod(environment_source, d, level).rgb * w - sum_error;
                precise vec3 next = sum + term;
                sum_error = (next - sum) - term;
                sum = next;
                precise float w_term = w - weight_error;
                precise float w_next = weight + w_term;
                weight_error = (w_next - weight) - w_term;
                weight = w_next;
            }
        }
    }
    imageStore(environment_target, ivec3(id), vec4(sum / weight, 1.0));
}
