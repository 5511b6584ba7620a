#version 460
#extension GL_GOOGLE_include_directive : require
// One level of the environment's radiance cube: level 0 evaluates the source at each
// texel's centre; level i > 0 is the mean of the four texels of level i − 1 it covers
// (one bilinear sample at their shared corner, which is the level-i texel's centre).
// params.x: the level's size; params.y: 0 = evaluate the source, 1 = reduce level
// params.z of environment_source.
#include "environment_bake.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    uint size = push.params.x;
    if (id.x >= size || id.y >= size) {
        return;
    }
    vec3 d = cube_texel_direction(id.z, id.xy, size);
    vec3 l = push.params.y == 0u
        ? environment_source_radiance(push.source, d)
        : textureLod(environment_source, d, float(push.params.z)).rgb;
    imageStore(environment_target, ivec3(id), vec4(l, 1.0));
}
