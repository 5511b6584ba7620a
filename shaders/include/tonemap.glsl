#ifndef COMBUSTION_TONEMAP_GLSL
#define COMBUSTION_TONEMAP_GLSL
// Per-channel exponential tone curve 1 − e^(−x): linear near black (slope 1), smooth
// roll-off, never clips, invertible (x = −ln(1 − y)), so a pixel of a golden image can
// be checked by hand. Mirrored by combustion_renderer::tonemap_exponential.
vec3 tonemap_exponential(vec3 x) {
    return vec3(1.0) - exp(-max(x, vec3(0.0)));
}
#endif
