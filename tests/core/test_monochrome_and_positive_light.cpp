// Monochromatic light (the seed paper's setting) and non-negative spectra through the scene-sum
// methods: a grey star at one wavelength against the point-source image at that wavelength, and
// saturated colours that must not come out as negative light.
#include <gtest/gtest.h>

#include <cmath>

#include "one_star_scene.h"
#include "summation_flag.h"

using namespace wavecam;
using test::kXyzTo709;

TEST(Monochrome, OneOrTwoWavelengthsGiveAMonochromeBasisAndCloseOnesToo) {
    for (const std::vector<double>& l : std::vector<std::vector<double>>{
             {550e-9}, {540e-9, 560e-9}, {549e-9, 550e-9, 551e-9}}) {
        const auto b = make_spectral_basis(explicit_sampling(l).value, kXyzTo709);
        ASSERT_TRUE(b.ok()) << b.error;
        EXPECT_TRUE(b.value.monochrome()) << l.size();
        EXPECT_NE(b.value.description().find("monochrome"), std::string::npos);
    }
    // asked for: even a colour-capable list is monochrome
    const auto asked = make_spectral_basis(visible_sampling(8).value, kXyzTo709, true);
    ASSERT_TRUE(asked.ok());
    EXPECT_TRUE(asked.value.monochrome());
    EXPECT_FALSE(make_spectral_basis(visible_sampling(8).value, kXyzTo709).value.monochrome());
}

// A grey star at 550 nm: every output channel is the point-source image at 550 nm, as
// compute_psf makes it, times the star's grey level.
TEST(Monochrome, GreyStarAtOneWavelengthIsThePsfInEveryChannel) {
    const test::OneStarScene star;
    const double lambda = 550e-9;
    const float grey = 0.7f, rgb[3] = {grey, grey, grey};
    const auto basis = make_spectral_basis(explicit_sampling({lambda}).value, kXyzTo709);
    ASSERT_TRUE(basis.ok()) << basis.error;
    const std::vector<float> xyz = star.diffract(basis.value, rgb);
    const std::vector<double> psf = star.expected(lambda);
    double peak = 0, worst = 0;
    for (int p = 0; p < star.w * star.w; ++p) {
        if (!star.in_window(p % star.w)) continue;
        const double expected = grey * psf[p];
        const Vector3 out = multiply(kXyzTo709, {xyz[3 * p], xyz[3 * p + 1], xyz[3 * p + 2]});
        peak = std::max(peak, expected);
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(out[k] - expected));
    }
    EXPECT_GT(peak, 0);
    EXPECT_LT(worst / peak, one_source_bound());
}

// Saturated primaries and secondaries as isolated stars on black, 8 wavelengths: every
// spectral power is non-negative, so one random-phase run (K = 1, the noisiest) never makes
// negative light - XYZ >= 0 at every pixel - and the expected image (the exact incoherent sum)
// has no negative channel in the working space. (Single runs can dip below zero in RGB where
// speckle leaves a pixel lit by a narrow band of wavelengths whose colour lies outside the
// working gamut; averaging K runs removes it as the speckle does.)
TEST(PositiveLight, SaturatedColoursThroughTheSceneSumMethodsStayNonNegative) {
    const double f = 20e-3, z = 0.3;
    const int w = 12;
    const PinholeCamera cam = test::small_camera(w, f, 25e-6);  // about the Airy radius: sharp fringes
    std::vector<float> rgb(3 * w * w, 0.0f), depth(w * w, float(z));
    const float colours[6][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};
    for (int j = 0; j < w; ++j)
        for (int i = 0; i < w; ++i)
            if (i % 3 == 1 && j % 3 == 1)  // isolated saturated stars on black
                for (int k = 0; k < 3; ++k) rgb[3 * (j * w + i) + k] = colours[(i / 3 + j / 3) % 6][k];
    const auto basis = make_spectral_basis(visible_sampling(8).value, kXyzTo709);
    ASSERT_TRUE(basis.ok());
    for (int s = 0; s < basis.value.size(); ++s)
        for (int p = 0; p < 3; ++p) ASSERT_GE(basis.value.power(s, p == 0, p == 1, p == 2), 0.0) << s << " " << p;
    for (auto method : {CoherenceMethod::RandomPhase, CoherenceMethod::Incoherent}) {
        SceneSumSettings s;
        s.summation = test_summation();
        s.aperture = {ApertureShape::Circle, 0.2e-3};
        s.runs = 1;
        s.method = method;
        std::vector<float> xyz(3 * w * w);
        ASSERT_TRUE(diffract_spectral({cam, rgb.data(), depth.data(), DepthMeaning::Planar}, basis.value, s.aperture,
                                      wave_propagator(s, test_device()), {true, xyz.data()})
                        .ok());
        double lowest_xyz = 0, lowest_rgb = 0, brightest = 0;
        for (int p = 0; p < w * w; ++p) {
            const Vector3 c{xyz[3 * p], xyz[3 * p + 1], xyz[3 * p + 2]};
            const Vector3 out = multiply(kXyzTo709, c);
            for (int k = 0; k < 3; ++k) {
                lowest_xyz = std::min(lowest_xyz, c[k]);
                lowest_rgb = std::min(lowest_rgb, out[k]);
                brightest = std::max(brightest, out[k]);
            }
        }
        EXPECT_GE(lowest_xyz, 0.0);
        if (method == CoherenceMethod::Incoherent) {
            EXPECT_GE(lowest_rgb, -1e-6 * brightest);
        }
    }
}
