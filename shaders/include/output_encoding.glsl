#ifndef COMBUSTION_OUTPUT_ENCODING_GLSL
#define COMBUSTION_OUTPUT_ENCODING_GLSL
// What a frame's target holds for a radiance, by the target's kind of format (the
// output pass's variants, combustion_renderer::OutputEncoding): for float targets
// (OUTPUT_LINEAR) the radiance × exposure; for display formats the tone curve of it,
// encoded exactly as sRGB here (UNORM targets) or by the driver on write
// (OUTPUT_HARDWARE_SRGB). One body for the output pass (tonemap.frag) and the lighting
// pass where the output is folded into it (lighting.frag, OUTPUT_FOLDED).
#include "tonemap.glsl"
#include "srgb.glsl"

vec4 output_encoded(vec3 radiance, float exposure, uint curve) {
#if defined(OUTPUT_LINEAR)
    return vec4(radiance * exposure, 1.0);
#else
    vec3 display = tonemap(radiance * exposure, curve);
#if defined(OUTPUT_HARDWARE_SRGB)
    return vec4(display, 1.0);
#else
    return vec4(srgb_encode(display), 1.0);
#endif
#endif
}

#endif
