#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "wavecam/aperture.h"

using namespace wavecam;

namespace {
double total_weight(const ApertureSamples& s) {
    return std::accumulate(s.weight.begin(), s.weight.end(), 0.0);
}
}  // namespace

TEST(Aperture, PitchIsHalfAWavelengthOrWiderForANarrowField) {
    EXPECT_DOUBLE_EQ(sample_pitch(550e-9), 275e-9);
    EXPECT_DOUBLE_EQ(sample_pitch(550e-9, 0.5), 550e-9);
}

TEST(Aperture, CircleWeightsAddUpToItsArea) {
    for (double d : {10e-6, 47e-6, 0.2e-3}) {
        const Aperture ap{ApertureShape::Circle, d};
        const auto s = sample_aperture(ap, sample_pitch(550e-9));
        EXPECT_NEAR(total_weight(s) / (M_PI * d * d / 4), 1.0, 1e-4) << "d = " << d;
        // every sample lies inside the disc
        for (size_t i = 0; i < s.size(); ++i) ASSERT_LE(std::hypot(s.x[i], s.y[i]), d / 2 * (1 + 1e-6));
    }
}

TEST(Aperture, SquareWeightsAddUpToItsArea) {
    const Aperture ap{ApertureShape::Square, 30.1e-6};
    const auto s = sample_aperture(ap, 1e-6);
    EXPECT_NEAR(total_weight(s), 30.1e-6 * 30.1e-6, 1e-6 * 30.1e-6 * 30.1e-6);
}

TEST(Aperture, SamplesAreCentredSoTheFirstMomentVanishes) {
    const Aperture ap{ApertureShape::Circle, 50e-6};
    const auto s = sample_aperture(ap, 0.3e-6);
    double mx = 0, my = 0;
    for (size_t i = 0; i < s.size(); ++i) {
        mx += s.weight[i] * s.x[i];
        my += s.weight[i] * s.y[i];
    }
    EXPECT_NEAR(mx / total_weight(s), 0.0, 1e-12);
    EXPECT_NEAR(my / total_weight(s), 0.0, 1e-12);
}

TEST(Aperture, UnknownShapeIsAnError) {
    const auto r = parse_aperture_shape("hexagon", "aperture");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error.find("aperture"), std::string::npos);
}
