// The direct evaluator: the two sums term by term (propagation.h), the reference.
#include <cmath>

#include "summation/sum_evaluator.h"

namespace wavecam::detail {
namespace {

class DirectEvaluator final : public SumEvaluator {
public:
    explicit DirectEvaluator(const SumGeometry& g) : g_(g) {}
    Result<bool> sources_to_pinhole(const std::vector<std::complex<double>>& weights, PinholeField& field,
                                    const ProgressFn& progress) const override {
        return finished(illuminate_pinhole(*g_.samples, weighted(*g_.sources, weights), g_.wavelength, field,
                                           g_.settings.nthreads, progress));
    }
    Result<bool> pinhole_to_film(const PinholeField& field, std::complex<double>* film_field,
                                 const ProgressFn& progress) const override {
        return finished(
            add_film_field({*g_.samples, field, *g_.film, g_.wavelength}, film_field, g_.settings.nthreads, progress));
    }

private:
    SumGeometry g_;
};

}  // namespace

std::vector<PointSource> weighted(const std::vector<PointSource>& sources,
                                  const std::vector<std::complex<double>>& weights) {
    std::vector<PointSource> out = sources;
    for (size_t s = 0; s < out.size(); ++s) {
        out[s].amplitude = std::abs(weights[s]);
        out[s].phase = std::arg(weights[s]);
    }
    return out;
}

std::unique_ptr<SumEvaluator> make_direct_evaluator(const SumGeometry& g) { return std::make_unique<DirectEvaluator>(g); }

}  // namespace wavecam::detail
