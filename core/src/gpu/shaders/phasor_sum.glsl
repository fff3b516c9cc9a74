// The phasor sum's parts shared by both compute shaders, the GLSL twin of the CPU kernel's
// sincos_turns.h and phasor_sum.h: phases in turns reduced exactly (the nearest quarter turn
// subtracted before the polynomial), float terms summed in blocks of kBlock, the blocks added in
// double (FP64 = 1) or as a compensated float pair (FP64 = 0, devices without shaderFloat64).

// Sums are handed out per output as 16 bytes: dvec2, or vec4 (sum, compensation).
#if FP64
#extension GL_ARB_gpu_shader_fp64 : require
#define Acc dvec2
#define ACC_ZERO dvec2(0.0)
#define OutType dvec2
#else
#define Acc vec4
#define ACC_ZERO vec4(0.0)
#define OutType vec4
#endif

// Terms per float block, as the CPU kernel's kPhasorBlock.
const uint kBlock = 1024u;
// Runs summed together (their weights differ, the phasor is shared); more run groups are the
// dispatch's second dimension.
const uint kRuns = 4u;

// sin and cos of 2 pi t for t in turns: q = nearest quarter turn, x = 2 pi (t - q/4) in
// [-pi/4, pi/4], Taylor series to x^9 and x^8 (truncation < 3e-8), then the quadrant identities.
void sincos_turns(float t, out float s, out float c) {
    float q = roundEven(4.0 * t);
    float x = (t - 0.25 * q) * 6.28318530717958647692;
    float x2 = x * x;
    float sp = x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362880.0)))));
    float cp = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0))));
    int iq = int(q) & 3;
    bool swap = (iq & 1) != 0;
    float sin_sign = 1.0 - float(iq & 2);
    float cos_sign = 1.0 - float((iq + 1) & 2);
    s = sin_sign * (swap ? cp : sp);
    c = cos_sign * (swap ? sp : cp);
}

// Adds a float block's sum to the accumulator.
void add_block(inout Acc acc, vec2 block) {
#if FP64
    acc += dvec2(block);
#else
    // two-sum (Knuth): the rounding error of sum + block kept exactly in the compensation
    precise vec2 t = acc.xy + block;
    precise vec2 bp = t - acc.xy;
    precise vec2 e = (acc.xy - (t - bp)) + (block - bp);
    acc = vec4(t, acc.zw + e);
#endif
}
