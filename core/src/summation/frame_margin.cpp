#include "summation/frame_margin.h"

#include <algorithm>
#include <cmath>

#include "convolution/far_tail.h"
#include "wavecam/fresnel_psf.h"

namespace wavecam::detail {
namespace {

struct Interval {
    int begin, end;
};

// One axis of the margin beyond the camera's [0, n): intervals from the camera's edge out to
// `reach` beyond the output frame [o, n - o), single pixels out to `rho` beyond the frame, then
// no wider than a quarter of their distance past rho.
std::vector<Interval> outside_intervals(int n, int o, int reach, int rho) {
    std::vector<Interval> out;
    auto width = [rho](int distance) { return std::max(1, (distance - rho) / 4); };
    for (int end = 0; end > o - reach;) {
        const int begin = std::max(o - reach, end - width(o - end + 1));
        out.push_back({begin, end});
        end = begin;
    }
    for (int begin = n; begin < n - o + reach;) {
        const int end = std::min(n - o + reach, begin + width(begin - (n - o) + 1));
        out.push_back({begin, end});
        begin = end;
    }
    return out;
}

}  // namespace

MarginRadii margin_radii(const Aperture& aperture, const PinholeCamera& c, int o, double nearest, double wavelength) {
    MarginRadii m;
    const int out_w = c.width - 2 * o, out_h = c.height - 2 * o, side = std::max(out_w, out_h);
    const double pitch = c.film_distance * c.tan_pitch();
    // R as the convolution method finds it: the kernel radius over the frame widened by R itself
    double cos_widened = 1;
    for (int pass = 0; pass < 2; ++pass) {
        cos_widened = c.cos_widest(o - m.kernel, o - m.kernel, o + out_w + m.kernel, o + out_h + m.kernel);
        m.kernel = psf_kernel_radius({aperture, c.film_distance, nearest, wavelength, cos_widened}, pitch, side);
    }
    m.reach = std::min(kTailReach * m.kernel, side);
    // the shadow (span / 2)(1 + f / z), stretched 1 / cos^3 radially off axis (fresnel_psf.h)
    const double shadow = aperture.bounding_radius() * (1 + c.film_distance / nearest);
    m.rho = int(std::ceil(shadow / (pitch * std::pow(cos_widened, 3)))) + 1;
    return m;
}

std::vector<MarginCell> margin_cells(const PinholeCamera& c, int o, int reach, int rho) {
    std::vector<MarginCell> cells;
    const auto xs = outside_intervals(c.width, o, reach, rho);
    const auto ys = outside_intervals(c.height, o, reach, rho);
    auto edge = [](const Interval& i, int n) { return std::clamp(i.begin, 0, n - 1); };
    for (const Interval& x : xs)
        for (int j = 0; j < c.height; ++j) cells.push_back({x.begin, x.end, j, j + 1, edge(x, c.width), j});
    for (const Interval& y : ys)
        for (int i = 0; i < c.width; ++i) cells.push_back({i, i + 1, y.begin, y.end, i, edge(y, c.height)});
    for (const Interval& x : xs)
        for (const Interval& y : ys)
            cells.push_back({x.begin, x.end, y.begin, y.end, edge(x, c.width), edge(y, c.height)});
    return cells;
}

double block_solid_angle(const PinholeCamera& c, double x0, double x1, double y0, double y1) {
    auto corner = [&c](double x, double y) {
        double u, v;
        c.tangent(x, y, u, v);
        return std::atan(u * v / std::sqrt(1 + u * u + v * v));
    };
    // v decreases as y grows: the signs make the result positive
    return -(corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0));
}

}  // namespace wavecam::detail
