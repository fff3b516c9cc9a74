// Which evaluator each of the exact methods' sums takes, and what a frame's sums cost: the
// direct and nufft evaluators by their cost model (summation_plan.h, choose_sum), the psf
// summation by its kernels' and runs' work (coherent_convolution.h).
#include <algorithm>
#include <cmath>

#include "scene_sum.h"

namespace wavecam {
namespace detail {
namespace {

// Directions within tangents |u| <= e.u, |v| <= e.v as in-plane direction components (sines).
DirectionRange direction_range(const Extent& e, double rho0, double rho1) {
    const double sx = e.u / std::sqrt(1 + e.u * e.u), sy = e.v / std::sqrt(1 + e.v * e.v);
    return {-sx, sx, -sy, sy, rho0, rho1};
}


// The two sums' counts for the cost model (the film's for the whole frame), on a pinhole lattice of
// `pitch` (the frame's, or the psf kernels' own).
struct FrameCounts {
    SumCounts in, out;
};
FrameCounts frame_counts(const ExactSettings& s, const SceneSum& sum, double pitch, const PinholeCamera& c,
                         double wavelength, double nearest, bool single) {
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
    n.in = {samples - off, off, across, single ? 1.0 : double(sum.emitters.size()),
            direction_range(sum.source_extent, 0, rho), radius, wavelength, false, s.summation_tolerance};
    n.out = n.in;
    n.out.points = film;
    n.out.range = direction_range(sum.film_extent, 1 / f, 1 / f);
    n.out.film = true;
    return n;
}

}  // namespace

SumPlan plan_sums(const ExactSettings& s, const SceneSum& sum, const PinholeCamera& c, double wavelength,
                  double nearest, bool single) {
    const FrameCounts n = frame_counts(s, sum, sum.samples.pitch, c, wavelength, nearest, single);
    // One source at a time (the incoherent method): forcing the NUFFTs would pay a lattice of FFTs
    // per source; there the cheaper evaluator stands.
    const Summation asked = single && s.summation == Summation::Nufft ? Summation::Auto : s.summation;
    SumPlan plan;
    plan.settings = {asked, s.summation_tolerance, s.nthreads, s.device};
    plan.in.fixed_choice = plan.out.fixed_choice = true;
    plan.in.choice = choose_sum(n.in, asked, s.device.gpu());
    plan.out.choice = choose_sum(n.out, asked, s.device.gpu());
    plan.out.fixed_range = true;
    plan.out.range = n.out.range;
    plan.in_work = plan.in.choice.work;
    plan.out_work = plan.out.choice.work;
    return plan;
}

// The runs as convolutions with amplitude PSFs (coherent_convolution.h) for this wavelength.
detail::CoherentSpec coherent_spec(const ExactSettings& s, const PinholeCamera& c, double wavelength,
                                   double nearest, int subsamples) {
    detail::CoherentSpec spec;
    spec.camera = c;
    spec.overscan = std::clamp(s.overscan, 0, std::min(c.width, c.height) / 2);
    spec.aperture = s.aperture;
    spec.wavelength = wavelength;
    spec.max_inverse_depth = std::isinf(nearest) ? 0.0 : 1.0 / nearest;
    spec.subsamples = subsamples;
    spec.incoherent = s.method == CoherenceMethod::Incoherent;
    spec.settings = {Summation::Auto, s.summation_tolerance, s.nthreads, s.device};
    return spec;
}

// Whether the scene's depths, nearest at `nearest`, need more amplitude layers than the psf
// summation takes (coherent_convolution.h).
bool too_deep_for_psf(double nearest, const Aperture& aperture, double wavelength) {
    const double rho = std::isinf(nearest) ? 0.0 : 1.0 / nearest;
    return detail::amplitude_layers(rho, aperture.bounding_radius(), wavelength).count > detail::kMaxPsfLayers;
}

// The psf summation's work: its kernels' sums counted on their own lattice of `pitch`.
detail::CoherentWork psf_work(const ExactSettings& s, const SceneSum& sum, const detail::CoherentSpec& spec,
                              double nearest, double pitch) {
    const FrameCounts n = frame_counts(s, sum, pitch, spec.camera, spec.wavelength, nearest, false);
    return detail::coherent_work(spec, n.in, n.out);
}

}  // namespace detail

using detail::coherent_spec;
using detail::psf_work;
using detail::plan_sums;
using detail::scene_sum;
using detail::SceneSum;
using detail::SumPlan;
using detail::too_deep_for_psf;
using detail::work_range;
using detail::WorkRange;
using detail::film_subsamples;

Summation chosen_summation(const ExactSettings& asked, const PinholeCamera& c, double wavelength) {
    if (asked.summation != Summation::Auto) return asked.summation;
    const double nearest = std::isnan(asked.nearest_depth) ? INFINITY : asked.nearest_depth;
    const ApertureShape shape = asked.aperture.shape;
    const bool one_opening =
        shape == ApertureShape::Circle || shape == ApertureShape::Square || shape == ApertureShape::Polygon;
    if (asked.jitter || !one_opening || too_deep_for_psf(nearest, asked.aperture, wavelength)) return Summation::Auto;
    ExactSettings s = asked;  // the whole job: every row and run
    s.row_begin = s.run_begin = 0;
    s.row_end = s.run_end = -1;
    const SceneSum sum = scene_sum({c, nullptr, nullptr}, wavelength, s, nearest, work_range(s, c.height), false);
    const bool incoherent = s.method == CoherenceMethod::Incoherent;
    const double runs = incoherent ? 1.0 : double(s.runs);
    const detail::CoherentSpec spec = coherent_spec(s, c, wavelength, nearest, sum.subsamples);
    const detail::CoherentWork psf =
        psf_work(s, sum, spec, nearest, detail::kernel_lattice_pitch(spec, sum.samples.pitch));
    const SumPlan plan = plan_sums(s, sum, c, wavelength, nearest, incoherent);
    const double exact = (plan.in_work + plan.out_work) * (incoherent ? double(sum.emitters.size()) : runs);
    return psf.kernels + psf.per_run * runs < exact ? Summation::Psf : Summation::Auto;
}

EvaluatorSet scene_evaluators(const ExactSettings& s, const PinholeCamera& camera, double wavelength) {
    const double nearest = std::isnan(s.nearest_depth) ? INFINITY : s.nearest_depth;
    const SceneSum sum = scene_sum({camera, nullptr, nullptr}, wavelength, s, nearest, work_range(s, camera.height), false);
    const SumPlan plan = plan_sums(s, sum, camera, wavelength, nearest, s.method == CoherenceMethod::Incoherent);
    const bool in = plan.in.choice.evaluator == Evaluator::Nufft, out = plan.out.choice.evaluator == Evaluator::Nufft;
    return {!in, in, !out, out};
}

double scene_terms(const ExactSettings& s, const PinholeCamera& camera, double wavelength) {
    const WorkRange w = work_range(s, camera.height);
    const double nearest = std::isnan(s.nearest_depth) ? INFINITY : s.nearest_depth;
    const SceneSum sum = scene_sum({camera, nullptr, nullptr}, wavelength, s, nearest, w, false);
    const bool incoherent = s.method == CoherenceMethod::Incoherent;
    if (s.summation == Summation::Psf) {  // a share computes every kernel, and the whole frame each run
        const detail::CoherentSpec spec = coherent_spec(s, camera, wavelength, nearest, sum.subsamples);
        const detail::CoherentWork cw =
            psf_work(s, sum, spec, nearest, detail::kernel_lattice_pitch(spec, sum.samples.pitch));
        return cw.kernels + cw.per_run * (incoherent ? 1 : w.run_end - w.run_begin);
    }
    const SumPlan plan = plan_sums(s, sum, camera, wavelength, nearest, incoherent);
    // this share's rows: their part of the film's work
    const int o = std::clamp(s.overscan, 0, std::min(camera.width, camera.height) / 2);
    const double rows = double(w.row_end - w.row_begin) / std::max(1, camera.height - 2 * o);
    const double work = plan.in_work + plan.out_work * rows;
    return incoherent ? double(sum.emitters.size()) * work : work * (w.run_end - w.run_begin);
}

double scene_summation_bytes(const ExactSettings& s, const PinholeCamera& camera, double wavelength) {
    if (s.summation != Summation::Psf) return 0;
    const double nearest = std::isnan(s.nearest_depth) ? INFINITY : s.nearest_depth;
    return detail::coherent_bytes(coherent_spec(s, camera, wavelength, nearest, film_subsamples(s, camera, wavelength)));
}

}  // namespace wavecam
