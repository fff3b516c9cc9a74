// The ImageBuf entry point: a render (RGB radiance + depth) in, the image a real pinhole camera
// of the given size makes out. ImageBufAlgo style: dst, src, options, nthreads; errors carried
// in dst (dst.geterror()), never thrown.
#pragma once
#include <OpenImageIO/imagebuf.h>
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include "wavecam/output_layout.h"
#include "wavecam/render_input.h"
#include "wavecam/convolution_method.h"
#include "wavecam/scene_diffraction.h"
#include "wavecam/spectral_diffraction.h"

namespace wavecam {

// Convolution: PSF-grid convolution (the default, `--method convolution`). The scene-sum methods,
// two sums over pinhole samples: RandomPhase, the seed paper's random-phase runs (`--method
// random-phase`), and Incoherent, every source propagated alone (`--method incoherent`).
enum class DiffractMethod { Convolution, RandomPhase, Incoherent };

// "convolution", "random-phase", "incoherent": the setting's words, as headers record them.
const char* method_word(DiffractMethod m);

// What a frame costs, found as diffract finds it before any work: the job line, the scene sums'
// terms and the seconds they take at the rate measured here and now where they run (measured_term_rate on
// the job's device), the
// bytes at the job's peak, and the refusal the job would meet (max-terms, max-memory), "" if
// none. The convolution method has no scene sums: terms and seconds 0.
struct JobEstimate {
    std::string job;  // "24x16 pixels x 3 wavelengths x 2 runs, ..." (the job line)
    double terms = 0, seconds = 0, rate = 0, bytes = 0;
    int threads = 0;      // the threads the rate was measured on
    std::string refusal;  // the job's refusal by its limits, naming `name`
};

struct DiffractOptions {
    DiffractMethod method = DiffractMethod::Convolution;
    RenderReadOptions read;                        // depth channel, fov
    DepthMeaning depth_meaning = DepthMeaning::Planar;
    double film_distance = 50e-3;                  // f, metres
    double pinhole = 0;                            // diameter (m); 0 = Rayleigh's optimum for f at 550 nm
    Aperture aperture;                             // shape (--aperture); its diameter comes from `pinhole`
    SceneSumSettings scene_sum;                    // scene-sum methods: runs, seed, jitter, film subsamples, summation
    Device device = Device::Cpu;                   // scene-sum methods: where the sums run; each job opens it
                                                   // as its handle (compute_device.h), passed to the sums
    // random-phase: the run count from the frame's PSF size (run_count.h) instead of scene_sum.runs;
    // what the fronts do unless a count is given
    bool runs_from_psf = false;
    ConvolutionSettings convolution;               // convolution method: tiles, kernel size
    int overscan = 0;                              // pixels of margin on every side: light sources, cropped
                                                   // from the output (the fov is the full input's)
    std::vector<double> wavelengths;               // explicit list (m); empty = wavelength_count in 400-700 nm
    int wavelength_count = 8;
    bool monochrome = false;                       // every channel through the same light (also when < 3 wavelengths)
    bool vignetting = true;                        // keep the natural cos^4 fall-off
    std::string colorconfig;                       // OCIO config; "" = the one wavecam ships
    std::string input_colorspace;                  // "" = the file's oiio:ColorSpace, else lin_rec709
    std::string output_colorspace;                 // "" = the input's
    bool desaturate_out_of_gamut = true;           // colours the output space cannot hold: pulled in at
                                                   // constant luminance (out_of_gamut.h); false keeps them
    bool other_channels = true;                    // every channel but the diffracted ones passes through
                                                   // (AOVs, Cryptomatte, IDs); false keeps RGB(A) and depth
    OIIO::TypeDesc pixel_type = OIIO::TypeUnknown;  // the diffracted channels' type in the file; unknown = the input's
    HalfOverflow half_overflow = HalfOverflow::Float;  // half channels with values beyond half's range (output_layout.h)
    std::string compression;                       // the file's compression; "" = the input's
    double max_terms = 4e12;                       // refuse larger scene-sum jobs (see term_rate.h for the time)
    double max_memory = 16.0 * (1ull << 30);       // bytes; refuse jobs estimated to need more
    ProgressFn progress;
    // Told the scene-sum methods' estimate before any work starts (the job line, its terms and
    // time; a share's own).
    std::function<void(const JobEstimate&)> on_estimate;
    // Replaces the scene-sum methods' physical propagator (shares and merges, share_files.h).
    MonochromePropagator scene_sum_propagator;
};

// The aperture the options resolve to: its diameter `pinhole`, Rayleigh's optimum when none is given.
Aperture resolved_aperture(const DiffractOptions& opt);

// Terms the job costs for an image of this size, field of view and depth (for refusing and
// reporting): the point sums' terms with the job's spectral basis (three propagations per
// wavelength for monochrome light); 0 for the convolution method or when that basis cannot be made.
double estimate_terms(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
                      const FileColour& file_colour = {});

// The random-phase runs the job averages: scene_sum.runs, or the count runs_for_convergence gives
// this frame where runs_from_psf (its longest wavelength, nearest source); 1 for the incoherent
// method, 0 for the convolution method or when the colour cannot be resolved.
int job_runs(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
             const FileColour& file_colour = {});

// Bytes the job needs at its peak (images, pinhole samples or PSF kernels), an upper estimate.
double estimate_memory(const DiffractOptions& opt, const PinholeCamera& camera);

struct RenderInput;
namespace detail {
struct ResolvedFrame;  // one frame's render, camera, colours and method settings (core/io/src/resolved_frame.h)
}

// Options resolved once and the convolution method's plan (kernel table, kernel spectra) kept for the next
// frame that shares its camera, pinhole, colours and depth range: a sequence, or an OIIO host
// opening the same shot again, pays for the table once. Safe to share between threads.
class DiffractPlan {
public:
    explicit DiffractPlan(DiffractOptions options);
    const DiffractOptions& options() const { return opt_; }

    // Diffracts `src`; `name` is used in error messages (the file name). dst gets float R, G, B
    // in the output colour space, the source's depth channel, and every parameter in its header.
    // A failure carries its kind and the setting it is about, for the front to word (result.h).
    Result<bool> diffract(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& name, int nthreads = 0);
    // What diffract(dst, src, name, nthreads) would cost, without the work (JobEstimate).
    Result<JobEstimate> estimate(const OIIO::ImageBuf& src, const std::string& name, int nthreads = 0);
    // The same, for a caller that has resolved the frame already under options() but for their
    // callbacks and limits (a share resolves it once, for its estimate and its run).
    Result<bool> diffract(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const detail::ResolvedFrame& frame,
                          const std::string& name, int nthreads = 0);

private:
    // diffract(dst, src, frame, ...), freeing `spent` (the frame's own render) once its image is
    // made, before the output's is: a 4K frame's radiance and depth are 130 MB of its peak
    Result<bool> diffract_frame(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const detail::ResolvedFrame& frame,
                                const std::string& name, int nthreads, RenderInput* spent);
    Result<bool> run_convolution(const DiffractOptions& opt, const detail::ResolvedFrame& frame, std::vector<float>& xyz);
    Result<bool> diffract_alpha(const DiffractOptions& opt, const detail::ResolvedFrame& frame, std::vector<float>& alpha);
    DiffractOptions opt_;
    std::mutex mutex_;
    std::shared_ptr<const ConvolutionPlan> convolution_;
};

// One frame through a plan of its own; errors in dst.geterror(), naming the setting they are about.
bool diffract(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& name, const DiffractOptions& opt,
              int nthreads = 0);

}  // namespace wavecam
