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
layout(location = 4) in vec2 in_uv;
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
#define UV_BASE_COLOR in_uv
#define UV_METALLIC_ROUGHNESS in_uv
#define UV_NORMAL in_uv
#define UV_EMISSIVE in_uv
#define UV_ANISOTROPY in_uv
#define UV_OCCLUSION in_uv
#define UV_TRANSMISSION in_uv
#define UV_THICKNESS in_uv
#define UV_CLEARCOAT in_uv
#define UV_CLEARCOAT_ROUGHNESS in_uv
#define UV_CLEARCOAT_NORMAL in_uv
#define UV_SHEEN_COLOR in_uv
#define UV_SHEEN_ROUGHNESS in_uv
#define UV_IRIDESCENCE in_uv
#define UV_IRIDESCENCE_THICKNESS in_uv
#define UV_SPECULAR in_uv
#define UV_SPECULAR_COLOR in_uv
#endif

// The vertex colour's alpha (1 without vertex colours).
float vertex_alpha() {
#ifdef VERTEX_COLORS
    return in_color.a;
#else
    return 1.0;
#endif
}

// What the fragment's material says of its surface, factors times textures times the
// vertex colour.
struct MaterialSurface {
    vec3 base_color;  // linear
    float alpha;      // the base colour factor's, texture's and vertex colour's alpha
    float metalness;
    float roughness;  // perceptual
    float anisotropy; // strength
    vec3 normal;      // unit shading normal (normal map applied; reversed on back faces)
    vec3 direction;   // unit anisotropy direction, in the plane of `normal`
    vec3 emissive;    // emitted radiance (EMISSIVE variant; 0 otherwise)
    float occlusion;  // glTF occlusion (OCCLUSION variant; 1 otherwise)
    // KHR_materials_clearcoat (CLEARCOAT variant; weight 0 otherwise): the coat's weight,
    // perceptual roughness and unit normal (its own normal map applied to the geometry's
    // normal, not the base's normal map; reversed on back faces).
    float clearcoat;
    float clearcoat_roughness;
    vec3 clearcoat_normal;
    // KHR_materials_sheen (SHEEN variant; black otherwise): its linear colour and
    // perceptual roughness.
    vec3 sheen_color;
    float sheen_roughness;
    // KHR_materials_iridescence (IRIDESCENCE variant; 0 otherwise): the thin film's
    // weight and thickness in nm (0: no film).
    float film_weight;
    float film_thickness_nm;
    // KHR_materials_specular (SPECULAR variant; 1 and 1 otherwise): the dielectric's
    // specular factor and its linear colour.
    float specular_factor;
    vec3 specular_color;
};

// A tangent-space normal map's texel (glTF convention: RGB mapped to [−1, 1]), its x
// and y scaled by `scale`, in `frame` (tangent, bitangent, normal); `fallback` where the
// result is degenerate.
vec3 normal_mapped(vec4 texel, float scale, mat3 frame, vec3 fallback) {
    vec3 m = texel.xyz * 2.0 - 1.0;
    m.xy *= scale;
    vec3 mapped = frame * m;
    return dot(mapped, mapped) > 1e-20 ? normalize(mapped) : fallback;
}

MaterialSurface material_surface(GpuMaterial material) {
    ivec4 tex0 = material.textures_base_mr_normal_occlusion;
    ivec4 tex1 = material.textures_emissive_anisotropy_specular;
    MaterialSurface s;

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
    // The geometry's frame, before the base's normal map: the coat's.
    mat3 geometry_frame = mat3(t, b, n);

    // Normal map (tangent space, glTF convention), scaled in x and y.
    if (tex0.z >= 0) {
        n = normal_mapped(texture(normal_texture, UV_NORMAL), material.emissive_normal_scale.a,
                          geometry_frame, n);
        t = normalize(t - n * dot(n, t));
        b = cross(n, t) * (in_tangent.w < 0.0 ? -1.0 : 1.0);
    }

    vec4 base = vec4(material.base_color_metalness.rgb, material.alpha_cutoff.x);
    if (tex0.x >= 0) {
        base *= texture(base_color_texture, UV_BASE_COLOR);
    }
#ifdef VERTEX_COLORS
    base *= in_color;
#endif
    vec4 metal_rough = tex0.y >= 0
        ? texture(metallic_roughness_texture, UV_METALLIC_ROUGHNESS)
        : vec4(1.0);
    // glTF: G = roughness, B = metalness
    s.base_color = base.rgb;
    s.alpha = base.a;
    s.metalness = material.base_color_metalness.a * metal_rough.b;
    s.roughness = material.roughness_anisotropy_ior.x * metal_rough.g;

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
    float c = cos(rotation), sn = sin(rotation);
    along = vec2(c * along.x - sn * along.y, sn * along.x + c * along.y);
    vec3 direction = along.x * t + along.y * b;
    if (!(dot(direction, direction) > 1e-20)) {
        direction = t;
    }
    s.anisotropy = strength;
    s.normal = n;
    s.direction = normalize(direction);

    s.emissive = vec3(0.0);
#ifdef EMISSIVE
    s.emissive = material.emissive_normal_scale.rgb;
    if (tex1.x >= 0) {
        s.emissive *= texture(emissive_texture, UV_EMISSIVE).rgb;
    }
#endif
    // glTF occlusion: 1 + strength · (R − 1), from the texture's red channel.
    s.occlusion = 1.0;
#ifdef OCCLUSION
    if (tex0.w >= 0) {
        float occlusion_strength = uintBitsToFloat(material.diffuse_model_flags.z);
        s.occlusion = 1.0 + occlusion_strength * (texture(occlusion_texture, UV_OCCLUSION).r - 1.0);
    }
#endif
    s.clearcoat = 0.0;
    s.clearcoat_roughness = 0.0;
    s.clearcoat_normal = geometry_frame[2];
#ifdef CLEARCOAT
    // KHR_materials_clearcoat: weight × R of its texture, roughness × G of its own, the
    // coat's normal map in the geometry's tangent frame, scaled in x and y.
    ivec4 tex2 = material.textures_clearcoat;
    s.clearcoat = material.clearcoat.x;
    if (tex2.x >= 0) {
        s.clearcoat *= texture(clearcoat_texture, UV_CLEARCOAT).r;
    }
    s.clearcoat_roughness = material.clearcoat.y;
    if (tex2.y >= 0) {
        s.clearcoat_roughness *= texture(clearcoat_roughness_texture, UV_CLEARCOAT_ROUGHNESS).g;
    }
    if (tex2.z >= 0) {
        s.clearcoat_normal = normal_mapped(texture(clearcoat_normal_texture, UV_CLEARCOAT_NORMAL),
                                           material.clearcoat.w, geometry_frame,
                                           s.clearcoat_normal);
    }
#endif
    s.sheen_color = vec3(0.0);
    s.sheen_roughness = 0.0;
#ifdef SHEEN
    // KHR_materials_sheen: colour × its texture's RGB (sRGB, decoded by the sampler's
    // format), roughness × its texture's A.
    ivec4 tex3 = material.textures_sheen;
    s.sheen_color = material.sheen.rgb;
    if (tex3.x >= 0) {
        s.sheen_color *= texture(sheen_color_texture, UV_SHEEN_COLOR).rgb;
    }
    s.sheen_roughness = material.sheen.a;
    if (tex3.y >= 0) {
        s.sheen_roughness *= texture(sheen_roughness_texture, UV_SHEEN_ROUGHNESS).a;
    }
#endif
    s.film_weight = 0.0;
    s.film_thickness_nm = 0.0;
#ifdef IRIDESCENCE
    // KHR_materials_iridescence: the factor × its texture's R; the thickness from the
    // minimum (z) to the maximum (w) by its texture's G, the maximum without one.
    ivec4 tex4 = material.textures_film;
    s.film_weight = material.film.x;
    if (tex4.x >= 0) {
        s.film_weight *= texture(iridescence_texture, UV_IRIDESCENCE).r;
    }
    s.film_thickness_nm = material.film.w;
    if (tex4.y >= 0) {
        s.film_thickness_nm = mix(material.film.z, material.film.w,
                                  texture(iridescence_thickness_texture, UV_IRIDESCENCE_THICKNESS).g);
    }
#endif
    s.specular_factor = 1.0;
    s.specular_color = vec3(1.0);
#ifdef SPECULAR
    // KHR_materials_specular: the factor × its texture's A, the colour × its colour
    // texture's RGB (sRGB, decoded by the sampler's format).
    s.specular_factor = material.specular.a;
    if (tex1.z >= 0) {
        s.specular_factor *= texture(specular_texture, UV_SPECULAR).a;
    }
    s.specular_color = material.specular.rgb;
    if (tex1.w >= 0) {
        s.specular_color *= texture(specular_color_texture, UV_SPECULAR_COLOR).rgb;
    }
#endif
    return s;
}

#endif
