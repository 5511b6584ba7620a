#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Path-traced frames averaged while nothing changes (combustion_renderer's passes/
// path_accumulation.rs): this frame's radiance joins the mean of the frames before it,
// m_k = m_{k-1} + (x_k - m_{k-1}) / k, into this frame's history (f32); the first frame
// of a history (push.frames == 1) takes its radiance alone (the other history is not
// read: it may hold another picture's mean, or nothing yet).
#include "bindings/path_accumulation.glsl"  // set 0: hdr_image, history
#include "push/path_accumulation.glsl"

layout(location = 0) out vec4 out_mean;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 current = texelFetch(hdr_image, pixel, 0);
    if (push.frames <= 1u) {
        out_mean = current;
        return;
    }
    vec4 mean = texelFetch(history, pixel, 0);
    out_mean = mean + (current - mean) / float(push.frames);
}
