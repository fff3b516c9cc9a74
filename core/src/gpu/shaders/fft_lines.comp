#version 450
// Complex FFTs of length n (a power of two, 2 <= n <= kMaxLength) along the lines of a row-major
// array, one line per workgroup: rows (element step 1, line step the width) or columns (element
// step the width, line step 1). Radix 2, decimation in time: the line is loaded in bit-reversed
// order into shared memory, goes through log2 n stages of butterflies
//   a' = a + w c,  c' = a - w c,  w = exp(-+ 2 pi i k / (2 h))  (h = 2^stage, k < h),
// and is written back in place. Unnormalised both ways, as core's own transforms (fft/complex_fft2d.h). The
// twiddles exp(-2 pi i j / n), j < n/2, are computed on the host in double.

layout(local_size_x = 64) in;

const uint kMaxLength = 4096u;  // 32 KiB of shared memory, the device's limit is checked on the host

layout(std430, binding = 0) buffer Data { vec2 v[]; } data;
layout(std430, binding = 1) readonly buffer Twiddles { vec2 w[]; } twiddles;

layout(push_constant) uniform Push {
    uint n;
    uint log2n;
    uint element_step;
    uint line_step;
    uint twiddle_offset;  // this length's table in the twiddle buffer
    uint inverse;         // 1: exp(+2 pi i ...)
} pc;

shared vec2 line[kMaxLength];

void main() {
    const uint base = gl_WorkGroupID.x * pc.line_step;
    for (uint i = gl_LocalInvocationID.x; i < pc.n; i += gl_WorkGroupSize.x)
        line[bitfieldReverse(i) >> (32u - pc.log2n)] = data.v[base + i * pc.element_step];
    memoryBarrierShared();
    barrier();
    for (uint s = 0u; s < pc.log2n; ++s) {
        const uint h = 1u << s;
        for (uint b = gl_LocalInvocationID.x; b < pc.n / 2u; b += gl_WorkGroupSize.x) {
            const uint k = b & (h - 1u);
            const uint i = ((b >> s) << (s + 1u)) + k, j = i + h;
            vec2 w = twiddles.w[pc.twiddle_offset + (k << (pc.log2n - 1u - s))];
            if (pc.inverse != 0u) w.y = -w.y;
            const vec2 a = line[i], c = line[j];
            const vec2 t = vec2(w.x * c.x - w.y * c.y, w.x * c.y + w.y * c.x);
            line[i] = a + t;
            line[j] = a - t;
        }
        memoryBarrierShared();
        barrier();
    }
    for (uint i = gl_LocalInvocationID.x; i < pc.n; i += gl_WorkGroupSize.x)
        data.v[base + i * pc.element_step] = line[i];
}
