#version 460
#extension GL_GOOGLE_include_directive : require
// One level of the environment's radiance cube: level 0 evaluates the analytic source
// at each texel's centre, or averages the equirectangular image over the texel (n × n
// bilinear samples, n at least the image's texels across one cube texel); level i > 0
// is the mean of the four texels of level i − 1 it covers (one bilinear sample at their
// shared corner, the level-i texel's centre).
#include "environment_bake.glsl"

layout(push_constant) uniform EnvironmentRadiancePush {
    EnvironmentSource source;
    uint size;            // the level's texels per side
    uint mode;            // 0: evaluate the analytic source; 1: reduce level source_level
                          // of environment_source; 2: average environment_equirect
    uint source_level;    // mode 1: the level read
    uint samples_across;  // mode 2: n
} push;

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    uint size = push.size;
    if (id.x >= size || id.y >= size) {
        return;
    }
    vec3 d = cube_texel_direction(id.z, id.xy, size);
    vec3 l;
    if (push.mode == 0u) {
        l = environment_source_radiance(push.source, d);
    } else if (push.mode == 1u) {
        l = textureLod(environment_source, d, float(push.source_level)).rgb;
    } else {
        uint n = max(push.samples_across, 1u);
        l = vec3(0.0);
        for (uint j = 0u; j < n; ++j) {
            for (uint i = 0u; i < n; ++i) {
                vec2 at = (vec2(id.xy) + (vec2(i, j) + 0.5) / float(n)) / float(size) * 2.0 - 1.0;
                vec2 uv = equirect_coordinates(cube_face_direction(id.z, at));
                l += textureLod(environment_equirect, uv, 0.0).rgb;
            }
        }
        l *= 1.0 / float(n * n);
    }
    imageStore(environment_target, ivec3(id), vec4(l, 1.0));
}
