#include "wavecam/diffract_image.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>

#include "colour_metadata.h"
#include "pixel_aspect.h"
#include "resolved_frame.h"
#include "wavecam/output_layout.h"
#include "wavecam/pinhole_design.h"
#include "wavecam/run_count.h"
#include "wavecam/source.h"
#include "wavecam/term_rate.h"
#include "wavecam/units.h"

namespace wavecam {
namespace {
using detail::JobColour;
using detail::ResolvedFrame;

constexpr double kDesignWavelength = 550e-9;
constexpr const char* kDefaultWorkingSpace = "lin_rec709";

// The input's working space: the setting, else the header's chromaticities or ACES flag
// (colour_metadata.h), else its oiio:ColorSpace where the config has it, else linear Rec.709.
Result<JobColour> resolve_colour(const DiffractOptions& opt, const FileColour& file) {
    using R = Result<JobColour>;
    JobColour c;
    auto config = load_colour_config(opt.colorconfig);
    if (!config.ok()) return R::failure(config);
    c.config = std::move(config.value);
    auto header = opt.input_colorspace.empty() ? detail::header_colour_space(file, c.config)
                                               : Result<std::string>::success(std::string());
    if (!header.ok()) return R::failure(header);
    c.in_space = !opt.input_colorspace.empty()                                        ? opt.input_colorspace
                 : !header.value.empty()                                            ? header.value
                 : !file.colorspace.empty() && c.config.has_colorspace(file.colorspace) ? file.colorspace
                                                                                      : kDefaultWorkingSpace;
    c.out_space = opt.output_colorspace.empty() ? c.in_space : opt.output_colorspace;
    auto xyz_to_rgb = c.config.xyz_to_rgb_matrix(c.in_space);
    if (!xyz_to_rgb.ok()) return R::failure(xyz_to_rgb);
    auto sampling = opt.wavelengths.empty() ? visible_sampling(opt.wavelength_count) : explicit_sampling(opt.wavelengths);
    if (!sampling.ok()) return R::failure(sampling.error, ErrorKind::Invalid, "wavelengths");
    c.sampling = std::move(sampling.value);
    auto basis = make_spectral_basis(c.sampling, xyz_to_rgb.value, opt.monochrome);
    if (!basis.ok()) return R::failure(basis);
    c.basis = std::move(basis.value);
    return R::success(std::move(c));
}

// The basis's distinct wavelengths (monochrome light has three samples of each).
int wavelength_count(const SpectralBasis& basis) {
    std::vector<double> w;
    for (int k = 0; k < basis.size(); ++k) w.push_back(basis.wavelength(k));
    std::sort(w.begin(), w.end());
    return int(std::unique(w.begin(), w.end()) - w.begin());
}

double longest_wavelength(const SpectralBasis& basis) {
    double longest = 0;
    for (int k = 0; k < basis.size(); ++k) longest = std::max(longest, basis.wavelength(k));
    return longest;
}

// The random-phase run count this frame's PSF asks (run_count.h), for settings `s` already
// holding the aperture and nearest source.
RunCount frame_run_count(const ExactSettings& s, const PinholeCamera& camera, const SpectralBasis& basis) {
    return runs_for_convergence(camera, s.aperture, longest_wavelength(basis), wavelength_count(basis), s.nearest_depth);
}

// The job's settings for the exact methods, `auto` summation decided once for the whole job
// (chosen_summation) at the middle of its wavelengths: both ways' work scales alike with the
// wavelength, and every wavelength then runs the same way.
ExactSettings exact_settings(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
                             const SpectralBasis& basis, int nthreads = 0, const ComputeDevice& device = {}) {
    ExactSettings s = opt.exact;
    s.device = device;  // what auto may choose depends on it
    s.aperture = resolved_aperture(opt);
    s.method = opt.method == DiffractMethod::Incoherent ? CoherenceMethod::Incoherent : CoherenceMethod::RandomPhase;
    s.overscan = opt.overscan;
    s.nthreads = nthreads;
    s.nearest_depth = nearest_depth(camera, depth.data(), opt.depth_meaning);
    if (opt.runs_from_psf && s.method == CoherenceMethod::RandomPhase && basis.size() > 0)
        s.runs = frame_run_count(s, camera, basis).runs;
    if (basis.size() > 0) s.summation = chosen_summation(s, camera, basis.wavelength(basis.size() / 2));
    return s;
}

double exact_terms(const ExactSettings& s, const PinholeCamera& camera, const SpectralBasis& basis) {
    // one propagation per basis sample: monochrome light has three per wavelength, one per
    // channel (spectrum.h), whether asked for or found (wavelengths too close to carry colour)
    double terms = 0;
    for (int k = 0; k < basis.size(); ++k) terms += scene_terms(s, camera, basis.wavelength(k));
    return terms;
}

// What `auto` chose for the job's sums: psf, else the evaluators that ran on the job's device
// (the header's), or, before they ran, those the estimate gives each sum (the job line's).
std::string auto_choice(const ExactSettings& s, const PinholeCamera& camera, const SpectralBasis& basis) {
    if (s.summation == Summation::Psf) return "psf";
    EvaluatorSet e = evaluators_run(s.device);
    if (e.words().empty())
        for (int k = 0; k < basis.size(); ++k) e.add(scene_evaluators(s, camera, basis.wavelength(k)));
    return e.words();
}

// What the camera's physics and sampling make sense for, checked before any work (docs/errors.md):
// every field angle within kMaxFieldAngle of the axis (a wider
// frame's corners see the pinhole edge-on and its pixels' footprints grow without bound); a
// pinhole at least a wavelength across (scalar diffraction through a smaller hole means
// nothing) and no wider than the film; no source nearer than kNearestDiameters pinhole
// diameters (the pinhole then images nothing: its blur disc is most of the frame).
constexpr double kMaxFieldAngleDeg = 80;
constexpr double kMinFovDeg = 0.01;
constexpr double kNearestDiameters = 10;

std::string window_text(const OIIO::ROI& r) {
    return "(" + std::to_string(r.xbegin) + ", " + std::to_string(r.ybegin) + ")-(" + std::to_string(r.xend - 1) +
           ", " + std::to_string(r.yend - 1) + ")";
}

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

std::string g6(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

Result<bool> check_camera(const ResolvedFrame& f, const std::string& name, const DepthMeaning meaning) {
    using R = Result<bool>;
    const RenderInput& in = f.in;
    const PinholeCamera& c = f.camera;
    const double fov_deg = in.fov_h * 180 / M_PI;
    const double aspect = double(in.height) / in.width;
    const double widest_fov = 2 * std::atan(std::tan(kMaxFieldAngleDeg * M_PI / 180) / std::sqrt(1 + aspect * aspect));
    if (!(fov_deg >= kMinFovDeg) || !(in.fov_h <= widest_fov)) {
        double u, v;
        c.tangent(0, 0, u, v);
        const double corner = std::atan(std::sqrt(u * u + v * v)) * 180 / M_PI;
        std::ostringstream m;
        m << name << ": a field of view of " << fov_deg << " degrees (from " << in.fov_from << ") ";
        if (!(fov_deg >= kMinFovDeg)) m << "is too narrow to image";
        else m << "puts the " << in.width << "x" << in.height << " frame's corners " << corner << " degrees off axis";
        m << "; expected " << kMinFovDeg << " to " << widest_fov * 180 / M_PI
          << " degrees across this frame (corners within " << kMaxFieldAngleDeg << " degrees of the axis)";
        return R::failure(m.str(), ErrorKind::Invalid, "fov");
    }
    const double d = f.aperture.diameter, film = c.pixel_pitch() * in.width;
    const std::vector<double>& wl = f.colour.sampling.wavelength;
    const double longest = wl.empty() ? 700e-9 : *std::max_element(wl.begin(), wl.end());
    if (!(d >= longest) || !(d <= film)) {
        std::ostringstream m;
        m << name << ": a pinhole of " << with_unit(d, 1e-3, "mm") << " is "
          << (d >= longest ? "wider than the film (" + with_unit(film, 1e-3, "mm") + " across at a film distance of " +
                                 with_unit(c.film_distance, 1e-3, "mm") + " and a field of view of " + g6(fov_deg) +
                                 " degrees)"
                           : "smaller than the wavelength of " + with_unit(longest, 1e-9, "nm"))
          << "; expected a pinhole from " << with_unit(longest, 1e-9, "nm") << " to " << with_unit(film, 1e-3, "mm");
        return R::failure(m.str(), ErrorKind::Invalid, "pinhole");
    }
    const double nearest = kNearestDiameters * d;
    for (int j = 0; j < c.height; ++j)
        for (int i = 0; i < c.width; ++i) {
            const double z = in.depth[size_t(j) * c.width + i];
            if (z >= kInfiniteDepth || c.planar_depth(i, j, z, meaning) >= nearest) continue;
            std::ostringstream m;
            m << name << ": channel '" << in.depth_channel << "' at pixel (" << i << ", " << j << ") is " << z
              << ", nearer than a pinhole of " << with_unit(d, 1e-3, "mm") << " can image; expected a distance of "
              << nearest << " m or more (" << kNearestDiameters << " pinhole diameters"
              << (meaning == DepthMeaning::Ray ? ", along the view axis" : "") << "), or inf for sky";
            return R::failure(m.str());
        }
    return R::success(true);
}

}  // namespace

const char* method_word(DiffractMethod m) {
    return m == DiffractMethod::Convolution ? "convolution" : m == DiffractMethod::RandomPhase ? "random-phase" : "incoherent";
}

Aperture resolved_aperture(const DiffractOptions& opt) {
    Aperture a = opt.aperture;
    a.diameter = opt.pinhole > 0 ? opt.pinhole : rayleigh_optimal_diameter(opt.film_distance, kDesignWavelength);
    return a;
}

double estimate_terms(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
                      const FileColour& file_colour) {
    if (opt.method == DiffractMethod::Convolution) return 0;  // PSF grid + FFTs: minutes at most
    auto colour = resolve_colour(opt, file_colour);
    if (!colour.ok()) return 0;
    return exact_terms(exact_settings(opt, camera, depth, colour.value.basis), camera, colour.value.basis);
}

int job_runs(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
             const FileColour& file_colour) {
    if (opt.method != DiffractMethod::RandomPhase) return opt.method == DiffractMethod::Incoherent ? 1 : 0;
    auto colour = resolve_colour(opt, file_colour);
    if (!colour.ok()) return 0;
    return exact_settings(opt, camera, depth, colour.value.basis).runs;
}

double estimate_memory(const DiffractOptions& opt, const PinholeCamera& camera) {
    const double pixels = double(camera.width) * camera.height;
    const double images = pixels * 4 * sizeof(float) * 4;  // source, its plain arrays, XYZ, output
    if (opt.method == DiffractMethod::Convolution) return images;  // + ConvolutionPlan::estimate_bytes, once the frame is known
    const double lambda = 400e-9;  // the shortest wavelength sampled: the densest pinhole grid
    const Aperture ap = resolved_aperture(opt);
    const double samples = estimate_sample_count(ap, sample_pitch(lambda, 1.0));
    const double film = pixels * 9;  // up to 3 x 3 film points per pixel
    return images + samples * 5 * sizeof(float) + film * 3 * sizeof(float) + pixels * sizeof(PointSource);
}

DiffractPlan::DiffractPlan(DiffractOptions options) : opt_(std::move(options)) {}

Result<ResolvedFrame> detail::resolve_frame(const DiffractOptions& opt, RenderInput input, const std::string& name,
                                            int nthreads) {
    using R = Result<ResolvedFrame>;
    ResolvedFrame f;
    f.in = std::move(input);
    const RenderInput& in = f.in;
    f.camera = in.camera(opt.film_distance);
    const int o = f.overscan = opt.overscan;
    f.out_w = in.width - 2 * o;
    f.out_h = in.height - 2 * o;
    if (o < 0 || f.out_w < 1 || f.out_h < 1) {
        std::ostringstream m;
        m << name << ": an overscan of " << o << " pixels leaves no image of " << in.width << "x" << in.height
          << "; expected 0 to " << (std::min(in.width, in.height) - 1) / 2 << " pixels";
        return R::failure(m.str(), ErrorKind::Invalid, "overscan");
    }
    const FrameWindows& w = in.windows;
    if (w.declared && o != 0)
        return R::failure(name + ": the file declares its own windows (data " + window_text(w.data) + ", display " +
                              window_text(w.display) + "), which say what is overscan; expected no overscan setting",
                          ErrorKind::Invalid, "overscan");
    f.kept = w.declared ? OIIO::ROI(w.data.xbegin - in.x0, w.data.xend - in.x0, w.data.ybegin - in.y0,
                                    w.data.yend - in.y0)
                        : OIIO::ROI(0, f.out_w, 0, f.out_h);
    auto colour = resolve_colour(opt, in.colour);
    if (!colour.ok()) return R::failure(name + ": " + colour.error, colour.kind, colour.field);
    f.colour = std::move(colour.value);
    f.aperture = resolved_aperture(opt);
    if (auto c = check_camera(f, name, opt.depth_meaning); !c.ok()) return R::failure(c);
    // the convolution method's plan: its image, or any method's alpha (diffract_alpha)
    f.convolution = {f.camera, o, f.aperture, f.colour.basis,
                     1.0 / nearest_depth(f.camera, in.depth.data(), opt.depth_meaning), opt.convolution};
    f.convolution.settings.nthreads = nthreads;
    if (opt.method == DiffractMethod::Convolution) return R::success(std::move(f));
    // the job's device (compute_device.h): `gpu` runs every sum there or is refused here, `auto`
    // says why it runs on the CPU
    Device setting = opt.device;
    std::string on_cpu;
    if (setting != Device::Cpu && opt.exact.summation == Summation::Nufft) {
        if (setting == Device::Gpu)
            return R::failure(name + ": " + nufft_on_gpu(setting), ErrorKind::Invalid, "summation");
        setting = Device::Cpu;
        on_cpu = "not used: the nufft summation has no GPU evaluator";
    }
    const ComputeDevice device = ComputeDevice::create(setting);
    if (!device.ok()) return R::failure(name + ": device gpu: " + device.error(), ErrorKind::Failed, "device");
    if (setting == Device::Auto && !device.gpu()) on_cpu = "none usable: " + device.error();
    f.exact = exact_settings(opt, f.camera, in.depth, f.colour.basis, nthreads, device);
    f.terms = exact_terms(f.exact, f.camera, f.colour.basis);
    std::ostringstream job;
    job << in.width << "x" << in.height << " pixels x " << f.colour.sampling.wavelength.size() << " wavelengths x "
        << (f.exact.method == CoherenceMethod::Incoherent ? 1 : f.exact.runs) << " runs";
    if (opt.runs_from_psf && f.exact.method == CoherenceMethod::RandomPhase) {
        // the count and why: the PSF's area, and the noise where the price caps the count
        const RunCount rc = frame_run_count(f.exact, f.camera, f.colour.basis);
        job << " (for a PSF of about " << long(std::lround(rc.psf_pixels)) << " pixels: ";
        if (rc.capped) job << "at most " << kMaxRuns << ", expect about " << std::lround(1000 * rc.expected_noise) / 10.0
                           << "% noise per channel; more with the runs setting)";
        else job << "noise within " << 100 * kRunNoiseGoal << "% per channel)";
    }
    job << ", " << summation_word(opt.exact.summation) << " summation";
    if (opt.exact.summation == Summation::Auto) job << " (" << auto_choice(f.exact, f.camera, f.colour.basis) << ")";
    if (device.gpu()) job << " on " << device.description();
    if (!on_cpu.empty()) job << " (GPU: " << on_cpu << "; on the CPU)";
    f.job = job.str();
    return R::success(std::move(f));
}

namespace {

// Coverage that varies over the frame is diffracted; an alpha of 1 (or 0) everywhere stays so.
bool alpha_is_diffracted(const RenderInput& in) {
    if (in.alpha.empty()) return false;
    const auto [lo, hi] = std::minmax_element(in.alpha.begin(), in.alpha.end());
    return !(*lo == *hi && (*lo == 0.0f || *lo == 1.0f));
}

// The job's terms and bytes against the max-terms and max-memory limits.
Result<bool> check_limits(const DiffractOptions& opt, const ResolvedFrame& f, const std::string& name,
                          int nthreads) {
    // (an estimate that is not a number, from settings beyond any sense, is refused too)
    if (!(f.terms <= opt.max_terms)) {
        const double rate = measured_term_rate(nthreads);
        std::ostringstream m;
        const double seconds = f.terms / rate;
        m << name << ": " << f.job << " = " << f.terms << " terms, about "
          << (seconds < 5400 ? std::to_string(long(std::ceil(seconds / 60))) + " min"
                             : std::to_string(long(std::round(seconds / 3600))) + " h")
          << " at the " << rate << " terms/s measured here, beyond the max-terms limit of " << opt.max_terms;
        return Result<bool>::failure(m.str(), ErrorKind::TooLarge, "max-terms");
    }
    double summation = 0;  // the psf summation's kernels: the largest wavelength's (one at a time)
    if (opt.method != DiffractMethod::Convolution)
        for (int k = 0; k < f.colour.basis.size(); ++k)
            summation = std::max(summation, scene_summation_bytes(f.exact, f.camera, f.colour.basis.wavelength(k)));
    const bool table = opt.method == DiffractMethod::Convolution || alpha_is_diffracted(f.in);
    const double bytes = estimate_memory(opt, f.camera) + summation +
                         (table ? ConvolutionPlan::estimate_bytes(f.convolution) : 0.0);
    if (!(bytes <= opt.max_memory)) {
        std::ostringstream m;
        m << name << ": " << f.in.width << "x" << f.in.height << " pixels need about " << bytes / (1 << 20)
          << " MiB";
        if (summation > 0) m << " (" << summation / (1 << 20) << " MiB of them the psf summation's kernels)";
        m << ", beyond the max-memory limit of " << opt.max_memory / (1 << 20) << " MiB";
        return Result<bool>::failure(m.str(), ErrorKind::TooLarge, "max-memory");
    }
    return Result<bool>::success(true);
}

// The exact sums light the film within the overscan from every input pixel and the scene beyond
// the input (frame_margin.h); the output frame is then moved to the front of the same buffer.
Result<bool> run_exact(const DiffractOptions& opt, const ResolvedFrame& f, std::vector<float>& xyz) {
    const int width = f.in.width, o = f.overscan;
    xyz.assign(3 * size_t(width) * f.in.height, 0.0f);
    auto r = diffract_spectral(f.scene(opt.depth_meaning), f.colour.basis, f.aperture,
                               opt.exact_propagator ? opt.exact_propagator : wave_propagator(f.exact), opt.vignetting,
                               xyz.data(), opt.progress);
    if (!r.ok()) return r;
    if (o > 0)  // each row moves to a place before its own: a forward copy in place
        for (int j = 0; j < f.out_h; ++j) {
            const float* row = &xyz[3 * (size_t(j + o) * width + o)];
            std::copy(row, row + 3 * size_t(f.out_w), &xyz[3 * size_t(j) * f.out_w]);
        }
    xyz.resize(3 * size_t(f.out_w) * f.out_h);
    return r;
}

// The output's header: the input's less what described the ideal camera (output_layout.h), the
// frame without its overscan, and every parameter of this run.
OIIO::ImageSpec output_spec(const OIIO::ImageSpec& input, const RenderChannels& channels, const DiffractOptions& opt,
                            const ResolvedFrame& f, size_t mapped) {
    const RenderInput& in = f.in;
    const ExactSettings& s = f.exact;
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
    // the depth channel is copied as the input had it: the scale read back gives the same metres
    spec.attribute("wavecam.depth-scale", with_unit(opt.read.depth_scale, 1.0, "m"));
    std::string wl;
    for (double l : f.colour.sampling.wavelength) wl += (wl.empty() ? "" : ",") + with_unit(l, 1e-9, "nm");
    spec.attribute("wavecam.wavelengths", wl);
    spec.attribute("wavecam.light", f.colour.basis.description());
    spec.attribute("wavecam.method", method_word(opt.method));
    if (opt.method != DiffractMethod::Convolution) {  // what only the exact sums use
        if (opt.method == DiffractMethod::RandomPhase) spec.attribute("wavecam.runs", s.runs);
        spec.attribute("wavecam.seed", std::to_string(s.seed));
        spec.attribute("wavecam.film-subsamples", s.film_subsamples);  // the setting: 0 = enough to resolve the PSF
        spec.attribute("wavecam.jitter", s.jitter ? "true" : "false");
        spec.attribute("wavecam.summation", summation_word(opt.exact.summation));  // the setting, and what it ran
        if (opt.exact.summation == Summation::Auto)
            spec.attribute("wavecam.summation-chosen", auto_choice(s, f.camera, f.colour.basis));
        if (opt.method == DiffractMethod::RandomPhase)
            spec.attribute("wavecam.phases", s.coded_phases ? "coded" : "independent");
        spec.attribute("wavecam.device", s.device.ran_on());
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
        auto made = ConvolutionPlan::create(f.convolution, progress_part(opt.progress, 0.0, 0.6));
        if (!made.ok()) return Result<bool>::failure(made);
        plan = made.value;
        std::lock_guard<std::mutex> lock(mutex_);
        convolution_ = plan;
    }
    return plan->apply(f.scene(opt.depth_meaning), opt.vignetting, xyz.data(),
                       progress_part(opt.progress, reused ? 0.0 : 0.6, 1.0));
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
        coverage.progress = progress_part(opt.progress, from + pass * (1 - from) / 2, from + (pass + 1) * (1 - from) / 2);
        if (auto r = run_convolution(coverage, grey, xyz[pass]); !r.ok()) return r;
        keep_data_window(xyz[pass], f.out_w, f.kept);
    }
    alpha.resize(xyz[0].size() / 3);
    for (size_t p = 0; p < alpha.size(); ++p)
        alpha[p] = std::clamp(xyz[0][3 * p + 1] / xyz[1][3 * p + 1], 0.0f, 1.0f);
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
    if (const double aspect = detail::pixel_aspect(src.spec()); aspect != 1.0) {
        // anamorphic: diffracted on square pixels, then back on the file's (pixel_aspect.h)
        using Fail = Result<bool>;
        if (opt_.overscan != 0)
            return Fail::failure(name + ": pixel aspect ratio " + g6(aspect) + " and an overscan setting: expected "
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
    return diffract(dst, src, frame.value, name, nthreads);
}

// Check the frame's limits, run its method, map its colours, write the output.
Result<bool> DiffractPlan::diffract(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const ResolvedFrame& f,
                                    const std::string& name, int nthreads) {
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
    if (opt.on_estimate && opt.method != DiffractMethod::Convolution) opt.on_estimate(f.job, f.terms);

    std::vector<float> xyz, alpha;
    const bool alpha_pass = alpha_is_diffracted(f.in);
    DiffractOptions image_opt = opt;
    if (alpha_pass) image_opt.progress = progress_part(opt.progress, 0.0, opt.method == DiffractMethod::Convolution ? 0.6 : 0.95);
    Result<bool> r = opt.method == DiffractMethod::Convolution ? run_convolution(image_opt, f, xyz)
                                                              : run_exact(image_opt, f, xyz);
    if (r.ok() && alpha_pass) r = diffract_alpha(opt, f, alpha);
    if (!r.ok() && (*stopped || r.kind == ErrorKind::Cancelled))
        return Fail::failure(name + ": interrupted", ErrorKind::Cancelled);
    if (!r.ok()) return Fail::failure(name + ": " + r.error);
    keep_data_window(xyz, f.out_w, f.kept);
    if (!alpha_pass && !f.in.alpha.empty()) alpha.assign(size_t(f.kept.npixels()), f.in.alpha.front());
    auto mapped = f.colour.config.output_colour(xyz.data(), xyz.size() / 3, f.colour.out_space, f.colour.in_space,
                                                opt.desaturate_out_of_gamut);
    if (!mapped.ok()) return Fail::failure(mapped);

    // float R, G, B in the output space under the input's names, then its alpha and depth unchanged
    auto channels = find_render_channels(src.spec(), opt.read);
    if (!channels.ok()) return Fail::failure(name + ": " + channels.error, channels.kind, channels.field);
    dst.reset(output_spec(src.spec(), channels.value, opt, f, mapped.value));
    if (auto w = fill_output(dst, src, channels.value, f.overscan, xyz.data(), alpha.data()); !w.ok())
        return Fail::failure(name + ": " + w.error);
    return Fail::success(true);
}

}  // namespace wavecam
