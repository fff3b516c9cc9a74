// The scene-sum methods' frames at their edge, through the point sums: the scene beyond the frame
// is its edge continued (frame_margin.h), so a uniform wall through the incoherent sum comes back
// uniform to the last pixel, the random-phase method's border agrees with its interior within its
// own noise, border pixels agree with the convolution method's, and an overscan margin's light
// reaches the frame.
#include <gtest/gtest.h>

#include <cmath>

#include "wavecam/convolution_method.h"
#include "wavecam/spectral_diffraction.h"
#include "wavecam/scene_diffraction.h"
#include "summation_flag.h"

using namespace wavecam;

namespace {

// A wall 2 m away, 24 x 24 pixels of 50 um on a 10 mm film distance through a 0.1 mm pinhole:
// the finest fringe lambda f / d = 55 um is wider than a pixel, so one film point per pixel
// already averages the PSF (the lattice sum over a uniform wall is then its integral); its 97%
// radius R is 9 pixels and a border pixel gets about half of its light from beyond the frame.
constexpr int kSide = 24;
constexpr double kF = 10e-3, kPixel = 50e-6, kPinhole = 0.1e-3, kDepth = 2.0, kLambda = 550e-9;

PinholeCamera wall_camera(int side) {
    PinholeCamera c;
    c.width = c.height = side;
    c.fov_h = 2 * std::atan(side * kPixel / (2 * kF));
    c.film_distance = kF;
    return c;
}

// Film irradiance of a uniform radiance divided by its cos^4 law (the exposure's cos(incidence)
// times the pixel's cos^3 solid angle): the same at every pixel for a wall that fills the scene.
double flattened(const PinholeCamera& c, const std::vector<float>& irr, int i, int j) {
    return irr[size_t(j) * c.width + i] * c.cos_incidence(i, j) / c.cos4(i, j);
}

// Rows [row_begin, row_end) of the wall through `s` (the others are left zero).
std::vector<float> wall_rows(const PinholeCamera& c, SceneSumSettings s, int row_begin, int row_end,
                             const std::vector<float>& power) {
    const std::vector<float> depth(power.size(), float(kDepth));
    std::vector<float> irr(power.size(), 0.0f);
    s.row_begin = row_begin;
    s.row_end = row_end;
    auto r = diffract_monochrome({c, power.data(), depth.data(), DepthMeaning::Planar}, kLambda, s, test_device(), irr.data());
    EXPECT_TRUE(r.ok()) << r.error;
    return irr;
}

SceneSumSettings settings(CoherenceMethod method) {
    SceneSumSettings s;
    s.summation = test_summation();
    s.aperture = {ApertureShape::Circle, kPinhole};
    s.method = method;
    s.film_subsamples = 1;
    s.nthreads = 1;  // small sums: threads would mostly wait for each other
    // 72 samples across instead of 128: the lattice's grating orders, lambda / pitch = 0.40 in
    // direction sine, stay beyond the film for every source the margin holds (at most 0.25 in
    // sine plus the film's 0.085 and the PSF's spread 2 lambda / d = 0.011)
    s.sin_theta_max = kLambda * 36 / kPinhole;
    return s;
}

}  // namespace

// The top row (corners included) and the middle row (whose ends are the left and right border
// pixels) against the frame's centre. A uniform wall's film irradiance is sum_s PSF(x - x_s) over
// all sources, the same sum at every pixel of an infinite wall, whatever the film sampling. What
// the margin cannot hold is the light beyond its reach M (here one frame side, 24 pixels, 1.2 mm):
// a sharp edge's tail holds 2 lambda f / (pi^2 d s) of the power beyond s past the rim (Born &
// Wolf 8.5.2), 1.5% at s = 1.15 mm, and a 1/r tail puts 1/pi of that across a straight edge:
// 0.5% on an edge, twice that in a corner, bounds the loss (the 1/r law overstates it near the
// core). Without the margin the border pixels lose about half their light.
TEST(PointSumFrame, UniformWallThroughTheIncoherentSumIsUniformToTheLastPixel) {
    const PinholeCamera c = wall_camera(kSide);
    const std::vector<float> power(kSide * kSide, 1.0f);
    const SceneSumSettings s = settings(CoherenceMethod::Incoherent);
    const auto top = wall_rows(c, s, 0, 1, power), middle = wall_rows(c, s, kSide / 2, kSide / 2 + 1, power);
    const double centre = flattened(c, middle, kSide / 2, kSide / 2);
    double worst = 0;
    for (int i = 0; i < kSide; ++i) worst = std::max(worst, std::abs(flattened(c, top, i, 0) / centre - 1));
    for (int i : {0, 1, kSide - 2, kSide - 1})
        worst = std::max(worst, std::abs(flattened(c, middle, i, kSide / 2) / centre - 1));
    std::printf("incoherent uniform wall: worst border pixel off the centre by %.3f%%\n", 100 * worst);
    EXPECT_LT(worst, 0.005);

    // the same wall inside a dark ring: its own edge is dark, so nothing continues it
    std::vector<float> ringed = power;
    for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i)
            if (i == 0 || j == 0 || i == kSide - 1 || j == kSide - 1) ringed[size_t(j) * kSide + i] = 0;
    const auto dark = wall_rows(c, s, 1, 2, ringed);
    EXPECT_LT(flattened(c, dark, kSide / 2, 1) / centre, 0.95) << "a dark edge continues dark";
}

// The seed paper's random phases make every film point a speckle sample: the border's mean
// must agree with the interior's within their standard errors (estimated here from the pixels'
// own scatter), where a missing margin would take about half of the border's light.
TEST(PointSumFrame, RandomPhaseBorderMeanIsTheInteriorsWithinItsNoise) {
    const PinholeCamera c = wall_camera(kSide);
    const std::vector<float> power(kSide * kSide, 1.0f);
    SceneSumSettings s = settings(CoherenceMethod::RandomPhase);
    s.runs = 24;
    s.film_subsamples = 2;
    const auto irr = wall_rows(c, s, 0, kSide, power);
    double sum[2] = {0, 0}, sq[2] = {0, 0};
    int n[2] = {0, 0};
    for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i) {
            const int border = i == 0 || j == 0 || i == kSide - 1 || j == kSide - 1;
            const double v = flattened(c, irr, i, j);
            sum[border] += v;
            sq[border] += v * v;
            ++n[border];
        }
    double mean[2], error[2];
    for (int k = 0; k < 2; ++k) {
        mean[k] = sum[k] / n[k];
        error[k] = std::sqrt((sq[k] / n[k] - mean[k] * mean[k]) / (n[k] - 1));
    }
    const double sigma = std::hypot(error[0], error[1]);
    std::printf("random phase: border mean / interior mean - 1 = %.4f, standard error %.4f\n", mean[1] / mean[0] - 1,
                sigma / mean[0]);
    EXPECT_LT(std::abs(mean[1] - mean[0]), 4 * sigma);
    EXPECT_LT(sigma, 0.05 * mean[0]) << "too noisy to see a rim";
}

// Border pixels of a wall whose radiance ramps along x and steps in depth along y (so the
// continued edge differs from side to side): the exact incoherent sum against the convolution method,
// which continues the edge the same way, within the 2% the two agree to inside the frame.
TEST(PointSumFrame, BorderPixelsAgreeWithTheConvolutionMethod) {
    const PinholeCamera c = wall_camera(kSide);
    std::vector<float> rgb(3 * kSide * kSide), depth(kSide * kSide);
    for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i) {
            for (int k = 0; k < 3; ++k) rgb[3 * (j * kSide + i) + k] = 0.3f + 0.7f * i / (kSide - 1);
            depth[j * kSide + i] = j < kSide / 2 ? 2.0f : 0.5f;
        }
    const SpectralScene scene{c, rgb.data(), depth.data(), DepthMeaning::Planar};
    const Matrix3 xyz_to_709{{{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};
    const SpectralBasis basis = make_spectral_basis(explicit_sampling({kLambda}).value, xyz_to_709).value;
    const Aperture ap{ApertureShape::Circle, kPinhole};
    std::vector<float> fast(rgb.size()), exact_top(rgb.size()), exact_bottom(rgb.size());
    ASSERT_TRUE(diffract_convolution(scene, basis, ap, {false, fast.data()}).ok());
    SceneSumSettings s = settings(CoherenceMethod::Incoherent);
    for (auto [rows, out] : {std::pair{0, &exact_top}, std::pair{kSide - 1, &exact_bottom}}) {
        s.row_begin = rows;
        s.row_end = rows + 1;
        ASSERT_TRUE(diffract_spectral(scene, basis, ap, wave_propagator(s, test_device()), {false, out->data()}).ok());
    }
    double worst = 0;
    for (int i = 0; i < kSide; ++i)
        for (auto [j, exact] : {std::pair{0, &exact_top}, std::pair{kSide - 1, &exact_bottom}}) {
            const size_t p = 3 * (size_t(j) * kSide + i) + 1;
            worst = std::max(worst, std::abs(double(fast[p]) / (*exact)[p] - 1));
        }
    std::printf("border pixels, fast against exact: worst %.3f%%\n", 100 * worst);
    EXPECT_LT(worst, 0.02);
}

// An input with an overscan margin: its pixels are sources, its film is only the cropped frame.
// A bright patch in the left margin lights the frame's left column beside it (its PSF's 97%
// radius is 9 pixels); the same rows of the right column, as far from anything bright, stay at
// the dim wall's level; the margin's own film pixels are not computed.
TEST(PointSumFrame, OverscanMarginLightsTheFrameAndIsNotFilm) {
    const int o = 4;
    const PinholeCamera c = wall_camera(kSide);
    std::vector<float> power(kSide * kSide, 0.05f);
    for (int j = 10; j < 14; ++j)
        for (int i = 1; i < o; ++i) power[size_t(j) * kSide + i] = 50.0f;
    SceneSumSettings s = settings(CoherenceMethod::RandomPhase);
    s.runs = 4;
    s.overscan = o;
    const auto irr = wall_rows(c, s, 0, kSide, power);
    for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i)
            if (i < o || j < o || i >= kSide - o || j >= kSide - o) {
                ASSERT_EQ(irr[size_t(j) * kSide + i], 0.0f);
            }
    double left = 0, right = 0;
    for (int j = 10; j < 14; ++j) {
        left += flattened(c, irr, o, j);
        right += flattened(c, irr, kSide - o - 1, j);
    }
    std::printf("overscan: frame's left column beside the patch / right column = %.1f\n", left / right);
    EXPECT_GT(left / right, 10.0);
}
