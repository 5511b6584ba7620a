#version 460
#extension GL_GOOGLE_include_directive : require
// One level of the GGX-prefiltered specular cube (the split sum's first factor, Karis
// 2013): for each texel direction n = v = r, the (n·l)-weighted mean of the radiance
// over directions l reflected about GGX normals sampled with n = v, each read from the
// radiance cube's mip whose texel solid angle matches the sample's (filtered importance
// sampling, Křivánek & Colbert 2008), so few samples give no fireflies.
#include "environment_bake.glsl"

layout(push_constant) uniform EnvironmentPrefilterPush {
    uint size;           // the level's texels per side
    uint samples;        // GGX samples per texel
    uint radiance_size;  // texels per side of the radiance cube's level 0
    float roughness;     // perceptual roughness r of the level (0: a copy of level 0)
} push;

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    uint size = push.size;
    if (id.x >= size || id.y >= size) {
        return;
    }
    vec3 n = cube_texel_direction(id.z, id.xy, size);
    float r = push.roughness;
    if (r <= 0.0) {
        imageStore(environment_target, ivec3(id), vec4(textureLod(environment_source, n, 0.0).rgb, 1.0));
        return;
    }
    float a = clamp_alpha(alpha_from_perceptual_roughness(r));
    // A frame about n (Duff et al. 2017).
    float sgn = n.z >= 0.0 ? 1.0 : -1.0;
    float q = -1.0 / (sgn + n.z);
    float bxy = n.x * n.y * q;
    vec3 t = vec3(1.0 + sgn * n.x * n.x * q, sgn * bxy, -sgn * n.x);
    vec3 b = vec3(bxy, sgn + n.y * n.y * q, -n.y);
    uint samples = push.samples;
    float base = float(push.radiance_size);
    float texel_solid_angle = 4.0 * PI / (6.0 * base * base);
    float top = float(textureQueryLevels(environment_source) - 1);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (uint i = 0u; i < samples; ++i) {
        vec3 h = sample_ggx_vndf(vec3(0.0, 0.0, 1.0), a, a, hammersley(i, samples));
        vec3 l = 2.0 * h.z * h - vec3(0.0, 0.0, 1.0);
        if (l.z <= 0.0) {
            continue;
        }
        // Density of l with v = n: D(h) G1(n) / 4 = D(h) / 4.
        float pdf = d_ggx(h, a) * 0.25;
        float sample_solid_angle = 1.0 / (float(samples) * pdf);
        float lod = clamp(0.5 * log2(sample_solid_angle / texel_solid_angle) + 1.0, 0.0, top);
        vec3 world = t * l.x + b * l.y + n * l.z;
        sum += textureLod(environment_source, world, lod).rgb * l.z;
        weight += l.z;
    }
    imageStore(environment_target, ivec3(id), vec4(sum / max(weight, 1e-30), 1.0));
}
