#version 460
#extension GL_GOOGLE_include_directive : require
// Back faces pass, vertex stage: object → world → clip, and the normal to world space
// (combustion_renderer::back_faces::BackFacesPass).
#include "gpu_types.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

#include "bindings/back_faces.glsl"  // set 0: see combustion_renderer::bindings::BACK_FACES

layout(push_constant) uniform BackFacesPush {
    mat4 view_projection;
    uint object_index;
} push;

layout(location = 0) out vec3 out_normal;

void main() {
    // Instanced draws (combustion_renderer::mesh_draw): instance i is the object after
    // the pushed one by i.
    GpuObject object = objects[push.object_index + uint(gl_InstanceIndex)];
    gl_Position = push.view_projection * (object.model * vec4(in_position, 1.0));
    out_normal = mat3(object.normal_matrix) * in_normal;
}
