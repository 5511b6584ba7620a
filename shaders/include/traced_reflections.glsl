// Ray-traced reflections in the real-time frame (RAY_TRACED_REFLECTIONS;
// crates/renderer/src/passes/ray_traced_reflections.rs): a smooth surface's split-sum
// specular lookup — the environment's prefiltered radiance along the lobe's dominant
// direction — replaced by one ray along that direction through the scene: what it
// meets shaded with its emission, every light's light with shadow rays and the
// environment's split sum (traced_surfaces.glsl), or, where it meets nothing, the same
// prefiltered radiance as before. Needs lighting.frag's set and push constants.
#ifndef COMBUSTION_TRACED_REFLECTIONS_GLSL
#define COMBUSTION_TRACED_REFLECTIONS_GLSL

#include "traced_surfaces.glsl"
#include "ray_traced_reflections/constants.glsl"

// The radiance arriving at a surface point `position` (unit shading normal `n`, seen
// from `eye`) along unit `direction`, from what the ray meets; the environment's
// prefiltered radiance at level `lod` where it meets nothing. `state`: random numbers
// for what a ray meets by chance (blended surfaces, points of lights with a size).
vec3 traced_reflection(vec3 position, vec3 n, vec3 eye, vec3 direction, float lod, inout uint state) {
    // Off the surface along its normal, past the depth's rounding (the occlusion rays'
    // rule, ENVIRONMENT_RAY_OFFSET per metre from the eye).
    vec3 origin = position + n * (ENVIRONMENT_RAY_OFFSET * distance(eye, position));
    return traced_radiance_along(origin, direction, lod, 0u, state);
}

// The share of the specular lookup a surface of perceptual roughness `roughness` takes
// from its traced ray: 1 up to REFLECTIONS_ROUGHNESS_FULL, 0 from REFLECTIONS_ROUGHNESS_NONE
// (one ray cannot stand for a broad lobe), linear between.
float traced_reflection_share(float roughness) {
    return clamp((REFLECTIONS_ROUGHNESS_NONE - roughness)
                 / (REFLECTIONS_ROUGHNESS_NONE - REFLECTIONS_ROUGHNESS_FULL), 0.0, 1.0);
}

#endif
