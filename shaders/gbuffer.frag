#version 460
#extension GL_GOOGLE_include_directive : require
// G-buffer pass, fragment stage: writes the per-pixel surface description.
// Layout: docs/gbuffer.md.
#include "gpu_types.glsl"
#include "gbuffer_encoding.glsl"
#include "srgb.glsl"
#ifdef ALPHA_MASK
#include "alpha_mask.glsl"
#endif

layout(location = 0) in vec3 in_world_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) flat in uint in_material;
#ifdef VERTEX_COLORS
layout(location = 8) in vec4 in_color;  // glTF COLOR_0, multiplied into base colour and alpha
#endif
#ifndef TEXTURE_TRANSFORMS
layout(location = 4) in vec2 in_uv;
#else
layout(location = 5) in vec4 in_slot_uv[3];  // gbuffer.vert: each slot's mapped coordinates
#endif

// Set 0: the object and material tables (combustion_renderer::bindings::GBUFFER).
#include "bindings/gbuffer.glsl"
// Set 1: the material's textures, bound per material; empty slots hold a 1×1 white
// texture and are not sampled: the material table's index is -1 for them. The occlusion
// slot is sampled in the OCCLUSION variant (environment lighting); the specular slots are
// bound but not sampled (specular is not shaded). See
// combustion_renderer::bindings::MATERIAL_TEXTURES.
#include "bindings/material_textures.glsl"

layout(location = 0) out vec4 out_base_color_metalness;       // GBufferStorage: sRGB-encoded rgb in RGBA8/16_UNORM, linear in RGBA16F
layout(location = 1) out vec4 out_normal_roughness_anisotropy; // RGBA16_UNORM or RGBA8_UNORM
layout(location = 2) out uvec2 out_material_direction;         // RG16_UINT
#ifdef EMISSIVE_OCCLUSION_TARGET
layout(location = 3) out vec4 out_emissive;  // the HDR image's format (f16/f32): rgb emitted radiance, a occlusion
#endif

// Where each sampled slot samples: its coordinate set through its KHR_texture_transform
// (mapped per vertex in the TEXTURE_TRANSFORMS variant), else the mesh's first set.
#ifdef TEXTURE_TRANSFORMS
#define UV_BASE_COLOR in_slot_uv[0].xy
#define UV_METALLIC_ROUGHNESS in_slot_uv[0].zw
#define UV_NORMAL in_slot_uv[1].xy
#define UV_EMISSIVE in_slot_uv[1].zw
#define UV_ANISOTROPY in_slot_uv[2].xy
#define UV_OCCLUSION in_slot_uv[2].zw
#else
#define UV_BASE_COLOR in_uv
#define UV_METALLIC_ROUGHNESS in_uv
#define UV_NORMAL in_uv
#define UV_EMISSIVE in_uv
#define UV_ANISOTROPY in_uv
#define UV_OCCLUSION in_uv
#endif

void main() {
#ifdef FLOOR_GEOMETRY
    // Measurement floor (combustion_renderer::MeasurementFloor::Geometry): the same
    // meshes, vertex format and targets with a trivial fragment stage (every input
    // read, so the interpolation is the real pass's).
#ifdef TEXTURE_TRANSFORMS
    vec2 uv = in_slot_uv[0].xy + in_slot_uv[0].zw + in_slot_uv[1].xy + in_slot_uv[1].zw + in_slot_uv[2].xy
            + in_slot_uv[2].zw;
#else
    vec2 uv = in_uv;
#endif
    out_base_color_metalness = vec4(
        clamp(in_world_position + in_normal + in_tangent.xyz + vec3(uv, in_tangent.w), 0.0, 1.0),
        0.0);
    out_normal_roughness_anisotropy = vec4(0.5, 0.5, 0.5, 0.0);
    out_material_direction = uvec2(in_material, 0u);
#ifdef EMISSIVE_OCCLUSION_TARGET
    out_emissive = vec4(0.0);
#endif
    return;
#endif
    GpuMaterial material = materials[in_material];
    ivec4 tex0 = material.textures_base_mr_normal_occlusion;
    ivec4 tex1 = material.textures_emissive_anisotropy_specular;
#ifdef ALPHA_MASK
    // Cut-out materials (their own pipeline): the test is made here, the discard at the
    // end, so every implicit derivative below is taken with the whole quad alive.
#ifdef VERTEX_COLORS
    float vertex_alpha = in_color.a;
#else
    float vertex_alpha = 1.0;
#endif
    bool cut_away = alpha_cut_away(material, base_color_texture, UV_BASE_COLOR, vertex_alpha);
#endif

    // Geometric frame: interpolated normal (facet normal if it is degenerate) and the
    // mesh tangent made orthogonal to it.
    vec3 geometric = cross(dFdx(in_world_position), dFdy(in_world_position));
    vec3 n = in_normal;
    if (!(dot(n, n) > 1e-20) || any(isnan(n)) || any(isinf(n))) {
        n = geometric;
    }
    n = normalize(n);
    if (!gl_FrontFacing) {
        n = -n;
    }
    vec3 t = in_tangent.xyz - n * dot(n, in_tangent.xyz);
    if (!(dot(t, t) > 1e-20) || any(isnan(t))) {
        vec3 unused;
        orthonormal_basis(n, t, unused);
    }
    t = normalize(t);
    vec3 b = cross(n, t) * (in_tangent.w < 0.0 ? -1.0 : 1.0);

    // Normal map (tangent space, glTF convention), scaled in x and y.
    if (tex0.z >= 0) {
        vec3 m = texture(normal_texture, UV_NORMAL).xyz * 2.0 - 1.0;
        m.xy *= material.emissive_normal_scale.a;
        vec3 mapped = mat3(t, b, n) * m;
        if (dot(mapped, mapped) > 1e-20) {
            n = normalize(mapped);
            t = normalize(t - n * dot(n, t));
            b = cross(n, t) * (in_tangent.w < 0.0 ? -1.0 : 1.0);
        }
    }

    vec4 base = material.base_color_metalness;
    if (tex0.x >= 0) {
        base.rgb *= texture(base_color_texture, UV_BASE_COLOR).rgb;
    }
#ifdef VERTEX_COLORS
    base.rgb *= in_color.rgb;
#endif
    vec4 metal_rough = tex0.y >= 0
        ? texture(metallic_roughness_texture, UV_METALLIC_ROUGHNESS)
        : vec4(1.0);
    // glTF: G = roughness, B = metalness
    float metalness = base.a * metal_rough.b;
    float roughness = material.roughness_anisotropy_ior.x * metal_rough.g;

    // Anisotropy (KHR_materials_anisotropy): direction in tangent space from the texture's
    // RG (or +x), rotated by the material's rotation; strength × the texture's B.
    float strength = material.roughness_anisotropy_ior.y;
    vec2 along = vec2(1.0, 0.0);
    if (tex1.y >= 0) {
        vec3 a = texture(anisotropy_texture, UV_ANISOTROPY).rgb;
        along = a.rg * 2.0 - 1.0;
        strength *= a.b;
    }
    float rotation = material.roughness_anisotropy_ior.z;
    float c = cos(rotation), s = sin(rotation);
    along = vec2(c * along.x - s * along.y, s * along.x + c * along.y);
    vec3 direction = along.x * t + along.y * b;
    if (!(dot(direction, direction) > 1e-20)) {
        direction = t;
    }

#ifdef BASE_COLOR_LINEAR
    out_base_color_metalness = vec4(clamp(base.rgb, 0.0, 1.0), metalness);  // RGBA16F
#else
    out_base_color_metalness = vec4(srgb_encode(base.rgb), metalness);
#endif
    out_normal_roughness_anisotropy = vec4(octahedral_encode(n), roughness, strength);
    out_material_direction = uvec2(in_material, anisotropy_direction_encode(stored_normal(n), normalize(direction)));
#ifdef EMISSIVE_OCCLUSION_TARGET
    vec3 emissive = vec3(0.0);
#ifdef EMISSIVE
    emissive = material.emissive_normal_scale.rgb;
    if (tex1.x >= 0) {
        emissive *= texture(emissive_texture, UV_EMISSIVE).rgb;
    }
#endif
    // glTF occlusion: 1 + strength · (R − 1), from the texture's red channel.
    float occlusion = 1.0;
#ifdef OCCLUSION
    if (tex0.w >= 0) {
        float strength = uintBitsToFloat(material.diffuse_model_flags.z);
        occlusion = 1.0 + strength * (texture(occlusion_texture, UV_OCCLUSION).r - 1.0);
    }
#endif
    out_emissive = vec4(emissive, occlusion);
#endif
#ifdef ALPHA_MASK
    if (cut_away) {
        discard;
    }
#endif
}
