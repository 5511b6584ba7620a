// CPU/GPU shared structures. Mirrored by crates/renderer/src/gpu_types.rs, whose
// compile-time size assertions keep the two in step; change both together.
#ifndef COMBUSTION_GPU_TYPES_GLSL
#define COMBUSTION_GPU_TYPES_GLSL

// MATERIAL_FLAG_* and LIGHT_KIND_*: generated from gpu_types.rs's constants.
#include "bindings/constants.glsl"

// One entry of the material table (std430, 912 bytes).
struct GpuMaterial {
    vec4 base_color_metalness;      // rgb: linear base colour, a: metalness
    vec4 roughness_anisotropy_ior;  // x: perceptual roughness, y: anisotropy strength,
                                    // z: anisotropy rotation (rad), w: dielectric IOR
    vec4 conductor_eta_outside_ior; // rgb: conductor η, a: outside-medium IOR ηi (resolved)
    vec4 conductor_k_polarisation;  // rgb: conductor k, a: polarisation weight
    uvec4 diffuse_model_flags;      // x: diffuse model (DIFFUSE_MODEL_*), y: MATERIAL_FLAG_*,
                                    // z: occlusion strength (f32 bits), w: unused
    ivec4 textures_base_mr_normal_occlusion;     // texture-array indices, -1: none
    ivec4 textures_emissive_anisotropy_specular; // specular: read by SPECULAR
    ivec4 textures_transmission_thickness;       // transmission, thickness, -1, -1
    vec4 emissive_normal_scale;     // rgb: emitted radiance factor × strength, a: normal scale
    // Per texture slot s (TextureSlot::ALL order, 17 slots): [2s] = (a, b, c, set), [2s + 1] =
    // (d, e, f, 0): samples at (a u + b v + c, d u + e v + f) of set 0 or 1
    // (KHR_texture_transform). Read only by the TEXTURE_TRANSFORMS G-buffer variant.
    vec4 uv_transforms[34];
    vec4 alpha_cutoff;              // x: base colour factor's alpha, y: alphaCutoff of a cut-out
                                    // (MASK) material, z: 1 where the base colour sampler picks
                                    // the nearest mip level; read by the ALPHA_MASK pipelines
    vec4 alpha_mip_scales[4];       // per base colour mip level ([level / 4][level % 4]): the
                                    // alpha scale that keeps the cut-out's coverage
    vec4 transmission_thickness;    // x: transmission factor (0: opaque), y: volume thickness in
                                    // the mesh's units (0: thin-walled); read by TRANSMISSION
    vec4 absorption;                // rgb: the volume's absorption coefficient σ (1/m)
    vec4 clearcoat;                 // x: the coat's weight (0: none), y: its perceptual roughness,
                                    // z: its IOR, w: its normal map's scale; read by CLEARCOAT
    ivec4 textures_clearcoat;       // clearcoat, clearcoat roughness, clearcoat normal, -1
    vec4 sheen;                     // rgb: the sheen's linear colour (black: none), a: its
                                    // perceptual roughness; read by SHEEN
    ivec4 textures_sheen;           // sheen colour, sheen roughness, -1, -1
    vec4 film;                      // x: the thin film's weight (0: none), y: its IOR, z, w: its
                                    // thickness in nm at the thickness texture's 0 and 1 (IRIDESCENCE)
    ivec4 textures_film;            // iridescence, iridescence thickness, -1, -1
    vec4 specular;                  // rgb: KHR_materials_specular's colour factor (linear, may
                                    // exceed 1), a: its factor; (1, 1, 1, 1): none (SPECULAR)
};

// One placed mesh (std430, 144 bytes).
struct GpuObject {
    mat4 model;
    mat4 normal_matrix;             // inverse transpose of model (upper 3x3 used)
    uvec4 material_index;           // x: index into the material table, y: 1 if the mesh has
                                    // vertex colours (stream 2)
};

// One light (std430, 64 bytes).
struct GpuLight {
    vec4 position_or_direction;     // point, spot: world position; directional: unit direction of travel
    vec4 power_kind;                // rgb: point/spot intensity (W/sr) or directional irradiance (W/m²);
                                    // a: LIGHT_KIND_*
    vec4 spot_axis;                 // spot: xyz = unit direction of travel along the cone axis;
                                    // w: size for soft shadows: radius (m; point, spot) or
                                    // tan(angular diameter / 2) (directional); 0: none
    vec4 spot_cone;                 // spot: x = 1 / max(1e-3, cos(inner) − cos(outer)),
                                    //       y = −cos(outer) · x   (KHR_lights_punctual falloff)
                                    // point, spot: z = 1/range² (0: no range, no window)
                                    // w: 1 + its first shadow cascade's index (0: no shadow)
};

// One shadow-map layer: a cascade of a directional light (std430, 96 bytes).
struct GpuShadowCascade {
    mat4 world_to_clip;             // world → map clip space: xy in [−1, 1], depth in [0, 1]
    vec4 texel_depth_slice;         // x: texel side (m); y: metres along the light per unit
                                    // depth; z: the end of its view slice (m from the eye)
    vec4 view_forward;              // xyz: the camera's unit view direction (cascades; zero
                                    // for local lights); w: its layer in its array of maps
};

// The range window (max(0, 1 − (d²/r²)²))² at squared distance d2; 1 without range
// (combustion_scene::range_window; CPU mirror GpuLight::range_attenuation).
float range_attenuation(GpuLight light, float d2) {
    float inverse_r2 = light.spot_cone.z;
    if (inverse_r2 == 0.0) {
        return 1.0;
    }
    float x2 = d2 * inverse_r2;
    float w = max(1.0 - x2 * x2, 0.0);
    return w * w;
}

// Angular falloff of a spot light for unit direction l from the surface to the light.
float spot_attenuation(GpuLight light, vec3 l) {
    float cos_axis = dot(light.spot_axis.xyz, -l);
    float a = clamp(cos_axis * light.spot_cone.x + light.spot_cone.y, 0.0, 1.0);
    return a * a;
}

#endif
