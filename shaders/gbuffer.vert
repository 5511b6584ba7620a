#version 460
#extension GL_GOOGLE_include_directive : require
// G-buffer pass, vertex stage: object → world → clip.
#include "gpu_types.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
#if defined(TEXTURES) || defined(TEXTURE_TRANSFORMS)
layout(location = 3) in vec2 in_uv;  // read where a material samples a texture
#endif
#ifdef TEXTURE_TRANSFORMS
layout(location = 4) in vec2 in_uv1;
#endif
#ifdef VERTEX_COLORS
layout(location = 5) in vec4 in_color;  // stream 2; read where the object's flag says
#endif

#include "bindings/gbuffer.glsl"  // set 0: see combustion_renderer::bindings::GBUFFER

layout(push_constant) uniform GBufferPush {
    mat4 view_projection;
    uint object_index;
} push;

layout(location = 0) out vec3 out_world_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec4 out_tangent;
layout(location = 3) flat out uint out_material;
#ifdef VERTEX_COLORS
layout(location = 8) out vec4 out_color;  // glTF COLOR_0, linear RGBA (white without one)
#endif
#ifndef TEXTURE_TRANSFORMS
#ifdef TEXTURES
layout(location = 4) out vec2 out_uv;
#endif
#else
// Each sampled slot's coordinates, mapped here per vertex (an affine map interpolates
// exactly), so the fragment stage's derivatives, helper invocations included, see the
// mapped coordinates: (base colour, metallic-roughness), (normal, emissive), (anisotropy,
// occlusion).
layout(location = 5) out vec4 out_slot_uv[3];
#ifdef TRANSMISSION
layout(location = 9) out vec4 out_slot_uv_transmission;  // transmission, thickness (forward pass)
#endif
#ifdef CLEARCOAT
layout(location = 10) out vec4 out_slot_uv_clearcoat;  // clearcoat, clearcoat roughness
layout(location = 11) out vec2 out_slot_uv_clearcoat_normal;
#endif
#ifdef SHEEN
layout(location = 12) out vec4 out_slot_uv_sheen;  // sheen colour, sheen roughness
#endif
#ifdef SPECULAR
layout(location = 14) out vec4 out_slot_uv_specular;  // specular, specular colour
#endif
#ifdef IRIDESCENCE
layout(location = 13) out vec4 out_slot_uv_film;  // iridescence, iridescence thickness
#endif
#include "texture_slots.glsl"
#endif

void main() {
    // Instanced draws (combustion_renderer::mesh_draw): instance i is the object after
    // the pushed one by i.
    GpuObject object = objects[push.object_index + uint(gl_InstanceIndex)];
    vec4 world = object.model * vec4(in_position, 1.0);
    out_world_position = world.xyz;
    out_normal = mat3(object.normal_matrix) * in_normal;
    out_tangent = vec4(mat3(object.model) * in_tangent.xyz, in_tangent.w);
    out_material = object.material_index.x;
#ifdef VERTEX_COLORS
    out_color = object.material_index.y != 0u ? in_color : vec4(1.0);
#endif
#ifndef TEXTURE_TRANSFORMS
#ifdef TEXTURES
    out_uv = in_uv;
#endif
#else
    // Slots in combustion_scene::TextureSlot::ALL order.
    uint m = object.material_index.x;
    out_slot_uv[0] = vec4(slot_uv(m, 0u, in_uv, in_uv1), slot_uv(m, 1u, in_uv, in_uv1));
    out_slot_uv[1] = vec4(slot_uv(m, 2u, in_uv, in_uv1), slot_uv(m, 4u, in_uv, in_uv1));
    out_slot_uv[2] = vec4(slot_uv(m, 5u, in_uv, in_uv1), slot_uv(m, 3u, in_uv, in_uv1));
#ifdef TRANSMISSION
    out_slot_uv_transmission = vec4(slot_uv(m, 8u, in_uv, in_uv1), slot_uv(m, 9u, in_uv, in_uv1));
#endif
#ifdef CLEARCOAT
    out_slot_uv_clearcoat = vec4(slot_uv(m, 10u, in_uv, in_uv1), slot_uv(m, 11u, in_uv, in_uv1));
    out_slot_uv_clearcoat_normal = slot_uv(m, 12u, in_uv, in_uv1);
#endif
#ifdef SHEEN
    out_slot_uv_sheen = vec4(slot_uv(m, 13u, in_uv, in_uv1), slot_uv(m, 14u, in_uv, in_uv1));
#endif
#ifdef IRIDESCENCE
    out_slot_uv_film = vec4(slot_uv(m, 15u, in_uv, in_uv1), slot_uv(m, 16u, in_uv, in_uv1));
#endif
#ifdef SPECULAR
    out_slot_uv_specular = vec4(slot_uv(m, 6u, in_uv, in_uv1), slot_uv(m, 7u, in_uv, in_uv1));
#endif
#endif
    gl_Position = push.view_projection * world;
#ifdef POINTS
    // A point list's pipeline: each point one pixel (Vulkan reads the size only there).
    gl_PointSize = 1.0;
#endif
}
