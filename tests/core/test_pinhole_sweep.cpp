// The paper's figure: spot size against pinhole diameter has a minimum, and it lies where the
// classic optimum (Rayleigh's 1.9 sqrt(f lambda)) says, within 1.2 to 2.2 sqrt(f lambda).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "wavecam/pinhole_sweep.h"

using namespace wavecam;

TEST(PinholeSweep, SpotSizeHasItsMinimumNearTheClassicOptimum) {
    SweepParams p;
    p.film_distance = 20e-3;
    p.wavelength = 550e-9;
    p.count = 9;
    p.resolution = 61;
    const auto r = sweep_pinholes(p);
    ASSERT_TRUE(r.ok()) << r.error;
    const auto& pts = r.value;
    const double unit = std::sqrt(p.film_distance * p.wavelength);
    const double best = optimal_diameter(pts) / unit;
    std::printf("measured optimum: %.3f sqrt(f lambda)\n", best);
    EXPECT_GT(best, 1.2);
    EXPECT_LT(best, 2.2);
    // both ends are worse than the middle: diffraction below, the geometric shadow above
    double smallest = pts[0].r50;
    for (const auto& pt : pts) smallest = std::min(smallest, pt.r50);
    EXPECT_GT(pts.front().r50, 1.5 * smallest);
    EXPECT_GT(pts.back().r50, 1.5 * smallest);
    // limits: far below the optimum the spot follows the Airy pattern (r50 ~ 0.42 lambda f / a
    // for the 50% radius of an Airy disc: v = 1.62 in k a r / f), far above the shadow (r50 = a/sqrt(2))
    const double a0 = pts.front().diameter / 2, a1 = pts.back().diameter / 2;
    EXPECT_NEAR(pts.front().r50 / (1.62 * p.wavelength * p.film_distance / (2 * M_PI * a0)), 1.0, 0.15);
    EXPECT_NEAR(pts.back().r50 / (a1 / std::sqrt(2.0)), 1.0, 0.15);
}
