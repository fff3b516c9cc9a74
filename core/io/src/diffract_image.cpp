#include "wavecam/diffract_image.h"

#include <OpenImageIO/imagebufalgo.h>

#include <atomic>
#include <cmath>
#include <sstream>

#include "wavecam/colour_pipeline.h"
#include "wavecam/output_layout.h"
#include "wavecam/pinhole_design.h"
#include "wavecam/source.h"
#include "wavecam/spectral_diffraction.h"
#include "wavecam/term_rate.h"
#include "wavecam/units.h"

namespace wavecam {
namespace {

constexpr double kDesignWavelength = 550e-9;
constexpr const char* kDefaultWorkingSpace = "lin_rec709";

Result<SpectralSampling> sampling_for(const DiffractOptions& opt) {
    return opt.wavelengths.empty() ? visible_sampling(opt.wavelength_count) : explicit_sampling(opt.wavelengths);
}

}  // namespace

double resolved_pinhole(const DiffractOptions& opt) {
    return opt.pinhole > 0 ? opt.pinhole : rayleigh_optimal_diameter(opt.film_distance, kDesignWavelength);
}

Aperture resolved_aperture(const DiffractOptions& opt) {
    Aperture a = opt.aperture;
    a.diameter = resolved_pinhole(opt);
    return a;
}

namespace {
// The input's linear working space: named by the options, else by the file, else Rec.709.
std::string working_space(const DiffractOptions& opt, const ColourConfig& config, const std::string& file_colorspace) {
    return !opt.input_colorspace.empty()                                          ? opt.input_colorspace
           : !file_colorspace.empty() && config.has_colorspace(file_colorspace) ? file_colorspace
                                                                                  : kDefaultWorkingSpace;
}
}  // namespace

Result<SpectralBasis> job_basis(const DiffractOptions& opt, const std::string& file_colorspace) {
    auto config = load_colour_config(opt.colorconfig);
    if (!config.ok()) return Result<SpectralBasis>::failure(config.error);
    auto xyz_to_rgb = config.value.xyz_to_rgb_matrix(working_space(opt, config.value, file_colorspace));
    if (!xyz_to_rgb.ok()) return Result<SpectralBasis>::failure(xyz_to_rgb.error);
    auto sampling = sampling_for(opt);
    if (!sampling.ok()) return Result<SpectralBasis>::failure(sampling.error, ErrorKind::Invalid, "wavelengths");
    return make_spectral_basis(sampling.value, xyz_to_rgb.value, opt.monochrome);
}

double estimate_terms(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
                      DepthMeaning meaning, const SpectralBasis& basis) {
    if (opt.method == DiffractMethod::Fast) return 0;  // PSF grid + FFTs: minutes at most
    DiffractionSettings s = opt.diffraction;
    s.aperture = resolved_aperture(opt);
    s.method = opt.method == DiffractMethod::Incoherent ? CoherenceMethod::Incoherent : CoherenceMethod::RandomPhase;
    s.overscan = opt.overscan;
    const double nearest = nearest_depth(camera, depth.data(), meaning);
    // one propagation per basis sample: monochrome light has three per wavelength, one per
    // channel (spectrum.h), whether asked for or found (wavelengths too close to carry colour)
    double terms = 0;
    for (int k = 0; k < basis.size(); ++k) terms += scene_terms(s, camera, basis.wavelength(k), nearest);
    return terms;
}

double estimate_terms(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
                      DepthMeaning meaning, const std::string& file_colorspace) {
    if (opt.method == DiffractMethod::Fast) return 0;
    auto basis = job_basis(opt, file_colorspace);
    return basis.ok() ? estimate_terms(opt, camera, depth, meaning, basis.value) : 0;
}

double estimate_memory(const DiffractOptions& opt, const PinholeCamera& camera) {
    const double pixels = double(camera.width) * camera.height;
    const double images = pixels * 4 * sizeof(float) * 6;  // source, input arrays, XYZ, output, written copy
    if (opt.method == DiffractMethod::Fast) return images;  // + FastPlan::estimate_bytes, once the frame is known
    const double lambda = 400e-9;  // the shortest wavelength sampled: the densest pinhole grid
    const Aperture ap = resolved_aperture(opt);
    const double samples = estimate_sample_count(ap, sample_pitch(lambda, 1.0));
    const double film = pixels * 9;  // up to 3 x 3 film points per pixel
    return images + samples * 5 * sizeof(float) + film * 3 * sizeof(float) + pixels * sizeof(PointSource);
}

DiffractPlan::DiffractPlan(DiffractOptions options) : opt_(std::move(options)) {}

std::shared_ptr<const FastPlan> DiffractPlan::fast_plan_for(const FastPlanSpec& spec, const ProgressFn& progress,
                                                            bool& reused, std::string& error) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        reused = fast_ && fast_->serves(spec);
        if (reused) return fast_;
    }
    auto plan = FastPlan::create(spec, progress);
    if (!plan.ok()) {
        error = plan.error;
        return nullptr;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    fast_ = plan.value;
    return fast_;
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
    auto input = load_render(src, name, opt.read);
    if (!input.ok()) return Fail::failure(input);
    const RenderInput& in = input.value;

    const PinholeCamera camera = in.camera(opt.film_distance);
    const int o = opt.overscan, out_w = in.width - 2 * o, out_h = in.height - 2 * o;
    if (o < 0 || out_w < 1 || out_h < 1) {
        std::ostringstream m;
        m << name << ": an overscan of " << o << " pixels leaves no image of " << in.width << "x" << in.height
          << "; expected 0 to " << (std::min(in.width, in.height) - 1) / 2 << " pixels";
        return Fail::failure(m.str(), ErrorKind::Invalid, "overscan");
    }

    // Colour: the basis is calibrated against the input's working space as the config defines it.
    auto config = load_colour_config(opt.colorconfig);
    if (!config.ok()) return Fail::failure(config);
    const std::string in_space = working_space(opt, config.value, in.colorspace);
    const std::string out_space = opt.output_colorspace.empty() ? in_space : opt.output_colorspace;
    auto xyz_to_rgb = config.value.xyz_to_rgb_matrix(in_space);
    if (!xyz_to_rgb.ok()) return Fail::failure(xyz_to_rgb);
    auto sampling = sampling_for(opt);
    if (!sampling.ok()) return Fail::failure(sampling.error, ErrorKind::Invalid, "wavelengths");
    auto basis = make_spectral_basis(sampling.value, xyz_to_rgb.value, opt.monochrome);
    if (!basis.ok()) return Fail::failure(basis);

    DiffractionSettings s = opt.diffraction;
    s.aperture = resolved_aperture(opt);
    s.method = opt.method == DiffractMethod::Incoherent ? CoherenceMethod::Incoherent : CoherenceMethod::RandomPhase;
    s.nthreads = nthreads;
    const double terms = estimate_terms(opt, camera, in.depth, opt.depth_meaning, basis.value);
    std::ostringstream job;
    job << in.width << "x" << in.height << " pixels x " << sampling.value.wavelength.size() << " wavelengths x "
        << (s.method == CoherenceMethod::Incoherent ? 1 : s.runs) << " runs";
    if (terms > opt.max_terms) {
        const double rate = measured_term_rate(nthreads);
        std::ostringstream m;
        const double seconds = terms / rate;
        m << name << ": " << job.str() << " = " << terms << " terms, about "
          << (seconds < 5400 ? std::to_string(long(std::ceil(seconds / 60))) + " min"
                             : std::to_string(long(std::round(seconds / 3600))) + " h")
          << " at the " << rate << " terms/s measured here, beyond the max-terms limit of " << opt.max_terms;
        return Fail::failure(m.str(), ErrorKind::TooLarge, "max-terms");
    }
    if (opt.on_estimate && opt.method != DiffractMethod::Fast) opt.on_estimate(job.str(), terms);

    const SpectralScene scene{camera, in.rgb.data(), in.depth.data(), opt.depth_meaning};
    FastPlanSpec fs{camera, o, s.aperture, basis.value, 0.0, opt.fast};
    fs.settings.nthreads = nthreads;
    if (opt.method == DiffractMethod::Fast) {
        auto w = max_inverse_depth(scene);
        if (!w.ok()) return Fail::failure(name + ": " + w.error);
        fs.max_inverse_depth = w.value;
    }
    const double bytes =
        estimate_memory(opt, camera) + (opt.method == DiffractMethod::Fast ? FastPlan::estimate_bytes(fs) : 0.0);
    if (bytes > opt.max_memory) {
        std::ostringstream m;
        m << name << ": " << in.width << "x" << in.height << " pixels need about " << bytes / (1 << 20)
          << " MiB, beyond the max-memory limit of " << opt.max_memory / (1 << 20) << " MiB";
        return Fail::failure(m.str(), ErrorKind::TooLarge, "max-memory");
    }
    std::vector<float> pixels(3 * size_t(out_w) * out_h);
    Result<bool> r = Result<bool>::success(true);
    if (opt.method == DiffractMethod::Fast) {
        std::string error;
        // the table costs about as much as applying it: the first 60% of the bar when built
        bool reused = false;
        auto part = [&opt](double from, double to) -> ProgressFn {
            if (!opt.progress) return {};
            return [&opt, from, to](double f) { return opt.progress(from + (to - from) * f); };
        };
        auto plan = fast_plan_for(fs, part(0.0, 0.6), reused, error);
        r = plan ? plan->apply(scene, opt.vignetting, pixels.data(), part(reused ? 0.0 : 0.6, 1.0))
                 : Result<bool>::failure(error);
    } else {
        // the exact methods light the film within the overscan from every input pixel and the
        // scene beyond the input (frame_margin.h), then crop
        s.overscan = o;
        std::vector<float> full(3 * size_t(in.width) * in.height);
        r = diffract_spectral(scene, basis.value, s.aperture,
                              opt.exact_propagator ? opt.exact_propagator : wave_propagator(s), opt.vignetting,
                              full.data(), opt.progress);
        for (int j = 0; j < out_h; ++j)
            std::copy_n(&full[3 * (size_t(j + o) * in.width + o)], 3 * size_t(out_w), &pixels[3 * size_t(j) * out_w]);
    }
    if (!r.ok() && (*stopped || r.kind == ErrorKind::Cancelled))
        return Fail::failure(name + ": interrupted", ErrorKind::Cancelled);
    if (!r.ok()) return Fail::failure(name + ": " + r.error);
    auto mapped = config.value.output_colour(pixels.data(), pixels.size() / 3, out_space, in_space,
                                             opt.desaturate_out_of_gamut);
    if (!mapped.ok()) return Fail::failure(mapped);

    // Output: float R, G, B in the output space under the input's names, then its alpha and depth
    // unchanged; the input's header less what described the ideal camera (output_layout.h).
    const RenderChannels channels = find_render_channels(src.spec(), opt.read.depth_channel);
    OIIO::ImageSpec spec = output_header(src.spec(), channels);
    spec.width = spec.full_width = out_w;  // the frame without its overscan margin
    spec.height = spec.full_height = out_h;
    spec.x = spec.y = spec.full_x = spec.full_y = 0;
    spec.attribute("oiio:ColorSpace", out_space);
    spec.attribute("wavecam.pinhole", with_unit(s.aperture.diameter, 1e-3, "mm"));
    spec.attribute("wavecam.aperture", s.aperture.name());
    spec.attribute("wavecam.film-distance", with_unit(opt.film_distance, 1e-3, "mm"));
    spec.attribute("wavecam.film-width", with_unit(camera.pixel_pitch() * out_w, 1e-3, "mm"));
    // the output's own field of view: the cropped frame's when the input had an overscan
    spec.attribute("wavecam.fov", static_cast<float>(2 * std::atan(std::tan(0.5 * in.fov_h) * out_w / in.width) * 180 / M_PI));
    if (o > 0) spec.attribute("wavecam.cropped-overscan", o);  // not wavecam.overscan: this frame has none
    spec.attribute("wavecam.fov-from", in.fov_from);
    spec.attribute("wavecam.depth", opt.depth_meaning == DepthMeaning::Planar ? "planar" : "ray");
    std::string wl;
    for (double l : sampling.value.wavelength) wl += (wl.empty() ? "" : ",") + with_unit(l, 1e-9, "nm");
    spec.attribute("wavecam.wavelengths", wl);
    spec.attribute("wavecam.light", basis.value.description());
    spec.attribute("wavecam.method", opt.method == DiffractMethod::Fast    ? "fast"
                                     : opt.method == DiffractMethod::RandomPhase ? "exact"
                                                                           : "incoherent");
    if (opt.method != DiffractMethod::Fast) {  // what only the exact sums use
        if (opt.method == DiffractMethod::RandomPhase) spec.attribute("wavecam.runs", s.runs);
        spec.attribute("wavecam.seed", std::to_string(s.seed));
        spec.attribute("wavecam.film-subsamples", s.film_subsamples);  // the setting: 0 = enough to resolve the PSF
        spec.attribute("wavecam.jitter", s.jitter ? "true" : "false");
    }
    spec.attribute("wavecam.vignetting", opt.vignetting ? "true" : "false");
    spec.attribute("wavecam.input-colorspace", in_space);
    spec.attribute("wavecam.output-colorspace", out_space);
    // the setting (read back as one), and what it did
    spec.attribute("wavecam.out-of-gamut", opt.desaturate_out_of_gamut ? "desaturate" : "keep");
    if (opt.desaturate_out_of_gamut)
        spec.attribute("wavecam.out-of-gamut-mapped", std::to_string(mapped.value) + " of " +
                                                          std::to_string(pixels.size() / 3) +
                                                          " pixels desaturated at constant luminance");
    spec.attribute("wavecam.colorconfig", config.value.path());
    spec.attribute("wavecam.fresnel-number",
                   static_cast<float>(fresnel_number(s.aperture.diameter / 2, opt.film_distance, INFINITY,
                                                     kDesignWavelength)));
    std::ostringstream summary;
    summary << sampling.value.wavelength.size() << " wavelengths" << (basis.value.monochrome() ? " (monochrome), " : ", ");
    if (opt.method == DiffractMethod::Fast) summary << "fast method";
    else if (opt.method == DiffractMethod::RandomPhase) summary << s.runs << " runs, " << terms << " terms";
    else summary << "incoherent sum, " << terms << " terms";
    spec.attribute("wavecam.summary", summary.str());

    dst.reset(spec);
    if (auto f = fill_output(dst, src, channels, o, pixels.data()); !f.ok()) return Fail::failure(name + ": " + f.error);
    return Result<bool>::success(true);
}

}  // namespace wavecam
