// Monochromatic light (the seed paper's setting) and non-negative spectra through the exact
// method: a grey star at one wavelength against the point-source image at that wavelength, and
// saturated colours that must not come out as negative light.
#include <gtest/gtest.h>

#include <cmath>

#include "wavecam/psf.h"
#include "wavecam/spectral_diffraction.h"

using namespace wavecam;

namespace {
// XYZ -> linear Rec.709 (IEC 61966-2-1)
const Matrix3 kXyzTo709{{{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};

PinholeCamera small_camera(int w, double f, double film_pixel) {
    PinholeCamera cam;
    cam.width = cam.height = w;
    cam.fov_h = 2 * std::atan(w * film_pixel / (2 * f));
    cam.film_distance = f;
    return cam;
}
}  // namespace

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
    const double f = 20e-3, z = 0.3, lambda = 550e-9;
    const int w = 9, i0 = 5, j0 = 4;
    const PinholeCamera cam = small_camera(w, f, 5e-6);
    std::vector<float> rgb(3 * w * w, 0.0f), depth(w * w, float(z));
    const float grey = 0.7f;
    for (int k = 0; k < 3; ++k) rgb[3 * (j0 * w + i0) + k] = grey;
    const auto basis = make_spectral_basis(explicit_sampling({lambda}).value, kXyzTo709);
    ASSERT_TRUE(basis.ok()) << basis.error;
    DiffractionSettings s;
    s.aperture = {ApertureShape::Circle, 0.2e-3};
    s.jitter = false;
    s.runs = 1;
    s.film_subsamples = 1;
    std::vector<float> xyz(3 * w * w);
    ASSERT_TRUE(diffract_spectral({cam, rgb.data(), depth.data(), DepthMeaning::Planar}, basis.value, s.aperture,
                                  wave_propagator(s), true, xyz.data())
                    .ok());

    double u, v;
    cam.tangent(i0 + 0.5, j0 + 0.5, u, v);
    PsfParams p;
    p.aperture = s.aperture;
    p.film_distance = f;
    p.source_distance = z * std::sqrt(1 + u * u + v * v);
    p.source_angle = std::atan(u);  // v = 0: the lit pixel sits on the middle row
    p.wavelength = lambda;
    p.resolution = w;
    p.film_size = w * f * cam.tan_pitch();
    p.sin_theta_max = p.wavelength / (2 * scene_sample_pitch(s, cam, p.wavelength, z));
    const PsfImage psf = compute_psf(p).value;
    // relative irradiance -> film irradiance: the star's L Omega |P|^2 / |P - C|^2, then the
    // camera's exposure and the film's cos(incidence)
    const double px = z * u, r2 = px * px + (z + f) * (z + f);
    const double unit = grey * cam.solid_angle(i0, j0) * z * z * (1 + u * u) / r2 * exposure_scale(s.aperture, f);
    double peak = 0, worst = 0;
    for (int j = 0; j < w; ++j)
        for (int i = 0; i < w; ++i) {
            const int pi = i - i0 + w / 2;  // the PSF window is centred on the star
            if (pi < 0 || pi >= w) continue;
            const double expected = unit * psf.irradiance[j * w + pi] * cam.cos_incidence(i, j);
            const Vector3 out = multiply(kXyzTo709, {xyz[3 * (j * w + i)], xyz[3 * (j * w + i) + 1], xyz[3 * (j * w + i) + 2]});
            peak = std::max(peak, expected);
            for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(out[k] - expected));
        }
    EXPECT_GT(peak, 0);
    EXPECT_LT(worst / peak, 1e-3);
}

// Saturated primaries and secondaries as isolated stars on black, 8 wavelengths: every
// spectral power is non-negative, so one random-phase run (K = 1, the noisiest) never makes
// negative light - XYZ >= 0 at every pixel - and the expected image (the exact incoherent sum)
// has no negative channel in the working space. (Single runs can dip below zero in RGB where
// speckle leaves a pixel lit by a narrow band of wavelengths whose colour lies outside the
// working gamut; averaging K runs removes it as the speckle does.)
TEST(PositiveLight, SaturatedColoursThroughTheExactMethodStayNonNegative) {
    const double f = 20e-3, z = 0.3;
    const int w = 12;
    const PinholeCamera cam = small_camera(w, f, 25e-6);  // about the Airy radius: sharp fringes
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
        DiffractionSettings s;
        s.aperture = {ApertureShape::Circle, 0.2e-3};
        s.runs = 1;
        s.method = method;
        std::vector<float> xyz(3 * w * w);
        ASSERT_TRUE(diffract_spectral({cam, rgb.data(), depth.data(), DepthMeaning::Planar}, basis.value, s.aperture,
                                      wave_propagator(s), true, xyz.data())
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
        if (method == CoherenceMethod::Incoherent) EXPECT_GE(lowest_rgb, -1e-6 * brightest);
    }
}
