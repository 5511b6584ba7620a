// The scene's textures as a path's hits read them (PATH_TRACE; crates/renderer/src/
// accel.rs, TracedSurfaces): per texture of the material table's texture array, one
// `uvec4` of `traced_textures` — the device address of its image's level 0 (RGBA8, four
// bytes a texel, row-major from the top-left), its width and height (16 bits each), its
// flags (wrap modes in bits 0–1 and 2–3: 0 repeat, 1 mirrored repeat, 2 clamp to edge;
// bit 4 linear magnification; bit 5 sRGB). A hit has no pixel footprint: it reads level
// 0 with the magnification filter, as the f64 path tracer does (texels decoded from sRGB
// before they are filtered, as a sampler of an sRGB format does). Needs the binding
// `traced_textures`, gpu_types.glsl, srgb.glsl and traced_scene.glsl (texel_wrap).
#ifndef COMBUSTION_TRACED_TEXTURES_GLSL
#define COMBUSTION_TRACED_TEXTURES_GLSL

#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer TracedTexels {
    uint values[];
};

// Texel (`x`, `y`) of `texels` (`width` wide), decoded from sRGB where `srgb`.
vec4 traced_texel(TracedTexels texels, int x, int y, int width, bool srgb) {
    vec4 c = unpackUnorm4x8(texels.values[y * width + x]);
    return srgb ? vec4(srgb_decode(c.rgb), c.a) : c;
}

// Texture `index` of the texture array at `uv`, level 0.
vec4 traced_texture(int index, vec2 uv) {
    uvec4 entry = traced_textures[index];
    TracedTexels texels = TracedTexels(entry.xy);
    int w = int(entry.z & 0xffffu);
    int h = int(entry.z >> 16);
    uint wrap_u = entry.w & 3u;
    uint wrap_v = (entry.w >> 2) & 3u;
    bool srgb = (entry.w & 32u) != 0u;
    vec2 texel = uv * vec2(w, h);
    if ((entry.w & 16u) == 0u) {
        return traced_texel(texels, texel_wrap(int(floor(texel.x)), w, wrap_u),
                            texel_wrap(int(floor(texel.y)), h, wrap_v), w, srgb);
    }
    vec2 p = texel - 0.5;
    vec2 p0 = floor(p);
    vec2 f = p - p0;
    int x0 = texel_wrap(int(p0.x), w, wrap_u);
    int x1 = texel_wrap(int(p0.x) + 1, w, wrap_u);
    int y0 = texel_wrap(int(p0.y), h, wrap_v);
    int y1 = texel_wrap(int(p0.y) + 1, h, wrap_v);
    return mix(mix(traced_texel(texels, x0, y0, w, srgb), traced_texel(texels, x1, y0, w, srgb), f.x),
               mix(traced_texel(texels, x0, y1, w, srgb), traced_texel(texels, x1, y1, w, srgb), f.x), f.y);
}

// Where `material`'s slot `slot` samples at texture coordinates `uvs` (sets 0 and 1):
// its set through its KHR_texture_transform (texture_slots.glsl's rule).
vec2 traced_slot_uv(GpuMaterial material, uint slot, vec4 uvs) {
    vec4 r0 = material.uv_transforms[2u * slot];
    vec4 r1 = material.uv_transforms[2u * slot + 1u];
    vec3 uv = vec3(r0.w != 0.0 ? uvs.zw : uvs.xy, 1.0);
    return vec2(dot(r0.xyz, uv), dot(r1.xyz, uv));
}

// A slot's texture as a hit reads it (material_surface_at.glsl's MATERIAL_TEXTURE).
#define MATERIAL_TEXTURE(sampler, uv, index, slot) traced_texture(index, traced_slot_uv(material, slot, uvs))
#define MATERIAL_SURFACE_FUNCTION material_surface_at
// A hit is shaded at once with its BRDF frame: a direction on isotropic surfaces too.
#define MATERIAL_SURFACE_DIRECTION_ALWAYS
#include "material_surface_at.glsl"

#endif
