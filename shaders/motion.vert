#version 460
#extension GL_GOOGLE_include_directive : require
// Motion vectors, vertex stage (combustion_renderer's passes/temporal_anti_aliasing.rs):
// each object drawn where the frame's jittered camera puts it (so its pixels are the
// G-buffer's), with where its vertex is now and was a frame ago seen by the camera
// unjittered (the previous frame's camera, the object's previous transform and, for a
// skinned or morphed object, its previous pose).
#include "gpu_types.glsl"

layout(location = 0) in vec3 in_position;

#include "bindings/motion.glsl"  // set 0: objects, previous_models
#include "push/motion.glsl"

layout(location = 0) out vec4 out_current;
layout(location = 1) out vec4 out_previous;

void main() {
    uint index = push.object_index + uint(gl_InstanceIndex);
    GpuObject object = objects[index];
    vec4 world = object.model * vec4(in_position, 1.0);
    // A posed object's vertex a frame ago: its previous pose's (the motion history's copy).
    uint base = previous_vertex_bases[index];
    vec3 then = in_position;
    if (base != 0xFFFFFFFFu) {
        uint v = (base + uint(gl_VertexIndex)) * 12u;  // GpuVertex: 12 floats, position first
        then = vec3(previous_vertices[v], previous_vertices[v + 1u], previous_vertices[v + 2u]);
    }
    vec4 before = previous_models[index] * vec4(then, 1.0);
    gl_Position = push.view_projection * world;
    out_current = push.unjittered * world;
    out_previous = push.previous * before;
}
