#version 460
#extension GL_GOOGLE_include_directive : require
// Per material (invocation z) and table entry (n·v, r) (x, y; vertex-centred): the
// directional albedos the split sum multiplies the prefiltered radiance and the
// irradiance by, with the material's own BRDF (brdf.glsl: full Fresnel with its η + ik
// per channel, outside medium, polarisation weight, TIR; its diffuse model):
//   [0].rgb  ∫ f_conductor cos        (metalness 1)
//   [0].a    ∫ f_dielectric,specular cos
//   [1].x    D1, [1].y D2: ∫ T T f_diffuse(ρ) cos = ρ D1 + ρ² D2 (D2 ≠ 0 only for the
//            full Oren–Nayar model's interreflection term)
//   [1].z    ∫ f_coat cos: a clear coat's own reflection (brdf.glsl's coat, weight 1, the
//            material's coat IOR, r the coat's roughness; 0 for materials without a coat)
//   [1].w    ∫ D V cos: the white lobe (F = 1), what KHR_materials_specular's rescaled
//            Fresnel needs beside [0].a (lighting_terms.glsl)
// Specular parts by sampling GGX's visible normals, diffuse by cosine-weighted
// directions, Hammersley points.
#include "environment_bake.glsl"
#include "diffuse.glsl"
#include "brdf.glsl"

layout(push_constant) uniform EnvironmentAlbedoPush {
    uint samples;  // per part per entry
} push;

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    uint size = ENVIRONMENT_TABLE_SIZE;
    if (id.x >= size || id.y >= size) {
        return;
    }
    GpuMaterial material = materials[id.z];
    // Vertex-centred entries (combustion_optics::environment::table_coordinate).
    float nv = max(float(id.x) / float(size - 1u), TABLE_MU_MIN);
    float r = float(id.y) / float(size - 1u);
    float a = clamp_alpha(alpha_from_perceptual_roughness(r));
    BrdfInputs m;
    m.base_color = vec3(0.0);
    m.metalness = 1.0;
    m.alpha_x = a;
    m.alpha_y = a;
    m.conductor_eta = material.conductor_eta_outside_ior.rgb;
    m.conductor_k = material.conductor_k_polarisation.rgb;
    m.dielectric_eta = material.roughness_anisotropy_ior.w;
    m.outside_eta = material.conductor_eta_outside_ior.a;
    m.polarisation_weight = material.conductor_k_polarisation.a;
    m.diffuse_model = material.diffuse_model_flags.x;
    m.oren_nayar_sigma = oren_nayar_sigma_from_roughness(r);
    vec3 n = vec3(0.0, 0.0, 1.0);
    vec3 t = vec3(1.0, 0.0, 0.0);
    vec3 b = vec3(0.0, 1.0, 0.0);
    vec3 v = vec3(sqrt(max(1.0 - nv * nv, 0.0)), 0.0, nv);
    BrdfInputs md = m;
    md.metalness = 0.0;
    BrdfView conductor = brdf_view(m, n, t, b, v);
    BrdfView dielectric = brdf_view(md, n, t, b, v);
    float g1_v = 1.0 / (1.0 + lambda_ggx(v, a));
    uint samples = push.samples;

    vec3 conductor_sum = vec3(0.0);
    float specular_sum = 0.0;
    float coat_sum = 0.0;
    float white_sum = 0.0;
    CoatInputs coat;
    coat.factor = material.clearcoat.x > 0.0 ? 1.0 : 0.0;
    coat.alpha = a;
    coat.eta = material.clearcoat.z;
    coat.outside_eta = m.outside_eta;
    coat.polarisation_weight = m.polarisation_weight;
    CoatView coat_seen = coat_view(coat, n, v);
    for (uint i = 0u; i < samples; ++i) {
        vec3 h = sample_ggx_vndf(v, a, a, hammersley(i, samples));
        vec3 l = 2.0 * dot(v, h) * h - v;
        if (l.z <= 0.0) {
            continue;
        }
        float pdf = d_ggx(h, a) * g1_v / (4.0 * nv);
        float w = l.z / pdf;
        conductor_sum += brdf_evaluate_view(m, conductor, l) * w;
        specular_sum += brdf_evaluate_view(md, dielectric, l).x * w;
        coat_sum += coat_evaluate_view(coat, coat_seen, l).x * w;
        white_sum += brdf_specular_lobe(dielectric, v, l, h) * w;
    }
    // Compensated (Kahan) sums, so a constant integrand (Lambert behind no interface:
    // f·π = ρ for every direction) comes out within an ulp or two.
    precise float one = 0.0;
    precise float one_error = 0.0;
    precise float half_ = 0.0;
    precise float half_error = 0.0;
    for (uint i = 0u; i < samples; ++i) {
        vec3 l = sample_cosine(hammersley(i, samples));
        if (l.z <= 0.0) {
            continue;
        }
        BrdfInputs lit = md;
        float none = brdf_evaluate_view(md, dielectric, l).x;
        lit.base_color = vec3(1.0);
        precise float term = (brdf_evaluate_view(lit, dielectric, l).x - none) - one_error;
        precise float next = one + term;
        one_error = (next - one) - term;
        one = next;
        lit.base_color = vec3(0.5);
        term = (brdf_evaluate_view(lit, dielectric, l).x - none) - half_error;
        next = half_ + term;
        half_error = (next - half_) - term;
        half_ = next;
    }
    // f·cos/pdf = f·π for cosine-weighted directions.
    one *= PI / float(samples);
    half_ *= PI / float(samples);
    float d2 = 2.0 * (one - 2.0 * half_);
    float d1 = one - d2;
    uint entry = ((id.z * size + id.y) * size + id.x) * 2u;
    environment_albedo[entry] = vec4(conductor_sum, specular_sum) / float(samples);
    environment_albedo[entry + 1u] = vec4(d1, d2, coat_sum / float(samples), white_sum / float(samples));
}
