#ifndef COMBUSTION_TONEMAP_GLSL
#define COMBUSTION_TONEMAP_GLSL
// Per-channel exponential tone curve 1 − e^(−x): linear near black (slope 1), smooth
// roll-off, never clips, invertible (x = −ln(1 − y)), so a pixel of a golden image can
// be checked by hand. Mirrored by combustion_renderer::tonemap_exponential.
vec3 tonemap_exponential(vec3 x) {
    return vec3(1.0) - exp(-max(x, vec3(0.0)));
}

// Khronos PBR Neutral (2024): colours below 0.76 pass unchanged but for a small offset
// near black; brighter ones are compressed towards 1 and desaturated. Mirrored by
// combustion_renderer::tonemap_pbr_neutral.
vec3 tonemap_pbr_neutral(vec3 color) {
    const float start_compression = 0.8 - 0.04;
    const float desaturation = 0.15;
    color = max(color, vec3(0.0));
    float x = min(color.r, min(color.g, color.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    color -= offset;
    float peak = max(color.r, max(color.g, color.b));
    if (peak < start_compression) {
        return color;
    }
    float d = 1.0 - start_compression;
    float new_peak = 1.0 - d * d / (peak + d - start_compression);
    color *= new_peak / peak;
    float g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(color, vec3(new_peak), g);
}

// K. Narkowicz's fit of the ACES filmic curve (2016), of 0.6 x, per channel. Mirrored by
// combustion_renderer::tonemap_aces.
vec3 tonemap_aces(vec3 x) {
    x = 0.6 * max(x, vec3(0.0));
    return clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// AgX (T. Sobotka) in B. Wrensch's minimal form (2024): inset matrix, log2 over
// [-12.47, 4.03] stops, a 6th-order fit of the default contrast curve, outset matrix,
// then decoded from its 2.2-power display encoding. Mirrored by
// combustion_renderer::tonemap_agx (which lists the matrices by rows; GLSL's constructor
// takes columns).
vec3 tonemap_agx(vec3 color) {
    const mat3 inset = mat3(
        0.842479062253094, 0.0423282422610123, 0.0423756549057051,
        0.0784335999999992, 0.878468636469772, 0.0784336,
        0.0792237451477643, 0.0791661274605434, 0.879142973793104);
    const mat3 outset = mat3(
        1.19687900512017, -0.0528968517574562, -0.0529716355144438,
        -0.0980208811401368, 1.15190312990417, -0.0980434501171241,
        -0.0990297440797205, -0.0989611768448433, 1.15107367264116);
    const float min_ev = -12.47393;
    const float max_ev = 4.026069;
    vec3 x = inset * max(color, vec3(1e-10));
    x = (clamp(log2(max(x, vec3(1e-10))), min_ev, max_ev) - min_ev) / (max_ev - min_ev);
    vec3 x2 = x * x;
    vec3 x4 = x2 * x2;
    x = 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2
        + 0.1191 * x - 0.00232;
    return min(pow(max(outset * x, vec3(0.0)), vec3(2.2)), vec3(1.0));
}

// The tone curve numbered `curve` (combustion_renderer::ToneMapping as u32).
vec3 tonemap(vec3 x, uint curve) {
    if (curve == 3u) {
        return tonemap_agx(x);
    }
    if (curve == 1u) {
        return tonemap_pbr_neutral(x);
    }
    if (curve == 2u) {
        return tonemap_aces(x);
    }
    return tonemap_exponential(x);
}
#endif
