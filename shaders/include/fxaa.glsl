#ifndef COMBUSTION_FXAA_GLSL
#define COMBUSTION_FXAA_GLSL
// FXAA (Lottes 2009, "FXAA", NVIDIA white paper; the structure of its 3.11 quality
// preset), on the output pass's own tone-mapped values: an edge is found where the local
// contrast of display luma is high, its orientation from second differences, its ends by
// stepping along it, and the pixel is resampled across the edge by how far it lies from
// the nearer end (with a sub-pixel blend for single-pixel features). The search reads
// display luma (interpolated as luma); the final resample is the HDR image's radiance,
// interpolated bilinearly as radiance and then tone-mapped, so the blend is of what the
// pixel's area receives, as a supersampled resolve's. Needs
// `display_of(vec3 radiance)` (the output's curve) and the `hdr_image` binding.

// A pixel is left as it is where its 3×3 cross's display-luma range is below both
// FXAA_CONTRAST_RELATIVE of its brightest and FXAA_CONTRAST_MIN (dark areas).
const float FXAA_CONTRAST_RELATIVE = 0.125;
const float FXAA_CONTRAST_MIN = 0.0312;
// How much of the sub-pixel blend (the preset's default is 0.75). Off: against 4×4
// supersampling it raised the error of the pixels FXAA changes (spheres at 480×360: mean
// FLIP 0.00581 with 0.75, 0.00580 without; hard cases 0.00631 and 0.00574; the sum of
// the changed pixels' code differences 1.22e5 and 5.4e4 on spheres).
const float FXAA_SUBPIXEL = 0.0;
#define FXAA_SEARCH_STEPS 10
// The steps along the edge, in whole pixels (the quality preset's growing strides, its
// 1.5 rounded to 2): every sample lies on the boundary between two pixel centres, where
// the luma is the mean of theirs.
const int FXAA_STEP[FXAA_SEARCH_STEPS] = int[](1, 1, 1, 1, 1, 2, 2, 2, 4, 8);

vec3 fxaa_radiance_at(ivec2 p) {
    ivec2 size = textureSize(hdr_image, 0);
    return texelFetch(hdr_image, clamp(p, ivec2(0), size - 1), 0).rgb;
}

// Bilinear radiance at `pos` in pixels (pixel i's centre at i + 0.5), clamped to the image.
vec3 fxaa_radiance_bilinear(vec2 pos) {
    vec2 q = pos - 0.5;
    vec2 base = floor(q);
    vec2 f = q - base;
    ivec2 i = ivec2(base);
    vec3 a = mix(fxaa_radiance_at(i), fxaa_radiance_at(i + ivec2(1, 0)), f.x);
    vec3 b = mix(fxaa_radiance_at(i + ivec2(0, 1)), fxaa_radiance_at(i + ivec2(1, 1)), f.x);
    return mix(a, b, f.y);
}

// Perceived brightness of a display value (Rec. 709 luminance, square-rooted as a
// display's response roughly is).
float fxaa_luma(vec3 display) {
    return sqrt(max(dot(display, vec3(0.2126, 0.7152, 0.0722)), 0.0));
}

float fxaa_luma_at(ivec2 p) {
    return fxaa_luma(display_of(fxaa_radiance_at(p)));
}

// The anti-aliased display value of pixel `p`.
vec3 fxaa(ivec2 p) {
    vec3 rc = fxaa_radiance_at(p);
    vec3 rn = fxaa_radiance_at(p + ivec2(0, -1));
    vec3 rs = fxaa_radiance_at(p + ivec2(0, 1));
    vec3 rw = fxaa_radiance_at(p + ivec2(-1, 0));
    vec3 re = fxaa_radiance_at(p + ivec2(1, 0));
    vec3 centre = display_of(rc);
    // A cross of one radiance (a flat area, the background) has no contrast: the pixel
    // stays as it is, decided before its neighbours are tone-mapped (where a whole block
    // of pixels is flat, lavapipe then skips the rest; NaN is never equal, so it goes on).
    if (all(equal(rn, rc)) && all(equal(rs, rc)) && all(equal(rw, rc)) && all(equal(re, rc))) {
        return centre;
    }
    float lc = fxaa_luma(centre);
    float ln = fxaa_luma(display_of(rn));
    float ls = fxaa_luma(display_of(rs));
    float lw = fxaa_luma(display_of(rw));
    float le = fxaa_luma(display_of(re));
    float highest = max(lc, max(max(ln, ls), max(lw, le)));
    float lowest = min(lc, min(min(ln, ls), min(lw, le)));
    float range = highest - lowest;
    if (range < max(FXAA_CONTRAST_MIN, highest * FXAA_CONTRAST_RELATIVE)) {
        return centre;
    }
    float lnw = fxaa_luma_at(p + ivec2(-1, -1));
    float lne = fxaa_luma_at(p + ivec2(1, -1));
    float lsw = fxaa_luma_at(p + ivec2(-1, 1));
    float lse = fxaa_luma_at(p + ivec2(1, 1));
    // Change across rows (an edge running horizontally) against change across columns.
    float across_rows = abs(lnw + lsw - 2.0 * lw) + 2.0 * abs(ln + ls - 2.0 * lc) + abs(lne + lse - 2.0 * le);
    float across_columns = abs(lnw + lne - 2.0 * ln) + 2.0 * abs(lw + le - 2.0 * lc) + abs(lsw + lse - 2.0 * ls);
    bool horizontal = across_rows >= across_columns;
    // The two neighbours across the edge; the steeper side is where the edge lies.
    float l_before = horizontal ? ln : lw;
    float l_after = horizontal ? ls : le;
    float g_before = l_before - lc;
    float g_after = l_after - lc;
    bool before = abs(g_before) >= abs(g_after);
    float gradient = 0.25 * max(abs(g_before), abs(g_after));
    float l_side = before ? l_before : l_after;
    float edge_luma = 0.5 * (l_side + lc);
    vec2 across = horizontal ? vec2(0.0, 1.0) : vec2(1.0, 0.0);
    ivec2 along_step = horizontal ? ivec2(1, 0) : ivec2(0, 1);
    float side = before ? -1.0 : 1.0;
    ivec2 beyond = p + ivec2(across * side);
    // The luma on the boundary between the pixel's row (or column) and the neighbour's,
    // k pixels along the edge: the mean of the two lumas there.
    int k_a = -FXAA_STEP[0];
    int k_b = FXAA_STEP[0];
    float delta_a = 0.5 * (fxaa_luma_at(p + along_step * k_a) + fxaa_luma_at(beyond + along_step * k_a)) - edge_luma;
    float delta_b = 0.5 * (fxaa_luma_at(p + along_step * k_b) + fxaa_luma_at(beyond + along_step * k_b)) - edge_luma;
    bool done_a = abs(delta_a) >= gradient;
    bool done_b = abs(delta_b) >= gradient;
    for (int i = 1; i < FXAA_SEARCH_STEPS && !(done_a && done_b); ++i) {
        if (!done_a) {
            k_a -= FXAA_STEP[i];
            delta_a = 0.5 * (fxaa_luma_at(p + along_step * k_a) + fxaa_luma_at(beyond + along_step * k_a)) - edge_luma;
            done_a = abs(delta_a) >= gradient;
        }
        if (!done_b) {
            k_b += FXAA_STEP[i];
            delta_b = 0.5 * (fxaa_luma_at(p + along_step * k_b) + fxaa_luma_at(beyond + along_step * k_b)) - edge_luma;
            done_b = abs(delta_b) >= gradient;
        }
    }
    float distance_a = float(-k_a);
    float distance_b = float(k_b);
    bool nearer_a = distance_a < distance_b;
    float nearer = min(distance_a, distance_b);
    float offset = 0.5 - nearer / (distance_a + distance_b);
    // Only where the nearer end's luma leaves the edge's on the side opposite the
    // centre's (the pixel is inside the step the edge makes there).
    bool centre_darker = lc < edge_luma;
    bool step_here = ((nearer_a ? delta_a : delta_b) < 0.0) != centre_darker;
    float edge_offset = step_here ? offset : 0.0;
    // Sub-pixel: the 3×3 mean's distance from the centre, over the range, smoothed.
    float mean = (2.0 * (ln + ls + lw + le) + (lnw + lne + lsw + lse)) / 12.0;
    float sub = clamp(abs(mean - lc) / range, 0.0, 1.0);
    sub = (3.0 - 2.0 * sub) * sub * sub;
    float sub_offset = sub * sub * FXAA_SUBPIXEL;
    float final_offset = max(edge_offset, sub_offset);
    vec2 centre_pos = vec2(p) + 0.5;
    return display_of(fxaa_radiance_bilinear(centre_pos + across * (side * final_offset)));
}

#endif // COMBUSTION_FXAA_GLSL
