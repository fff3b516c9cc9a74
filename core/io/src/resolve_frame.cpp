// A frame resolved before any work (resolved_frame.h): its camera, colours, method settings,
// device and job line, checked against what the optics make sense for; and the estimates the
// fronts make from the same settings.
#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include <OpenImageIO/strutil.h>

#include "colour_metadata.h"
#include "resolved_frame.h"
#include "wavecam/pinhole_design.h"
#include "wavecam/run_count.h"
#include "wavecam/source.h"
#include "wavecam/units.h"

namespace wavecam {
namespace {
using detail::JobColour;
using detail::ResolvedFrame;
using detail::kDesignWavelength;

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
RunCount frame_run_count(const SceneSumSettings& s, const PinholeCamera& camera, const SpectralBasis& basis) {
    return runs_for_convergence(camera, s.aperture, longest_wavelength(basis), wavelength_count(basis), s.nearest_depth);
}

// The job's settings for the scene-sum methods with the job's one decision (decide_summation):
// the kernel summation or the point sums at the middle of its wavelengths (both ways' work scales alike with the
// wavelength, and every wavelength then runs the same way), and each point sum's evaluator at
// each wavelength, which the sums then follow.
SceneSumSettings scene_sum_settings(const DiffractOptions& opt, const PinholeCamera& camera,
                                    const std::vector<float>& depth, const SpectralBasis& basis,
                                    const ComputeDevice& device, int nthreads = 0) {
    SceneSumSettings s = opt.scene_sum;
    s.aperture = resolved_aperture(opt);
    s.method = opt.method == DiffractMethod::Incoherent ? CoherenceMethod::Incoherent : CoherenceMethod::RandomPhase;
    s.overscan = opt.overscan;
    s.nthreads = nthreads;
    s.nearest_depth = nearest_depth(camera, depth.data(), opt.depth_meaning);
    if (opt.runs_from_psf && s.method == CoherenceMethod::RandomPhase && basis.size() > 0)
        s.runs = frame_run_count(s, camera, basis).runs;
    // the job's one decision: the kernel summation or the point sums, and each sum's evaluator at each wavelength
    std::vector<double> wavelengths;
    for (int k = 0; k < basis.size(); ++k) wavelengths.push_back(basis.wavelength(k));
    // (what auto may choose depends on the device)
    auto decision = std::make_shared<SummationDecision>(decide_summation(s, device, camera, wavelengths));
    s.summation = decision->summation;
    s.decision = std::move(decision);
    return s;
}

double scene_sum_terms(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& camera,
                       const SpectralBasis& basis) {
    // one propagation per basis sample: monochrome light has three per wavelength, one per
    // channel (spectrum.h), whether asked for or found (wavelengths too close to carry colour)
    double terms = 0;
    for (int k = 0; k < basis.size(); ++k) terms += scene_terms(s, device, camera, basis.wavelength(k));
    return terms;
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

// What `auto` chose for the job's sums: kernel, else the evaluators that ran, from the job's report
// (the header's), or, before they ran, those the decision gives each sum (the job line's).
std::string detail::auto_choice(const SceneSumSettings& s, const ComputeDevice& device, const SumReport* report,
                                const PinholeCamera& camera, const SpectralBasis& basis) {
    if (s.summation == Summation::Kernel) return "kernel";
    EvaluatorSet e = report ? report->evaluators() : EvaluatorSet{};
    // (before they ran: the job's decision, which scene_evaluators reads where it holds one)
    if (e.words().empty())
        for (int k = 0; k < basis.size(); ++k) e.add(scene_evaluators(s, device, camera, basis.wavelength(k)));
    return e.words();
}

std::string detail::decision_text(const SceneSumSettings& s) {
    const std::string device = s.decision && s.decision->gpu ? " on gpu" : " on cpu";
    if (s.summation == Summation::Kernel || !s.decision) return std::string(summation_word(s.summation)) + device;
    const SummationDecision& d = *s.decision;
    std::string text;
    for (const SummationDecision::AtWavelength& c : d.choices)
        text += (text.empty() ? "" : ", ") + std::to_string(std::lround(c.wavelength * 1e9)) + "nm " +
                evaluator_word(c.to_pinhole.evaluator) + "/" + evaluator_word(c.to_film.evaluator);
    return text + device;
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
    const ComputeDevice cpu;  // (estimated as on the CPU)
    return scene_sum_terms(scene_sum_settings(opt, camera, depth, colour.value.basis, cpu), cpu, camera,
                           colour.value.basis);
}

int job_runs(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
             const FileColour& file_colour) {
    if (opt.method != DiffractMethod::RandomPhase) return opt.method == DiffractMethod::Incoherent ? 1 : 0;
    auto colour = resolve_colour(opt, file_colour);
    if (!colour.ok()) return 0;
    return scene_sum_settings(opt, camera, depth, colour.value.basis, ComputeDevice{}).runs;
}

double estimate_memory(const DiffractOptions& opt, const PinholeCamera& camera) {
    const double pixels = double(camera.width) * camera.height;
    const double images = pixels * 4 * sizeof(float) * 4;  // source, its plain arrays, XYZ, output
    // The convolution method's peak holds three of them (the plain arrays are freed before the
    // output is made: 11 floats a pixel, measured 46-47 bytes at 4K with either evaluation), plus
    // ConvolutionPlan::estimate_bytes once the frame is known
    if (opt.method == DiffractMethod::Convolution) return pixels * 11 * sizeof(float);
    const double lambda = 400e-9;  // the shortest wavelength sampled: the densest pinhole grid
    const Aperture ap = resolved_aperture(opt);
    const double samples = estimate_sample_count(ap, sample_pitch(lambda, 1.0));
    const double film = pixels * 9;  // up to 3 x 3 film points per pixel
    return images + samples * 5 * sizeof(float) + film * 3 * sizeof(float) + pixels * sizeof(PointSource);
}

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
    const DeviceChoice chosen = choose_device(opt.scene_sum.summation, opt.device);
    if (!chosen.refusal.empty()) return R::failure(name + ": " + chosen.refusal, ErrorKind::Invalid, "summation");
    const Device setting = chosen.open;
    std::string on_cpu = chosen.on_cpu;
    const ComputeDevice device = ComputeDevice::create(setting);
    if (!device.ok()) return R::failure(name + ": device gpu: " + device.error(), ErrorKind::Failed, "device");
    if (setting == Device::Auto && !device.gpu()) on_cpu = "none usable: " + device.error();
    f.device = device;
    f.scene_sum = scene_sum_settings(opt, f.camera, in.depth, f.colour.basis, device, nthreads);
    f.terms = scene_sum_terms(f.scene_sum, device, f.camera, f.colour.basis);
    std::ostringstream job;
    job << in.width << "x" << in.height << " pixels x " << f.colour.sampling.wavelength.size() << " wavelengths x "
        << (f.scene_sum.method == CoherenceMethod::Incoherent ? 1 : f.scene_sum.runs) << " runs";
    if (opt.runs_from_psf && f.scene_sum.method == CoherenceMethod::RandomPhase) {
        // the count and why: the PSF's area, and the noise where the price caps the count
        const RunCount rc = frame_run_count(f.scene_sum, f.camera, f.colour.basis);
        job << " (for a PSF of about " << long(std::lround(rc.psf_pixels)) << " pixels: ";
        if (rc.capped) job << "at most " << kMaxRuns << ", expect about " << std::lround(1000 * rc.expected_noise) / 10.0
                           << "% noise per channel; more with the runs setting)";
        else job << "noise within " << 100 * kRunNoiseGoal << "% per channel)";
    }
    job << ", " << summation_word(opt.scene_sum.summation) << " summation";
    if (opt.scene_sum.summation == Summation::Auto && f.colour.basis.size() > 0) {
        // what ran, and why at the middle wavelength, where the job weighed the kernel summation (the chooser's reason)
        SceneSumSettings asked = f.scene_sum;
        asked.summation = Summation::Auto;
        const double middle = f.colour.basis.wavelength(f.colour.basis.size() / 2);
        job << " (" << auto_choice(f.scene_sum, device, nullptr, f.camera, f.colour.basis) << "; at "
            << std::lround(middle * 1e9) << " nm, " << estimate_summation(asked, device, f.camera, middle).reason << ")";
    }
    if (device.gpu()) job << " on " << device.description();
    if (!on_cpu.empty()) job << " (GPU: " << on_cpu << "; on the CPU)";
    f.job = job.str();
    return R::success(std::move(f));
}

}  // namespace wavecam
