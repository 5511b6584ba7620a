#ifndef COMBUSTION_DEBUG_VIEWS_GLSL
#define COMBUSTION_DEBUG_VIEWS_GLSL
// Debug views of the lighting pass (the DEBUG_VIEWS variant; combustion_renderer::DebugView
// mirrors the numbering). Each view writes a radiance that the output pass, at exposure 1,
// turns back into the value shown: a "display" value c in [0, 1] becomes the 8-bit code c
// (the tone curve and the sRGB encoding are undone here), a colour is shown as the colour
// it is (linear, through the tone curve only), and an unbounded term (D) goes through the
// tone curve as radiance would.
#include "brdf.glsl"
#include "constants.glsl"

// DEBUG_VIEW_*: generated from combustion_renderer::DebugView.
#include "bindings/constants.glsl"

struct DebugSurface {
    vec3 base_color;
    float metalness;
    vec3 normal;
    vec3 tangent;
    float roughness;
    float anisotropy;
    uint material;
    float distance;
    float tile_light_fraction;  // lights the pixel's tile loops over / the frame's lights
    float shadow;               // the first light's lit fraction (1 without shadows)
    int cascade;                // its shadow cascade (−1: none)
};

// The radiance the tone curve 1 − e^(−x) maps to the linear value y.
vec3 debug_untonemap(vec3 y) {
    return -log(vec3(1.0) - clamp(y, vec3(0.0), vec3(0.999)));
}

// The exact sRGB decoding of an encoded value e in [0, 1].
vec3 debug_srgb_decode(vec3 e) {
    return mix(e / 12.92, pow((e + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), e));
}

// The radiance shown as the display code c (the sRGB encoding undone too).
vec3 debug_code(vec3 c) {
    return debug_untonemap(debug_srgb_decode(clamp(c, vec3(0.0), vec3(1.0))));
}

// A colour per material index (a hash), for telling materials apart.
vec3 debug_index_colour(uint i) {
    uint h = i * 2654435761u;
    return vec3(float((h >> 8) & 255u), float((h >> 16) & 255u), float((h >> 24) & 255u)) / 255.0;
}

vec3 debug_view_radiance(uint which, DebugSurface s, BrdfInputs m, BrdfView view, vec3 l, bool lit) {
    if (which == DEBUG_VIEW_BASE_COLOR) {
        return debug_untonemap(s.base_color);
    } else if (which == DEBUG_VIEW_NORMAL) {
        return debug_code(s.normal * 0.5 + 0.5);
    } else if (which == DEBUG_VIEW_ROUGHNESS) {
        return debug_code(vec3(s.roughness));
    } else if (which == DEBUG_VIEW_ANISOTROPY_STRENGTH) {
        return debug_code(vec3(s.anisotropy));
    } else if (which == DEBUG_VIEW_ANISOTROPY_DIRECTION) {
        return debug_code(s.tangent * 0.5 + 0.5);
    } else if (which == DEBUG_VIEW_METALNESS) {
        return debug_code(vec3(s.metalness));
    } else if (which == DEBUG_VIEW_MATERIAL_INDEX) {
        return debug_code(debug_index_colour(s.material));
    } else if (which == DEBUG_VIEW_DEPTH) {
        // Distance d from the eye as d / (1 + d): monotonic, 0.5 at one unit.
        return debug_code(vec3(s.distance / (1.0 + s.distance)));
    } else if (which == DEBUG_VIEW_LIGHTS_PER_TILE) {
        return debug_code(vec3(s.tile_light_fraction));
    } else if (which == DEBUG_VIEW_SHADOW_FACTOR) {
        return debug_code(vec3(s.shadow));
    } else if (which == DEBUG_VIEW_SHADOW_CASCADE) {
        const vec3 colours[4] = vec3[4](vec3(0.9, 0.2, 0.2), vec3(0.2, 0.8, 0.2),
                                        vec3(0.2, 0.4, 0.9), vec3(0.9, 0.8, 0.2));
        return debug_code(s.cascade < 0 ? vec3(0.5) : colours[s.cascade & 3]);
    }
    // The BRDF's terms for the frame's first light (black without lights or below the
    // horizon), in the shading frame the lighting pass uses.
    vec3 vl = view.v;
    vec3 ll = shading_frame_to_local(view.frame, safe_normalize(l));
    if (!lit || !(vl.z > 0.0 && ll.z > 0.0)) {
        return vec3(0.0);
    }
    vec3 sum = vl + ll;
    float len = sqrt(dot(sum, sum));
    vec3 h = sum * (1.0 / len);
    float cos_h = min(0.5 * len, 1.0);
    if (which == DEBUG_VIEW_DISTRIBUTION) {
        return vec3(d_ggx_anisotropic(h, view.ax, view.ay));
    } else if (which == DEBUG_VIEW_SMITH) {
        vec2 light_half = smith_ggx_visibility_half(ll, view.ax, view.ay);
        float visibility = 0.5 / (light_half.x * view.visibility_half.y + view.visibility_half.x * light_half.y);
        return debug_code(vec3(visibility * 4.0 * vl.z * ll.z));
    } else if (which == DEBUG_VIEW_FRESNEL) {
        vec3 f = mix(vec3(brdf_dielectric_fresnel(m, view, cos_h)),
                     brdf_conductor_fresnel(m, view, cos_h), view.metal);
        return debug_code(f);
    }
    // DEBUG_VIEW_DIFFUSE: the diffuse lobe times π (the albedo it shows), weighted by the
    // dielectric part.
    return debug_untonemap(brdf_diffuse_lobe(m, vl, ll) * PI * (1.0 - view.metal));
}
#endif
