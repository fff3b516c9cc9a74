#include "wavecam/pinhole_sweep.h"

#include <algorithm>
#include <cmath>

namespace wavecam {
namespace {

// Radius (m) within which `fraction` of `total` lies, from pixel sums in rings of one pixel.
double encircled_radius(const PsfImage& img, double total, double fraction) {
    const int n = img.resolution;
    const double c = 0.5 * (n - 1), area = img.pixel_pitch * img.pixel_pitch;
    std::vector<double> ring(size_t(n), 0.0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const size_t r = size_t(std::hypot(i - c, j - c));
            if (r < ring.size()) ring[r] += img.irradiance[size_t(j) * n + i] * area;
        }
    double sum = 0;
    for (size_t r = 0; r < ring.size(); ++r) {
        if (sum + ring[r] >= fraction * total) return (r + (fraction * total - sum) / ring[r]) * img.pixel_pitch;
        sum += ring[r];
    }
    return ring.size() * img.pixel_pitch;
}

}  // namespace

Result<std::vector<SweepPoint>> sweep_pinholes(const SweepParams& p, const ProgressFn& progress) {
    if (p.count < 3) return Result<std::vector<SweepPoint>>::failure("count: expected at least 3 diameters");
    if (!(p.min_scale > 0 && p.max_scale > p.min_scale))
        return Result<std::vector<SweepPoint>>::failure("range: expected 0 < min < max");
    const double unit = std::sqrt(p.film_distance * p.wavelength);
    std::vector<SweepPoint> points;
    for (int k = 0; k < p.count; ++k) {
        SweepPoint pt;
        pt.diameter = unit * p.min_scale * std::pow(p.max_scale / p.min_scale, double(k) / (p.count - 1));
        PsfParams q;
        q.aperture = p.aperture;
        q.aperture.diameter = pt.diameter;
        q.film_distance = p.film_distance;
        q.wavelength = p.wavelength;
        q.film_size = 3.0 * std::max(2 * q.aperture.bounding_radius(), 2.44 * p.wavelength * p.film_distance / pt.diameter);
        q.resolution = p.resolution;
        // every ray between pinhole and window within theta_max (plus the pinhole's own spread)
        q.sin_theta_max = std::min(1.0, 1.5 * (0.5 * q.film_size + 0.5 * pt.diameter) / p.film_distance +
                                            p.wavelength / pt.diameter);
        q.nthreads = p.nthreads;
        ProgressFn sub;
        if (progress) sub = [&, k](double f) { return progress((k + f) / p.count); };
        auto img = compute_psf(q, ComputeDevice{}, sub);  // on the CPU
        if (!img.ok()) return Result<std::vector<SweepPoint>>::failure(img.error);
        pt.psf = std::move(img.value);
        const double total = q.aperture.area();
        pt.r50 = encircled_radius(pt.psf, total, 0.5);
        pt.r80 = encircled_radius(pt.psf, total, 0.8);
        points.push_back(std::move(pt));
    }
    return Result<std::vector<SweepPoint>>::success(std::move(points));
}

double optimal_diameter(const std::vector<SweepPoint>& points) {
    size_t m = 0;
    for (size_t k = 1; k < points.size(); ++k)
        if (points[k].r50 < points[m].r50) m = k;
    if (m == 0 || m + 1 == points.size()) return points[m].diameter;
    const double x0 = std::log(points[m - 1].diameter), x1 = std::log(points[m].diameter),
                 x2 = std::log(points[m + 1].diameter);
    const double y0 = points[m - 1].r50, y1 = points[m].r50, y2 = points[m + 1].r50;
    // vertex of the parabola through the three points
    const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1), a = (d12 - d01) / (x2 - x0);
    if (!(a > 0)) return points[m].diameter;
    // y' at the midpoint of x0, x1 is d01 = 2 a (mid - vertex)
    return std::exp(0.5 * (x0 + x1) - d01 / (2 * a));
}

}  // namespace wavecam
