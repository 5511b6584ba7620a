#version 460
// One triangle covering the viewport; full-screen passes read their inputs with texelFetch.
// AT_FAR_PLANE (depth-tested passes, fullscreen.rs): at depth 1, which the pass's depth
// test compares with the frame's depth.
void main() {
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
#ifdef AT_FAR_PLANE
    gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0);
#else
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
#endif
}
