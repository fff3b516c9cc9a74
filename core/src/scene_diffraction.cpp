#include "wavecam/scene_diffraction.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "coherent_convolution.h"
#include "counter_random.h"
#include "frame_margin.h"
#include "phase_codes.h"
#include "wavecam/summation_plan.h"

namespace wavecam {
namespace {

// The settings one wavelength's sum needs (the pixels are check_pixels').
Result<bool> check_settings(const PinholeCamera& c, double wavelength, const ExactSettings& s) {
    auto fail = [](const std::string& m) { return Result<bool>::failure(m); };
    if (!(s.aperture.diameter > 0)) return fail("pinhole: expected a diameter > 0");
    if (!(c.film_distance > 0)) return fail("film-distance: expected a distance > 0");
    if (!(c.fov_h > 0 && c.fov_h < M_PI * 0.999)) return fail("fov: expected a field of view in (0deg, 180deg)");
    if (!(wavelength > 0)) return fail("wavelengths: expected wavelengths > 0");
    if (s.runs < 1) return fail("runs: expected at least 1 run");
    if (s.summation == Summation::Psf && s.jitter)
        return fail("jitter: the psf summation places every source at its pixel's centre; expected no jitter, or "
                    "summation auto, direct or nufft");
    return check_frame(c, s.overscan);
}

// A point source at image position (x, y) (camera pixels) with power `power_on_pinhole` =
// radiance x solid angle: the irradiance it puts on the pinhole whatever its depth
// (docs/physics.md), so a finite source gets amplitude sqrt(L Omega) |P|.
PointSource source_at(const PinholeCamera& c, double x, double y, double power_on_pinhole, double depth,
                      DepthMeaning meaning, double phase) {
    double u, v;
    c.tangent(x, y, u, v);
    const double norm = std::sqrt(1.0 + u * u + v * v);
    const double root_power = std::sqrt(power_on_pinhole);
    PointSource s;
    s.phase = phase;
    if (depth >= kInfiniteDepth) {
        s.at_infinity = true;
        s.x = u / norm;
        s.y = v / norm;
        s.z = 1.0 / norm;
        s.amplitude = root_power;
        return s;
    }
    // planar depth: P = Z (u, v, 1); ray depth: P = D (u, v, 1) / |(u, v, 1)|
    const double scale = meaning == DepthMeaning::Planar ? depth : depth / norm;
    s.x = scale * u;
    s.y = scale * v;
    s.z = scale;
    s.amplitude = root_power * scale * norm;
    return s;
}

// What emits light: a lit pixel of the input, or a lit cell of the margin beyond it (its edge
// pixel's radiance over the cell's solid angle, at the edge pixel's planar depth). A source is
// placed within [x, x + w) x [y, y + h): at the centre, or anywhere (jitter) in a run.
struct Emitter {
    double x, y, w, h;
    double power;  // radiance x solid angle
    double depth;
    DepthMeaning meaning;
    uint64_t key;  // its random numbers' index
};

std::vector<Emitter> scene_emitters(const MonochromeScene& scene, const std::vector<detail::MarginCell>& cells) {
    const PinholeCamera& c = scene.camera;
    std::vector<Emitter> e;
    const uint64_t pixels = uint64_t(c.width) * c.height;
    for (int j = 0; j < c.height; ++j)
        for (int i = 0; i < c.width; ++i) {
            const uint64_t p = uint64_t(j) * c.width + i;
            if (scene.power[p] <= 0) continue;
            e.push_back({double(i), double(j), 1.0, 1.0, scene.power[p] * c.solid_angle(i, j), scene.depth[p],
                         scene.depth_meaning, p});
        }
    for (size_t k = 0; k < cells.size(); ++k) {
        const detail::MarginCell& m = cells[k];
        const size_t q = size_t(m.edge_y) * c.width + m.edge_x;
        if (scene.power[q] <= 0) continue;
        const double d = scene.depth[q];
        e.push_back({double(m.x0), double(m.y0), double(m.x1 - m.x0), double(m.y1 - m.y0),
                     scene.power[q] * detail::block_solid_angle(c, m.x0, m.x1, m.y0, m.y1),
                     d >= kInfiniteDepth ? d : c.planar_depth(m.edge_x, m.edge_y, d, scene.depth_meaning),
                     DepthMeaning::Planar, pixels + k});
    }
    return e;
}

// The widest tangents |u|, |v| of a set of directions: a lattice axis at a time (below).
struct Extent {
    double u = 0, v = 0;
    void add(const PinholeCamera& c, double x0, double y0, double x1, double y1) {
        for (double x : {x0, x1})
            for (double y : {y0, y1}) {
                double tu, tv;
                c.tangent(x, y, tu, tv);
                u = std::max(u, std::abs(tu));
                v = std::max(v, std::abs(tv));
            }
    }
};

// The pinhole lattice for sources within `source` and film points within `film`: the frame's
// own (scene_sample_pitch), refined where sources beyond it need it. A square lattice of pitch h
// also sends light to directions shifted by lambda / h along each axis; they miss the film while
// lambda / h >= sin(widest source) + sin(widest film point) on that axis (frame_margin.h).
double lattice_pitch(const ExactSettings& s, const PinholeCamera& c, double wavelength, double nearest,
                     const Extent& source, const Extent& film) {
    const double frame = scene_sample_pitch(s, c, wavelength, nearest);
    if (s.sin_theta_max > 0) return frame;
    const double widen = 0.5 * s.aperture.diameter / std::min(c.film_distance, nearest);
    auto sine = [&](double t) {
        return std::min(1.0, (t + widen) / std::sqrt(1.0 + (t + widen) * (t + widen)) + wavelength / s.aperture.diameter);
    };
    const double need = std::max(sine(source.u) + sine(film.u), sine(source.v) + sine(film.v));
    return std::min(frame, wavelength / need);
}

// n x n film points per output pixel of rows [row_begin, row_end) and columns [col_begin,
// col_end), at the centres of an n x n split of the pixel, stored pixel by pixel so that point
// p * n^2 + k belongs to the p-th pixel of that window.
FilmPoints camera_film(const PinholeCamera& c, int n, int row_begin, int row_end, int col_begin, int col_end) {
    FilmPoints film;
    film.film_distance = c.film_distance;
    for (int j = row_begin; j < row_end; ++j)
        for (int i = col_begin; i < col_end; ++i)
            for (int b = 0; b < n; ++b)
                for (int a = 0; a < n; ++a) {
                    double u, v;
                    c.tangent(i + (a + 0.5) / n, j + (b + 0.5) / n, u, v);
                    film.x.push_back(static_cast<float>(-c.film_distance * u));
                    film.y.push_back(static_cast<float>(-c.film_distance * v));
                }
    return film;
}

// The share of the work the settings ask for: film rows (within the overscan) and runs,
// clamped to the job.
struct WorkRange {
    int row_begin, row_end, run_begin, run_end;
};
WorkRange work_range(const ExactSettings& s, int height) {
    const int o = std::clamp(s.overscan, 0, height / 2);
    WorkRange w;
    w.row_begin = std::clamp(s.row_begin, o, height - o);
    w.row_end = s.row_end < 0 ? height - o : std::clamp(s.row_end, w.row_begin, height - o);
    w.run_begin = std::clamp(s.run_begin, 0, s.runs);
    w.run_end = s.run_end < 0 ? s.runs : std::clamp(s.run_end, w.run_begin, s.runs);
    return w;
}

uint64_t wavelength_stream(double wavelength) {
    uint64_t bits;
    std::memcpy(&bits, &wavelength, sizeof bits);
    return bits;
}

}  // namespace

Result<bool> check_frame(const PinholeCamera& c, int overscan) {
    if (c.width < 1 || c.height < 1) return Result<bool>::failure("image: expected at least 1x1 pixels");
    if (overscan >= 0 && 2 * overscan < std::min(c.width, c.height)) return Result<bool>::success(true);
    std::ostringstream m;
    m << "overscan: expected 0 to " << (std::min(c.width, c.height) - 1) / 2 << " pixels for a " << c.width << "x"
      << c.height << " image, got " << overscan;
    return Result<bool>::failure(m.str());
}

Result<bool> check_pixels(const PinholeCamera& c, const float* radiance, int channels, bool non_negative,
                          const float* depth) {
    if (!radiance || !depth) return Result<bool>::failure("image: radiance and depth are required");
    auto bad = [&c](const char* field, size_t p, float value, const char* expected) {
        std::ostringstream m;
        m << field << ": pixel (" << p % c.width << ", " << p / c.width << ") is " << value << ", expected "
          << expected;
        return Result<bool>::failure(m.str());
    };
    const size_t n = size_t(c.width) * c.height;
    for (size_t p = 0; p < n; ++p) {
        for (int k = 0; k < channels; ++k) {
            const float v = radiance[channels * p + k];
            if (!radiance_in_range(v) || (non_negative && v < 0))
                return bad("radiance", p, v,
                           non_negative ? "a finite value from 0 to 1e30" : "a finite value within +-1e30");
        }
        if (!depth_in_range(depth[p]))
            return bad("depth", p, depth[p], "a distance > 0 (inf or >= 1e9 for sky)");
    }
    return Result<bool>::success(true);
}

namespace {

// Film points per pixel side: as asked, or auto_film_subsamples.
int film_subsamples(const ExactSettings& s, const PinholeCamera& camera, double wavelength) {
    return s.film_subsamples > 0 ? s.film_subsamples : auto_film_subsamples(s.aperture, camera, wavelength);
}

// The frame's sources (the input's pixels and its margin's cells), the pinhole lattice and the
// film points of one wavelength's sum.
struct SceneSum {
    std::vector<Emitter> emitters;
    ApertureSamples samples;
    FilmPoints film;
    int subsamples = 1;
    Extent source_extent, film_extent;  // tangents of the widest source and film point
};

// With `scene.power` null every pixel and margin cell counts as lit (estimates).
SceneSum scene_sum(const MonochromeScene& scene, double wavelength, const ExactSettings& s, double nearest,
                   const WorkRange& range, bool with_samples) {
    const PinholeCamera& c = scene.camera;
    const int o = std::clamp(s.overscan, 0, std::min(c.width, c.height) / 2);
    SceneSum sum;
    Extent film, frame;
    film.add(c, o, o, c.width - o, c.height - o);
    frame.add(c, 0, 0, c.width, c.height);
    // The margin's reach: as far as the frame's own lattice carries, within the radii (frame_margin.h).
    const detail::MarginRadii radii = detail::margin_radii(s.aperture, c, o, nearest, wavelength);
    const double frame_pitch = lattice_pitch(s, c, wavelength, nearest, frame, film);
    const int least = std::min(radii.reach, detail::kMinReachRadii * radii.kernel);
    int reach = radii.reach;
    for (;;) {
        Extent margin = frame;
        margin.add(c, o - reach, o - reach, c.width - o + reach, c.height - o + reach);
        if (reach <= least || lattice_pitch(s, c, wavelength, nearest, margin, film) >= frame_pitch) break;
        reach = std::max(least, reach - std::max(1, radii.kernel / 2));
    }
    const std::vector<detail::MarginCell> cells = detail::margin_cells(c, o, reach, radii.rho);
    Extent source = frame;
    if (scene.power) {
        sum.emitters = scene_emitters(scene, cells);
        for (const Emitter& e : sum.emitters) source.add(c, e.x, e.y, e.x + e.w, e.y + e.h);
    } else {
        source.add(c, o - reach, o - reach, c.width - o + reach, c.height - o + reach);
        sum.emitters.resize(size_t(c.width) * c.height + cells.size());
    }
    const double pitch = lattice_pitch(s, c, wavelength, nearest, source, film);
    sum.source_extent = source;
    sum.film_extent = film;
    if (with_samples) sum.samples = sample_aperture(s.aperture, pitch);
    else sum.samples.pitch = pitch;
    sum.subsamples = film_subsamples(s, c, wavelength);
    if (with_samples) sum.film = camera_film(c, sum.subsamples, range.row_begin, range.row_end, o, c.width - o);
    return sum;
}

}  // namespace

namespace {

// Directions within tangents |u| <= e.u, |v| <= e.v as in-plane direction components (sines).
DirectionRange direction_range(const Extent& e, double rho0, double rho1) {
    const double sx = e.u / std::sqrt(1 + e.u * e.u), sy = e.v / std::sqrt(1 + e.v * e.v);
    return {-sx, sx, -sy, sy, rho0, rho1};
}

// How one run's two sums (or one source's, `single`) are evaluated, and their work in direct
// terms: sum 1 from the sources to the pinhole, sum 2 to the film, each by the evaluator
// s.summation asks for (summation_plan.h, choose_sum). Decided from the whole frame's counts, so
// that every share of a job evaluates its part as the job would; the film's chirps planned over
// the frame.
struct SumPlan {
    SummationSettings settings;
    PlanScope in, out;
    double in_work = 0, out_work = 0;  // the film's for the whole frame
};

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

}  // namespace

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

// Random phase (the seed paper): each run every source at once with its own phase, weighted
// 1/runs and averaged into the output on its own, so a job equals the sum of its shares. The
// sources stay where they are from run to run (but for independent phases with jitter): one plan
// serves every run, each run only new weights.
Result<bool> random_phase_runs(const SceneSum& sum, const PinholeCamera& c, double wavelength,
                               const ExactSettings& s, const SumPlan& plan, const WorkRange& range,
                               std::vector<float>& points, float* irradiance, const ProgressFn& progress) {
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
Result<bool> psf_runs(const MonochromeScene& scene, const SceneSum& sum, double wavelength, const ExactSettings& s,
                      double nearest, const WorkRange& range, float* irradiance, const ProgressFn& progress,
                      detail::CoherentMemo* memo) {
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
    if (s.summation == Summation::Psf) return psf_runs(scene, sum, wavelength, s, nearest, range, irradiance, progress, memo);
    std::vector<float> points(sum.film.size(), 0.0f);  // irradiance at every film point
    const bool incoherent = s.method == CoherenceMethod::Incoherent;
    const SumPlan plan = plan_sums(s, sum, c, wavelength, nearest, incoherent);
    if (!incoherent) return random_phase_runs(sum, c, wavelength, s, plan, range, points, irradiance, progress);
    auto r = incoherent_sum(sum, c, wavelength, plan, points, progress);
    if (r.ok()) average_into_output(points, sum, c, s.overscan, range, irradiance);
    return r;
}

}  // namespace wavecam
