#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#if defined(RAY_TRACED_REFRACTION) && !defined(TRANSMISSION)
// Refraction is traced in place of the screen-space transmission: without transmissive
// objects there is none (the pass does not run).
#undef RAY_TRACED_REFRACTION
#endif
#ifdef RAY_TRACED_REFRACTION
// Rays that meet the scene's surfaces and read them (traced_surfaces.glsl).
#define TRACED_SURFACES
#extension GL_EXT_ray_query : require
#endif
// Forward pass, fragment stage (vertex stage: gbuffer.vert): the blended objects
// (glTF alphaMode BLEND) and the transmissive ones (KHR_materials_transmission, in the
// TRANSMISSION variant), drawn after the deferred lighting, back to front, each
// fragment shaded at once from its own surface with the lighting pass's terms (the same
// lights, shadows, environment and BRDF: lighting_terms.glsl) and blended "over" the
// HDR image with its alpha (straight alpha: rgb · α + behind · (1 − α)). Specialised as
// the lighting pass is (combustion_renderer::LightingFeatures). docs/gltf.md,
// "Transmission", states what the screen-space transmission can and cannot do.
#include "gpu_types.glsl"
#include "srgb.glsl"
#include "brdf.glsl"

#include "bindings/forward.glsl"  // set 0: see combustion_renderer::bindings::FORWARD
#include "bindings/constants.glsl"
// The forward pass lights the surface at once with its BRDF frame: a direction on isotropic
// surfaces too.
#define MATERIAL_SURFACE_DIRECTION_ALWAYS
#include "material_surface.glsl"  // the fragment inputs and set 1, the material's textures

layout(push_constant) uniform ForwardPush {
    mat4 view_projection;  // read by gbuffer.vert (and here, to find what is behind)
    uint object_index;     // read by gbuffer.vert
    uint light_count;
    float object_scale;    // the object's scale: a volume's thickness in metres per mesh unit
    float object_extent;   // the diagonal of the object's world box (VOLUME: the longest path)
    vec4 camera_position;
} push;

#ifdef SHADOWS
#include "shadows.glsl"
#endif
#include "lighting_terms.glsl"
#ifdef RAY_TRACED_REFRACTION
#define TRACED_LIGHT_COUNT push.light_count
#include "traced_surfaces.glsl"
#include "ray_traced_refraction/constants.glsl"
#endif

layout(location = 0) out vec4 out_radiance;

#ifdef TRANSMISSION
// The smallest cosine between a ray and the normal it crosses.
const float TRANSMISSION_MIN_COS = 1e-4;

// `n` bent towards `towards` until their cosine is at least TRANSMISSION_MIN_COS: an
// interpolated normal may face away from the ray near a silhouette (the face itself
// faces it), and Snell's law assumes it does not.
vec3 facing(vec3 n, vec3 towards) {
    float c = dot(n, towards);
    return c > TRANSMISSION_MIN_COS ? n : normalize(n + (TRANSMISSION_MIN_COS - c) * towards);
}

// Where world point `p` lands: (uv in [0, 1]², normalised depth, clip w).
vec4 screen_point(vec3 p) {
    vec4 clip = push.view_projection * vec4(p, 1.0);
    return vec4(clip.xy / clip.w * 0.5 + 0.5, clip.z / clip.w, clip.w);
}

bool on_screen(vec2 uv) {
    return all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)));
}

// The texel of the frame's images (the opaque depth's, the back faces') at `uv`.
ivec2 texel_of(vec2 uv) {
    ivec2 size = textureSize(scene_depth, 0);
    return clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1);
}

// The two levels of `behind` whose blurs, averaged, spread it as a rough transmissive
// surface spreads the light it lets through, seen `beyond` metres past the surface at
// clip depth `w_beyond`. Through a microfacet tilted by θ (small angles) light bends by
// about (η − 1)θ, η = η_t/η_i, entering and leaving alike, and the tilts of the two
// interfaces (thin wall or volume) add as a difference: the light's deviation is
// distributed as GGX's slopes (tilt tan θ within s for a share s²/(α² + s²), α = r²)
// scaled by (η − 1)√2. That lobe is a sharp core in wide tails, which no single blur
// is: each half of its light gets its own, the inner half a blur of the inner half's
// median radius (share 1/4: s = α/√3), the outer half of the outer's (share 3/4:
// s = α√3), in pixels across `beyond`. A bilinear lookup at level L of a chain of 2×
// box reductions weighs level 0 by a box 2^L wide (variance 4^L/12 per axis) under a
// tent 2^(L+1) wide (4^L/6): variance 4^L/4, half its weight within 1.18σ = 0.59·2^L
// of its centre (as a Gaussian's): level = log2(radius / 0.59).
vec2 rough_lods(float roughness, float eta, float beyond, float w_beyond) {
    float slope = abs(eta - 1.0) * sqrt(2.0) * roughness * roughness;
    // 1/tan(fov/2): the projection's y scale, the length of the view-projection's second
    // row (the view's rows are orthonormal).
    float focal = length(vec3(push.view_projection[0][1], push.view_projection[1][1],
                              push.view_projection[2][1]));
    float pixel = 2.0 * w_beyond / (focal * float(textureSize(behind, 0).y));
    float radius = beyond * slope / max(pixel, 1e-30);
    vec2 radii = radius * vec2(1.0 / sqrt(3.0), sqrt(3.0));
    return log2(max(radii / 0.59, vec2(1.0)));
}

// How far past `p` (on a transmissive surface) the opaque surface the eye sees through
// it lies, along the eye's ray (0 in front of it), and that surface's clip depth w.
float behind_distance(vec3 p, out float w_beyond) {
    vec3 eye = push.camera_position.xyz;
    vec3 dir = normalize(p - eye);
    vec4 c0 = push.view_projection * vec4(eye, 1.0);
    vec4 cd = push.view_projection * vec4(dir, 0.0);
    vec4 q = screen_point(p);
    float z = texelFetch(scene_depth, texel_of(q.xy), 0).r;
    float t = (z * c0.w - c0.z) / (cd.z - z * cd.w);
    w_beyond = c0.w + t * cd.w;
    return max(t - distance(p, eye), 0.0);
}

// What the eye sees through a transmissive surface along `direction` from `origin`
// when the screen-space lookup is the pixel `uv` (`found`: the ray's own surface was
// found there): the lit image behind at that pixel (coarser levels `lods`, averaged, for rough
// surfaces), or the environment along the ray where the lookup leaves the screen or
// reaches the sky.
vec3 seen_behind(vec2 uv, bool found, bool sky, vec3 direction, vec2 lods, float roughness) {
#ifdef ENVIRONMENT
    if (!found || sky) {
        float levels = float(textureQueryLevels(environment_specular) - 1);
        return textureLod(environment_specular, direction, clamp(roughness, 0.0, 1.0) * levels).rgb;
    }
#endif
    uv = clamp(uv, vec2(0.0), vec2(1.0));
    return 0.5 * (textureLod(behind, uv, lods.x).rgb + textureLod(behind, uv, lods.y).rgb);
}

#ifdef VOLUME
// The linear search through a volume, whose far side the ray crosses once (steps), then
// its refinement (halvings).
const int EXIT_STEPS = 8;
const int REFINE_STEPS = 7;

// How a ray is marched on screen: a step every `pixels` pixels, at most `steps` steps,
// then `halvings` halvings of the step that crossed a surface.
struct ScreenMarch {
    float pixels;
    int steps;
    int halvings;
};
// The ray through the volume: to the lookup's precision (a fraction of a pixel).
const ScreenMarch THROUGH = ScreenMarch(8.0, 32, 8);
// The ray the far side reflects back out, weighted by its reflectance (R ≈ 0.04 in air):
// coarser.
const ScreenMarch RETURNED = ScreenMarch(12.0, 16, 5);

// Whether the point `q` (screen_point) lies past the nearest back face of the volumes
// drawn at its pixel, or where there is none (the ray has left the volume's outline).
bool past_back_face(vec4 q) {
    float back = texelFetch(back_face_depth, texel_of(q.xy), 0).r;
    return back >= 1.0 || q.z >= back;
}

// Where the ray p + s·d, refracted into a volume at p, leaves it: s at the far side the
// back faces pass drew, searched for within `reach` (the object's longest path); -1 if
// the ray leaves the screen first.
float volume_exit(vec3 p, vec3 d, float reach) {
    float inside = 0.0;
    for (int i = 1; i <= EXIT_STEPS; ++i) {
        float s = reach * float(i) / float(EXIT_STEPS);
        vec4 q = screen_point(p + s * d);
        if (!(q.w > 0.0) || !on_screen(q.xy)) {
            return -1.0;
        }
        if (past_back_face(q)) {
            float outside = s;
            for (int k = 0; k < REFINE_STEPS; ++k) {
                float mid = 0.5 * (inside + outside);
                if (past_back_face(screen_point(p + mid * d))) {
                    outside = mid;
                } else {
                    inside = mid;
                }
            }
            return outside;
        }
        inside = s;
    }
    return -1.0;
}

// The outward normal of the far side where the ray p + s·d leaves: the normals drawn
// there, interpolated between texels (those with none, outside the outline, weigh
// nothing once normalised).
vec3 exit_normal(vec3 p, vec3 d, float s) {
    vec3 n = textureLod(back_face_normal, screen_point(p + s * d).xy, 0.0).xyz;
    return dot(n, n) > 0.0 ? normalize(n) : d;
}

// What the ray p + u·d, leaving a volume at p, meets first on screen: marched in
// screen space (where the normalised depth along a projected line is linear) against
// the opaque surfaces' depth, up to the near plane and the screen's edge. `uv` is where
// it meets a surface (`sky`: the background, depth 1) and the function returns true;
// false if it leaves the screen first (`uv`: where it did). `travelled`: how far from p
// along d that is; `w_hit`: its clip depth.
bool opaque_hit(vec3 p, vec3 d, ScreenMarch march, out vec2 uv, out bool sky,
                out float travelled, out float w_hit) {
    vec4 c0 = push.view_projection * vec4(p, 1.0);
    vec4 cd = push.view_projection * vec4(d, 0.0);
    float reach = 1e4 * max(distance(p, push.camera_position.xyz), 1.0);
    // Stop short of the near plane (clip z = 0) and of the eye's plane (w = 0).
    if (cd.z < 0.0) {
        reach = min(reach, 0.999 * c0.z / -cd.z);
    }
    if (cd.w < 0.0) {
        reach = min(reach, 0.999 * c0.w / -cd.w);
    }
    vec4 c1 = c0 + reach * cd;
    vec3 a = c0.xyz / c0.w;
    vec3 b = c1.xyz / c1.w;
    // The part of the line on screen: t in [0, t_end].
    float t_end = 1.0;
    for (int axis = 0; axis < 2; ++axis) {
        float delta = b[axis] - a[axis];
        if (delta > 0.0) {
            t_end = min(t_end, (1.0 - a[axis]) / delta);
        } else if (delta < 0.0) {
            t_end = min(t_end, (-1.0 - a[axis]) / delta);
        }
    }
    t_end = max(t_end, 0.0);
    sky = false;
    // The world distance along d of the point a screen-space fraction t along: clip
    // coordinates interpolate linearly in the world, their divisions by w on screen.
    float w0 = c0.w;
    float w1 = c1.w;
    travelled = reach * t_end * w0 / ((1.0 - t_end) * w1 + t_end * w0);
    w_hit = w0 + travelled * cd.w;
    float before = 0.0;
    vec2 size = vec2(textureSize(scene_depth, 0));
    float pixels = length((b.xy - a.xy) * 0.5 * size) * t_end;
    int steps = clamp(int(ceil(pixels / march.pixels)), 1, march.steps);
    for (int i = 0; i <= steps; ++i) {
        float t = t_end * float(i) / float(steps);
        vec3 q = mix(a, b, t);
        uv = q.xy * 0.5 + 0.5;
        float depth = texelFetch(scene_depth, texel_of(uv), 0).r;
        if (q.z >= depth) {
            float after = t;
            for (int k = 0; k < march.halvings && i > 0; ++k) {
                float mid = 0.5 * (before + after);
                vec3 m = mix(a, b, mid);
                if (m.z >= texelFetch(scene_depth, texel_of(m.xy * 0.5 + 0.5), 0).r) {
                    after = mid;
                } else {
                    before = mid;
                }
            }
            q = mix(a, b, after);
            uv = q.xy * 0.5 + 0.5;
            sky = texelFetch(scene_depth, texel_of(uv), 0).r >= 1.0;
            travelled = reach * after * w0 / ((1.0 - after) * w1 + after * w0);
            w_hit = w0 + travelled * cd.w;
            return true;
        }
        before = t;
    }
    return false;
}
#endif

// The radiance that passes through a transmissive surface towards the eye: what lies
// behind it (the lit image before this pass, `behind`, or the environment where the
// lookup leaves the screen), through its two interfaces and its volume.
// - Entry: the exact dielectric transmittance T = 1 − R per polarisation at the view
//   angle, from the outside medium η_i into the material's η_t (0 past the critical
//   angle when η_i > η_t); refraction by Snell's law, η_i/η_t.
// - With a volume, in the VOLUME variant: the refracted ray is followed to where it
//   leaves the object, the nearest far side the back faces pass drew (marched against
//   its depth), refracted out there through the normal drawn there (η_t/η_i, its own
//   transmittance; nothing past the critical angle: the light reflected inside is not
//   followed), and on to the opaque surface it meets (marched against the scene's
//   depth), whose pixel of the lit image is what it sees. Beer–Lambert absorption
//   e^(−σs) over the path s inside; the internal reflections between the two interfaces
//   summed as a slab's: T₁T₂a / (1 − R₁R₂a²) per polarisation and channel.
// - Otherwise (a volume whose exit leaves the screen, or outside the VOLUME variant):
//   the exit face is taken parallel to the entry face (a slab `thickness` thick, × the
//   object's scale), so the light leaves at the angle it entered, through the same
//   transmittance, along the view ray, and the lookup is the exit point's pixel:
//   T² a / (1 − R² a²).
// - Thin-walled (no volume): the same slab with no thickness, a = 1: (1 − R)/(1 + R).
// - Rough surfaces read a coarser level of `behind`, as wide as their two interfaces
//   spread the light over the distance to what it meets (rough_lods).
#include "crossing.glsl"

// Per polarisation and channel, the light that leaves by the far side (through both
// interfaces, after any number of round trips inside: `seen` is what it shows) and the
// light that leaves by the near side after one reflection at the far side (and any round
// trips more: `seen_returned`), `absorbed` the volume's transmission along one chord.
vec3 through_interfaces(BrdfInputs m, Crossing entry, Crossing far_side, Crossing back_out, vec3 absorbed,
                        vec3 seen, vec3 seen_returned) {
    float w = m.polarisation_weight;
    vec3 radiance = vec3(0.0);
    for (int c = 0; c < 3; ++c) {
        float a = absorbed[c];
        vec2 t_entry = vec2(entry.s[c], entry.p[c]);
        vec2 t_exit = vec2(far_side.s[c], far_side.p[c]);
        vec2 r_exit = vec2(1.0) - t_exit;
        vec2 t_return = vec2(back_out.s[c], back_out.p[c]);
        vec2 r_return = vec2(1.0) - t_return;
        vec2 round_trips = vec2(1.0) / max(vec2(1.0) - r_return * r_exit * a * a, vec2(1e-30));
        vec2 through = t_entry * t_exit * a * round_trips;
        vec2 back = t_entry * r_exit * t_return * a * a * round_trips;
        radiance[c] = ((1.0 - w) * through.x + w * through.y) * seen[c]
                    + ((1.0 - w) * back.x + w * back.y) * seen_returned[c];
    }
    return radiance;
}

#ifdef RAY_TRACED_REFRACTION
// transmitted_radiance with rays traced through the scene (RAY_TRACED_REFRACTION;
// passes/ray_traced_refraction.rs): the same interfaces and sums, what lies behind found
// by ray queries — a volume's exit at the interface its refracted ray meets inside
// (whichever object's), the part reflected there followed to the interface it meets
// next, what leaves shaded where it lands (traced_radiance_along, through thin walls) —
// never a screen lookup.
vec3 traced_transmitted_radiance(GpuMaterial material, BrdfInputs m, vec3 n, vec3 along, vec3 v,
                                 vec3 position, float roughness, float thickness, vec3 film) {
    float eta_i = m.outside_eta;
    float eta_t = m.dielectric_eta;
    n = facing(n, v);
    Crossing entry = surface_crossing(clamp(dot(n, v), 0.0, 1.0), eta_i, eta_t, film);
    uint state = path_seed(uint(gl_FragCoord.x) + 65536u * uint(gl_FragCoord.y), push.object_index,
                           REFRACTION_STREAM);
#ifdef ENVIRONMENT
    float lod = clamp(roughness, 0.0, 1.0) * float(textureQueryLevels(environment_specular) - 1);
#else
    float lod = 0.0;
#endif
    vec3 absorbed = vec3(1.0);
    Crossing far_side = entry;
    Crossing back_out = entry;
    vec3 seen = vec3(0.0);
    vec3 seen_returned = vec3(0.0);
    if (thickness > 0.0) {
        vec3 refracted = refract(-v, n, eta_i / eta_t);
        if (dot(refracted, refracted) == 0.0) {
            return vec3(0.0);  // totally reflected at the entry (η_i > η_t)
        }
        refracted = normalize(refracted);
        PathSurface exit;
        if (!path_next_surface(position, refracted, surface_offset(position), false, state, exit)) {
            return vec3(0.0);  // an open mesh: the light is lost inside
        }
        vec3 n_exit = traced_outward(exit, refracted);
        far_side = surface_crossing(dot(refracted, n_exit), eta_t, eta_i, film);
        absorbed = exp(-material.absorption.rgb * distance(position, exit.position));
        vec3 leaving = refract(refracted, -n_exit, eta_t / eta_i);
        if (dot(leaving, leaving) > 0.0) {
            seen = traced_radiance_along(exit.position, normalize(leaving), lod, REFRACTION_THIN_WALLS, state);
        }
        // The part the exit reflects back inside, to the interface it meets next.
        vec3 returning = reflect(refracted, n_exit);
        PathSurface back;
        if (path_next_surface(exit.position, returning, surface_offset(exit.position), false, state, back)) {
            vec3 n_return = traced_outward(back, returning);
            back_out = surface_crossing(dot(returning, n_return), eta_t, eta_i, film);
            vec3 returned = refract(returning, -n_return, eta_t / eta_i);
            if (dot(returned, returned) > 0.0) {
                seen_returned = traced_radiance_along(back.position, normalize(returned), lod,
                                                      REFRACTION_THIN_WALLS, state);
            }
        }
    } else if (!(roughness > 0.0)) {
        // A smooth thin wall: straight on, through the walls beyond it.
        seen = traced_radiance_along(position, -v, lod, REFRACTION_THIN_WALLS, state);
    } else {
        // A rough one: the mean of REFRACTION_ROUGH_RAYS directions drawn from the spread
        // of its two rough interfaces (the path tracer's rule).
        for (uint k = 0u; k < REFRACTION_ROUGH_RAYS; ++k) {
            vec3 d = path_thin_wall_direction(n, along, v, m.alpha_x, m.alpha_y, eta_i, eta_t, roughness, state);
            seen += traced_radiance_along(position, d, lod, REFRACTION_THIN_WALLS, state);
        }
        seen /= float(REFRACTION_ROUGH_RAYS);
    }
    return through_interfaces(m, entry, far_side, back_out, absorbed, seen, seen_returned);
}
#endif

vec3 transmitted_radiance(GpuMaterial material, BrdfInputs m, vec3 n, vec3 v, vec3 position,
                          float roughness, float thickness, vec3 film) {
    float eta_i = m.outside_eta;
    float eta_t = m.dielectric_eta;
    n = facing(n, v);
    float cos_v = clamp(dot(n, v), 0.0, 1.0);
    // Every crossing of the surface under its film (a thin wall's far side and a
    // volume's exits are the same surface, its film as here).
    Crossing entry = surface_crossing(cos_v, eta_i, eta_t, film);
    float eta = eta_t / eta_i;
    vec3 exit_point = position;
    vec3 absorbed = vec3(1.0);
    Crossing far_side = entry;
    Crossing back_out = entry;
    vec3 seen = vec3(0.0);
    vec3 seen_returned = vec3(0.0);
    bool traced = false;
    if (thickness > 0.0) {
        vec3 refracted = refract(-v, n, eta_i / eta_t);
        if (dot(refracted, refracted) == 0.0) {
            return vec3(0.0);  // totally reflected at the entry (η_i > η_t)
        }
#ifdef VOLUME
        float s = volume_exit(position, refracted, push.object_extent);
        if (s > 0.0) {
            exit_point = position + s * refracted;
            vec3 n_exit = facing(exit_normal(position, refracted, s), refracted);
            vec3 leaving = refract(refracted, -n_exit, eta_t / eta_i);
            float cos_exit = dot(refracted, n_exit);
            far_side = surface_crossing(cos_exit, eta_t, eta_i, film);
            absorbed = exp(-material.absorption.rgb * s);
            vec2 uv;
            bool sky;
            float beyond;
            float w_beyond;
            if (dot(leaving, leaving) > 0.0) {
                bool found = opaque_hit(exit_point, leaving, THROUGH, uv, sky, beyond, w_beyond);
                vec2 lods = rough_lods(roughness, eta, beyond, w_beyond);
                seen = seen_behind(uv, found, sky, leaving, lods, roughness);
            }
            // The part the exit reflects back inside, to where it leaves on the side it
            // entered by: a chord as long again, meeting the entry normal mirrored about
            // the exit's (exact for a sphere and a slab) at the exit's angle.
            vec3 returning = reflect(refracted, n_exit);
            vec3 n_return = facing(2.0 * dot(n, n_exit) * n_exit - n, returning);
            vec3 returned = refract(returning, -n_return, eta_t / eta_i);
            back_out = surface_crossing(dot(returning, n_return), eta_t, eta_i, film);
            if (dot(returned, returned) > 0.0) {
                bool found = opaque_hit(exit_point + s * returning, returned, RETURNED, uv, sky,
                                        beyond, w_beyond);
                vec2 lods = rough_lods(roughness, eta, beyond, w_beyond);
#ifndef ENVIRONMENT
                // Off the screen without an environment: nothing known is seen there.
                if (found)
#endif
                seen_returned = seen_behind(uv, found, sky, returned, lods, roughness);
            }
            traced = true;
        }
#endif
        if (!traced) {
            exit_point = position + refracted * thickness;
            absorbed = exp(-material.absorption.rgb * thickness);
        }
    }
    if (!traced) {
        vec4 q = screen_point(exit_point);
        float w_beyond;
        float beyond = behind_distance(exit_point, w_beyond);
        vec2 lods = rough_lods(roughness, eta, beyond, w_beyond);
        seen = seen_behind(q.xy, q.w > 0.0 && on_screen(q.xy), false, -v, lods, roughness);
    }
    return through_interfaces(m, entry, far_side, back_out, absorbed, seen, seen_returned);
}
#endif

void main() {
    GpuMaterial material = materials[in_material];
    MaterialSurface s = material_surface(material);
    float alpha = clamp(s.alpha, 0.0, 1.0);
#ifndef NO_UNLIT
    // KHR_materials_unlit: the base colour is the radiance; nothing lights it.
    if ((material.diffuse_model_flags.y & MATERIAL_FLAG_UNLIT) != 0u) {
        out_radiance = vec4(s.base_color, alpha);
        return;
    }
#endif
    vec3 position = in_world_position;
    vec3 v = normalize(push.camera_position.xyz - position);
    vec3 base_color = clamp(s.base_color, 0.0, 1.0);
    vec3 base_color_code = round(srgb_encode(base_color) * 255.0);
#ifdef TRANSMISSION
    // KHR_materials_transmission: of what the dielectric part lets through its surface,
    // the share `transmission` passes on through the object instead of scattering
    // diffusely: the diffuse lobe (and its environment term) keeps 1 − transmission.
    // The transmission and the thickness (material_surface_at.glsl), the thickness in
    // metres through the object's scale.
    float transmission = s.transmission;
    float thickness = s.thickness * push.object_scale;
    BrdfInputs m = brdf_inputs(material, base_color * (1.0 - transmission), s.metalness,
                               s.roughness, s.anisotropy, base_color_code);
#else
    BrdfInputs m = brdf_inputs(material, base_color, s.metalness, s.roughness, s.anisotropy,
                               base_color_code);
#endif
    // The shading normal made to face the eye (brdf.glsl, facing_view), as the lighting
    // pass does; the BRDF's frame re-orthogonalises the direction against it.
    vec3 n = facing_view(s.normal, v);
    vec3 t = s.direction;
    BrdfView view = brdf_view(m, n, t, cross(n, t), v);
#ifdef SPECULAR
    // The dielectric's specular strength and colour (its reflection; what glass
    // transmits crosses the bare interface), before a film over them.
    brdf_view_apply_specular(view, m, DielectricSpecular(s.specular_factor, s.specular_color));
#endif
#ifdef IRIDESCENCE
    brdf_view_apply_film(view, m, ThinFilm(s.film_weight, material.film.y, s.film_thickness_nm));
#endif
#ifdef CLEARCOAT
    SurfaceCoat coat = surface_coat(material, m, s.clearcoat, s.clearcoat_roughness,
                                    facing_view(s.clearcoat_normal, v), v);
#else
    SurfaceCoat coat = no_surface_coat();
#endif
    SurfaceLayers layers;
    layers.coat = coat;
#ifdef SHEEN
    layers.sheen = surface_sheen(s.sheen_color, s.sheen_roughness, view);
#else
    layers.sheen = no_surface_sheen();
#endif
    vec3 radiance = s.emissive;
    for (uint i = 0u; i < push.light_count; ++i) {
        radiance += light_radiance(m, view, layers, lights[i], position, n,
                                   push.camera_position.xyz, gl_FragCoord.xy);
    }
#ifdef ENVIRONMENT
    radiance += environment_radiance(material, in_material, m, view, layers, view.frame[2], v,
                                     s.roughness, base_color_code, s.occlusion);
#endif
#ifdef TRANSMISSION
    if (transmission > 0.0) {
        // What passes through leaves through the layers towards the eye: a coat's A(v), a
        // sheen's 1 − max(c) E(n·v) (crates/optics/src/layers.rs, through_layers_v).
        float sheen_max = max(layers.sheen.color.r, max(layers.sheen.color.g, layers.sheen.color.b));
        float through_layers = coat.view.attenuation_v * (1.0 - sheen_max * layers.sheen.albedo_v);
        radiance += (1.0 - s.metalness) * transmission * base_color * through_layers
#ifdef RAY_TRACED_REFRACTION
                  * traced_transmitted_radiance(material, m, n, t, v, position, s.roughness, thickness,
#else
                  * transmitted_radiance(material, m, n, v, position, s.roughness, thickness,
#endif
#ifdef IRIDESCENCE
                                         vec3(s.film_weight, material.film.y, s.film_thickness_nm)
#else
                                         vec3(0.0)
#endif
                    );
    }
#endif
    out_radiance = vec4(radiance, alpha);
}
