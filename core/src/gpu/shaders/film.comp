#version 450
// Sum 2 of the exact propagator: the film field at every film point T = (tx, ty, -f) from every
// pinhole sample's re-emitted field w_j (Rayleigh-Sommerfeld I, Goodman eq. 3-41), taken from the
// reference path r0 = |T|: num = |xi|^2 - 2 xi.T, r - r0 = num / (r + r0), amplitude f / r^2.
#include "phasor_sum.glsl"

layout(local_size_x = 64) in;

// film points (tx, ty, r0^2, r0)
layout(std430, binding = 0) readonly buffer Film { vec4 t[]; } film;
// pinhole samples (x, y)
layout(std430, binding = 1) readonly buffer Samples { vec2 xy[]; } samples;
// weights[run * n_terms + j]: the sample's field in each run
layout(std430, binding = 2) readonly buffer Weights { vec2 w[]; } weights;
// out[run * n_out + t]
layout(std430, binding = 3) writeonly buffer Out { OutType v[]; } outs;

layout(push_constant) uniform Push {
    uint n_out;
    uint n_unused;
    uint n_terms;
    uint runs;
    float inv_lambda;
    float f;
} pc;

void main() {
    uint t = gl_GlobalInvocationID.x;
    uint run0 = gl_WorkGroupID.y * kRuns;
    uint nr = min(kRuns, pc.runs - run0);
    vec4 T = t < pc.n_out ? film.t[t] : vec4(0.0, 0.0, 1.0, 1.0);
    Acc acc[kRuns];
    for (uint k = 0u; k < kRuns; ++k) acc[k] = ACC_ZERO;
    // every invocation reads the same sample at the same time (a broadcast)
    for (uint b = 0u; b < pc.n_terms; b += kBlock) {
        vec2 block[kRuns];
        for (uint k = 0u; k < kRuns; ++k) block[k] = vec2(0.0);
        uint e = min(pc.n_terms, b + kBlock);
        for (uint s = b; s < e; ++s) {
            vec2 xy = samples.xy[s];
            float num = xy.x * (xy.x - 2.0 * T.x) + xy.y * (xy.y - 2.0 * T.y);
            float rsq = T.z + num;
            float turns = num * pc.inv_lambda / (sqrt(rsq) + T.w);
            float amp = pc.f / rsq;
            float sn, cs;
            sincos_turns(turns, sn, cs);
            float ac = amp * cs, as_ = amp * sn;
            for (uint k = 0u; k < nr; ++k) {
                vec2 w = weights.w[(run0 + k) * pc.n_terms + s];
                block[k] += vec2(w.x * ac - w.y * as_, w.x * as_ + w.y * ac);
            }
        }
        for (uint k = 0u; k < kRuns; ++k) add_block(acc[k], block[k]);
    }
    if (t < pc.n_out)
        for (uint k = 0u; k < nr; ++k) outs.v[(run0 + k) * pc.n_out + t] = acc[k];
}
