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

// Set 0: the object and material tables (combustion_renderer::bindings::GBUFFER).
#include "bindings/gbuffer.glsl"
// The fragment inputs, set 1 (the material's textures) and the surface they describe.
#include "material_surface.glsl"

layout(location = 0) out vec4 out_base_color_metalness;       // GBufferStorage: sRGB-encoded rgb in RGBA8/16_UNORM, linear in RGBA16F
layout(location = 1) out vec4 out_normal_roughness_anisotropy; // RGBA16_UNORM or RGBA8_UNORM
layout(location = 2) out uvec2 out_material_direction;         // RG16_UINT
#ifdef EMISSIVE_OCCLUSION_TARGET
layout(location = 3) out vec4 out_emissive;  // the HDR image's format (f16/f32): rgb emitted radiance, a occlusion
#endif
#ifdef CLEARCOAT
// RGBA16_UNORM: the coat's octahedral normal (rg), perceptual roughness (b), weight (a);
// the attachment after the emissive target, or in its place.
#ifdef EMISSIVE_OCCLUSION_TARGET
layout(location = 4) out vec4 out_clearcoat;
#else
layout(location = 3) out vec4 out_clearcoat;
#endif
#endif
#ifdef SHEEN
// RGBA16_UNORM: the sheen's linear colour (rgb) and perceptual roughness (a); the
// attachment after the emissive and clear coat targets that the variant has.
#if defined(EMISSIVE_OCCLUSION_TARGET) && defined(CLEARCOAT)
layout(location = 5) out vec4 out_sheen;
#elif defined(EMISSIVE_OCCLUSION_TARGET) || defined(CLEARCOAT)
layout(location = 4) out vec4 out_sheen;
#else
layout(location = 3) out vec4 out_sheen;
#endif
#endif

#ifdef IRIDESCENCE
// RG32F: the thin film's weight (r) and thickness in nm (g); the attachment after the
// emissive, clear coat and sheen targets that the variant has.
#ifdef EMISSIVE_OCCLUSION_TARGET
#define FILM_AFTER_EMISSIVE 1
#else
#define FILM_AFTER_EMISSIVE 0
#endif
#ifdef CLEARCOAT
#define FILM_AFTER_CLEARCOAT 1
#else
#define FILM_AFTER_CLEARCOAT 0
#endif
#ifdef SHEEN
#define FILM_AFTER_SHEEN 1
#else
#define FILM_AFTER_SHEEN 0
#endif
layout(location = 3 + FILM_AFTER_EMISSIVE + FILM_AFTER_CLEARCOAT + FILM_AFTER_SHEEN) out vec2 out_film;
#endif

#ifdef SPECULAR
// RGBA16F: the dielectric's specular colour (rgb) and factor (a); the last attachment.
#ifdef EMISSIVE_OCCLUSION_TARGET
#define SPECULAR_AFTER_EMISSIVE 1
#else
#define SPECULAR_AFTER_EMISSIVE 0
#endif
#ifdef CLEARCOAT
#define SPECULAR_AFTER_CLEARCOAT 1
#else
#define SPECULAR_AFTER_CLEARCOAT 0
#endif
#ifdef SHEEN
#define SPECULAR_AFTER_SHEEN 1
#else
#define SPECULAR_AFTER_SHEEN 0
#endif
#ifdef IRIDESCENCE
#define SPECULAR_AFTER_FILM 1
#else
#define SPECULAR_AFTER_FILM 0
#endif
layout(location = 3 + SPECULAR_AFTER_EMISSIVE + SPECULAR_AFTER_CLEARCOAT + SPECULAR_AFTER_SHEEN
                  + SPECULAR_AFTER_FILM) out vec4 out_specular;
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
    vec2 uv = SURFACE_UV;
#endif
    out_base_color_metalness = vec4(
        clamp(in_world_position + in_normal + in_tangent.xyz + vec3(uv, in_tangent.w), 0.0, 1.0),
        0.0);
    out_normal_roughness_anisotropy = vec4(0.5, 0.5, 0.5, 0.0);
    out_material_direction = uvec2(in_material, 0u);
#ifdef EMISSIVE_OCCLUSION_TARGET
    out_emissive = vec4(0.0);
#endif
#ifdef CLEARCOAT
    out_clearcoat = vec4(0.0);
#endif
#ifdef SHEEN
    out_sheen = vec4(0.0);
#endif
#ifdef IRIDESCENCE
    out_film = vec2(0.0);
#endif
#ifdef SPECULAR
    out_specular = vec4(1.0);
#endif
    return;
#endif
    GpuMaterial material = materials[in_material];
#ifdef ALPHA_MASK
    // Cut-out materials (their own pipeline): the test is made here, the discard at the
    // end, so every implicit derivative below is taken with the whole quad alive.
    bool cut_away = alpha_cut_away(material, base_color_texture, UV_BASE_COLOR, vertex_alpha());
#endif
    MaterialSurface s = material_surface(material);
#ifdef BASE_COLOR_LINEAR
    out_base_color_metalness = vec4(clamp(s.base_color, 0.0, 1.0), s.metalness);  // RGBA16F
#else
    out_base_color_metalness = vec4(srgb_encode(s.base_color), s.metalness);
#endif
    out_normal_roughness_anisotropy = vec4(octahedral_encode(s.normal), s.roughness, s.anisotropy);
    // The direction's angle only where the surface is anisotropic (an isotropic pixel's
    // direction is any in its plane: code 0, the decoder's reference tangent).
    uint direction_code = 0u;
    if (s.anisotropy != 0.0) {
        direction_code = anisotropy_direction_encode(stored_normal(s.normal), s.direction);
    }
    out_material_direction = uvec2(in_material, direction_code);
#ifdef EMISSIVE_OCCLUSION_TARGET
    out_emissive = vec4(s.emissive, s.occlusion);
#endif
#ifdef CLEARCOAT
    out_clearcoat = vec4(octahedral_encode(s.clearcoat_normal), s.clearcoat_roughness, s.clearcoat);
#endif
#ifdef SHEEN
    out_sheen = vec4(clamp(s.sheen_color, 0.0, 1.0), s.sheen_roughness);
#endif
#ifdef IRIDESCENCE
    out_film = vec2(s.film_weight, s.film_thickness_nm);
#endif
#ifdef SPECULAR
    // f16 holds 1 exactly (a pixel without the extension stays the plain dielectric) and
    // colours up to 65504; a colour beyond 1/F₀ saturates F₀′ at 1 anyway.
    out_specular = vec4(clamp(s.specular_color, 0.0, 65504.0), clamp(s.specular_factor, 0.0, 1.0));
#endif
#ifdef ALPHA_MASK
    if (cut_away) {
        discard;
    }
#endif
}
