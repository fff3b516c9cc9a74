// The chooser's estimates (core/src/summation/choose.h) against the time each evaluator takes:
// for small frames like tests/bench/run_summation_bench.sh's parts 1, 2 and 6 (uniform noise x a
// checker, depth 0.3 m at the top to 20 m at the bottom, the default pinhole for f = 50 mm, at
// 550 nm), each summation's estimate (estimate_summation, seconds at the term rate measured
// here) and its measured time through diffract_monochrome, and their ratio (measured /
// estimated; the chooser needs it within 2 either way). The label is the chooser's reason.
// Run: tests/bench/run_choice_bench.sh [build-dir]
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "wavecam/pinhole_design.h"
#include "wavecam/scene_diffraction.h"
#include "wavecam/term_rate.h"

using namespace wavecam;

namespace {

// A w x h frame at `fov_deg` (horizontal): radiance and planar depth.
struct Frame {
    PinholeCamera camera;
    std::vector<float> power, depth;
    Frame(int w, int h, double fov_deg) : camera{w, h, fov_deg * M_PI / 180, 50e-3} {
        uint64_t state = 1;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                state = state * 6364136223846793005ull + 1442695040888963407ull;
                const double noise = double(state >> 11) / double(1ull << 53);
                const bool light = ((i / 16) + (j / 16)) % 2 == 0;
                power.push_back(float(noise * (light ? 1.0 : 0.2)));
                depth.push_back(float(0.3 + (20 - 0.3) * (j + 0.5) / h));
            }
    }
};

// A case: the frame's side, its runs and method, and the summation measured.
struct Case {
    int side;
    int runs;
    bool incoherent;
    Summation summation;
};

void run_case(benchmark::State& state, const Case& k) {
    const Frame frame(k.side, k.side, 50.0);
    const double lambda = 550e-9;
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, rayleigh_optimal_diameter(50e-3, lambda)};
    s.method = k.incoherent ? CoherenceMethod::Incoherent : CoherenceMethod::RandomPhase;
    s.runs = k.runs;
    s.nearest_depth = nearest_depth(frame.camera, frame.depth.data(), DepthMeaning::Planar);
    s.summation = k.summation;
    // (auto: the estimate weighs the kernel summation against the point sums; the run takes what the job would)
    const double rate = measured_term_rate(0);
    const ComputeDevice cpu;
    const SummationEstimate e = estimate_summation(s, cpu, frame.camera, lambda, rate);
    s.summation = chosen_summation(s, cpu, frame.camera, lambda);
    const MonochromeScene scene{frame.camera, frame.power.data(), frame.depth.data(), DepthMeaning::Planar};
    std::vector<float> out(frame.power.size());
    double measured = 0;
    for (auto _ : state) {
        std::fill(out.begin(), out.end(), 0.0f);
        const auto start = std::chrono::steady_clock::now();
        const auto r = diffract_monochrome(scene, lambda, s, cpu, out.data());
        measured = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!r.ok()) state.SkipWithError(r.error.c_str());
        state.SetIterationTime(measured);
    }
    state.counters["estimated_s"] = e.seconds;
    state.counters["measured_s"] = measured;
    state.counters["term_rate"] = rate;
    state.counters["measured/estimated"] = e.seconds > 0 ? measured / e.seconds : 0.0;
    state.SetLabel(e.reason);
}

// part 1 (96 x 96, 1 run) shrunk: 40 x 40, 1 run, every evaluator
void BM_Part1_40px_1run(benchmark::State& state) {
    run_case(state, {40, 1, false, Summation(state.range(0))});
}
// part 2 (256 x 256, 3 wavelengths, 16 runs) shrunk: 96 x 96, 1 wavelength, 4 runs; the direct
// sums would take minutes
void BM_Part2_96px_4runs(benchmark::State& state) {
    run_case(state, {96, 4, false, Summation(state.range(0))});
}
// part 6 (128 x 128, 3 wavelengths, 16 and 64 runs, incoherent, the defaults) shrunk: 64 x 64,
// 1 wavelength
void BM_Part6_64px_16runs(benchmark::State& state) {
    run_case(state, {64, 16, false, Summation(state.range(0))});
}
void BM_Part6_64px_incoherent(benchmark::State& state) {
    run_case(state, {64, 1, true, Summation(state.range(0))});
}

constexpr int kAuto = int(Summation::Auto), kDirect = int(Summation::Direct), kNufft = int(Summation::Nufft),
              kPsf = int(Summation::Kernel);

}  // namespace

// (Arg: the summation, 0 auto, 1 direct, 2 nufft, 3 kernel)
BENCHMARK(BM_Part1_40px_1run)->Arg(kDirect)->Arg(kNufft)->Arg(kPsf)->Arg(kAuto)
    ->Unit(benchmark::kSecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_Part2_96px_4runs)->Arg(kNufft)->Arg(kPsf)->Arg(kAuto)
    ->Unit(benchmark::kSecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_Part6_64px_16runs)->Arg(kNufft)->Arg(kPsf)->Arg(kAuto)
    ->Unit(benchmark::kSecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_Part6_64px_incoherent)->Arg(kPsf)->Arg(kAuto)
    ->Unit(benchmark::kSecond)->UseManualTime()->Iterations(1);

BENCHMARK_MAIN();
