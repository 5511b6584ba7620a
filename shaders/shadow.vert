#version 460
#extension GL_GOOGLE_include_directive : require
// Shadow-caster pass, vertex stage: object → world → a shadow map's clip space
// (combustion_renderer::shadows::ShadowCasterPass). Positions only.
#include "gpu_types.glsl"

layout(location = 0) in vec3 in_position;

#include "bindings/shadow_casters.glsl"  // set 0: see combustion_renderer::bindings::SHADOW_CASTERS

layout(push_constant) uniform ShadowPush {
    mat4 world_to_clip;
    uint object_index;
} push;

void main() {
    gl_Position = push.world_to_clip * (objects[push.object_index].model * vec4(in_position, 1.0));
}
