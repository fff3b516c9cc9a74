// gpu_kernel_summation.h in a build without Vulkan: no GpuKernelSummation can be made, and asking for one
// says why (as gpu_sums_absent.cpp).
#include "gpu/gpu_kernel_summation.h"

#include "wavecam/gpu_sums.h"

namespace wavecam::detail {

struct GpuKernelSummation::Impl {};

Result<std::unique_ptr<GpuKernelSummation>> GpuKernelSummation::create(const ComputeDevice& device, int, int, int, int) {
    auto why = GpuSums::create(device);
    return Result<std::unique_ptr<GpuKernelSummation>>::failure(why.error, ErrorKind::Invalid, "device");
}

// Unreachable without an object; defined so that the class links.
GpuKernelSummation::GpuKernelSummation(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GpuKernelSummation::~GpuKernelSummation() = default;
Result<bool> GpuKernelSummation::set_spectrum(int, int, const std::complex<float>*) {
    return Result<bool>::failure("no Vulkan evaluator in this build");
}
void GpuKernelSummation::begin_run() {}
std::complex<float>* GpuKernelSummation::sources() { return nullptr; }
Result<bool> GpuKernelSummation::add_sources(int) { return Result<bool>::failure("no Vulkan evaluator in this build"); }
Result<bool> GpuKernelSummation::finish_run(bool, std::vector<float>&) {
    return Result<bool>::failure("no Vulkan evaluator in this build");
}

}  // namespace wavecam::detail
