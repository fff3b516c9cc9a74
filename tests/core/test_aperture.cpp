#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <vector>

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

// even_in_x / even_in_y (which let the convolution method mirror one anchor's kernels into its
// mirror image's) say yes exactly where the transmission reads the same at (-x, y) / (x, -y);
// even_across_antidiagonal (which lets the kernel summation transpose them on a square frame), where
// it reads the same at (-y, -x).
TEST(Aperture, EvenInXOrYOrAcrossTheAntidiagonalExactlyWhereTheTransmissionIs) {
    auto parsed = [](const char* text) { return parse_aperture(text, "aperture").value; };
    struct Shape {
        Aperture aperture;
        const char* what;
    };
    std::vector<Shape> shapes;
    for (const char* text : {"circle", "square", "polygon:6", "polygon:5", "polygon:5:90deg", "polygon:5:10deg",
                             "polygon:4:45deg", "polygon:3:30deg", "zoneplate:8", "sieve:8"}) {
        Aperture a = parsed(text);
        a.diameter = 1e-3;
        shapes.push_back({a, text});
    }
    // masks: one even in x only (a wedge pointing up), one in neither
    for (bool skewed : {false, true}) {
        Aperture a = parsed("mask:wedge.png");
        std::vector<float> px(8 * 6, 0.0f);
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 8; ++c) px[r * 8 + c] = std::abs(2 * c - 7) <= r + (skewed && c > 4 ? 2 : 0) ? 1 : 0;
        ASSERT_TRUE(set_aperture_mask(a, 8, 6, px, "aperture").ok());
        a.diameter = 1e-3;
        shapes.push_back({a, skewed ? "skewed wedge mask" : "wedge mask"});
    }
    for (const auto& [a, what] : shapes) {
        int odd_x = 0, odd_y = 0, odd_d = 0;
        for (int k = 0; k < 20000; ++k) {
            const double x = 0.5e-3 * std::sin(k * 1.7), y = 0.5e-3 * std::cos(k * 2.3 + 0.4);
            odd_x += a.transmission(x, y) != a.transmission(-x, y);
            odd_y += a.transmission(x, y) != a.transmission(x, -y);
            odd_d += a.transmission(x, y) != a.transmission(-y, -x);
        }
        EXPECT_EQ(a.even_across_antidiagonal(), odd_d == 0) << what << ": " << odd_d << " points differ across y = -x";
        EXPECT_EQ(a.even_in_x(), odd_x == 0) << what << ": " << odd_x << " points differ across x";
        EXPECT_EQ(a.even_in_y(), odd_y == 0) << what << ": " << odd_y << " points differ across y";
    }
    // the cases the table relies on, named
    EXPECT_TRUE(parsed("polygon:5:90deg").even_in_x());
    EXPECT_FALSE(parsed("polygon:5:90deg").even_in_y());
    EXPECT_FALSE(parsed("sieve:8").even_in_x());
    EXPECT_TRUE(parsed("polygon:8").even_across_antidiagonal());
    EXPECT_FALSE(parsed("polygon:6").even_across_antidiagonal());
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
        if (zones >= 3) {
            EXPECT_TRUE(zp.contains(r * std::sqrt(2.5 / zones), 0));
        }
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

// ---- Photon sieve ------------------------------------------------------------------------

namespace {
Aperture sieve_aperture(const std::string& text, double diameter) {
    auto a = parse_aperture(text, "aperture");
    EXPECT_TRUE(a.ok()) << a.error;
    a.value.diameter = diameter;
    return a.value;
}
}  // namespace

TEST(Aperture, DiscInCellMatchesAFineGridInAreaAndMoments) {
    // A disc of radius 1 against cells cutting it every way: inside, across one edge, across a
    // corner, holding the whole disc, missing it.
    const double cx = 0.3, cy = -0.2, a = 1.0;
    const double cells[][4] = {{-0.2, 0.4, -0.5, 0.1}, {0.9, 1.6, -0.9, 0.3}, {0.8, 1.5, 0.5, 1.2},
                               {-1.0, 1.6, -1.5, 1.0}, {1.35, 2.0, 0.0, 1.0}, {-0.75, 0.05, 0.4, 0.8}};
    for (const auto& c : cells) {
        const DiscMoments m = disc_in_cell(cx, cy, a, {c[0], c[1], c[2], c[3]});
        const int g = 2000;  // reference: midpoints of a g x g grid over the cell
        double area = 0, mx = 0, my = 0;
        const double hx = (c[1] - c[0]) / g, hy = (c[3] - c[2]) / g;
        for (int j = 0; j < g; ++j)
            for (int i = 0; i < g; ++i) {
                const double x = c[0] + (i + 0.5) * hx, y = c[2] + (j + 0.5) * hy;
                if ((x - cx) * (x - cx) + (y - cy) * (y - cy) >= a * a) continue;
                area += hx * hy;
                mx += x * hx * hy;
                my += y * hx * hy;
            }
        EXPECT_NEAR(m.area, area, 2e-5) << c[0] << " " << c[2];
        EXPECT_NEAR(m.mx, mx, 2e-5) << c[0] << " " << c[2];
        EXPECT_NEAR(m.my, my, 2e-5) << c[0] << " " << c[2];
    }
    EXPECT_NEAR(disc_in_cell(cx, cy, a, {-5, 5, -5, 5}).area, M_PI, 1e-12);
}

TEST(Aperture, PhotonSieveHolesSitOnTheOpenZonesAtOneAndAHalfZoneWidths) {
    // sieve:8 of outer diameter 0.4 mm: the zone radii written out here, r_n = R sqrt(n / 8).
    const double D = 0.4e-3, R = D / 2;
    const int N = 8;
    const Aperture ap = sieve_aperture("sieve:8", D);
    EXPECT_EQ(ap.name(), "sieve:8:1.5x:50%:1");
    const auto holes = sieve_holes(ap.sieve(), R);
    ASSERT_GT(holes.size(), 1u);
    EXPECT_DOUBLE_EQ(holes[0].radius, R / std::sqrt(8.0));  // the central zone, open
    std::map<int, int> per_zone;
    for (size_t h = 1; h < holes.size(); ++h) {
        const double rho = std::hypot(holes[h].x, holes[h].y);
        const int n = int(std::floor(N * (rho / R) * (rho / R))) + 1;  // zone holding the centre
        ASSERT_TRUE(n % 2 == 1 && n >= 3 && n <= N) << rho;
        EXPECT_NEAR(rho, R * std::sqrt((n - 0.5) / N), 1e-12 * R);
        const double width = R * (std::sqrt(double(n) / N) - std::sqrt((n - 1.0) / N));
        EXPECT_NEAR(2 * holes[h].radius, 1.5 * width, 1e-12 * R);
        ++per_zone[n];
    }
    // diameters cover half of each ring's circumference (rounded down)
    for (int n : {3, 5, 7}) {
        const double rho = R * std::sqrt((n - 0.5) / N), d = 1.5 * R * (std::sqrt(double(n) / N) - std::sqrt((n - 1.0) / N));
        EXPECT_EQ(per_zone[n], int(std::floor(0.5 * 2 * M_PI * rho / d))) << n;
    }
    EXPECT_EQ(per_zone.size(), 3u);
    // no two holes overlap, and the angles are random: the gaps along a ring vary
    for (size_t p = 0; p < holes.size(); ++p)
        for (size_t q = p + 1; q < holes.size(); ++q)
            ASSERT_GT(std::hypot(holes[p].x - holes[q].x, holes[p].y - holes[q].y), holes[p].radius + holes[q].radius);
    std::vector<double> angles;
    for (size_t h = 1; h < holes.size(); ++h)
        if (std::hypot(holes[h].x, holes[h].y) > 0.8 * R) angles.push_back(std::atan2(holes[h].y, holes[h].x));
    std::sort(angles.begin(), angles.end());
    double sum = 0, sum2 = 0;
    for (size_t k = 0; k < angles.size(); ++k) {
        const double gap = k + 1 < angles.size() ? angles[k + 1] - angles[k] : angles[0] + 2 * M_PI - angles[k];
        sum += gap;
        sum2 += gap * gap;
    }
    const double mean = sum / angles.size(), spread = std::sqrt(sum2 / angles.size() - mean * mean);
    EXPECT_GT(spread, 0.15 * mean) << angles.size() << " holes on the outer ring";
    // the seed decides the angles, the same every time
    const auto again = sieve_holes(ap.sieve(), R);
    EXPECT_EQ(again[5].x, holes[5].x);
    const auto other = sieve_holes(sieve_aperture("sieve:8:7", D).sieve(), R);
    EXPECT_NE(other[5].x, holes[5].x);
}

TEST(Aperture, PhotonSieveTransmitsTheSumOfItsHolesAreas) {
    const double D = 0.3e-3, R = D / 2;
    for (const char* text : {"sieve:8", "sieve:15:1.2x:70%:3", "sieve:40:1.9x"}) {
        const Aperture ap = sieve_aperture(text, D);
        double holes = 0;
        for (const auto& h : sieve_holes(ap.sieve(), R)) holes += M_PI * h.radius * h.radius;
        EXPECT_NEAR(ap.area() / holes, 1.0, 1e-12) << text;
        // the samples' weights at the propagators' pitch (lambda / 2 at 550 nm)
        const auto s = sample_aperture(ap, sample_pitch(550e-9));
        EXPECT_NEAR(total_weight(s) / holes, 1.0, 1e-5) << text;
        // a coarse pitch is refined to 4 samples across the smallest hole
        EXPECT_LE(sample_aperture(ap, 10e-6).pitch, ap.finest_width() / 4 * (1 + 1e-12)) << text;
    }
}

TEST(Aperture, PhotonSieveLooksUpTheSameHolesItLists) {
    // transmission() and the per-cell coverage find holes through their ring and sector; check
    // them against a plain scan of the list.
    const double D = 0.4e-3, R = D / 2;
    const Aperture ap = sieve_aperture("sieve:12:1.7x:80%:5", D);
    const auto holes = sieve_holes(ap.sieve(), R);
    auto inside = [&](double x, double y) {
        for (const auto& h : holes)
            if ((x - h.x) * (x - h.x) + (y - h.y) * (y - h.y) < h.radius * h.radius) return true;
        return false;
    };
    int open = 0;
    for (int k = 0; k < 20000; ++k) {
        const double x = 1.05 * R * std::sin(k * 1.37), y = 1.05 * R * std::cos(k * 2.91);
        ASSERT_EQ(ap.contains(x, y), inside(x, y)) << x << " " << y;
        open += inside(x, y);
    }
    EXPECT_GT(open, 2000);
    for (double cell : {0.3e-6, 7e-6, 60e-6}) {
        for (int k = 0; k < 300; ++k) {
            const double x0 = 0.9 * R * std::sin(k * 0.73), y0 = 0.9 * R * std::cos(k * 1.19);
            double cx = 0, cy = 0;
            const double c = ap.coverage(x0, x0 + cell, y0, y0 + cell, cx, cy) * cell * cell;
            DiscMoments all;
            for (const auto& h : holes) {
                const DiscMoments m = disc_in_cell(h.x, h.y, h.radius, {x0, x0 + cell, y0, y0 + cell});
                all.area += m.area;
                all.mx += m.mx;
                all.my += m.my;
            }
            ASSERT_NEAR(c, all.area, 1e-9 * cell * cell) << cell << " " << k;
            if (all.area > 0) {
                EXPECT_NEAR(cx, all.mx / all.area, 1e-9 * cell);
                EXPECT_NEAR(cy, all.my / all.area, 1e-9 * cell);
            }
        }
    }
}

TEST(Aperture, BadPhotonSievesAreRefusedNamingTheField) {
    struct Case {
        const char* text;
        const char* says;
    } cases[] = {{"sieve:0", "number of zones N"},
                 {"sieve:", "number of zones N"},
                 {"sieve:2", "N >= 3"},
                 {"sieve:8:2.5x", "at most 1.95"},
                 {"sieve:8:0x", "more than 0x"},
                 {"sieve:8:95%", "at most 90%"},
                 {"sieve:8:0.5%", "without a hole"},
                 {"sieve:8:1.5x:1.2x", "once each"},
                 {"sieve:8:-4", "seed"},
                 {"sieve:8:abc", "seed"}};
    for (const Case& c : cases) {
        const auto r = parse_aperture(c.text, "aperture");
        ASSERT_FALSE(r.ok()) << c.text;
        EXPECT_EQ(r.error.rfind("aperture: ", 0), 0u) << r.error;
        EXPECT_NE(r.error.find(c.says), std::string::npos) << c.text << ": " << r.error;
    }
    const auto full = parse_aperture("sieve:20:50%:1.2x:42", "aperture");
    ASSERT_TRUE(full.ok()) << full.error;
    EXPECT_EQ(full.value.name(), "sieve:20:1.2x:50%:42");
    EXPECT_EQ(parse_aperture(full.value.name(), "aperture").value.name(), full.value.name());
}
