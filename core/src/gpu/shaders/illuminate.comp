#version 450
// Sum 1 of the exact propagator: the field at every pinhole sample (x, y, 0) from every source.
// Finite source P: exp(2 pi i (|xi|^2 - 2 xi.P) / (lambda (r + |P|))) / r, r = |P - xi|;
// plane wave along u: exp(-2 pi i u.xi / lambda). Each term times the source's complex weight in
// each run. The host scales by the sample's area / lambda.
#include "phasor_sum.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Samples { vec2 xy[]; } samples;
// finite sources (Px, Py, |P|^2, |P|), then plane waves (ux, uy, -, -)
layout(std430, binding = 1) readonly buffer Sources { vec4 p[]; } sources;
// weights[run * n_terms + s]
layout(std430, binding = 2) readonly buffer Weights { vec2 w[]; } weights;
// out[run * n_out + j]
layout(std430, binding = 3) writeonly buffer Out { OutType v[]; } outs;

layout(push_constant) uniform Push {
    uint n_out;
    uint n_finite;
    uint n_terms;  // finite + plane
    uint runs;
    float inv_lambda;
} pc;

void main() {
    uint j = gl_GlobalInvocationID.x;
    uint run0 = gl_WorkGroupID.y * kRuns;
    uint nr = min(kRuns, pc.runs - run0);
    vec2 xy = j < pc.n_out ? samples.xy[j] : vec2(0.0);
    float x = xy.x, y = xy.y;
    float q = x * x + y * y;
    Acc acc[kRuns];
    for (uint k = 0u; k < kRuns; ++k) acc[k] = ACC_ZERO;
    // finite sources and plane waves each start their own blocks, as on the CPU; every
    // invocation reads the same term at the same time (a broadcast)
    for (uint part = 0u; part < 2u; ++part) {
        uint begin = part == 0u ? 0u : pc.n_finite, end = part == 0u ? pc.n_finite : pc.n_terms;
        for (uint b = begin; b < end; b += kBlock) {
            vec2 block[kRuns];
            for (uint k = 0u; k < kRuns; ++k) block[k] = vec2(0.0);
            uint e = min(end, b + kBlock);
            for (uint s = b; s < e; ++s) {
                vec4 p = sources.p[s];
                float turns, amp;
                if (part == 0u) {
                    float num = q - 2.0 * (x * p.x + y * p.y);
                    float r = sqrt(p.z + num);
                    turns = num * pc.inv_lambda / (r + p.w);
                    amp = 1.0 / r;
                } else {
                    turns = -(x * p.x + y * p.y) * pc.inv_lambda;
                    amp = 1.0;
                }
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
    }
    if (j < pc.n_out)
        for (uint k = 0u; k < nr; ++k) outs.v[(run0 + k) * pc.n_out + j] = acc[k];
}
