// The direct terms on a GPU (gpu_sums.h): the direct evaluator's sums through Vulkan compute.
#include "gpu/compute_device_impl.h"
#include "summation/sum_evaluator.h"
#include "wavecam/gpu_sums.h"

namespace wavecam::detail {
namespace {

class GpuDirectEvaluator final : public SumEvaluator {
public:
    GpuDirectEvaluator(const SumGeometry& g, std::shared_ptr<GpuSums> gpu) : g_(g), gpu_(std::move(gpu)) {}
    Result<bool> sources_to_pinhole(const std::vector<std::complex<double>>& weights, PinholeField& field,
                                    const ProgressFn& progress) const override {
        // the weights as they are (one run): no round trip through amplitude and phase
        std::vector<PinholeField> fields;
        auto r = gpu_->illuminate_pinhole_runs(*g_.samples, *g_.sources, {weights, 1}, g_.wavelength, fields, progress);
        if (r.ok()) field = std::move(fields[0]);
        return r;
    }
    Result<bool> pinhole_to_film(const PinholeField& field, std::complex<double>* film_field,
                                 const ProgressFn& progress) const override {
        return gpu_->add_film_field(*g_.samples, field, *g_.film, g_.wavelength, film_field, progress);
    }

private:
    SumGeometry g_;
    std::shared_ptr<GpuSums> gpu_;
};

}  // namespace

std::unique_ptr<SumEvaluator> make_gpu_direct_evaluator(const SumGeometry& g) {
    return std::make_unique<GpuDirectEvaluator>(g, g.device->impl()->sums);
}

}  // namespace wavecam::detail
