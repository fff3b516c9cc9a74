// Diffracting a rendered scene at one wavelength, against the point-source image, analytic
// zone counts, ray optics (an independent shadow-casting sum written here) and the exact
// incoherent sum that the random-phase method must approach.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "one_star_scene.h"
#include "summation_flag.h"

using namespace wavecam;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

struct TestScene {
    PinholeCamera camera;
    std::vector<float> power, depth;
    explicit TestScene(const PinholeCamera& c)
        : camera(c), power(size_t(c.width) * c.height, 0.0f), depth(size_t(c.width) * c.height, 1.0f) {}
    MonochromeScene view() const { return {camera, power.data(), depth.data(), DepthMeaning::Planar}; }
    std::vector<float> diffract(double lambda, const SceneSumSettings& s) const {
        std::vector<float> out(power.size(), 0.0f);
        auto r = diffract_monochrome(view(), lambda, s, test_device(), out.data());
        EXPECT_TRUE(r.ok()) << r.error;
        return out;
    }
};

double rms_difference(const std::vector<float>& a, const std::vector<float>& b) {
    double s = 0;
    for (size_t i = 0; i < a.size(); ++i) s += std::pow(double(a[i]) - b[i], 2);
    return std::sqrt(s / a.size());
}

double rms(const std::vector<float>& a) { return rms_difference(a, std::vector<float>(a.size(), 0.0f)); }

// 3x3 box average (clamped at the border): compares light at the scale of a few pixels, where
// Fresnel ringing at the shadow's rim averages out.
std::vector<float> box3(const std::vector<float>& a, int w) {
    const int h = int(a.size()) / w;
    std::vector<float> out(a.size());
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double s = 0;
            int n = 0;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di)
                    if (i + di >= 0 && i + di < w && j + dj >= 0 && j + dj < h) {
                        s += a[(j + dj) * w + i + di];
                        ++n;
                    }
            out[j * w + i] = float(s / n);
        }
    return out;
}
}  // namespace

// One lit pixel on black is the point-source image of a source on that pixel's ray.
TEST(SceneDiffraction, OneBrightPixelIsThePointSourceImage) {
    const double f = 20e-3, lambda = 550e-9, z = 0.5;
    TestScene scene(test::small_camera(15, f, 4e-6));  // 4 um film pixels
    SceneSumSettings s;
    s.summation = test_summation();
    s.aperture = {ApertureShape::Circle, 0.2e-3};
    s.jitter = false;
    s.runs = 1;
    s.film_subsamples = 1;  // point samples at pixel centres, like the PSF image
    for (int i0 : {7, 10}) {
        std::fill(scene.power.begin(), scene.power.end(), 0.0f);
        const int j0 = 7;
        scene.power[j0 * 15 + i0] = 3.0f;
        std::fill(scene.depth.begin(), scene.depth.end(), float(z));
        const auto img = scene.diffract(lambda, s);

        double u, v;
        scene.camera.tangent(i0 + 0.5, j0 + 0.5, u, v);
        PsfParams p;
        p.summation = test_summation();
        p.aperture = s.aperture;
        p.film_distance = f;
        p.source_distance = z * std::sqrt(1 + u * u);
        p.source_angle = std::atan(u);
        p.wavelength = lambda;
        p.resolution = 15;
        p.film_size = 15 * scene.camera.pixel_pitch();
        p.sin_theta_max = lambda / (2 * scene_sample_pitch(s, scene.camera, lambda, z));
        const PsfImage psf = compute_psf(p, test_device()).value;
        // relative irradiance -> |U|^2: times the free irradiance L Omega |P|^2 / |P - C|^2
        const double px = z * u, r2 = px * px + (z + f) * (z + f);
        const double unit = 3.0 * scene.camera.solid_angle(i0, j0) * (z * z * (1 + u * u)) / r2;
        double worst = 0, peak = 0;
        for (int j = 0; j < 15; ++j)
            for (int i = 0; i < 15; ++i) {
                const int pi = i - i0 + 7;
                if (pi < 0 || pi >= 15) continue;
                const double expected = unit * psf.irradiance[j * 15 + pi];
                peak = std::max(peak, expected);
                worst = std::max(worst, std::fabs(img[j * 15 + i] - expected));
            }
        EXPECT_LT(worst / peak, one_source_bound()) << "pixel " << i0;
    }
}

// Depth enters through the zone count N = 2(sagitta_f + sagitta_z)/lambda: a source at 5 cm
// in front of a 50 mm camera spans twice the zones of one at infinity.
TEST(SceneDiffraction, DepthChangesTheZoneCountAsTheoryPredicts) {
    const double f = 50e-3, lambda = 550e-9, d = 0.315e-3, a = d / 2;
    for (double z : {kInf, 0.05}) {
        TestScene scene(test::small_camera(5, f, 10e-6));
        scene.power[12] = 1.0f;
        scene.depth[12] = std::isinf(z) ? 1e10f : float(z);
        SceneSumSettings s;
        s.summation = test_summation();
        s.aperture = {ApertureShape::Circle, d};
        s.jitter = false;
        s.runs = 1;
        s.film_subsamples = 1;
        const auto img = scene.diffract(lambda, s);
        const double n = 2 * (std::sqrt(f * f + a * a) - f + (std::isinf(z) ? 0 : std::sqrt(z * z + a * a) - z)) / lambda;
        const double free = scene.camera.solid_angle(2, 2) * (std::isinf(z) ? 1.0 : z * z / ((z + f) * (z + f)));
        const double expected = free * 4 * std::pow(std::sin(M_PI * n / 2), 2);
        EXPECT_NEAR(img[12] / free, expected / free, std::max(0.01 * expected / free, 0.01)) << "z = " << z;
    }
}

// With N >> 1 every pixel is blurred into the pinhole's shadow. The reference here is ray
// optics: film point x is lit by source P when the segment P -> x crosses the pinhole disc,
// with the spherical wave's irradiance L Omega |P|^2 / |x - P|^2.
TEST(SceneDiffraction, LargePinholeApproachesRayOptics) {
    const double f = 2e-3, lambda = 500e-9, d = 0.28e-3;  // N ~ 20
    const int w = 14;
    TestScene scene(test::small_camera(w, f, d / 4));  // film pixel = d / 4
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uni(0.2f, 1.0f);
    for (int j = 4; j < 10; ++j)
        for (int i = 4; i < 10; ++i) {
            scene.power[j * w + i] = uni(rng);
            scene.depth[j * w + i] = (i + j) % 3 == 0 ? 1e10f : 0.02f;  // sky and near points
        }
    SceneSumSettings s;
    s.summation = test_summation();
    s.aperture = {ApertureShape::Circle, d};
    s.method = CoherenceMethod::Incoherent;
    s.film_subsamples = 3;
    const auto wave = scene.diffract(lambda, s);

    std::vector<float> rays(wave.size(), 0.0f);
    const auto& cam = scene.camera;
    for (int sj = 0; sj < w; ++sj)
        for (int si = 0; si < w; ++si) {
            const float L = scene.power[sj * w + si];
            if (L <= 0) continue;
            double u, v;
            cam.tangent(si + 0.5, sj + 0.5, u, v);
            const double z = scene.depth[sj * w + si];
            const double omega = cam.solid_angle(si, sj);
            for (int j = 0; j < w; ++j)
                for (int i = 0; i < w; ++i) {
                  for (int b = 0; b < 3; ++b)
                   for (int a = 0; a < 3; ++a) {  // the same 3 x 3 points per film pixel
                    double fu, fv;
                    cam.tangent(i + (a + 0.5) / 3, j + (b + 0.5) / 3, fu, fv);
                    const double x = -f * fu, y = -f * fv;
                    double hx, hy, irr;
                    if (z >= kInfiniteDepth) {  // parallel rays along -(u, v, 1)
                        hx = x + f * u;
                        hy = y + f * v;
                        irr = L * omega;
                    } else {  // segment from P = z (u, v, 1) to (x, y, -f) crosses z = 0 at t = z / (z + f)
                        const double t = z / (z + f);
                        hx = z * u + t * (x - z * u);
                        hy = z * v + t * (y - z * v);
                        const double dx = x - z * u, dy = y - z * v, dz = -f - z;
                        irr = L * omega * z * z * (1 + u * u + v * v) / (dx * dx + dy * dy + dz * dz);
                    }
                    if (hx * hx + hy * hy <= d * d / 4) rays[j * w + i] += float(irr / 9);
                   }
                }
        }
    const auto rays_box = box3(rays, w);
    const double rel = rms_difference(box3(wave, w), rays_box) / rms(rays_box);
    EXPECT_LT(rel, 0.06);
    EXPECT_LT(rms_difference(wave, rays) / rms(rays), 0.12);  // pixel by pixel, rim ringing included

    // The same comparison for a diffraction-limited pinhole fails: the test can tell them apart.
    SceneSumSettings small = s;
    small.aperture.diameter = d / 6;
    auto narrow = scene.diffract(lambda, small);
    const double scale = std::pow(6.0, 2);  // area ratio, so both have the same total energy
    for (auto& x : narrow) x *= float(scale);
    EXPECT_GT(rms_difference(box3(narrow, w), rays_box) / rms(rays_box), 2 * rel);
}

// The seed paper's method: the random-phase average approaches the exact incoherent image and
// its error falls as 1/sqrt(K).
TEST(SceneDiffraction, RandomPhaseAverageConvergesAsOneOverRootK) {
    const double f = 5e-3, lambda = 500e-9;
    TestScene scene(test::small_camera(8, f, 40e-6));
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    // a dark frame edge: no scene beyond it (test_point_sum_frame.cpp tests that), whose margin
    // would cost 9 times the frame's sources here, where the PSF is wider than the frame
    for (size_t p = 0; p < scene.power.size(); ++p) {
        const size_t i = p % 8, j = p / 8;
        scene.power[p] = i == 0 || j == 0 || i == 7 || j == 7 ? 0.0f : uni(rng);
        scene.depth[p] = p % 5 == 0 ? 1e10f : 0.1f + uni(rng);
    }
    SceneSumSettings s;
    s.summation = test_summation();
    s.aperture = {ApertureShape::Circle, 40e-6};
    s.jitter = false;  // jitter would change the expectation itself
    s.coded_phases = false;  // the seed paper's independent phases: noise as 1/sqrt(K)
    s.film_subsamples = 1;
    s.method = CoherenceMethod::Incoherent;
    const auto exact = scene.diffract(lambda, s);
    s.method = CoherenceMethod::RandomPhase;
    auto mean_square_error = [&](int runs) {
        double e = 0;
        for (uint64_t seed = 1; seed <= 12; ++seed) {
            s.runs = runs;
            s.seed = seed;
            e += std::pow(rms_difference(scene.diffract(lambda, s), exact), 2);
        }
        return std::sqrt(e / 12);
    };
    const double e8 = mean_square_error(8), e32 = mean_square_error(32);
    EXPECT_NEAR(e8 / e32, 2.0, 0.4);
    EXPECT_LT(e32 / rms(exact), 0.25);
}

TEST(SceneDiffraction, BadPixelsAreErrorsNamingTheField) {
    TestScene scene({4, 4, 0.1, 10e-3});
    SceneSumSettings s;
    s.summation = test_summation();
    s.aperture = {ApertureShape::Circle, 50e-6};
    std::vector<float> out(16);
    scene.power[5] = std::numeric_limits<float>::quiet_NaN();
    auto r = diffract_monochrome(scene.view(), 500e-9, s, test_device(), out.data());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error.rfind("radiance: pixel (1, 1)", 0), 0u) << r.error;
    scene.power[5] = 1;
    scene.depth[6] = -2;
    r = diffract_monochrome(scene.view(), 500e-9, s, test_device(), out.data());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error.rfind("depth: pixel (2, 1)", 0), 0u) << r.error;
}

// In colour: one lit pixel gives, in XYZ, the sum over wavelengths of the point-source images
// weighted by the pixel's spectral power and the colour-matching functions.
TEST(SceneDiffraction, OneBrightPixelInColourIsTheWavelengthMixOfPsfs) {
    const test::OneStarScene star;
    const float colour[3] = {0.8f, 0.3f, 0.1f};
    const auto basis = make_spectral_basis(visible_sampling(3).value, test::kXyzTo709).value;
    const std::vector<float> xyz = star.diffract(basis, colour);
    std::vector<double> expected(xyz.size(), 0.0);
    for (int sidx = 0; sidx < 3; ++sidx) {
        const std::vector<double> psf = star.expected(basis.wavelength(sidx));
        const double power = basis.power(sidx, colour[0], colour[1], colour[2]);
        for (size_t p = 0; p < psf.size(); ++p)
            for (int k = 0; k < 3; ++k) expected[3 * p + k] += power * psf[p] * basis.xyz_per_power(sidx)[k];
    }
    double peak = 0, worst = 0;
    for (size_t k = 0; k < expected.size(); ++k) peak = std::max(peak, std::fabs(expected[k]));
    for (size_t k = 0; k < expected.size(); ++k)
        if (star.in_window(int(k / 3) % star.w)) worst = std::max(worst, std::fabs(xyz[k] - expected[k]));
    EXPECT_LT(worst / peak, one_source_bound());
}

// The default film sampling averages a large pinhole's Fresnel structure over each pixel: a
// star's energy and the mean over its shadow's inner part with the default film points agree
// within 1% with twice as many per side (one point per pixel missed by 2-3%).
TEST(SceneDiffraction, DefaultFilmSamplingAveragesFresnelStructure) {
    struct Case {
        double d, pixel;
        int w;
    };
    for (const Case& c : {Case{0.8e-3, 120e-6, 11}, Case{1.5e-3, 150e-6, 13}}) {
        const double f = 50e-3, lambda = 550e-9;
        TestScene scene(test::small_camera(c.w, f, c.pixel));
        const int mid = c.w / 2;
        scene.power[mid * c.w + mid] = 1.0f;
        std::fill(scene.depth.begin(), scene.depth.end(), 1e10f);  // a star
        SceneSumSettings s;
        s.summation = test_summation();
        s.aperture = {ApertureShape::Circle, c.d};
        s.method = CoherenceMethod::Incoherent;
        const int n = auto_film_subsamples(s.aperture, scene.camera, lambda);
        // film points closer than the finest fringe lambda f / d
        EXPECT_LT(c.pixel / n, lambda * f / c.d);
        const auto measure = [&](int sub, double& energy, double& plateau) {
            s.film_subsamples = sub;
            const auto img = scene.diffract(lambda, s);
            energy = plateau = 0;
            int inner = 0;
            for (int j = 0; j < c.w; ++j)
                for (int i = 0; i < c.w; ++i) {
                    energy += img[j * c.w + i];
                    if (std::hypot(i - mid, j - mid) * c.pixel <= 0.3 * c.d) {
                        plateau += img[j * c.w + i];
                        ++inner;
                    }
                }
            plateau /= inner;
        };
        double e_default, p_default, e_dense, p_dense;
        measure(0, e_default, p_default);
        measure(2 * n, e_dense, p_dense);
        EXPECT_NEAR(e_default, e_dense, 0.01 * e_dense) << c.d * 1e3 << " mm";
        EXPECT_NEAR(p_default, p_dense, 0.01 * p_dense) << c.d * 1e3 << " mm";
        // the plateau is the geometric irradiance L Omega to within the Fresnel ripple's average
        EXPECT_NEAR(p_dense / scene.camera.solid_angle(mid, mid), 1.0, 0.1) << c.d * 1e3 << " mm";
    }
}
