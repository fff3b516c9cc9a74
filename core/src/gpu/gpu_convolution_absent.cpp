// gpu_convolution.h in a build without Vulkan: no GpuConvolution can be made, and asking for one
// says why (as gpu_sums_absent.cpp).
#include "gpu_convolution.h"

#include "wavecam/gpu_sums.h"

namespace wavecam::detail {

struct GpuConvolution::Impl {};

Result<std::unique_ptr<GpuConvolution>> GpuConvolution::create(const ComputeDevice& device, int, int, int, int) {
    auto why = GpuSums::create(device);
    return Result<std::unique_ptr<GpuConvolution>>::failure(why.error, ErrorKind::Invalid, "device");
}

// Unreachable without an object; defined so that the class links.
GpuConvolution::GpuConvolution(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GpuConvolution::~GpuConvolution() = default;
Result<bool> GpuConvolution::set_spectrum(int, int, const std::complex<float>*) {
    return Result<bool>::failure("no Vulkan evaluator in this build");
}
void GpuConvolution::begin_run() {}
std::complex<float>* GpuConvolution::sources() { return nullptr; }
Result<bool> GpuConvolution::add_sources(int) { return Result<bool>::failure("no Vulkan evaluator in this build"); }
Result<bool> GpuConvolution::finish_run(bool, std::vector<float>&) {
    return Result<bool>::failure("no Vulkan evaluator in this build");
}

}  // namespace wavecam::detail
