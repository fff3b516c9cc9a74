#version 450
// A film point's share of its pixel after the inverse transform (kernel_summation.h):
//   pixel[q] += |u[q]|^2   (amplitudes), or  u[q].x  (the incoherent case: powers convolved).

layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Field { vec2 v[]; } field;
layout(std430, binding = 1) buffer Pixel { float v[]; } pixel;

layout(push_constant) uniform Push {
    uint n;
    uint powers;  // 1: the field holds powers already
} pc;

void main() {
    const uint q = gl_GlobalInvocationID.x;
    if (q >= pc.n) return;
    const vec2 u = field.v[q];
    pixel.v[q] += pc.powers != 0u ? u.x : dot(u, u);
}
