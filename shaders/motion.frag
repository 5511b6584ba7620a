#version 460
#extension GL_GOOGLE_include_directive : require
// Motion vectors, fragment stage: the pixel's motion since the previous frame (pixels,
// now less then: x right, y down) and the surface's view depth then and now (clip w).
layout(location = 0) in vec4 in_current;
layout(location = 1) in vec4 in_previous;

layout(location = 0) out vec4 out_motion;

#include "push/motion.glsl"

void main() {
    vec2 now = in_current.xy / in_current.w;
    vec2 then = in_previous.xy / in_previous.w;
    out_motion = vec4((now - then) * 0.5 * push.extent, in_previous.w, in_current.w);
}
