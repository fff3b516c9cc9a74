// Colour through OpenColorIO: the shipped config against the standard matrices, how the config
// is found, errors naming the config and the colour space, and the spectral round trip
// RGB -> spectra -> XYZ -> RGB with OCIO doing the last step.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

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

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Sets an environment variable for one scope and restores it afterwards.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old, had_ = true;
        setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() { had_ ? setenv(name_, old_.c_str(), 1) : unsetenv(name_); }

private:
    const char* name_;
    std::string old_;
    bool had_ = false;
};
}  // namespace

TEST(ColourConfigTest, LinearRec709MatchesTheStandardMatrix) {
    const auto m = config().xyz_to_rgb_matrix("lin_rec709");
    ASSERT_TRUE(m.ok()) << m.error;
    // IEC 61966-2-1 / ITU-R BT.709 XYZ -> linear RGB, as printed to 4 decimals.
    const double expected[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(m.value[i][j], expected[i][j], 2e-3) << i << "," << j;
}

TEST(ColourConfigTest, WhiteIsD65AndStaysWhiteInAcescg) {
    const ColourConfig c = config();
    const auto to709 = c.xyz_to_rgb_matrix("lin_rec709");
    ASSERT_TRUE(to709.ok()) << to709.error;
    const Vector3 xyz = multiply(inverse(to709.value), {1, 1, 1});
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
    EXPECT_TRUE(contains(missing.error, "/nonexistent/wavecam.ocio")) << missing.error;
    for (const auto& error : {config().xyz_to_rgb_matrix("NoSuchSpace").error,
                              [] {
                                  float px[3] = {0, 0, 0};
                                  return config().convert_from_xyz(px, 1, "NoSuchSpace").error;
                              }()}) {
        EXPECT_TRUE(contains(error, "NoSuchSpace")) << error;
        EXPECT_TRUE(contains(error, kConfig)) << error;
    }
    auto nonlinear = config().xyz_to_rgb_matrix("sRGB");
    ASSERT_FALSE(nonlinear.ok());
    EXPECT_TRUE(contains(nonlinear.error, "not linear")) << nonlinear.error;
    EXPECT_TRUE(contains(nonlinear.error, "sRGB")) << nonlinear.error;
}

TEST(ColourConfigTest, ConfigWithoutXyzIsRefused) {
    const auto path = std::filesystem::path(testing::TempDir()) / "wavecam_no_xyz.ocio";
    std::ofstream(path) << "ocio_profile_version: 2.1\n"
                           "roles: {default: lin, scene_linear: lin, reference: lin}\n"
                           "displays: {sRGB: [!<View> {name: Raw, colorspace: lin}]}\n"
                           "colorspaces:\n  - !<ColorSpace> {name: lin}\n";
    const auto c = load_colour_config(path.string());
    ASSERT_FALSE(c.ok());
    EXPECT_TRUE(contains(c.error, path.string())) << c.error;
    EXPECT_TRUE(contains(c.error, kXyzColorspace)) << c.error;
}

// An empty path means $WAVECAM_OCIO_CONFIG first, then the installed or source-tree config.
TEST(ColourConfigTest, EmptyPathFindsTheShippedConfig) {
    {
        ScopedEnv env("WAVECAM_OCIO_CONFIG", "/nonexistent/from_env.ocio");
        const auto c = load_colour_config("");
        ASSERT_FALSE(c.ok());
        EXPECT_TRUE(contains(c.error, "/nonexistent/from_env.ocio")) << c.error;
    }
    ScopedEnv env("WAVECAM_OCIO_CONFIG", "");
    const auto c = load_colour_config("");
    ASSERT_TRUE(c.ok()) << c.error;
    EXPECT_TRUE(c.value.has_colorspace("lin_rec709"));
}

// RGB -> spectrum -> XYZ (sum over samples) -> RGB through OCIO is the identity, to float rounding.
TEST(SpectralBasisTest, RoundTripThroughOcioReturnsTheInputRgb) {
    const ColourConfig c = config();
    const float colours[][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0.02f, 0.9f, 0.1f}, {0.18f, 0.18f, 0.18f},
                                {4.0f, 2.5f, 0.3f}};
    std::vector<SpectralSampling> samplings;
    for (int n : {3, 8, 16, 31}) samplings.push_back(visible_sampling(n).value);
    samplings.push_back(explicit_sampling({440e-9, 470e-9, 530e-9, 560e-9, 610e-9, 660e-9}).value);
    for (const std::string space : {"lin_rec709", "ACEScg"}) {
        const auto m = c.xyz_to_rgb_matrix(space);
        ASSERT_TRUE(m.ok()) << m.error;
        for (const auto& sampling : samplings) {
            const auto basis = make_spectral_basis(sampling, m.value);
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
    ASSERT_TRUE(diffract_spectral({cam, rgb.data(), depth.data(), DepthMeaning::Planar}, basis.value, ap, ideal,
                                  {false, xyz.data()})
                    .ok());
    ASSERT_TRUE(c.convert_from_xyz(xyz.data(), 6, "lin_rec709").ok());
    for (size_t k = 0; k < 18; ++k) EXPECT_NEAR(xyz[k], rgb[k], 1e-4) << k;
}
