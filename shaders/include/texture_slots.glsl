// Where a material's texture slot samples: its coordinate set (TEXCOORD_0 or _1) through
// its KHR_texture_transform, from the material table's rows (GpuMaterial::uv_transforms;
// slots in combustion_scene::TextureSlot::ALL order). Needs gpu_types.glsl and the set
// declaring `materials`.
#ifndef COMBUSTION_TEXTURE_SLOTS_GLSL
#define COMBUSTION_TEXTURE_SLOTS_GLSL

vec2 slot_uv(uint material, uint slot, vec2 uv0, vec2 uv1) {
    vec4 r0 = materials[material].uv_transforms[2u * slot];
    vec4 r1 = materials[material].uv_transforms[2u * slot + 1u];
    vec3 uv = vec3(r0.w != 0.0 ? uv1 : uv0, 1.0);
    return vec2(dot(r0.xyz, uv), dot(r1.xyz, uv));
}

#endif
