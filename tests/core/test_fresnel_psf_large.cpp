// The convolution method's PSFs for large pinholes (many Fresnel zones, the transfer-function
// evaluation) against the exact Rayleigh-Sommerfeld sum: 1.26 and 2.5 mm at f = 50 mm, 4 and 8
// times the optimum, on axis and at 20deg. Heavy: the point sums take about a minute each.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "exact_kernel.h"
#include "wavecam/fresnel_psf.h"

using namespace wavecam;
using namespace wavecam::test;

TEST(FresnelPsfLarge, LargePinholesAt50mmMatchTheExactImage) {
    for (double d : {1.26e-3, 2.5e-3})
        for (double deg : {0.0, 20.0}) {
            FieldPsfRequest q;
            q.aperture = {ApertureShape::Circle, d};
            q.film_distance = 50e-3;
            q.depth = deg > 0 ? 0.5 : INFINITY;
            q.wavelength = 550e-9;
            q.u = std::tan(deg * M_PI / 180);
            q.pixel_pitch = pitch_512_40deg_50mm();
            const double cos_theta = std::cos(deg * M_PI / 180);
            q.radius =
                psf_kernel_radius({q.aperture, q.film_distance, q.depth, q.wavelength, cos_theta}, q.pixel_pitch, 200);
            const std::vector<float> fast = field_psf_kernel(q).weight;
            // pinhole sampling: the largest angle between a pinhole point and a window point
            const double window = (1.5 * (q.radius + 1) * q.pixel_pitch + 0.5 * d) / q.film_distance;
            const auto exact = exact_kernel(q, 3, window);
            const std::string what = std::to_string(d * 1e3) + " mm, " + std::to_string(deg) + " deg";
            // Inside the shadow the point sum's 3 x 3 film points per pixel sample Fresnel ripples
            // finer than themselves (11 um at 2.5 mm), so its inner radii carry ~1% of noise.
            const int R = q.radius;
            for (double r : {0.25, 0.5, 0.75, 1.0})
                EXPECT_NEAR(encircled(fast, R, r * R), encircled(exact, R, r * R), 0.02 * encircled(exact, R, r * R))
                    << what << ", r = " << r * R << " px";
            EXPECT_NEAR(total(fast), total(exact), 0.005 * total(exact)) << what;
            EXPECT_GE(total(exact), kPsfKernelEnergy) << what;
        }
}
