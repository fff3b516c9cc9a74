// An evaluator behind a committed summation plan (summation_plan.h): the two sums for the plan's
// fixed geometry, executed for one set of weights at a time. Internal to core.
#pragma once
#include <complex>
#include <memory>
#include <vector>

#include "wavecam/summation_plan.h"

namespace wavecam::detail {

class SumEvaluator {
public:
    virtual ~SumEvaluator() = default;
    // Sources to pinhole: `field` set (resized to the samples).
    virtual Result<bool> sources_to_pinhole(const std::vector<std::complex<double>>& weights, PinholeField& field,
                                            const ProgressFn& progress) const = 0;
    // Pinhole to film: added to film_field.
    virtual Result<bool> pinhole_to_film(const PinholeField& field, std::complex<double>* film_field,
                                         const ProgressFn& progress) const = 0;
};

// What an evaluator is built for: the plan's geometry, its points committed.
struct SumGeometry {
    SumKind kind = SumKind::SourcesToPinhole;
    const ApertureSamples* samples = nullptr;
    double wavelength = 0;
    SummationSettings settings;
    const ComputeDevice* device = nullptr;              // the plan's
    PlanScope scope;
    const std::vector<PointSource>* sources = nullptr;  // SourcesToPinhole
    const FilmPoints* film = nullptr;                   // PinholeToFilm
};

std::unique_ptr<SumEvaluator> make_direct_evaluator(const SumGeometry& g);
std::unique_ptr<SumEvaluator> make_nufft_evaluator(const SumGeometry& g, const SumChoice& choice);
// The direct terms on the GPU of the plan's device (a handle with one: gpu_sums.h).
std::unique_ptr<SumEvaluator> make_gpu_direct_evaluator(const SumGeometry& g);

// What the CPU evaluators' `false` (cancelled through progress) becomes.
inline Result<bool> finished(bool done) {
    return done ? Result<bool>::success(true) : Result<bool>::failure("cancelled", ErrorKind::Cancelled);
}

// Sources with the complex amplitudes `weights` (the direct kernel's form, propagation.h).
std::vector<PointSource> weighted(const std::vector<PointSource>& sources,
                                  const std::vector<std::complex<double>>& weights);

}  // namespace wavecam::detail
