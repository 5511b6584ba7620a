// What every environment-bake compute shader declares: its descriptor set and push
// constants (combustion_renderer::environment; gpu_types::EnvironmentBakePush).
#ifndef COMBUSTION_ENVIRONMENT_BAKE_GLSL
#define COMBUSTION_ENVIRONMENT_BAKE_GLSL

#include "gpu_types.glsl"
#include "environment.glsl"
#include "bindings/environment_bake.glsl"  // set 0: combustion_renderer::bindings::ENVIRONMENT_BAKE

layout(push_constant) uniform EnvironmentBakePush {
    EnvironmentSource source;
    uvec4 params;  // per shader: see its header
    vec4 values;
} push;

#endif
