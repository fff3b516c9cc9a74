// Direct terms per second of the point sums on every device found: the CPU's direct kernel
// (propagation.cpp, all cores) and the Vulkan evaluator (gpu_sums.h) on the device `gpu` picks
// (set VK_ICD_FILENAMES to choose a driver, e.g. Mesa's lavapipe). One term = one pinhole sample
// contributing to one film point (sum 2) or one source to one pinhole sample (sum 1).
// And the kernel summation's frames (kernel_summation.h) on each device: 1 and 16 runs of a
// 96 x 96 frame, so that the script can take one run's time as the difference over 15.
// Run: tests/bench/run_gpu_bench.sh [build-dir]
#include <benchmark/benchmark.h>

#include <cmath>
#include <complex>

#include "wavecam/gpu_sums.h"
#include "wavecam/propagation.h"
#include "wavecam/scene_diffraction.h"

using namespace wavecam;

namespace {
// bench_kernel's case: the optimal pinhole of `wavecam psf`'s default (0.3 mm, f = 65 mm,
// 550 nm, about 9.3e5 samples at lambda / 2), a plane wave on axis; a 0.6 mm film window of
// 32 x 32 points; for sum 1, 1024 sources 1 m away within 5 degrees of the axis.
struct Case {
    double f = 65e-3, lambda = 550e-9;
    ApertureSamples samples = sample_aperture({ApertureShape::Circle, 0.3e-3}, sample_pitch(550e-9));
    PinholeField field;
    FilmPoints film;
    std::vector<PointSource> sources;
    Case() {
        illuminate_pinhole(samples, {source_at_field_angle(INFINITY, 0)}, lambda, field);
        film.film_distance = f;
        const int n = 32;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                film.x.push_back(static_cast<float>((i - n / 2) * 0.6e-3 / n));
                film.y.push_back(static_cast<float>((j - n / 2) * 0.6e-3 / n));
                PointSource s;
                s.x = (i - n / 2) * 0.09 / n;
                s.y = (j - n / 2) * 0.09 / n;
                s.z = 1.0;
                s.phase = 0.1 * (i + 7 * j);
                sources.push_back(s);
            }
    }
    double film_terms() const { return double(samples.size()) * film.size(); }
    double pinhole_terms() const { return double(samples.size()) * sources.size(); }
};

const Case& the_case() {
    static const Case c;
    return c;
}

void rate(benchmark::State& state, double terms) {
    state.counters["terms_per_s"] = benchmark::Counter(terms * state.iterations(), benchmark::Counter::kIsRate);
}

void BM_FilmSumCpu(benchmark::State& state) {
    const Case& c = the_case();
    std::vector<std::complex<double>> u(c.film.size());
    for (auto _ : state) add_film_field({c.samples, c.field, c.film, c.lambda}, u.data());
    state.SetLabel("CPU direct kernel");
    rate(state, c.film_terms());
}

void BM_PinholeSumCpu(benchmark::State& state) {
    const Case& c = the_case();
    PinholeField w;
    for (auto _ : state) illuminate_pinhole(c.samples, c.sources, c.lambda, w);
    state.SetLabel("CPU direct kernel");
    rate(state, c.pinhole_terms());
}

// A handle on the Vulkan device for one benchmark (opened before its timing), or none: the
// benchmark skipped with the reason.
ComputeDevice gpu_device(benchmark::State& state) {
    ComputeDevice d = ComputeDevice::create(Device::Gpu);
    if (!d.ok()) state.SkipWithError(d.error().c_str());
    else state.SetLabel(d.description());
    return d;
}

// The device's direct sums (they keep its context), or null.
std::shared_ptr<GpuSums> gpu(benchmark::State& state) {
    const ComputeDevice d = gpu_device(state);
    return d.ok() ? GpuSums::create(d).value : nullptr;
}

// state.range(0) runs at once (their weight vectors share the geometry: one dispatch).
void BM_FilmSumGpu(benchmark::State& state) {
    const Case& c = the_case();
    auto g = gpu(state);
    if (!g) return;
    const size_t runs = size_t(state.range(0));
    const std::vector<PinholeField> fields(runs, c.field);
    std::vector<std::vector<std::complex<double>>> u(runs, std::vector<std::complex<double>>(c.film.size()));
    std::vector<std::complex<double>*> out;
    for (auto& v : u) out.push_back(v.data());
    for (auto _ : state)
        if (auto r = g->add_film_field_runs(c.samples, fields, c.film, c.lambda, out); !r.ok())
            state.SkipWithError(r.error.c_str());
    rate(state, c.film_terms() * runs);
}

void BM_PinholeSumGpu(benchmark::State& state) {
    const Case& c = the_case();
    auto g = gpu(state);
    if (!g) return;
    PinholeField w;
    for (auto _ : state)
        if (auto r = g->illuminate_pinhole(c.samples, c.sources, c.lambda, w); !r.ok())
            state.SkipWithError(r.error.c_str());
    rate(state, c.pinhole_terms());
}
// A textured 96 x 96 frame at 30 deg, f = 2 mm, a 0.05 mm pinhole, 550 nm, two depths: the kernel
// summation with state.range(0) runs on `device`.
void psf_frame(benchmark::State& state, const ComputeDevice& device) {
    PinholeCamera c{96, 96, 30 * M_PI / 180, 2e-3};
    std::vector<float> power(size_t(c.width) * c.height), depth(power.size()), out(power.size());
    for (size_t p = 0; p < power.size(); ++p) {
        power[p] = float(0.2 + 0.8 * ((p * 2654435761u) >> 8 & 0xffff) / 65535.0);
        depth[p] = p % c.width < 48 ? 0.05f : 2.0f;
    }
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, 0.05e-3};
    s.runs = int(state.range(0));
    s.summation = Summation::Kernel;
    const MonochromeScene scene{c, power.data(), depth.data(), DepthMeaning::Planar};
    for (auto _ : state)
        if (auto r = diffract_monochrome(scene, 550e-9, s, device, out.data()); !r.ok())
            state.SkipWithError(r.error.c_str());
}

void BM_PsfFrameCpu(benchmark::State& state) {
    state.SetLabel("CPU");
    psf_frame(state, ComputeDevice{});
}

void BM_PsfFrameGpu(benchmark::State& state) {
    const ComputeDevice d = gpu_device(state);
    if (d.ok()) psf_frame(state, d);
}
}  // namespace

BENCHMARK(BM_PsfFrameCpu)->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_PsfFrameGpu)->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_FilmSumCpu)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_PinholeSumCpu)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_FilmSumGpu)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_PinholeSumGpu)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_MAIN();
