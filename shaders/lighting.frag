#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#if defined(RAY_TRACED_REFLECTIONS) && !defined(ENVIRONMENT)
// Reflections are traced in place of the environment's specular lookup: without an
// environment there is none (the pass does not run).
#undef RAY_TRACED_REFLECTIONS
#endif
#if defined(PATH_TRACE) || defined(RAY_TRACED_REFLECTIONS)
// Rays that meet the scene's surfaces and read them (traced_surfaces.glsl).
#define TRACED_SURFACES
#endif
#if defined(RAY_TRACED_OCCLUSION) || defined(TRACED_SURFACES)
#extension GL_EXT_ray_query : require
#endif
#ifdef RAY_TRACED_OCCLUSION
#ifdef ENVIRONMENT_SAMPLES
// The sampled environment traces each of its directions against the scene.
#define ENVIRONMENT_SAMPLE_VISIBILITY
#endif
#endif
// Lighting pass: reads the G-buffer and depth, the material table and the lights, and
// writes HDR radiance (W·sr⁻¹·m⁻² per RGB channel). Mirrored on the CPU by
// combustion_renderer::reference (the parity tests and the viewer's error view).
// Specialised per scene (combustion_renderer::LightingFeatures): NO_ANISOTROPY,
// NO_CONDUCTORS, NO_CONDUCTOR_TABLE, NO_DIELECTRICS, OUTSIDE_ETA_ONE, NO_LAMBERT,
// NO_OREN_NAYAR_QUALITATIVE, NO_OREN_NAYAR_FULL, NO_UNLIT remove what the scene cannot use;
// CLEARCOAT (scenes with a clear coat) adds the coat's lobe over the base, SHEEN (scenes
// with sheen) the sheen's lobe and its albedo scaling of the base, IRIDESCENCE (scenes with
// a thin film) the film's Fresnel reflectance mixed into the base's, SPECULAR (scenes with
// KHR_materials_specular) the dielectric's Fresnel rescaled by its strength and colour;
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
    uvec4 sampling;   // x: the frame's environment sample seed; y: the paths' depth;
                      // z, w: the exposure (f32 bits) and tone curve (OUTPUT_FOLDED)
} push;

#ifdef DEBUG_VIEWS
#include "debug_views.glsl"
#endif

#ifdef SHADOWS
#include "shadows.glsl"
#endif

// The light, environment and BRDF-input terms shared with the forward pass.
#include "lighting_terms.glsl"
#ifdef PATH_TRACE
#include "path_trace.glsl"
#endif
#ifdef RAY_TRACED_REFLECTIONS
#include "traced_reflections.glsl"
#endif

#ifdef OUTPUT_FOLDED
// Frames where nothing reads the radiance between this pass and the output pass have
// the output pass's work done here (passes/lighting.rs): the pixel's radiance written
// as the target's format holds it (output_encoding.glsl), into the frame's target.
#include "output_encoding.glsl"
#endif

// The pixel's radiance (alpha 0 where no surface is), or the frame target's value
// (OUTPUT_FOLDED: written by main from the radiance).
layout(location = 0) out vec4 out_radiance;

// The radiance where no surface is (alpha 0 marks it): the background's, or the
// environment along the pixel's ray where it is the background.
vec4 background_radiance() {
    vec4 radiance = vec4(push.background.rgb, 0.0);
#ifdef ENVIRONMENT
    if (push.background.w != 0.0) {
        // The environment along the pixel's ray: through a point of the view volume
        // at depth 0.5 (finite with an infinite far plane too).
        vec2 ndc = gl_FragCoord.xy / vec2(textureSize(gbuffer_depth, 0)) * 2.0 - 1.0;
        vec4 along = push.inverse_view_projection * vec4(ndc, 0.5, 1.0);
        vec3 direction = normalize(along.xyz / along.w - push.camera_position.xyz);
        radiance = vec4(textureLod(environment_specular, direction, 0.0).rgb, 0.0);
    }
#endif
    return radiance;
}

#ifndef BACKGROUND_PIXELS
// Writes the pixel's radiance into out_radiance, or discards it.
void light_pixel() {
#ifdef PATH_TRACE
    // The frame path traced (path_trace.glsl), not the G-buffer shaded.
    out_radiance = vec4(path_traced_pixel(gl_FragCoord.xy, vec2(textureSize(gbuffer_depth, 0)),
                                          push.camera_position.xyz, push.sampling.x), 1.0);
    return;
#endif
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float depth = texelFetch(gbuffer_depth, pixel, 0).r;
    if (isnan(depth)) {
        // No draw writes a depth that is not a number; such a pixel keeps the pass's
        // clear (passes/lighting.rs: the background's radiance, or nothing where the
        // environment is the background) rather than shading NaN. A shader that may
        // discard is also compiled once by lavapipe, not a second time for whole tiles
        // (docs/build.md, "Build cost"). Folded into the output, the pass has no clear:
        // the pixel is written as that clear would have been shown.
#ifdef OUTPUT_FOLDED
        out_radiance = vec4(push.background.w != 0.0 ? vec3(0.0) : push.background.rgb, 0.0);
        return;
#else
        discard;
#endif
    }
    if (depth >= 1.0) {
        // Background: nothing was drawn here. Depth-tested pipelines shade only where
        // a surface is (passes/lighting.rs), the background pipeline the rest.
        out_radiance = background_radiance();
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

    vec3 v = normalize(push.camera_position.xyz - position);
    // The stored normal and the anisotropy direction in its plane; then the normal made
    // to face the eye (brdf.glsl, facing_view: every term below shades with it, and the
    // BRDF's frame re-orthogonalises the direction against it).
    vec3 n = octahedral_decode(nra.xy);
    vec3 t = anisotropy_direction_decode(n, md.y);
    n = facing_view(n, v);
    vec3 b = cross(n, t);

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
    BrdfInputs m = brdf_inputs(material, base_color_decode(base_metal.rgb), base_metal.a, nra.z,
                               nra.w, base_color_srgb8_code(base_metal.rgb));

    // The view-dependent half of the BRDF once per pixel; per light only the rest.
    BrdfView view = brdf_view(m, n, t, b, v);
#ifdef SPECULAR
    // The dielectric's specular colour (rgb) and factor (a), before a film over them.
    vec4 specular_texel = texelFetch(gbuffer_specular, pixel, 0);
    brdf_view_apply_specular(view, m, DielectricSpecular(specular_texel.a, specular_texel.rgb));
#endif
#ifdef IRIDESCENCE
    // The thin film: weight (r), thickness in nm (g); its IOR from the material.
    vec2 film_texel = texelFetch(gbuffer_film, pixel, 0).rg;
    brdf_view_apply_film(view, m, ThinFilm(film_texel.r, material.film.y, film_texel.g));
#endif
#ifdef CLEARCOAT
    // The clear coat: weight (a), perceptual roughness (b), octahedral normal (rg).
    vec4 coat_texel = texelFetch(gbuffer_clearcoat, pixel, 0);
    SurfaceCoat coat = surface_coat(material, m, coat_texel.a, coat_texel.b,
                                    facing_view(octahedral_decode(coat_texel.rg), v), v);
#else
    SurfaceCoat coat = no_surface_coat();
#endif
    SurfaceLayers layers;
    layers.coat = coat;
#ifdef SHEEN
    // The sheen: linear colour (rgb), perceptual roughness (a).
    vec4 sheen_texel = texelFetch(gbuffer_sheen, pixel, 0);
    layers.sheen = surface_sheen(sheen_texel.rgb, sheen_texel.a, view);
#else
    layers.sheen = no_surface_sheen();
#endif

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
#ifdef RAY_TRACED_SHADOWS
        surface.shadow = float(texelFetch(ray_traced_shadows, pixel, 0).r & 15u) / 15.0;
#endif
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
#ifdef RAY_TRACED_SHADOWS
    // Nibble i: how many of light i's rays reach the pixel, of 15 (the ray-traced shadows
    // pass; the first 32 lights).
    uvec4 reaching = texelFetch(ray_traced_shadows, pixel, 0);
#endif
    for (uint j = 0u; j < light_count; ++j) {
        uint i = culled ? tile_lights[list + 1u + j] : j;
        float lit = 1.0;
#ifdef RAY_TRACED_SHADOWS
        if (i < 32u) {
            uint rays = (reaching[i >> 3] >> ((i & 7u) * 4u)) & 15u;
            if (rays == 0u) {
                continue;
            }
            lit = float(rays) / 15.0;
        }
#endif
        radiance += lit * light_radiance(m, view, layers, lights[i], position, n,
                                         push.camera_position.xyz, gl_FragCoord.xy);
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
#ifdef AMBIENT_OCCLUSION
    // The ambient-occlusion pass's visibility: with the texture's, their minimum (both
    // see the same contacts; a product would count them twice).
    occlusion = min(occlusion, texelFetch(ambient_occlusion, pixel, 0).r);
#endif
#if defined(RAY_TRACED_OCCLUSION) && !defined(ENVIRONMENT_SAMPLE_VISIBILITY)
    // The ray-traced occlusion pass's visibility, by the same rule (the sampled
    // environment traces its own directions instead).
    occlusion = min(occlusion, texelFetch(ray_traced_occlusion, pixel, 0).r);
#endif
#ifdef ENVIRONMENT_SAMPLES
    // Visibility rays start off the surface as the ray-traced occlusion pass's do.
    vec3 ray_origin = position + n * (ENVIRONMENT_RAY_OFFSET * length(push.camera_position.xyz - position));
    radiance += environment_sampled(m, view, layers, view.frame[2], gl_FragCoord.xy, push.sampling.x,
                                    occlusion, nra.z, ray_origin);
#elif defined(RAY_TRACED_REFLECTIONS)
    // A smooth surface reflects what its ray meets instead of the environment's
    // prefiltered radiance (traced_reflections.glsl), blended out with roughness.
    SpecularLookup lookup;
    radiance += environment_radiance_looked_up(material, md.x, m, view, layers, view.frame[2], normalize(v),
                                               nra.z, base_color_srgb8_code(base_metal.rgb), occlusion,
                                               lookup);
    float share = traced_reflection_share(nra.z);
    if (share > 0.0 && any(greaterThan(lookup.weight, vec3(0.0)))) {
        uint state = path_seed(uint(pixel.x) + 65536u * uint(pixel.y), push.sampling.x, REFLECTIONS_STREAM);
        vec3 traced = traced_reflection(position, view.frame[2], push.camera_position.xyz, lookup.direction,
                                        lookup.lod, state);
        radiance += lookup.weight * share
                  * (traced - textureLod(environment_specular, lookup.direction, lookup.lod).rgb);
    }
#else
    radiance += environment_radiance(material, md.x, m, view, layers, view.frame[2], normalize(v),
                                     nra.z, base_color_srgb8_code(base_metal.rgb), occlusion);
#endif
#endif
#ifdef EMISSIVE
    radiance += emissive_occlusion.rgb;
#endif
    out_radiance = vec4(radiance, 1.0);
}

#endif

void main() {
#ifdef BACKGROUND_PIXELS
    // The background pipeline: only where no surface was drawn (its depth test).
    out_radiance = background_radiance();
#else
    light_pixel();
#endif
#ifdef OUTPUT_FOLDED
    out_radiance = output_encoded(out_radiance.rgb, uintBitsToFloat(push.sampling.z), push.sampling.w);
#endif
}
