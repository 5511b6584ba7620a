#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Output pass: HDR radiance → the frame's target (the host's image, or the renderer's
// own display image). One variant per kind of target format:
// - default (UNORM targets, e.g. R8G8B8A8_UNORM, B8G8R8A8_UNORM): tone curve (the frame's:
//   tonemap.glsl), then the
//   exact sRGB encoding here rather than the driver's approximate conversion on write;
// - OUTPUT_HARDWARE_SRGB (_SRGB targets): tone curve; the driver encodes on write;
// The exposure is the push's, or in frames that meter it the auto exposure's.
// - OUTPUT_LINEAR (float targets, e.g. R16G16B16A16_SFLOAT): radiance × exposure, no
//   tone curve, for a host's own post-processing.
// FXAA (display formats; a pipeline of its own for frames that ask for it): fxaa.glsl.
#include "output_encoding.glsl"

#include "bindings/output.glsl"  // set 0: see combustion_renderer::bindings::OUTPUT

layout(push_constant) uniform TonemapPush {
    float exposure;
    uint curve;  // combustion_renderer::ToneMapping as u32
    uint metered;  // 1: the auto exposure's factor (exposure_state[0]) replaces exposure
} push;

// The frame's exposure: the one given, or the one the auto exposure metered.
float frame_exposure() {
    return push.metered != 0u ? uintBitsToFloat(exposure_state[0]) : push.exposure;
}

layout(location = 0) out vec4 out_color;

// The display value (before sRGB encoding) of a radiance: exposure, then the frame's curve.
vec3 display_of(vec3 radiance) {
    return tonemap(radiance * frame_exposure(), push.curve);
}

#ifdef FXAA
#include "fxaa.glsl"
#endif

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
#if defined(FXAA) && !defined(OUTPUT_LINEAR)
    vec3 display = fxaa(pixel);  // AntiAliasing::Fxaa: its own pipeline
#if defined(OUTPUT_HARDWARE_SRGB)
    out_color = vec4(display, 1.0);
#else
    out_color = vec4(srgb_encode(display), 1.0);
#endif
#else
    out_color = output_encoded(texelFetch(hdr_image, pixel, 0).rgb, frame_exposure(), push.curve);
#endif
}
