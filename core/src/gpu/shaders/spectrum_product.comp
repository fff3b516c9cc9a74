#version 450
// One kernel's share of a run in the frequency domain (kernel_summation.h):
//   total[q] += image[q] * spectrum[q]
// for the n points of a transform; the spectrum at an offset in its buffer (several spectra share
// one buffer).

layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Image { vec2 v[]; } image;
layout(std430, binding = 1) readonly buffer Spectra { vec2 v[]; } spectra;
layout(std430, binding = 2) buffer Total { vec2 v[]; } total;

layout(push_constant) uniform Push {
    uint n;
    uint spectrum_offset;
} pc;

void main() {
    const uint q = gl_GlobalInvocationID.x;
    if (q >= pc.n) return;
    const vec2 a = image.v[q], k = spectra.v[pc.spectrum_offset + q];
    total.v[q] += vec2(a.x * k.x - a.y * k.y, a.x * k.y + a.y * k.x);
}
