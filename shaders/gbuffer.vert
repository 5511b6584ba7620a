#version 460
#extension GL_GOOGLE_include_directive : require
// G-buffer pass, vertex stage: object → world → clip.
#include "gpu_types.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec2 in_uv;

#include "bindings/gbuffer.glsl"  // set 0: see combustion_renderer::bindings::GBUFFER

layout(push_constant) uniform GBufferPush {
    mat4 view_projection;
    uint object_index;
} push;

layout(location = 0) out vec3 out_world_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec4 out_tangent;
layout(location = 3) flat out uint out_material;
layout(location = 4) out vec2 out_uv;

void main() {
    GpuObject object = objects[push.object_index];
    vec4 world = object.model * vec4(in_position, 1.0);
    out_world_position = world.xyz;
    out_normal = mat3(object.normal_matrix) * in_normal;
    out_tangent = vec4(mat3(object.model) * in_tangent.xyz, in_tangent.w);
    out_material = object.material_index.x;
    out_uv = in_uv;
    gl_Position = push.view_projection * world;
}
