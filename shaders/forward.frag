#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Forward pass, fragment stage (vertex stage: gbuffer.vert): the blended objects
// (glTF alphaMode BLEND) and the transmissive ones (KHR_materials_transmission, in the
// TRANSMISSION variant), drawn after the deferred lighting, back to front, each
// fragment shaded at once from its own surface with the lighting pass's terms (the same
// lights, shadows, environment and BRDF: lighting_terms.glsl) and blended "over" the
// HDR image with its alpha (straight alpha: rgb · α + behind · (1 − α)). Specialised as
// the lighting pass is (combustion_renderer::LightingFeatures). docs/gltf.md,
// "Transmission", states what the screen-space transmission can and cannot do.
#include "gpu_types.glsl"
#include "srgb.glsl"
#include "brdf.glsl"

#include "bindings/forward.glsl"  // set 0: see combustion_renderer::bindings::FORWARD
#include "bindings/constants.glsl"
#include "material_surface.glsl"  // the fragment inputs and set 1, the material's textures

layout(push_constant) uniform ForwardPush {
    mat4 view_projection;  // read by gbuffer.vert (and here, to find what is behind)
    uint object_index;     // read by gbuffer.vert
    uint light_count;
    float object_scale;    // the object's scale: a volume's thickness in metres per mesh unit
    vec4 camera_position;
} push;

#ifdef SHADOWS
#include "shadows.glsl"
#endif
#include "lighting_terms.glsl"

layout(location = 0) out vec4 out_radiance;

#ifdef TRANSMISSION
// The smallest cosine between the view and the normal the light enters by.
const float TRANSMISSION_MIN_COS = 1e-4;

// The radiance that passes through a transmissive surface towards the eye: what lies
// behind it (the lit image before this pass, `behind`, or the environment where the
// lookup leaves the screen), through its two interfaces and its volume.
// - Entry: the exact dielectric transmittance T = 1 − R per polarisation at the view
//   angle, from the outside medium η_i into the material's η_t (0 past the critical
//   angle when η_i > η_t); refraction by Snell's law, η_i/η_t.
// - With a volume: the path runs `thickness` (× the object's scale) along the refracted
//   ray; the exit face is taken parallel to the entry face (a slab), so the light leaves
//   at the angle it entered, through the same transmittance (reciprocity), along the
//   view ray, and the lookup is the exit point's pixel. Beer–Lambert absorption e^(−σd)
//   on the way, and the slab's internal reflections summed: T² a / (1 − R² a²) per
//   polarisation and channel.
// - Thin-walled (no volume): the same slab with no thickness, a = 1: (1 − R)/(1 + R).
// - Rough surfaces read a coarser level of `behind`: log2(size) · r · clamp(2η_t/η_i − 2,
//   0, 1) (the glTF sample viewer's rule), not the rough interfaces' true spread.
vec3 transmitted_radiance(GpuMaterial material, BrdfInputs m, vec3 n, vec3 v, vec3 position,
                          float roughness, float thickness) {
    float eta_i = m.outside_eta;
    float eta_t = m.dielectric_eta;
    // An interpolated normal may face away from the eye near a silhouette (the face
    // itself faces it): bent towards the eye until it faces it, so that the light still
    // enters (and Snell's law, which assumes so, holds).
    float cos_v = dot(n, v);
    if (!(cos_v > TRANSMISSION_MIN_COS)) {
        n = normalize(n + (TRANSMISSION_MIN_COS - cos_v) * v);
        cos_v = clamp(dot(n, v), 0.0, 1.0);
    }
    vec2 t = fresnel_dielectric_transmittance(cos_v, eta_i, eta_t);
    vec2 r = vec2(1.0) - t;
    vec3 exit_point = position;
    vec3 absorbed = vec3(1.0);
    if (thickness > 0.0) {
        vec3 refracted = refract(-v, n, eta_i / eta_t);
        if (dot(refracted, refracted) == 0.0) {
            return vec3(0.0);  // totally reflected at the entry (η_i > η_t)
        }
        exit_point = position + refracted * thickness;
        absorbed = exp(-material.absorption.rgb * thickness);
    }
    float w = m.polarisation_weight;
    vec3 slab = vec3(0.0);
    for (int c = 0; c < 3; ++c) {
        float a = absorbed[c];
        vec2 through = t * t * a / max(vec2(1.0) - r * r * a * a, vec2(1e-30));
        slab[c] = (1.0 - w) * through.x + w * through.y;
    }
    vec4 clip = push.view_projection * vec4(exit_point, 1.0);
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    float size = float(max(textureSize(behind, 0).x, textureSize(behind, 0).y));
    float lod = log2(size) * roughness * clamp(2.0 * eta_t / eta_i - 2.0, 0.0, 1.0);
    vec3 seen;
    bool on_screen = clip.w > 0.0 && all(greaterThanEqual(uv, vec2(0.0)))
                  && all(lessThanEqual(uv, vec2(1.0)));
#ifdef ENVIRONMENT
    if (!on_screen) {
        float levels = float(textureQueryLevels(environment_specular) - 1);
        seen = textureLod(environment_specular, -v, clamp(roughness, 0.0, 1.0) * levels).rgb;
    } else
#endif
    {
        seen = textureLod(behind, clamp(uv, vec2(0.0), vec2(1.0)), lod).rgb;
    }
    return slab * seen;
}
#endif

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
    vec3 base_color_code = round(srgb_encode(base_color) * 255.0);
#ifdef TRANSMISSION
    // KHR_materials_transmission: of what the dielectric part lets through its surface,
    // the share `transmission` passes on through the object instead of scattering
    // diffusely: the diffuse lobe (and its environment term) keeps 1 − transmission.
    // The transmission factor × its texture's R; the thickness factor × its texture's G,
    // in metres through the object's scale.
    float transmission = material.transmission_thickness.x;
    if (material.textures_transmission_thickness.x >= 0) {
        transmission *= texture(transmission_texture, UV_TRANSMISSION).r;
    }
    float thickness = material.transmission_thickness.y * push.object_scale;
    if (material.textures_transmission_thickness.y >= 0) {
        thickness *= texture(thickness_texture, UV_THICKNESS).g;
    }
    BrdfInputs m = brdf_inputs(material, base_color * (1.0 - transmission), s.metalness,
                               s.roughness, s.anisotropy, base_color_code);
#else
    BrdfInputs m = brdf_inputs(material, base_color, s.metalness, s.roughness, s.anisotropy,
                               base_color_code);
#endif
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
                                     base_color_code, s.occlusion);
#endif
#ifdef TRANSMISSION
    if (transmission > 0.0) {
        radiance += (1.0 - s.metalness) * transmission * base_color
                  * transmitted_radiance(material, m, n, v, position, s.roughness, thickness);
    }
#endif
    out_radiance = vec4(radiance, alpha);
}
