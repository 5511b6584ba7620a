// What every environment-bake compute shader declares: its descriptor set
// (combustion_renderer::environment). Each shader declares its own push constants,
// mirrored by a struct of the same name in combustion_renderer::gpu_types.
#ifndef COMBUSTION_ENVIRONMENT_BAKE_GLSL
#define COMBUSTION_ENVIRONMENT_BAKE_GLSL

#include "gpu_types.glsl"
#include "environment.glsl"
#include "bindings/environment_bake.glsl"  // set 0: combustion_renderer::bindings::ENVIRONMENT_BAKE

#endif
