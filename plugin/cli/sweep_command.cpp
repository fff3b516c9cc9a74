// `wavecam sweep`: the seed paper's "Diffraction of a point source" - PSFs over pinhole
// diameters as a labelled contact sheet, spot size against diameter as a plot and a CSV, the
// theoretical optima marked.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "commands.h"
#include "display_header.h"
#include "output_paths.h"
#include "sweep_plot.h"
#include "terminal_progress.h"
#include "wavecam/aperture_mask.h"
#include "wavecam/atomic_write.h"
#include "wavecam/pinhole_design.h"
#include "wavecam/pinhole_sweep.h"
#include "wavecam/units.h"
#include "../front/settings.h"

namespace wavecam::cli {
namespace {

// The flags' defaults: SweepParams' own, written as the flags take them.
const SweepParams kDefaults;
struct SweepFlags {
    std::string film_distance = with_unit(kDefaults.film_distance, 1e-3, "mm"),
                wavelength = with_unit(kDefaults.wavelength, 1e-9, "nm"), prefix = "sweep",
                aperture = kDefaults.aperture.name();
    int count = kDefaults.count, resolution = kDefaults.resolution;
};

int fail(const std::string& message, int status = 1) {
    finish_progress();
    if (status == 1 && interrupted()) status = interrupted_status();  // (a write refused at a signal)
    std::fprintf(stderr, "wavecam sweep: %s\n", message.c_str());
    return status;
}

int run(const SweepFlags& f) {
    SweepParams p;
    std::string error;
    auto take = [&error](const auto& r, auto& dst) {
        if (!error.empty()) return;
        if (!r.ok()) error = "--" + r.error;
        else dst = r.value;
    };
    take(front::parse_film_distance(f.film_distance, "film-distance"), p.film_distance);
    take(parse_length(f.wavelength, "wavelength"), p.wavelength);
    take(load_aperture(f.aperture, "aperture"), p.aperture);
    if (error.empty() && (f.count < 3 || f.count > 64)) error = "--count: expected 3 to 64 diameters";
    if (error.empty() && (f.resolution < 21 || f.resolution > 1001)) error = "--resolution: expected 21 to 1001";
    if (!error.empty()) return fail(error, 2);
    const std::vector<PathUse> writes{
        {f.prefix + ".csv", "-o"}, {f.prefix + "_psfs.png", "-o"}, {f.prefix + "_spot_size.png", "-o"}};
    for (const PathUse& w : writes)
        if (const std::string bad = output_name_problem(w.path); !bad.empty()) return fail(bad, 2);
    if (const std::string clash = path_conflict({{aperture_mask_file(f.aperture), "the --aperture mask"}}, writes);
        !clash.empty())
        return fail(clash, 2);
    p.count = f.count;
    p.resolution = f.resolution;
    auto r = sweep_pinholes(p, terminal_progress("sweep"));
    finish_progress();
    if (!r.ok()) return fail(r.error, interrupted() ? interrupted_status() : 1);
    const auto& pts = r.value;
    const double unit = std::sqrt(p.film_distance * p.wavelength);
    const double best = optimal_diameter(pts), rayleigh = rayleigh_optimal_diameter(p.film_distance, p.wavelength);
    const double nyquist = nyquist_optimal_diameter(5 * p.film_distance, p.wavelength);
    const std::string csv = f.prefix + ".csv";
    std::ostringstream table;
    table << "diameter_mm,diameter_over_sqrt_f_lambda,fresnel_number,r50_um,r80_um\n";
    for (const auto& pt : pts)
        table << pt.diameter * 1e3 << "," << pt.diameter / unit << "," << pt.psf.fresnel_number << "," << pt.r50 * 1e6
              << "," << pt.r80 * 1e6 << "\n";
    if (auto w = write_text_atomically(table.str(), csv); !w.ok()) return fail(w.error);
    const SweepFigure figure{p.film_distance, p.wavelength, p.aperture.name(), rayleigh, nyquist, best};
    for (auto [img, path] : {std::pair{psf_sheet(pts, figure), f.prefix + "_psfs.png"},
                             std::pair{spot_size_plot(pts, figure), f.prefix + "_spot_size.png"}}) {
        tag_display_encoded(img.specmod());
        if (auto w = write_image_atomically(img, path, OIIO::TypeDesc::UINT8); !w.ok()) return fail(w.error);
    }
    std::printf("measured optimum (smallest r50): %.4g mm = %.3f sqrt(f lambda)\n", best * 1e3, best / unit);
    std::printf("Rayleigh 1.9 sqrt(f lambda):     %.4g mm\n", rayleigh * 1e3);
    std::printf("paper sqrt(D lambda / 2), D = 5f: %.4g mm\n", nyquist * 1e3);
    if (p.aperture.shape != ApertureShape::Circle)
        std::printf("(%s: 'diameter' is its size parameter - side, circumscribed diameter, mask width or outer\n"
                    " diameter; the Rayleigh and Nyquist optima are the disc's, r50 a centred circle's radius)\n",
                    p.aperture.name().c_str());
    if (has_zone_focus(p.aperture))  // r_1^2 / lambda = f with r_1 = (D/2) / sqrt(N)
        std::printf("(%s is in focus at D = 2 sqrt(N f lambda) = %.4g mm; other diameters defocus it)\n",
                    p.aperture.name().c_str(), 2 * std::sqrt(p.aperture.zones * p.film_distance * p.wavelength) * 1e3);
    std::printf("wrote %s, %s_psfs.png, %s_spot_size.png\n", csv.c_str(), f.prefix.c_str(), f.prefix.c_str());
    return 0;
}

}  // namespace

void add_sweep_command(CLI::App& app, int& status) {
    auto f = std::make_shared<SweepFlags>();
    CLI::App* cmd = app.add_subcommand("sweep", "PSFs and spot size over pinhole diameters (the paper's figure)");
    cmd->add_option("--film-distance", f->film_distance, "Pinhole to film, e.g. 50mm")->capture_default_str();
    cmd->add_option("--wavelength", f->wavelength, "Wavelength, e.g. 550nm")->capture_default_str();
    cmd->add_option("--aperture", f->aperture, "circle, square, polygon:N[:ROTATIONdeg], mask:FILE, zoneplate:N or sieve:N[:Kx][:FILL%][:SEED]")
        ->capture_default_str();
    cmd->add_option("--count", f->count, "Diameters, log-spaced from 0.4 to 4 sqrt(f lambda)")->capture_default_str();
    cmd->add_option("--resolution", f->resolution, "Pixels across each PSF")->capture_default_str();
    cmd->add_option("-o,--output", f->prefix, "Output prefix: PREFIX.csv, PREFIX_psfs.png, PREFIX_spot_size.png")
        ->capture_default_str();
    cmd->callback([f, &status] { status = run(*f); });
}

}  // namespace wavecam::cli
