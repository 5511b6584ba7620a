// Diffuse BRDFs (values, not multiplied by n·l). GLSL mirror of
// crates/optics/src/diffuse.rs: same names and arrangements; here ρ is a vec3 (one value
// per channel) and the geometry is computed once. v, l in the shading frame (z = normal).
#ifndef COMBUSTION_DIFFUSE_GLSL
#define COMBUSTION_DIFFUSE_GLSL

#include "constants.glsl"

// σ = α/√2 with α = r² (before the ALPHA_MIN floor): per-axis slope deviation of the
// specular lobe, so both lobes describe one surface. r ∈ [0, 1].
float oren_nayar_sigma_from_roughness(float r) {
    float rc = min(max(r, 0.0), 1.0);
    return rc * rc * INV_SQRT_2;
}

float clamp_sigma(float sigma) {
    return min(max(sigma, 0.0), 0.5 * PI);
}

// Lambert 1760: f = ρ/π.
vec3 diffuse_lambert(vec3 rho) {
    return rho * INV_PI;
}

// Oren & Nayar 1994 qualitative model: ρ/π (A + B max(0, cosφ) sin α tan β), with
// cosφ sin α tan β = (v.x l.x + v.y l.y)/max(cosθ_i, cosθ_r).
vec3 diffuse_oren_nayar_qualitative(vec3 rho, float sigma, float a_constant, vec3 v, vec3 l) {
    if (!(v.z > 0.0 && l.z > 0.0)) {
        return vec3(0.0);
    }
    float ci = max(l.z, COS_MIN);
    float cr = max(v.z, COS_MIN);
    float sin_sin_cos_phi = v.x * l.x + v.y * l.y;
    float sc = clamp_sigma(sigma);
    float s2 = sc * sc;
    float a = s2 > 0.0 ? 1.0 - 0.5 * s2 / (s2 + max(a_constant, 0.0)) : 1.0;
    float b = 0.45 * s2 / (s2 + 0.09);
    float x = max(sin_sin_cos_phi, 0.0) / max(ci, cr);
    return rho * INV_PI * (a + b * x);
}

// Oren & Nayar 1994 full model (C1, C2, C3 and the interreflection term), L₁ clamped at 0.
vec3 diffuse_oren_nayar_full(vec3 rho, float sigma, vec3 v, vec3 l) {
    if (!(v.z > 0.0 && l.z > 0.0)) {
        return vec3(0.0);
    }
    float ci = max(l.z, COS_MIN);
    float cr = max(v.z, COS_MIN);
    float si = sqrt(l.x * l.x + l.y * l.y);
    float sr = sqrt(v.x * v.x + v.y * v.y);
    float sc = clamp_sigma(sigma);
    float s2 = sc * sc;
    float theta_i = atan(si, ci);
    float theta_r = atan(sr, cr);
    float theta_max = max(theta_i, theta_r);
    float theta_min = min(theta_i, theta_r);
    // (sin, cos) of α = max(θ_i, θ_r) and of β = min(θ_i, θ_r)
    bool i_is_min = theta_i < theta_r;
    float s_max_angle = i_is_min ? sr : si;
    float c_max_angle = i_is_min ? cr : ci;
    float s_min_angle = i_is_min ? si : sr;
    float c_min_angle = i_is_min ? ci : cr;
    float tan_beta = s_min_angle / c_min_angle;

    float cos_phi = 0.0;
    float one_minus_abs_cos_phi = 1.0;
    if (si > 0.0 && sr > 0.0) {
        float vx = v.x / sr;
        float vy = v.y / sr;
        float lx = l.x / si;
        float ly = l.y / si;
        cos_phi = min(max(vx * lx + vy * ly, -1.0), 1.0);
        float sin_phi = vx * ly - vy * lx;
        one_minus_abs_cos_phi = sin_phi * sin_phi / (1.0 + abs(cos_phi));
    }

    float tmp = s2 / (s2 + 0.09);
    float c1 = 1.0 - 0.5 * s2 / (s2 + 0.33);
    float two_beta_over_pi = 2.0 * theta_min * INV_PI;
    float x = 2.0 * INV_PI * atan(c_min_angle, s_min_angle);  // 1 − 2β/π
    float c2;
    if (cos_phi >= 0.0) {
        c2 = 0.45 * tmp * s_max_angle;
    } else {
        // sin α − (2β/π)³ = x (3 − 3x + x²) − cos²α/(1 + sin α), free of cancellation
        float one_minus_sin_alpha = c_max_angle * c_max_angle / (1.0 + s_max_angle);
        c2 = 0.45 * tmp * (x * (3.0 - 3.0 * x + x * x) - one_minus_sin_alpha);
    }
    float four_ab_over_pi2 = 4.0 * theta_max * theta_min * INV_PI * INV_PI;
    float c3 = 0.125 * tmp * (four_ab_over_pi2 * four_ab_over_pi2);
    float tan_half_sum = (si + sr) / (ci + cr);
    float bracket = max(c1 + cos_phi * c2 * tan_beta + one_minus_abs_cos_phi * c3 * tan_half_sum, 0.0);
    float c4 = 0.17 * s2 / (s2 + 0.13);
    float interreflection = cos_phi > 0.0
        ? one_minus_abs_cos_phi + cos_phi * x * (2.0 - x)
        : 1.0 - cos_phi * (two_beta_over_pi * two_beta_over_pi);
    return (rho * bracket + rho * rho * c4 * interreflection) * INV_PI;
}

#endif // COMBUSTION_DIFFUSE_GLSL
