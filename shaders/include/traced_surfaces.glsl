// What a ray that meets the scene's surfaces finds there, for the lighting pass's
// traced light (TRACED_SURFACES: path tracing, ray-traced reflections): the surface table
// and the scene's textures (crates/renderer/src/accel.rs, TracedSurfaces), the nearest
// surface along a ray as a path sees it, the surface a hit shows (the G-buffer pass's
// own code, material_surface_at.glsl) set up for the lighting pass's material terms, and
// its direct light with shadow rays. Needs the set of lighting.frag or forward.frag
// (materials, lights, the traced scene, `traced_surfaces`, `traced_textures`) and the
// frame's light count (TRACED_LIGHT_COUNT: lighting.frag's push.counts.x by default).
#ifndef COMBUSTION_TRACED_SURFACES_GLSL
#define COMBUSTION_TRACED_SURFACES_GLSL

#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require

#include "environment.glsl"  // sample_ggx_vndf
#include "traced_scene.glsl"
#include "traced_textures.glsl"
#include "crossing.glsl"

// How many of `lights` the frame has (the includer's push constants say).
#ifndef TRACED_LIGHT_COUNT
#define TRACED_LIGHT_COUNT push.counts.x
#endif

// A mesh's vertices (GpuVertex: position, normal, tangent, uv; 12 floats) and indices.
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer TracedVertices {
    float values[];
};
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer TracedIndices {
    uint values[];
};
// A mesh's second texture-coordinate set and vertex colour (6 floats a vertex), where it
// has either.
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer TracedExtras {
    float values[];
};

// A PCG step and a uniform float in [0, 1) from it.
float path_random(inout uint state) {
    state = state * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    word = (word >> 22u) ^ word;
    return float(word >> 8) * (1.0 / 16777216.0);
}

// A hash of three words: a path's first state.
uint path_seed(uint a, uint b, uint c) {
    uint h = a * 0x9E3779B9u ^ (b + 0x7F4A7C15u) * 0x85EBCA6Bu ^ (c + 0x165667B1u) * 0xC2B2AE35u;
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    return h ^ (h >> 16);
}

// What a ray meets: the surface's point, its interpolated normal (world space, towards
// the mesh's front), tangent and bitangent sign, its geometric normal (the winding's
// front), its texture coordinates (sets 0 and 1), vertex colour and material; `front`:
// the ray meets the winding's front.
struct PathSurface {
    vec3 position;
    vec3 normal;
    vec4 tangent;
    vec3 geometric;
    vec4 uvs;
    vec4 color;
    uint material;
    bool front;
};

// The surface table's rows per instance (accel.rs, TracedSurfaces).
#define SURFACE_ROWS 3u

vec3 traced_vertex3(TracedVertices vertices, uint index, uint offset) {
    uint at = 12u * index + offset;
    return vec3(vertices.values[at], vertices.values[at + 1u], vertices.values[at + 2u]);
}

// The nearest surface along the ray from `origin` along unit `direction` beyond
// `t_min`: cut-outs tested where it meets them; where `seen`, as a path sees it — back
// faces of single-sided materials passed (the rasteriser culls them; the f64 path tracer
// passes them too), a blended surface met with probability α (`state`: the path's
// random numbers) — else any triangle (light inside a volume meets whatever it meets).
// False where nothing.
bool path_next_surface(vec3 origin, vec3 direction, float t_min, bool seen, inout uint state,
                       out PathSurface surface) {
    for (int passed = 0; passed < 16; ++passed) {
        rayQueryEXT query;
        rayQueryInitializeEXT(query, scene, gl_RayFlagsNoneEXT, 0xffu, origin, t_min, direction, 1e30);
        proceed_past_cutout_holes(query);
        if (rayQueryGetIntersectionTypeEXT(query, true) == gl_RayQueryCommittedIntersectionNoneEXT) {
            return false;
        }
        uint instance = uint(rayQueryGetIntersectionInstanceIdEXT(query, true));
        uint primitive = uint(rayQueryGetIntersectionPrimitiveIndexEXT(query, true));
        vec2 b = rayQueryGetIntersectionBarycentricsEXT(query, true);
        float t = rayQueryGetIntersectionTEXT(query, true);
        mat4x3 to_world = rayQueryGetIntersectionObjectToWorldEXT(query, true);
        uvec4 where = traced_surfaces[SURFACE_ROWS * instance];
        uvec4 what = traced_surfaces[SURFACE_ROWS * instance + 1u];
        uvec4 extras_at = traced_surfaces[SURFACE_ROWS * instance + 2u];
        if (primitive >= what.w) {
            return false;  // not the instance's triangle: never read past its mesh
        }
        TracedVertices vertices = TracedVertices(where.xy);
        TracedIndices indices = TracedIndices(where.zw);
        uvec3 corner = uvec3(indices.values[3u * primitive], indices.values[3u * primitive + 1u],
                             indices.values[3u * primitive + 2u]);
        vec3 w = vec3(1.0 - b.x - b.y, b.x, b.y);
        vec3 p0 = to_world * vec4(traced_vertex3(vertices, corner.x, 0u), 1.0);
        vec3 p1 = to_world * vec4(traced_vertex3(vertices, corner.y, 0u), 1.0);
        vec3 p2 = to_world * vec4(traced_vertex3(vertices, corner.z, 0u), 1.0);
        vec3 geometric = normalize(cross(p1 - p0, p2 - p0));
        bool front = dot(geometric, direction) < 0.0;
        bool double_sided = (what.z & 1u) != 0u;
        bool passes = seen && !front && !double_sided;
        vec4 uvs = vec4(0.0);
        vec4 color = vec4(1.0);
        for (uint k = 0u; k < 3u; ++k) {
            uint at = 12u * corner[k] + 10u;
            uvs.xy += vec2(vertices.values[at], vertices.values[at + 1u]) * w[k];
        }
        if (extras_at.x != 0u || extras_at.y != 0u) {
            TracedExtras extras = TracedExtras(extras_at.xy);
            color = vec4(0.0);
            for (uint k = 0u; k < 3u; ++k) {
                uint at = 6u * corner[k];
                uvs.zw += vec2(extras.values[at], extras.values[at + 1u]) * w[k];
                color += vec4(extras.values[at + 2u], extras.values[at + 3u], extras.values[at + 4u],
                              extras.values[at + 5u]) * w[k];
            }
        }
        if (seen && (what.z & 2u) != 0u) {
            // A blended surface's alpha: its factor × the base colour texture's × the
            // vertex colour's.
            GpuMaterial blended = materials[what.x];
            float alpha = blended.alpha_cutoff.x * color.a;
            int base_texture = blended.textures_base_mr_normal_occlusion.x;
            if (base_texture >= 0) {
                alpha *= traced_texture(base_texture, traced_slot_uv(blended, 0u, uvs)).a;
            }
            passes = passes || path_random(state) >= alpha;
        }
        if (passes) {
            // On past it: the next cast starts just beyond this face.
            t_min = t + 1e-5 * max(1.0, t);
            continue;
        }
        mat3 linear = mat3(to_world);
        mat3 normal_matrix = transpose(inverse(linear));
        vec3 n = traced_vertex3(vertices, corner.x, 3u) * w.x + traced_vertex3(vertices, corner.y, 3u) * w.y
                 + traced_vertex3(vertices, corner.z, 3u) * w.z;
        n = normal_matrix * n;
        uint at0 = 12u * corner.x + 6u;
        uint at1 = 12u * corner.y + 6u;
        uint at2 = 12u * corner.z + 6u;
        vec4 tangent = vec4(vertices.values[at0], vertices.values[at0 + 1u], vertices.values[at0 + 2u],
                            vertices.values[at0 + 3u]) * w.x
                       + vec4(vertices.values[at1], vertices.values[at1 + 1u], vertices.values[at1 + 2u],
                              vertices.values[at1 + 3u]) * w.y
                       + vec4(vertices.values[at2], vertices.values[at2 + 1u], vertices.values[at2 + 2u],
                              vertices.values[at2 + 3u]) * w.z;
        surface.position = origin + direction * t;
        surface.normal = dot(n, n) > 1e-20 ? normalize(n) : geometric;
        surface.tangent = vec4(linear * tangent.xyz, tangent.w);
        surface.geometric = geometric;
        surface.uvs = uvs;
        surface.color = color;
        surface.material = what.x;
        surface.front = front;
        return true;
    }
    return false;
}


// A surface a ray met, set up to be lit as the forward pass lights a fragment: what its
// material makes of it (textures read at level 0), the normal made to face the viewer,
// the BRDF's inputs and view-dependent half, the layers over it, and what it lets
// through.
struct TracedShading {
    MaterialSurface s;
    vec3 n;          // the shading normal, facing the viewer (facing_view)
    vec3 along;      // the anisotropy direction, in the plane of `n`
    vec3 base;       // the base colour, clamped to [0, 1]
    vec3 film;       // the thin film: weight, IOR, thickness in nm (0: none)
    float transmits; // (1 − metalness) · transmission: what passes through
    BrdfInputs m;
    BrdfView view;
    SurfaceLayers layers;
};

// `surface` seen along unit `direction` (the viewer at −direction).
TracedShading traced_shading(PathSurface surface, vec3 direction) {
    GpuMaterial material = materials[surface.material];
    vec3 v = -direction;
    TracedShading h;
    h.s = material_surface_at(material, surface.front ? surface.normal : -surface.normal,
                              surface.tangent, surface.color, surface.uvs);
    h.base = clamp(h.s.base_color, 0.0, 1.0);
    h.n = facing_view(h.s.normal, v);
    h.along = normalize(h.s.direction - h.n * dot(h.n, h.s.direction));
    vec3 across = cross(h.n, h.along);
    // KHR_materials_transmission: the diffuse lobe keeps 1 − transmission; the rest of
    // what the surface does not reflect passes through it.
    h.transmits = (1.0 - h.s.metalness) * h.s.transmission;
    vec3 reflecting = h.transmits > 0.0 ? h.base * (1.0 - h.s.transmission) : h.base;
    h.m = brdf_inputs(material, reflecting, h.s.metalness, h.s.roughness, h.s.anisotropy,
                      round(srgb_encode(h.base) * 255.0));
    h.view = brdf_view(h.m, h.n, h.along, across, v);
#ifdef SPECULAR
    brdf_view_apply_specular(h.view, h.m, DielectricSpecular(h.s.specular_factor, h.s.specular_color));
#endif
    h.film = vec3(0.0);
#ifdef IRIDESCENCE
    h.film = vec3(h.s.film_weight, material.film.y, h.s.film_thickness_nm);
    brdf_view_apply_film(h.view, h.m, ThinFilm(h.film.x, h.film.y, h.film.z));
#endif
#ifdef CLEARCOAT
    h.layers.coat = surface_coat(material, h.m, h.s.clearcoat, h.s.clearcoat_roughness,
                                 facing_view(h.s.clearcoat_normal, v), v);
#else
    h.layers.coat = no_surface_coat();
#endif
#ifdef SHEEN
    h.layers.sheen = surface_sheen(h.s.sheen_color, h.s.sheen_roughness, h.view);
#else
    h.layers.sheen = no_surface_sheen();
#endif
    return h;
}

// Whether `material` is unlit (KHR_materials_unlit: its base colour is its radiance).
bool traced_unlit(GpuMaterial material) {
#ifndef NO_UNLIT
    return (material.diffuse_model_flags.y & MATERIAL_FLAG_UNLIT) != 0u;
#else
    return false;
#endif
}

// The light every light sends `surface` (shaded as `h`) and it reflects back along its
// view, each light's with a shadow ray from off the surface along its shading normal,
// ending short of a point light (the f64 reference's offset rule,
// combustion_reference::visibility); towards a light with a size, one point of the disc
// (or cone) the f64 reference samples for its visible fraction, drawn uniformly
// (`state`): that fraction in expectation.
vec3 traced_direct_light(PathSurface surface, TracedShading h, inout uint state) {
    vec3 radiance = vec3(0.0);
    float offset = surface_offset(surface.position);
    vec3 from = surface.position + h.n * offset;
    for (uint i = 0u; i < TRACED_LIGHT_COUNT; ++i) {
        vec3 l;
        vec3 irradiance;
        float reach = light_incidence(lights[i], surface.position, l, irradiance);
        if (!faces_surface(h.layers, h.n, l) || all(lessThanEqual(irradiance, vec3(0.0)))) {
            continue;
        }
        vec3 response = surface_response(h.m, h.view, h.layers, h.n, l) * irradiance;
        if (all(lessThanEqual(response, vec3(0.0)))) {
            continue;
        }
        float size = lights[i].spot_axis.w;
        vec2 d = vec2(0.0);
        if (size > 0.0) {
            vec2 u = vec2(path_random(state), path_random(state));
            d = sqrt(u.x) * vec2(cos(2.0 * PI * u.y), sin(2.0 * PI * u.y)) * size;
        }
        float clear = 1e30;
        if (reach < 1e30) {
            vec3 target = lights[i].position_or_direction.xyz;
            if (size > 0.0) {
                vec3 facing = surface.position - target;
                vec3 axis = dot(facing, facing) > 0.0 ? normalize(facing) : vec3(0.0, 0.0, 1.0);
                vec3 t;
                vec3 b;
                orthonormal_basis(axis, t, b);
                target += t * d.x + b * d.y;
            }
            clear = distance(from, target) - surface_offset(target);
            l = normalize(target - from);
        } else if (size > 0.0) {
            vec3 t;
            vec3 b;
            orthonormal_basis(l, t, b);
            l = normalize(l + t * d.x + b * d.y);
        }
        if (clear > 0.0 && !scene_blocks(from, l, clear)) {
            radiance += response;
        }
    }
    return radiance;
}

// G₁ of a direction below the surface (shading frame), as seen from below.
float path_g1_below(vec3 d, float ax, float ay) {
    return 1.0 / (1.0 + lambda_ggx_anisotropic(vec3(d.xy, -d.z), ax, ay));
}

// The direction light leaves a thin wall in towards the side opposite its viewer `v`:
// straight on where it is smooth; a rough one's two interfaces (each of α `ax`, `ay`)
// refract it — in through a microfacet the view sees, out through one of the far
// wall's — the pair kept with probability of both refracted rays' masking: drawn from
// by rejection, as the f64 path tracer draws it.
vec3 path_thin_wall_direction(vec3 n, vec3 along, vec3 v, float ax, float ay, float eta_i,
                              float eta_t, float roughness, inout uint state) {
    if (!(roughness > 0.0) || eta_i == eta_t) {
        return -v;
    }
    vec3 t = along - n * dot(n, along);
    vec3 b;
    if (!(dot(t, t) > 1e-20)) {
        orthonormal_basis(n, t, b);
    }
    t = normalize(t);
    b = cross(n, t);
    vec3 v_local = vec3(dot(v, t), dot(v, b), dot(v, n));
    for (int draw = 0; draw < 64; ++draw) {
        vec3 m_in = sample_ggx_vndf(v_local, ax, ay, vec2(path_random(state), path_random(state)));
        vec2 u_out = vec2(path_random(state), path_random(state));
        float accept = path_random(state);
        vec3 inside = refract(-v_local, m_in, eta_i / eta_t);
        if (dot(inside, inside) == 0.0) {
            continue;
        }
        vec3 m_out = sample_ggx_vndf(-inside, ax, ay, u_out);
        vec3 leaving = refract(inside, dot(m_out, inside) > 0.0 ? -m_out : m_out, eta_t / eta_i);
        if (dot(leaving, leaving) == 0.0 || !(inside.z < 0.0 && leaving.z < 0.0)) {
            continue;
        }
        if (accept < path_g1_below(inside, ax, ay) * path_g1_below(leaving, ax, ay)) {
            return normalize(t * leaving.x + b * leaving.y + n * leaving.z);
        }
    }
    return -v;
}

// `n` bent towards `towards` (unit) until their cosine is at least 1e-4 (the f64
// transmission's rule).
vec3 path_facing(vec3 n, vec3 towards) {
    float c = dot(n, towards);
    return c > 1e-4 ? n : normalize(n + (1e-4 - c) * towards);
}

// The unit normal of the interface a ray along `direction` meets at `hit`, facing the
// ray's way on (out of a volume it is inside), bent as path_facing bends it.
vec3 traced_outward(PathSurface hit, vec3 direction) {
    vec3 outward = dot(hit.normal, hit.geometric) < 0.0 ? -hit.normal : hit.normal;
    if (dot(hit.geometric, direction) < 0.0) {
        outward = -outward;
    }
    return path_facing(outward, direction);
}

// The radiance arriving at `origin` along unit `direction` from what the ray meets there:
// the surface's emission, every light's light with shadow rays and (ENVIRONMENT) the
// environment's split sum at its own material; the ray goes on through up to
// `thin_walls` thin-walled transmissive surfaces (each adding what it reflects and
// passing (1 − R)/(1 + R) per polarisation of the rest, tinted by its base colour, as the
// path tracer's thin walls do, straight on). Where it meets nothing, the environment's
// prefiltered radiance at level `lod` (nothing without an environment).
vec3 traced_radiance_along(vec3 origin, vec3 direction, float lod, uint thin_walls, inout uint state) {
    vec3 radiance = vec3(0.0);
    vec3 carried = vec3(1.0);
    for (uint walls = 0u; walls <= thin_walls; ++walls) {
        PathSurface hit;
        if (!path_next_surface(origin, direction, surface_offset(origin), true, state, hit)) {
#ifdef ENVIRONMENT
            radiance += carried * textureLod(environment_specular, direction, lod).rgb;
#endif
            break;
        }
        GpuMaterial material = materials[hit.material];
        if (traced_unlit(material)) {
            radiance += carried * material_surface_at(material, hit.front ? hit.normal : -hit.normal,
                                                      hit.tangent, hit.color, hit.uvs).base_color;
            break;
        }
        TracedShading h = traced_shading(hit, direction);
        vec3 reflected = h.s.emissive + traced_direct_light(hit, h, state);
#ifdef ENVIRONMENT
        reflected += environment_radiance(material, hit.material, h.m, h.view, h.layers, h.n, -direction,
                                          h.s.roughness, round(srgb_encode(h.base) * 255.0), 1.0);
#endif
        radiance += carried * reflected;
        if (!(h.transmits > 0.0) || material.transmission_thickness.y > 0.0 || walls == thin_walls) {
            break;
        }
        // Through a thin wall, straight on.
        Crossing entry = surface_crossing(clamp(dot(h.n, -direction), 0.0, 1.0), h.m.outside_eta,
                                          h.m.dielectric_eta, h.film);
        vec3 rs = 1.0 - entry.s;
        vec3 rp = 1.0 - entry.p;
        float out_layers = h.layers.coat.view.attenuation_v
            * (1.0 - clamp(max(h.layers.sheen.color.r, max(h.layers.sheen.color.g, h.layers.sheen.color.b)), 0.0, 1.0)
               * h.layers.sheen.albedo_v);
        carried *= mix((1.0 - rs) / (1.0 + rs), (1.0 - rp) / (1.0 + rp), h.m.polarisation_weight)
                 * h.transmits * out_layers * h.base;
        origin = hit.position;
    }
    return radiance;
}

#endif
