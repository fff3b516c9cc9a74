#include "sweep_plot.h"

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>

#include "plot_marks.h"

namespace wavecam::cli {
namespace {

std::string format(const char* pattern, double a, double b = 0) {
    char text[160];
    std::snprintf(text, sizeof text, pattern, a, b);
    return text;
}

const Colour kBlack{0, 0, 0}, kGrey{0.55f, 0.55f, 0.55f}, kGrid{0.9f, 0.9f, 0.9f}, kRed{0.8f, 0.1f, 0.1f},
    kGreen{0.1f, 0.5f, 0.1f}, kBlue{0.1f, 0.2f, 0.85f}, kWhite{1, 1, 1}, kYellow{1, 1, 0.3f};

void line(OIIO::ImageBuf& img, int x0, int y0, int x1, int y1, const Colour& c) {
    OIIO::ImageBufAlgo::render_line(img, x0, y0, x1, y1, OIIO::cspan<float>(c.data(), 3));
}

// Pixels (x0, y0) and (x1, y1), opposite corners of a box, both in it.
struct Corners {
    int x0, y0, x1, y1;
};

void box(OIIO::ImageBuf& img, const Corners& at, const Colour& c, bool fill) {
    OIIO::ImageBufAlgo::render_box(img, at.x0, at.y0, at.x1, at.y1, OIIO::cspan<float>(c.data(), 3), fill);
}

// A vertical dashed line from y0 down to y1.
void dashed(OIIO::ImageBuf& img, int x, int y0, int y1, const Colour& c) {
    for (int y = y0; y < y1; y += 10) line(img, x, y, x, std::min(y + 5, y1), c);
}

}  // namespace

double r50_at(const std::vector<SweepPoint>& pts, double d) {
    size_t m = 0;
    for (size_t k = 1; k < pts.size(); ++k)
        if (std::abs(std::log(pts[k].diameter / d)) < std::abs(std::log(pts[m].diameter / d))) m = k;
    if (pts.size() < 3) return pts[m].r50;
    m = std::clamp<size_t>(m, 1, pts.size() - 2);
    double r = 0;  // Lagrange's form of the parabola through points m - 1, m, m + 1 in log d
    const double x = std::log(d);
    for (size_t i = m - 1; i <= m + 1; ++i) {
        double w = pts[i].r50;
        for (size_t j = m - 1; j <= m + 1; ++j)
            if (j != i) w *= (x - std::log(pts[j].diameter)) / (std::log(pts[i].diameter) - std::log(pts[j].diameter));
        r += w;
    }
    return r;
}

// Each PSF scaled to its own peak, sRGB-encoded (rings show), its window 3 x the spot: the
// windows differ in size, so each cell carries its diameter, r50 and a scale bar in um.
OIIO::ImageBuf psf_sheet(const std::vector<SweepPoint>& pts, const SweepFigure& fig) {
    const int n = pts.front().psf.resolution, cols = std::min<int>(int(pts.size()), 5);
    const int rows = (int(pts.size()) + cols - 1) / cols, cell = std::max(n, 200), head = 44, label = 20;
    OIIO::ImageBuf sheet(OIIO::ImageSpec(cols * cell, head + rows * (cell + label), 3, OIIO::TypeDesc::FLOAT));
    draw_text(sheet, 6, 17,
              "Point-source images (PSFs), f = " + format("%.4g mm", fig.film_distance * 1e3) + ", lambda = " +
                  format("%.4g nm", fig.wavelength * 1e9) + ", " + fig.aperture + ", source on axis at infinity",
              {13, kWhite});
    draw_text(sheet, 6, 36,
              "Windows differ in size (3x the larger of the shadow and the Airy disc: see the bars, micrometres on the "
              "film); each is scaled to its own peak, sRGB-encoded.",
              {12, kGrey});
    for (size_t k = 0; k < pts.size(); ++k) {
        const PsfImage& p = pts[k].psf;
        OIIO::ImageBuf one(OIIO::ImageSpec(n, n, 1, OIIO::TypeDesc::FLOAT));
        one.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, p.irradiance.data());
        one = OIIO::ImageBufAlgo::mul(one, float(1.0 / p.peak));
        one = OIIO::ImageBufAlgo::resize(one, "box", 0, OIIO::ROI(0, cell, 0, cell));
        const int order[3] = {0, 0, 0};
        one = OIIO::ImageBufAlgo::channels(one, 3, OIIO::cspan<int>(order, 3));
        one = OIIO::ImageBufAlgo::colorconvert(one, "linear", "sRGB");
        const int x = int(k % cols) * cell, y = head + int(k / cols) * (cell + label);
        OIIO::ImageBufAlgo::paste(sheet, x, y + label, 0, 0, one);
        draw_text(sheet, x + 4, y + 15, format("d = %.3g mm, r50 = %.3g um", pts[k].diameter * 1e3, pts[k].r50 * 1e6),
                  {12, kYellow});
        draw_scale_bar(sheet, x + 8, y + label + cell - 8, p.resolution * p.pixel_pitch / cell, cell / 3, kWhite);
    }
    return sheet;
}

// Spot radius against diameter on log axes: the r50 and r80 curves, Rayleigh's and the paper's
// optima, the measured optimum marked with its diameter and spot size, a legend beside.
OIIO::ImageBuf spot_size_plot(const std::vector<SweepPoint>& pts, const SweepFigure& fig) {
    const int W = 1060, H = 600, L = 80, R = W - 390, T = 60, B = H - 70;  // the plot box
    OIIO::ImageBuf img(OIIO::ImageSpec(W, H, 3, OIIO::TypeDesc::FLOAT));
    OIIO::ImageBufAlgo::fill(img, {1.0f, 1.0f, 1.0f});
    double r0 = 1e30, r1 = 0;
    for (const auto& p : pts) r0 = std::min(r0, p.r50 * 1e6), r1 = std::max(r1, p.r80 * 1e6);
    const double d0 = pts.front().diameter * 1e3 / 1.08, d1 = pts.back().diameter * 1e3 * 1.08;  // mm
    r0 /= 1.35, r1 *= 1.15;                                                                          // um
    auto px = [&](double mm) { return L + int(std::lround((R - L) * std::log(mm / d0) / std::log(d1 / d0))); };
    auto py = [&](double um) { return B - int(std::lround((B - T) * std::log(um / r0) / std::log(r1 / r0))); };

    for (const Tick& t : log_ticks(d0, d1)) {  // grid, ticks and numbers: diameter in mm
        if (t.labelled) line(img, px(t.value), T, px(t.value), B, kGrid);
        line(img, px(t.value), B, px(t.value), B + (t.labelled ? 7 : 4), kBlack);
        if (t.labelled) draw_text(img, px(t.value), B + 22, tick_label(t.value), {13, kBlack, Align::Centre});
    }
    for (const Tick& t : log_ticks(r0, r1)) {  // spot radius in um
        if (t.labelled) line(img, L, py(t.value), R, py(t.value), kGrid);
        line(img, L - (t.labelled ? 7 : 4), py(t.value), L, py(t.value), kBlack);
        if (t.labelled) draw_text(img, L - 10, py(t.value) + 5, tick_label(t.value), {13, kBlack, Align::Right});
    }
    box(img, {L, T, R, B}, kBlack, false);
    draw_text(img, (L + R) / 2, H - 18, "pinhole diameter d (mm), log scale", {14, kBlack, Align::Centre});
    draw_text(img, 10, T - 14, "spot radius r (micrometres), log scale", {14, kBlack});
    draw_text(img, 10, 24,
              "Spot size against pinhole diameter: f = " + format("%.4g mm", fig.film_distance * 1e3) + ", lambda = " +
                  format("%.4g nm", fig.wavelength * 1e9) + ", " + fig.aperture,
              {16, kBlack});

    const double best_um = r50_at(pts, fig.best) * 1e6;
    auto mark = [&](double d, const Colour& c, bool dash) {
        if (d * 1e3 <= d0 || d * 1e3 >= d1) return;
        if (dash) dashed(img, px(d * 1e3), T + 1, B - 1, c);
        else line(img, px(d * 1e3), T + 1, px(d * 1e3), B - 1, c);
    };
    mark(fig.rayleigh, kRed, true);
    mark(fig.paper, kGreen, true);
    mark(fig.best, kBlue, false);
    for (size_t k = 1; k < pts.size(); ++k) {
        const double a = pts[k - 1].diameter * 1e3, b = pts[k].diameter * 1e3;
        line(img, px(a), py(pts[k - 1].r80 * 1e6), px(b), py(pts[k].r80 * 1e6), kGrey);
        line(img, px(a), py(pts[k - 1].r50 * 1e6), px(b), py(pts[k].r50 * 1e6), kBlack);
    }
    for (const auto& p : pts) {
        const int x = px(p.diameter * 1e3);
        box(img, {x - 3, py(p.r50 * 1e6) - 3, x + 3, py(p.r50 * 1e6) + 3}, kBlack, true);
        box(img, {x - 2, py(p.r80 * 1e6) - 2, x + 2, py(p.r80 * 1e6) + 2}, kGrey, true);
    }
    // the optimum: a blue diamond on the r50 curve and its values beneath
    const int bx = px(fig.best * 1e3), by = py(best_um);
    for (int k = 0; k <= 6; ++k) line(img, bx - (6 - k), by - k, bx + (6 - k), by - k, kBlue), line(img, bx - (6 - k), by + k, bx + (6 - k), by + k, kBlue);
    // its values left of and below it, on white, clear of the curve (which rises to either side)
    const std::string values[2] = {format("d = %#.3g mm", fig.best * 1e3), format("r50 = %.3g um", best_um)};
    for (int k = 0; k < 2; ++k) {
        const int right = bx - 10, base = by + 20 + 16 * k;
        box(img, {right - text_width(values[k], 13) - 2, base - 13, right + 1, base + 4}, kWhite, true);
        draw_text(img, right, base, values[k], {13, kBlue, Align::Right});
    }

    int y = T + 10;  // the legend: a sample of each line, then its words
    auto entry = [&](const Colour& c, bool dash, bool points, std::initializer_list<std::string> words) {
        const int x = R + 20;
        if (dash) for (int s = 0; s < 30; s += 10) line(img, x + s, y, x + s + 5, y, c);
        else line(img, x, y, x + 30, y, c);
        if (points) box(img, {x + 12, y - 3, x + 18, y + 3}, c, true);
        for (const std::string& w : words) draw_text(img, x + 40, y + 5, w, {13, kBlack}), y += 18;
        y += 12;
    };
    const double unit = std::sqrt(fig.film_distance * fig.wavelength);
    entry(kBlack, false, true, {"r50: radius of the circle holding 50%", "of the light through the pinhole"});
    entry(kGrey, false, true, {"r80: the same for 80%"});
    entry(kBlue, false, false, {"measured optimum (least r50, interpolated):",
                                format("d = %#.3g mm = %.3g sqrt(f lambda),", fig.best * 1e3, fig.best / unit),
                                format("r50 = %.3g um", best_um)});
    entry(kRed, true, false, {format("Rayleigh's 1.9 sqrt(f lambda): d = %.3g mm", fig.rayleigh * 1e3)});
    entry(kGreen, true, false, {"the paper's sqrt(D lambda / 2) with film width", format("D = 5f: d = %.3g mm", fig.paper * 1e3)});
    return img;
}

}  // namespace wavecam::cli
