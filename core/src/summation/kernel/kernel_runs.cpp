// The kernel summation's runs (summation_evaluator.h; the kernel row): each run a convolution of the
// sources' complex weights with amplitude PSFs (kernel_summation.h). The sources are every
// pixel of the convolution's domain at its centre: the input's, and beyond it the edge continued
// pixel by pixel (each with the edge pixel's radiance and planar depth at its own field
// position), each with the phases the direct sums give it (scene_runs.h): an input pixel keeps
// its key, so a scene whose edge is dark gets the direct sums' runs, kernel blends apart. The
// convolution comes from the job's memo where one is given (the kernels of a wavelength's other
// part), and the runs go through it several at once.
#include <algorithm>
#include <cmath>

#include "base/parallel.h"
#include "wavecam/edge_continuation.h"
#include "summation/kernel/source_kernels.h"
#include "summation/scene_runs.h"
#include "summation/summation_evaluator.h"

namespace wavecam::detail {
namespace {

class KernelRuns final : public SummationEvaluator {
public:
    explicit KernelRuns(const EvaluatorSetup& setup) : setup_(setup) {
        const SceneSumSettings& s = *setup.settings;
        const SceneSum& sum = *setup.sum;
        too_deep_ = too_deep_for_kernel(setup.nearest, s.aperture, setup.wavelength);
        if (too_deep_) return;  // refused by set_points, before any work
        spec_ = kernel_summation_spec(s, setup.scene->camera, setup.wavelength, setup.nearest, sum.subsamples);
        // progress: the kernels and the runs by their work
        const int runs = spec_.incoherent ? 1 : setup.range.run_end - setup.range.run_begin;
        pitch_ = kernel_lattice_pitch(spec_, sum.samples.pitch);
        const KernelSummationWork work = kernel_work(s, sum, spec_, setup.nearest, pitch_, *setup.device);
        kernels_ = work.kernels / (work.kernels + runs * work.per_run);
    }

    double setup_share() const override { return kernels_; }

    Result<bool> set_points(const ProgressFn& progress) override {
        const PinholeCamera& c = setup_.scene->camera;
        if (too_deep_) return too_many_layers();
        auto make = [&] { return KernelSummation::create(*setup_.device, spec_, pitch_, unit_sources(c), progress); };
        KernelSummationMemo none;
        auto made = (setup_.memo ? setup_.memo : &none)->get(spec_, pitch_, make);
        if (!made.ok()) return Result<bool>::failure(made);
        conv_ = made.value;
        if (setup_.report) setup_.report->note_runs(conv_->on_gpu());
        place_sources();
        // the far tail, in every run's mean (added with each run: a job is the sum of its shares)
        const MonochromeScene& scene = *setup_.scene;
        tail_.assign(size_t(c.width) * c.height, 0.0f);
        conv_->add_far_tail(scene.power, scene.depth, scene.depth_meaning, 1.0, rows(), tail_.data());
        // and what the runs' mean lacks of the kernels' intensity blend (kernel_summation.h)
        conv_->add_blend_mean(sources_, power_, balance_, rows(), tail_.data());
        return Result<bool>::success(true);
    }

    Result<bool> execute(const RunBatch& batch, float* irradiance, const ProgressFn& progress) override {
        const SceneSumSettings& s = *setup_.settings;
        const KernelSummation& conv = *conv_;
        const bool incoherent = spec_.incoherent;
        const int W = conv.domain_width(), origin = conv.origin();
        const size_t n = size_t(W) * conv.domain_height();
        const int runs = incoherent ? 1 : batch.run_end - batch.run_begin;
        const PhaseCode code(s.runs);
        const PhaseDraw draw{s, code, wavelength_stream(setup_.wavelength)};
        const double per_run = 1.0 / runs;
        const int at_once = conv.runs_at_once();
        for (int k0 = 0; k0 < runs; k0 += at_once) {
            sources_.runs = std::min(at_once, runs - k0);
            sources_.weight.resize(size_t(sources_.runs) * n);
            // (the runs' phases, drawn per source, are a good part of a cheap run: over the threads)
            parallel_for(0, sources_.runs, thread_count(s.nthreads), [&](int64_t k) {
                const int run = batch.run_begin + k0 + int(k);
                std::complex<float>* weight = sources_.weight.data() + size_t(k) * n;
                if (s.coded_phases && !incoherent) {  // the cell's phasor times the class's K-th root of unity
                    for (size_t p = 0; p < n; ++p)
                        weight[p] = cell_weight_[p] * root_[size_t((long(run) * code_class_[p]) % s.runs)];
                    return;
                }
                for (size_t p = 0; p < n; ++p) {
                    const long ci = long(p % W) - origin, cj = long(p / W) - origin;
                    const double turns = incoherent ? 0.0 : source_turns(draw, ci, cj, key_[p], run);
                    weight[p] = std::polar(amplitude_[p], float(2 * M_PI * turns));
                }
            });
            const double at = k0 * per_run;
            if (auto r = conv.run(sources_, incoherent ? 1.0 : 1.0 / s.runs, rows(), tail_.data(), irradiance,
                                  progress_slice(progress, at, at + sources_.runs * per_run));
                !r.ok())
                return r;
        }
        return Result<bool>::success(true);
    }

private:
    RowRange rows() const { return {setup_.range.row_begin, setup_.range.row_end}; }  // the share's film rows

    // Every domain pixel's layer, amplitude (its power balanced, kernel_summation.h) and
    // random numbers' key.
    void place_sources() {
        const MonochromeScene& scene = *setup_.scene;
        const PinholeCamera& c = scene.camera;
        const KernelSummation& conv = *conv_;
        const int W = conv.domain_width(), H = conv.domain_height(), origin = conv.origin();
        const size_t n = size_t(W) * H;
        sources_.weight.resize(n);
        sources_.lower.resize(n);
        sources_.upper_share.resize(n);
        amplitude_.resize(n);
        power_.resize(n);
        key_.resize(n);  // independent: the pixel's random numbers
        const uint64_t pixels = uint64_t(c.width) * c.height;
        const EdgeContinuation edge(scene.power, 1, c.width, c.height);  // a lone bright edge pixel is not copied beyond
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i) {
                const size_t p = size_t(j) * W + i;
                const int ci = i - origin, cj = j - origin;
                const int qi = std::clamp(ci, 0, c.width - 1), qj = std::clamp(cj, 0, c.height - 1);
                const size_t q = size_t(qj) * c.width + qi;
                const double power = *edge.light(ci, cj) * c.solid_angle(ci, cj), d = scene.depth[q];
                const double w = d >= kInfiniteDepth ? 0.0 : 1.0 / c.planar_depth(qi, qj, d, scene.depth_meaning);
                int lower = 0;
                conv.layers().locate(w, lower, sources_.upper_share[p]);
                sources_.lower[p] = uint8_t(lower);
                amplitude_[p] = float(spec_.incoherent ? power : std::sqrt(power));
                power_[p] = float(power);
                key_[p] = ci == qi && cj == qj ? uint64_t(q) : pixels + p;
            }
        const SceneSumSettings& s = *setup_.settings;
        // coded phases: each pixel's cell phase and class, the same in every run (scene_runs.h)
        const PhaseCode code(s.runs);
        const PhaseDraw draw{s, code, wavelength_stream(setup_.wavelength)};
        std::vector<double> turns(s.coded_phases ? n : 0);
        code_class_.resize(turns.size());
        parallel_for(0, long(turns.size()), thread_count(s.nthreads), [&](int64_t p) {
            const long ci = long(p % W) - origin, cj = long(p / W) - origin;
            turns[size_t(p)] = cell_turns(draw, ci, cj);
            code_class_[size_t(p)] = code.code_class(ci, cj);
        });
        balance_ = conv.power_balance(sources_);
        for (size_t p = 0; p < n; ++p) amplitude_[p] *= balance_[p];
        cell_weight_.resize(turns.size());
        for (size_t p = 0; p < cell_weight_.size(); ++p)
            cell_weight_[p] = std::polar(amplitude_[p], float(2 * M_PI * turns[p]));
        root_.resize(size_t(s.runs));
        for (int m = 0; m < s.runs; ++m) root_[size_t(m)] = std::polar(1.0f, float(2 * M_PI * m / s.runs));
    }

    EvaluatorSetup setup_;
    bool too_deep_ = false;  // the scene's depths need more layers than the kernels take
    KernelSummationSpec spec_;
    double pitch_ = 0, kernels_ = 0;
    std::shared_ptr<const KernelSummation> conv_;
    KernelSummationSources sources_;
    std::vector<float> amplitude_, tail_;
    std::vector<float> power_, balance_;  // each domain pixel's power, and its weight's balance
    std::vector<uint64_t> key_;
    // coded phases (scene_runs.h, phase_codes.h): each pixel's class, its weight at its cell's
    // phase, and the K-th roots of unity its class turns by from run to run
    std::vector<int> code_class_;
    std::vector<std::complex<float>> cell_weight_, root_;
};

}  // namespace

std::unique_ptr<SummationEvaluator> make_kernel_runs(const EvaluatorSetup& setup) {
    return std::make_unique<KernelRuns>(setup);
}

}  // namespace wavecam::detail
