// Spectra without OCIO: the CIE 1931 fit against the CIE table, wavelength sampling and its
// errors, and the calibrated RGB basis (RGB -> spectrum -> XYZ -> RGB is the identity).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "wavecam/spectrum.h"

using namespace wavecam;

namespace {
// IEC 61966-2-1 (sRGB) / ITU-R BT.709 XYZ -> linear RGB, D65 white, as the standard prints it.
const Matrix3 kXyzToRec709{{{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};

Vector3 xyz_of(const SpectralBasis& basis, double r, double g, double b) {
    Vector3 xyz{0, 0, 0};
    for (int s = 0; s < basis.size(); ++s)
        for (int k = 0; k < 3; ++k) xyz[k] += basis.power(s, r, g, b) * basis.xyz_per_power(s)[k];
    return xyz;
}

bool starts_with_field(const std::string& error) { return error.rfind("wavelengths: ", 0) == 0; }
}  // namespace

// CIE 1931 2-degree table (CIE 15:2004, 5 nm table) at a few wavelengths. The Wyman-Sloan-Shirley
// fit is good to a few percent of each function's peak (x 1.06, y 1.00, z 1.78): tolerance 3%.
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

// Equal energy: the CIE functions integrate to 106.86 nm each over 360-830 nm, so a flat spectrum
// is the white point E (x = y = 1/3); 400-700 nm holds all but ~0.2% of it.
TEST(Cie1931, EqualEnergyIntegratesToWhiteE) {
    const auto basis = make_spectral_basis(visible_sampling(31).value, kXyzToRec709);
    ASSERT_TRUE(basis.ok()) << basis.error;
    Vector3 xyz{0, 0, 0};
    for (int s = 0; s < basis.value.size(); ++s)
        for (int k = 0; k < 3; ++k) xyz[k] += basis.value.xyz_per_power(s)[k];
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(xyz[k], 106.86e-9, 0.02 * 106.86e-9) << k;
    const double sum = xyz[0] + xyz[1] + xyz[2];
    EXPECT_NEAR(xyz[0] / sum, 1.0 / 3, 3e-3);
    EXPECT_NEAR(xyz[1] / sum, 1.0 / 3, 3e-3);
}

TEST(SpectralSamplingTest, VisibleSamplingUsesBinCentres) {
    const auto s = visible_sampling(30);
    ASSERT_TRUE(s.ok()) << s.error;
    ASSERT_EQ(s.value.wavelength.size(), 30u);
    EXPECT_NEAR(s.value.wavelength.front(), 405e-9, 1e-15);
    EXPECT_NEAR(s.value.wavelength.back(), 695e-9, 1e-15);
    for (double w : s.value.weight) EXPECT_NEAR(w, 10e-9, 1e-15);
}

TEST(SpectralSamplingTest, ExplicitWeightsSpanHalfwayToTheNeighbours) {
    const auto s = explicit_sampling({440e-9, 470e-9, 530e-9, 560e-9});
    ASSERT_TRUE(s.ok()) << s.error;
    const double expected[] = {30e-9, 45e-9, 45e-9, 30e-9};
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(s.value.weight[k], expected[k], 1e-15) << k;
}

TEST(SpectralSamplingTest, BadWavelengthsAreNamedErrors) {
    const auto none = visible_sampling(0);
    ASSERT_FALSE(none.ok());
    EXPECT_TRUE(starts_with_field(none.error)) << none.error;
    for (const std::vector<double>& bad : std::vector<std::vector<double>>{
             {}, {-500e-9, 600e-9}, {0.0, 600e-9}, {NAN, 600e-9}, {500e-9, INFINITY}, {500e-9, 450e-9, 600e-9},
             {500e-9, 500e-9}}) {
        const auto r = explicit_sampling(bad);
        ASSERT_FALSE(r.ok()) << bad.size();
        EXPECT_TRUE(starts_with_field(r.error)) << r.error;
    }
}

TEST(SpectralBasisTest, MismatchedWeightsAreErrors) {
    SpectralSampling mismatched = visible_sampling(8).value;
    mismatched.weight.pop_back();
    const auto r = make_spectral_basis(mismatched, kXyzToRec709);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(starts_with_field(r.error)) << r.error;
}

// Fewer than 3 wavelengths, or three a picometre apart, cannot carry colour: monochrome light,
// each channel through the same wavelengths, and the round trip still holds.
TEST(SpectralBasisTest, WavelengthsThatCannotCarryColourAreMonochrome) {
    for (const auto& sampling : {visible_sampling(1).value, visible_sampling(2).value,
                                 explicit_sampling({550e-9, 550.001e-9, 550.002e-9}).value}) {
        const auto b = make_spectral_basis(sampling, kXyzToRec709);
        ASSERT_TRUE(b.ok()) << b.error;
        EXPECT_TRUE(b.value.monochrome());
        EXPECT_EQ(b.value.size(), 3 * int(sampling.wavelength.size()));
        for (int s = 0; s < b.value.size(); ++s)
            for (int p = 0; p < 3; ++p) EXPECT_GE(b.value.power(s, p == 0, p == 1, p == 2), 0.0);
        const Vector3 out = multiply(kXyzToRec709, xyz_of(b.value, 0.3, 0.6, 0.1));
        EXPECT_NEAR(out[0], 0.3, 1e-9);
        EXPECT_NEAR(out[1], 0.6, 1e-9);
        EXPECT_NEAR(out[2], 0.1, 1e-9);
    }
}

// Every non-negative Rec.709 colour is a non-negative spectrum once 5 or more wavelengths span
// the visible range: the three primaries' spectra are non-negative at every sample.
TEST(SpectralBasisTest, Rec709PrimariesAreNonNegativeLight) {
    for (int n : {5, 8, 16, 31}) {
        const auto b = make_spectral_basis(visible_sampling(n).value, kXyzToRec709);
        ASSERT_TRUE(b.ok()) << b.error;
        EXPECT_FALSE(b.value.monochrome());
        for (int p = 0; p < 3; ++p) EXPECT_EQ(b.value.desaturation()[p], 0.0) << n;
        for (int s = 0; s < b.value.size(); ++s)
            for (int p = 0; p < 3; ++p) EXPECT_GE(b.value.power(s, p == 0, p == 1, p == 2), 0.0) << n << " " << s;
    }
}

// Smooth: at 31 samples each primary's spectrum is one sigmoid of a quadratic - at most one
// hump or one step, so its differences change sign at most twice (a signed three-band basis
// or a ragged fit would wiggle).
TEST(SpectralBasisTest, PrimarySpectraAreSmooth) {
    const auto b = make_spectral_basis(visible_sampling(31).value, kXyzToRec709);
    ASSERT_TRUE(b.ok());
    for (int p = 0; p < 3; ++p) {
        int turns = 0;
        double last = 0;
        for (int s = 1; s < b.value.size(); ++s) {
            const double d = b.value.power(s, p == 0, p == 1, p == 2) - b.value.power(s - 1, p == 0, p == 1, p == 2);
            if (d * last < 0) ++turns;
            if (d != 0) last = d;
        }
        EXPECT_LE(turns, 2) << p;
    }
}

// Out of gamut: three wavelengths (450, 550, 650 nm) cannot make Rec.709 blue from non-negative
// light (it lies outside their triangle on the chromaticity diagram); its primary is pulled toward
// white, the round trip stays exact and pure blue carries a negative share, reported.
TEST(SpectralBasisTest, UnreachablePrimariesArePulledTowardWhiteAndSaySo) {
    const auto b = make_spectral_basis(explicit_sampling({450e-9, 550e-9, 650e-9}).value, kXyzToRec709);
    ASSERT_TRUE(b.ok()) << b.error;
    EXPECT_GT(b.value.desaturation()[2], 0.0);
    EXPECT_EQ(b.value.desaturation()[0], 0.0);
    EXPECT_NE(b.value.description().find("pulled toward white"), std::string::npos);
    const Vector3 out = multiply(kXyzToRec709, xyz_of(b.value, 0, 0, 1));
    EXPECT_NEAR(out[2], 1.0, 1e-9);
    // grey stays non-negative light
    for (int s = 0; s < b.value.size(); ++s) EXPECT_GT(b.value.power(s, 0.2, 0.2, 0.2), 0.0);
}

// RGB -> spectrum -> XYZ (sum over samples) -> RGB through the same matrix gives back the input,
// saturated colours included; in double precision, so to 1e-9 rather than float's 1e-4.
TEST(SpectralBasisTest, RoundTripReturnsTheInputRgb) {
    const double colours[][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1},    {1, 0, 1},
                                 {0.02, 0.9, 0.1}, {0.18, 0.18, 0.18}, {4.0, 2.5, 0.3}};
    std::vector<SpectralSampling> samplings;
    for (int n : {3, 8, 16, 31}) samplings.push_back(visible_sampling(n).value);
    samplings.push_back(explicit_sampling({440e-9, 470e-9, 530e-9, 560e-9, 610e-9, 660e-9}).value);
    for (const auto& sampling : samplings) {
        const auto basis = make_spectral_basis(sampling, kXyzToRec709);
        ASSERT_TRUE(basis.ok()) << basis.error;
        for (const auto& rgb : colours) {
            const Vector3 out = multiply(kXyzToRec709, xyz_of(basis.value, rgb[0], rgb[1], rgb[2]));
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[k], rgb[k], 1e-9) << "S=" << sampling.wavelength.size();
        }
    }
}

// RGB white is D65 (x 0.3127, y 0.3290) with Y = 1, and its spectrum is physical light:
// non-negative at every wavelength (single saturated primaries may go negative).
TEST(SpectralBasisTest, WhiteIsAPhysicalD65Spectrum) {
    for (int n : {8, 31}) {
        const auto basis = make_spectral_basis(visible_sampling(n).value, kXyzToRec709);
        ASSERT_TRUE(basis.ok()) << basis.error;
        const Vector3 xyz = xyz_of(basis.value, 1, 1, 1);
        const double sum = xyz[0] + xyz[1] + xyz[2];
        EXPECT_NEAR(xyz[1], 1.0, 1e-3) << n;
        EXPECT_NEAR(xyz[0] / sum, 0.3127, 1e-3) << n;
        EXPECT_NEAR(xyz[1] / sum, 0.3290, 1e-3) << n;
        for (int s = 0; s < basis.value.size(); ++s) EXPECT_GT(basis.value.power(s, 1, 1, 1), 0.0) << s;
    }
}
