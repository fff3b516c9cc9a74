// A frame's sums counted for the chooser (summation/choose.h, which decides and prices them):
// the point sums' sources, pinhole samples and film points, and the kernel summation's kernels on
// their own lattice; and the estimates the jobs read from its choice.
#include <algorithm>
#include <cmath>

#include "summation/kernel/kernel_error_check.h"
#include "summation/kernel/source_kernels.h"
#include "summation/scene_sum.h"
#include "summation/choose.h"

namespace wavecam {
namespace detail {
namespace {

// Directions within tangents |u| <= e.u, |v| <= e.v as in-plane direction components (sines).
DirectionRange direction_range(const Extent& e, double rho0, double rho1) {
    const double sx = e.u / std::sqrt(1 + e.u * e.u), sy = e.v / std::sqrt(1 + e.v * e.v);
    return {-sx, sx, -sy, sy, rho0, rho1};
}


// A wavelength's frame: its camera, the wavelength and the nearest source's depth.
struct WavelengthFrame {
    const PinholeCamera& camera;
    double wavelength, nearest;
};

// The two sums' counts for the cost model (the film's for the whole frame), on a pinhole lattice of
// `pitch` (the frame's, or the kernel summation's kernels' own), for one source at a time where `single`.
struct FrameCounts {
    SumCounts in, out;
};
FrameCounts frame_counts(const SceneSumSettings& s, const SceneSum& sum, const WavelengthFrame& frame, double pitch,
                         bool single) {
    const PinholeCamera& c = frame.camera;
    const double wavelength = frame.wavelength, nearest = frame.nearest;
    const double radius = s.aperture.bounding_radius(), f = c.film_distance;
    const double samples = estimate_sample_count(s.aperture, pitch);
    // Samples off the lattice: the rim's cells (about 1.3 per pitch of perimeter, twice for a
    // zone plate's every zone edge); every sample of a grey mask or a sieve's holes.
    const bool irregular = s.aperture.shape == ApertureShape::Mask || s.aperture.shape == ApertureShape::PhotonSieve;
    const double rims = s.aperture.shape == ApertureShape::ZonePlate ? 2.0 * s.aperture.zones : 1.0;
    const double off = irregular ? samples : std::min(samples, rims * 1.3 * 2 * M_PI * radius / pitch);
    const int across = int(std::ceil(2 * radius / pitch)) + 1;
    const int o = std::clamp(s.overscan, 0, std::min(c.width, c.height) / 2);
    const double film = double(c.width - 2 * o) * (c.height - 2 * o) * sum.subsamples * sum.subsamples;
    const double rho = std::isinf(nearest) ? 0.0 : 1.0 / nearest;
    FrameCounts n;
    n.in = {samples - off, off, across, single ? 1.0 : double(sum.emitter_count),
            direction_range(sum.source_extent, 0, rho), radius, wavelength, false, s.summation_tolerance};
    n.out = n.in;
    n.out.points = film;
    n.out.range = direction_range(sum.film_extent, 1 / f, 1 / f);
    n.out.film = true;
    return n;
}

}  // namespace

SumChoices decide_sums(const SceneSumSettings& s, const ComputeDevice& device, const SceneSum& sum,
                       const PinholeCamera& c, double wavelength, double nearest, bool single) {
    const FrameCounts n = frame_counts(s, sum, {c, wavelength, nearest}, sum.samples.pitch, single);
    SumChoices sums;
    sums.settings = {point_sum_asked(s.summation, single), s.summation_tolerance, s.nthreads};
    sums.in.fixed_choice = sums.out.fixed_choice = true;
    const SumChoice* in = s.decision ? s.decision->to_pinhole_at(wavelength) : nullptr;
    const SumChoice* out = s.decision ? s.decision->to_film_at(wavelength) : nullptr;
    if (in && out) {  // the job's decision
        sums.in.choice = *in;
        sums.out.choice = *out;
    } else {  // a frame diffracted alone decides for itself
        FrameSums frame;
        frame.in = n.in;
        frame.out = n.out;
        frame.single = single;
        const SummationChoice chosen = choose_summation(frame, device, {s.summation, false, 0});
        sums.in.choice = chosen.in;
        sums.out.choice = chosen.out;
    }
    sums.out.fixed_range = true;
    sums.out.range = n.out.range;
    sums.in_work = sums.in.choice.work;
    sums.out_work = sums.out.choice.work;
    return sums;
}

// The runs as convolutions with amplitude PSFs (kernel_summation.h) for this wavelength.
detail::KernelSummationSpec kernel_summation_spec(const SceneSumSettings& s, const PinholeCamera& c, double wavelength,
                                            double nearest, int subsamples) {
    detail::KernelSummationSpec spec;
    spec.camera = c;
    spec.overscan = std::clamp(s.overscan, 0, std::min(c.width, c.height) / 2);
    spec.aperture = s.aperture;
    spec.wavelength = wavelength;
    spec.max_inverse_depth = std::isinf(nearest) ? 0.0 : 1.0 / nearest;
    spec.subsamples = subsamples;
    spec.incoherent = s.method == CoherenceMethod::Incoherent;
    spec.runs = s.runs;
    spec.settings = {Summation::Auto, s.summation_tolerance, s.nthreads};
    return spec;
}

// Whether the scene's depths, nearest at `nearest`, need more amplitude layers than the kernel
// summation takes (kernel_summation.h).
bool too_deep_for_kernel(double nearest, const Aperture& aperture, double wavelength) {
    const double rho = std::isinf(nearest) ? 0.0 : 1.0 / nearest;
    return detail::amplitude_layers(rho, aperture.bounding_radius(), wavelength).count > detail::kMaxKernelLayers;
}

// The kernel summation's work: its kernels' sums counted on their own lattice of `pitch`.
detail::KernelSummationWork kernel_work(const SceneSumSettings& s, const SceneSum& sum,
                                        const detail::KernelSummationSpec& spec, double nearest, double pitch,
                                        const ComputeDevice& device) {
    const FrameCounts n = frame_counts(s, sum, {spec.camera, spec.wavelength, nearest}, pitch, false);
    return detail::kernel_summation_work(spec, n.in, n.out, device);
}

// The kernel summation's plan-time check (kernel_error_check.h) for the settings' frame at `wavelength`.
Result<KernelErrorCheck> kernel_error_check(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& c,
                                            double wavelength) {
    const double nearest = std::isnan(s.nearest_depth) ? INFINITY : s.nearest_depth;
    const SceneSum sum = scene_sum({c, nullptr, nullptr}, wavelength, s, nearest, work_range(s, c.height), false);
    const KernelSummationSpec spec = kernel_summation_spec(s, c, wavelength, nearest, sum.subsamples);
    return check_kernel_error(device, spec, kernel_lattice_pitch(spec, sum.samples.pitch), unit_sources(c));
}

namespace {

// Where the kernel summation applies: sources at their pixels' centres (no jitter), an opening of one
// piece (masks, zone plates and sieves have structure finer than the kernels' lattice), the
// scene's depths within its layers.
bool kernel_applies(const SceneSumSettings& s, double nearest, double wavelength) {
    const ApertureShape shape = s.aperture.shape;
    const bool one_opening =
        shape == ApertureShape::Circle || shape == ApertureShape::Square || shape == ApertureShape::Polygon;
    return !s.jitter && one_opening && !too_deep_for_kernel(nearest, s.aperture, wavelength);
}

// The chooser's view of the settings' share of a frame at `wavelength`, every pixel lit, for
// s.nearest_depth (NaN counts as all sky): the point sums (but where the kernel summation is asked), the kernel summation where
// asked, or weighed by `auto` where it applies.
SummationChoice scene_choice(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& c,
                             double wavelength, const ChoiceSettings& asked) {
    const WorkRange w = work_range(s, c.height);
    const double nearest = std::isnan(s.nearest_depth) ? INFINITY : s.nearest_depth;
    const SceneSum sum = scene_sum({c, nullptr, nullptr}, wavelength, s, nearest, w, false);
    const bool incoherent = s.method == CoherenceMethod::Incoherent;
    const double runs = w.run_end - w.run_begin;
    FrameSums frame;
    if (s.summation != Summation::Kernel) {
        const FrameCounts n = frame_counts(s, sum, {c, wavelength, nearest}, sum.samples.pitch, incoherent);
        frame.in = n.in;
        frame.out = n.out;
    }
    frame.single = incoherent;
    frame.repeats = incoherent ? double(sum.emitter_count) : runs;
    // this share's rows: their part of the film's work
    const int o = std::clamp(s.overscan, 0, std::min(c.width, c.height) / 2);
    frame.film_share = double(w.row_end - w.row_begin) / std::max(1, c.height - 2 * o);
    frame.kernel_applies = kernel_applies(s, nearest, wavelength);
    frame.kernel_counted = s.summation == Summation::Kernel || (asked.weigh_kernel && frame.kernel_applies);
    if (frame.kernel_counted) {
        frame.kernel = kernel_summation_spec(s, c, wavelength, nearest, sum.subsamples);
        const double pitch = kernel_lattice_pitch(frame.kernel, sum.samples.pitch);
        const FrameCounts n = frame_counts(s, sum, {c, wavelength, nearest}, pitch, false);
        frame.kernel_in = n.in;
        frame.kernel_out = n.out;
        frame.kernel_runs = incoherent ? 1.0 : runs;
    }
    ChoiceSettings priced = asked;  // the job's decision priced, where it holds this wavelength
    if (s.decision && s.summation != Summation::Kernel) {
        priced.decided_in = s.decision->to_pinhole_at(wavelength);
        priced.decided_out = s.decision->to_film_at(wavelength);
        if (!priced.decided_in || !priced.decided_out) priced.decided_in = priced.decided_out = nullptr;
    }
    return choose_summation(frame, device, priced);
}

}  // namespace
}  // namespace detail

using detail::ChoiceSettings;
using detail::kernel_summation_spec;
using detail::film_subsamples;
using detail::scene_choice;
using detail::SummationChoice;

namespace {

const SummationDecision::AtWavelength* choices_at(const SummationDecision& d, double wavelength) {
    for (const SummationDecision::AtWavelength& c : d.choices)
        if (c.wavelength == wavelength) return &c;
    return nullptr;
}

}  // namespace

const SumChoice* SummationDecision::to_pinhole_at(double wavelength) const {
    const AtWavelength* c = choices_at(*this, wavelength);
    return c ? &c->to_pinhole : nullptr;
}
const SumChoice* SummationDecision::to_film_at(double wavelength) const {
    const AtWavelength* c = choices_at(*this, wavelength);
    return c ? &c->to_film : nullptr;
}

SummationDecision decide_summation(const SceneSumSettings& asked, const ComputeDevice& device, const PinholeCamera& camera,
                                   const std::vector<double>& wavelengths) {
    SummationDecision d;
    d.gpu = device.gpu();
    if (wavelengths.empty()) return d;
    d.summation = chosen_summation(asked, device, camera, wavelengths[wavelengths.size() / 2]);
    if (d.summation == Summation::Kernel) return d;
    SceneSumSettings s = asked;  // the whole job, as chosen_summation weighs it: every share decides alike
    s.summation = d.summation;
    s.decision = nullptr;
    s.row_begin = s.run_begin = 0;
    s.row_end = s.run_end = -1;
    for (const double wavelength : wavelengths) {
        if (d.to_pinhole_at(wavelength)) continue;  // (monochrome light: three samples of one wavelength)
        const SummationChoice c = scene_choice(s, device, camera, wavelength, {s.summation, false, 0});
        d.choices.push_back({wavelength, c.in, c.out});
    }
    return d;
}

Summation chosen_summation(const SceneSumSettings& asked, const ComputeDevice& device, const PinholeCamera& c,
                           double wavelength) {
    if (asked.summation != Summation::Auto) return asked.summation;
    const double nearest = std::isnan(asked.nearest_depth) ? INFINITY : asked.nearest_depth;
    if (!detail::kernel_applies(asked, nearest, wavelength)) return Summation::Auto;
    SceneSumSettings s = asked;  // the whole job: every row and run
    s.row_begin = s.run_begin = 0;
    s.row_end = s.run_end = -1;
    const SummationChoice chosen = scene_choice(s, device, c, wavelength, {Summation::Auto, true, 0});
    if (chosen.summation != Summation::Kernel) return Summation::Auto;
    // cheaper: the kernel summation where its plan-time check finds it within its stated error (kernel_error_check.h)
    const auto check = detail::kernel_error_check(s, device, c, wavelength);
    return check.ok() && check.value.within() ? Summation::Kernel : Summation::Auto;
}

SummationEstimate estimate_summation(const SceneSumSettings& s, const ComputeDevice& device,
                                     const PinholeCamera& camera, double wavelength, double term_rate) {
    const SummationChoice c = scene_choice(s, device, camera, wavelength, {s.summation, true, term_rate});
    SummationEstimate e;
    e.summation = c.summation;
    if (c.summation != Summation::Kernel) {
        e.sums.add(false, c.in.evaluator);
        e.sums.add(true, c.out.evaluator);
    }
    e.gpu = c.gpu;
    e.terms = c.work;
    e.seconds = c.seconds;
    e.bytes = c.bytes;
    e.reason = c.reason;
    return e;
}

EvaluatorSet scene_evaluators(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& camera,
                              double wavelength) {
    const SummationChoice c = scene_choice(s, device, camera, wavelength, {s.summation, false, 0});
    EvaluatorSet e;
    e.add(false, c.in.evaluator);
    e.add(true, c.out.evaluator);
    return e;
}

double scene_terms(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& camera,
                   double wavelength) {
    return scene_choice(s, device, camera, wavelength, {s.summation, false, 0}).work;
}

double scene_summation_bytes(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& camera,
                             double wavelength) {
    if (s.summation != Summation::Kernel) return 0;
    const double nearest = std::isnan(s.nearest_depth) ? INFINITY : s.nearest_depth;
    const int subsamples = film_subsamples(s, camera, wavelength);
    return detail::kernel_summation_bytes(kernel_summation_spec(s, camera, wavelength, nearest, subsamples), device);
}

}  // namespace wavecam
