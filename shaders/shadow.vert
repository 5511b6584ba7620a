#version 460
#extension GL_GOOGLE_include_directive : require
// Shadow-caster pass, vertex stage: object → world → a shadow map's clip space
// (combustion_renderer::shadows::ShadowCasterPass). Positions only; the ALPHA_MASK
// pipeline (cut-out materials) also passes the base colour slot's coordinates, the
// material and the vertex colour's alpha on.
#include "gpu_types.glsl"

layout(location = 0) in vec3 in_position;
#ifdef ALPHA_MASK
layout(location = 1) in vec2 in_uv;
layout(location = 2) in vec2 in_uv1;
layout(location = 3) in vec4 in_color;  // stream 2; read where the object's flag says
#endif

#include "bindings/shadow_casters.glsl"  // set 0: see combustion_renderer::bindings::SHADOW_CASTERS

layout(push_constant) uniform ShadowPush {
    mat4 world_to_clip;
    uint object_index;
} push;

#ifdef ALPHA_MASK
#include "texture_slots.glsl"
layout(location = 0) out vec2 out_base_color_uv;
layout(location = 1) flat out uint out_material;
layout(location = 2) out float out_vertex_alpha;
#endif

void main() {
    // Instanced draws (combustion_renderer::mesh_draw): instance i is the object after
    // the pushed one by i.
    GpuObject object = objects[push.object_index + uint(gl_InstanceIndex)];
    gl_Position = push.world_to_clip * (object.model * vec4(in_position, 1.0));
#ifdef ALPHA_MASK
    out_material = object.material_index.x;
    out_base_color_uv = slot_uv(out_material, 0u, in_uv, in_uv1);  // TextureSlot::BaseColor
    out_vertex_alpha = object.material_index.y != 0u ? in_color.a : 1.0;
#endif
}
