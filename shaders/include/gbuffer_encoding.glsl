// G-buffer encodings, shared by the G-buffer pass (encode) and the lighting pass
// (decode). Mirrored on the CPU by crates/renderer/src/gbuffer.rs for parity tests.
// Layout and precision: docs/gbuffer.md.
#ifndef COMBUSTION_GBUFFER_ENCODING_GLSL
#define COMBUSTION_GBUFFER_ENCODING_GLSL

#include "constants.glsl"
#include "srgb.glsl"

// The base colour as the lighting pass reads it from its target (GBufferStorage,
// docs/gbuffer.md): the linear albedo.
vec3 base_color_decode(vec3 stored) {
#if defined(BASE_COLOR_LINEAR)
    return stored;
#elif defined(BASE_COLOR_SRGB16)
    return srgb_decode(stored);
#else
    return srgb_decode_unorm8(stored);
#endif
}

// The base colour's 8-bit sRGB code per channel (0 to 255, as a float): the index of the
// conductor tables of materials whose conductor is derived from the base colour, in
// every storage.
vec3 base_color_srgb8_code(vec3 stored) {
#ifdef BASE_COLOR_LINEAR
    return round(srgb_encode(stored) * 255.0);
#else
    return round(stored * 255.0);
#endif
}
vec2 sign_not_zero(vec2 v) {
    return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
}

// Octahedral unit-vector encoding to [0, 1]^2 (Cigolle et al. 2014, "A Survey of
// Efficient Representations for Independent Unit Vectors", JCGT 3(2)).
vec2 octahedral_encode(vec3 n) {
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    vec2 e = n.z >= 0.0 ? n.xy : (1.0 - abs(n.yx)) * sign_not_zero(n.xy);
    return e * 0.5 + 0.5;
}

vec3 octahedral_decode(vec2 encoded) {
    vec2 e = encoded * 2.0 - 1.0;
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) {
        n.xy = (1.0 - abs(n.yx)) * sign_not_zero(n.xy);
    }
    return normalize(n);
}

// Orthonormal basis (t, b) around unit n (Duff et al. 2017, "Building an Orthonormal
// Basis, Revisited", JCGT 6(1)). The reference frame for the anisotropy direction.
void orthonormal_basis(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// The largest code of the normal's octahedral coordinates (GBufferStorage's surface
// target: 16- or 8-bit unorm).
#ifdef SURFACE_UNORM8
const float SURFACE_CODE_MAX = 255.0;
#else
const float SURFACE_CODE_MAX = 65535.0;
#endif

// The normal the lighting pass will decode from the surface target: the anisotropy
// direction is stored in its basis, so that the tangent read back is the direction's
// projection on the stored normal's plane (and not turned by the difference between
// the bases of the exact and the stored normal, 10⁻² rad at 8 bits).
vec3 stored_normal(vec3 n) {
    return octahedral_decode(round(octahedral_encode(n) * SURFACE_CODE_MAX) / SURFACE_CODE_MAX);
}

// The anisotropy direction is stored as its angle φ in the basis of n, folded into
// [0, π) (GGX is symmetric under t → −t) and quantised to 16 bits.
uint anisotropy_direction_encode(vec3 n, vec3 direction) {
    vec3 t0, b0;
    orthonormal_basis(n, t0, b0);
    float phi = atan(dot(direction, b0), dot(direction, t0));  // (−π, π]
    if (phi < 0.0) {
        phi += PI;
    }
    return uint(round(phi * (65536.0 / PI))) & 0xffffu;
}

vec3 anisotropy_direction_decode(vec3 n, uint encoded) {
    vec3 t0, b0;
    orthonormal_basis(n, t0, b0);
    float phi = float(encoded) * (PI / 65536.0);
    return cos(phi) * t0 + sin(phi) * b0;
}

#endif
