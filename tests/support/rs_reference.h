// An independent reference for a star's image at any field: the Rayleigh-Sommerfeld integral
// (first kind, Goodman, Introduction to Fourier Optics, eq. 3-41) summed directly over a
// circular pinhole, in double precision, written here without any of core's optics:
//   U(T) = sum_xi A(xi) exp(i k (r1 + r2)) / (r1 r2) * (f / r2) dA,
//   r1 = |P - xi| (a point source P; a plane wave from direction P: exp(-i k P.xi)),
//   r2 = |T - xi|, the film at z = -f, the pinhole in z = 0,
// and the film's irradiance |U|^2 (f / |T|) (the flux through the film's plane), averaged over
// n x n points of each film pixel. A(xi) is each cell's open fraction of the disc. Path
// differences are taken as (|x - xi|^2 - |x|^2) / (|x - xi| + |x|), which does not cancel.
#pragma once
#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "wavecam/pinhole_camera.h"

namespace wavecam::test {

struct RsStar {
    PinholeCamera camera;
    double diameter = 0;     // the pinhole's, m
    double depth = INFINITY;  // planar depth of the star, m (inf: a plane wave)
    double wavelength = 550e-9;
    int i = 0, j = 0;  // the star's pixel; its source sits at the pixel's centre
};

// The film's irradiance on the (2 half + 1)^2 output pixels centred on pixel (s.i, s.j) (the
// output is upright, as wavecam writes it), each pixel the mean over n x n points; arbitrary
// scale (compare shapes).
inline std::vector<double> rs_window(const RsStar& s, int half, int n) {
    const PinholeCamera& c = s.camera;
    const double k = 2 * M_PI / s.wavelength, f = c.film_distance, a = 0.5 * s.diameter;
    double u0, v0;
    c.tangent(s.i + 0.5, s.j + 0.5, u0, v0);
    // the source: P = z (u0, v0, 1), or the plane wave's unit direction toward it
    const bool plane = std::isinf(s.depth);
    const double pn = std::sqrt(1 + u0 * u0 + v0 * v0);
    const double px = plane ? u0 / pn : s.depth * u0, py = plane ? v0 / pn : s.depth * v0,
                 pz = plane ? 1 / pn : s.depth;
    const double p_len = std::sqrt(px * px + py * py + pz * pz);
    // the aperture's cells: fine enough that the phase turns by at most pi/4 across one, for
    // film points up to `half` pixels (plus one) off the image
    double uw, vw;
    c.tangent(s.i + 0.5 + half + 1, s.j + 0.5 + half + 1, uw, vw);
    const double tilt = std::hypot(uw / std::sqrt(1 + uw * uw + vw * vw) - u0 / pn,
                                   vw / std::sqrt(1 + uw * uw + vw * vw) - v0 / pn);
    const double gradient = k * (tilt + a * (1 / f + (plane ? 0 : 1 / s.depth)));
    const int cells = std::max(64, int(std::ceil(2 * a * gradient / (M_PI / 4))));
    const double h = 2 * a / cells;
    std::vector<double> xs, ys, open;
    for (int m = 0; m < cells; ++m)
        for (int l = 0; l < cells; ++l) {
            const double x = (-0.5 * (cells - 1) + l) * h, y = (-0.5 * (cells - 1) + m) * h;
            int in = 0;
            for (int b = 0; b < 8; ++b)
                for (int e = 0; e < 8; ++e)
                    in += std::hypot(x + ((e + 0.5) / 8 - 0.5) * h, y + ((b + 0.5) / 8 - 0.5) * h) <= a;
            if (in == 0) continue;
            xs.push_back(x);
            ys.push_back(y);
            open.push_back(in / 64.0);
        }
    // the incident field on each cell
    std::vector<std::complex<double>> incident(xs.size());
    for (size_t q = 0; q < xs.size(); ++q) {
        if (plane) {
            incident[q] = open[q] * std::polar(1.0, -k * (px * xs[q] + py * ys[q]));
        } else {
            const double rho2 = xs[q] * xs[q] + ys[q] * ys[q] - 2 * (px * xs[q] + py * ys[q]);
            const double r1 = std::sqrt(p_len * p_len + rho2);
            incident[q] = open[q] / r1 * std::polar(1.0, k * rho2 / (r1 + p_len));
        }
    }
    const int w = 2 * half + 1;
    std::vector<double> out(size_t(w) * w, 0.0);
#pragma omp parallel for schedule(dynamic)
    for (int pixel_row = 0; pixel_row < w; ++pixel_row) {  // (a pixel row per thread: no shared sums)
        for (int row = pixel_row * n; row < (pixel_row + 1) * n; ++row)
        for (int col = 0; col < w * n; ++col) {
            double u, v;
            c.tangent(s.i - half + (col + 0.5) / n, s.j - half + (row + 0.5) / n, u, v);
            // output pixels are upright: the film point is the geometric image of that ray
            const double tx = -f * u, ty = -f * v, tz = -f, t_len = std::sqrt(tx * tx + ty * ty + tz * tz);
            std::complex<double> sum = 0;
            for (size_t q = 0; q < xs.size(); ++q) {
                const double rho2 = xs[q] * xs[q] + ys[q] * ys[q] - 2 * (tx * xs[q] + ty * ys[q]);
                const double r2 = std::sqrt(t_len * t_len + rho2);
                sum += incident[q] * std::polar(f / (r2 * r2), k * rho2 / (r2 + t_len));
            }
            out[size_t(row / n) * w + col / n] += std::norm(sum) * f / t_len;
        }
    }
    return out;
}

}  // namespace wavecam::test
