// A thin dielectric film over the BRDF's base (KHR_materials_iridescence). GLSL mirror of
// crates/optics/src/thin_film.rs (thin_film_reflectance, ThinFilm): the Airy series of
// Belcour & Barla (2017) in Fourier form, with the base's exact complex Fresnel
// amplitudes (η + ik per channel; k = 0 for a dielectric) and their phase shifts.
#ifndef COMBUSTION_THIN_FILM_GLSL
#define COMBUSTION_THIN_FILM_GLSL

#include "constants.glsl"
#include "fresnel.glsl"

struct ThinFilm {
    float weight;        // share of the Fresnel that is the film's (0: none)
    float eta;           // the film's real IOR
    float thickness_nm;  // 0: no film
};

// Rust: FILM_THICKNESS_MAX_NM, FILM_HARMONICS.
const float FILM_THICKNESS_MAX_NM = 1.0e5;
#define FILM_HARMONICS 4

// Rust: sensitivity_weights(): S_c(D, φ) = Σ_g W_cg cos(k_g D + φ) e^(−a_g D²), D in nm;
// Belcour & Barla's Gaussians of the CIE 1931 functions, in linear sRGB, each channel's
// weights summing to 1 (checked against the Rust derivation by tests/glsl_mirror.rs).
const vec4 FILM_SENSITIVITY_WEIGHTS_R = vec4(2.27593101, -1.27552633, -0.414056689, 0.413652004);
const vec4 FILM_SENSITIVITY_WEIGHTS_G = vec4(-0.865289501, 1.97868659, 0.0438698626, -0.157266953);
const vec4 FILM_SENSITIVITY_WEIGHTS_B = vec4(0.0517655457, -0.224251657, 1.16307769, 0.00940842301);
const vec4 FILM_SENSITIVITY_FREQUENCIES = vec4(0.0105620345, 0.0112802026, 0.0138757864, 0.0140737068);
const vec4 FILM_SENSITIVITY_DECAYS = vec4(1.70854696e-07, 3.67330884e-07, 2.61035245e-07, 1.78766171e-07);

bool thin_film_is_present(ThinFilm film) {
    return film.weight > 0.0 && film.thickness_nm > 0.0;
}

// S(D, ·) = cos φ · cos_part − sin φ · sin_part, per channel.
void thin_film_sensitivity(float opd_nm, out vec3 cos_part, out vec3 sin_part) {
    vec4 phase = FILM_SENSITIVITY_FREQUENCIES * opd_nm;
    vec4 envelope = exp(-(FILM_SENSITIVITY_DECAYS * opd_nm * opd_nm));
    vec4 cg = cos(phase) * envelope;
    vec4 sg = sin(phase) * envelope;
    cos_part = vec3(dot(FILM_SENSITIVITY_WEIGHTS_R, cg), dot(FILM_SENSITIVITY_WEIGHTS_G, cg),
                    dot(FILM_SENSITIVITY_WEIGHTS_B, cg));
    sin_part = vec3(dot(FILM_SENSITIVITY_WEIGHTS_R, sg), dot(FILM_SENSITIVITY_WEIGHTS_G, sg),
                    dot(FILM_SENSITIVITY_WEIGHTS_B, sg));
}

// Complex numbers as vec2 (re, im).
vec2 complex_mul(vec2 a, vec2 b) {
    return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

// (a − b)/(a + b); 1 where a + b = 0.
vec2 complex_ratio_of_difference(vec2 a, vec2 b) {
    vec2 num = a - b;
    vec2 den = a + b;
    float d = den.x * den.x + den.y * den.y;
    if (!(d > 0.0)) {
        return vec2(1.0, 0.0);
    }
    return vec2(num.x * den.x + num.y * den.y, num.y * den.x - num.x * den.y) / d;
}

// The principal square root (Im ≥ 0 for Im(z) ≥ 0).
vec2 complex_sqrt(vec2 z) {
    float r = sqrt(z.x * z.x + z.y * z.y);
    float re = sqrt(max(0.5 * (r + z.x), 0.0));
    float im = sqrt(max(0.5 * (r - z.x), 0.0));
    return vec2(re, z.y >= 0.0 ? im : -im);
}

// |r|² of one polarisation: c0 + Σ 2 c_m S_c(m OPD, m Φ) for channel `channel`.
float thin_film_airy(float r12, vec2 r23, vec3 cos_parts[FILM_HARMONICS],
                     vec3 sin_parts[FILM_HARMONICS], int channel) {
    float big_r12 = r12 * r12;
    float big_r23 = min(r23.x * r23.x + r23.y * r23.y, 1.0);
    float transmitted = 1.0 - big_r12;
    float denominator = 1.0 - big_r12 * big_r23;
    if (!(denominator > 0.0)) {
        return 1.0;
    }
    float amplitude = -(transmitted * (1.0 - big_r23)) / denominator;
    float phase_23 = big_r23 > 0.0 ? atan(r23.y, r23.x) : 0.0;
    float ratio = abs(r12) * sqrt(big_r23);
    float series_phase = r12 > 0.0 ? phase_23 + PI : phase_23;
    float value = 1.0 + amplitude;
    float c_m = amplitude;
    for (int m = 0; m < FILM_HARMONICS; ++m) {
        c_m *= ratio;
        float phase = float(m + 1) * series_phase;
        float s_c = cos(phase) * cos_parts[m][channel] - sin(phase) * sin_parts[m][channel];
        value += 2.0 * c_m * s_c;
    }
    return clamp(value, 0.0, 1.0);
}

// The film's reflectance per channel, s-polarised (rs) and p-polarised (rp), at the
// cosine cos_theta to the (micro)surface normal in the outside medium, over a base
// η + ik per channel. The film's weight is not applied.
void thin_film_reflectance(float cos_theta, float outside_eta, ThinFilm film, vec3 base_eta,
                           vec3 base_k, out vec3 rs, out vec3 rp) {
    float c1 = clamp(cos_theta, 0.0, 1.0);
    float eta1 = clamp(outside_eta, ETA_MIN, ETA_MAX);
    float eta2 = clamp(film.eta, ETA_MIN, ETA_MAX);
    float d = clamp(film.thickness_nm, 0.0, FILM_THICKNESS_MAX_NM);
    float ratio = eta1 / eta2;
    float sin2_2 = ratio * ratio * ((1.0 - c1) * (1.0 + c1));
    if (sin2_2 >= 1.0) {
        rs = vec3(1.0);
        rp = vec3(1.0);
        return;
    }
    float c2 = sqrt(max(1.0 - sin2_2, 0.0));
    float r12_s = (eta1 * c1 - eta2 * c2) / (eta1 * c1 + eta2 * c2);
    float r12_p = (eta2 * c1 - eta1 * c2) / (eta2 * c1 + eta1 * c2);
    float opd = 2.0 * eta2 * d * c2;
    vec3 cos_parts[FILM_HARMONICS];
    vec3 sin_parts[FILM_HARMONICS];
    for (int m = 0; m < FILM_HARMONICS; ++m) {
        thin_film_sensitivity(float(m + 1) * opd, cos_parts[m], sin_parts[m]);
    }
    vec2 film_side = vec2(eta2 * c2, 0.0);
    for (int c = 0; c < 3; ++c) {
        float n3 = clamp(base_eta[c], ETA_MIN, ETA_MAX);
        float k3 = clamp(abs(base_k[c]), 0.0, ETA_MAX);
        vec2 n3_sq = vec2((n3 - k3) * (n3 + k3), 2.0 * n3 * k3);
        vec2 w = complex_sqrt(vec2(n3_sq.x - eta2 * eta2 * sin2_2, n3_sq.y));
        vec2 r23_s = complex_ratio_of_difference(film_side, w);
        vec2 r23_p = complex_ratio_of_difference(n3_sq * c2, w * eta2);
        rs[c] = thin_film_airy(r12_s, r23_s, cos_parts, sin_parts, c);
        rp[c] = thin_film_airy(r12_p, r23_p, cos_parts, sin_parts, c);
    }
}

// (1 − w) R_s + w R_p of the film per channel (w already clamped to [0, 1]).
vec3 thin_film_reflectance_weighted(float cos_theta, float outside_eta, ThinFilm film,
                                    vec3 base_eta, vec3 base_k, float w) {
    vec3 rs;
    vec3 rp;
    thin_film_reflectance(cos_theta, outside_eta, film, base_eta, base_k, rs, rp);
    return (1.0 - w) * rs + w * rp;
}

// The transmittance per channel, s in ts and p in tp, of one crossing of a dielectric
// interface from eta_from into eta_to at cos_theta (on the eta_from side) under `film`
// (Rust: film_crossing_transmittance): T + w ((1 − R_film) − T), the film absorbing
// nothing; without a film (no weight or thickness) the interface's own.
void film_crossing_transmittance(float cos_theta, float eta_from, float eta_to, ThinFilm film,
                                 out vec3 ts, out vec3 tp) {
    vec2 t = fresnel_dielectric_transmittance(cos_theta, eta_from, eta_to);
    ts = vec3(t.x);
    tp = vec3(t.y);
    if (thin_film_is_present(film)) {
        vec3 rs;
        vec3 rp;
        thin_film_reflectance(cos_theta, eta_from, film, vec3(eta_to), vec3(0.0), rs, rp);
        float w = min(film.weight, 1.0);
        ts += w * ((1.0 - rs) - ts);
        tp += w * ((1.0 - rp) - tp);
    }
}

#endif // COMBUSTION_THIN_FILM_GLSL
