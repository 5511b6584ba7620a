#version 460
#extension GL_GOOGLE_include_directive : require
// Auto exposure, adaptation (combustion_renderer's passes/auto_exposure.rs), one group:
// the frame's histogram of log2 luminance (the metering pass's) is read and cleared for
// the next frame; the mean log2 luminance of the pixels ranked between the window's two
// fractions (a bin straddling an end counted in part, each at its bin's centre) gives
// the reflected-light meter's EV100 = mean + log2(100 / K), less the compensation: the
// target. A first frame (push.reset) takes it at once; later ones step towards it by at
// most rise · elapsed (a darker scene: the exposure rises, EV100 falls) or fall · elapsed.
// A frame with no pixel counted keeps the previous EV100 (a first one: the fallback, the
// frame's own exposure), so no frame, all zeros or all infinities, makes it NaN.
// The state written: the exposure factor 1 / (1.2 · 2^EV100), EV100, the target, the
// pixels counted, then the histogram (the output pass reads the factor; the frame's end
// copies the whole for the host).
#include "bindings/exposure_adaptation.glsl"  // set 0: histogram, exposure_state
#include "push/exposure_adaptation.glsl"

layout(local_size_x = 256) in;

shared uint counts[256];

void main() {
    uint bin_index = gl_LocalInvocationIndex;
    uint count = histogram[bin_index];
    counts[bin_index] = count;
    histogram[bin_index] = 0u;
    exposure_state[4u + bin_index] = count;
    barrier();
    if (bin_index != 0u) {
        return;
    }
    uint total = 0u;
    for (uint b = 0u; b < 256u; ++b) {
        total += counts[b];
    }
    float low = push.window.x * float(total);
    float high = push.window.y * float(total);
    float bin_width = (push.log2_luminance.y - push.log2_luminance.x) / 256.0;
    float below = 0.0;
    float weight = 0.0;
    float sum = 0.0;
    for (uint b = 0u; b < 256u; ++b) {
        float n = float(counts[b]);
        float inside = max(0.0, min(below + n, high) - max(below, low));
        sum += inside * (push.log2_luminance.x + (float(b) + 0.5) * bin_width);
        weight += inside;
        below += n;
    }
    float previous = push.reset != 0u ? push.fallback_ev100 : uintBitsToFloat(exposure_state[1]);
    float target = weight > 0.0 ? sum / weight + push.meter_offset - push.compensation : previous;
    float ev100 = push.reset != 0u
        ? target
        : previous + clamp(target - previous, -push.rise * push.elapsed, push.fall * push.elapsed);
    exposure_state[0] = floatBitsToUint(1.0 / (1.2 * exp2(ev100)));
    exposure_state[1] = floatBitsToUint(ev100);
    exposure_state[2] = floatBitsToUint(target);
    exposure_state[3] = total;
}
