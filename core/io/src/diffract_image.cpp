// The ImageBuf entry point (diffract_image.h): a resolved frame's limits checked, its method run
// (and its alpha as coverage), its colours mapped and its output header written.
#include "wavecam/diffract_image.h"


#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>

#include "colour_metadata.h"
#include "multi_view.h"
#include "pixel_aspect.h"
#include "resolved_frame.h"
#include "wavecam/edge_continuation.h"
#include "wavecam/output_layout.h"
#include "wavecam/pinhole_design.h"
#include "wavecam/term_rate.h"
#include "wavecam/threads.h"
#include "wavecam/units.h"

namespace wavecam {
namespace {
using detail::ResolvedFrame;
using detail::kDesignWavelength;

// The output's pixels out of the film's (XYZ rows): the data window within a widened frame. Each
// row moves to a place before its own: a forward copy in place.
void keep_data_window(std::vector<float>& xyz, int film_w, const OIIO::ROI& kept) {
    if (3 * kept.npixels() == xyz.size()) return;
    for (int j = 0; j < kept.height(); ++j) {
        const float* row = &xyz[3 * (size_t(j + kept.ybegin) * film_w + kept.xbegin)];
        std::copy(row, row + 3 * size_t(kept.width()), &xyz[3 * size_t(j) * kept.width()]);
    }
    xyz.resize(3 * kept.npixels());
}

}  // namespace

const char* method_word(DiffractMethod m) {
    return m == DiffractMethod::Convolution ? "convolution" : m == DiffractMethod::RandomPhase ? "random-phase" : "incoherent";
}

DiffractPlan::DiffractPlan(DiffractOptions options) : opt_(std::move(options)) {}

namespace {

// Coverage that varies over the frame is diffracted; an alpha of 1 (or 0) everywhere stays so.
bool alpha_is_diffracted(const RenderInput& in) {
    if (in.alpha.empty()) return false;
    const auto [lo, hi] = std::minmax_element(in.alpha.begin(), in.alpha.end());
    return !(*lo == *hi && (*lo == 0.0f || *lo == 1.0f));
}

// Bytes the job needs at its peak, `summation` of them the kernel summation's kernels (the largest
// wavelength's: one at a time).
double job_bytes(const DiffractOptions& opt, const ResolvedFrame& f, double& summation) {
    summation = 0;
    if (opt.method != DiffractMethod::Convolution)
        for (int k = 0; k < f.colour.basis.size(); ++k)
            summation = std::max(summation, scene_summation_bytes(f.scene_sum, f.device, f.camera, f.colour.basis.wavelength(k)));
    const bool table = opt.method == DiffractMethod::Convolution || alpha_is_diffracted(f.in);
    return estimate_memory(opt, f.camera) + summation + (table ? ConvolutionPlan::estimate_bytes(f.convolution) : 0.0);
}

// The job's terms and bytes against the max-terms and max-memory limits.
Result<bool> check_limits(const DiffractOptions& opt, const ResolvedFrame& f, const std::string& name,
                          int nthreads) {
    // (an estimate that is not a number, from settings beyond any sense, is refused too)
    if (!(f.terms <= opt.max_terms)) {
        const double rate = measured_term_rate(f.device, nthreads);
        std::ostringstream m;
        const double seconds = f.terms / rate;
        m << name << ": " << f.job << " = " << f.terms << " terms, about "
          << (seconds < 5400 ? std::to_string(long(std::ceil(seconds / 60))) + " min"
                             : std::to_string(long(std::round(seconds / 3600))) + " h")
          << " at the " << rate << " terms/s measured here, beyond the max-terms limit of " << opt.max_terms;
        return Result<bool>::failure(m.str(), ErrorKind::TooLarge, "max-terms");
    }
    double summation = 0;
    const double bytes = job_bytes(opt, f, summation);
    if (!(bytes <= opt.max_memory)) {
        std::ostringstream m;
        m << name << ": " << f.in.width << "x" << f.in.height << " pixels need about " << bytes / (1 << 20)
          << " MiB";
        if (summation > 0) m << " (" << summation / (1 << 20) << " MiB of them the kernel summation's kernels)";
        m << ", beyond the max-memory limit of " << opt.max_memory / (1 << 20) << " MiB";
        return Result<bool>::failure(m.str(), ErrorKind::TooLarge, "max-memory");
    }
    return Result<bool>::success(true);
}

}  // namespace

JobEstimate detail::job_estimate(const DiffractOptions& opt, const ResolvedFrame& f, int nthreads) {
    JobEstimate e;
    e.job = f.job;
    e.terms = f.terms;
    e.threads = nthreads > 0 ? nthreads : default_threads();
    if (opt.method != DiffractMethod::Convolution) {
        e.rate = measured_term_rate(f.device, e.threads);
        e.seconds = f.terms / e.rate;
    }
    return e;
}

namespace {

// The point sums light the film within the overscan from every input pixel and the scene beyond
// the input (frame_margin.h); the output frame is then moved to the front of the same buffer.
Result<bool> run_scene_sum(const DiffractOptions& opt, const ResolvedFrame& f, std::vector<float>& xyz) {
    const int width = f.in.width, o = f.overscan;
    xyz.assign(3 * size_t(width) * f.in.height, 0.0f);
    auto r = diffract_spectral(f.scene(opt.depth_meaning), f.colour.basis, f.aperture,
                               opt.scene_sum_propagator ? opt.scene_sum_propagator
                                                        : wave_propagator(f.scene_sum, f.device, f.report.get()),
                               {opt.vignetting, xyz.data()}, opt.progress);
    if (!r.ok()) return r;
    if (o > 0)  // each row moves to a place before its own: a forward copy in place
        for (int j = 0; j < f.out_h; ++j) {
            const float* row = &xyz[3 * (size_t(j + o) * width + o)];
            std::copy(row, row + 3 * size_t(f.out_w), &xyz[3 * size_t(j) * f.out_w]);
        }
    xyz.resize(3 * size_t(f.out_w) * f.out_h);
    return r;
}

// What the frame's edge continuation left out (edge_continuation.h): "" where every edge pixel
// is continued as it is, or the overscan reaches the kernels' radius.
std::string edge_note(const ResolvedFrame& f) {
    const EdgeContinuation edge(f.in.rgb.data(), 3, f.in.width, f.in.height);
    if (edge.bounded() == 0) return {};
    const int radius = ConvolutionPlan::kernel_radius(f.convolution);
    if (f.overscan >= radius) return {};
    return std::to_string(edge.bounded()) + " edge pixels far brighter than their neighbours along the edge (a sun, "
           "a glint) were continued beyond the frame only as bright as those neighbours: the light beyond the edge "
           "is unknown. For the exact image render " + std::to_string(radius) + " more pixels on every side and give "
           "--overscan " + std::to_string(radius) + " (the plugin: wavecam:overscan " + std::to_string(radius) + ")";
}

// The output's header: the input's less what described the ideal camera (output_layout.h), the
// frame without its overscan, and every parameter of this run.
OIIO::ImageSpec output_spec(const OIIO::ImageSpec& input, const RenderChannels& channels, const DiffractOptions& opt,
                            const ResolvedFrame& f, size_t mapped, const std::string& edge) {
    const RenderInput& in = f.in;
    const SceneSumSettings& s = f.scene_sum;
    // the input's data and display windows, its channels but the diffracted ones as they were
    OIIO::ImageSpec spec = output_header(input, channels, opt.other_channels);
    if (f.overscan > 0) {  // the frame within the overscan setting's margin, an image of its own
        spec.width = spec.full_width = f.out_w;
        spec.height = spec.full_height = f.out_h;
        spec.x = spec.y = spec.full_x = spec.full_y = 0;
    }
    const int frame_w = in.windows.declared ? in.windows.display.width() : f.out_w;
    detail::write_colour_attributes(spec, f.colour.out_space, f.colour.config);
    spec.attribute("wavecam.pinhole", with_unit(f.aperture.diameter, 1e-3, "mm"));
    spec.attribute("wavecam.aperture", f.aperture.name());
    spec.attribute("wavecam.film-distance", with_unit(opt.film_distance, 1e-3, "mm"));
    spec.attribute("wavecam.film-width", with_unit(f.camera.pixel_pitch() * frame_w, 1e-3, "mm"));
    // the output's own field of view: its display window's, or the frame's within an overscan setting
    spec.attribute("wavecam.fov",
                   static_cast<float>(2 * std::atan(std::tan(0.5 * in.fov_h) * frame_w / in.width) * 180 / M_PI));
    if (f.overscan > 0) spec.attribute("wavecam.cropped-overscan", f.overscan);  // not wavecam.overscan: none here
    spec.attribute("wavecam.fov-from", in.fov_from);
    spec.attribute("wavecam.depth", opt.depth_meaning == DepthMeaning::Planar ? "planar" : "ray");
    // the channel read as depth, by its full name: a later run of this file reads the same one
    spec.attribute("wavecam.depth-channel", in.depth_channel);
    // the depth channel is copied as the input had it: the scale read back gives the same metres
    spec.attribute("wavecam.depth-scale", with_unit(opt.read.depth_scale, 1.0, "m"));
    std::string wl;
    for (double l : f.colour.sampling.wavelength) wl += (wl.empty() ? "" : ",") + with_unit(l, 1e-9, "nm");
    spec.attribute("wavecam.wavelengths", wl);
    spec.attribute("wavecam.light", f.colour.basis.description());
    spec.attribute("wavecam.method", method_word(opt.method));
    if (opt.method != DiffractMethod::Convolution) {  // what only the scene-sum methods use
        if (opt.method == DiffractMethod::RandomPhase) spec.attribute("wavecam.runs", s.runs);
        spec.attribute("wavecam.seed", std::to_string(s.seed));
        spec.attribute("wavecam.film-subsamples", s.film_subsamples);  // the setting: 0 = enough to resolve the PSF
        spec.attribute("wavecam.jitter", s.jitter ? "true" : "false");
        spec.attribute("wavecam.summation", summation_word(opt.scene_sum.summation));  // the setting, and what it ran
        if (opt.scene_sum.summation == Summation::Auto)
            spec.attribute("wavecam.summation-chosen",
                           detail::auto_choice(s, f.device, f.report.get(), f.camera, f.colour.basis));
        if (opt.method == DiffractMethod::RandomPhase)
            spec.attribute("wavecam.phases", s.coded_phases ? "coded" : "independent");
        spec.attribute("wavecam.device", f.report->ran_on(f.device));  // the job's report
    }
    spec.attribute("wavecam.vignetting", opt.vignetting ? "true" : "false");
    spec.attribute("wavecam.layer", channels.layer);
    if (!in.alpha.empty())
        spec.attribute("wavecam.alpha", std::string(alpha_is_diffracted(in) ? "diffracted as neutral grey light "
                                                                          "(the convolution method's PSFs, no vignetting)"
                                                                        : "uniform, kept") +
                                            (in.premultiplied_on_reading ? "; the input's unassociated colour "
                                                                           "premultiplied by it on reading" : ""));
    if (in.premultiplied_on_reading)  // the output's colour is premultiplied, whatever the input's format said
        for (const char* flag : {"oiio:UnassociatedAlpha", "tiff:UnassociatedAlpha"}) spec.erase_attribute(flag);
    if (opt.read.clamp_negative) spec.attribute("wavecam.negative-clamped", std::to_string(in.clamped) + " values");
    if (!edge.empty()) spec.attribute("wavecam.edge", edge);
    if (!opt.compression.empty()) spec.attribute("compression", opt.compression);
    spec.attribute("wavecam.input-colorspace", f.colour.in_space);
    spec.attribute("wavecam.output-colorspace", f.colour.out_space);
    // the setting (read back as one), and what it did
    spec.attribute("wavecam.out-of-gamut", opt.desaturate_out_of_gamut ? "desaturate" : "keep");
    if (opt.desaturate_out_of_gamut)
        spec.attribute("wavecam.out-of-gamut-mapped", std::to_string(mapped) + " of " +
                                                          std::to_string(size_t(f.out_w) * f.out_h) +
                                                          " pixels desaturated at constant luminance");
    spec.attribute("wavecam.colorconfig", f.colour.config.path());
    spec.attribute("wavecam.fresnel-number", static_cast<float>(fresnel_number(f.aperture.diameter / 2, opt.film_distance,
                                                                               INFINITY, kDesignWavelength)));
    std::ostringstream summary;
    summary << f.colour.sampling.wavelength.size() << " wavelengths"
            << (f.colour.basis.monochrome() ? " (monochrome), " : ", ");
    if (opt.method == DiffractMethod::Convolution) summary << "convolution method";
    else if (opt.method == DiffractMethod::RandomPhase) summary << s.runs << " runs, " << f.terms << " terms";
    else summary << "incoherent sum, " << f.terms << " terms";
    if (in.clamped > 0) summary << ", " << in.clamped << " negative values clamped to 0";
    spec.attribute("wavecam.summary", summary.str());
    return spec;
}

}  // namespace

// The convolution method through the kept plan when it serves this frame, else a new one: the table costs
// about as much as applying it, so a new plan's building is the first 60% of the bar.
Result<bool> DiffractPlan::run_convolution(const DiffractOptions& opt, const ResolvedFrame& f, std::vector<float>& xyz) {
    xyz.resize(3 * size_t(f.out_w) * f.out_h);
    std::shared_ptr<const ConvolutionPlan> plan;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (convolution_ && convolution_->serves(f.convolution)) plan = convolution_;
    }
    const bool reused = plan != nullptr;
    if (!reused) {
        auto made = ConvolutionPlan::create(f.convolution, progress_slice(opt.progress, 0.0, 0.6));
        if (!made.ok()) return Result<bool>::failure(made);
        plan = made.value;
        std::lock_guard<std::mutex> lock(mutex_);
        convolution_ = plan;
    }
    return plan->apply(f.scene(opt.depth_meaning), opt.vignetting, xyz.data(),
                       progress_slice(opt.progress, reused ? 0.0 : 0.6, 1.0));
}

// Alpha is coverage: the share of a pixel's light that the element holds, with its premultiplied
// colour. Diffracted with the colour, each pixel's coverage spreads as its light does. Light
// of every colour takes a slightly different PSF; coverage takes the one neutral grey light
// takes, so that an element diffracted alone and laid --over a grey plate at its depth gives
// what diffracting the whole scene gives. It is the expected (incoherent) PSF whatever the
// method, computed by the convolution method's plan: coverage has no speckle. The luminance Y
// of the film's XYZ is the diffracted coverage (grey light of level a has Y = a in every working
// space), divided by what coverage 1 everywhere gives (no vignetting): whole coverage stays 1.
Result<bool> DiffractPlan::diffract_alpha(const DiffractOptions& opt, const ResolvedFrame& f, std::vector<float>& alpha) {
    const double from = opt.method == DiffractMethod::Convolution ? 0.6 : 0.95;
    ResolvedFrame grey = f;
    DiffractOptions coverage = opt;
    coverage.vignetting = false;
    std::vector<float> xyz[2];
    for (int pass = 0; pass < 2; ++pass) {
        for (size_t p = 0; p < f.in.alpha.size(); ++p)
            std::fill_n(&grey.in.rgb[3 * p], 3, pass == 0 ? f.in.alpha[p] : 1.0f);
        coverage.progress = progress_slice(opt.progress, from + pass * (1 - from) / 2, from + (pass + 1) * (1 - from) / 2);
        if (auto r = run_convolution(coverage, grey, xyz[pass]); !r.ok()) return r;
        keep_data_window(xyz[pass], f.out_w, f.kept);
    }
    // each pixel's coverage is a weighted mean of the input's: within [0, its largest] but for
    // rounding. An input's alpha above 1 (additive elements) stays above 1, as the input had it.
    const float most = *std::max_element(f.in.alpha.begin(), f.in.alpha.end());
    alpha.resize(xyz[0].size() / 3);
    for (size_t p = 0; p < alpha.size(); ++p)
        alpha[p] = std::clamp(xyz[0][3 * p + 1] / xyz[1][3 * p + 1], 0.0f, most);
    return Result<bool>::success(true);
}

bool diffract(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& name, const DiffractOptions& opt,
              int nthreads) {
    DiffractPlan plan(opt);
    auto r = plan.diffract(dst, src, name, nthreads);
    if (!r.ok()) dst.errorfmt("{}", r.field.empty() ? r.error : r.error + " (setting: " + r.field + ")");
    return r.ok();
}

Result<bool> DiffractPlan::diffract(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& name,
                                    int nthreads) {
    if (!detail::view_names(src.spec()).empty())  // stereo: each view with its own depth (multi_view.h)
        return detail::diffract_each_view(dst, src, name,
                                          [this, nthreads](OIIO::ImageBuf& d, const OIIO::ImageBuf& s, const std::string& n) {
                                              return diffract(d, s, n, nthreads);
                                          });
    if (const double aspect = detail::pixel_aspect(src.spec()); aspect != 1.0) {
        // anamorphic: diffracted on square pixels, then back on the file's (pixel_aspect.h)
        using Fail = Result<bool>;
        if (opt_.overscan != 0)
            return Fail::failure(name + ": pixel aspect ratio " + OIIO::Strutil::fmt::format("{:g}", aspect) + " and an overscan setting: expected "
                                 "no overscan setting for non-square pixels (give the file a data window instead)",
                                 ErrorKind::Invalid, "overscan");
        auto channels = find_render_channels(src.spec(), opt_.read);
        if (!channels.ok()) return Fail::failure(name + ": " + channels.error, channels.kind, channels.field);
        auto square = detail::to_square_pixels(src, channels.value, aspect);
        if (!square.ok()) return Fail::failure(name + ": " + square.error);
        OIIO::ImageBuf diffracted;
        if (auto r = diffract(diffracted, square.value, name, nthreads); !r.ok()) return r;
        auto back = detail::to_file_pixels(diffracted, src, aspect);
        if (!back.ok()) return Fail::failure(name + ": " + back.error);
        dst = std::move(back.value);
        return Fail::success(true);
    }
    auto input = load_render(src, name, opt_.read);
    if (!input.ok()) return Result<bool>::failure(input);
    auto frame = detail::resolve_frame(opt_, std::move(input.value), name, nthreads);
    if (!frame.ok()) return Result<bool>::failure(frame);
    return diffract_frame(dst, src, frame.value, name, nthreads, &frame.value.in);
}

Result<JobEstimate> DiffractPlan::estimate(const OIIO::ImageBuf& src, const std::string& name, int nthreads) {
    using R = Result<JobEstimate>;
    auto input = load_render(src, name, opt_.read);
    if (!input.ok()) return R::failure(input);
    auto frame = detail::resolve_frame(opt_, std::move(input.value), name, nthreads);
    if (!frame.ok()) return R::failure(frame);
    const ResolvedFrame& f = frame.value;
    JobEstimate e = detail::job_estimate(opt_, f, nthreads);
    if (e.job.empty())
        e.job = std::to_string(f.in.width) + "x" + std::to_string(f.in.height) + " pixels x " +
                std::to_string(f.colour.sampling.wavelength.size()) + " wavelengths, convolution method";
    double summation = 0;
    e.bytes = job_bytes(opt_, f, summation);
    if (auto r = check_limits(opt_, f, name, nthreads); !r.ok()) e.refusal = r.error;
    return R::success(std::move(e));
}

Result<bool> DiffractPlan::diffract(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const ResolvedFrame& f,
                                    const std::string& name, int nthreads) {
    return diffract_frame(dst, src, f, name, nthreads, nullptr);
}

// Check the frame's limits, run its method, map its colours, write the output.
Result<bool> DiffractPlan::diffract_frame(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const ResolvedFrame& f,
                                          const std::string& name, int nthreads, RenderInput* spent) {
    using Fail = Result<bool>;
    // A stop asked for through the progress callback is a cancellation, whatever failed with it.
    auto stopped = std::make_shared<std::atomic<bool>>(false);
    DiffractOptions opt = opt_;
    if (opt_.progress)
        opt.progress = [stopped, progress = opt_.progress](double f) {
            if (progress(f)) return true;
            *stopped = true;
            return false;
        };
    if (auto r = check_limits(opt, f, name, nthreads); !r.ok()) return r;
    if (opt.on_estimate && opt.method != DiffractMethod::Convolution) opt.on_estimate(detail::job_estimate(opt, f, nthreads));

    std::vector<float> xyz, alpha;
    const bool alpha_pass = alpha_is_diffracted(f.in);
    DiffractOptions image_opt = opt;
    if (alpha_pass) image_opt.progress = progress_slice(opt.progress, 0.0, opt.method == DiffractMethod::Convolution ? 0.6 : 0.95);
    Result<bool> r = opt.method == DiffractMethod::Convolution ? run_convolution(image_opt, f, xyz)
                                                              : run_scene_sum(image_opt, f, xyz);
    if (r.ok() && alpha_pass) r = diffract_alpha(opt, f, alpha);
    if (!r.ok() && (*stopped || r.kind == ErrorKind::Cancelled))
        return Fail::failure(name + ": interrupted", ErrorKind::Cancelled);
    if (!r.ok()) return Fail::failure(name + ": " + r.error);
    const std::string edge = edge_note(f);
    if (spent) {  // (f is *spent's frame: its radiance and depth are not read again)
        std::vector<float>().swap(spent->rgb);
        std::vector<float>().swap(spent->depth);
    }
    keep_data_window(xyz, f.out_w, f.kept);
    if (!alpha_pass && !f.in.alpha.empty()) alpha.assign(size_t(f.kept.npixels()), f.in.alpha.front());
    auto mapped = f.colour.config.output_colour(xyz.data(), xyz.size() / 3, f.colour.out_space, f.colour.in_space,
                                                opt.desaturate_out_of_gamut);
    if (!mapped.ok()) return Fail::failure(mapped);

    // the radiance layer in the output space and its alpha under the input's names, every other channel as it was
    dst.reset(output_spec(src.spec(), f.in.channels, opt, f, mapped.value, edge));
    if (auto w = fill_output(dst, src, f.in.channels, f.overscan, xyz.data(), alpha.data()); !w.ok())
        return Fail::failure(name + ": " + w.error);
    return Fail::success(true);
}

}  // namespace wavecam
