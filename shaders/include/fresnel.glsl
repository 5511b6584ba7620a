// Fresnel reflectance. GLSL mirror of crates/optics/src/fresnel.rs: same names, same
// arrangements (derivations and citations in the Rust doc comments).
//
// A pair (R_s, R_p) is a vec2: x = s-polarised (perpendicular), y = p-polarised
// (parallel). cosθ is clamped to [0, 1], IORs to [ETA_MIN, ETA_MAX], k to [0, ETA_MAX].
#ifndef COMBUSTION_FRESNEL_GLSL
#define COMBUSTION_FRESNEL_GLSL

#include "constants.glsl"

float clamp_eta(float eta) {
    return min(max(eta, ETA_MIN), ETA_MAX);
}

// (1 − w) R_s + w R_p: w = 0 perpendicular (s), 1 parallel (p), 0.5 unpolarised.
// Rust: Polarised::weighted.
float polarised_weighted(vec2 r, float polarisation_weight) {
    float w = min(max(polarisation_weight, 0.0), 1.0);
    return (1.0 - w) * r.x + w * r.y;
}

// Dielectric–conductor Fresnel, outside index η_i, conductor η_t + i k_t (rendering
// notes §7, after Lagarde 2013), arranged without the cancellation of the printed form:
// R_s = ((a − c)² + b²)/((a + c)² + b²) with a − c = (a² − c²)/(a + c), and
// R_p = R_s ((ac − s²)² + b²c²)/((ac + s²)² + b²c²). Exactly 1 under TIR (k = 0).
vec2 fresnel_conductor(float cos_theta_i, float eta_i, float eta_t, float k_t) {
    float c = min(max(cos_theta_i, 0.0), 1.0);
    float ei = clamp_eta(eta_i);
    float et = clamp_eta(eta_t);
    float k = min(max(abs(k_t), 0.0), ETA_MAX);
    if (et == ei && k == 0.0) {
        return vec2(0.0);
    }
    float c2 = c * c;
    float s2 = (1.0 - c) * (1.0 + c);
    float inv_ei2 = 1.0 / (ei * ei);
    float dk = (et - ei) * (et + ei) - k * k;
    float p = dk * inv_ei2;
    float q = 2.0 * et * k * inv_ei2;
    float q2 = q * q;
    float u = (dk + ei * ei * c2) * inv_ei2;
    float w = sqrt(u * u + q2);
    float a2;
    float b2;
    if (u >= 0.0) {
        a2 = 0.5 * (w + u);
        b2 = a2 > 0.0 ? q2 / (4.0 * a2) : 0.0;
    } else {
        b2 = 0.5 * (w - u);
        a2 = b2 > 0.0 ? q2 / (4.0 * b2) : 0.0;
    }
    float a = sqrt(a2);
    float w_plus_c2 = w + c2;
    float w_minus_c2 = w_plus_c2 > 0.0 ? (p * (p + 2.0 * c2) + q2) / w_plus_c2 : 0.0;
    float d = 0.5 * (w_minus_c2 + p);  // a² − c²
    float a_minus_c = a > 0.0 ? d / (a + c) : -c;
    float a_plus_c = a + c;
    float rs_den = a_plus_c * a_plus_c + b2;
    float rs = rs_den > 0.0 ? min((a_minus_c * a_minus_c + b2) / rs_den, 1.0) : 0.0;
    float s = sqrt(s2);
    float ac = a * c;
    float ac_minus_s2 = a > 0.0 ? (c2 * d + (c - s) * (c + s)) / (ac + s2) : -s2;
    float ac_plus_s2 = ac + s2;
    float b2c2 = b2 * c2;
    float rp_den = ac_plus_s2 * ac_plus_s2 + b2c2;
    float factor = rp_den > 0.0 ? min((ac_minus_s2 * ac_minus_s2 + b2c2) / rp_den, 1.0) : 1.0;
    return vec2(rs, rs * factor);
}

// fresnel_conductor for three channels at once, weighted by polarisation: the same
// arrangement, with what depends on the angle alone (c², s², s, 1/η_i²) computed once
// and the per-channel branches as selects. The lighting pass's conductor lobe.
vec3 fresnel_conductor_rgb(float cos_theta_i, float eta_i, vec3 eta_t, vec3 k_t, float polarisation_weight) {
    float c = min(max(cos_theta_i, 0.0), 1.0);
    float ei = clamp_eta(eta_i);
    vec3 et = min(max(eta_t, vec3(ETA_MIN)), vec3(ETA_MAX));
    vec3 k = min(max(abs(k_t), vec3(0.0)), vec3(ETA_MAX));
    float c2 = c * c;
    float s2 = (1.0 - c) * (1.0 + c);
    float s = sqrt(s2);
    float inv_ei2 = 1.0 / (ei * ei);
    vec3 dk = (et - ei) * (et + ei) - k * k;
    vec3 p = dk * inv_ei2;
    vec3 q = 2.0 * et * k * inv_ei2;
    vec3 q2 = q * q;
    vec3 u = (dk + ei * ei * c2) * inv_ei2;
    vec3 w = sqrt(u * u + q2);
    vec3 zero = vec3(0.0);
    vec3 half_sum = 0.5 * (w + u);   // a² where u ≥ 0
    vec3 half_diff = 0.5 * (w - u);  // b² where u < 0
    bvec3 u_positive = greaterThanEqual(u, zero);
    vec3 a2 = mix(mix(q2 / (4.0 * half_diff), zero, lessThanEqual(half_diff, zero)), half_sum, u_positive);
    vec3 b2 = mix(half_diff, mix(q2 / (4.0 * half_sum), zero, lessThanEqual(half_sum, zero)), u_positive);
    vec3 a = sqrt(a2);
    bvec3 a_positive = greaterThan(a, zero);
    vec3 w_plus_c2 = w + c2;
    vec3 w_minus_c2 = mix(zero, (p * (p + 2.0 * c2) + q2) / w_plus_c2, greaterThan(w_plus_c2, zero));
    vec3 d = 0.5 * (w_minus_c2 + p);  // a² − c²
    vec3 a_plus_c = a + c;
    vec3 a_minus_c = mix(vec3(-c), d / a_plus_c, a_positive);
    vec3 rs_den = a_plus_c * a_plus_c + b2;
    vec3 rs = mix(zero, min((a_minus_c * a_minus_c + b2) / rs_den, vec3(1.0)), greaterThan(rs_den, zero));
    vec3 ac = a * c;
    vec3 ac_minus_s2 = mix(vec3(-s2), (c2 * d + (c - s) * (c + s)) / (ac + s2), a_positive);
    vec3 ac_plus_s2 = ac + s2;
    vec3 b2c2 = b2 * c2;
    vec3 rp_den = ac_plus_s2 * ac_plus_s2 + b2c2;
    vec3 factor = mix(vec3(1.0), min((ac_minus_s2 * ac_minus_s2 + b2c2) / rp_den, vec3(1.0)), greaterThan(rp_den, zero));
    float pw = min(max(polarisation_weight, 0.0), 1.0);
    vec3 r = (1.0 - pw) * rs + pw * (rs * factor);
    // A conductor that matches the medium exactly reflects nothing.
    return mix(r, zero, bvec3(uvec3(equal(et, vec3(ei))) & uvec3(equal(k, zero))));
}

// Dielectric Fresnel with total internal reflection (Born & Wolf §1.5.2):
// r_s = −Δ/(η_i c + η_t c_t)², r_p = Δ (η_t c − η_i s)(η_t c + η_i s)/(η_t² (η_t c + η_i c_t)²),
// Δ = (η_t − η_i)(η_t + η_i), η_t c_t = √(Δ + η_i² c²); exactly 1 at/past the critical angle.
vec2 fresnel_dielectric(float cos_theta_i, float eta_i, float eta_t) {
    float c = min(max(cos_theta_i, 0.0), 1.0);
    float ei = clamp_eta(eta_i);
    float et = clamp_eta(eta_t);
    float delta = (et - ei) * (et + ei);
    if (delta == 0.0) {
        return vec2(0.0);
    }
    float et2_ct2 = delta + ei * ei * c * c;
    if (!(et2_ct2 > 0.0)) {
        return vec2(1.0);
    }
    float et_ct = sqrt(et2_ct2);
    float ei_ct = ei * et_ct / et;
    float den_s = ei * c + et_ct;
    float rs = delta / (den_s * den_s);
    float s = sqrt((1.0 - c) * (1.0 + c));
    float den_p = et * c + ei_ct;
    float rp = delta * (et * c - ei * s) * (et * c + ei * s) / (et * et * den_p * den_p);
    float r_s = min(rs * rs, 1.0);
    return vec2(r_s, min(rp * rp, r_s));
}

// Dielectric transmittance T = 1 − R per polarisation, without the cancellation of 1 − R:
// T_s = 4 η_i c η_t c_t/(η_i c + η_t c_t)², T_p = 4 η_t c η_i c_t/(η_t c + η_i c_t)².
vec2 fresnel_dielectric_transmittance(float cos_theta_i, float eta_i, float eta_t) {
    float c = min(max(cos_theta_i, 0.0), 1.0);
    float ei = clamp_eta(eta_i);
    float et = clamp_eta(eta_t);
    float delta = (et - ei) * (et + ei);
    if (delta == 0.0) {
        return vec2(1.0);
    }
    float et2_ct2 = delta + ei * ei * c * c;
    if (!(et2_ct2 > 0.0)) {
        return vec2(0.0);
    }
    float et_ct = sqrt(et2_ct2);
    float ei_ct = ei * et_ct / et;
    float den_s = ei * c + et_ct;
    float den_p = et * c + ei_ct;
    return vec2(min(4.0 * ei * c * et_ct / (den_s * den_s), 1.0),
                min(4.0 * et * c * ei_ct / (den_p * den_p), 1.0));
}

// Cook & Torrance 1981 dielectric Fresnel (g, c form), unpolarised, relative η = η_t/η_i.
float fresnel_cook_torrance_1981(float cos_theta, float eta) {
    float c = min(max(cos_theta, 0.0), 1.0);
    float n = clamp_eta(eta);
    float n2m1 = (n - 1.0) * (n + 1.0);
    if (n2m1 == 0.0) {
        return 0.0;
    }
    float g2 = n2m1 + c * c;
    if (!(g2 > 0.0)) {
        return 1.0;
    }
    float g = sqrt(g2);
    float s2 = (1.0 - c) * (1.0 + c);
    float s = sqrt(s2);
    float gpc = g + c;
    float first = n2m1 / (gpc * gpc);
    float cg_s2 = c * g + s2;
    float second = (c * n - s) * (c * n + s) / (cg_s2 * cg_s2);
    return min(0.5 * first * first * (1.0 + second * second), 1.0);
}

// Schlick 1994, F0 + (1 − F0)(1 − cosθ)⁵: for comparison only.
float fresnel_schlick(float cos_theta, float f0) {
    float f = min(max(f0, 0.0), 1.0);
    float m = 1.0 - min(max(cos_theta, 0.0), 1.0);
    float m2 = m * m;
    return f + (1.0 - f) * m2 * m2 * m;
}

// Hoffman's F82 model (comparison variant FRESNEL_F82; Rust: fresnel_f82_coefficient,
// fresnel_f82): Schlick's curve less b μ (1 − μ)⁶, b fitted so the curve passes through
// the exact reflectance at μ̄ = F82_COS = 1/7.
const float F82_COS = 1.0 / 7.0;

float fresnel_f82_coefficient(float f0, float f_at_f82_cos) {
    float m = 1.0 - F82_COS;
    float m3 = m * m * m;
    return (fresnel_schlick(F82_COS, f0) - f_at_f82_cos) / (F82_COS * m3 * m3);
}

float fresnel_f82(float cos_theta, float f0, float b) {
    float mu = min(max(cos_theta, 0.0), 1.0);
    float m = 1.0 - mu;
    float m3 = m * m * m;
    return min(max(fresnel_schlick(mu, f0) - b * mu * m3 * m3, 0.0), 1.0);
}

// F(0) = ((η_t − η_i)/(η_t + η_i))².
float f0_dielectric(float eta_i, float eta_t) {
    float ei = clamp_eta(eta_i);
    float et = clamp_eta(eta_t);
    float r = (et - ei) / (et + ei);
    return r * r;
}

// Relative index η_t/η_i ≥ 1 from F0 (equals η_t only in air, seed-notes 8).
float eta_from_f0(float f0) {
    float r = min(sqrt(min(max(f0, 0.0), 1.0)), 1.0 - FLT_EPSILON);
    return (1.0 + r) / (1.0 - r);
}

#endif // COMBUSTION_FRESNEL_GLSL
