// The fast path's PSFs (matrix Fourier transform about the chief ray) against the exact
// Rayleigh-Sommerfeld sum of `wavecam psf`, on and off axis, near and far.
#include <gtest/gtest.h>

#include <cmath>

#include "wavecam/fresnel_psf.h"
#include "wavecam/psf.h"

using namespace wavecam;

namespace {

// The exact PSF on the same pixel grid, each pixel averaged over n x n points, unit sum.
std::vector<double> exact_kernel(const FieldPsfRequest& q, int n) {
    const double theta = std::atan(q.u);  // tests put the field in the x-z plane (v = 0)
    PsfParams p;
    p.aperture = q.aperture;
    p.film_distance = q.film_distance;
    p.source_distance = std::isinf(q.depth) ? q.depth : q.depth / std::cos(theta);
    p.source_angle = theta;
    p.wavelength = q.wavelength;
    const int w = 2 * q.radius + 1;
    p.resolution = w * n;
    p.film_size = w * q.pixel_pitch;
    p.sin_theta_max = std::min(1.0, std::sin(theta + 0.2));
    const PsfImage img = compute_psf(p).value;
    std::vector<double> k(size_t(w) * w, 0.0);
    double total = 0;
    for (int j = 0; j < w * n; ++j)
        for (int i = 0; i < w * n; ++i) {
            k[size_t(j / n) * w + i / n] += img.irradiance[size_t(j) * w * n + i];
            total += img.irradiance[size_t(j) * w * n + i];
        }
    for (double& x : k) x /= total;
    return k;
}

double encircled(const std::vector<double>& k, int radius, double r) {
    const int w = 2 * radius + 1;
    double s = 0;
    for (int b = -radius; b <= radius; ++b)
        for (int a = -radius; a <= radius; ++a)
            if (std::hypot(a, b) <= r) s += k[size_t(b + radius) * w + a + radius];
    return s;
}

}  // namespace

TEST(FresnelPsf, MatchesTheExactPointSourceImage) {
    for (double depth : {double(INFINITY), 0.1})
        for (double deg : {0.0, 30.0, 50.0}) {
            FieldPsfRequest q;
            q.aperture = {ApertureShape::Circle, 0.2e-3};  // the optimum 1.9 sqrt(f lambda)
            q.film_distance = 20e-3;
            q.depth = depth;
            q.wavelength = 550e-9;
            q.u = std::tan(deg * M_PI / 180);
            q.pixel_pitch = 15e-6;
            q.radius = 12;
            const PsfKernel fast = field_psf_kernel(q);
            std::vector<double> f(fast.weight.begin(), fast.weight.end());
            const auto exact = exact_kernel(q, 3);
            // centroid (the peak position) within 2% of the PSF's Airy radius
            double fx = 0, fy = 0, ex = 0, ey = 0;
            for (int b = -12; b <= 12; ++b)
                for (int a = -12; a <= 12; ++a) {
                    const size_t i = size_t(b + 12) * 25 + a + 12;
                    fx += a * f[i];
                    fy += b * f[i];
                    ex += a * exact[i];
                    ey += b * exact[i];
                }
            const double airy_px = 1.22 * q.wavelength * q.film_distance / q.aperture.diameter / q.pixel_pitch;
            EXPECT_LT(std::hypot(fx - ex, fy - ey), 0.02 * airy_px) << deg << " deg, z = " << depth;
            for (double r : {2.0, 4.0, 6.0, 9.0})
                EXPECT_NEAR(encircled(f, 12, r), encircled(exact, 12, r), 0.02 * encircled(exact, 12, r))
                    << "r = " << r << " px, " << deg << " deg, z = " << depth;
        }
}

TEST(FresnelPsf, KernelRadiusCoversShadowAndRings) {
    const Aperture ap{ApertureShape::Circle, 0.2e-3};
    // shadow 0.1 mm x (1 + 20/100) + 5 Airy radii 0.335 mm, / 15 um = 30.4 px on axis
    EXPECT_EQ(psf_kernel_radius(ap, 20e-3, 0.1, 550e-9, 1.0, 15e-6, 64), 31);
    EXPECT_EQ(psf_kernel_radius(ap, 20e-3, 0.1, 550e-9, 1.0, 15e-6, 16), 16);
}

// Four times the optimum: 14 Fresnel zones across the pinhole, the geometric regime. The pupil
// grid must follow the quadratic phase or aliased copies of the PSF appear.
TEST(FresnelPsf, LargePinholeMatchesTheExactImage) {
    FieldPsfRequest q;
    q.aperture = {ApertureShape::Circle, 0.8e-3};
    q.film_distance = 20e-3;
    q.wavelength = 550e-9;
    q.pixel_pitch = 40e-6;
    q.radius = 12;
    const PsfKernel fast = field_psf_kernel(q);
    std::vector<double> f(fast.weight.begin(), fast.weight.end());
    PsfParams p;
    p.aperture = q.aperture;
    p.film_distance = q.film_distance;
    p.wavelength = q.wavelength;
    p.resolution = 25 * 3;
    p.film_size = 25 * q.pixel_pitch;
    p.sin_theta_max = 0.06;  // film within 0.5 mm of the axis at 20 mm, pinhole radius 0.4 mm
    const PsfImage img = compute_psf(p).value;
    std::vector<double> exact(25 * 25, 0.0);
    double total = 0;
    for (int j = 0; j < 75; ++j)
        for (int i = 0; i < 75; ++i) {
            exact[size_t(j / 3) * 25 + i / 3] += img.irradiance[size_t(j) * 75 + i];
            total += img.irradiance[size_t(j) * 75 + i];
        }
    for (double& x : exact) x /= total;
    for (double r : {3.0, 6.0, 9.0, 11.0})
        EXPECT_NEAR(encircled(f, 12, r), encircled(exact, 12, r), 0.02 * encircled(exact, 12, r)) << "r = " << r;
    // outside the shadow (radius 10 px) almost nothing: no aliased copies
    EXPECT_LT(1.0 - encircled(f, 12, 11.5), 0.03);

    // Coarse pixels (the shadow 2 px across) and a wide kernel: the transform's periodic copies
    // must stay outside the kernel too.
    q.pixel_pitch = 0.4e-3;
    q.radius = 14;
    const PsfKernel coarse = field_psf_kernel(q);
    std::vector<double> k(coarse.weight.begin(), coarse.weight.end());
    EXPECT_GT(encircled(k, 14, 2.5), 0.97);
}
