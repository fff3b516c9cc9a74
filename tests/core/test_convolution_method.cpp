// The convolution method against the exact incoherent sum on small scenes with depth changes, colour
// and occlusion edges (a near square over a far textured plane), inside a black border so that
// the frame's edge (continued beyond the frame by the convolution method, absent from the exact sum)
// carries no light; then the frame's edge itself, seams, overscan and the plan.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "wavecam/convolution_method.h"
#include "wavecam/spectral_diffraction.h"

using namespace wavecam;

namespace {
// XYZ -> linear Rec.709 (IEC 61966-2-1); any invertible matrix serves the basis
const Matrix3 kXyzTo709{{{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};

struct Scene {
    PinholeCamera cam;
    std::vector<float> rgb, depth;
};

Scene occlusion_scene(int w, double fov, double f, double far, double near, int border) {
    Scene s;
    s.cam.width = s.cam.height = w;
    s.cam.fov_h = fov;
    s.cam.film_distance = f;
    s.rgb.resize(3 * w * w);
    s.depth.resize(w * w);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    for (int j = 0; j < w; ++j)
        for (int i = 0; i < w; ++i) {
            const size_t p = size_t(j) * w + i;
            const bool square = i >= w / 4 && i < w / 2 + 2 && j >= w / 3 && j < (3 * w) / 4;
            s.depth[p] = float(square ? near : (i > w / 2 + 2 ? 1e10 : far));  // a strip of sky too
            const bool dark = i < border || j < border || i >= w - border || j >= w - border;
            const float t = dark ? 0.0f : ((i / 3 + j / 3) % 2) ? 1.0f : 0.2f;
            s.rgb[3 * p + 0] = square ? 0.9f : t * uni(rng);
            s.rgb[3 * p + 1] = square ? 0.2f : 0.5f * t;
            s.rgb[3 * p + 2] = square ? 0.1f : dark ? 0.0f : 1.0f - 0.5f * t;
        }
    return s;
}
}  // namespace

TEST(ConvolutionMethod, AgreesWithTheExactIncoherentSum) {
    const double f = 2e-3;
    const int w = 18;
    const Scene sc = occlusion_scene(w, 2 * std::atan(w * 15e-6 / (2 * f)), f, 0.05, 0.005, 4);
    const auto basis = make_spectral_basis(visible_sampling(3).value, kXyzTo709).value;
    const Aperture ap{ApertureShape::Circle, 1.9 * std::sqrt(f * 550e-9)};
    const SpectralScene scene{sc.cam, sc.rgb.data(), sc.depth.data(), DepthMeaning::Planar};

    SceneSumSettings exact;
    exact.aperture = ap;
    exact.method = CoherenceMethod::Incoherent;
    exact.film_subsamples = 3;  // film pixels averaged over their area, as the convolution kernels are
    std::vector<float> reference(3 * w * w), fast(3 * w * w);
    ASSERT_TRUE(diffract_spectral(scene, basis, ap, wave_propagator(exact, ComputeDevice{}), {true, reference.data()}).ok());
    ConvolutionSettings fs;
    fs.tile = 4;           // several tiles and anchor cells, so overlap-add and interpolation are exercised
    fs.anchor_cells = 3;
    ASSERT_TRUE(diffract_convolution(scene, basis, ap, {true, fast.data()}, fs).ok());

    double err = 0, ref = 0;
    for (size_t k = 0; k < fast.size(); ++k) {
        err += std::pow(double(fast[k]) - reference[k], 2);
        ref += std::pow(double(reference[k]), 2);
    }
    EXPECT_LT(std::sqrt(err / ref), 0.02);
    std::printf("fast vs exact: relative RMS %.4f\n", std::sqrt(err / ref));
    // no 9 x 9 block worse than 5%
    for (int by = 0; by < w; by += 9)
        for (int bx = 0; bx < w; bx += 9) {
            double e = 0, r = 0;
            for (int j = by; j < by + 9; ++j)
                for (int i = bx; i < bx + 9; ++i)
                    for (int q = 0; q < 3; ++q) {
                        const size_t k = 3 * (size_t(j) * w + i) + q;
                        e += std::pow(double(fast[k]) - reference[k], 2);
                        r += std::pow(double(reference[k]), 2);
                    }
            EXPECT_LT(std::sqrt(e / r), 0.05) << "block " << bx << "," << by;
        }
}

// A pinhole whose kernels are wide against the frame makes the whole domain one tile, its kernel
// groups spread over the threads, each with its own arrays or all sharing one set: the same
// image every run, and, within float rounding, the image that tiles of twice the kernel radius
// give (their kernel spectra kept and shared, each tile's anchors applied one at a time: the
// other path through the same sum), and tiles of one kernel radius (their passes every third
// tile, the same image every run).
TEST(ConvolutionMethod, AWholeDomainTileGivesTheSameImageEveryRunAndWhatTilesGive) {
    const double f = 2e-3;
    const int w = 40;
    const Scene sc = occlusion_scene(w, 2 * std::atan(w * 15e-6 / (2 * f)), f, 0.05, 0.005, 0);
    const auto basis = make_spectral_basis(visible_sampling(3).value, kXyzTo709).value;
    const Aperture ap{ApertureShape::Circle, 0.25 * std::sqrt(f * 550e-9)};  // far below the optimum
    const SpectralScene scene{sc.cam, sc.rgb.data(), sc.depth.data(), DepthMeaning::Planar};
    ConvolutionSettings whole;
    whole.tile = 1 << 20;  // a tile wider than the domain: the domain's
    whole.nthreads = 4;
    whole.anchor_cells = 3;
    const ConvolutionPlanSpec spec{sc.cam, 0, ap, basis, 1 / 0.005, whole};
    const int R = ConvolutionPlan::kernel_radius(spec);
    ASSERT_GT(2 * R, w / 2) << "kernels wide against the frame";
    ConvolutionSettings tiled = whole;
    tiled.tile = 2 * R;
    ConvolutionSettings narrow = whole;  // tiles of R: every third in a pass (pass_period)
    narrow.tile = R;
    ConvolutionSettings shared = whole;
    shared.tile_memory = 0;  // one set of the tile's arrays for all threads
    std::vector<float> first(3 * w * w), again(3 * w * w), tiles(3 * w * w), one_set(3 * w * w), one_again(3 * w * w),
        narrow_tiles(3 * w * w), narrow_again(3 * w * w);
    ASSERT_TRUE(diffract_convolution(scene, basis, ap, {true, first.data()}, whole).ok());
    ASSERT_TRUE(diffract_convolution(scene, basis, ap, {true, again.data()}, whole).ok());
    ASSERT_TRUE(diffract_convolution(scene, basis, ap, {true, tiles.data()}, tiled).ok());
    ASSERT_TRUE(diffract_convolution(scene, basis, ap, {true, narrow_tiles.data()}, narrow).ok());
    ASSERT_TRUE(diffract_convolution(scene, basis, ap, {true, narrow_again.data()}, narrow).ok());
    ASSERT_TRUE(diffract_convolution(scene, basis, ap, {true, one_set.data()}, shared).ok());
    ASSERT_TRUE(diffract_convolution(scene, basis, ap, {true, one_again.data()}, shared).ok());
    EXPECT_EQ(first, again);
    EXPECT_EQ(one_set, one_again);
    EXPECT_EQ(narrow_tiles, narrow_again);
    double largest = 0;
    for (float v : first) largest = std::max(largest, double(v));
    ASSERT_GT(largest, 0);
    for (size_t k = 0; k < first.size(); ++k) {
        ASSERT_NEAR(first[k], tiles[k], 1e-5 * largest) << "value " << k;
        ASSERT_NEAR(one_set[k], tiles[k], 1e-5 * largest) << "value " << k;
        ASSERT_NEAR(narrow_tiles[k], tiles[k], 1e-5 * largest) << "value " << k;
    }
}
