// One frame resolved before any work, once: its render (read and checked by load_render), the
// camera, the colours, and what its method derives from the options. The estimate, the run, the
// output's header and a share of the job (share_files.cpp) all read this one value. Internal to
// wavecam_io.
#pragma once
#include <string>
#include "wavecam/colour_pipeline.h"
#include "wavecam/diffract_image.h"

namespace wavecam::detail {

// A job's colour: the config, the input's linear working space (named by the options, else by
// the file, else Rec.709), the output's, and the spectral basis calibrated against the working
// space as the config defines it.
struct JobColour {
    ColourConfig config;
    std::string in_space, out_space;
    SpectralSampling sampling;
    SpectralBasis basis;
};

struct ResolvedFrame {
    RenderInput in;
    PinholeCamera camera;
    int overscan = 0, out_w = 0, out_h = 0;  // the film: the frame within the overscan
    OIIO::ROI kept;  // the film's pixels the output holds: all, or the data window within a widened frame
    Aperture aperture;
    JobColour colour;
    SceneSumSettings scene_sum;       // scene-sum methods: the estimate's and run's settings
    ComputeDevice device;             // scene-sum methods: the job's device handle, passed to its sums
    std::shared_ptr<SumReport> report = std::make_shared<SumReport>();  // what the job's sums ran
    ConvolutionPlanSpec convolution;  // convolution method: what its plan is built for
    double terms = 0;                 // scene-sum methods: the sums' cost
    std::string job;                  // "24x16 pixels x 3 wavelengths x 2 runs"

    SpectralScene scene(DepthMeaning meaning) const {
        return {camera, in.rgb.data(), in.depth.data(), meaning, true};
    }
};

// The wavelength the pinhole formulas are designed at: Rayleigh's optimum, the Fresnel number.
constexpr double kDesignWavelength = 550e-9;

// What `auto` chose for the job's sums (resolve_frame.cpp): kernel, else the evaluators that ran,
// from the job's report (the header's), or, before they ran (no report, or nothing in it), those
// the job's decision gives each sum on `device`.
std::string auto_choice(const SceneSumSettings& s, const ComputeDevice& device, const SumReport* report,
                        const PinholeCamera& camera, const SpectralBasis& basis);

// The job's decision (SceneSumSettings::decision) and device in words, as a share file records it
// so that a merge refuses shares that decided otherwise (another device, another build):
// "kernel on cpu", or each wavelength's sums "450nm direct/nufft, 550nm nufft/nufft on gpu".
std::string decision_text(const SceneSumSettings& s);

// The frame's estimate (diffract_image.h's JobEstimate) but for its bytes and refusal: its job
// line, terms, and their time at the rate measured on the job's device.
JobEstimate job_estimate(const DiffractOptions& opt, const ResolvedFrame& f, int nthreads);

// `input` (load_render's value) under `opt`; errors name `name`.
Result<ResolvedFrame> resolve_frame(const DiffractOptions& opt, RenderInput input, const std::string& name,
                                    int nthreads);

}  // namespace wavecam::detail
