#include "wavecam/aperture.h"

#include <algorithm>
#include <cmath>

namespace wavecam {

double Aperture::area() const {
    return shape == ApertureShape::Circle ? M_PI * diameter * diameter / 4.0 : diameter * diameter;
}

bool Aperture::contains(double x, double y) const {
    const double r = diameter / 2.0;
    return shape == ApertureShape::Circle ? x * x + y * y < r * r : std::fabs(x) < r && std::fabs(y) < r;
}

double Aperture::coverage(double x0, double x1, double y0, double y1, double& cx, double& cy) const {
    const double r = diameter / 2.0;
    cx = 0.5 * (x0 + x1);
    cy = 0.5 * (y0 + y1);
    if (shape == ApertureShape::Square) {
        const double ox0 = std::max(x0, -r), ox1 = std::min(x1, r);
        const double oy0 = std::max(y0, -r), oy1 = std::min(y1, r);
        if (ox1 <= ox0 || oy1 <= oy0) return 0.0;
        cx = 0.5 * (ox0 + ox1);
        cy = 0.5 * (oy0 + oy1);
        return (ox1 - ox0) * (oy1 - oy0) / ((x1 - x0) * (y1 - y0));
    }
    // Circle: nearest and farthest points of the cell from the centre decide the easy cases.
    const double nx = std::clamp(0.0, x0, x1), ny = std::clamp(0.0, y0, y1);
    if (nx * nx + ny * ny >= r * r) return 0.0;
    const double fx = std::max(std::fabs(x0), std::fabs(x1)), fy = std::max(std::fabs(y0), std::fabs(y1));
    if (fx * fx + fy * fy <= r * r) return 1.0;
    constexpr int kSub = 16;
    int inside = 0;
    double sx = 0, sy = 0;
    for (int j = 0; j < kSub; ++j)
        for (int i = 0; i < kSub; ++i) {
            const double px = x0 + (x1 - x0) * (i + 0.5) / kSub;
            const double py = y0 + (y1 - y0) * (j + 0.5) / kSub;
            if (px * px + py * py < r * r) {
                ++inside;
                sx += px;
                sy += py;
            }
        }
    if (inside == 0) return 0.0;
    cx = sx / inside;
    cy = sy / inside;
    return double(inside) / (kSub * kSub);
}

Result<ApertureShape> parse_aperture_shape(const std::string& name, const std::string& field) {
    if (name == "circle") return Result<ApertureShape>::success(ApertureShape::Circle);
    if (name == "square") return Result<ApertureShape>::success(ApertureShape::Square);
    return Result<ApertureShape>::failure(field + ": expected 'circle' or 'square', got '" + name + "'");
}

double sample_pitch(double wavelength, double sin_theta_max) {
    return wavelength / (2.0 * std::clamp(sin_theta_max, 1e-6, 1.0));
}

double estimate_sample_count(const Aperture& aperture, double pitch) {
    return aperture.area() / (pitch * pitch);
}

ApertureSamples sample_aperture(const Aperture& aperture, double pitch) {
    ApertureSamples s;
    s.pitch = pitch;
    const long n = static_cast<long>(std::ceil(aperture.diameter / (2.0 * pitch))) + 1;
    const size_t reserve = static_cast<size_t>(estimate_sample_count(aperture, pitch) * 1.05) + 16;
    s.x.reserve(reserve);
    s.y.reserve(reserve);
    s.weight.reserve(reserve);
    const double cell = pitch * pitch;
    for (long j = -n; j <= n; ++j)
        for (long i = -n; i <= n; ++i) {
            double cx, cy;
            const double c = aperture.coverage((i - 0.5) * pitch, (i + 0.5) * pitch, (j - 0.5) * pitch,
                                               (j + 0.5) * pitch, cx, cy);
            if (c <= 0.0) continue;
            s.x.push_back(static_cast<float>(cx));
            s.y.push_back(static_cast<float>(cy));
            s.weight.push_back(static_cast<float>(c * cell));
        }
    return s;
}

}  // namespace wavecam
