// The kernel summation's runs (kernel_summation.h) on a Vulkan device (docs/gpu.md): the
// kernels' spectra kept on the device; per run, each kernel's share of the sources transformed
// there, multiplied by its spectra and summed per film sub-point, then transformed back and
// squared (or, for powers, taken as they are) into one value per domain point. Transforms are
// radix-2 FFTs in shared memory (shaders/fft_lines.comp): both sides powers of two up to 4096.
// Internal to core; errors are values.
#pragma once
#include <complex>
#include <memory>
#include <vector>

#include "wavecam/compute_device.h"
#include "wavecam/result.h"

namespace wavecam::detail {

class GpuKernelSummation {
public:
    // The largest transform side the device's shaders take.
    static constexpr int kMaxSide = 4096;
    // On `device`'s Vulkan context (the one its direct sums use) for transforms of nx x ny points
    // (powers of two), `kernels` kernels of `points` sub-points each. Fails naming what is
    // missing or what the device cannot hold.
    static Result<std::unique_ptr<GpuKernelSummation>> create(const ComputeDevice& device, int nx, int ny, int kernels,
                                                           int points);
    ~GpuKernelSummation();
    GpuKernelSummation(const GpuKernelSummation&) = delete;
    GpuKernelSummation& operator=(const GpuKernelSummation&) = delete;

    // The spectrum (nx x ny, row-major) of kernel `kernel`'s sub-point `point`.
    Result<bool> set_spectrum(int kernel, int point, const std::complex<float>* spectrum);

    // A run: begin; for each kernel with light, fill sources() (nx x ny, row-major, in the
    // device's mapped memory) and add it; finish with each domain point's sum over sub-points of
    // |u|^2 (or of Re u where `powers`), unnormalised as core's transforms (fft/).
    void begin_run();
    std::complex<float>* sources();
    Result<bool> add_sources(int kernel);
    Result<bool> finish_run(bool powers, std::vector<float>& sum);

    struct Impl;

private:
    explicit GpuKernelSummation(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace wavecam::detail
