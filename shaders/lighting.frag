#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Lighting pass: reads the G-buffer and depth, the material table and the lights, and
// writes HDR radiance (W·sr⁻¹·m⁻² per RGB channel). Mirrored on the CPU by
// combustion_renderer::reference (the parity tests and the viewer's error view).
// Specialised per scene (combustion_renderer::LightingFeatures): NO_ANISOTROPY,
// NO_CONDUCTORS, NO_CONDUCTOR_TABLE, NO_DIELECTRICS, OUTSIDE_ETA_ONE, NO_LAMBERT,
// NO_OREN_NAYAR_QUALITATIVE, NO_OREN_NAYAR_FULL, NO_UNLIT remove what the scene cannot use;
// SHADOWS (a shading option) multiplies each shadowed light by its shadow maps' verdict.
#include "gpu_types.glsl"
#include "gbuffer_encoding.glsl"
#include "srgb.glsl"
#include "brdf.glsl"

#include "bindings/lighting.glsl"  // set 0: see combustion_renderer::bindings::LIGHTING
#include "bindings/constants.glsl"  // generated from the renderer's Rust constants

layout(push_constant) uniform LightingPush {
    mat4 inverse_view_projection;
    vec4 camera_position;
    uvec4 counts;  // x: light count; y: debug view (DEBUG_VIEWS variant; 0: none);
                   // z: tiles across (0: no culling, every light); w: tile list stride
    vec4 background;  // where no surface is: rgb radiance, or w = 1: the environment's
} push;

#ifdef DEBUG_VIEWS
#include "debug_views.glsl"
#endif

#ifdef SHADOWS
#include "shadows.glsl"
#endif

// The four cells (row-major indices into a size × size table: (x0,y0), (x1,y0), (x0,y1),
// (x1,y1)) and weights of a bilinear lookup at coord in [0, 1]², cell-centred and
// clamped at the edges, as every albedo table here is read.
uvec4 bilinear_cells(vec2 coord, uint size, out vec2 f) {
    vec2 x = clamp(coord * float(size) - 0.5, vec2(0.0), vec2(float(size - 1u)));
    uvec2 i0 = uvec2(x);
    uvec2 i1 = min(i0 + 1u, uvec2(size - 1u));
    f = x - vec2(i0);
    return uvec4(i0.y * size + i0.x, i0.y * size + i1.x, i1.y * size + i0.x, i1.y * size + i1.x);
}

#ifdef ENERGY_COMPENSATION
// E(μ, α) bilinear in the white specular albedo table over (μ, r = √α)
// (combustion_renderer::environment::white_specular_albedo_table), ENERGY_TABLE_SIZE²
// entries (bindings/constants.glsl).
float energy_white_albedo_lookup(float cos_v, float alpha) {
    vec2 f;
    uvec4 c = bilinear_cells(vec2(cos_v, sqrt(max(alpha, 0.0))), ENERGY_TABLE_SIZE, f);
    return mix(mix(energy_white_albedo[c.x], energy_white_albedo[c.y], f.x),
               mix(energy_white_albedo[c.z], energy_white_albedo[c.w], f.x), f.y);
}
#endif

#ifdef ENVIRONMENT
#include "environment.glsl"

// Bilinear lookup in material `material`'s albedo table (environment_albedo.comp), part
// `part` (0: specular, 1: diffuse), at (n·v, r); cell-centred, clamped at the edges.
vec4 environment_table(uint material, uint part, vec2 coord) {
    vec2 f;
    uvec4 c = bilinear_cells(coord, ENVIRONMENT_TABLE_SIZE, f)
            + material * ENVIRONMENT_TABLE_SIZE * ENVIRONMENT_TABLE_SIZE;
    c = c * 2u + part;
    return mix(mix(environment_albedo[c.x], environment_albedo[c.y], f.x),
               mix(environment_albedo[c.z], environment_albedo[c.w], f.x), f.y);
}

// The same in per-code table `table` (environment_code_albedo.comp), code `code`.
float environment_code_table(uint table, uint code, vec2 coord) {
    vec2 f;
    uvec4 c = bilinear_cells(coord, ENVIRONMENT_CODE_TABLE_SIZE, f)
            + (table * 256u + code) * ENVIRONMENT_CODE_TABLE_SIZE * ENVIRONMENT_CODE_TABLE_SIZE;
    return mix(mix(environment_code_albedo[c.x], environment_code_albedo[c.y], f.x),
               mix(environment_code_albedo[c.z], environment_code_albedo[c.w], f.x), f.y);
}

// The split-sum environment term (combustion_renderer::environment): the prefiltered
// radiance along the mirror direction times the material's specular directional albedo
// (full Fresnel), plus the cosine-weighted mean radiance about n times its diffuse
// albedo ρ D1 + ρ² D2. Anisotropic pixels use the roughness of their mean α.
vec3 environment_radiance(GpuMaterial material, uint material_index, BrdfInputs m, BrdfView view,
                          vec3 n, vec3 v, float roughness, vec3 base_color_code,
                          float occlusion) {
    float nv = view.v.z;
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
    // Occlusion (glTF occlusion textures, OCCLUSION variant; 1 otherwise) darkens the
    // diffuse term as it is, and the specular term by Lagarde & de Rousiers' (2014,
    // eq. 58) specular occlusion, weaker than the diffuse occlusion at normal incidence
    // and on smooth surfaces; direct lights are never occluded.
    #ifdef OCCLUSION
    float specular_occlusion = clamp(
        pow(nv + occlusion, exp2(-16.0 * alpha - 1.0)) - 1.0 + occlusion, 0.0, 1.0);
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
    float lod = clamp(roughness, 0.0, 1.0) * float(textureQueryLevels(environment_specular) - 1);
    return textureLod(environment_specular, r, lod).rgb * specular_albedo
         + textureLod(environment_irradiance, n, 0.0).rgb * diffuse_albedo;
}
#endif

layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float depth = texelFetch(gbuffer_depth, pixel, 0).r;
    if (depth >= 1.0) {
        // Background: nothing was drawn here (alpha 0 marks it).
        out_radiance = vec4(push.background.rgb, 0.0);
#ifdef ENVIRONMENT
        if (push.background.w != 0.0) {
            // The environment along the pixel's ray: through a point of the view volume
            // at depth 0.5 (finite with an infinite far plane too).
            vec2 ndc = gl_FragCoord.xy / vec2(textureSize(gbuffer_depth, 0)) * 2.0 - 1.0;
            vec4 along = push.inverse_view_projection * vec4(ndc, 0.5, 1.0);
            vec3 direction = normalize(along.xyz / along.w - push.camera_position.xyz);
            out_radiance = vec4(textureLod(environment_specular, direction, 0.0).rgb, 0.0);
        }
#endif
        return;
    }
    vec4 base_metal = texelFetch(gbuffer_base_color_metalness, pixel, 0);
    vec4 nra = texelFetch(gbuffer_normal_roughness_anisotropy, pixel, 0);
    uvec2 md = texelFetch(gbuffer_material_direction, pixel, 0).xy;
#ifdef FLOOR_FETCH
    // Measurement floor (combustion_renderer::MeasurementFloor::LightingFetch): fetch
    // the G-buffer and write, nothing shaded.
    out_radiance = vec4(base_metal.rgb * nra.xyz + vec3(float(md.x) + depth + nra.w), 1.0);
    return;
#endif
    GpuMaterial material = materials[md.x];

    vec2 uv = gl_FragCoord.xy / vec2(textureSize(gbuffer_depth, 0));
    vec4 world = push.inverse_view_projection * vec4(uv * 2.0 - 1.0, depth, 1.0);
    vec3 position = world.xyz / world.w;

    vec3 n = octahedral_decode(nra.xy);
    vec3 t = anisotropy_direction_decode(n, md.y);
    vec3 b = cross(n, t);
    vec3 v = normalize(push.camera_position.xyz - position);

#ifdef FLOOR_PLAIN_GGX
    // Measurement floor (MeasurementFloor::LightingPlainGgx): a plain isotropic GGX D,
    // height-correlated Smith visibility and the full conductor Fresnel equations (η_i
    // = 1) per channel, for every light: no shading frame, no dielectric, no diffuse.
    {
        float a = clamp_alpha(alpha_from_perceptual_roughness(nra.z));
        float a2 = a * a;
        vec3 eta = material.conductor_eta_outside_ior.rgb;
        vec3 k = material.conductor_k_polarisation.rgb;
        float nv = max(dot(n, v), COS_MIN);
        vec3 sum = vec3(0.0);
        for (uint i = 0u; i < push.counts.x; ++i) {
            GpuLight light = lights[i];
            vec3 l;
            vec3 e;
            if (light.power_kind.a != LIGHT_KIND_DIRECTIONAL) {
                vec3 to_light = light.position_or_direction.xyz - position;
                float d2 = max(dot(to_light, to_light), 1e-12);
                l = to_light * inversesqrt(d2);
                e = light.power_kind.rgb / d2;
            } else {
                l = -light.position_or_direction.xyz;
                e = light.power_kind.rgb;
            }
            float nl = dot(n, l);
            if (nl <= 0.0) {
                continue;
            }
            vec3 h = normalize(v + l);
            float nh = dot(n, h);
            float t = nh * nh * (a2 - 1.0) + 1.0;
            float d = a2 / (PI * t * t);
            float sv = sqrt(nv * nv * (1.0 - a2) + a2);
            float sl = sqrt(nl * nl * (1.0 - a2) + a2);
            float vis = 0.5 / (nl * sv + nv * sl);
            float vh = clamp(dot(v, h), 0.0, 1.0);
            vec3 f = vec3(
                polarised_weighted(fresnel_conductor(vh, 1.0, eta.x, k.x), 0.5),
                polarised_weighted(fresnel_conductor(vh, 1.0, eta.y, k.y), 0.5),
                polarised_weighted(fresnel_conductor(vh, 1.0, eta.z, k.z), 0.5));
            sum += d * vis * f * e * nl;
        }
        out_radiance = vec4(sum, 1.0);
        return;
    }
#endif
    float alpha = alpha_from_perceptual_roughness(nra.z);
    vec2 alphas = anisotropic_alphas(alpha, nra.w);
    BrdfInputs m;
    m.base_color = base_color_decode(base_metal.rgb);
    m.metalness = base_metal.a;
    m.alpha_x = alphas.x;
    m.alpha_y = alphas.y;
    m.conductor_eta = material.conductor_eta_outside_ior.rgb;
    m.conductor_k = material.conductor_k_polarisation.rgb;
#ifndef NO_CONDUCTOR_TABLE
    if ((material.diffuse_model_flags.y & MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR) != 0u) {
        ivec3 code = ivec3(base_color_srgb8_code(base_metal.rgb));
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
    m.oren_nayar_sigma = oren_nayar_sigma_from_roughness(nra.z);

    // The view-dependent half of the BRDF once per pixel; per light only the rest.
    BrdfView view = brdf_view(m, n, t, b, v);

    // Culled frames: only the lights the tile's list names, in index order (the same
    // sum as over every light, less terms that are exactly 0 here).
    bool culled = push.counts.z != 0u;
    uint list = 0u;
    uint light_count = push.counts.x;
    if (culled) {
        uvec2 tile = uvec2(pixel) / uint(TILE_SIZE);
        list = (tile.y * push.counts.z + tile.x) * push.counts.w;
        light_count = tile_lights[list];
    }
#ifdef DEBUG_VIEWS
    if (push.counts.y != 0u) {
        vec3 l0 = vec3(0.0, 0.0, 1.0);
        if (push.counts.x > 0u) {
            GpuLight first = lights[0];
            l0 = first.power_kind.a != LIGHT_KIND_DIRECTIONAL
                ? normalize(first.position_or_direction.xyz - position)
                : -first.position_or_direction.xyz;
        }
        DebugSurface surface;
        surface.base_color = m.base_color;
        surface.metalness = m.metalness;
        surface.normal = n;
        surface.tangent = t;
        surface.roughness = nra.z;
        surface.anisotropy = nra.w;
        surface.material = md.x;
        surface.distance = length(push.camera_position.xyz - position);
        surface.tile_light_fraction = float(light_count) / float(max(push.counts.x, 1u));
        surface.shadow = 1.0;
        surface.cascade = -1;
#ifdef SHADOWS
        if (push.counts.x > 0u && lights[0].spot_cone.w != 0.0) {
            uint first = uint(lights[0].spot_cone.w) - 1u;
            surface.shadow = shadow_visibility_of(lights[0], first, position,
                                                  push.camera_position.xyz, n, l0, gl_FragCoord.xy);
            if (lights[0].power_kind.a == LIGHT_KIND_DIRECTIONAL) {
                float blend;
                uint cascade = shadow_cascade(
                    first, shadow_view_distance(first, position, push.camera_position.xyz), blend);
                surface.cascade = cascade < uint(SHADOW_CASCADES) ? int(cascade) : -1;
            }
        }
#endif
        out_radiance = vec4(debug_view_radiance(push.counts.y, surface, m, view, l0, push.counts.x > 0u), 1.0);
        return;
    }
#endif
#ifndef NO_UNLIT
    // KHR_materials_unlit: the base colour (factor × texture × vertex colour, as the
    // G-buffer holds it) is the pixel's radiance; nothing lights it.
    if ((material.diffuse_model_flags.y & MATERIAL_FLAG_UNLIT) != 0u) {
        out_radiance = vec4(m.base_color, 1.0);
        return;
    }
#endif
    vec3 radiance = vec3(0.0);
    for (uint j = 0u; j < light_count; ++j) {
        uint i = culled ? tile_lights[list + 1u + j] : j;
        GpuLight light = lights[i];
        vec3 l;
        vec3 irradiance;
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
        } else {
            l = -light.position_or_direction.xyz;
            irradiance = light.power_kind.rgb;
        }
        float n_dot_l = dot(n, l);
        if (n_dot_l <= 0.0) {
            continue;
        }
#ifdef SHADOWS
        if (light.spot_cone.w != 0.0) {
            irradiance *= shadow_visibility_of(light, uint(light.spot_cone.w) - 1u, position,
                                               push.camera_position.xyz, n, l, gl_FragCoord.xy);
        }
#endif
        radiance += brdf_evaluate_view(m, view, l) * irradiance * n_dot_l;
    }
#ifdef EMISSIVE_OCCLUSION_TARGET
    vec4 emissive_occlusion = texelFetch(gbuffer_emissive, pixel, 0);
#endif
#ifdef ENVIRONMENT
#ifdef OCCLUSION
    float occlusion = emissive_occlusion.a;
#else
    float occlusion = 1.0;
#endif
    radiance += environment_radiance(material, md.x, m, view, view.frame[2], normalize(v), nra.z,
                                     base_color_srgb8_code(base_metal.rgb), occlusion);
#endif
#ifdef EMISSIVE
    radiance += emissive_occlusion.rgb;
#endif
    out_radiance = vec4(radiance, 1.0);
}
