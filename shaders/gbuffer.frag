#version 460
#extension GL_GOOGLE_include_directive : require
// G-buffer pass, fragment stage: writes the per-pixel surface description.
// Layout: docs/gbuffer.md.
#include "gpu_types.glsl"
#include "gbuffer_encoding.glsl"
#include "srgb.glsl"

layout(location = 0) in vec3 in_world_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) flat in uint in_material;

layout(std430, set = 0, binding = 1) readonly buffer Materials { GpuMaterial materials[]; };

layout(location = 0) out vec4 out_base_color_metalness;       // RGBA8_UNORM, sRGB-encoded rgb
layout(location = 1) out vec4 out_normal_roughness_anisotropy; // RGBA16_UNORM
layout(location = 2) out uvec2 out_material_direction;         // RG16_UINT

void main() {
    GpuMaterial material = materials[in_material];
    vec3 geometric = cross(dFdx(in_world_position), dFdy(in_world_position));
    vec3 n = in_normal;
    // A zero or non-finite interpolated normal falls back to the facet normal.
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
    float rotation = material.roughness_anisotropy_ior.z;
    vec3 direction = cos(rotation) * t + sin(rotation) * b;

    out_base_color_metalness = vec4(
        srgb_encode(material.base_color_metalness.rgb),
        material.base_color_metalness.a);
    out_normal_roughness_anisotropy = vec4(
        octahedral_encode(n),
        material.roughness_anisotropy_ior.x,
        material.roughness_anisotropy_ior.y);
    out_material_direction = uvec2(in_material, anisotropy_direction_encode(n, direction));
}
