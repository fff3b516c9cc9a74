#include "wavecam/scene_diffraction.h"

#include <algorithm>
#include <cmath>

#include "counter_random.h"
#include "phase_codes.h"
#include "scene_sum.h"

namespace wavecam {
using detail::check_settings;
using detail::coherent_spec;
using detail::Emitter;
using detail::plan_sums;
using detail::psf_work;
using detail::scene_sum;
using detail::SceneSum;
using detail::source_at;
using detail::SumPlan;
using detail::too_deep_for_psf;
using detail::wavelength_stream;
using detail::work_range;
using detail::WorkRange;

namespace {

// The film points' irradiance of one sum, n x n points per output pixel averaged into the output
// rows of `range` (within the overscan), then cleared for the next run.
void average_into_output(std::vector<float>& points, const SceneSum& sum, const PinholeCamera& c, int overscan,
                         const WorkRange& range, float* irradiance) {
    const size_t n2 = size_t(sum.subsamples) * sum.subsamples, width = size_t(c.width - 2 * overscan);
    for (size_t p = 0; p < points.size() / n2; ++p) {
        double total = 0;
        for (size_t k = 0; k < n2; ++k) total += points[p * n2 + k];
        irradiance[(range.row_begin + p / width) * c.width + overscan + p % width] += static_cast<float>(total / n2);
    }
    std::fill(points.begin(), points.end(), 0.0f);
}

PointSource centred(const PinholeCamera& c, const Emitter& e, double phase) {
    return source_at(c, e.x + 0.5 * e.w, e.y + 0.5 * e.h, e.power, e.depth, e.meaning, phase);
}

// A source's phase in one run, in turns. Coded (phase_codes.h): its cell's random phase and ramp
// at pixel (i, j) plus its class's offset for the run; independent: a fresh draw per run for
// `key`, the source's random numbers.
double source_turns(const ExactSettings& s, const detail::PhaseCode& code, long i, long j, uint64_t key, int run,
                    uint64_t stream) {
    if (!s.coded_phases) return detail::counter_uniform(s.seed ^ stream, uint64_t(run), key, 3);
    const detail::PhaseCode::CellPhase place = code.cell_phase(i, j);
    return detail::counter_uniform(s.seed ^ stream, 0, place.key, 4) + place.ramp_turns +
           code.offset_turns(run, code.code_class(i, j));
}

// One run's sources. Coded (phase_codes.h): each emitter's phase 2 pi (theta + k m / K), theta
// uniform per emitter and wavelength, m its class; with jitter, every emitter moved by one common
// random offset within its cell, the same in every run: the codes cancel the cross terms of
// different classes only if nothing moves between runs, and a common offset keeps a uniform wall
// uniform (an offset per emitter would leave lumps that no run averages away).
// Independent (the seed paper's own): a fresh uniform phase and place per emitter and run.
std::vector<PointSource> run_sources(const PinholeCamera& c, const std::vector<Emitter>& emitters,
                                     const ExactSettings& s, const detail::PhaseCode& code, int run,
                                     uint64_t stream) {
    std::vector<PointSource> sources;
    sources.reserve(emitters.size());
    const uint64_t draw = s.coded_phases ? 0 : uint64_t(run);  // the counter the random numbers use
    for (const Emitter& e : emitters) {
        const long i = long(std::floor(e.x)), j = long(std::floor(e.y));
        const double phase = 2 * M_PI * source_turns(s, code, i, j, e.key, run, stream);
        if (!s.jitter) {
            sources.push_back(centred(c, e, phase));
            continue;
        }
        const uint64_t place = s.coded_phases ? ~0ull : e.key;  // one offset for all, or one each
        const double jx = detail::counter_uniform(s.seed, draw, place, 1);
        const double jy = detail::counter_uniform(s.seed, draw, place, 2);
        sources.push_back(source_at(c, e.x + jx * e.w, e.y + jy * e.h, e.power, e.depth, e.meaning, phase));
    }
    return sources;
}

// Incoherent: every source through the pinhole alone, the film's irradiances summed.
Result<bool> incoherent_sum(const SceneSum& sum, const PinholeCamera& c, double wavelength, const SumPlan& plan,
                            std::vector<float>& points, const ProgressFn& progress) {
    SummationPlan to_film = SummationPlan::create(SumKind::PinholeToFilm, sum.samples, wavelength, plan.settings, plan.out);
    if (auto r = to_film.set_points(sum.film); !r.ok()) return r;
    PinholeField field;
    const size_t n = sum.emitters.size();
    for (size_t k = 0; k < n; ++k) {
        const std::vector<PointSource> one{centred(c, sum.emitters[k], 0.0)};
        SummationPlan to_pinhole =
            SummationPlan::create(SumKind::SourcesToPinhole, sum.samples, wavelength, plan.settings, plan.in);
        if (auto r = to_pinhole.set_points(one); !r.ok()) return r;
        if (auto r = to_pinhole.execute(source_weights(one), field); !r.ok()) return r;
        if (auto r = to_film.execute_irradiance(field, 1.0, points.data(),
                                                progress_part(progress, double(k) / n, double(k + 1) / n));
            !r.ok())
            return r;
    }
    return Result<bool>::success(true);
}

// One wavelength's work: the scene's sums `sum` at `wavelength` under `settings`, for the runs
// and output rows of `range`.
struct WavelengthWork {
    const SceneSum& sum;
    double wavelength;
    const ExactSettings& settings;
    const WorkRange& range;
};

// Random phase (the seed paper): each run every source at once with its own phase, weighted
// 1/runs and averaged into the output on its own, so a job equals the sum of its shares. The
// sources stay where they are from run to run (but for independent phases with jitter): one plan
// serves every run, each run only new weights.
Result<bool> random_phase_runs(const WavelengthWork& job, const PinholeCamera& c, const SumPlan& plan,
                               std::vector<float>& points, float* irradiance, const ProgressFn& progress) {
    const SceneSum& sum = job.sum;
    const double wavelength = job.wavelength;
    const ExactSettings& s = job.settings;
    const WorkRange& range = job.range;
    const uint64_t stream = wavelength_stream(wavelength);
    PinholeField field;
    const detail::PhaseCode code(s.runs);
    const bool moving = s.jitter && !s.coded_phases;
    SummationPlan to_pinhole, to_film = SummationPlan::create(SumKind::PinholeToFilm, sum.samples, wavelength,
                                                              plan.settings, plan.out);
    if (auto r = to_film.set_points(sum.film); !r.ok()) return r;
    const int first = range.run_begin, runs = range.run_end - range.run_begin;
    for (int run = first; run < range.run_end; ++run) {
        const std::vector<PointSource> sources = run_sources(c, sum.emitters, s, code, run, stream);
        if (!to_pinhole || moving) {
            to_pinhole = SummationPlan::create(SumKind::SourcesToPinhole, sum.samples, wavelength, plan.settings, plan.in);
            if (auto r = to_pinhole.set_points(sources); !r.ok()) return r;
        }
        // half of a run's terms go to the pinhole, half to the film
        const double at = double(run - first) / runs, half = 0.5 / runs;
        if (auto r = to_pinhole.execute(source_weights(sources), field, progress_part(progress, at, at + half)); !r.ok())
            return r;
        if (auto r = to_film.execute_irradiance(field, 1.0 / s.runs, points.data(),
                                                progress_part(progress, at + half, at + 2 * half));
            !r.ok())
            return r;
        average_into_output(points, sum, c, s.overscan, range, irradiance);
    }
    return Result<bool>::success(true);
}

// The runs as convolutions with amplitude PSFs (coherent_convolution.h). The sources are every
// pixel of the convolution's domain at its centre: the input's, and beyond it the edge continued
// pixel by pixel (each with the edge pixel's radiance and planar depth at its own field
// position), each with the phases the direct sums give it (run_sources): an input pixel keeps its
// key, so a scene whose edge is dark gets the direct sums' runs, kernel blends apart. The
// convolution comes from the job's memo where one is given (the kernels of a wavelength's other
// part), and the runs go through it several at once.
Result<bool> psf_runs(const MonochromeScene& scene, const WavelengthWork& job, double nearest, float* irradiance,
                      const ProgressFn& progress, detail::CoherentMemo* memo) {
    const SceneSum& sum = job.sum;
    const double wavelength = job.wavelength;
    const ExactSettings& s = job.settings;
    const WorkRange& range = job.range;
    const PinholeCamera& c = scene.camera;
    const detail::CoherentSpec spec = coherent_spec(s, c, wavelength, nearest, sum.subsamples);
    const bool incoherent = spec.incoherent;
    const int runs = incoherent ? 1 : range.run_end - range.run_begin;
    // progress: the kernels and the runs by their work
    const double pitch = detail::kernel_lattice_pitch(spec, sum.samples.pitch);
    const detail::CoherentWork work = psf_work(s, sum, spec, nearest, pitch);
    const double kernels = work.kernels / (work.kernels + runs * work.per_run);
    auto unit = [&c](double x, double y, double w) {
        return source_at(c, x, y, 1.0, w > 0 ? 1.0 / w : INFINITY, DepthMeaning::Planar, 0.0);
    };
    auto make = [&] {
        return detail::CoherentConvolution::create(spec, pitch, unit, progress_part(progress, 0.0, kernels));
    };
    detail::CoherentMemo none;
    auto made = (memo ? memo : &none)->get(spec, pitch, make);
    if (!made.ok()) return Result<bool>::failure(made);
    const detail::CoherentConvolution& conv = *made.value;
    const int W = conv.domain_width(), H = conv.domain_height(), origin = conv.origin();
    const size_t n = size_t(W) * H;
    detail::CoherentSources sources;
    sources.weight.resize(n);
    sources.lower.resize(n);
    sources.upper_share.resize(n);
    std::vector<float> amplitude(n);
    std::vector<uint64_t> key(n);  // independent: the pixel's random numbers
    const detail::PhaseCode code(s.runs);
    const uint64_t stream = wavelength_stream(wavelength), pixels = uint64_t(c.width) * c.height;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const size_t p = size_t(j) * W + i;
            const int ci = i - origin, cj = j - origin;
            const int qi = std::clamp(ci, 0, c.width - 1), qj = std::clamp(cj, 0, c.height - 1);
            const size_t q = size_t(qj) * c.width + qi;
            const double power = scene.power[q] * c.solid_angle(ci, cj), d = scene.depth[q];
            const double w = d >= kInfiniteDepth ? 0.0 : 1.0 / c.planar_depth(qi, qj, d, scene.depth_meaning);
            int lower = 0;
            conv.layers().locate(w, lower, sources.upper_share[p]);
            sources.lower[p] = uint8_t(lower);
            amplitude[p] = float(incoherent ? power : std::sqrt(power));
            key[p] = ci == qi && cj == qj ? uint64_t(q) : pixels + p;
        }
    const std::vector<float> balance = conv.power_balance(sources);
    for (size_t p = 0; p < n; ++p) amplitude[p] *= balance[p];
    // the far tail, in every run's mean (added with each run: a job is the sum of its shares)
    std::vector<float> tail(size_t(c.width) * c.height, 0.0f);
    conv.add_far_tail(scene.power, scene.depth, scene.depth_meaning, 1.0, range.row_begin, range.row_end, tail.data());
    const double per_run = (1 - kernels) / runs;
    const int at_once = conv.runs_at_once();
    for (int k0 = 0; k0 < runs; k0 += at_once) {
        sources.runs = std::min(at_once, runs - k0);
        sources.weight.resize(size_t(sources.runs) * n);
        for (int k = 0; k < sources.runs; ++k) {
            const int run = range.run_begin + k0 + k;
            for (size_t p = 0; p < n; ++p) {
                const long ci = long(p % W) - origin, cj = long(p / W) - origin;
                const double turns = incoherent ? 0.0 : source_turns(s, code, ci, cj, key[p], run, stream);
                sources.weight[size_t(k) * n + p] = std::polar(amplitude[p], float(2 * M_PI * turns));
            }
        }
        const double at = kernels + k0 * per_run;
        if (auto r = conv.run(sources, incoherent ? 1.0 : 1.0 / s.runs, range.row_begin, range.row_end, tail.data(),
                              irradiance, progress_part(progress, at, at + sources.runs * per_run));
            !r.ok())
            return r;
    }
    return Result<bool>::success(true);
}

}  // namespace

Result<bool> diffract_monochrome(const MonochromeScene& scene, double wavelength, const ExactSettings& s,
                                 float* irradiance, const ProgressFn& progress) {
    return detail::diffract_monochrome(scene, wavelength, s, irradiance, progress, nullptr);
}

Result<bool> detail::diffract_monochrome(const MonochromeScene& scene, double wavelength, const ExactSettings& s,
                                         float* irradiance, const ProgressFn& progress, CoherentMemo* memo) {
    const PinholeCamera& c = scene.camera;
    if (auto v = check_settings(c, wavelength, s); !v.ok()) return v;
    if (!scene.checked)
        if (auto v = check_pixels(c, scene.power, 1, true, scene.depth); !v.ok()) return v;
    const WorkRange range = work_range(s, c.height);
    const double nearest =
        std::isnan(s.nearest_depth) ? nearest_depth(c, scene.depth, scene.depth_meaning) : s.nearest_depth;
    if (s.summation == Summation::Psf && too_deep_for_psf(nearest, s.aperture, wavelength))
        return detail::too_many_layers();  // refused before the lattice is sampled
    // (the psf summation samples the pinhole for its kernels alone)
    const SceneSum sum = scene_sum(scene, wavelength, s, nearest, range, s.summation != Summation::Psf);
    const WavelengthWork job{sum, wavelength, s, range};
    if (s.summation == Summation::Psf) return psf_runs(scene, job, nearest, irradiance, progress, memo);
    std::vector<float> points(sum.film.size(), 0.0f);  // irradiance at every film point
    const bool incoherent = s.method == CoherenceMethod::Incoherent;
    const SumPlan plan = plan_sums(s, sum, c, wavelength, nearest, incoherent);
    if (!incoherent) return random_phase_runs(job, c, plan, points, irradiance, progress);
    auto r = incoherent_sum(sum, c, wavelength, plan, points, progress);
    if (r.ok()) average_into_output(points, sum, c, s.overscan, range, irradiance);
    return r;
}

}  // namespace wavecam
