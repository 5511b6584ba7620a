// One quad of the text overlay. Mirrors combustion_renderer::overlay::OverlayQuad.
#ifndef COMBUSTION_OVERLAY_GLSL
#define COMBUSTION_OVERLAY_GLSL

struct OverlayQuad {
    vec4 rect;   // target pixels x0, y0, x1, y1 (whole pixels, y down)
    vec4 atlas;  // xy: the atlas (or image) texel at the top-left corner;
                 // z: 0 glyph, 1 solid, 2 the overlay image
    vec4 color;  // sRGB-encoded colour and opacity
};

layout(push_constant) uniform OverlayPush {
    vec2 target_size;
    uint atlas_width;
    uint image_width;
} push;

#endif
