// gpu_psf_summation.h in a build without Vulkan: no GpuPsfSummation can be made, and asking for one
// says why (as gpu_sums_absent.cpp).
#include "gpu/gpu_psf_summation.h"

#include "wavecam/gpu_sums.h"

namespace wavecam::detail {

struct GpuPsfSummation::Impl {};

Result<std::unique_ptr<GpuPsfSummation>> GpuPsfSummation::create(const ComputeDevice& device, int, int, int, int) {
    auto why = GpuSums::create(device);
    return Result<std::unique_ptr<GpuPsfSummation>>::failure(why.error, ErrorKind::Invalid, "device");
}

// Unreachable without an object; defined so that the class links.
GpuPsfSummation::GpuPsfSummation(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GpuPsfSummation::~GpuPsfSummation() = default;
Result<bool> GpuPsfSummation::set_spectrum(int, int, const std::complex<float>*) {
    return Result<bool>::failure("no Vulkan evaluator in this build");
}
void GpuPsfSummation::begin_run() {}
std::complex<float>* GpuPsfSummation::sources() { return nullptr; }
Result<bool> GpuPsfSummation::add_sources(int) { return Result<bool>::failure("no Vulkan evaluator in this build"); }
Result<bool> GpuPsfSummation::finish_run(bool, std::vector<float>&) {
    return Result<bool>::failure("no Vulkan evaluator in this build");
}

}  // namespace wavecam::detail
