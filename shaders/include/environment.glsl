// Environment lighting: the analytic source radiance (combustion_scene::Environment,
// whose f64 definition this mirrors), cube-map directions, sampling of the GGX
// distribution of visible normals (Rust: combustion_optics::environment), and the
// table layout the bake writes and the lighting pass reads.
#ifndef COMBUSTION_ENVIRONMENT_GLSL
#define COMBUSTION_ENVIRONMENT_GLSL

#include "constants.glsl"
#include "microfacet.glsl"

// Directional-albedo tables: ENVIRONMENT_TABLE_SIZE² entries over (n·v, perceptual
// roughness r), vertex-centred (entry i at i/(size − 1), μ at least TABLE_MU_MIN), clamped at the edges; per
// material 2 vec4 per entry. Conductors derived from the base colour: one scalar table
// per stored 8-bit code, ENVIRONMENT_CODE_TABLE_SIZE² entries.
// (combustion_renderer::environment::{TABLE_SIZE, CODE_TABLE_SIZE}, generated:)
#include "bindings/constants.glsl"

// The source as push constants (combustion_renderer::gpu_types::EnvironmentSource):
// L(ω) = ground + (sky − ground)(1 + ω_y)/2 + Σ_i B_i max(0, ω·k_i)^p_i.
struct EnvironmentSource {
    vec4 sky;
    vec4 ground;
    vec4 box_direction[2];          // xyz: unit k_i
    vec4 box_radiance_exponent[2];  // rgb: B_i, a: p_i
};

vec3 environment_source_radiance(EnvironmentSource s, vec3 d) {
    vec3 l = s.ground.rgb + (s.sky.rgb - s.ground.rgb) * (0.5 * (1.0 + d.y));
    for (int i = 0; i < 2; ++i) {
        float c = dot(d, s.box_direction[i].xyz);
        if (c > 0.0) {
            l += s.box_radiance_exponent[i].rgb * pow(c, s.box_radiance_exponent[i].a);
        }
    }
    return l;
}

// The unit direction through face coordinates `uv` (−1 … 1) of face `face` (+X, −X,
// +Y, −Y, +Z, −Z) of a cube map (Vulkan's cube-map face selection, inverted).
vec3 cube_face_direction(uint face, vec2 uv) {
    vec3 d;
    switch (face) {
        case 0u: d = vec3(1.0, -uv.y, -uv.x); break;
        case 1u: d = vec3(-1.0, -uv.y, uv.x); break;
        case 2u: d = vec3(uv.x, 1.0, uv.y); break;
        case 3u: d = vec3(uv.x, -1.0, -uv.y); break;
        case 4u: d = vec3(uv.x, -uv.y, 1.0); break;
        default: d = vec3(-uv.x, -uv.y, -1.0); break;
    }
    return normalize(d);
}

// The unit direction through the centre of texel `texel` of face `face` of a cube level
// `size` texels across.
vec3 cube_texel_direction(uint face, uvec2 texel, uint size) {
    return cube_face_direction(face, (vec2(texel) + 0.5) / float(size) * 2.0 - 1.0);
}

// (u, v) of a unit direction on an equirectangular image, row 0 at +y, the centre column
// along −z (combustion_scene::equirect_coordinates).
vec2 equirect_coordinates(vec3 d) {
    return vec2(0.5 + atan(d.x, -d.z) * (0.5 * INV_PI), acos(clamp(d.y, -1.0, 1.0)) * INV_PI);
}

// Solid angle of the texel of a cube face spanning [x0, x1] × [y0, y1] in face
// coordinates (−1 … 1): exact, from the area element's antiderivative atan(xy/√(x²+y²+1)).
float cube_area_element(float x, float y) {
    return atan(x * y, sqrt(x * x + y * y + 1.0));
}

float cube_texel_solid_angle(uvec2 texel, uint size) {
    float s = 2.0 / float(size);
    float x0 = float(texel.x) * s - 1.0;
    float y0 = float(texel.y) * s - 1.0;
    float x1 = x0 + s;
    float y1 = y0 + s;
    return cube_area_element(x0, y0) - cube_area_element(x0, y1) - cube_area_element(x1, y0)
         + cube_area_element(x1, y1);
}

// Point i of n of the Hammersley set: (i/n, radical inverse of i in base 2).
vec2 hammersley(uint i, uint n) {
    return vec2(float(i) / float(n), float(bitfieldReverse(i)) * 2.3283064365386963e-10);
}

// A microfacet normal from GGX's distribution of normals visible from v (local frame,
// v.z > 0) (Heitz 2018; Rust: combustion_optics::environment::sample_ggx_vndf).
vec3 sample_ggx_vndf(vec3 v, float ax, float ay, vec2 u) {
    vec3 vh = normalize(vec3(ax * v.x, ay * v.y, v.z));
    float len2 = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = len2 > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(len2) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u.x);
    float phi = 2.0 * PI * u.y;
    float p1 = r * cos(phi);
    float s = 0.5 * (1.0 + vh.z);
    float p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    float p3 = sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    vec3 nh = t1 * p1 + t2 * p2 + vh * p3;
    return normalize(vec3(ax * nh.x, ay * nh.y, max(nh.z, 0.0)));
}

// A cosine-weighted direction about z (density z/π).
vec3 sample_cosine(vec2 u) {
    float r = sqrt(u.x);
    float phi = 2.0 * PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(1.0 - u.x, 0.0)));
}

#endif  // COMBUSTION_ENVIRONMENT_GLSL
