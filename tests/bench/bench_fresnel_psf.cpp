// Cost of one fast-path PSF kernel (field_psf_kernel) against the pinhole's size, for the
// benchmark camera: a 512-wide frame, 40deg across, f = 50 mm, 550 nm, the source at infinity in
// the frame's corner (the largest kernel). The radius is the one the convolution method asks for,
// psf_kernel_radius (kPsfKernelEnergy of the PSF), capped at the frame's half-width (256) or at
// the convolution method's default cap (32). Pinhole in micrometres is the benchmark's argument.
// Repeated requests share the transfer function's pupil spectrum, as a table's requests at one
// depth do, so the large pinholes' times are the per-request work without its forward FFT.
#include <benchmark/benchmark.h>

#include <cmath>

#include "wavecam/fresnel_psf.h"

using namespace wavecam;

namespace {
FieldPsfRequest corner_request(double pinhole, int max_radius) {
    const double f = 50e-3, tan_half = std::tan(20 * M_PI / 180);
    FieldPsfRequest q;
    q.aperture = {ApertureShape::Circle, pinhole};
    q.film_distance = f;
    q.wavelength = 550e-9;
    q.u = q.v = tan_half;
    q.pixel_pitch = 2 * f * tan_half / 512;
    const double cos_corner = 1.0 / std::sqrt(1.0 + 2 * tan_half * tan_half);
    q.radius = psf_kernel_radius({q.aperture, f, INFINITY, q.wavelength, cos_corner}, q.pixel_pitch, max_radius);
    return q;
}

void run(benchmark::State& state, int max_radius) {
    const FieldPsfRequest q = corner_request(state.range(0) * 1e-6, max_radius);
    for (auto _ : state) {
        PsfKernel k = field_psf_kernel(q);
        benchmark::DoNotOptimize(k.weight.data());
    }
    state.counters["radius"] = q.radius;
}

void BM_FieldPsfKernel(benchmark::State& state) { run(state, 256); }
void BM_FieldPsfKernelCap32(benchmark::State& state) { run(state, 32); }
}  // namespace

BENCHMARK(BM_FieldPsfKernel)->Arg(20)->Arg(80)->Arg(315)->Arg(1260)->Arg(2500)->Arg(5000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FieldPsfKernelCap32)->Arg(20)->Arg(80)->Arg(315)->Arg(1260)->Arg(2500)->Arg(5000)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
