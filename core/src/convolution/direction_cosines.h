// Direction cosines in units of the pitch on the axis ("axis pixels"). Internal to core.
//
// a = (u, v) / (pitch sqrt(1 + u^2 + v^2)) for tangent-plane (u, v). In them a PSF is one function
// of a_film - a_source for every source (Fraunhofer optics: a planar pupil sends a plane wave from
// n_in to the directions n as its transform at (n - n_in)_transverse / lambda), and a film pixel
// at (u, v) covers cos^4 = (1 + u^2 + v^2)^-2 of an axis pixel (its area's Jacobian). The disc
// |a| < 1 / pitch holds every direction.
#pragma once
#include <cmath>

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

}  // namespace wavecam::detail
