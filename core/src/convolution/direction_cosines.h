// Direction cosines in units of the pitch on the axis ("axis pixels"). Internal to core.
//
// a = (u, v) / (pitch sqrt(1 + u^2 + v^2)) for tangent-plane (u, v). In them a PSF is one function
// of a_film - a_source for every source (Fraunhofer optics: a planar pupil sends a plane wave from
// n_in to the directions n as its transform at (n - n_in)_transverse / lambda), and a film pixel
// at (u, v) covers cos^4 = (1 + u^2 + v^2)^-2 of an axis pixel (its area's Jacobian). The disc
// |a| < 1 / pitch holds every direction.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "wavecam/pinhole_camera.h"

namespace wavecam::detail {

struct DirectionCosines {
    double pitch;  // the tangent of one pixel on the axis (PinholeCamera::tan_pitch)
    void of_tangent(double u, double v, double& ax, double& ay) const {
        const double n = pitch * std::sqrt(1 + u * u + v * v);
        ax = u / n;
        ay = v / n;
    }
    // false beyond the disc
    bool to_tangent(double ax, double ay, double& u, double& v) const {
        const double x = ax * pitch, y = ay * pitch, r2 = 1 - x * x - y * y;
        if (r2 <= 0) return false;
        u = x / std::sqrt(r2);
        v = y / std::sqrt(r2);
        return true;
    }
};

// The tangents u of the camera pixel columns [x0, x0 + count) and v of the rows [y0, y0 + count),
// at their centres (PinholeCamera::tangent's, one axis at a time).
inline std::vector<double> column_tangents(const PinholeCamera& c, int x0, int count) {
    std::vector<double> u(size_t(std::max(0, count)));
    double unused;
    for (int i = 0; i < count; ++i) c.tangent(x0 + i + 0.5, 0.5, u[i], unused);
    return u;
}
inline std::vector<double> row_tangents(const PinholeCamera& c, int y0, int count) {
    std::vector<double> v(size_t(std::max(0, count)));
    double unused;
    for (int j = 0; j < count; ++j) c.tangent(0.5, y0 + j + 0.5, unused, v[j]);
    return v;
}

// The extremes of the direction cosines (axis pixels, a right and b up) over the centres of camera
// pixels [x0, x0 + width) x [y0, y0 + height): they lie on its border, a and b being monotone in
// u and v.
struct DirectionBox {
    double lo_a = INFINITY, hi_a = -INFINITY, lo_b = INFINITY, hi_b = -INFINITY;
};
inline DirectionBox direction_box(const PinholeCamera& c, const DirectionCosines& dc, int x0, int y0, int width,
                                  int height) {
    DirectionBox box;
    auto border = [&](int i, int j) {
        double u, v, ax, ay;
        c.tangent(x0 + i + 0.5, y0 + j + 0.5, u, v);
        dc.of_tangent(u, v, ax, ay);
        box.lo_a = std::min(box.lo_a, ax), box.hi_a = std::max(box.hi_a, ax);
        box.lo_b = std::min(box.lo_b, ay), box.hi_b = std::max(box.hi_b, ay);
    };
    for (int i = 0; i < width; ++i) border(i, 0), border(i, height - 1);
    for (int j = 0; j < height; ++j) border(0, j), border(width - 1, j);
    return box;
}

}  // namespace wavecam::detail
