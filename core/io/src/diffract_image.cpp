#include "wavecam/diffract_image.h"

#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <sstream>

#include "wavecam/colour_pipeline.h"
#include "wavecam/pinhole_design.h"
#include "wavecam/source.h"
#include "wavecam/spectral_diffraction.h"

namespace wavecam {
namespace {

constexpr double kDesignWavelength = 550e-9;
constexpr const char* kDefaultWorkingSpace = "lin_rec709";

std::string with_unit(double v, double scale, const char* unit) {
    std::ostringstream s;
    s << v / scale << unit;
    return s.str();
}

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

double estimate_terms(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
                      DepthMeaning meaning) {
    if (opt.method == DiffractMethod::Fast) return 0;  // PSF grid + FFTs: minutes at most
    DiffractionSettings s = opt.diffraction;
    s.aperture = resolved_aperture(opt);
    s.method = opt.method == DiffractMethod::Incoherent ? CoherenceMethod::Incoherent : CoherenceMethod::RandomPhase;
    auto sampling = sampling_for(opt);
    if (!sampling.ok()) return 0;
    const double nearest = nearest_depth(camera, depth.data(), meaning);
    double terms = 0;
    for (double lambda : sampling.value.wavelength) terms += scene_terms(s, camera, lambda, nearest);
    // monochrome light diffracts each channel on its own (spectrum.h)
    return opt.monochrome || sampling.value.wavelength.size() < 3 ? 3 * terms : terms;
}

double estimate_memory(const DiffractOptions& opt, const PinholeCamera& camera) {
    const double pixels = double(camera.width) * camera.height;
    const double images = pixels * 4 * sizeof(float) * 6;  // source, input arrays, XYZ, output, written copy
    if (opt.method == DiffractMethod::Fast) {
        // worst case: 16 depth layers x the field anchors x 9 kernels of 65 x 65, plus tiles
        const double anchors = 25, side = 2.0 * std::max(1, opt.fast.max_radius) + 1;
        return images + 16 * anchors * 9 * side * side * sizeof(float) + 2 * 64.0 * (1 << 20);
    }
    const double lambda = 400e-9;  // the shortest wavelength sampled: the densest pinhole grid
    const Aperture ap = resolved_aperture(opt);
    const double samples = estimate_sample_count(ap, sample_pitch(lambda, 1.0));
    const double film = pixels * 9;  // up to 3 x 3 film points per pixel
    return images + samples * 5 * sizeof(float) + film * 3 * sizeof(float) + pixels * sizeof(PointSource);
}

bool diffract(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& name, const DiffractOptions& opt,
              int nthreads) {
    auto fail = [&dst](const std::string& m) {
        dst.errorfmt("{}", m);
        return false;
    };
    auto input = load_render(src, name, opt.read);
    if (!input.ok()) return fail(input.error);
    const RenderInput& in = input.value;

    PinholeCamera camera;
    camera.width = in.width;
    camera.height = in.height;
    camera.fov_h = in.fov_h;
    camera.film_distance = opt.film_distance;
    if (!(opt.film_distance > 0)) return fail("--film-distance: expected a distance > 0");
    if (opt.pinhole < 0) return fail("--pinhole: expected a diameter > 0");

    // Colour: the basis is calibrated against the input's working space as the config defines it.
    auto config = load_colour_config(opt.colorconfig);
    if (!config.ok()) return fail(config.error);
    const std::string in_space = !opt.input_colorspace.empty() ? opt.input_colorspace
                                 : !in.colorspace.empty() && config.value.has_colorspace(in.colorspace)
                                     ? in.colorspace
                                     : kDefaultWorkingSpace;
    const std::string out_space = opt.output_colorspace.empty() ? in_space : opt.output_colorspace;
    auto xyz_to_rgb = config.value.xyz_to_rgb_matrix(in_space);
    if (!xyz_to_rgb.ok()) return fail(xyz_to_rgb.error);
    auto sampling = sampling_for(opt);
    if (!sampling.ok()) return fail("--" + sampling.error);
    auto basis = make_spectral_basis(sampling.value, xyz_to_rgb.value, opt.monochrome);
    if (!basis.ok()) return fail("--" + basis.error);

    DiffractionSettings s = opt.diffraction;
    s.aperture = resolved_aperture(opt);
    s.method = opt.method == DiffractMethod::Incoherent ? CoherenceMethod::Incoherent : CoherenceMethod::RandomPhase;
    s.nthreads = nthreads;
    const double terms = estimate_terms(opt, camera, in.depth, opt.depth_meaning);
    if (terms > opt.max_terms) {
        std::ostringstream m;
        m << name << ": " << in.width << "x" << in.height << " pixels x " << sampling.value.wavelength.size()
          << " wavelengths x " << s.runs << " runs = " << terms << " terms, beyond --max-terms " << opt.max_terms
          << " (about an hour on 2 cores); lower --runs, --wavelengths or the image size, or raise --max-terms";
        return fail(m.str());
    }

    if (const double bytes = estimate_memory(opt, camera); bytes > opt.max_memory) {
        std::ostringstream m;
        m << name << ": " << in.width << "x" << in.height << " pixels need about " << bytes / (1 << 20)
          << " MiB, beyond --max-memory " << opt.max_memory / (1 << 20)
          << " MiB; use a smaller image or pinhole, or raise --max-memory (e.g. 32GiB)";
        return fail(m.str());
    }
    const SpectralScene scene{camera, in.rgb.data(), in.depth.data(), opt.depth_meaning};
    std::vector<float> pixels(3 * size_t(in.width) * in.height);
    FastSettings fast = opt.fast;
    fast.nthreads = nthreads;
    auto r = opt.method == DiffractMethod::Fast
                 ? diffract_fast(scene, basis.value, s.aperture, opt.vignetting, pixels.data(), fast, opt.progress)
                 : diffract_spectral(scene, basis.value, s.aperture, wave_propagator(s), opt.vignetting,
                                     pixels.data(), opt.progress);
    if (!r.ok()) return fail(r.error == "cancelled" ? name + ": interrupted" : name + ": " + r.error);
    if (auto c = config.value.convert_from_xyz(pixels.data(), pixels.size() / 3, out_space); !c.ok())
        return fail(c.error);

    // Output: float R, G, B in the output space, then the source's depth channel unchanged.
    OIIO::ImageSpec spec = in.spec;
    spec.nchannels = 4;
    spec.channelnames = {"R", "G", "B", in.depth_channel};
    spec.alpha_channel = -1;
    spec.z_channel = 3;
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    spec.attribute("oiio:ColorSpace", out_space);
    spec.attribute("wavecam.pinhole", with_unit(s.aperture.diameter, 1e-3, "mm"));
    spec.attribute("wavecam.aperture", s.aperture.name());
    spec.attribute("wavecam.film-distance", with_unit(opt.film_distance, 1e-3, "mm"));
    spec.attribute("wavecam.film-width", with_unit(camera.film_width(), 1e-3, "mm"));
    spec.attribute("wavecam.fov", static_cast<float>(in.fov_h * 180 / M_PI));
    spec.attribute("wavecam.fov-from", in.fov_from);
    spec.attribute("wavecam.depth", opt.depth_meaning == DepthMeaning::Planar ? "planar" : "ray");
    std::string wl;
    for (double l : sampling.value.wavelength) wl += (wl.empty() ? "" : ",") + with_unit(l, 1e-9, "nm");
    spec.attribute("wavecam.wavelengths", wl);
    spec.attribute("wavecam.light", basis.value.description());
    spec.attribute("wavecam.method", opt.method == DiffractMethod::Fast    ? "fast"
                                     : opt.method == DiffractMethod::Exact ? "exact"
                                                                           : "incoherent");
    spec.attribute("wavecam.runs", s.runs);
    spec.attribute("wavecam.seed", std::to_string(s.seed));
    spec.attribute("wavecam.film-subsamples",
                   s.film_subsamples > 0 ? s.film_subsamples
                                         : auto_film_subsamples(s.aperture, camera, sampling.value.wavelength[0]));
    spec.attribute("wavecam.jitter", s.jitter ? "true" : "false");
    spec.attribute("wavecam.vignetting", opt.vignetting ? "true" : "false");
    spec.attribute("wavecam.input-colorspace", in_space);
    spec.attribute("wavecam.output-colorspace", out_space);
    spec.attribute("wavecam.colorconfig", config.value.path());
    spec.attribute("wavecam.fresnel-number",
                   static_cast<float>(fresnel_number(s.aperture.diameter / 2, opt.film_distance, INFINITY,
                                                     kDesignWavelength)));
    std::ostringstream summary;
    summary << sampling.value.wavelength.size() << " wavelengths" << (basis.value.monochrome() ? " (monochrome), " : ", ");
    if (opt.method == DiffractMethod::Fast) summary << "fast method";
    else summary << s.runs << " runs, " << terms << " terms";
    spec.attribute("wavecam.summary", summary.str());

    dst.reset(spec);
    std::vector<float> out(4 * size_t(in.width) * in.height);
    for (size_t p = 0; p < size_t(in.width) * in.height; ++p) {
        for (int k = 0; k < 3; ++k) out[4 * p + k] = pixels[3 * p + k];
        out[4 * p + 3] = in.depth[p];
    }
    if (!dst.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, out.data()))
        return fail(name + ": cannot fill the output image: " + dst.geterror());
    return true;
}

}  // namespace wavecam
