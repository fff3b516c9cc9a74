// References for the convolution method's PSF kernels, written independently of fresnel_psf.cpp: the
// exact Rayleigh-Sommerfeld sum of `wavecam psf` on the kernel's pixel grid, and the Airy
// pattern's power inside a square.
#pragma once
#include <cmath>
#include <vector>

#include "wavecam/fresnel_psf.h"
#include "wavecam/psf.h"

namespace wavecam::test {

// The exact PSF on the kernel's pixel grid (each pixel the sum over n x n points), as shares of
// the power through the pinhole (docs/physics.md, result 3, with the units below). The field lies in the x-z
// plane (v = 0). sin_theta_max: the point sum's pinhole sampling, lambda / (2 sin_theta_max);
// it must cover the largest angle between a pinhole point and a film point of the window.
inline std::vector<double> exact_kernel(const FieldPsfRequest& q, int n, double sin_theta_max) {
    const double theta = std::atan(q.u);
    PsfParams p;
    p.aperture = q.aperture;
    p.film_distance = q.film_distance;
    p.source_distance = std::isinf(q.depth) ? q.depth : q.depth / std::cos(theta);
    p.source_angle = theta;
    p.wavelength = q.wavelength;
    const int w = 2 * q.radius + 1;
    p.resolution = w * n;
    p.film_size = w * q.pixel_pitch;
    p.sin_theta_max = sin_theta_max;
    p.max_terms = 1e14;
    const PsfImage img = compute_psf(p, ComputeDevice{}).value;
    // Relative irradiance is |U|^2 over the source's free irradiance at the film centre (0, 0, -f);
    // the pinhole receives |P - C|^2 / |P|^2 of that, on an area seen at cos theta, and the film
    // meets the beam at cos theta too: relative irradiance integrates to area |P - C|^2 / |P|^2.
    double spread = 1.0;
    if (!std::isinf(q.depth)) {
        const double x = q.depth * q.u, z = q.depth;  // the source, planar depth z
        spread = (x * x + (z + q.film_distance) * (z + q.film_distance)) / (x * x + z * z);
    }
    const double unit = std::pow(q.pixel_pitch / n, 2) / (q.aperture.area() * spread);
    std::vector<double> k(size_t(w) * w, 0.0);
    for (int j = 0; j < w * n; ++j)
        for (int i = 0; i < w * n; ++i) k[size_t(j / n) * w + i / n] += unit * img.irradiance[size_t(j) * w * n + i];
    return k;
}

// Sum of kernel weights whose pixel centres lie within r pixels of the centre.
template <class Weights>
double encircled(const Weights& k, int radius, double r) {
    const int w = 2 * radius + 1;
    double s = 0;
    for (int b = -radius; b <= radius; ++b)
        for (int a = -radius; a <= radius; ++a)
            if (std::hypot(a, b) <= r) s += k[size_t(b + radius) * w + a + radius];
    return s;
}

template <class Weights>
double total(const Weights& k) {
    double s = 0;
    for (double x : k) s += x;
    return s;
}

// Share of the Airy pattern's power (far field, disc of diameter D) inside the square
// |x|, |y| <= H on the film: the disc of radius H holds 1 - J0(x)^2 - J1(x)^2, x = pi D H /
// (lambda f) (Born & Wolf 8.5.2); the corners add the pattern's density (pi D^2 / (4 lambda^2
// f^2)) (2 J1(x) / x)^2 over the arcs of radius r in (H, H sqrt 2) that lie inside the square,
// 8 (pi/4 - acos(H/r)) r dr.
inline double airy_in_square(double D, double lambda, double f, double H) {
    auto x_of = [&](double r) { return M_PI * D * r / (lambda * f); };
    const double xh = x_of(H);
    double share = 1 - std::pow(std::cyl_bessel_j(0, xh), 2) - std::pow(std::cyl_bessel_j(1, xh), 2);
    const int n = 20000;
    const double dr = (std::sqrt(2.0) - 1) * H / n;
    for (int i = 0; i < n; ++i) {
        const double r = H + (i + 0.5) * dr, x = x_of(r);
        const double density = M_PI * D * D / (4 * lambda * lambda * f * f) * std::pow(2 * std::cyl_bessel_j(1, x) / x, 2);
        share += density * 8 * (M_PI / 4 - std::acos(H / r)) * r * dr;
    }
    return share;
}

// Film pixel pitch of a 512-wide frame with a 40deg horizontal field at f = 50 mm.
inline double pitch_512_40deg_50mm() { return 2 * 50e-3 * std::tan(20 * M_PI / 180) / 512; }

}  // namespace wavecam::test
