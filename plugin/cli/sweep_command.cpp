// `wavecam sweep`: the seed paper's "Diffraction of a point source" - PSFs over pinhole
// diameters as a labelled contact sheet, spot size against diameter as a plot and a CSV, the
// theoretical optima marked.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "commands.h"
#include "terminal_progress.h"
#include "wavecam/aperture_mask.h"
#include "wavecam/atomic_write.h"
#include "wavecam/pinhole_design.h"
#include "wavecam/pinhole_sweep.h"
#include "wavecam/units.h"

namespace wavecam::cli {
namespace {

constexpr const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// The flags' defaults: SweepParams' own, written as the flags take them.
const SweepParams kDefaults;
struct SweepFlags {
    std::string film_distance = with_unit(kDefaults.film_distance, 1e-3, "mm"),
                wavelength = with_unit(kDefaults.wavelength, 1e-9, "nm"), prefix = "sweep",
                aperture = kDefaults.aperture.name();
    int count = kDefaults.count, resolution = kDefaults.resolution;
};

using Colour = std::array<float, 3>;

void text(OIIO::ImageBuf& img, int x, int y, const std::string& s, int size, const Colour& colour) {
    OIIO::ImageBufAlgo::render_text(img, x, y, s, size, kFont, OIIO::cspan<float>(colour.data(), 3));
}

// Each PSF scaled to its own peak, sRGB-encoded (rings show), labelled with its diameter.
OIIO::ImageBuf contact_sheet(const std::vector<SweepPoint>& pts) {
    const int n = pts.front().psf.resolution, cols = std::min<int>(int(pts.size()), 5);
    const int rows = (int(pts.size()) + cols - 1) / cols, cell = std::max(n, 160);
    OIIO::ImageBuf sheet(OIIO::ImageSpec(cols * cell, rows * (cell + 20), 3, OIIO::TypeDesc::FLOAT));
    for (size_t k = 0; k < pts.size(); ++k) {
        const PsfImage& p = pts[k].psf;
        OIIO::ImageBuf one(OIIO::ImageSpec(n, n, 1, OIIO::TypeDesc::FLOAT));
        one.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, p.irradiance.data());
        one = OIIO::ImageBufAlgo::mul(one, float(1.0 / p.peak));
        one = OIIO::ImageBufAlgo::resize(one, "box", 0, OIIO::ROI(0, cell, 0, cell));
        const int order[3] = {0, 0, 0};
        one = OIIO::ImageBufAlgo::channels(one, 3, OIIO::cspan<int>(order, 3));
        one = OIIO::ImageBufAlgo::colorconvert(one, "linear", "sRGB");
        const int x = int(k % cols) * cell, y = int(k / cols) * (cell + 20);
        OIIO::ImageBufAlgo::paste(sheet, x, y + 20, 0, 0, one);
        std::ostringstream label;
        label.precision(3);
        label << "d = " << pts[k].diameter * 1e3 << " mm";
        text(sheet, x + 4, y + 15, label.str(), 12, {1, 1, 0.3f});
    }
    return sheet;
}

// Spot radius against diameter on log axes, with Rayleigh's and the paper's optima marked.
OIIO::ImageBuf plot(const std::vector<SweepPoint>& pts, double rayleigh, double nyquist_5f, double best) {
    const int W = 800, H = 500, L = 80, R = 30, T = 40, B = 60;
    OIIO::ImageBuf img(OIIO::ImageSpec(W, H, 3, OIIO::TypeDesc::FLOAT));
    OIIO::ImageBufAlgo::fill(img, {1.0f, 1.0f, 1.0f});
    double d0 = pts.front().diameter, d1 = pts.back().diameter, r0 = 1e9, r1 = 0;
    for (const auto& p : pts) {
        r0 = std::min(r0, p.r50);
        r1 = std::max(r1, p.r80);
    }
    auto px = [&](double d) { return L + int((W - L - R) * std::log(d / d0) / std::log(d1 / d0)); };
    auto py = [&](double r) { return H - B - int((H - T - B) * std::log(r / (0.8 * r0)) / std::log(1.25 * r1 / (0.8 * r0))); };
    OIIO::ImageBufAlgo::render_box(img, L, T, W - R, H - B, {0.0f, 0.0f, 0.0f});
    auto vline = [&](double d, const Colour& c, const std::string& name, int dy) {
        OIIO::ImageBufAlgo::render_line(img, px(d), T, px(d), H - B, OIIO::cspan<float>(c.data(), 3));
        text(img, px(d) + 4, T + 14 + dy, name, 13, c);
    };
    vline(rayleigh, {0.8f, 0.1f, 0.1f}, "Rayleigh 1.9 sqrt(f lambda)", 0);
    vline(nyquist_5f, {0.1f, 0.5f, 0.1f}, "paper sqrt(D lambda/2), D = 5f", 16);
    vline(best, {0.1f, 0.1f, 0.8f}, "measured optimum (r50)", 32);
    for (size_t k = 1; k < pts.size(); ++k) {
        OIIO::ImageBufAlgo::render_line(img, px(pts[k - 1].diameter), py(pts[k - 1].r50), px(pts[k].diameter),
                                        py(pts[k].r50), {0, 0, 0});
        OIIO::ImageBufAlgo::render_line(img, px(pts[k - 1].diameter), py(pts[k - 1].r80), px(pts[k].diameter),
                                        py(pts[k].r80), {0.5f, 0.5f, 0.5f});
    }
    for (const auto& p : pts) OIIO::ImageBufAlgo::render_box(img, px(p.diameter) - 2, py(p.r50) - 2, px(p.diameter) + 2, py(p.r50) + 2, {0, 0, 0}, true);
    text(img, L, H - 20, "pinhole diameter (log), " + std::to_string(pts.front().diameter * 1e3).substr(0, 5) +
                             " to " + std::to_string(pts.back().diameter * 1e3).substr(0, 5) + " mm",
         14, {0, 0, 0});
    text(img, 8, 24, "encircled-energy radius (log): r50 black, r80 grey", 14, {0, 0, 0});
    return img;
}

int fail(const std::string& message, int status = 1) {
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
    take(parse_length(f.film_distance, "film-distance"), p.film_distance);
    take(parse_length(f.wavelength, "wavelength"), p.wavelength);
    take(load_aperture(f.aperture, "aperture"), p.aperture);
    if (error.empty() && (f.count < 3 || f.count > 64)) error = "--count: expected 3 to 64 diameters";
    if (error.empty() && (f.resolution < 21 || f.resolution > 1001)) error = "--resolution: expected 21 to 1001";
    if (!error.empty()) return fail(error, 2);
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
    for (auto [img, path] : {std::pair{contact_sheet(pts), f.prefix + "_psfs.png"},
                             std::pair{plot(pts, rayleigh, nyquist, best), f.prefix + "_spot_size.png"}})
        if (auto w = write_image_atomically(img, path, OIIO::TypeDesc::UINT8); !w.ok()) return fail(w.error);
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
