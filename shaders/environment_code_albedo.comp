#version 460
#extension GL_GOOGLE_include_directive : require
// Conductors derived from the base colour: per stored 8-bit code (invocation z) and
// entry (n·v, r), the directional albedo ∫ D V F cos of the conductor whose η + ik that
// code stands for (conductor_from_code), seen from η_i with polarisation weight w. With
// normals sampled from GGX's visible normals, each sample's weight is F(v·h) G2/G1(v)
// exactly (height-correlated G2 = 1/(1 + Λ(v) + Λ(l))).
#include "environment_bake.glsl"
#include "fresnel.glsl"

layout(push_constant) uniform EnvironmentCodeAlbedoPush {
    uint samples;               // per entry
    uint table;                 // which set of tables (its place in environment_code_albedo)
    float outside_ior;          // η_i
    float polarisation_weight;  // w
} push;

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    uint size = ENVIRONMENT_CODE_TABLE_SIZE;
    if (id.x >= size || id.y >= size) {
        return;
    }
    vec2 eta_k = conductor_from_code[id.z];
    // Vertex-centred entries (combustion_optics::environment::table_coordinate).
    float nv = max(float(id.x) / float(size - 1u), TABLE_MU_MIN);
    float r = float(id.y) / float(size - 1u);
    float a = clamp_alpha(alpha_from_perceptual_roughness(r));
    vec3 v = vec3(sqrt(max(1.0 - nv * nv, 0.0)), 0.0, nv);
    float lambda_v = lambda_ggx(v, a);
    uint samples = push.samples;
    float sum = 0.0;
    for (uint i = 0u; i < samples; ++i) {
        vec3 h = sample_ggx_vndf(v, a, a, hammersley(i, samples));
        float vh = dot(v, h);
        vec3 l = 2.0 * vh * h - v;
        if (l.z <= 0.0) {
            continue;
        }
        float f = polarised_weighted(fresnel_conductor(min(vh, 1.0), push.outside_ior, eta_k.x, eta_k.y), push.polarisation_weight);
        sum += f * (1.0 + lambda_v) / (1.0 + lambda_v + lambda_ggx(l, a));
    }
    uint entry = ((push.table * ENVIRONMENT_CODES + id.z) * size + id.y) * size + id.x;
    environment_code_albedo[entry] = sum / float(samples);
}
