// `wavecam psf`: the image of one point source, as a float EXR of relative irradiance.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "commands.h"
#include "display_header.h"
#include "output_paths.h"
#include "plot_marks.h"
#include "terminal_progress.h"
#include "wavecam/aperture_mask.h"
#include "wavecam/atomic_write.h"
#include "wavecam/psf.h"
#include "wavecam/units.h"
#include "../front/settings.h"

namespace wavecam::cli {
namespace {

struct PsfFlags {
    std::string pinhole, aperture, film_distance, source_distance, source_angle, wavelength, film_size, resolution,
        max_angle, output = "psf.exr", png, max_terms;
    int threads = 0;
};

// Parameters as the flags take them, and as the output's header records them; the flags'
// defaults are PsfParams' own.
PsfFlags as_flags(const PsfParams& p) {
    PsfFlags f;
    f.pinhole = with_unit(p.aperture.diameter, 1e-3, "mm");
    f.aperture = p.aperture.name();
    f.film_distance = with_unit(p.film_distance, 1e-3, "mm");
    f.source_distance = std::isinf(p.source_distance) ? "inf" : with_unit(p.source_distance, 1.0, "m");
    f.source_angle = with_unit(p.source_angle, M_PI / 180, "deg");
    f.wavelength = with_unit(p.wavelength, 1e-9, "nm");
    f.film_size = with_unit(p.film_size, 1e-3, "mm");
    f.resolution = std::to_string(p.resolution);
    f.max_angle = with_unit(std::asin(p.sin_theta_max), M_PI / 180, "deg");
    f.max_terms = OIIO::Strutil::fmt::format("{:g}", p.max_terms);
    f.threads = p.nthreads;
    return f;
}

// --max-terms: a finite count of terms > 0 (nan or inf would switch the bound off).
Result<double> parse_max_terms(const std::string& text) {
    char* end = nullptr;
    const double t = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(t > 0) || !std::isfinite(t))
        return Result<double>::failure("max-terms: expected a number of terms > 0 such as 4e12 (not inf or nan), got '" +
                                       text + "'");
    return Result<double>::success(t);
}

// Turns the flags into parameters; the first error names its flag.
Result<PsfParams> parse_flags(const PsfFlags& f) {
    PsfParams p;
    std::string error;
    auto take = [&error](const auto& r, auto& dst) {
        if (!error.empty()) return;
        if (!r.ok()) error = "--" + r.error;
        else dst = r.value;
    };
    take(load_aperture(f.aperture, "aperture"), p.aperture);
    take(parse_length(f.pinhole, "pinhole"), p.aperture.diameter);
    take(front::parse_film_distance(f.film_distance, "film-distance"), p.film_distance);
    take(parse_length_or_inf(f.source_distance, "source-distance"), p.source_distance);
    take(parse_angle(f.source_angle, "source-angle"), p.source_angle);
    take(parse_length(f.wavelength, "wavelength"), p.wavelength);
    take(parse_length(f.film_size, "film-size"), p.film_size);
    long res = 0;
    take(parse_whole_number(f.resolution, "resolution", 1, 16384), res);
    double max_angle = 0;
    take(parse_angle(f.max_angle, "max-angle"), max_angle);
    take(parse_max_terms(f.max_terms), p.max_terms);
    if (error.empty())
        if (auto t = parse_threads(f.threads); !t.ok()) error = "--" + t.error;
    if (!error.empty()) return Result<PsfParams>::failure(error);
    p.resolution = static_cast<int>(res);
    p.sin_theta_max = std::sin(max_angle);
    p.nthreads = f.threads;
    if (auto v = validate(p); !v.ok()) return Result<PsfParams>::failure("--" + v.error);
    return Result<PsfParams>::success(p);
}

OIIO::ImageBuf to_imagebuf(const PsfImage& img, const PsfParams& p) {
    const int n = img.resolution;
    const PsfFlags given = as_flags(p);
    OIIO::ImageSpec spec(n, n, 1, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"Y"};
    spec.attribute("wavecam.quantity", "relative irradiance (1 = unobstructed irradiance at the film centre)");
    spec.attribute("wavecam.aperture", p.aperture.name());
    if (has_zone_focus(p.aperture))
        spec.attribute("wavecam.zoneplate-focus", with_unit(zone_plate_focus(p.aperture, p.wavelength), 1e-3, "mm"));
    spec.attribute("wavecam.pinhole", given.pinhole);
    spec.attribute("wavecam.film-distance", given.film_distance);
    spec.attribute("wavecam.source-distance", given.source_distance);
    spec.attribute("wavecam.source-angle", given.source_angle);
    spec.attribute("wavecam.wavelength", given.wavelength);
    spec.attribute("wavecam.film-size", given.film_size);
    spec.attribute("wavecam.pixel-pitch", with_unit(img.pixel_pitch, 1e-6, "um"));
    spec.attribute("wavecam.film-centre",
                   with_unit(img.centre_x, 1e-3, "mm") + " " + with_unit(img.centre_y, 1e-3, "mm"));
    spec.attribute("wavecam.sample-pitch", with_unit(img.sample_pitch, 1e-9, "nm"));
    spec.attribute("wavecam.sample-count", static_cast<int>(img.sample_count));
    spec.attribute("wavecam.fresnel-number", static_cast<float>(img.fresnel_number));
    spec.attribute("wavecam.orientation", "upright: column grows with scene +x, row 0 at the top");
    OIIO::ImageBuf buf(spec);
    buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, img.irradiance.data());
    return buf;
}

// A picture for people: irradiance / peak, sRGB-encoded so the rings show, enlarged to at least
// 256 pixels (each pixel repeated) with a scale bar in micrometres on the film at its lower left.
Result<bool> write_png(const OIIO::ImageBuf& psf, double peak, double pitch, const std::string& path) {
    OIIO::ImageBuf scaled = OIIO::ImageBufAlgo::mul(psf, float(peak > 0 ? 1.0 / peak : 1.0));
    OIIO::ImageBuf display = OIIO::ImageBufAlgo::colorconvert(scaled, "linear", "sRGB");
    if (display.has_error()) return Result<bool>::failure(path + ": " + display.geterror());
    const int n = display.spec().width, factor = std::max(1, (256 + n - 1) / n);
    if (factor > 1) display = OIIO::ImageBufAlgo::resize(display, "box", 0, OIIO::ROI(0, n * factor, 0, n * factor));
    draw_scale_bar(display, 8, n * factor - 8, pitch / factor, n * factor / 3, {1, 1, 1});
    tag_display_encoded(display.specmod());
    return write_image_atomically(display, path, OIIO::TypeDesc::UINT8);
}

int fail(const std::string& message, int status = 1) {
    finish_progress();
    if (status == 1 && interrupted()) status = interrupted_status();  // (a write refused at a signal)
    std::fprintf(stderr, "wavecam psf: %s\n", message.c_str());
    return status;
}

int run(const PsfFlags& flags) {
    auto params = parse_flags(flags);
    if (!params.ok()) return fail(params.error, 2);
    for (const std::string* name : {&flags.output, &flags.png})  // before any work
        if (!name->empty())
            if (const std::string bad = output_name_problem(*name); !bad.empty()) return fail(bad, 2);
    if (const std::string clash = path_conflict({{aperture_mask_file(flags.aperture), "the --aperture mask"}},
                                                {{flags.output, "-o"}, {flags.png, "--png"}});
        !clash.empty())
        return fail(clash, 2);
    const PsfParams& p = params.value;
    const double samples = estimate_sample_count(p.aperture, sample_pitch(p.wavelength, p.sin_theta_max));
    std::fprintf(stderr, "psf: %s x %d x %d film points = %.3g terms\n", aperture_work(p.aperture, samples).c_str(),
                 p.resolution, p.resolution, samples * p.resolution * p.resolution);
    auto img = compute_psf(p, ComputeDevice{}, terminal_progress("psf"));  // on the CPU
    finish_progress();
    if (!img.ok()) return fail(img.error, interrupted() ? interrupted_status() : 1);
    const OIIO::ImageBuf buf = to_imagebuf(img.value, p);
    if (auto w = write_image_atomically(buf, flags.output, OIIO::TypeDesc::FLOAT); !w.ok()) return fail(w.error);
    if (!flags.png.empty())
        if (auto w = write_png(buf, img.value.peak, img.value.pixel_pitch, flags.png); !w.ok()) return fail(w.error);
    std::printf("Fresnel number  %.4g\n", img.value.fresnel_number);
    if (has_zone_focus(p.aperture))
        std::printf("%s first focus r1^2/lambda = %.4g mm at %.4g nm (film at %.4g mm)\n",
                    p.aperture.shape == ApertureShape::ZonePlate ? "zone plate     " : "photon sieve   ", zone_plate_focus(p.aperture, p.wavelength) * 1e3, p.wavelength * 1e9, p.film_distance * 1e3);
    std::printf("pinhole samples %zu (pitch %.4g nm)\n", img.value.sample_count, img.value.sample_pitch * 1e9);
    std::printf("peak            %.6g (relative irradiance)\n", img.value.peak);
    std::printf("time            %.3f s\n", img.value.seconds);
    std::printf("wrote           %s%s%s\n", flags.output.c_str(), flags.png.empty() ? "" : ", ", flags.png.c_str());
    return 0;
}

}  // namespace

void add_psf_command(CLI::App& app, int& status) {
    auto flags = std::make_shared<PsfFlags>(as_flags(PsfParams{}));
    CLI::App* cmd = app.add_subcommand("psf", "Image one point source through the pinhole (exact propagation)");
    cmd->add_option("--pinhole", flags->pinhole, "Pinhole diameter, e.g. 0.3mm")->capture_default_str();
    cmd->add_option("--aperture", flags->aperture, "circle, square, polygon:N[:ROTATIONdeg], mask:FILE, zoneplate:N or sieve:N[:Kx][:FILL%][:SEED]")->capture_default_str();
    cmd->add_option("--film-distance", flags->film_distance, "Pinhole to film, e.g. 65mm")->capture_default_str();
    cmd->add_option("--source-distance", flags->source_distance, "Source distance along its ray, or inf")
        ->capture_default_str();
    cmd->add_option("--source-angle", flags->source_angle, "Field angle of the source, e.g. 20deg")
        ->capture_default_str();
    cmd->add_option("--wavelength", flags->wavelength, "Wavelength, e.g. 550nm")->capture_default_str();
    cmd->add_option("--film-size", flags->film_size, "Width of the square film window, e.g. 0.6mm")
        ->capture_default_str();
    cmd->add_option("--resolution", flags->resolution, "Pixels across the window (odd: one on the image point)")
        ->capture_default_str();
    cmd->add_option("--max-angle", flags->max_angle,
                    "Largest source/film angle: samples the pinhole at lambda/(2 sin angle)")
        ->capture_default_str();
    cmd->add_option("--max-terms", flags->max_terms, "Refuse work beyond this many terms")->capture_default_str();
    cmd->add_option("--threads", flags->threads, "Threads (0 = every core)")->capture_default_str();
    cmd->add_option("-o,--output", flags->output, "Output EXR")->capture_default_str();
    cmd->add_option("--png", flags->png, "Also write a PNG for people (peak-normalised, sRGB, a scale bar in micrometres)");
    cmd->callback([flags, &status] { status = run(*flags); });
}

}  // namespace wavecam::cli
