// Colour: the CIE 1931 fit against the CIE table, the shipped OCIO config against the
// standard matrices, and the spectral round trip RGB -> spectra -> XYZ -> RGB.
#include <gtest/gtest.h>

#include <cmath>

#include "wavecam/colour_pipeline.h"
#include "wavecam/spectral_diffraction.h"
#include "wavecam/spectrum.h"

using namespace wavecam;

namespace {
const std::string kConfig = std::string(WAVECAM_SOURCE_DIR) + "/ocio_configs/wavecam.ocio";

ColourConfig config() {
    auto c = load_colour_config(kConfig);
    EXPECT_TRUE(c.ok()) << c.error;
    return c.value;
}
}  // namespace

// CIE 1931 2-degree table (CIE 15:2004, 5 nm table) at a few wavelengths. The fit's stated
// accuracy is a few percent of each function's peak (x 1.06, y 1.0, z 1.78).
TEST(Cie1931, FitFollowsTheTable) {
    struct Row {
        double nm, x, y, z;
    } table[] = {{450, 0.33620, 0.03800, 1.77211}, {500, 0.00490, 0.32300, 0.27200},
                 {550, 0.43345, 0.99495, 0.00875}, {600, 1.06220, 0.63100, 0.00080},
                 {650, 0.28350, 0.10700, 0.00000}};
    for (const Row& r : table) {
        const Vector3 c = cie1931_cmf(r.nm * 1e-9);
        EXPECT_NEAR(c[0], r.x, 0.03 * 1.06) << r.nm;
        EXPECT_NEAR(c[1], r.y, 0.03) << r.nm;
        EXPECT_NEAR(c[2], r.z, 0.03 * 1.78) << r.nm;
    }
}

TEST(ColourConfigTest, LinearRec709MatchesTheStandardMatrix) {
    const auto m = config().xyz_to_rgb_matrix("lin_rec709");
    ASSERT_TRUE(m.ok()) << m.error;
    // IEC 61966-2-1 XYZ -> linear sRGB
    const double expected[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(m.value[i][j], expected[i][j], 2e-3) << i << "," << j;
}

TEST(ColourConfigTest, WhiteIsD65AndStaysWhiteInAcescg) {
    const ColourConfig c = config();
    const Matrix3 to709 = c.xyz_to_rgb_matrix("lin_rec709").value;
    const Matrix3 white_xyz_m = inverse(to709);
    const Vector3 xyz = multiply(white_xyz_m, {1, 1, 1});
    const double sum = xyz[0] + xyz[1] + xyz[2];
    EXPECT_NEAR(xyz[0] / sum, 0.3127, 1e-3);
    EXPECT_NEAR(xyz[1] / sum, 0.3290, 1e-3);
    float px[3] = {float(xyz[0]), float(xyz[1]), float(xyz[2])};
    ASSERT_TRUE(c.convert_from_xyz(px, 1, "ACEScg").ok());
    for (float v : px) EXPECT_NEAR(v, 1.0, 2e-3);
}

TEST(ColourConfigTest, ErrorsNameTheConfigAndTheSpace) {
    auto missing = load_colour_config("/nonexistent/wavecam.ocio");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error.find("/nonexistent/wavecam.ocio"), std::string::npos);
    auto bad = config().xyz_to_rgb_matrix("NoSuchSpace");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error.find("NoSuchSpace"), std::string::npos);
    auto nonlinear = config().xyz_to_rgb_matrix("sRGB");
    ASSERT_FALSE(nonlinear.ok());
    EXPECT_NE(nonlinear.error.find("not linear"), std::string::npos);
}

// RGB -> spectrum -> XYZ (sum over samples) -> RGB through OCIO is the identity.
TEST(SpectralBasisTest, RoundTripReturnsTheInputRgb) {
    const ColourConfig c = config();
    const float colours[][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0.02f, 0.9f, 0.1f}, {0.18f, 0.18f, 0.18f},
                                {4.0f, 2.5f, 0.3f}};
    std::vector<SpectralSampling> samplings;
    for (int n : {3, 8, 16, 31}) samplings.push_back(visible_sampling(n).value);
    samplings.push_back(explicit_sampling({440e-9, 470e-9, 530e-9, 560e-9, 610e-9, 660e-9}).value);
    for (const std::string space : {"lin_rec709", "ACEScg"}) {
        const Matrix3 m = c.xyz_to_rgb_matrix(space).value;
        for (const auto& sampling : samplings) {
            const auto basis = make_spectral_basis(sampling, m);
            ASSERT_TRUE(basis.ok()) << basis.error;
            for (const auto& rgb : colours) {
                double xyz[3] = {0, 0, 0};
                for (int s = 0; s < basis.value.size(); ++s) {
                    const double p = basis.value.power(s, rgb[0], rgb[1], rgb[2]);
                    for (int k = 0; k < 3; ++k) xyz[k] += p * basis.value.xyz_per_power(s)[k];
                }
                float out[3] = {float(xyz[0]), float(xyz[1]), float(xyz[2])};
                ASSERT_TRUE(c.convert_from_xyz(out, 1, space).ok());
                for (int k = 0; k < 3; ++k)
                    EXPECT_NEAR(out[k], rgb[k], 1e-4) << space << " S=" << sampling.wavelength.size();
            }
        }
    }
}

// The same round trip through the spectral diffraction layer with an ideal (delta) propagator
// that puts each pixel's light on its own film pixel at the camera's exposure.
TEST(SpectralBasisTest, IdealPropagatorGivesBackTheImage) {
    const ColourConfig c = config();
    const auto basis = make_spectral_basis(visible_sampling(16).value, c.xyz_to_rgb_matrix("lin_rec709").value);
    PinholeCamera cam;
    cam.width = 3;
    cam.height = 2;
    cam.fov_h = 1.0;
    cam.film_distance = 50e-3;
    const std::vector<float> rgb = {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0.02f, 0.9f, 0.1f, 0.5f, 0.5f, 0.5f};
    const std::vector<float> depth(6, 1.0f);
    const Aperture ap{ApertureShape::Circle, 0.3e-3};
    MonochromePropagator ideal = [&](const MonochromeScene& scene, double, float* irr, const ProgressFn&) {
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i)
                irr[j * 3 + i] += float(scene.power[j * 3 + i] / exposure_scale(ap, cam.film_distance) *
                                        cam.cos4(i, j) / cam.cos_incidence(i, j));
        return Result<bool>::success(true);
    };
    std::vector<float> xyz(18);
    ASSERT_TRUE(diffract_spectral({cam, rgb.data(), depth.data(), DepthMeaning::Planar}, basis.value, ap, ideal, false,
                                  xyz.data())
                    .ok());
    ASSERT_TRUE(c.convert_from_xyz(xyz.data(), 6, "lin_rec709").ok());
    for (size_t k = 0; k < 18; ++k) EXPECT_NEAR(xyz[k], rgb[k], 1e-4) << k;
}

TEST(SpectralBasisTest, TooFewWavelengthsAreAnError) {
    const auto r = make_spectral_basis(visible_sampling(2).value, config().xyz_to_rgb_matrix("lin_rec709").value);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error.rfind("wavelengths:", 0), 0u);
    EXPECT_FALSE(explicit_sampling({500e-9, 450e-9, 600e-9}).ok());
}
