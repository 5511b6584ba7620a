// What lights a surface, shared by the passes that shade (the lighting pass from the
// G-buffer, the forward pass from the blended objects' own fragments): the BRDF's inputs
// from a material and a surface's values, one light's reflected radiance (times its
// shadow maps' verdict in the SHADOWS variant), and the environment's split sum
// (ENVIRONMENT variant). Needs gpu_types.glsl, brdf.glsl, the generated constants, and a
// set declaring `materials`, `lights`, `conductor_from_code`, `energy_white_albedo` and
// the environment's and shadows' bindings as bindings::LIGHTING does (shadows.glsl
// included first in the SHADOWS variant).
#ifndef COMBUSTION_LIGHTING_TERMS_GLSL
#define COMBUSTION_LIGHTING_TERMS_GLSL

// The entries and weights about the table position x (in entries, within the table).
uvec4 bilinear_at(vec2 x, uint size, out vec2 f) {
    uvec2 i0 = uvec2(x);
    uvec2 i1 = min(i0 + 1u, uvec2(size - 1u));
    f = x - vec2(i0);
    return uvec4(i0.y * size + i0.x, i0.y * size + i1.x, i1.y * size + i0.x, i1.y * size + i1.x);
}

// The four entries (row-major indices into a size × size table: (x0,y0), (x1,y0),
// (x0,y1), (x1,y1)) and weights of a bilinear lookup at coord in [0, 1]², entry i at
// i/(size − 1) (vertex-centred: combustion_optics::environment::table_coordinate) and
// clamped at the edges, as the GGX albedo tables are read.
uvec4 bilinear_entries(vec2 coord, uint size, out vec2 f) {
    return bilinear_at(clamp(coord * float(size - 1u), vec2(0.0), vec2(float(size - 1u))), size, f);
}

// The same for a cell-centred table (entry i at (i + ½)/size), as the sheen's tables are
// read (combustion_optics::sheen::sheen_albedo_lookup).
uvec4 bilinear_cells(vec2 coord, uint size, out vec2 f) {
    return bilinear_at(clamp(coord * float(size) - 0.5, vec2(0.0), vec2(float(size - 1u))), size, f);
}

#ifdef ENERGY_COMPENSATION
// E(μ, α) bilinear in the white specular albedo table over (μ, r = √α)
// (combustion_renderer::environment::white_specular_albedo_table), ENERGY_TABLE_SIZE²
// entries (bindings/constants.glsl).
float energy_white_albedo_lookup(float cos_v, float alpha) {
    vec2 f;
    uvec4 c = bilinear_entries(vec2(cos_v, sqrt(max(alpha, 0.0))), ENERGY_TABLE_SIZE, f);
    return mix(mix(energy_white_albedo[c.x], energy_white_albedo[c.y], f.x),
               mix(energy_white_albedo[c.z], energy_white_albedo[c.w], f.x), f.y);
}
#endif

// The clear coat of the surface being shaded (KHR_materials_clearcoat; read only in
// CLEARCOAT variants): its inputs, its view half and its perceptual roughness.
struct SurfaceCoat {
    CoatInputs inputs;
    CoatView view;
    float roughness;
};

// The coat of weight `weight`, perceptual roughness `roughness` and unit normal `normal`
// over a surface of `material` (its coat IOR) whose BRDF inputs are `m` (its outside
// medium and polarisation weight), seen from `v`.
SurfaceCoat surface_coat(GpuMaterial material, BrdfInputs m, float weight, float roughness,
                         vec3 normal, vec3 v) {
    SurfaceCoat coat;
    coat.inputs.factor = weight;
    coat.inputs.alpha = alpha_from_perceptual_roughness(roughness);
    coat.inputs.eta = material.clearcoat.z;
    coat.inputs.outside_eta = m.outside_eta;
    coat.inputs.polarisation_weight = m.polarisation_weight;
    coat.view = coat_view(coat.inputs, normal, v);
    coat.roughness = roughness;
    return coat;
}

// The sheen of the surface being shaded (KHR_materials_sheen; read only in SHEEN
// variants), on the base's shading normal (the BRDF view's frame): its colour, α, its
// perceptual roughness and E(n·v).
struct SurfaceSheen {
    vec3 color;
    float alpha;
    float roughness;
    float albedo_v;
};

// What lies over the BRDF: the coat on top, the sheen under it (crates/optics/src/
// layers.rs).
struct SurfaceLayers {
    SurfaceCoat coat;
    SurfaceSheen sheen;
};

#ifdef SHEEN
// Bilinear in table `table` of the sheen's buffer (0: E(μ, r) of the white sheen lobe,
// combustion_optics::sheen::sheen_albedo_lookup; 1: M(μ, r), sheen_scaling_table).
float sheen_table_lookup(uint table, float mu, float r) {
    vec2 f;
    uvec4 c = bilinear_cells(vec2(mu, r), SHEEN_TABLE_SIZE, f)
            + table * SHEEN_TABLE_SIZE * SHEEN_TABLE_SIZE;
    return mix(mix(sheen_albedo[c.x], sheen_albedo[c.y], f.x),
               mix(sheen_albedo[c.z], sheen_albedo[c.w], f.x), f.y);
}

float sheen_albedo_lookup(float mu, float r) {
    return sheen_table_lookup(0u, mu, r);
}

// The sheen of colour `color` and perceptual roughness `roughness` seen as `view` sees.
SurfaceSheen surface_sheen(vec3 color, float roughness, BrdfView view) {
    SurfaceSheen sheen;
    sheen.color = clamp(color, 0.0, 1.0);
    sheen.roughness = clamp(roughness, 0.0, 1.0);
    sheen.alpha = sheen.roughness * sheen.roughness;
    sheen.albedo_v = sheen_albedo_lookup(view.v.z, sheen.roughness);
    return sheen;
}
#endif

// No sheen: what variants without SHEEN pass (and never read).
SurfaceSheen no_surface_sheen() {
    SurfaceSheen sheen;
    sheen.color = vec3(0.0);
    sheen.alpha = 1.0;
    sheen.roughness = 1.0;
    sheen.albedo_v = 0.0;
    return sheen;
}

// No coat: what variants without CLEARCOAT pass (and never read).
SurfaceCoat no_surface_coat() {
    SurfaceCoat coat;
    coat.inputs = CoatInputs(0.0, 1.0, 1.0, 1.0, 0.5);
    coat.view.frame = mat3(1.0);
    coat.view.v = vec3(0.0, 0.0, 1.0);
    coat.view.alpha = 1.0;
    coat.view.factor = 0.0;
    coat.view.w = 0.5;
    coat.view.visibility_half = vec2(1.0);
    coat.view.attenuation_v = 1.0;
    coat.roughness = 1.0;
    return coat;
}

#ifdef ENVIRONMENT
#include "environment.glsl"

// Bilinear lookup in material `material`'s albedo table (environment_albedo.comp), part
// `part` (0: specular, 1: diffuse), at (n·v, r); vertex-centred, clamped at the edges.
vec4 environment_table(uint material, uint part, vec2 coord) {
    vec2 f;
    uvec4 c = bilinear_entries(coord, ENVIRONMENT_TABLE_SIZE, f)
            + material * ENVIRONMENT_TABLE_SIZE * ENVIRONMENT_TABLE_SIZE;
    c = c * 2u + part;
    return mix(mix(environment_albedo[c.x], environment_albedo[c.y], f.x),
               mix(environment_albedo[c.z], environment_albedo[c.w], f.x), f.y);
}

// The same in per-code table `table` (environment_code_albedo.comp), code `code`.
float environment_code_table(uint table, uint code, vec2 coord) {
    vec2 f;
    uvec4 c = bilinear_entries(coord, ENVIRONMENT_CODE_TABLE_SIZE, f)
            + (table * 256u + code) * ENVIRONMENT_CODE_TABLE_SIZE * ENVIRONMENT_CODE_TABLE_SIZE;
    return mix(mix(environment_code_albedo[c.x], environment_code_albedo[c.y], f.x),
               mix(environment_code_albedo[c.z], environment_code_albedo[c.w], f.x), f.y);
}

// The environment's occlusion: glTF occlusion textures (OCCLUSION) or an occlusion pass
// (AMBIENT_OCCLUSION, RAY_TRACED_OCCLUSION), applied one way (the pass's visibility and the
// texture's combined by their minimum in lighting.frag).
#if defined(OCCLUSION) || defined(AMBIENT_OCCLUSION) || defined(RAY_TRACED_OCCLUSION)
#define ENVIRONMENT_OCCLUSION
#endif

#ifdef ENVIRONMENT_OCCLUSION
// Lagarde & de Rousiers' (2014, eq. 58) specular occlusion from the glTF occlusion, at n·v
// and the lobe's α: weaker than the diffuse occlusion at normal incidence and on smooth
// surfaces (the reference's twin: ReferenceShading::shade_environment).
float specular_occlusion_of(float nv, float alpha, float occlusion) {
    return clamp(pow(nv + occlusion, exp2(-16.0 * alpha - 1.0)) - 1.0 + occlusion, 0.0, 1.0);
}
#endif

// The split-sum environment term (combustion_renderer::environment): the prefiltered
// radiance along the mirror direction times the material's specular directional albedo
// (full Fresnel), plus the cosine-weighted mean radiance about n times its diffuse
// albedo ρ D1 + ρ² D2. Anisotropic pixels use the roughness of their mean α.
// A clear coat (CLEARCOAT variants) adds its own lobe the same way, from its albedo in
// the table ([1].z at (n_c·v, its roughness)) times its weight, along its own mirror
// direction, and attenuates the rest by A(v)², the light arriving about the mirror
// direction crossing the coat at the angle the view leaves it.
// A sheen (SHEEN variants) adds c E(n·v) times the most blurred radiance on a ring about
// n at the lobe's mean cosine (its lobe is broad and gathers towards the horizon: no one
// mirror direction stands for it), and scales the base's term by 1 − max(c) M(n·v), the
// extension's scaling averaged over cosine-weighted light.
// The base's specular lookup of the split-sum term: its direction and level, and the
// weight its prefiltered radiance was added with (the specular albedo, times what a sheen
// or coat over it scales it by): what ray-traced reflections replace.
struct SpecularLookup {
    vec3 direction;
    float lod;
    vec3 weight;
};

// environment_radiance, with its base's specular lookup (`lookup.weight` 0 where none).
vec3 environment_radiance_looked_up(GpuMaterial material, uint material_index, BrdfInputs m,
                                    BrdfView view, SurfaceLayers layers, vec3 n, vec3 v,
                                    float roughness, vec3 base_color_code, float occlusion,
                                    out SpecularLookup lookup) {
    SurfaceCoat coat = layers.coat;
    float nv = view.v.z;
    lookup.direction = n;
    lookup.lod = 0.0;
    lookup.weight = vec3(0.0);
    if (!(nv > 0.0)) {
        return vec3(0.0);
    }
#ifndef NO_ANISOTROPY
    bool anisotropic = view.ax != view.ay;
    // An anisotropic lobe is looked up (tables and cube) at the roughness of its mean α
    // (an isotropic one at its own r, as the specialised pipeline without anisotropy).
    if (anisotropic) {
        roughness = sqrt(0.5 * (view.ax + view.ay));
    }
#endif
    float alpha = roughness * roughness;
    vec2 coord = vec2(nv, roughness);
    vec4 specular = environment_table(material_index, 0u, coord);
    vec4 diffuse = environment_table(material_index, 1u, coord);
    vec3 conductor = specular.rgb;
    if ((material.diffuse_model_flags.y & MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR) != 0u) {
        uint table = environment_code_table_of_material[material_index];
        uvec3 code = uvec3(base_color_code);
        conductor = vec3(environment_code_table(table, code.r, coord),
                         environment_code_table(table, code.g, coord),
                         environment_code_table(table, code.b, coord));
    }
    float metal = view.metal;
    vec3 rho = clamp(m.base_color, vec3(0.0), vec3(1.0));
    // Occlusion (glTF occlusion textures or an occlusion pass: ENVIRONMENT_OCCLUSION; 1
    // otherwise) darkens the
    // diffuse term as it is, and the specular term by Lagarde & de Rousiers' (2014,
    // eq. 58) specular occlusion, weaker than the diffuse occlusion at normal incidence
    // and on smooth surfaces; direct lights are never occluded.
#ifdef ENVIRONMENT_OCCLUSION
    float specular_occlusion = specular_occlusion_of(nv, alpha, occlusion);
#else
    const float specular_occlusion = 1.0;
#endif
#ifdef ENERGY_COMPENSATION
    vec3 specular_albedo = ((1.0 - metal) * specular.a * view.compensation_dielectric
                            + metal * conductor * view.compensation_conductor) * specular_occlusion;
#else
    vec3 specular_albedo = ((1.0 - metal) * specular.a + metal * conductor) * specular_occlusion;
#endif
    vec3 diffuse_albedo = (1.0 - metal) * (rho * diffuse.x + rho * rho * diffuse.y) * occlusion;
    // The dielectric's specular albedo per channel (the table's, or with a specular
    // strength and colour, below).
    vec3 dielectric_albedo = vec3(specular.a);
#ifdef SPECULAR
    // KHR_materials_specular: F′ is affine in the bare reflectance F per channel,
    // F′ = factor ((F₀′ − F₀ k) + k F), k = (1 − F₀′)/(1 − F₀), so its albedo is
    // factor ((F₀′ − F₀ k) E_white + k E_F) from the table's white lobe ([1].w) and its
    // dielectric's ([0].a) (F′'s clamp to [0, 1] left out). The diffuse albedo × T′/T of
    // both crossings: at n·v, and at n·l = ½ for the light's (where the bare T equals its
    // cosine-weighted mean over the hemisphere for IORs about 1.5).
    if (view.specular_present) {
        float f0 = view.bare_f0;
        vec3 k = f0 < 1.0 ? (1.0 - view.specular_f0) / (1.0 - f0) : vec3(0.0);
        dielectric_albedo = view.specular_factor
                          * ((view.specular_f0 - f0 * k) * diffuse.w + k * specular.a);
#ifdef ENERGY_COMPENSATION
        specular_albedo = ((1.0 - metal) * dielectric_albedo * view.compensation_dielectric
                           + metal * conductor * view.compensation_conductor) * specular_occlusion;
#else
        specular_albedo = ((1.0 - metal) * dielectric_albedo + metal * conductor) * specular_occlusion;
#endif
        float bare_v = brdf_dielectric_transmittance(m, view, nv);
        float bare_l = brdf_dielectric_transmittance(m, view, 0.5);
        float specular_l = specular_transmittance(view, brdf_dielectric_fresnel(m, view, 0.5));
        diffuse_albedo *= (bare_v > 1e-4 ? view.transmittance_v / bare_v : 1.0)
                        * (bare_l > 1e-4 ? specular_l / bare_l : 1.0);
    }
#endif
#ifdef IRIDESCENCE
    // A thin film: each specular albedo × the film's mixed reflectance over the base's at
    // n·v, the diffuse albedo × its transmittance over the base's at n·v (the tables
    // integrate the base's Fresnel; the film's is taken as varying over the lobe as the
    // base's does). Where the base reflects nothing at n·v the terms are left.
    if (view.film.weight > 0.0) {
        float w = view.w;
        vec3 f_dielectric = vec3(polarised_weighted(fresnel_dielectric(nv, m.outside_eta, m.dielectric_eta), w));
#ifdef SPECULAR
        if (view.specular_present) {
            f_dielectric = specular_reflectance(view, f_dielectric.x);
        }
#endif
        vec3 f_conductor = fresnel_conductor_rgb(nv, m.outside_eta, m.conductor_eta, m.conductor_k, w);
        vec3 r_conductor = thin_film_reflectance_weighted(nv, m.outside_eta, view.film,
                                                          m.conductor_eta, m.conductor_k, w);
        vec3 dielectric_scale = vec3(1.0);
        vec3 conductor_scale = vec3(1.0);
        for (int c = 0; c < 3; ++c) {
            if (f_dielectric[c] > 1e-4) {
                dielectric_scale[c] = (f_dielectric[c] + view.film.weight * (view.film_reflectance_v[c] - f_dielectric[c]))
                                    / f_dielectric[c];
            }
            if (f_conductor[c] > 1e-4) {
                conductor_scale[c] = (f_conductor[c] + view.film.weight * (r_conductor[c] - f_conductor[c]))
                                   / f_conductor[c];
            }
        }
        vec3 dielectric_part = (1.0 - metal) * dielectric_albedo;
        vec3 conductor_part = metal * conductor;
#ifdef ENERGY_COMPENSATION
        dielectric_part *= view.compensation_dielectric;
        conductor_part *= view.compensation_conductor;
#endif
        specular_albedo = (dielectric_part * dielectric_scale + conductor_part * conductor_scale)
                        * specular_occlusion;
        if (view.transmittance_v > 1e-4) {
            diffuse_albedo *= view.film_transmittance_v / view.transmittance_v;
        }
    }
#endif
    // The lookup direction: for anisotropic pixels the reflection about a normal bent
    // towards the one the stretched lobe favours (McAuley 2015, as Filament does); then
    // the lobe's dominant direction, pulled from the mirror direction towards the normal
    // as roughness grows (Lagarde & de Rousiers 2014, eq. 55).
    vec3 lookup_normal = n;
#ifndef NO_ANISOTROPY
    float strength = anisotropic ? abs(view.ax - view.ay) / max(view.ax, view.ay) : 0.0;
    if (strength > 0.0) {
        vec3 direction = view.ax > view.ay ? view.frame[1] : view.frame[0];
        vec3 anisotropic_normal = cross(cross(direction, v), direction);
        float bend = strength * clamp(5.0 * roughness, 0.0, 1.0);
        lookup_normal = normalize(mix(n, anisotropic_normal, bend));
    }
#endif
    float smoothness = 1.0 - alpha;
    vec3 r = normalize(mix(n, reflect(-v, lookup_normal), smoothness * (sqrt(smoothness) + alpha)));
    float levels = float(textureQueryLevels(environment_specular) - 1);
    float lod = clamp(roughness, 0.0, 1.0) * levels;
    vec3 radiance = textureLod(environment_specular, r, lod).rgb * specular_albedo
                  + textureLod(environment_irradiance, n, 0.0).rgb * diffuse_albedo;
    lookup.direction = r;
    lookup.lod = lod;
    lookup.weight = specular_albedo;
#ifdef SHEEN
    SurfaceSheen sheen = layers.sheen;
    float sheen_max = max(sheen.color.r, max(sheen.color.g, sheen.color.b));
    if (sheen_max > 0.0) {
        float scaling = 1.0 - min(sheen_max, 1.0) * sheen_table_lookup(1u, view.v.z, sheen.roughness);
        // The lobe gathers towards the horizon: the most blurred radiance on a ring about n
        // at the lobe's mean cosine (cos-weighted, from the f64 lobe: 0.23–0.37 at r = 0.3,
        // 0.40–0.49 at 0.5, 0.55–0.58 at 1 over n·v from 1 to 0.4; ≈ 0.6 √r), four taps.
        vec3 t1 = normalize(abs(n.z) < 0.9 ? cross(n, vec3(0.0, 0.0, 1.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
        vec3 t2 = cross(n, t1);
        float ring_cos = max(0.6 * sqrt(sheen.roughness), 0.1);
        float ring_sin = sqrt(1.0 - ring_cos * ring_cos);
        vec3 ring = vec3(0.0);
        for (int k = 0; k < 4; ++k) {
            float phi = float(k) * 1.5707963;
            vec3 d = n * ring_cos + (t1 * cos(phi) + t2 * sin(phi)) * ring_sin;
            ring += textureLod(environment_specular, d, levels).rgb;
        }
        radiance = radiance * scaling + 0.25 * ring * sheen.color * sheen.albedo_v * occlusion;
        lookup.weight *= scaling;
    }
#endif
#ifdef CLEARCOAT
    if (coat.view.factor > 0.0) {
        float nv_coat = coat.view.v.z;
        vec3 n_coat = coat.view.frame[2];
        float r_coat = clamp(coat.roughness, 0.0, 1.0);
        float a_coat = r_coat * r_coat;
        float albedo = nv_coat > 0.0
            ? environment_table(material_index, 1u, vec2(nv_coat, r_coat)).z : 0.0;
#ifdef ENVIRONMENT_OCCLUSION
        albedo *= clamp(pow(max(nv_coat, 0.0) + occlusion, exp2(-16.0 * a_coat - 1.0)) - 1.0 + occlusion,
                        0.0, 1.0);
#endif
        float smooth_coat = 1.0 - a_coat;
        vec3 r_c = normalize(mix(n_coat, reflect(-v, n_coat), smooth_coat * (sqrt(smooth_coat) + a_coat)));
        radiance = radiance * (coat.view.attenuation_v * coat.view.attenuation_v)
                 + textureLod(environment_specular, r_c, r_coat * levels).rgb * (coat.view.factor * albedo);
        lookup.weight *= coat.view.attenuation_v * coat.view.attenuation_v;
    }
#endif
    return radiance;
}

vec3 environment_radiance(GpuMaterial material, uint material_index, BrdfInputs m, BrdfView view,
                          SurfaceLayers layers, vec3 n, vec3 v, float roughness,
                          vec3 base_color_code, float occlusion) {
    SpecularLookup unused;
    return environment_radiance_looked_up(material, material_index, m, view, layers, n, v, roughness,
                                          base_color_code, occlusion, unused);
}
#endif

// The BRDF's inputs at a surface of `material` whose linear base colour, metalness,
// perceptual roughness and anisotropy strength are these; `base_color_code` is the base
// colour's 8-bit sRGB codes (round(255 · sRGB)), which index the conductor table of a
// conductor derived from its base colour.
BrdfInputs brdf_inputs(GpuMaterial material, vec3 base_color, float metalness, float roughness,
                       float anisotropy, vec3 base_color_code) {
    float alpha = alpha_from_perceptual_roughness(roughness);
    vec2 alphas = anisotropic_alphas(alpha, anisotropy);
    BrdfInputs m;
    m.base_color = base_color;
    m.metalness = metalness;
    m.alpha_x = alphas.x;
    m.alpha_y = alphas.y;
    m.conductor_eta = material.conductor_eta_outside_ior.rgb;
    m.conductor_k = material.conductor_k_polarisation.rgb;
#ifndef NO_CONDUCTOR_TABLE
    if ((material.diffuse_model_flags.y & MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR) != 0u) {
        ivec3 code = ivec3(base_color_code);
        vec2 red = conductor_from_code[code.r];
        vec2 green = conductor_from_code[code.g];
        vec2 blue = conductor_from_code[code.b];
        m.conductor_eta = vec3(red.x, green.x, blue.x);
        m.conductor_k = vec3(red.y, green.y, blue.y);
    }
#endif
    m.dielectric_eta = material.roughness_anisotropy_ior.w;
#ifdef OUTSIDE_ETA_ONE
    m.outside_eta = 1.0;  // every material's, as the table holds it
#else
    m.outside_eta = material.conductor_eta_outside_ior.a;
#endif
    m.polarisation_weight = material.conductor_k_polarisation.a;
    m.diffuse_model = material.diffuse_model_flags.x;
    m.oren_nayar_sigma = oren_nayar_sigma_from_roughness(roughness);
    return m;
}

// Whether light from `l` reaches the surface: n·l > 0, or (CLEARCOAT) a coat with its own
// normal faces it.
bool faces_surface(SurfaceLayers layers, vec3 n, vec3 l) {
#ifdef CLEARCOAT
    SurfaceCoat coat = layers.coat;
    return dot(n, l) > 0.0 || (coat.view.factor > 0.0 && dot(coat.view.frame[2], l) > 0.0);
#else
    return dot(n, l) > 0.0;
#endif
}

// What a unit irradiance from `l` (normal to l) reflects towards the eye: f(v, l)(n·l),
// the sheen over the base (SHEEN) and each layer lit with the cosine to its own normal
// under a coat (CLEARCOAT, brdf.glsl's coated_radiance). Zero unless faces_surface.
vec3 surface_response(BrdfInputs m, BrdfView view, SurfaceLayers layers, vec3 n, vec3 l) {
    if (!faces_surface(layers, n, l)) {
        return vec3(0.0);
    }
    float n_dot_l = dot(n, l);
    vec3 f = brdf_evaluate_view(m, view, l);
#ifdef SHEEN
    // The sheen over the base (crates/optics/src/layers.rs): c D V + s f_base.
    SurfaceSheen sheen = layers.sheen;
    if (max(sheen.color.r, max(sheen.color.g, sheen.color.b)) > 0.0) {
        vec3 ll = shading_frame_to_local(view.frame, safe_normalize(l));
        float scaling = sheen_albedo_scaling(sheen.color, sheen.albedo_v,
                                             sheen_albedo_lookup(ll.z, sheen.roughness));
        f = sheen.color * sheen_lobe(view.v, ll, sheen.alpha) + scaling * f;
    }
#endif
#ifdef CLEARCOAT
    SurfaceCoat coat = layers.coat;
    if (coat.view.factor > 0.0) {
        return coated_radiance(f, n_dot_l, coat.view, coat_evaluate_view(coat.inputs, coat.view, l));
    }
#endif
    return f * n_dot_l;
}

#if (defined(ENVIRONMENT) && defined(ENVIRONMENT_SAMPLES)) || defined(PATH_TRACE)
// Density of directions l (shading frame) that reflecting v about a normal drawn from
// GGX's visible normals (sample_ggx_vndf) gives: D_v(h) / (4 v·h) = G1(v) D(h) / (4 n·v).
float pdf_ggx_vndf_reflection(vec3 v, vec3 l, float ax, float ay) {
    if (!(l.z > 0.0) || !(v.z > 0.0)) {
        return 0.0;
    }
    vec3 h = normalize(v + l);
    float g1 = 1.0 / (1.0 + lambda_ggx_anisotropic(v, ax, ay));
    return g1 * d_ggx_anisotropic(h, ax, ay) / (4.0 * v.z);
}
#endif

#if defined(ENVIRONMENT) && defined(ENVIRONMENT_SAMPLES)

// A hash of the pixel to [0, 1)² (PCG), which turns each pixel's sample set.
vec2 pixel_rotation(vec2 pixel) {
    uvec2 p = uvec2(pixel);
    uint state = p.x * 747796405u + p.y * 2891336453u + 1u;
    uint a = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    a = (a >> 22u) ^ a;
    uint b = a * 747796405u + 2891336453u;
    b = ((b >> ((b >> 28u) + 4u)) ^ b) * 277803737u;
    b = (b >> 22u) ^ b;
    return vec2(a, b) * 2.3283064365386963e-10;
}

#ifdef ENVIRONMENT_SAMPLE_VISIBILITY
#include "traced_scene.glsl"

// Whether the environment is seen from `origin` along `direction`: nothing of the scene
// (its acceleration structure as the ray-traced occlusion pass built it) in the way.
bool environment_open(vec3 origin, vec3 direction) {
    return !scene_blocks(origin, direction, 1e30);
}
#endif

// The environment's share of the radiance towards the eye, integrated by sampling
// (ShadingOptions::environment_samples): ENVIRONMENT_SAMPLES points of the Hammersley set,
// turned per pixel and per `seed` (FrameInputs::environment_seed), each giving one
// direction from GGX's visible normals and one from the cosine, combined by the balance
// heuristic: Σ V(l) L(l) r(l) / (p_ggx(l) + p_cos(l)) / N, r = surface_response and L the
// radiance cube's finest level. V is 1 unless ENVIRONMENT_SAMPLE_VISIBILITY: then each
// direction is traced from `origin` against the scene (0 where something is in the
// way) — the rendering equation's direct environment light with the scene's geometry.
// Occlusion (`occlusion`: glTF textures and the screen-space pass) as the split sum
// applies it: the diffuse term × occlusion, the rest × the specular occlusion at the
// lobe's α (`roughness`: the perceptual roughness, as environment_radiance takes it); the
// rest is the response over a black base colour. With traced visibility, the occlusion
// applied is what the traced directions have not already counted: min(1, occlusion /
// V̂), V̂ the share of the cosine directions that were open — the diffuse visibility is
// then min(occlusion, V̂), the rule the split sum's passes follow.
vec3 environment_sampled(BrdfInputs m, BrdfView view, SurfaceLayers layers, vec3 n,
                         vec2 pixel, uint seed, float occlusion, float roughness, vec3 origin) {
    if (!(view.v.z > 0.0)) {
        return vec3(0.0);
    }
#ifdef ENVIRONMENT_OCCLUSION
    BrdfInputs black = m;
    black.base_color = vec3(0.0);
    vec3 sum_rest = vec3(0.0);
#endif
#ifdef ENVIRONMENT_SAMPLE_VISIBILITY
    uint cosine_open = 0u;
    uint cosine_drawn = 0u;
#endif
    const uint count = uint(ENVIRONMENT_SAMPLES);
    // Seed k turns every pixel's set further by the k-th point of the R2 sequence
    // (Roberts 2018), so frames of successive seeds draw independent sets.
    vec2 turn = fract(pixel_rotation(pixel) + float(seed) * vec2(0.7548776662, 0.5698402910));
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < count; ++i) {
        vec2 u = fract(hammersley(i, count) + turn);
        vec3 h = sample_ggx_vndf(view.v, view.ax, view.ay, u);
        vec3 candidates[2] = vec3[2](reflect(-view.v, h), sample_cosine(u));
        for (int k = 0; k < 2; ++k) {
            vec3 l = candidates[k];
            float pdf = pdf_ggx_vndf_reflection(view.v, l, view.ax, view.ay) + max(l.z, 0.0) * INV_PI;
            if (!(pdf > 0.0)) {
                continue;
            }
            vec3 world = normalize(view.frame * l);
            vec3 response = surface_response(m, view, layers, n, world);
#ifdef ENVIRONMENT_SAMPLE_VISIBILITY
            // Cosine directions are always traced (their open share is V̂); others only
            // where they would add light.
            if (k == 1 || any(greaterThan(response, vec3(0.0)))) {
                bool open = environment_open(origin, world);
                if (k == 1) {
                    ++cosine_drawn;
                    cosine_open += open ? 1u : 0u;
                }
                if (!open) {
                    continue;
                }
            }
#endif
            vec3 radiance = textureLod(environment_specular, world, 0.0).rgb / pdf;
#ifdef ENVIRONMENT_OCCLUSION
            sum_rest += surface_response(black, view, layers, n, world) * radiance;
#endif
            sum += response * radiance;
        }
    }
#ifdef ENVIRONMENT_OCCLUSION
    float applied = occlusion;
#ifdef ENVIRONMENT_SAMPLE_VISIBILITY
    float traced = float(cosine_open) / float(max(cosine_drawn, 1u));
    applied = traced > 0.0 ? min(1.0, occlusion / traced) : 1.0;
#endif
    float alpha = view.ax != view.ay ? 0.5 * (view.ax + view.ay) : roughness * roughness;
    float occlusion_specular = specular_occlusion_of(view.v.z, alpha, applied);
    sum = sum_rest * occlusion_specular + (sum - sum_rest) * applied;
#endif
    return sum / float(count);
}
#endif

// The radiance `light` reflects towards the eye from a surface at `position` with shading
// normal `n` (the BRDF's inputs `m` and view half `view`; in CLEARCOAT variants under
// `coat`, each layer lit with the cosine to its own normal, brdf.glsl's
// coated_radiance): f(v, l) E (n·l), times the
// light's shadow maps' verdict in the SHADOWS variant (`eye`: the camera's position,
// `pixel`: the fragment's window coordinates, for the cascade choice and the filter's
// noise).
// The direction `l` from `position` to `light` (unit) and the irradiance it gives there
// on a surface facing it (inverse-square law, range window, spot cone); returns the
// distance to the light (infinite for a directional light).
float light_incidence(GpuLight light, vec3 position, out vec3 l, out vec3 irradiance) {
    if (light.power_kind.a != LIGHT_KIND_DIRECTIONAL) {
        vec3 to_light = light.position_or_direction.xyz - position;
        float distance_squared = max(dot(to_light, to_light), 1e-12);
        l = to_light * inversesqrt(distance_squared);
        irradiance = light.power_kind.rgb / distance_squared;
        if (light.spot_cone.z != 0.0) {  // a range: the window (none: exact 1/d²)
            irradiance *= range_attenuation(light, distance_squared);
        }
        if (light.power_kind.a == LIGHT_KIND_SPOT) {
            irradiance *= spot_attenuation(light, l);
        }
        return sqrt(distance_squared);
    }
    l = -light.position_or_direction.xyz;
    irradiance = light.power_kind.rgb;
    return 3.0e38;
}

vec3 light_radiance(BrdfInputs m, BrdfView view, SurfaceLayers layers, GpuLight light,
                    vec3 position, vec3 n, vec3 eye, vec2 pixel) {
    vec3 l;
    vec3 irradiance;
    light_incidence(light, position, l, irradiance);
    if (!faces_surface(layers, n, l)) {
        return vec3(0.0);
    }
#ifdef SHADOWS
    if (light.spot_cone.w != 0.0) {
        irradiance *= shadow_visibility_of(light, uint(light.spot_cone.w) - 1u, position, eye, n, l,
                                           pixel);
    }
#endif
    return surface_response(m, view, layers, n, l) * irradiance;
}

#endif
