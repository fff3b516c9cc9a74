#include "summation/kernel/gpu_run_cost.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "gpu/gpu_kernel_summation.h"
#include "summation/choose.h"
#include "wavecam/term_rate.h"

namespace wavecam::detail {
namespace {

// One domain of the probe: K kernels of one sub-point through nx x ny transforms, and what the
// cost model counts for its run (kernel_summation_work: K forward transforms, K + 1 products a
// point, one inverse transform).
struct ProbeDomain {
    int nx, ny, kernels;
    double terms() const {
        const double N = double(nx) * ny, transform = kFftCost * N * std::log2(N);
        return kernels * transform + (kernels + 1) * N * kMacCost + transform;
    }
};

// The fastest of a few runs through the device's shaders (the first pays for the pipelines'
// first use); NaN where the device cannot run them.
double fastest_run(const ComputeDevice& device, const ProbeDomain& d) {
    auto made = GpuKernelSummation::create(device, d.nx, d.ny, d.kernels, 1);
    if (!made.ok()) return NAN;
    GpuKernelSummation& runs = *made.value;
    const size_t N = size_t(d.nx) * d.ny;
    const std::vector<std::complex<float>> spectrum(N, std::complex<float>(1.0f / N, 0.0f));
    for (int k = 0; k < d.kernels; ++k)
        if (!runs.set_spectrum(k, 0, spectrum.data()).ok()) return NAN;
    std::vector<float> sum;
    using clock = std::chrono::steady_clock;
    double fastest = INFINITY;
    for (int pass = 0; pass < 4; ++pass) {
        const auto begin = clock::now();
        runs.begin_run();
        for (int k = 0; k < d.kernels; ++k) {
            std::complex<float>* s = runs.sources();
            for (size_t p = 0; p < N; ++p) s[p] = std::complex<float>(float((p * 2654435761u) % 97) / 97.0f, 0.0f);
            if (!runs.add_sources(k).ok()) return NAN;
        }
        if (!runs.finish_run(false, sum).ok()) return NAN;
        if (pass > 0) fastest = std::min(fastest, std::chrono::duration<double>(clock::now() - begin).count());
    }
    return fastest;
}

GpuRunCost probe(const ComputeDevice& device) {
    // latency: many kernels on a small domain; work: few on a large one. Solved for both from
    // t = (K + 1) latency + factor x terms / rate at each.
    const ProbeDomain many{64, 32, 16}, large{256, 256, 4};
    const double t_many = fastest_run(device, many), t_large = fastest_run(device, large);
    if (!std::isfinite(t_many) || !std::isfinite(t_large)) return {};
    const double rate = measured_term_rate(device);
    const double share = many.terms() / large.terms();
    const double latency =
        std::max(0.0, (t_many - t_large * share) / ((many.kernels + 1) - (large.kernels + 1) * share));
    GpuRunCost cost;
    cost.factor = std::clamp((t_large - (large.kernels + 1) * latency) * rate / large.terms(), 0.1, 100.0);
    cost.per_dispatch = latency * rate;
    return cost;
}

}  // namespace

GpuRunCost gpu_run_cost(const ComputeDevice& device) {
    if (!device.gpu()) return {};
    static std::mutex lock;
    static std::map<std::string, GpuRunCost> measured;
    std::lock_guard<std::mutex> guard(lock);
    const std::string name = device.description();
    if (auto it = measured.find(name); it != measured.end()) return it->second;
    return measured[name] = probe(device);
}

}  // namespace wavecam::detail
