#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
// Auto exposure, metering (combustion_renderer's passes/auto_exposure.rs): each pixel's
// luminance Y = 0.2126 R + 0.7152 G + 0.0722 B of the HDR image counted in a histogram
// of log2 Y, 256 bins over push.log2_luminance (METERED_LOG2_LUMINANCE). Black pixels
// (Y = 0: no surface under a black background, unlit) are not counted, nor NaN; darker
// ones than the span count in the first bin, brighter ones and infinities in the last, so
// that a scene lit 1e5 times brighter ranks the same pixels the same way. Each group
// of 16×16 invocations counts a 128×128-pixel block in shared memory, then adds its
// nonzero bins to the frame's histogram (which the adaptation pass reads and clears).
#include "bindings/exposure_metering.glsl"  // set 0: hdr_image, histogram
#include "push/exposure_metering.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

shared uint group_bins[256];

// Pixels a group counts along each side: 16 invocations × 8. On lavapipe at 1280×720
// (builtin:grid-7x7, GPU medians of 10 frames) a 16×16-pixel group cost 11.8 ms, a
// 64×64 one 4.8 ms, 128×128 1.85 ms: the shared histogram's clearing, barriers and
// flush are paid once per block.
const int GROUP_SIDE = 128;

void main() {
    uint bin_index = gl_LocalInvocationIndex;
    group_bins[bin_index] = 0u;
    barrier();
    ivec2 size = textureSize(hdr_image, 0);
    float low = push.log2_luminance.x;
    float span = push.log2_luminance.y - low;
    ivec2 origin = ivec2(gl_WorkGroupID.xy) * GROUP_SIDE + ivec2(gl_LocalInvocationID.xy);
    for (int j = 0; j < GROUP_SIDE; j += 16) {
        for (int i = 0; i < GROUP_SIDE; i += 16) {
            ivec2 pixel = origin + ivec2(i, j);
            if (any(greaterThanEqual(pixel, size))) {
                continue;
            }
            vec3 radiance = texelFetch(hdr_image, pixel, 0).rgb;
            float luminance = dot(radiance, vec3(0.2126, 0.7152, 0.0722));
            // NaN fails the comparison: not counted.
            if (luminance > 0.0) {
                float t = clamp((log2(luminance) - low) / span, 0.0, 1.0);
                atomicAdd(group_bins[min(uint(t * 256.0), 255u)], 1u);
            }
        }
    }
    barrier();
    uint count = group_bins[bin_index];
    if (count != 0u) {
        atomicAdd(histogram[bin_index], count);
    }
}
