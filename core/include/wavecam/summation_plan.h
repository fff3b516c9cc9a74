// The scene-sum methods' two sums as plans (docs/summation.md), in the manner of FINUFFT's:
//   create     on a device handle, for one sum (sources -> pinhole samples, or pinhole samples
//              -> film points), a pinhole lattice and a wavelength;
//   set_points the points on the far side (source positions, or film points); this commits the
//              plan to one evaluator, chosen in one place (core/src/summation/choose.h), and
//              builds what that evaluator keeps (lattice layouts, stencils, chirp interpolation);
//   execute    as often as the weights change (every run of the random-phase method);
//   release    (or let the last copy go).
// Evaluators behind a plan, the same terms with the same amplitudes, obliquity and phases:
//   direct  term by term (propagation.h): the reference;
//   nufft   NUFFTs over the pinhole lattice with interpolated chirps (docs/summation.md),
//           each sum within `tolerance` of the direct one, relative to the sum of its terms' sizes;
// the direct terms run on the CPU, or on a GPU through Vulkan (gpu_sums.h), as the plan's device
// handle says (compute_device.h), passed to create as Embree passes its RTCDevice; nufft has no
// GPU evaluator.
// Plain types only (no threading or SIMD types). A plan's executes are not for concurrent calls.
#pragma once
#include <atomic>
#include <complex>
#include <memory>
#include <string>
#include <utility>
#include <vector>
#include "wavecam/aperture.h"
#include "wavecam/compute_device.h"
#include "wavecam/progress.h"
#include "wavecam/propagation.h"
#include "wavecam/result.h"
#include "wavecam/source.h"

namespace wavecam {

// What a user asks for: `auto` the cheaper evaluator by the cost model (default), or one of them;
// or `kernel`: a scene's runs as convolutions with amplitude PSFs that the sums compute at field
// anchors and depth layers (scene_diffraction.h; its plans then take `auto`).
enum class Summation { Auto, Direct, Nufft, Kernel };
const char* summation_word(Summation s);  // "auto", "direct", "nufft", "kernel"
// Every word the `summation` setting takes with its value: `auto`, then each evaluator's, from
// the evaluators' table (core/src/summation/evaluator_table.cpp).
std::vector<std::pair<const char*, Summation>> summation_choices();

// What a committed plan runs.
enum class Evaluator { Direct, Nufft };
const char* evaluator_word(Evaluator e);  // "direct", "nufft"

constexpr double kSummationTolerance = 3e-4;

struct SummationSettings {
    Summation summation = Summation::Auto;
    double tolerance = kSummationTolerance;
    int nthreads = 0;  // 0: every core
};

// The parameters a sum's chirps depend on: in-plane direction components (ux, uy) of the sources
// or film points, and inverse distance 1/R (0: plane waves), as ranges.
struct DirectionRange {
    double ux0 = 0, ux1 = 0, uy0 = 0, uy1 = 0;
    double rho0 = 0, rho1 = 0;
};

// How one sum is evaluated and what it costs, in direct terms (the time of one term of the
// direct kernel, so that --max-terms and the time printed mean the same for either evaluator).
struct SumChoice {
    Evaluator evaluator = Evaluator::Direct;
    int blocks = 1;        // nufft: the lattice cut into blocks x blocks sub-apertures
    bool stencil = true;   // nufft: off-lattice samples through the band-limited stencil where it reaches
    double work = 0;       // the chosen evaluator's
    double direct_work = 0, nufft_work = 0;
    int nufft_count = 0;   // nufft: transforms (interpolation nodes x sub-apertures)
    bool gpu = false;      // direct: on a GPU (set when the plan is committed)
};

// What a sum's cost depends on: counts, not samples, so that an estimate needs no work.
struct SumCounts {
    double lattice_samples = 0;  // samples at lattice cell centres
    double off_lattice = 0;      // samples elsewhere (rim centroids, grey masks, sieve holes)
    int samples_across = 0;      // lattice cells across the aperture
    double points = 0;           // sources or film points
    DirectionRange range;
    double aperture_radius = 0, wavelength = 0;
    bool film = false;           // the sum to the film (else from the sources)
    double tolerance = kSummationTolerance;
};

// One sum's evaluator: `asked` direct or nufft as asked; auto the cheaper by the cost model, or,
// `on_gpu`, direct: the one evaluator a GPU has. Part of the chooser (core/src/summation/choose.h),
// which holds every cost model and decides for the frame.
SumChoice choose_sum(const SumCounts& counts, Summation asked, bool on_gpu = false);

// The device a job opens for its `device` setting and the summation asked (decided with the
// evaluators, core/src/summation/choose.cpp): `gpu` with nufft is refused (a GPU has no nufft
// evaluator), `auto` with nufft stays on the CPU and says why.
struct DeviceChoice {
    Device open = Device::Cpu;
    std::string refusal;  // non-empty: the job is refused (setting `summation`)
    std::string on_cpu;   // `auto` on the CPU: why ("" where a GPU may be used)
};
DeviceChoice choose_device(Summation asked, Device setting);

// Which evaluators a job's sums take, by sum: bit 1 << e for each Evaluator e.
struct EvaluatorSet {
    unsigned to_pinhole = 0, to_film = 0;
    void add(bool to_the_film, Evaluator e) { (to_the_film ? to_film : to_pinhole) |= 1u << unsigned(e); }
    void add(const EvaluatorSet& o) { to_pinhole |= o.to_pinhole, to_film |= o.to_film; }
    bool has(bool to_the_film, Evaluator e) const { return (to_the_film ? to_film : to_pinhole) >> unsigned(e) & 1; }
    // "direct" or "nufft" where every sum took it; else each sum's: "nufft to the pinhole, direct
    // to the film" ("direct and nufft" for a sum that took both, at different wavelengths or for
    // different parts of the light); "" where none.
    std::string words() const;
};

// What a share of a job takes from the job, so that its part is evaluated, to the bit, as the
// job's: the chirps planned over the frame's range, and the job's choice.
struct PlanScope {
    bool fixed_range = false;
    DirectionRange range;
    bool fixed_choice = false;
    SumChoice choice;
};

enum class SumKind {
    SourcesToPinhole,  // U(xi) = sum_s w_s exp(i k (r_s - |P_s|)) / r_s (plane waves: w_s exp(-i k u_s.xi))
    PinholeToFilm,     // U(t) = sum_xi w(xi) exp(i k (r - |T|)) f / r^2 (Rayleigh-Sommerfeld I)
};

// What a job's sums ran: its report, filled as they run (not kept on the device, which a host
// may share between jobs): each sum's evaluators, as its plans commit, and where they ran (the
// device, the CPU, or both where the kernel summation's runs left a device that could not hold
// them). Notes from any thread.
class SumReport {
public:
    void note(SumKind kind, const SumChoice& committed);  // a committed plan with points
    void note_runs(bool on_gpu);                          // runs without plans (the kernel summation's)
    EvaluatorSet evaluators() const;
    // Where the sums ran: `device`'s description, "cpu", or "<description> and the CPU";
    // `device`'s description before anything ran.
    std::string ran_on(const ComputeDevice& device) const;

private:
    std::atomic<unsigned> ran_{0};
};

class SummationPlan {
public:
    SummationPlan() = default;  // empty: create() makes one
    // On `device` (compute_device.h), which the plan holds until it is released.
    static SummationPlan create(const ComputeDevice& device, SumKind kind, const ApertureSamples& samples,
                                double wavelength, const SummationSettings& settings, const PlanScope& scope = {});

    // SourcesToPinhole: the sources' positions (x, y, z or a plane wave's direction); their
    // amplitudes and phases are ignored here, they come with each execute. Fails only where the
    // plan's device cannot run the evaluator (nufft on a GPU), or a `gpu` handle has no device.
    Result<bool> set_points(const std::vector<PointSource>& sources);
    // PinholeToFilm: the film points.
    Result<bool> set_points(const FilmPoints& film);

    // Executes fail with ErrorKind::Cancelled when `progress` cancels, or with the device's error.
    // SourcesToPinhole: `field` = the field at every pinhole sample for sources of complex
    // amplitudes `weights` (a_s e^{i phase_s}, one per source), times the sample's area / lambda.
    Result<bool> execute(const std::vector<std::complex<double>>& weights, PinholeField& field,
                         const ProgressFn& progress = {}) const;
    // PinholeToFilm: adds the film field of the pinhole field `field` to film_field[t].
    Result<bool> execute(const PinholeField& field, std::complex<double>* film_field,
                         const ProgressFn& progress = {}) const;
    // PinholeToFilm: adds scale |U(t)|^2 to irradiance[t].
    Result<bool> execute_irradiance(const PinholeField& field, double scale, float* irradiance,
                                    const ProgressFn& progress = {}) const;

    const SumChoice& choice() const;
    size_t point_count() const;
    void release() { impl_.reset(); }
    explicit operator bool() const { return bool(impl_); }

    struct Impl;

private:
    std::shared_ptr<Impl> impl_;
};

// The complex amplitudes of sources as they are given (amplitude e^{i phase}): the weights of a
// SourcesToPinhole plan made from the same sources.
std::vector<std::complex<double>> source_weights(const std::vector<PointSource>& sources);

}  // namespace wavecam
