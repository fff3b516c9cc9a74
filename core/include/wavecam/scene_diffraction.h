// Diffracting a rendered scene at one wavelength by the scene-sum methods: every pixel is a point
// source on its ray at its depth, and the seed paper's random-phase method (or the exact
// incoherent sum) carries each source's waves through the sampled pinhole to every film pixel.
#pragma once
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>
#include "wavecam/aperture.h"
#include "wavecam/summation_plan.h"
#include "wavecam/pinhole_camera.h"
#include "wavecam/spectral_scene.h"
#include "wavecam/progress.h"
#include "wavecam/result.h"

namespace wavecam {

// A job's one decision of how its scene sums are evaluated (decide_summation, made before any
// work): the kernel summation, or the point sums with each sum's evaluator at each wavelength. Every wavelength's
// sums read it; nothing below decides again, so the job line, the header and what runs agree,
// and every share of the job evaluates as the job.
struct SummationDecision {
    Summation summation = Summation::Auto;  // Kernel, or the point sums
    bool gpu = false;                        // decided for a device's GPU (compute_device.h)
    // One wavelength's two sums: to the pinhole and to the film.
    struct AtWavelength {
        double wavelength;  // (m)
        SumChoice to_pinhole, to_film;
    };
    std::vector<AtWavelength> choices;  // the point sums' wavelengths, each once
    // The choice at `wavelength` (null where the decision holds none: that frame decides alone).
    const SumChoice* to_pinhole_at(double wavelength) const;
    const SumChoice* to_film_at(double wavelength) const;
};

enum class CoherenceMethod {
    RandomPhase,  // the seed paper: random phase per source, coherent sum, K runs averaged
    Incoherent,   // exact: every source propagated alone, irradiances summed (small images)
};

// The scene-sum methods' settings (random-phase and incoherent).
struct SceneSumSettings {
    Aperture aperture{ApertureShape::Circle, 0.0};
    CoherenceMethod method = CoherenceMethod::RandomPhase;
    int runs = 64;             // K, random-phase runs averaged (64: every channel within 2% of the limit)
    // Move the sources within their pixels: with coded phases all by one random offset a job, with
    // independent phases each anew every run. Off by default: sources at pixel centres, as the
    // convolution method and the incoherent sum place them, so that the runs converge to its image.
    bool jitter = false;
    // Coded phases (phase_codes.h, docs/phase_codes.md): the runs' phases offset by 2 pi k m / K so
    // that sources of different classes cancel exactly over the K runs. false: the seed paper's
    // independent phases, noise falling as 1/sqrt(K).
    bool coded_phases = true;
    uint64_t seed = 1;         // random phases and jitter; same seed, same image
    double sin_theta_max = 0;  // aperture sampling lambda/(2 sin theta_max); 0 = from the frame
    int film_subsamples = 0;   // n: each film pixel averages n x n points; 0 = auto_film_subsamples
    int nthreads = 0;
    // How the two sums are evaluated (summation_plan.h): direct and nufft evaluate the same terms;
    // kernel, convolutions with the amplitude PSFs they compute. `auto` here: each sum the cheaper of
    // direct and nufft; a job first weighs the kernel summation against them (chosen_summation).
    Summation summation = Summation::Auto;
    double summation_tolerance = kSummationTolerance;
    // One share of the work (work_share.h): runs [run_begin, run_end) of the `runs` averaged, each
    // still weighted 1/runs, on output rows [row_begin, row_end); an end < 0 means the last.
    // Every run is averaged into the output on its own, so a job equals the sum of its shares.
    int run_begin = 0, run_end = -1;
    int row_begin = 0, row_end = -1;
    // Pixels of margin on every side of the input: light sources, not film (cropped by the
    // caller). Beyond the input the scene is its edge continued (frame_margin.h).
    int overscan = 0;
    // The scene's nearest planar depth (m; inf: all sky), found once per job (nearest_depth()) so
    // that the estimate and every wavelength's sum derive the same lattice; NaN: each call finds it.
    double nearest_depth = NAN;
    // The job's decision (decide_summation), which every wavelength's sums follow; null: each
    // wavelength's frame decides its sums' evaluators as it starts (a frame diffracted alone).
    std::shared_ptr<const SummationDecision> decision;
};

// Per-pixel inputs at one wavelength, row-major width x height.
struct MonochromeScene {
    PinholeCamera camera;
    const float* power = nullptr;  // spectral radiance (any consistent unit), >= 0
    const float* depth = nullptr;  // metres; >= kInfiniteDepth or inf = sky
    DepthMeaning depth_meaning = DepthMeaning::Planar;
    int spectral_index = 0;  // which wavelength sample of a spectral job this is
    int sign = +1;           // +1: the spectral power where positive, -1: where negative
    bool checked = false;    // its pixels already checked, once for the job: not again here
};

// The aperture sampling pitch used for this camera at this wavelength, its sources and film
// points both within the frame: lambda/2, or wider when every ray between a pinhole sample and a
// source or film point stays within theta_max of the axis: tan theta_max = tan(corner field
// angle) + a / min(f, nearest depth), plus the aperture's own diffraction spread lambda/d as
// margin; never coarser than d / kMinSamplesAcross. A lit scene beyond the frame can need a
// finer one (frame_margin.h).
constexpr double kMinSamplesAcross = 128;
double scene_sample_pitch(const SceneSumSettings& s, const PinholeCamera& camera, double wavelength,
                          double nearest_depth);

// What a job runs for `auto` summation (diffract_image decides it once per job): `kernel` where it
// applies — sources at their pixels' centres (no jitter), an opening of one piece (circle, square,
// polygon), the scene's depths within kMaxKernelLayers amplitude layers — its work at this
// wavelength (kernels, then every run) is below the point sums', and a check at plan time finds it
// within 1.5% of the point sums' same runs (probe stars against the point sums' kernels, and the
// far tail's cross terms; docs/summation.md); else `auto`, each of the two sums
// the cheaper of direct and nufft (estimate_summation's chooser), as diffract_monochrome reads `auto`. Counted for
// the whole job (every run and row, the frame as lit), so every share decides as its job; for
// s.nearest_depth (NaN counts as all sky). A summation asked by name is returned as it is.
Summation chosen_summation(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& camera,
                           double wavelength);

// The job's decision for its wavelengths (m): chosen_summation's kernel summation or point sums at the middle
// one, then each point sum's evaluator at each wavelength from the same counts (the whole job,
// every pixel lit, s.nearest_depth), the lowest estimate among those `device` allows.
SummationDecision decide_summation(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& camera,
                                   const std::vector<double>& wavelengths);

// What the chooser (core/src/summation/choose.h, the one place evaluators and devices are chosen
// and priced) makes of the settings' share of a frame at `wavelength`, every pixel lit, for
// s.nearest_depth (NaN counts as all sky): `auto` weighs the kernel summation where it applies against the exact
// sums (chosen_summation's choice, for the settings' rows and runs). `term_rate` (terms/s,
// term_rate.h) gives `seconds`; 0 leaves them 0 and says the reason in terms.
struct SummationEstimate {
    Summation summation = Summation::Auto;  // kernel, direct, nufft, or auto: the two sums differ
    EvaluatorSet sums;                      // the point sums' evaluators (none for kernel)
    bool gpu = false;                       // on the device's GPU
    double terms = 0, seconds = 0;          // work in direct terms, and at term_rate
    double bytes = 0;                       // what the kernel summation holds at once (0 for the point sums)
    std::string reason;                     // e.g. "kernel: 1.9 s estimated against nufft 6.3 s"
};
SummationEstimate estimate_summation(const SceneSumSettings& s, const ComputeDevice& device,
                                     const PinholeCamera& camera, double wavelength, double term_rate = 0);

// The evaluators the two sums take at `wavelength` (s.summation auto, direct or nufft), as the
// estimate counts the frame (every pixel lit, s.nearest_depth): what decide_summation records for
// a job, and so what its sums take.
EvaluatorSet scene_evaluators(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& camera,
                              double wavelength);

// Work estimate in direct terms (the time of one term of the direct sums, so that --max-terms
// and the time printed mean the same for either evaluator): direct, pinhole samples x (sources +
// film points); nufft, the NUFFTs' and chirps' work (the chooser's cost model), each sum by
// the evaluator s.summation picks for it (kernel: its kernels and runs); over the runs and rows set,
// the margin beyond the frame counted as lit, for s.nearest_depth (NaN counts as all sky).
double scene_terms(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& camera,
                   double wavelength);

// Bytes the kernel summation holds at once for one wavelength on `device` (its kernels' spectra:
// layers x anchors x film points per pixel transforms of the frame; the runs' sums; in direction
// cosines its transforms' grids, sources and film points), for s.nearest_depth (NaN counts as all
// sky); 0 for the other summations.
double scene_summation_bytes(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& camera,
                             double wavelength);

// Film points per pixel side so that the points are closer than the irradiance's finest
// fringe, lambda f / span (span: the aperture's largest width): then a pixel's points average
// its Fresnel structure instead of sampling it; and so that they average the pixel's area to
// within kPixelAverageError at every frequency the optics pass, weighted by the OTF (1 per pixel
// where pixels are a quarter of a fringe, 4 at 1.3 fringes, 8 at 5.6). At most kMaxFilmSubsamples.
constexpr int kMaxFilmSubsamples = 64;
constexpr double kPixelAverageError = 0.015;
int auto_film_subsamples(const Aperture& aperture, const PinholeCamera& camera, double wavelength);

// Adds the film irradiance |U|^2 of the scene at `wavelength` to irradiance[width * height]
// (output pixel (i, j) averages n x n points over the film area of pixel (i, j), the geometric
// image of render pixel (i, j)), in units of power x steradian. The sources are every pixel and
// the scene beyond the input (frame_margin.h); the film is the frame within s.overscan, whose
// margin pixels are left untouched. The sums run on `device` (compute_device.h: the CPU, or a
// GPU that runs the direct terms and the kernel summation's runs; nufft is refused there), and
// what they ran is noted in `report` where one is given (the job's, summation_plan.h).
Result<bool> diffract_monochrome(const MonochromeScene& scene, double wavelength, const SceneSumSettings& s,
                                 const ComputeDevice& device, float* irradiance, const ProgressFn& progress = {},
                                 SumReport* report = nullptr);

}  // namespace wavecam
