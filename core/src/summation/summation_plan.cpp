// The point sums' plans (summation_plan.h): committed to the evaluator the chooser (choose.h) picks.
#include "wavecam/summation_plan.h"

#include <cmath>

#include "summation/nufft/lattice_layout.h"
#include "summation/summation_evaluator.h"
#include "summation/choose.h"

namespace wavecam {

struct SummationPlan::Impl {
    ComputeDevice device;
    SumKind kind;
    ApertureSamples samples;
    double wavelength;
    SummationSettings settings;
    PlanScope scope;
    std::vector<PointSource> sources;
    FilmPoints film;
    SumChoice choice;
    std::unique_ptr<detail::SumEvaluator> evaluator;

    size_t points() const { return kind == SumKind::PinholeToFilm ? film.size() : sources.size(); }

    // The plan's counts for the cost model: its own samples and points.
    SumCounts counts(const DirectionRange& range) const {
        const detail::SampleCount n = detail::count_samples(samples);
        SumCounts c;
        c.lattice_samples = n.on;
        c.off_lattice = n.off;
        c.samples_across = samples.pitch > 0 ? int(std::ceil(2 * n.reach / samples.pitch)) + 1 : 0;
        c.points = double(points());
        c.range = range;
        c.aperture_radius = n.reach;
        c.wavelength = wavelength;
        c.film = kind == SumKind::PinholeToFilm;
        c.tolerance = settings.tolerance;
        return c;
    }

    // The points' direction range (film points at the film's inverse distance).
    DirectionRange range() const {
        if (scope.fixed_range) return scope.range;
        DirectionRange r;
        bool first = true;
        auto take = [&](double ux, double uy, double rho) {
            if (first) r = {ux, ux, uy, uy, rho, rho}, first = false;
            r.ux0 = std::min(r.ux0, ux), r.ux1 = std::max(r.ux1, ux);
            r.uy0 = std::min(r.uy0, uy), r.uy1 = std::max(r.uy1, uy);
            r.rho0 = std::min(r.rho0, rho), r.rho1 = std::max(r.rho1, rho);
        };
        if (kind == SumKind::PinholeToFilm) {
            const double f = film.film_distance;
            for (size_t t = 0; t < film.size(); ++t) {
                const double R = std::sqrt(double(film.x[t]) * film.x[t] + double(film.y[t]) * film.y[t] + f * f);
                take(film.x[t] / R, film.y[t] / R, 1 / f);
            }
        } else {
            for (const PointSource& s : sources) {
                const double R = s.at_infinity ? 1 : std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
                take(s.x / R, s.y / R, s.at_infinity ? 0.0 : 1.0 / R);
            }
        }
        return r;
    }

    // Commit: the evaluator chosen (choose.h; or the job's, for a share) and built for the
    // points; the direct terms on the plan's device (a GPU runs the direct terms alone).
    Result<bool> commit() {
        const bool empty = points() == 0 || samples.size() == 0;
        // (counted only where the chooser weighs them: not for the job's choice, nor no points)
        const bool weighed = !empty && !scope.fixed_choice;
        const SumCounts n = weighed ? counts(range()) : SumCounts{};
        auto chosen = detail::choose_plan_sum(
            {&n, empty, settings.summation, scope.fixed_choice ? &scope.choice : nullptr}, device);
        if (!chosen.ok()) return Result<bool>::failure(chosen);
        choice = chosen.value;
        const detail::SumGeometry g{kind, &samples, wavelength, settings, &device, scope, &sources, &film};
        // its evaluator from the evaluators' table (no points: the direct terms, none of them)
        const Summation runs = empty ? Summation::Direct : detail::summation_of(choice.evaluator);
        evaluator = detail::evaluator_row(runs, choice.gpu ? Device::Gpu : Device::Cpu).create_sum(g, choice);
        return Result<bool>::success(true);
    }
};

SummationPlan SummationPlan::create(const ComputeDevice& device, SumKind kind, const ApertureSamples& samples,
                                    double wavelength, const SummationSettings& settings, const PlanScope& scope) {
    SummationPlan plan;
    plan.impl_ = std::make_shared<Impl>();
    Impl& p = *plan.impl_;
    p.device = device;
    p.kind = kind;
    p.samples = samples;
    p.wavelength = wavelength;
    p.settings = settings;
    p.scope = scope;
    return plan;
}

Result<bool> SummationPlan::set_points(const std::vector<PointSource>& sources) {
    impl_->sources = sources;
    return impl_->commit();
}

Result<bool> SummationPlan::set_points(const FilmPoints& film) {
    impl_->film = film;
    return impl_->commit();
}

Result<bool> SummationPlan::execute(const std::vector<std::complex<double>>& weights, PinholeField& field,
                                    const ProgressFn& progress) const {
    return impl_->evaluator->sources_to_pinhole(weights, field, progress);
}

Result<bool> SummationPlan::execute(const PinholeField& field, std::complex<double>* film_field,
                                    const ProgressFn& progress) const {
    return impl_->evaluator->pinhole_to_film(field, film_field, progress);
}

Result<bool> SummationPlan::execute_irradiance(const PinholeField& field, double scale, float* irradiance,
                                               const ProgressFn& progress) const {
    std::vector<std::complex<double>> u(impl_->film.size(), 0.0);
    if (auto r = execute(field, u.data(), progress); !r.ok()) return r;
    for (size_t t = 0; t < u.size(); ++t) irradiance[t] += static_cast<float>(scale * std::norm(u[t]));
    return Result<bool>::success(true);
}

const SumChoice& SummationPlan::choice() const { return impl_->choice; }

size_t SummationPlan::point_count() const { return impl_->points(); }

std::vector<std::complex<double>> source_weights(const std::vector<PointSource>& sources) {
    std::vector<std::complex<double>> w;
    w.reserve(sources.size());
    for (const PointSource& s : sources) w.push_back(std::polar(s.amplitude, s.phase));
    return w;
}

}  // namespace wavecam
