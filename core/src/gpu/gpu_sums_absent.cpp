// wavecam/gpu_sums.h in a build without Vulkan (WAVECAM_VULKAN off, or the loader or glslc not
// found): no Vulkan context and no GpuSums can be made, and asking for one says why.
#include "wavecam/gpu_sums.h"

#include "gpu/compute_device_impl.h"

namespace wavecam {

namespace {
const char* const kWithoutVulkan =
    "this wavecam was built without its Vulkan evaluator (the Vulkan loader or glslc was not found when it "
    "was built): only the device `cpu` is available";
}

Result<std::shared_ptr<gpu::Context>> detail::open_vulkan(bool) {
    return Result<std::shared_ptr<gpu::Context>>::failure(kWithoutVulkan, ErrorKind::Invalid, "device");
}


struct GpuSums::Impl {};

Result<std::shared_ptr<GpuSums>> GpuSums::create(const ComputeDevice&, bool) {
    return Result<std::shared_ptr<GpuSums>>::failure(kWithoutVulkan, ErrorKind::Invalid, "device");
}

// Unreachable without an object; defined so that the class links.
GpuSums::GpuSums(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GpuSums::~GpuSums() = default;
const std::string& GpuSums::device_name() const {
    static const std::string none;
    return none;
}
const std::string& GpuSums::driver() const { return device_name(); }
bool GpuSums::double_blocks() const { return false; }
std::string GpuSums::description() const { return {}; }
Result<bool> GpuSums::illuminate_pinhole(const ApertureSamples&, const std::vector<PointSource>&, double,
                                         PinholeField&, const ProgressFn&) {
    return Result<bool>::failure(kWithoutVulkan);
}
Result<bool> GpuSums::illuminate_pinhole_runs(const ApertureSamples&, const std::vector<PointSource>&,
                                              const RunWeights&, double, std::vector<PinholeField>&,
                                              const ProgressFn&) {
    return Result<bool>::failure(kWithoutVulkan);
}
Result<bool> GpuSums::add_film_field(const ApertureSamples&, const PinholeField&, const FilmPoints&, double,
                                     std::complex<double>*, const ProgressFn&) {
    return Result<bool>::failure(kWithoutVulkan);
}
Result<bool> GpuSums::add_film_field_runs(const ApertureSamples&, const std::vector<PinholeField>&,
                                          const FilmPoints&, double, const std::vector<std::complex<double>*>&,
                                          const ProgressFn&) {
    return Result<bool>::failure(kWithoutVulkan);
}

}  // namespace wavecam
