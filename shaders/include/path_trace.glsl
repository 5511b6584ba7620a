// Path tracing in the lighting pass (PATH_TRACE; crates/renderer/src/passes/path_trace.rs
// says what is traced and what not yet): each pixel's PATHS_PER_FRAME paths from the eye
// through its centre, by ray queries against the scene's acceleration structure, each
// surface lit by next-event estimation to every light and to the environment, and its
// reflection or transmission sampled, with the lighting pass's own material terms
// (traced_surfaces.glsl: the surfaces a ray meets, set up as the forward pass sets up a
// fragment) — the rules of the f64 path tracer (crates/reference/src/path.rs) that this is
// measured against. Needs lighting.frag's set (materials, lights, the traced scene, the
// surface and texture tables, the environment's distribution) and push constants.
#ifndef COMBUSTION_PATH_TRACE_GLSL
#define COMBUSTION_PATH_TRACE_GLSL

#include "environment.glsl"
#include "traced_surfaces.glsl"
#include "path_trace/constants.glsl"
#include "crossing.glsl"

// Light inside a volume from `origin` along unit `direction` (the medium `eta_inside`
// inside, `eta_outside` out, absorption `sigma`, under the entry's thin film `film`,
// polarisation weight `w`): followed to the interface it meets next (whichever
// object's), absorbed on the way (Beer–Lambert), and there refracted out or reflected
// back in with the Fresnel equations' probabilities, until it leaves — `origin` and
// `direction` then where and how it leaves, `carried` times what it carries. False where
// it is lost (it meets nothing, or is reflected inside 64 times).
bool path_through_volume(inout vec3 origin, inout vec3 direction, float eta_inside,
                         float eta_outside, vec3 sigma, vec3 film, float w, inout uint state,
                         inout vec3 carried) {
    for (int crossed = 0; crossed < 64; ++crossed) {
        PathSurface exit;
        if (!path_next_surface(origin, direction, surface_offset(origin), false, state, exit)) {
            return false;
        }
        carried *= exp(-sigma * distance(origin, exit.position));
        vec3 outward = traced_outward(exit, direction);
        Crossing crossing = surface_crossing(clamp(dot(outward, direction), 0.0, 1.0), eta_inside,
                                             eta_outside, film);
        vec3 transmittance = mix(crossing.s, crossing.p, w);
        vec3 reflectance = 1.0 - transmittance;
        vec3 leaving = refract(direction, -outward, eta_inside / eta_outside);
        float mean_t = dot(transmittance, vec3(1.0 / 3.0));
        float mean_r = dot(reflectance, vec3(1.0 / 3.0));
        float leave = dot(leaving, leaving) > 0.0 ? mean_t / (mean_t + mean_r) : 0.0;
        origin = exit.position;
        if (path_random(state) < leave) {
            carried *= transmittance / leave;
            direction = normalize(leaving);
            return true;
        }
        carried *= reflectance / (1.0 - leave);
        direction = normalize(reflect(direction, outward));
    }
    return false;
}

// Whether the reflection of a surface seen as `view` under `layers` is sampled with a
// coat's visible normals too (a third strategy).
bool path_coat_sampled(SurfaceLayers layers) {
#ifdef CLEARCOAT
    return layers.coat.view.factor > 0.0 && layers.coat.view.v.z > 0.0;
#else
    return false;
#endif
}

// The density (per steradian) with which the reflection's sampling draws unit `l`: the
// mean of its strategies' (GGX's visible normals, the cosine, a coat's visible normals);
// 0 where the view is below the surface (nothing is sampled there).
float path_reflection_density(BrdfView view, SurfaceLayers layers, vec3 l) {
    if (!(view.v.z > 0.0)) {
        return 0.0;
    }
    vec3 local = shading_frame_to_local(view.frame, l);
    float density = pdf_ggx_vndf_reflection(view.v, local, view.ax, view.ay) + max(local.z, 0.0) * INV_PI;
    float strategies = 2.0;
#ifdef CLEARCOAT
    if (path_coat_sampled(layers)) {
        density += pdf_ggx_vndf_reflection(layers.coat.view.v, shading_frame_to_local(layers.coat.view.frame, l),
                                           layers.coat.view.alpha, layers.coat.view.alpha);
        strategies = 3.0;
    }
#endif
    return density / strategies;
}

#ifdef ENVIRONMENT
// The environment's distribution of directions (crates/renderer/src/
// environment_importance.rs): `environment_importance[0]` its total weight (0: nothing
// to sample), then the rows' cumulative distribution, then each row's over its columns.
#define ENVIRONMENT_MARGINAL 1u
#define ENVIRONMENT_CONDITIONAL (ENVIRONMENT_MARGINAL + ENVIRONMENT_ROWS + 1u)

// The last k in [0, n) with cdf[first + k] ≤ u (cdf non-decreasing from 0 to 1): a
// cell of positive probability for u in [0, 1).
uint path_environment_search(uint first, uint n, float u) {
    uint low = 0u;
    uint high = n;
    while (high - low > 1u) {
        uint middle = (low + high) / 2u;
        if (environment_importance[first + middle] <= u) {
            low = middle;
        } else {
            high = middle;
        }
    }
    return low;
}

// The density per steradian of cell (`column`, `row`): its probability over its solid
// angle, 4π / (columns · rows).
float path_environment_cell_density(uint column, uint row) {
    float p_row = environment_importance[ENVIRONMENT_MARGINAL + row + 1u]
                  - environment_importance[ENVIRONMENT_MARGINAL + row];
    uint first = ENVIRONMENT_CONDITIONAL + row * (ENVIRONMENT_COLUMNS + 1u);
    float p_column = environment_importance[first + column + 1u] - environment_importance[first + column];
    return p_row * p_column * float(ENVIRONMENT_COLUMNS * ENVIRONMENT_ROWS) / (4.0 * PI);
}

// The density per steradian with which path_environment_sample draws unit `l`.
float path_environment_density(vec3 l) {
    if (!(environment_importance[0] > 0.0)) {
        return 0.0;
    }
    float phi = atan(l.z, l.x);
    phi = phi < 0.0 ? phi + 2.0 * PI : phi;
    uint column = min(uint(phi / (2.0 * PI) * float(ENVIRONMENT_COLUMNS)), ENVIRONMENT_COLUMNS - 1u);
    uint row = min(uint(clamp((l.y + 1.0) * 0.5, 0.0, 1.0) * float(ENVIRONMENT_ROWS)), ENVIRONMENT_ROWS - 1u);
    return path_environment_cell_density(column, row);
}

// A direction drawn from the environment's distribution (`density`: per steradian; 0:
// nothing drawn).
vec3 path_environment_sample(inout uint state, out float density) {
    density = 0.0;
    if (!(environment_importance[0] > 0.0)) {
        return vec3(0.0, 1.0, 0.0);
    }
    uint row = path_environment_search(ENVIRONMENT_MARGINAL, ENVIRONMENT_ROWS, path_random(state));
    uint column = path_environment_search(ENVIRONMENT_CONDITIONAL + row * (ENVIRONMENT_COLUMNS + 1u),
                                          ENVIRONMENT_COLUMNS, path_random(state));
    float y = clamp(-1.0 + 2.0 * (float(row) + path_random(state)) / float(ENVIRONMENT_ROWS), -1.0, 1.0);
    float phi = 2.0 * PI * (float(column) + path_random(state)) / float(ENVIRONMENT_COLUMNS);
    float r = sqrt(max(1.0 - y * y, 0.0));
    density = path_environment_cell_density(column, row);
    return vec3(r * cos(phi), y, r * sin(phi));
}
#endif

// The radiance a path from the eye along `direction` carries back (push.sampling.y
// surfaces at most: ShadingOptions::path_depth; `state`: its random numbers). `surface`
// is what the eye's ray met.
vec3 path_radiance(PathSurface surface, vec3 direction, inout uint state) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    uint max_depth = push.sampling.y;
    // The density with which the last surface's reflection sampling drew the direction
    // the path goes on along, where that surface also estimated the environment's light
    // by sampling it (0: a pass through glass, whose escape is not weighted).
    float reflection_density = 0.0;
    // One step past the deepest surface lit: what the last one's sampled direction meets
    // adds its emission (its direct light), nothing more.
    for (uint depth = 1u; depth <= max_depth + 1u; ++depth) {
        GpuMaterial material = materials[surface.material];
        if (traced_unlit(material) || depth > max_depth) {
            // An unlit surface's radiance is its base colour, nothing lights it; past the
            // deepest surface lit, what the last one's direction meets adds its emission.
            MaterialSurface s = material_surface_at(material, surface.front ? surface.normal : -surface.normal,
                                                    surface.tangent, surface.color, surface.uvs);
            radiance += throughput * (traced_unlit(material) ? s.base_color : s.emissive);
            break;
        }
        // The surface as the G-buffer pass makes it (material_surface_at.glsl: the
        // normal reversed on a double-sided material's back, textures read at level 0),
        // lit as the forward pass lights it; then next-event estimation to every light.
        vec3 v = -direction;
        TracedShading h = traced_shading(surface, direction);
        radiance += throughput * h.s.emissive;
        radiance += throughput * traced_direct_light(surface, h, state);
#ifdef ENVIRONMENT
        // Next-event estimation to the environment: a direction drawn from its
        // distribution, kept where nothing a path would meet lies along it (the same test
        // as the path's own next surface: glass, blended surfaces met with probability α
        // and cut-out holes as a path meets them), weighted against the reflection's
        // sampling by the power heuristic (Veach 1997; the path's own escape takes the
        // other weight).
        {
            float environment_density;
            vec3 towards = path_environment_sample(state, environment_density);
            if (environment_density > 0.0 && faces_surface(h.layers, h.n, towards)) {
                vec3 response = surface_response(h.m, h.view, h.layers, h.n, towards);
                if (any(greaterThan(response, vec3(0.0)))) {
                    PathSurface blocking;
                    if (!path_next_surface(surface.position, towards, surface_offset(surface.position), true,
                                           state, blocking)) {
                        float bsdf = path_reflection_density(h.view, h.layers, towards)
                                     * (h.transmits > 0.0 ? 0.5 : 1.0);
                        float e2 = environment_density * environment_density;
                        vec3 contribution = response * textureLod(environment_specular, towards, 0.0).rgb
                                            * (environment_density / (e2 + bsdf * bsdf));
                        if (!any(isnan(contribution)) && !any(isinf(contribution))) {
                            radiance += throughput * contribution;
                        }
                    }
                }
            }
        }
#endif
        bool last = depth == max_depth;
        reflection_density = 0.0;
        vec3 origin = surface.position;
        vec3 l;
        if (h.transmits > 0.0 && path_random(state) < 0.5) {
            // Through the surface, with probability ½ (the f64 tracer's rule), weighted
            // by what the coat and sheen let out.
            float eta_i = h.m.outside_eta;
            float eta_t = h.m.dielectric_eta;
            float w = h.m.polarisation_weight;
            Crossing entry = surface_crossing(clamp(dot(h.n, v), 0.0, 1.0), eta_i, eta_t, h.film);
            vec3 carried;
            if (material.transmission_thickness.y > 0.0) {
                // A volume: refracted in, followed to where it leaves.
                l = refract(-v, h.n, eta_i / eta_t);
                if (dot(l, l) == 0.0) {
                    break;
                }
                carried = mix(entry.s, entry.p, w);
                if (!path_through_volume(origin, l, eta_t, eta_i, material.absorption.rgb, h.film, w,
                                         state, carried)) {
                    break;
                }
            } else {
                // A thin wall: both interfaces and the light between them.
                vec3 rs = 1.0 - entry.s;
                vec3 rp = 1.0 - entry.p;
                carried = mix((1.0 - rs) / (1.0 + rs), (1.0 - rp) / (1.0 + rp), w);
                l = path_thin_wall_direction(h.n, h.along, v, h.m.alpha_x, h.m.alpha_y, eta_i, eta_t,
                                             h.s.roughness, state);
            }
            float out_layers = h.layers.coat.view.attenuation_v
                * (1.0 - clamp(max(h.layers.sheen.color.r, max(h.layers.sheen.color.g, h.layers.sheen.color.b)), 0.0, 1.0)
                   * h.layers.sheen.albedo_v);
            throughput *= carried * (h.transmits * out_layers / 0.5) * h.base;
        } else {
            // The reflection sampled: GGX's visible normals, the cosine, a coat's visible
            // normals, one chosen uniformly; weighted by f (n·l) over their mean density.
            if (!(h.view.v.z > 0.0)) {
                break;
            }
            bool coated = path_coat_sampled(h.layers);
            float strategies = coated ? 3.0 : 2.0;
            float pick = path_random(state) * strategies;
            vec2 u = vec2(path_random(state), path_random(state));
            l = h.view.frame[2];
            if (pick < 1.0) {
                l = h.view.frame * reflect(-h.view.v, sample_ggx_vndf(h.view.v, h.view.ax, h.view.ay, u));
            } else if (pick < 2.0 || !coated) {
                l = h.view.frame * sample_cosine(u);
            } else {
#ifdef CLEARCOAT
                vec3 coat_v = h.layers.coat.view.v;
                float coat_alpha = h.layers.coat.view.alpha;
                l = h.layers.coat.view.frame * reflect(-coat_v, sample_ggx_vndf(coat_v, coat_alpha, coat_alpha, u));
#endif
            }
            l = normalize(l);
            float density = path_reflection_density(h.view, h.layers, l);
            if (!(density > 0.0) || !faces_surface(h.layers, h.n, l)) {
                break;
            }
            vec3 weight = surface_response(h.m, h.view, h.layers, h.n, l) / density;
            if (any(isnan(weight)) || any(isinf(weight))) {
                break;
            }
            reflection_density = density * (h.transmits > 0.0 ? 0.5 : 1.0);
            throughput *= weight / (h.transmits > 0.0 ? 0.5 : 1.0);
        }
        if (depth >= uint(PATH_ROULETTE_START) && !last) {
            float q = min(max(throughput.r, max(throughput.g, throughput.b)), PATH_ROULETTE_MAX);
            if (path_random(state) >= q) {
                break;
            }
            throughput /= q;
        }
        PathSurface next;
        if (!path_next_surface(origin, l, surface_offset(origin), true, state, next)) {
#ifdef ENVIRONMENT
            // The escape's weight against the environment's sampling at the surface it
            // left (power heuristic; 1 after a pass through glass).
            float weight = 1.0;
            if (reflection_density > 0.0) {
                float e = path_environment_density(l);
                float b2 = reflection_density * reflection_density;
                weight = b2 / (b2 + e * e);
            }
            radiance += throughput * textureLod(environment_specular, l, 0.0).rgb * weight;
#endif
            break;
        }
        direction = l;
        surface = next;
    }
    return radiance;
}

// The pixel's radiance: the mean of its PATHS_PER_FRAME paths this frame (seed `seed`),
// each from what the eye's ray through the pixel's centre meets (blended surfaces met
// with probability α); the background (the environment, or its colour) where it meets
// nothing.
vec3 path_traced_pixel(vec2 pixel, vec2 size, vec3 eye, uint seed) {
    vec2 ndc = pixel / size * 2.0 - 1.0;
    vec4 along = push.inverse_view_projection * vec4(ndc, 0.5, 1.0);
    vec3 direction = normalize(along.xyz / along.w - eye);
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < uint(PATHS_PER_FRAME); ++i) {
        uint state = path_seed(uint(pixel.x) + 65536u * uint(pixel.y), seed, i);
        PathSurface first;
        if (!path_next_surface(eye, direction, 0.0, true, state, first)) {
#ifdef ENVIRONMENT
            if (push.background.w != 0.0) {
                sum += textureLod(environment_specular, direction, 0.0).rgb;
                continue;
            }
#endif
            sum += push.background.rgb;
            continue;
        }
        sum += path_radiance(first, direction, state);
    }
    return sum / float(PATHS_PER_FRAME);
}

#endif
