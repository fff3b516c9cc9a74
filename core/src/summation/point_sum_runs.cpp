// The point sums' runs (summation_evaluator.h; the direct and nufft rows): each run's two sums
// through two plans (summation_plan.h), each sum by the evaluator decided for the frame
// (decide_sums, in diffract_monochrome), so that every share evaluates its part as the job would.
#include <algorithm>

#include "summation/scene_runs.h"
#include "summation/summation_evaluator.h"

namespace wavecam::detail {
namespace {

class PointSumRuns final : public SummationEvaluator {
public:
    explicit PointSumRuns(const EvaluatorSetup& setup) : setup_(setup) {
        const SceneSumSettings& s = *setup.settings;
        incoherent_ = s.method == CoherenceMethod::Incoherent;
        sums_ = *setup.sums;
    }

    Result<bool> set_points(const ProgressFn&) override {
        const SceneSum& sum = *setup_.sum;
        to_film_ = SummationPlan::create(*setup_.device, SumKind::PinholeToFilm, sum.samples, setup_.wavelength,
                                         sums_.settings, sums_.out);
        points_.assign(sum.film.size(), 0.0f);  // irradiance at every film point
        auto r = to_film_.set_points(sum.film);
        if (r.ok()) note(to_film_, SumKind::PinholeToFilm);
        return r;
    }

    Result<bool> execute(const RunBatch& batch, float* irradiance, const ProgressFn& progress) override {
        if (!incoherent_) return random_phase_runs(batch, irradiance, progress);
        auto r = incoherent_sum(progress);
        if (r.ok()) average_into_output(points_, *setup_.sum, setup_.scene->camera, setup_.settings->overscan,
                                        setup_.range, irradiance);
        return r;
    }

private:
    // A committed plan's evaluator, noted in the job's report (a plan with points and samples).
    void note(const SummationPlan& plan, SumKind kind) const {
        if (setup_.report && plan.point_count() > 0 && setup_.sum->samples.size() > 0)
            setup_.report->note(kind, plan.choice());
    }

    // Incoherent: every source through the pinhole alone, the film's irradiances summed.
    Result<bool> incoherent_sum(const ProgressFn& progress) {
        const SceneSum& sum = *setup_.sum;
        const PinholeCamera& c = setup_.scene->camera;
        PinholeField field;
        const size_t n = sum.emitters.size();
        for (size_t k = 0; k < n; ++k) {
            const std::vector<PointSource> one{centred(c, sum.emitters[k], 0.0)};
            SummationPlan to_pinhole = SummationPlan::create(*setup_.device, SumKind::SourcesToPinhole, sum.samples,
                                                             setup_.wavelength, sums_.settings, sums_.in);
            if (auto r = to_pinhole.set_points(one); !r.ok()) return r;
            note(to_pinhole, SumKind::SourcesToPinhole);
            if (auto r = to_pinhole.execute(source_weights(one), field); !r.ok()) return r;
            if (auto r = to_film_.execute_irradiance(field, 1.0, points_.data(),
                                                     progress_slice(progress, double(k) / n, double(k + 1) / n));
                !r.ok())
                return r;
        }
        return Result<bool>::success(true);
    }

    // Random phase (the seed paper): each run every source at once with its own phase, weighted
    // 1/runs and averaged into the output on its own, so a job equals the sum of its shares. The
    // sources stay where they are from run to run (but for independent phases with jitter): one
    // plan serves every run, each run only new weights.
    Result<bool> random_phase_runs(const RunBatch& batch, float* irradiance, const ProgressFn& progress) {
        const SceneSum& sum = *setup_.sum;
        const PinholeCamera& c = setup_.scene->camera;
        const SceneSumSettings& s = *setup_.settings;
        const double wavelength = setup_.wavelength;
        PinholeField field;
        const PhaseCode code(s.runs);
        const PhaseDraw draw{s, code, wavelength_stream(wavelength)};
        const bool moving = s.jitter && !s.coded_phases;
        SummationPlan to_pinhole;
        const int first = batch.run_begin, runs = batch.run_end - batch.run_begin;
        for (int run = first; run < batch.run_end; ++run) {
            const std::vector<PointSource> sources = run_sources(c, sum.emitters, draw, run);
            if (!to_pinhole || moving) {
                to_pinhole = SummationPlan::create(*setup_.device, SumKind::SourcesToPinhole, sum.samples, wavelength,
                                                   sums_.settings, sums_.in);
                if (auto r = to_pinhole.set_points(sources); !r.ok()) return r;
                note(to_pinhole, SumKind::SourcesToPinhole);
            }
            // half of a run's terms go to the pinhole, half to the film
            const double at = double(run - first) / runs, half = 0.5 / runs;
            if (auto r = to_pinhole.execute(source_weights(sources), field, progress_slice(progress, at, at + half));
                !r.ok())
                return r;
            if (auto r = to_film_.execute_irradiance(field, 1.0 / s.runs, points_.data(),
                                                     progress_slice(progress, at + half, at + 2 * half));
                !r.ok())
                return r;
            average_into_output(points_, sum, c, s.overscan, setup_.range, irradiance);
        }
        return Result<bool>::success(true);
    }

    EvaluatorSetup setup_;
    bool incoherent_ = false;
    SumChoices sums_;
    SummationPlan to_film_;
    std::vector<float> points_;
};

}  // namespace

std::unique_ptr<SummationEvaluator> make_point_sum_runs(const EvaluatorSetup& setup) {
    return std::make_unique<PointSumRuns>(setup);
}

}  // namespace wavecam::detail
