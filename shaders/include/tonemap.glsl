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

// The tone curve numbered `curve` (combustion_renderer::ToneMapping as u32).
vec3 tonemap(vec3 x, uint curve) {
    if (curve == 1u) {
        return tonemap_pbr_neutral(x);
    }
    if (curve == 2u) {
        return tonemap_aces(x);
    }
    return tonemap_exponential(x);
}
#endif
