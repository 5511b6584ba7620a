#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Temporal anti-aliasing, the resolve (combustion_renderer's passes/
// temporal_anti_aliasing.rs): each pixel's jittered radiance of this frame blended with
// the history (the previous resolve) where this pixel's surface was a frame ago:
// - the pixel's surface: the nearest of its 3×3 neighbourhood (its motion and depths);
//   where no surface is, the camera's motion of the direction at the far plane;
// - reprojection: the history sampled bilinearly at the pixel less its motion;
// - rejection: no history outside the frame, on a frame that starts one (push.reset), or
//   where the surface there a frame ago was another (disocclusion: the view depth the
//   history kept differs from this surface's depth a frame ago by more than 2 %; a
//   surface where background was, or the reverse, is left to the clipping: a silhouette's
//   jittered pixels are both in turn);
// - neighbourhood clipping: the history's colour clipped, in YCoCg, towards the centre of
//   the box of this pixel's 3×3 neighbourhood of this frame (so what moved or changed
//   does not ghost);
// - the blend: push.blend of this frame (more where the surface moves: + a quarter per
//   pixel of motion, at most a half), the rest clipped history.
// The resolved radiance goes to this frame's history (alpha: the view depth of the
// pixel's surface, 0 where none), then into the HDR image.
#include "bindings/temporal_resolve.glsl"  // set 0: hdr_image, motion, gbuffer_depth, history
#include "push/temporal_resolve.glsl"

layout(location = 0) out vec4 out_history;

vec3 to_ycocg(vec3 c) {
    return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b,
        -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}

vec3 from_ycocg(vec3 c) {
    return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

// The history at `position` (pixels), bilinearly, the edge repeated.
vec4 history_at(vec2 position) {
    ivec2 size = textureSize(history, 0);
    vec2 q = position - 0.5;
    ivec2 base = ivec2(floor(q));
    vec2 f = q - vec2(base);
    vec4 texels[4];
    for (int i = 0; i < 4; ++i) {
        ivec2 p = clamp(base + ivec2(i & 1, i >> 1), ivec2(0), size - 1);
        texels[i] = texelFetch(history, p, 0);
    }
    // A background texel (depth 0) beside surfaces would mix depths: the depth is the
    // nearest texel's, the colour the bilinear mean.
    vec4 mixed = mix(mix(texels[0], texels[1], f.x), mix(texels[2], texels[3], f.x), f.y);
    ivec2 nearest = ivec2(round(f));
    mixed.a = texels[nearest.x + 2 * nearest.y].a;
    return mixed;
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(hdr_image, 0);
    vec3 current = texelFetch(hdr_image, pixel, 0).rgb;
    vec2 centre = vec2(pixel) + 0.5;
    // One pass over the 3×3 neighbourhood: its colours' box in YCoCg, and its nearest
    // surface (the smallest depth), which speaks for the pixel (its motion, its depths),
    // so that a silhouette pixel, surface in one jittered frame and background in the
    // next, keeps one history.
    vec3 low = vec3(1e30);
    vec3 high = vec3(-1e30);
    float nearest_depth = 1.0;
    ivec2 nearest_pixel = pixel;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 p = clamp(pixel + ivec2(dx, dy), ivec2(0), size - 1);
            vec3 c = to_ycocg(texelFetch(hdr_image, p, 0).rgb);
            low = min(low, c);
            high = max(high, c);
            float d = texelFetch(gbuffer_depth, p, 0).r;
            if (d < nearest_depth) {
                nearest_depth = d;
                nearest_pixel = p;
            }
        }
    }
    bool surface = nearest_depth < 1.0;
    vec4 nearest = surface ? texelFetch(motion_vectors, nearest_pixel, 0) : vec4(0.0);
    vec2 motion;
    if (surface) {
        motion = nearest.xy;
    } else {
        // The direction through the pixel, at the far plane, seen by the previous camera.
        vec2 ndc = centre / vec2(size) * 2.0 - 1.0;
        vec4 far = push.inverse_unjittered * vec4(ndc, 1.0, 1.0);
        vec4 then = push.previous * vec4(far.xyz / far.w, 1.0);
        motion = centre - (then.xy / then.w * 0.5 + 0.5) * vec2(size);
    }
    vec2 from = centre - motion;
    bool reset = push.reset != 0u || any(lessThan(from, vec2(0.0)))
        || any(greaterThanEqual(from, vec2(size)));
    vec4 past = reset ? vec4(0.0) : history_at(from);
    if (!reset) {
        bool was_surface = past.a > 0.0;
        if (surface && was_surface && abs(past.a - nearest.z) > 0.02 * nearest.z) {
            reset = true;
        }
    }
    vec3 resolved = current;
    if (!reset) {
        // Clip the history towards the box's centre until it lies inside.
        vec3 h = to_ycocg(past.rgb);
        vec3 middle = 0.5 * (low + high);
        vec3 half_size = max(0.5 * (high - low), vec3(1e-7));
        vec3 offset = h - middle;
        vec3 units = abs(offset / half_size);
        float largest = max(units.x, max(units.y, units.z));
        if (largest > 1.0) {
            h = middle + offset / largest;
        }
        vec3 clipped = max(from_ycocg(h), vec3(0.0));
        float alpha = clamp(push.blend + 0.25 * length(motion), push.blend, 0.5);
        resolved = mix(clipped, current, alpha);
    }
    out_history = vec4(resolved, surface ? nearest.w : 0.0);
}
