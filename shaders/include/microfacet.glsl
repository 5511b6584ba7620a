// Microfacet distributions, Smith masking–shadowing, Cook–Torrance G, roughness
// conventions. GLSL mirror of crates/optics/src/microfacet.rs: same names, same
// arrangements (see the Rust doc comments for the derivations and citations).
//
// Every direction is a unit vector in the shading frame (z = normal, x = tangent,
// y = bitangent): n·m = m.z and sin²θ = |n × m|² = m.x² + m.y², never 1 − (n·m)².
// Every α is clamped to [ALPHA_MIN, 1]; cosines are raised to COS_MIN before division.
#ifndef COMBUSTION_MICROFACET_GLSL
#define COMBUSTION_MICROFACET_GLSL

#include "constants.glsl"

float clamp_alpha(float alpha) {
    return min(max(alpha, ALPHA_MIN), 1.0);
}

// α = max(r², ALPHA_MIN) from perceptual roughness r ∈ [0, 1] (glTF convention); the one
// place roughness is squared.
float alpha_from_perceptual_roughness(float r) {
    float rc = min(max(r, 0.0), 1.0);
    return max(rc * rc, ALPHA_MIN);
}

// (α_t, α_b) = (mix(α, 1, s²), α), KHR_materials_anisotropy; x = tangent, y = bitangent.
vec2 anisotropic_alphas(float alpha, float strength) {
    float a = clamp_alpha(alpha);
    float s = min(max(strength, 0.0), 1.0);
    return vec2(a + (1.0 - a) * s * s, a);
}

// GGX D, isotropic (Walter et al. 2007, eq. 33): 1/(π α² (sin²θ/α² + cos²θ)²).
float d_ggx(vec3 m, float alpha) {
    float c = m.z;
    if (!(c > 0.0)) {
        return 0.0;
    }
    float a = clamp_alpha(alpha);
    float a2 = a * a;
    float s2 = m.x * m.x + m.y * m.y;
    float t = s2 / a2 + c * c;
    return 1.0 / (PI * a2 * t * t);
}

// GGX D, anisotropic (Burley 2012, appendix B.2).
float d_ggx_anisotropic(vec3 m, float alpha_x, float alpha_y) {
    float c = m.z;
    if (!(c > 0.0)) {
        return 0.0;
    }
    float ax = clamp_alpha(alpha_x);
    float ay = clamp_alpha(alpha_y);
    float tx = m.x / ax;
    float ty = m.y / ay;
    float t = tx * tx + ty * ty + c * c;
    return 1.0 / (PI * ax * ay * t * t);
}

// Beckmann D, normalised (Beckmann & Spizzichino 1963; Walter et al. 2007, eq. 25).
float d_beckmann(vec3 m, float alpha) {
    float c = m.z;
    if (!(c > 0.0)) {
        return 0.0;
    }
    float a = clamp_alpha(alpha);
    float a2 = a * a;
    float c2 = c * c;
    float s2 = m.x * m.x + m.y * m.y;
    float e = exp(-(s2 / a2) / c2);
    if (!(e > 0.0)) {
        return 0.0;
    }
    return e / (PI * a2 * c2 * c2);
}

// Beckmann D, anisotropic (comparison variant D_BECKMANN; Rust: d_beckmann_anisotropic).
float d_beckmann_anisotropic(vec3 m, float alpha_x, float alpha_y) {
    float c = m.z;
    if (!(c > 0.0)) {
        return 0.0;
    }
    float ax = clamp_alpha(alpha_x);
    float ay = clamp_alpha(alpha_y);
    float c2 = c * c;
    float tx = m.x / ax;
    float ty = m.y / ay;
    float e = exp(-(tx * tx + ty * ty) / c2);
    if (!(e > 0.0)) {
        return 0.0;
    }
    return e / (PI * ax * ay * c2 * c2);
}

// (α_x v.x)² + (α_y v.y)², the α² sin²θ of the anisotropic Smith Λ (Heitz 2014, §5.3).
float alpha2_sin2(vec3 v, float ax, float ay) {
    float x = ax * v.x;
    float y = ay * v.y;
    return x * x + y * y;
}

// Λ = α² sin²θ / (2c (√(c² + α² sin²θ) + c)): no tangent, no cancellation.
float lambda_from_cos(float c, float a2s2) {
    if (!(c > 0.0)) {
        return FLT_MAX;
    }
    if (!(a2s2 > 0.0)) {
        return 0.0;
    }
    float s = sqrt(c * c + a2s2);
    return min(a2s2 / (2.0 * c * (s + c)), FLT_MAX);
}

// Smith Λ for Beckmann, anisotropic, Walter et al. 2007's rational form (comparison
// variant D_BECKMANN; Rust: lambda_beckmann_anisotropic). FLT_MAX for v.z ≤ 0.
float lambda_beckmann_anisotropic(vec3 v, float alpha_x, float alpha_y) {
    float c = v.z;
    if (!(c > 0.0)) {
        return FLT_MAX;
    }
    float a2s2 = alpha2_sin2(v, clamp_alpha(alpha_x), clamp_alpha(alpha_y));
    if (c * c >= 2.56 * a2s2) {
        return 0.0;
    }
    float a = c / sqrt(a2s2);
    return (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a);
}

// G₁ = 2c/(c + √(c² + α² sin²θ)).
float g1_from_cos(float c, float a2s2) {
    if (!(c > 0.0)) {
        return 0.0;
    }
    float s = sqrt(c * c + a2s2);
    return 2.0 * c / (c + s);
}

// Smith Λ for GGX, isotropic (Heitz 2014, §5.3). FLT_MAX for v.z ≤ 0.
float lambda_ggx(vec3 v, float alpha) {
    float a = clamp_alpha(alpha);
    return lambda_from_cos(v.z, a * a * (v.x * v.x + v.y * v.y));
}

// Smith Λ for GGX, anisotropic (Heitz 2014, §5.3).
float lambda_ggx_anisotropic(vec3 v, float alpha_x, float alpha_y) {
    return lambda_from_cos(v.z, alpha2_sin2(v, clamp_alpha(alpha_x), clamp_alpha(alpha_y)));
}

// Smith G₁ for GGX with χ⁺((v·m)/(v·n)), isotropic (Walter et al. 2007, eq. 34).
float g1_smith_ggx(vec3 v, vec3 m, float alpha) {
    if (!(dot(v, m) > 0.0)) {
        return 0.0;
    }
    float a = clamp_alpha(alpha);
    return g1_from_cos(v.z, a * a * (v.x * v.x + v.y * v.y));
}

// Smith G₁ for GGX, anisotropic (Heitz 2014, §5.3).
float g1_smith_ggx_anisotropic(vec3 v, vec3 m, float alpha_x, float alpha_y) {
    if (!(dot(v, m) > 0.0)) {
        return 0.0;
    }
    return g1_from_cos(v.z, alpha2_sin2(v, clamp_alpha(alpha_x), clamp_alpha(alpha_y)));
}

// Separable Smith G₂ = G₁(v) G₁(l) (Heitz 2014, §6.1).
float g2_smith_ggx_separable(vec3 v, vec3 l, vec3 m, float alpha) {
    return g1_smith_ggx(v, m, alpha) * g1_smith_ggx(l, m, alpha);
}

float g2_smith_ggx_separable_anisotropic(vec3 v, vec3 l, vec3 m, float alpha_x, float alpha_y) {
    return g1_smith_ggx_anisotropic(v, m, alpha_x, alpha_y)
         * g1_smith_ggx_anisotropic(l, m, alpha_x, alpha_y);
}

// Height-correlated Smith G₂ = 2 c_v c_l / (c_l S_v + c_v S_l), anisotropic (Heitz 2014, §6.2).
float g2_smith_ggx_height_correlated_anisotropic(vec3 v, vec3 l, vec3 m, float alpha_x, float alpha_y) {
    if (!(v.z > 0.0 && l.z > 0.0 && dot(v, m) > 0.0 && dot(l, m) > 0.0)) {
        return 0.0;
    }
    float ax = clamp_alpha(alpha_x);
    float ay = clamp_alpha(alpha_y);
    float cv = v.z;
    float cl = l.z;
    float sv = sqrt(cv * cv + alpha2_sin2(v, ax, ay));
    float sl = sqrt(cl * cl + alpha2_sin2(l, ax, ay));
    return 2.0 * cv * cl / (cl * sv + cv * sl);
}

float g2_smith_ggx_height_correlated(vec3 v, vec3 l, vec3 m, float alpha) {
    float a = clamp_alpha(alpha);
    return g2_smith_ggx_height_correlated_anisotropic(v, l, m, a, a);
}

// One direction's half of the height-correlated visibility: (c, S) with
// c = max(w·n, COS_MIN), S = √(c² + αx² wx² + αy² wy²); V = ½ / (c_l S_v + c_v S_l).
// α already clamped. Lets the lighting pass compute the view's half once per pixel.
vec2 smith_ggx_visibility_half(vec3 w, float ax, float ay) {
    float c = max(w.z, COS_MIN);
    return vec2(c, sqrt(c * c + alpha2_sin2(w, ax, ay)));
}

// V = G₂/(4 n·v n·l) = 1/(2 (c_l S_v + c_v S_l)) for the height-correlated anisotropic
// Smith G₂ (Heitz 2014, §6.2); cosines raised to COS_MIN.
float visibility_smith_ggx_height_correlated_anisotropic(vec3 v, vec3 l, float alpha_x, float alpha_y) {
    if (!(v.z > 0.0 && l.z > 0.0)) {
        return 0.0;
    }
    float ax = clamp_alpha(alpha_x);
    float ay = clamp_alpha(alpha_y);
    vec2 view_half = smith_ggx_visibility_half(v, ax, ay);
    vec2 light_half = smith_ggx_visibility_half(l, ax, ay);
    return 0.5 / (light_half.x * view_half.y + view_half.x * light_half.y);
}

// Cook–Torrance G = min{1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h)} (Cook & Torrance 1981).
float g_cook_torrance_1981(vec3 v, vec3 l, vec3 h) {
    float vh = dot(v, h);
    if (!(v.z > 0.0 && l.z > 0.0 && h.z > 0.0 && vh > 0.0)) {
        return 0.0;
    }
    return min(2.0 * h.z * min(v.z, l.z) / vh, 1.0);
}

// D F G / (4 (n·v)(n·l)) (Walter et al. 2007, eq. 20): 4, not π, with a normalised D.
float specular_microfacet(float d, float f, float g, float cos_v, float cos_l) {
    if (!(cos_v > 0.0 && cos_l > 0.0)) {
        return 0.0;
    }
    return d * f * g / (4.0 * max(cos_v, COS_MIN) * max(cos_l, COS_MIN));
}

#endif // COMBUSTION_MICROFACET_GLSL
