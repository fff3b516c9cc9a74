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
    const auto r = parse_aperture("hexagon", "aperture");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error.find("aperture"), std::string::npos);
    EXPECT_NE(r.error.find("polygon:N"), std::string::npos) << r.error;
}

TEST(Aperture, BadPolygonsAndZonePlatesNameTheField) {
    for (const char* bad : {"polygon:2", "polygon:", "polygon:six", "polygon:5:10", "zoneplate:0", "zoneplate:",
                            "zoneplate:-3", "mask:", "circle:3"}) {
        const auto r = parse_aperture(bad, "aperture");
        ASSERT_FALSE(r.ok()) << bad;
        EXPECT_EQ(r.error.rfind("aperture", 0), 0u) << r.error;
    }
    EXPECT_NE(parse_aperture("polygon:2", "aperture").error.find("number of sides N"), std::string::npos);
    EXPECT_NE(parse_aperture("zoneplate:0", "aperture").error.find("number of zones N"), std::string::npos);
}

TEST(Aperture, ParsesEveryShapeAndNamesItBack) {
    const auto p = parse_aperture("polygon:6:15deg", "aperture");
    ASSERT_TRUE(p.ok()) << p.error;
    EXPECT_EQ(p.value.shape, ApertureShape::Polygon);
    EXPECT_EQ(p.value.sides, 6);
    EXPECT_NEAR(p.value.rotation, 15 * M_PI / 180, 1e-12);
    EXPECT_EQ(p.value.name(), "polygon:6:15deg");
    const auto z = parse_aperture("zoneplate:12", "aperture");
    ASSERT_TRUE(z.ok());
    EXPECT_EQ(z.value.zones, 12);
    EXPECT_EQ(z.value.name(), "zoneplate:12");
    EXPECT_EQ(parse_aperture("mask:a:b.png", "aperture").value.mask_file, "a:b.png");
}

TEST(Aperture, RegularPolygonHasAVertexOnPlusXAtZeroRotation) {
    const double d = 1e-3, r = d / 2;
    const Aperture square_on_vertex{ApertureShape::Polygon, d, 4, 0.0};
    EXPECT_TRUE(square_on_vertex.contains(0.99 * r, 0));  // the vertex
    EXPECT_FALSE(square_on_vertex.contains(0.8 * r, 0.3 * r));  // |x| + |y| > r: outside the diamond
    EXPECT_TRUE(square_on_vertex.contains(0.6 * r, 0.3 * r));
    // polygon:4:45deg is the axis-aligned square of side d / sqrt 2
    const Aperture turned{ApertureShape::Polygon, d, 4, M_PI / 4};
    const Aperture square{ApertureShape::Square, d / std::sqrt(2.0)};
    for (int k = 0; k < 2000; ++k) {
        const double x = r * std::sin(k * 1.7), y = r * std::cos(k * 2.3);
        if (std::fabs(std::fabs(x) - r / std::sqrt(2.0)) < 1e-9 * r || std::fabs(std::fabs(y) - r / std::sqrt(2.0)) < 1e-9 * r)
            continue;
        ASSERT_EQ(turned.contains(x, y), square.contains(x, y)) << x << " " << y;
    }
}

TEST(Aperture, PolygonAndZonePlateWeightsAddUpToTheirAreas) {
    const double d = 40e-6, r = d / 2;
    for (int n : {3, 5, 6, 8}) {
        const Aperture ap{ApertureShape::Polygon, d, n, 0.3};
        // area of a regular n-gon: n/2 r^2 sin(2 pi / n)
        const double area = 0.5 * n * r * r * std::sin(2 * M_PI / n);
        EXPECT_NEAR(ap.area() / area, 1.0, 1e-12);
        EXPECT_NEAR(total_weight(sample_aperture(ap, 0.25e-6)) / area, 1.0, 2e-4) << n;
    }
    for (int zones : {1, 4, 7}) {
        const Aperture zp{ApertureShape::ZonePlate, d, 0, 0.0, zones};
        // odd zones, each of area pi r^2 / N
        const double open = M_PI * r * r / zones * ((zones + 1) / 2);
        EXPECT_NEAR(total_weight(sample_aperture(zp, 0.1e-6)) / open, 1.0, 1e-3) << zones;
        // radius r_n = r sqrt(n / N): just inside r_1 is open, just outside is shut (unless N = 1)
        const double r1 = r / std::sqrt(double(zones));
        EXPECT_TRUE(zp.contains(0.999 * r1, 0));
        EXPECT_FALSE(zp.contains(1.001 * r1, 0));  // zone 2 shut, or outside when N = 1
        if (zones >= 3) EXPECT_TRUE(zp.contains(r * std::sqrt(2.5 / zones), 0));
    }
}

TEST(Aperture, MaskIsBoxSampledWithItsWidthSpanningTheDiameter) {
    // 4 x 2 mask, 1 mm wide: pixels 0.25 mm square; rows 0.25 mm, so it is 0.5 mm tall.
    Aperture ap{ApertureShape::Mask, 1e-3};
    ap.mask_file = "test";
    ASSERT_TRUE(set_aperture_mask(ap, 4, 2, {1, 0, 0, 0.5f, 0, 0, 0, 0.25f}, "aperture").ok());
    EXPECT_DOUBLE_EQ(ap.transmission(-0.4e-3, 0.1e-3), 1.0);   // top-left pixel
    EXPECT_DOUBLE_EQ(ap.transmission(0.4e-3, 0.1e-3), 0.5);    // top-right
    EXPECT_DOUBLE_EQ(ap.transmission(0.4e-3, -0.1e-3), 0.25);  // bottom-right
    EXPECT_DOUBLE_EQ(ap.transmission(0.4e-3, 0.3e-3), 0.0);    // above the image
    // power through: sum t^2 x pixel area
    EXPECT_NEAR(ap.area(), (1 + 0.25 + 0.0625) * 0.0625e-6, 1e-18);
    // amplitude-weighted sample weights: sum t x pixel area
    EXPECT_NEAR(total_weight(sample_aperture(ap, 0.07e-3)), (1 + 0.5 + 0.25) * 0.0625e-6, 1e-12);
    EXPECT_NEAR(ap.bounding_radius(), std::hypot(0.5e-3, 0.25e-3), 1e-12);
}

TEST(Aperture, AllBlackOrOutOfRangeMaskIsRefusedNamingTheFile) {
    Aperture ap{ApertureShape::Mask, 1e-3};
    ap.mask_file = "black.png";
    auto r = set_aperture_mask(ap, 2, 2, {0, 0, 0, 0}, "aperture");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error.find("black.png"), std::string::npos);
    EXPECT_NE(r.error.find("no light"), std::string::npos);
    EXPECT_FALSE(set_aperture_mask(ap, 2, 1, {0.5f, 1.5f}, "aperture").ok());
}
