// The surface a rasterised fragment shows, from its material, its textures and the
// interpolated vertex attributes: shared by the passes that shade the scene's objects
// themselves, the G-buffer pass (which stores it) and the forward pass (which lights it
// at once: blended materials). Declares the fragment inputs gbuffer.vert writes and set 1,
// the material's textures; needs gpu_types.glsl.
#ifndef COMBUSTION_MATERIAL_SURFACE_GLSL
#define COMBUSTION_MATERIAL_SURFACE_GLSL

#include "gbuffer_encoding.glsl"

layout(location = 0) in vec3 in_world_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) flat in uint in_material;
#ifdef VERTEX_COLORS
layout(location = 8) in vec4 in_color;  // glTF COLOR_0, multiplied into base colour and alpha
#endif
#ifndef TEXTURE_TRANSFORMS
#ifdef TEXTURES
layout(location = 4) in vec2 in_uv;
#define SURFACE_UV in_uv
#else
// Without textures no slot is sampled: no coordinates are interpolated.
#define SURFACE_UV vec2(0.0)
#endif
#else
layout(location = 5) in vec4 in_slot_uv[3];  // gbuffer.vert: each slot's mapped coordinates
#ifdef TRANSMISSION
layout(location = 9) in vec4 in_slot_uv_transmission;  // the transmission and thickness slots'
#endif
#ifdef CLEARCOAT
layout(location = 10) in vec4 in_slot_uv_clearcoat;  // the clearcoat and its roughness slots'
layout(location = 11) in vec2 in_slot_uv_clearcoat_normal;
#endif
#ifdef SHEEN
layout(location = 12) in vec4 in_slot_uv_sheen;  // the sheen colour and roughness slots'
#endif
#ifdef IRIDESCENCE
layout(location = 13) in vec4 in_slot_uv_film;  // the iridescence and its thickness slots'
#endif
#ifdef SPECULAR
layout(location = 14) in vec4 in_slot_uv_specular;  // the specular and its colour slots'
#endif
#endif

// Set 1: the material's textures, bound per material; empty slots hold a 1×1 white
// texture and are not sampled: the material table's index is -1 for them. The occlusion
// slot is sampled in the OCCLUSION variant (environment lighting), the specular slots in
// the SPECULAR variant. See combustion_renderer::bindings::MATERIAL_TEXTURES.
#include "bindings/material_textures.glsl"

// Where each sampled slot samples: its coordinate set through its KHR_texture_transform
// (mapped per vertex in the TEXTURE_TRANSFORMS variant), else the mesh's first set.
#ifdef TEXTURE_TRANSFORMS
#define UV_BASE_COLOR in_slot_uv[0].xy
#define UV_METALLIC_ROUGHNESS in_slot_uv[0].zw
#define UV_NORMAL in_slot_uv[1].xy
#define UV_EMISSIVE in_slot_uv[1].zw
#define UV_ANISOTROPY in_slot_uv[2].xy
#define UV_OCCLUSION in_slot_uv[2].zw
#define UV_TRANSMISSION in_slot_uv_transmission.xy
#define UV_THICKNESS in_slot_uv_transmission.zw
#define UV_CLEARCOAT in_slot_uv_clearcoat.xy
#define UV_CLEARCOAT_ROUGHNESS in_slot_uv_clearcoat.zw
#define UV_CLEARCOAT_NORMAL in_slot_uv_clearcoat_normal
#define UV_SHEEN_COLOR in_slot_uv_sheen.xy
#define UV_SHEEN_ROUGHNESS in_slot_uv_sheen.zw
#define UV_IRIDESCENCE in_slot_uv_film.xy
#define UV_IRIDESCENCE_THICKNESS in_slot_uv_film.zw
#define UV_SPECULAR in_slot_uv_specular.xy
#define UV_SPECULAR_COLOR in_slot_uv_specular.zw
#else
#define UV_BASE_COLOR SURFACE_UV
#define UV_METALLIC_ROUGHNESS SURFACE_UV
#define UV_NORMAL SURFACE_UV
#define UV_EMISSIVE SURFACE_UV
#define UV_ANISOTROPY SURFACE_UV
#define UV_OCCLUSION SURFACE_UV
#define UV_TRANSMISSION SURFACE_UV
#define UV_THICKNESS SURFACE_UV
#define UV_CLEARCOAT SURFACE_UV
#define UV_CLEARCOAT_ROUGHNESS SURFACE_UV
#define UV_CLEARCOAT_NORMAL SURFACE_UV
#define UV_SHEEN_COLOR SURFACE_UV
#define UV_SHEEN_ROUGHNESS SURFACE_UV
#define UV_IRIDESCENCE SURFACE_UV
#define UV_IRIDESCENCE_THICKNESS SURFACE_UV
#define UV_SPECULAR SURFACE_UV
#define UV_SPECULAR_COLOR SURFACE_UV
#endif

// The vertex colour's alpha (1 without vertex colours).
float vertex_alpha() {
#ifdef VERTEX_COLORS
    return in_color.a;
#else
    return 1.0;
#endif
}

// A slot's texture as the rasteriser samples it: its set 1 binding at the fragment's
// mapped coordinates, with the derivatives' mip level. In scenes without textures
// (no TEXTURES) every slot's index is -1 and no read is made: the reads, and the
// coordinates they would interpolate, are compiled out.
#ifdef TEXTURES
#define MATERIAL_TEXTURE(sampler, uv, index, slot) texture(sampler, uv)
#else
#define MATERIAL_TEXTURE(sampler, uv, index, slot) vec4(1.0)
#endif
#define MATERIAL_SURFACE_FUNCTION material_surface_of_fragment
#include "material_surface_at.glsl"

// The surface the fragment shows: its interpolated normal (the facet's where that is
// degenerate; reversed on a back face), tangent, vertex colour and coordinates.
MaterialSurface material_surface(GpuMaterial material) {
    // The facet's normal from derivatives taken in uniform control flow.
    vec3 geometric = cross(dFdx(in_world_position), dFdy(in_world_position));
    vec3 n = in_normal;
    if (!(dot(n, n) > 1e-20) || any(isnan(n)) || any(isinf(n))) {
        n = geometric;
    }
    n = normalize(n);
    if (!gl_FrontFacing) {
        n = -n;
    }
#ifdef VERTEX_COLORS
    vec4 color = in_color;
#else
    vec4 color = vec4(1.0);
#endif
    return material_surface_of_fragment(material, n, in_tangent, color, vec4(0.0));
}

#endif
