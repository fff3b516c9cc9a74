// The seed paper's two sums (propagation.h: scene -> pinhole samples, pinhole samples -> film
// points), the same terms with the same amplitudes, obliquity and phases, evaluated in about
// O(N log N) instead of term by term (docs/fast_summation.md):
//   - each path length is split exactly as r = R - u.xi + psi(u, 1/R, xi): the linear part is a
//     Fourier kernel on the pinhole lattice, summed by a gridding NUFFT (type 1 from the sources,
//     type 2 to the film points);
//   - the lattice is cut into sub-apertures; on each, psi's value and slope at its centre are
//     exact per point (a phase, a shift of the point's frequency), and the quadratic remainder,
//     smooth in the point's direction and inverse distance, is interpolated over Chebyshev nodes
//     whose chirps are compressed to a few skeleton nodes, one NUFFT each;
//   - samples off the lattice (rim cells' centroids) are read from or spread onto the lattice with
//     a band-limited stencil where the lattice's band leaves room, else summed directly (grey
//     masks and sieves, all samples off it, take the stencil only at the full tolerance).
// The stated error: each sum within `tolerance` of the direct one, relative to the sum of its
// terms' sizes, checked against the direct sums in tests/test_fast_summation.cpp.
#pragma once
#include <complex>
#include <vector>
#include "wavecam/propagation.h"

namespace wavecam {

enum class Summation {
    Fast,    // per sum, NUFFTs over the lattice with interpolated chirps unless the work estimate
             // says the direct terms are cheaper (large Fresnel numbers, one source) (default)
    Direct,  // term by term, the reference evaluator
    Nufft,   // the NUFFTs always (tests, benchmarks), but for the incoherent method's one-source sums
};

constexpr double kSummationTolerance = 3e-4;

// The default evaluator: Fast, unless the environment variable WAVECAM_SUMMATION names another
// (fast, direct or nufft) - how the test suite runs every exact-method test through each.
Summation default_summation();

// The parameters a sum's chirps depend on: in-plane direction components (ux, uy) of the sources
// or film points, and inverse distance 1/R (0: plane waves), as ranges.
struct DirectionRange {
    double ux0 = 0, ux1 = 0, uy0 = 0, uy1 = 0;
    double rho0 = 0, rho1 = 0;
};

struct SummationSettings {
    Summation method = default_summation();
    double tolerance = kSummationTolerance;
    int nthreads = 0;
    // The chirps' interpolation planned over this range rather than the points' own, so that a
    // share of the points (rows of a frame) gets the plan, and the bits, of the whole frame.
    bool fixed_range = false;
    DirectionRange range{};
    // Sub-apertures per side the lattice is cut into (each expanded about its centre), or 0: the
    // cheapest by summation_work, chosen here. A job's shares are given the job's choice.
    int blocks = 0;
    // With blocks given: whether off-lattice samples go through the band-limited stencil where it
    // reaches (else all direct), as summation_work chose for the job.
    bool stencil = true;
};

// propagation.h's sums through `settings.method`.
bool illuminate_pinhole(const ApertureSamples& samples, const std::vector<PointSource>& sources, double wavelength,
                        PinholeField& field, const SummationSettings& settings, const ProgressFn& progress = {});
bool add_film_field(const ApertureSamples& samples, const PinholeField& field, const FilmPoints& film,
                    double wavelength, std::complex<double>* film_field, const SummationSettings& settings,
                    const ProgressFn& progress = {});
bool accumulate_film_irradiance(const ApertureSamples& samples, const PinholeField& field, const FilmPoints& film,
                                double wavelength, double scale, float* irradiance,
                                const SummationSettings& settings, const ProgressFn& progress = {});

// Work of one sum in direct terms (the time of one term of propagation.cpp's kernel), for
// `points` sources or film points within `range` on the lattice of `samples_across` x
// `samples_across` (`off_lattice` of them summed directly). Direct: samples x points.
struct SummationWork {
    double direct = 0, fast = 0;
    int nufft_count = 0;  // the fast path's transforms (interpolation nodes x sub-apertures)
    int blocks = 1;       // the cheapest division: blocks x blocks sub-apertures
    bool stencil = true;  // off-lattice samples through the stencil (where it reaches) rather than direct
};
SummationWork summation_work(double lattice_samples, int samples_across, double off_lattice, double points,
                             const DirectionRange& range, double aperture_radius, double wavelength,
                             bool film, double tolerance);

// "fast summation", "direct summation", "NUFFT summation": for estimates and headers.
const char* summation_name(Summation s);

// Whether `settings.method` takes the NUFFTs for that work.
bool use_fast(const SummationSettings& settings, const SummationWork& work);

}  // namespace wavecam
