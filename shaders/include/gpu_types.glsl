// CPU/GPU shared structures. Mirrored by crates/renderer/src/gpu_types.rs, whose
// compile-time size assertions keep the two in step; change both together.
#ifndef COMBUSTION_GPU_TYPES_GLSL
#define COMBUSTION_GPU_TYPES_GLSL

// One entry of the material table (std430, 80 bytes).
struct GpuMaterial {
    vec4 base_color_metalness;      // rgb: linear base colour, a: metalness
    vec4 roughness_anisotropy_ior;  // x: perceptual roughness, y: anisotropy strength,
                                    // z: anisotropy rotation (rad), w: dielectric IOR
    vec4 conductor_eta_outside_ior; // rgb: conductor η, a: outside-medium IOR ηi (resolved)
    vec4 conductor_k_polarisation;  // rgb: conductor k, a: polarisation weight
    uvec4 diffuse_model_flags;      // x: diffuse model (DIFFUSE_MODEL_*), yzw: reserved (0)
};

// One placed mesh (std430, 144 bytes).
struct GpuObject {
    mat4 model;
    mat4 normal_matrix;             // inverse transpose of model (upper 3x3 used)
    uvec4 material_index;           // x: index into the material table
};

// One light (std430, 32 bytes).
#define LIGHT_KIND_DIRECTIONAL 0u
#define LIGHT_KIND_POINT 1u
struct GpuLight {
    vec4 position_or_direction;     // point: world position; directional: unit direction of travel
    vec4 power_kind;                // rgb: point intensity (W/sr) or directional irradiance (W/m²);
                                    // a: LIGHT_KIND_* as a float
};

#endif
