// sRGB transfer curve (IEC 61966-2-1), done exactly in the shaders. Mirrored by
// combustion_renderer::{linear_to_srgb, gbuffer::srgb_to_linear}.
#ifndef COMBUSTION_SRGB_GLSL
#define COMBUSTION_SRGB_GLSL

// Base colour is stored sRGB-encoded in a UNORM target and decoded here with the exact
// formula in f32 (4.9e-7 relative error on lavapipe, measured by tests/identities.rs):
// the driver's own _SRGB conversion is a polynomial approximation (≈0.4 % relative error,
// measured by the parity test), too coarse for a reference renderer. (A 256-entry const
// table was exact too, but dynamic indexing of a const array made the lighting pass 20×
// slower on lavapipe.)
vec3 srgb_encode(vec3 linear) {
    vec3 c = clamp(linear, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

vec3 srgb_decode(vec3 e) {
    return mix(e / 12.92, pow((e + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), e));
}

// `stored` is the UNORM value c/255 of an 8-bit code c.
vec3 srgb_decode_unorm8(vec3 stored) {
    return srgb_decode(round(stored * 255.0) / 255.0);
}

#endif
