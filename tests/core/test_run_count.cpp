// The random-phase run count chosen from the PSF's size (run_count.h): the PSF's area against
// the Airy pattern and the pinhole's shadow worked out here, the stretch at wide fields, and
// what the count promises. That the count converges on a real frame: tests/io/test_phase_code_noise.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "wavecam/run_count.h"

using namespace wavecam;

namespace {
const Aperture kCircle{ApertureShape::Circle, 0.2e-3};

PinholeCamera camera(int side, double fov_deg) { return {side, side, fov_deg * M_PI / 180, 50e-3}; }

// The Airy disc's radius: the first zero of J1, 3.8317, at k a sin(theta) on the film f away.
double airy_radius(double lambda, double diameter, double f) { return 3.8317 / M_PI * lambda * f / diameter; }
}  // namespace

// On a narrow frame the area is the Airy disc's plus the shadow's, the shadow of a 0.2 mm hole
// cast by a point 2 m away on a film 50 mm behind it (similar triangles: 0.1 mm x 2.05 / 2).
TEST(RunCount, NarrowFramePsfIsTheAiryDiscAndTheShadow) {
    const PinholeCamera c = camera(64, 2.5);
    const RunCount r = runs_for_convergence(c, kCircle, 690e-9, 8, 2.0);
    const double pitch = 50e-3 * 2 * std::tan(1.25 * M_PI / 180) / 64;
    const double airy = airy_radius(690e-9, 0.2e-3, 50e-3), shadow = 0.1e-3 * (2.0 + 0.05) / 2.0;
    // the widest field here is 1.77 deg: its 1/cos^4 is 1.002
    EXPECT_NEAR(r.psf_pixels, M_PI * (airy * airy + shadow * shadow) / (pitch * pitch), 0.01 * r.psf_pixels);
}

// At a wide field the Airy part is stretched 1/cos^3 radially and 1/cos tangentially at the
// frame's corner, the shadow not at all.
TEST(RunCount, WideFrameTakesTheCornersStretchedAiryDisc) {
    const PinholeCamera c = camera(256, 90);
    const RunCount r = runs_for_convergence(c, kCircle, 690e-9, 8, INFINITY);
    const double corner = std::atan(std::tan(M_PI / 4) * std::sqrt(2.0) * 255.0 / 256.0);  // the corner pixel's edge: 54.7 deg
    const double pitch = 50e-3 * 2.0 / 256, airy = airy_radius(690e-9, 0.2e-3, 50e-3), shadow = 0.1e-3;
    const double expected =
        M_PI * (airy * airy / std::pow(std::cos(corner), 4) + shadow * shadow) / (pitch * pitch);
    EXPECT_NEAR(r.psf_pixels, expected, 0.02 * expected);
    EXPECT_GT(r.psf_pixels, 2 * runs_for_convergence(camera(256, 10), kCircle, 690e-9, 8, INFINITY).psf_pixels *
                                std::pow(std::tan(5 * M_PI / 180) / std::tan(M_PI / 4), 2));
}

// PSFs of a few pixels keep the 64 runs that hold them within 2%; larger PSFs take more, never
// fewer, in steps of 16; where the price caps the count the expected noise is beyond the count's
// aim, and below the cap within it. Fewer wavelengths per channel need more runs.
TEST(RunCount, RunsGrowWithThePsfUpToThePrice) {
    int previous = 0;
    for (double fov : {20.0, 10.0, 5.0, 2.5, 1.2, 0.6, 0.3}) {
        const RunCount r = runs_for_convergence(camera(96, fov), kCircle, 690e-9, 8, 2.0);
        std::printf("fov %4.1f deg: PSF %7.0f pixels, %4d runs, expected noise %.2f%%\n", fov, r.psf_pixels, r.runs,
                    100 * r.expected_noise);
        EXPECT_GE(r.runs, previous);
        EXPECT_EQ(r.runs % 16, 0);
        EXPECT_GE(r.runs, kMinRuns);
        EXPECT_LE(r.runs, kMaxRuns);
        if (!r.capped) {
            EXPECT_LE(r.expected_noise, kRunNoiseAim + 1e-9) << fov;
        }
        previous = r.runs;
    }
    EXPECT_EQ(runs_for_convergence(camera(96, 20), kCircle, 690e-9, 8, 2.0).runs, kMinRuns);
    const RunCount huge = runs_for_convergence(camera(96, 0.3), kCircle, 690e-9, 3, 2.0);
    EXPECT_EQ(huge.runs, kMaxRuns);
    EXPECT_TRUE(huge.capped);
    EXPECT_GT(huge.expected_noise, kRunNoiseAim);
    EXPECT_GT(runs_for_convergence(camera(96, 2.5), kCircle, 690e-9, 3, 2.0).runs,
              runs_for_convergence(camera(96, 2.5), kCircle, 690e-9, 16, 2.0).runs);
}
