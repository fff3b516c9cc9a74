// The convolution method's PSFs (fresnel_psf.cpp) against the exact Rayleigh-Sommerfeld sum of
// `wavecam psf` and the Airy pattern: shapes and absolute shares of the transmitted power, on
// and off axis, near and far. Pinholes of 1.26 and 2.5 mm at f = 50 mm are in
// test_fresnel_psf_large.cpp (heavy: their point sums take minutes).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include "exact_kernel.h"
#include "fft/column_fft.h"
#include "optics/fresnel_field.h"
#include "optics/fresnel_transfer.h"
#include "wavecam/fresnel_psf.h"

using namespace wavecam;
using namespace wavecam::test;

namespace {

std::vector<double> weights(const PsfKernel& k) { return {k.weight.begin(), k.weight.end()}; }

// Encircled shares at four radii and the totals within `tolerance` (relative) of the exact sum.
void expect_matches_exact(const FieldPsfRequest& q, int film_points, double sin_theta_max, double tolerance,
                          const char* what) {
    const auto fast = weights(field_psf_kernel(q));
    const auto exact = exact_kernel(q, film_points, sin_theta_max);
    const int R = q.radius;
    for (double r : {0.25, 0.5, 0.75, 1.0})
        EXPECT_NEAR(encircled(fast, R, r * R), encircled(exact, R, r * R), tolerance * encircled(exact, R, r * R))
            << what << ", r = " << r * R << " px";
    EXPECT_NEAR(total(fast), total(exact), tolerance * total(exact)) << what;
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
            const auto f = weights(field_psf_kernel(q));
            const auto exact = exact_kernel(q, 3, std::min(1.0, std::sin(deg * M_PI / 180 + 0.2)));
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
            EXPECT_LT(std::hypot(fx / total(f) - ex / total(exact), fy / total(f) - ey / total(exact)),
                      0.02 * airy_px)
                << deg << " deg, z = " << depth;
            // absolute shares of the transmitted power, not shapes renormalised to the window
            for (double r : {2.0, 4.0, 6.0, 9.0, 12.0})
                EXPECT_NEAR(encircled(f, 12, r), encircled(exact, 12, r), 0.02 * encircled(exact, 12, r))
                    << "r = " << r << " px, " << deg << " deg, z = " << depth;
        }
}

// The benchmark camera (512 wide, 40deg, f = 50 mm): the optimum 0.315 mm and a quarter of it,
// on axis at infinity and at 20deg at 0.5 m, with the kernel radius the convolution method uses.
TEST(FresnelPsf, SmallPinholesAt50mmMatchTheExactImage) {
    struct Case {
        double d, deg, depth;
    };
    for (const Case& c : {Case{0.08e-3, 0, INFINITY}, Case{0.08e-3, 20, 0.5}, Case{0.315e-3, 0, INFINITY},
                          Case{0.315e-3, 20, 0.5}}) {
        FieldPsfRequest q;
        q.aperture = {ApertureShape::Circle, c.d};
        q.film_distance = 50e-3;
        q.depth = c.depth;
        q.wavelength = 550e-9;
        q.u = std::tan(c.deg * M_PI / 180);
        q.pixel_pitch = pitch_512_40deg_50mm();
        q.radius = psf_kernel_radius({q.aperture, q.film_distance, c.depth, q.wavelength, std::cos(c.deg * M_PI / 180)},
                                     q.pixel_pitch, 200);
        // pinhole sampling: the window's half-diagonal over f plus the pinhole's diffraction angle
        const double window = 1.5 * (q.radius + 1) * q.pixel_pitch / q.film_distance;
        const std::string what =
            "d = " + std::to_string(c.d * 1e3) + " mm, " + std::to_string(c.deg) + " deg, z = " + std::to_string(c.depth);
        // 2 x 2 exact film points per pixel where the PSF spans many pixels (Airy radius 4.7 px)
        expect_matches_exact(q, c.d < 0.1e-3 ? 2 : 3, window + 2 * q.wavelength / c.d, 0.02, what.c_str());
    }
}

// Few zones: the kernel's sum is the Airy pattern's share inside the kernel square (far field:
// 0.02 mm at 50 mm spans 0.004 zones, 0.08 mm 0.06), cut tails and all.
TEST(FresnelPsf, KernelSumIsTheAiryShareInsideIt) {
    const double f = 50e-3, lambda = 550e-9, p = pitch_512_40deg_50mm();
    for (double d : {0.02e-3, 0.04e-3, 0.08e-3})
        for (int R : {5, 20, 60}) {
            FieldPsfRequest q;
            q.aperture = {ApertureShape::Circle, d};
            q.film_distance = f;
            q.wavelength = lambda;
            q.pixel_pitch = p;
            q.radius = R;
            const double expected = airy_in_square(d, lambda, f, (R + 0.5) * p);
            EXPECT_NEAR(total(field_psf_kernel(q).weight), expected, 0.005 * expected) << d * 1e3 << " mm, R = " << R;
        }
}

// The radius psf_kernel_radius picks holds the stated share: checked against the Airy pattern
// (far field) and the exact sum (Fresnel regime), and by the kernel itself.
TEST(FresnelPsf, KernelRadiusHoldsTheStatedEnergy) {
    const double f = 50e-3, lambda = 550e-9, p = pitch_512_40deg_50mm();
    for (double d : {0.02e-3, 0.04e-3, 0.08e-3}) {
        const Aperture ap{ApertureShape::Circle, d};
        const int R = psf_kernel_radius({ap, f, INFINITY, lambda, 1.0}, p, 1000);
        EXPECT_GE(airy_in_square(d, lambda, f, (R + 0.5) * p), kPsfKernelEnergy) << d * 1e3 << " mm";
        // and not wastefully: a kernel of half that radius holds less
        EXPECT_LT(airy_in_square(d, lambda, f, (R / 2 + 0.5) * p), kPsfKernelEnergy) << d * 1e3 << " mm";
        if (d > 0.03e-3) {  // (0.02 mm needs a 600-px radius: too slow to build here)
            FieldPsfRequest q;
            q.aperture = ap;
            q.film_distance = f;
            q.wavelength = lambda;
            q.pixel_pitch = p;
            q.radius = R;
            EXPECT_GE(total(field_psf_kernel(q).weight), kPsfKernelEnergy) << d * 1e3 << " mm";
        }
    }
    for (double d : {0.2e-3, 0.315e-3, 0.6e-3}) {
        FieldPsfRequest q;
        q.aperture = {ApertureShape::Circle, d};
        q.film_distance = f;
        q.depth = 0.3;
        q.wavelength = lambda;
        q.u = std::tan(25 * M_PI / 180);
        q.pixel_pitch = p;
        q.radius = psf_kernel_radius({q.aperture, f, q.depth, lambda, std::cos(25 * M_PI / 180)}, p, 1000);
        const auto exact = exact_kernel(q, 2, 2.0 * (q.radius + 1) * p / f + 2 * lambda / d);
        EXPECT_GE(total(exact), kPsfKernelEnergy) << d * 1e3 << " mm";
        EXPECT_NEAR(total(field_psf_kernel(q).weight), total(exact), 0.005 * total(exact)) << d * 1e3 << " mm";
    }
    EXPECT_EQ(psf_kernel_radius({{ApertureShape::Circle, 0.08e-3}, f, INFINITY, lambda, 1.0}, p, 16), 16);
}

// The two evaluations (matrix Fourier transform, transfer function) where both are affordable:
// independent sampling of the same integral, pixel by pixel.
// The matrix transform and the transfer function are independent evaluations of the same
// integral. The transfer function computes half the field of a point-symmetric pupil (circle,
// square, hexagon) and mirrors it; the pentagon takes the whole transform. Their totals inside
// the kernel differ by the far tail the transfer grid folds back (fresnel_transfer.cpp bounds it
// by 0.7%): straight edges send more of it along their normals, the square 0.44% here (0.06% on a
// grid 3x finer, measured).
TEST(FresnelPsf, BothEvaluationsAgree) {
    auto polygon = [](int sides, double d) {
        Aperture a{ApertureShape::Polygon, d};
        a.sides = sides;
        return a;
    };
    struct Pupil {
        Aperture aperture;
        double total_tolerance;
        const char* what;
    };
    const Pupil pupils[] = {{{ApertureShape::Circle, 0.6e-3}, 0.003, "circle 0.6 mm"},
                            {{ApertureShape::Circle, 1.26e-3}, 0.003, "circle 1.26 mm"},
                            {{ApertureShape::Square, 0.9e-3}, 0.006, "square 0.9 mm"},
                            {polygon(6, 1e-3), 0.004, "hexagon 1 mm"},
                            {polygon(5, 1e-3), 0.004, "pentagon 1 mm"}};
    for (const auto& [aperture, total_tolerance, what] : pupils) {
        FieldPsfRequest q;
        q.aperture = aperture;
        q.film_distance = 50e-3;
        q.depth = 0.4;
        q.wavelength = 600e-9;
        q.u = 0.3;
        q.v = -0.2;
        q.pixel_pitch = pitch_512_40deg_50mm();
        q.radius = psf_kernel_radius({q.aperture, q.film_distance, q.depth, q.wavelength, 0.85}, q.pixel_pitch, 200);
        q.method = FieldPsfMethod::MatrixFourier;
        const auto mft = weights(field_psf_kernel(q));
        q.method = FieldPsfMethod::TransferFunction;
        const auto tf = weights(field_psf_kernel(q));
        double peak = 0, worst = 0;
        for (size_t i = 0; i < mft.size(); ++i) {
            peak = std::max(peak, mft[i]);
            worst = std::max(worst, std::fabs(mft[i] - tf[i]));
        }
        EXPECT_LT(worst, 0.03 * peak) << what;
        EXPECT_NEAR(total(tf), total(mft), total_tolerance) << what;
    }
}

// A kernel narrower than the PSF (R = 6 px where 99% of it needs 14): the matrix transform's
// grid then spans the kernel square at the field's azimuth, and only the grid nodes the pixel
// averages read are computed (fresnel_mft.cpp). The outermost pixels, cut through the PSF, hold
// 2.6% of its power; each against the transfer function's (an independent evaluation on the
// whole plane) at azimuths where the square meets the grid at different angles. Computing too few
// nodes, by three grid steps, put pixels 40% low at 0deg and 7% low at 30deg.
TEST(FresnelPsf, KernelEdgesCutThroughThePsfMatchTheTransferFunctionAtEveryAzimuth) {
    for (double azimuth : {0.0, 30.0, 45.0, 60.0, 110.0}) {
        FieldPsfRequest q;
        q.aperture = {ApertureShape::Circle, 0.6e-3};
        q.film_distance = 50e-3;
        q.depth = 0.4;
        q.wavelength = 600e-9;
        const double field = std::tan(35 * M_PI / 180);
        q.u = field * std::cos(azimuth * M_PI / 180);
        q.v = field * std::sin(azimuth * M_PI / 180);
        q.pixel_pitch = pitch_512_40deg_50mm();
        q.radius = 6;
        q.method = FieldPsfMethod::MatrixFourier;
        const auto mft = weights(field_psf_kernel(q));
        q.method = FieldPsfMethod::TransferFunction;
        const auto tf = weights(field_psf_kernel(q));
        const int R = q.radius, w = 2 * R + 1;
        double edge = 0, lowest = INFINITY, highest = 0;
        for (int b = -R; b <= R; ++b)
            for (int a = -R; a <= R; ++a) {
                if (std::max(std::abs(a), std::abs(b)) != R) continue;
                const size_t i = size_t(b + R) * w + (a + R);
                edge += tf[i];
                lowest = std::min(lowest, mft[i] / tf[i]);
                highest = std::max(highest, mft[i] / tf[i]);
            }
        EXPECT_GT(edge, 0.02 * total(tf)) << azimuth << " deg: the kernel's edge should cut through the PSF";
        EXPECT_GT(lowest, 0.95) << azimuth << " deg";
        EXPECT_LT(highest, 1.05) << azimuth << " deg";
    }
}

// The camera is its own mirror image across x = 0 when the aperture is even in x, so the PSF at
// field (-u, v) is the one at (u, v) with its columns reversed: the convolution method computes
// one of each such pair of anchors and mirrors it. A pentagon with a vertex on +y is even in x
// and not in y, and its PSFs show both where its shadow shows (8 Fresnel zones; a Fraunhofer
// pattern is point-symmetric, so there the pentagon's would look even in y as well).
TEST(FresnelPsf, MirrorImageFieldsGiveMirrorImagePsfsWhereTheApertureIsEven) {
    FieldPsfRequest q;
    q.aperture = parse_aperture("polygon:5:90deg", "aperture").value;
    q.aperture.diameter = 0.6e-3;
    q.film_distance = 20e-3;
    q.depth = 1.5;
    q.wavelength = 550e-9;
    q.pixel_pitch = 40e-6;
    q.radius = 12;
    q.u = 0.5;
    q.v = 0.35;
    const auto psf = weights(field_psf_kernel(q));
    q.u = -0.5;
    const auto across_x = weights(field_psf_kernel(q));
    q.u = 0.5;
    q.v = -0.35;
    const auto across_y = weights(field_psf_kernel(q));
    const int w = 2 * q.radius + 1;
    double peak = 0, odd_x = 0, odd_y = 0;
    for (int b = 0; b < w; ++b)
        for (int e = 0; e < w; ++e) {
            peak = std::max(peak, psf[b * w + e]);
            odd_x = std::max(odd_x, std::fabs(psf[b * w + e] - across_x[b * w + (w - 1 - e)]));
            odd_y = std::max(odd_y, std::fabs(psf[b * w + e] - across_y[(w - 1 - b) * w + e]));
        }
    std::printf("mirrored across x: %.2e of the peak; across y: %.2e\n", odd_x / peak, odd_y / peak);
    EXPECT_LT(odd_x, 1e-3 * peak);  // (the evaluations' own rounding: 2e-4 measured, the method's bound 2%)
    EXPECT_GT(odd_y, 0.05 * peak);  // not even in y: the mirror image is another PSF
}

// A table's requests at one depth share their transfer grids (share_transfer_grids): a shorter
// wavelength goes on the longer one's wider grid, which changes its kernel only by the band
// edge's faint ringing, and its kernel is the same bit for bit whether its thread served other
// requests first (a spectrum on a slightly wider grid kept, the longer wavelength's on its own
// grid) or nothing.
TEST(FresnelPsf, SharedTransferGridsGiveTheSameKernelWhateverWasServedBefore) {
    FieldPsfRequest q;
    q.aperture = {ApertureShape::Circle, 2.5e-3};
    q.film_distance = 50e-3;
    q.depth = 1.0;
    q.u = 0.25;
    q.v = 0.1;
    q.pixel_pitch = pitch_512_40deg_50mm();
    q.radius = 30;
    q.method = FieldPsfMethod::TransferFunction;
    q.wavelength = 450e-9;  // a grid of 216 points alone, 240 at 620 nm
    FieldPsfRequest red = q;
    red.wavelength = 620e-9;
    std::vector<FieldPsfRequest> set = {q, red};
    share_transfer_grids(set);
    const detail::FieldGeometry g = detail::geometry_of(q);
    EXPECT_EQ(set[0].transfer_grid, detail::plan_transfer(red, g).n);
    EXPECT_GT(set[0].transfer_grid, detail::plan_transfer(q, g).n) << "one grid each: nothing shared";
    EXPECT_EQ(set[1].transfer_grid, set[0].transfer_grid);
    std::vector<double> own, alone, after_red;
    std::thread([&] { own = weights(field_psf_kernel(q)); }).join();
    std::thread([&] { alone = weights(field_psf_kernel(set[0])); }).join();
    std::thread([&] {
        FieldPsfRequest wider = q;
        wider.wavelength = 760e-9;  // a grid of 250 points alone: within kSharedGridArea of 240's
        field_psf_kernel(wider);
        field_psf_kernel(set[1]);
        after_red = weights(field_psf_kernel(set[0]));
    }).join();
    EXPECT_EQ(alone, after_red);
    double peak = 0, worst = 0;
    for (size_t i = 0; i < own.size(); ++i) {
        peak = std::max(peak, own[i]);
        worst = std::max(worst, std::fabs(own[i] - alone[i]));
    }
    EXPECT_GT(peak, 0);
    EXPECT_LT(worst, 1e-3 * peak);
    EXPECT_NEAR(total(alone), total(own), 1e-4);
}

// The transfer function's grid is periodic: its period must keep the copies of the
// band-limited chirp off every pupil point-kernel pixel pair (fresnel_transfer.cpp). A grid
// twice as wide then changes nothing but the band edge's faint ringing (up to 1e-3 of the peak
// on this camera's coarse pixels, where the pupil spans fewest grid cells): on and off axis,
// short and long wavelengths, pinholes of 4 and 16 times the optimum.
TEST(FresnelPsf, TransferGridTwiceAsWideGivesTheSameKernel) {
    for (double diameter : {1.26e-3, 5e-3})
        for (double u : {0.0, 0.7})
            for (double wavelength : {450e-9, 700e-9}) {
                FieldPsfRequest q;
                q.aperture = {ApertureShape::Circle, diameter};
                q.film_distance = 50e-3;
                q.depth = 0.5;
                q.wavelength = wavelength;
                q.u = u;
                q.v = 0.5 * u;
                q.pixel_pitch = pitch_512_40deg_50mm();
                q.radius = psf_kernel_radius({q.aperture, q.film_distance, q.depth, q.wavelength, 0.8}, q.pixel_pitch, 200);
                const detail::FieldGeometry g = detail::geometry_of(q);
                const detail::TransferPlan plan = detail::plan_transfer(q, g);
                detail::TransferPlan wide = plan;
                wide.n = detail::fft_friendly_size(2 * plan.n);
                const std::vector<float> kernel = detail::kernel_by_transfer(q, g, plan);
                const std::vector<float> reference = detail::kernel_by_transfer(q, g, wide);
                double peak = 0, worst = 0;
                for (size_t i = 0; i < kernel.size(); ++i) {
                    peak = std::max(peak, double(reference[i]));
                    worst = std::max(worst, std::fabs(double(kernel[i]) - reference[i]));
                }
                EXPECT_LT(worst, 2e-3 * peak) << diameter * 1e3 << " mm, u = " << u << ", " << wavelength * 1e9
                                              << " nm, n = " << plan.n << " and " << wide.n;
            }
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
    const auto f = weights(field_psf_kernel(q));
    // film within 0.5 mm of the axis at 20 mm, pinhole radius 0.4 mm
    const auto exact = exact_kernel(q, 3, 0.06);
    for (double r : {3.0, 6.0, 9.0, 11.0})
        EXPECT_NEAR(encircled(f, 12, r), encircled(exact, 12, r), 0.02 * encircled(exact, 12, r)) << "r = " << r;
    // outside the shadow (radius 10 px) almost nothing: no aliased copies
    EXPECT_LT(total(f) - encircled(f, 12, 11.5), 0.03);

    // Coarse pixels (the shadow 2 px across) and a wide kernel: the transform's periodic copies
    // must stay outside the kernel too.
    q.pixel_pitch = 0.4e-3;
    q.radius = 14;
    const auto coarse = weights(field_psf_kernel(q));
    EXPECT_GT(encircled(coarse, 14, 2.5), 0.97);
}
