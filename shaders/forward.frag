#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Forward pass, fragment stage (vertex stage: gbuffer.vert): the blended objects
// (glTF alphaMode BLEND), drawn after the deferred lighting, back to front, each
// fragment shaded at once from its own surface with the lighting pass's terms (the same
// lights, shadows, environment and BRDF: lighting_terms.glsl) and blended "over" the
// HDR image with its alpha (straight alpha: rgb · α + behind · (1 − α)). Specialised as
// the lighting pass is (combustion_renderer::LightingFeatures).
#include "gpu_types.glsl"
#include "srgb.glsl"
#include "brdf.glsl"

#include "bindings/forward.glsl"  // set 0: see combustion_renderer::bindings::FORWARD
#include "bindings/constants.glsl"
#include "material_surface.glsl"  // the fragment inputs and set 1, the material's textures

layout(push_constant) uniform ForwardPush {
    mat4 view_projection;  // read by gbuffer.vert
    uint object_index;     // read by gbuffer.vert
    uint light_count;
    vec4 camera_position;
} push;

#ifdef SHADOWS
#include "shadows.glsl"
#endif
#include "lighting_terms.glsl"

layout(location = 0) out vec4 out_radiance;

void main() {
    GpuMaterial material = materials[in_material];
    MaterialSurface s = material_surface(material);
    float alpha = clamp(s.alpha, 0.0, 1.0);
#ifndef NO_UNLIT
    // KHR_materials_unlit: the base colour is the radiance; nothing lights it.
    if ((material.diffuse_model_flags.y & MATERIAL_FLAG_UNLIT) != 0u) {
        out_radiance = vec4(s.base_color, alpha);
        return;
    }
#endif
    vec3 position = in_world_position;
    vec3 v = normalize(push.camera_position.xyz - position);
    vec3 base_color = clamp(s.base_color, 0.0, 1.0);
    BrdfInputs m = brdf_inputs(material, base_color, s.metalness, s.roughness, s.anisotropy,
                               round(srgb_encode(base_color) * 255.0));
    vec3 n = s.normal;
    vec3 t = s.direction;
    BrdfView view = brdf_view(m, n, t, cross(n, t), v);
    vec3 radiance = s.emissive;
    for (uint i = 0u; i < push.light_count; ++i) {
        radiance += light_radiance(m, view, lights[i], position, n, push.camera_position.xyz,
                                   gl_FragCoord.xy);
    }
#ifdef ENVIRONMENT
    radiance += environment_radiance(material, in_material, m, view, view.frame[2], v, s.roughness,
                                     round(srgb_encode(base_color) * 255.0), s.occlusion);
#endif
    out_radiance = vec4(radiance, alpha);
}
