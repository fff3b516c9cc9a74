// The convolution method's frames as a user sees them: a uniform wall stays uniform to the last pixel
// (no dark rim, no seams at tiles or anchors), light from an overscan margin lands in the
// frame, a plan serves the frames it was made for, and a star's light, tail included, lands
// where an independent Fresnel integral puts it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "wavecam/convolution_method.h"
#include "wavecam/spectral_diffraction.h"

using namespace wavecam;

namespace {
// XYZ -> linear Rec.709 (IEC 61966-2-1); any invertible matrix serves the basis
const Matrix3 kXyzTo709{{{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};

SpectralBasis basis(int wavelengths) { return make_spectral_basis(visible_sampling(wavelengths).value, kXyzTo709).value; }

struct Frame {
    PinholeCamera cam;
    std::vector<float> rgb, depth;
    SpectralScene scene() const { return {cam, rgb.data(), depth.data(), DepthMeaning::Planar}; }
};

Frame wall(int w, int h, double fov_deg, double depth, float value) {
    Frame f;
    f.cam = {w, h, fov_deg * M_PI / 180, 50e-3};
    f.rgb.assign(3 * size_t(w) * h, value);
    f.depth.assign(size_t(w) * h, float(depth));
    return f;
}

// Largest relative deviation of any pixel, and of any row or column mean, from the mean (Y).
void uniformity(const std::vector<float>& xyz, int w, int h, double& pixel, double& line, double& mean) {
    mean = 0;
    for (int p = 0; p < w * h; ++p) mean += xyz[3 * p + 1];
    mean /= w * h;
    pixel = line = 0;
    for (int p = 0; p < w * h; ++p) pixel = std::max(pixel, std::abs(xyz[3 * p + 1] / mean - 1));
    for (int j = 0; j < h; ++j) {
        double row = 0;
        for (int i = 0; i < w; ++i) row += xyz[3 * (j * w + i) + 1];
        line = std::max(line, std::abs(row / w / mean - 1));
    }
    for (int i = 0; i < w; ++i) {
        double col = 0;
        for (int j = 0; j < h; ++j) col += xyz[3 * (j * w + i) + 1];
        line = std::max(line, std::abs(col / h / mean - 1));
    }
}
}  // namespace

TEST(ConvolutionFrame, UniformWallIsUniformToTheLastPixel) {
    const SpectralBasis b = basis(4);
    for (double pinhole : {0.315e-3, 1.0e-3}) {
        // small tiles and many anchor cells: a seam at any tile or cell boundary would show
        for (int tile : {0, 24}) {
            const Frame f = wall(200, 112, 40, 2.0, 0.5f);
            ConvolutionSettings s;
            s.tile = tile;
            s.anchor_cells = tile ? 6 : 4;
            std::vector<float> xyz(3 * 200 * 112);
            ASSERT_TRUE(diffract_convolution(f.scene(), b, {ApertureShape::Circle, pinhole}, {false, xyz.data()}, s)
                            .ok());
            double pixel, line, mean;
            uniformity(xyz, 200, 112, pixel, line, mean);
            std::printf("pinhole %.3f mm, tile %d: worst pixel %.4f%%, worst row/column %.4f%%, mean Y %.4f\n",
                        pinhole * 1e3, tile, 100 * pixel, 100 * line, mean);
            EXPECT_LT(pixel, 0.005) << "pinhole " << pinhole << " tile " << tile;
            EXPECT_LT(line, 0.002) << "pinhole " << pinhole << " tile " << tile;
            // the wall's own radiance comes back (a grey of Y = 0.5), less only the far tail
            EXPECT_GT(mean, 0.5 * 0.985);
            EXPECT_LT(mean, 0.5 * 1.005);
        }
    }
}

// A strip's transforms are as long as each side needs (its short side one tile of its own
// length, not the long side's): a wall on a 600 x 12 strip is as uniform as on a square, and a
// 4096 x 64 strip at 40 deg needs at most 2x the plan memory of a 512 x 512 frame of as many
// pixels at the same pitch (the same PSF in pixels). It needs 1.9x: the kernels of its wider
// field's anchors, and its margin of R on every side, 2.6x the strip's pixels; square transforms
// of the long side would hold 4340 x 4340 arrays per thread, many times the square's plan. The
// whole process's peak, images and libraries included, is 1.3x (tests/bench/run_fast_bench.sh 5).
TEST(ConvolutionFrame, AStripIsUniformAndCostsWhatASquareOfAsManyPixelsCosts) {
    const SpectralBasis b = basis(4);
    for (int tile : {0, 24}) {
        const Frame f = wall(600, 12, 40, 2.0, 0.5f);
        ConvolutionSettings s;
        s.tile = tile;
        std::vector<float> xyz(3 * 600 * 12);
        ASSERT_TRUE(diffract_convolution(f.scene(), b, {ApertureShape::Circle, 0.315e-3}, {false, xyz.data()}, s).ok());
        double pixel, line, mean;
        uniformity(xyz, 600, 12, pixel, line, mean);
        EXPECT_LT(pixel, 0.005) << "tile " << tile;
        EXPECT_LT(line, 0.002) << "tile " << tile;
        EXPECT_GT(mean, 0.5 * 0.985);
        EXPECT_LT(mean, 0.5 * 1.005);
    }
    const SpectralBasis b16 = basis(16);
    const double square_fov = 2 * std::atan(std::tan(20 * M_PI / 180) * 512 / 4096);
    const ConvolutionPlanSpec strip{{4096, 64, 40 * M_PI / 180, 50e-3}, 0, {ApertureShape::Circle, 0.315e-3}, b16, 1 / 0.3, {}};
    const ConvolutionPlanSpec square{{512, 512, square_fov, 50e-3}, 0, {ApertureShape::Circle, 0.315e-3}, b16, 1 / 0.3, {}};
    const double ratio = ConvolutionPlan::estimate_bytes(strip) / ConvolutionPlan::estimate_bytes(square);
    std::printf("4096 x 64 strip against 512 x 512: %.2fx the memory\n", ratio);
    EXPECT_LT(ratio, 2.0);
}

// A uniform wall (no vignetting) comes back at its own radiance at every pixel where the PSF is
// narrower than a pixel and its kernel is 3 x 3: what lies beyond such a kernel (1.4% at 16 px,
// 30 deg, f = 20 mm, 0.2 mm) is spread by the far tail as every wider kernel's is.
TEST(ConvolutionFrame, UniformWallComesBackAtItsRadianceUnderASubPixelPsf) {
    struct Case {
        int width;
        double fov;
    };
    for (int wavelengths : {3, 8}) {
        const SpectralBasis b = basis(wavelengths);
        for (const Case& k : {Case{16, 30}, Case{24, 10}}) {
            Frame f = wall(k.width, k.width, k.fov, 3.0, 0.5f);
            f.cam.film_distance = 20e-3;
            ConvolutionSettings s;
            std::vector<float> xyz(3 * size_t(k.width) * k.width);
            ASSERT_TRUE(diffract_convolution(f.scene(), b, {ApertureShape::Circle, 0.2e-3}, {false, xyz.data()}, s)
                            .ok());
            // grey 0.5 in the working space is Y = 0.5
            double lo = 1e9, hi = -1e9;
            for (int p = 0; p < k.width * k.width; ++p) {
                lo = std::min(lo, xyz[3 * p + 1] / 0.5);
                hi = std::max(hi, xyz[3 * p + 1] / 0.5);
            }
            std::printf("%d wavelengths, %d px, %2.0f deg: Y / radiance %.4f to %.4f\n", wavelengths, k.width, k.fov, lo, hi);
            EXPECT_GT(lo, 0.997) << wavelengths << " wavelengths, " << k.fov << " deg";
            EXPECT_LT(hi, 1.003) << wavelengths << " wavelengths, " << k.fov << " deg";
        }
    }
}

TEST(ConvolutionFrame, OverscanMarginLightsTheFrameAndIsCropped) {
    // a dim wall with a bright patch just outside the output frame, in the overscan margin
    const int w = 120, h = 80, margin = 12;
    Frame f = wall(w, h, 30, 3.0, 0.05f);
    for (int j = 30; j < 50; ++j)
        for (int i = margin - 4; i < margin; ++i)
            for (int k = 0; k < 3; ++k) f.rgb[3 * (j * w + i) + k] = 50.0f;
    const SpectralBasis b = basis(3);
    const Aperture ap{ApertureShape::Circle, 2e-3};  // geometric blur of a few pixels
    ConvolutionPlanSpec spec{f.cam, margin, ap, b, 1.0 / 3.0, {}};
    auto plan = ConvolutionPlan::create(spec);
    ASSERT_TRUE(plan.ok()) << plan.error;
    ASSERT_LT(plan.value->kernel_radius(), margin) << "the margin must hold every source that reaches the frame";
    const int ow = w - 2 * margin, oh = h - 2 * margin;
    std::vector<float> cropped(3 * ow * oh), full(3 * w * h);
    ASSERT_TRUE(plan.value->apply(f.scene(), true, cropped.data()).ok());
    // the same sources, whole: its centre is the cropped frame (the anchors differ, so the
    // kernels are interpolated from other field positions: within 0.5% of the brightest pixel)
    ASSERT_TRUE(diffract_convolution(f.scene(), b, ap, {true, full.data()}).ok());
    double worst = 0, brightest = 0, patch_light = 0;
    for (int j = 0; j < oh; ++j)
        for (int i = 0; i < ow; ++i) {
            const double a = cropped[3 * (j * ow + i) + 1], c = full[3 * ((j + margin) * w + i + margin) + 1];
            worst = std::max(worst, std::abs(a - c));
            brightest = std::max(brightest, c);
            if (i == 0 && j + margin >= 35 && j + margin < 45) patch_light += a;
        }
    EXPECT_LT(worst, 0.005 * brightest);
    // the patch's blur reaches into the frame: the edge column beside it is far brighter than
    // the dim wall (0.05 x cos^4) would be alone
    EXPECT_GT(patch_light / 10, 0.2);
}

TEST(ConvolutionFrame, PlanServesTheFramesItWasMadeFor) {
    const Frame near = wall(64, 48, 40, 0.5, 0.3f), about = wall(64, 48, 40, 0.51, 0.7f);
    const SpectralBasis b = basis(3);
    const Aperture ap{ApertureShape::Circle, 0.4e-3};
    ConvolutionPlanSpec spec{near.cam, 0, ap, b, 1 / 0.5, {}};
    auto plan = ConvolutionPlan::create(spec);
    ASSERT_TRUE(plan.ok());
    ConvolutionPlanSpec similar = spec;
    similar.max_inverse_depth = 1 / 0.51;  // the same layers and kernel radius
    EXPECT_TRUE(plan.value->serves(similar));
    ConvolutionPlanSpec far = spec;
    far.max_inverse_depth = 1 / 50.0;  // fewer layers: a plan of its own
    EXPECT_FALSE(plan.value->serves(far));
    ConvolutionPlanSpec nearer = spec;
    nearer.max_inverse_depth = 1 / 0.05;
    EXPECT_FALSE(plan.value->serves(nearer));
    ConvolutionPlanSpec other_pinhole = spec;
    other_pinhole.aperture.diameter = 0.5e-3;
    EXPECT_FALSE(plan.value->serves(other_pinhole));
    ConvolutionPlanSpec other_colour = spec;
    other_colour.basis = basis(4);
    EXPECT_FALSE(plan.value->serves(other_colour));
    // a frame through the shared plan equals, bit for bit, the frame through a plan of its own
    std::vector<float> shared(3 * 64 * 48), own(3 * 64 * 48);
    ASSERT_TRUE(plan.value->apply(about.scene(), true, shared.data()).ok());
    auto own_plan = ConvolutionPlan::create(similar);
    ASSERT_TRUE(own_plan.value->apply(about.scene(), true, own.data()).ok());
    EXPECT_EQ(shared, own);
}

// On-axis Fresnel PSF of a circular pinhole for a source at infinity, by the Hankel integral
//   U(rho) = (2 pi / (lambda f)) int_0^a exp(i pi r^2 / (lambda f)) J0(2 pi r rho / (lambda f)) r dr,
// normalised by the power through the pinhole (Parseval: int |U|^2 dA = pi a^2), so it
// integrates to 1 over the whole film. Tabulated on a radial grid for interpolation.
struct RadialPsf {
    double step;
    std::vector<double> value;
    RadialPsf(double a, double f, double lambda, double max_rho, double step_) : step(step_) {
        const int nr = 4000;
        for (double rho = 0; rho <= max_rho + 2 * step; rho += step) {
            std::complex<double> u = 0;
            for (int k = 0; k < nr; ++k) {  // midpoint rule over r
                const double r = (k + 0.5) * a / nr;
                u += std::exp(std::complex<double>(0, M_PI * r * r / (lambda * f))) *
                     std::cyl_bessel_j(0.0, 2 * M_PI * r * rho / (lambda * f)) * r;
            }
            u *= 2 * M_PI / (lambda * f) * a / nr;
            value.push_back(std::norm(u) / (M_PI * a * a));
        }
    }
    double at(double rho) const {
        const double x = rho / step;
        const size_t i = size_t(x);
        return value[i] + (x - i) * (value[i + 1] - value[i]);
    }
};

TEST(ConvolutionFrame, StarLightLandsWhereTheFresnelIntegralPutsIt) {
    // one white star at the centre of a 97 x 97 frame, at infinity, the optimal pinhole
    const int w = 97, c = 48;
    const double f = 50e-3, d = 0.315e-3;
    Frame star = wall(w, w, 4.0, 1e10, 0.0f);
    for (int k = 0; k < 3; ++k) star.rgb[3 * (c * w + c) + k] = 1.0f;
    const SpectralBasis b = basis(3);
    std::vector<float> xyz(3 * w * w);
    ASSERT_TRUE(diffract_convolution(star.scene(), b, {ApertureShape::Circle, d}, {true, xyz.data()}).ok());

    // the reference Y per pixel: each wavelength's Fresnel PSF averaged over the pixel's area
    const double pitch = star.cam.pixel_pitch();
    std::vector<double> ref(w * w, 0.0);
    for (int s = 0; s < b.size(); ++s) {
        const RadialPsf psf(d / 2, f, b.wavelength(s), pitch * w, pitch / 16);
        const double weight = b.power(s, 1, 1, 1) * b.xyz_per_power(s)[1];
        const int sub = 6;
        for (int j = 0; j < w; ++j)
            for (int i = 0; i < w; ++i) {
                double sum = 0;
                for (int sj = 0; sj < sub; ++sj)
                    for (int si = 0; si < sub; ++si) {
                        const double x = (i - c + (si + 0.5) / sub - 0.5) * pitch;
                        const double y = (j - c + (sj + 0.5) / sub - 0.5) * pitch;
                        sum += psf.at(std::hypot(x, y));
                    }
                ref[j * w + i] += weight * sum / (sub * sub) * pitch * pitch;
            }
    }
    // energy in square rings around the star: the core, the first rings, the far tail
    const int edges[] = {0, 1, 3, 8, 20, 48};
    double total_fast = 0, total_ref = 0;
    for (int r = 0; r + 1 < int(std::size(edges)); ++r) {
        double fast = 0, reference = 0;
        for (int j = 0; j < w; ++j)
            for (int i = 0; i < w; ++i) {
                const int ring = std::max(std::abs(i - c), std::abs(j - c));
                if (ring < edges[r] || ring >= edges[r + 1]) continue;
                fast += xyz[3 * (j * w + i) + 1];
                reference += ref[j * w + i];
            }
        std::printf("ring %2d-%2d px: fast %.5f, Fresnel integral %.5f\n", edges[r], edges[r + 1] - 1, fast, reference);
        EXPECT_NEAR(fast, reference, 0.02 * reference + 1e-3) << "ring " << edges[r];
        total_fast += fast;
        total_ref += reference;
    }
    std::printf("in the frame: fast %.5f, Fresnel integral %.5f\n", total_fast, total_ref);
    EXPECT_NEAR(total_fast, total_ref, 0.005 * total_ref);
}

// The pixels are checked once, before any work: a bad one is named by its field and pixel, by the
// convolution method and by the spectral sum before any wavelength is propagated.
TEST(ConvolutionFrame, BadPixelsAreNamedBeforeAnyWork) {
    Frame f = wall(8, 6, 40, 2.0, 0.5f);
    std::vector<float> xyz(3 * 8 * 6);
    int propagations = 0;
    const MonochromePropagator counting = [&](const MonochromeScene&, double, float*, const ProgressFn&) {
        ++propagations;
        return Result<bool>::success(true);
    };
    const Aperture pinhole{ApertureShape::Circle, 0.3e-3};
    f.rgb[3 * (2 * 8 + 5) + 1] = std::nanf("");
    for (auto r : {diffract_convolution(f.scene(), basis(3), pinhole, {true, xyz.data()}),
                   diffract_spectral(f.scene(), basis(3), pinhole, counting, {true, xyz.data()})})
        EXPECT_EQ(r.error.rfind("radiance: pixel (5, 2) is nan, expected a finite value", 0), 0u) << r.error;
    // finite, but its sums would overflow single precision (the image came back NaN)
    f.rgb[3 * (2 * 8 + 5) + 1] = 3e38f;
    for (auto r : {diffract_convolution(f.scene(), basis(3), pinhole, {true, xyz.data()}),
                   diffract_spectral(f.scene(), basis(3), pinhole, counting, {true, xyz.data()})})
        EXPECT_EQ(r.error.rfind("radiance: pixel (5, 2) is 3e+38, expected a finite value within +-1e30", 0), 0u)
            << r.error;
    f.rgb[3 * (2 * 8 + 5) + 1] = 0.5f;
    f.depth[3 * 8 + 1] = -1;
    for (auto r : {diffract_convolution(f.scene(), basis(3), pinhole, {true, xyz.data()}),
                   diffract_spectral(f.scene(), basis(3), pinhole, counting, {true, xyz.data()})})
        EXPECT_EQ(r.error.rfind("depth: pixel (1, 3) is -1, expected a distance > 0", 0), 0u) << r.error;
    EXPECT_EQ(propagations, 0);
}

// A pinhole far below its optimum convolves in direction cosines (one kernel for every field). A
// uniform wall (no vignetting) then comes back at its radiance times what the PSF, centred on the
// pixel's direction, holds within the disc of directions (beyond it the light would leave the
// pinhole at more than 90 deg: evanescent, no film point lies there). Rayleigh-Sommerfeld's
// obliquity and the film's incidence (spectral_diffraction.cpp: |U|^2 cos(incidence)) weight a
// source's light on the film by cos(out) / cos(in) against the Fraunhofer pattern's power per unit
// of direction cosines, so a pixel at direction cosines n gets
//   L cos(n) x integral over the disc of PSF(n' - n) / cos(n') dn',
// the PSF the pinhole's Airy pattern (pi a^2 / lambda^2) (2 J1(k a rho) / (k a rho))^2 (holding 1
// over the plane). Computed here in rings of radius rho about n, each ring's 1 / cos(n') summed
// in closed form: integral over phi of (A - B cos phi)^-1/2, A = 1 - |n|^2 - rho^2, B = 2 |n| rho,
// is 4 K(2B / (A + B)) / sqrt(A + B) where the ring lies within the disc and 4 K((A + B) / 2B) /
// sqrt(2B) where it crosses its edge (complete elliptic integrals of the first kind, parameter m).
// From 20 to 120 deg the share falls from 99.7% to 85% toward the wide frames' corners; every
// pixel within 0.4% of it.
TEST(ConvolutionFrame, UniformWallInDirectionCosinesKeepsWhatFallsWithinTheDiscOfDirections) {
    const double lambda = 550e-9;
    const SpectralBasis b = make_spectral_basis(explicit_sampling({lambda}).value, kXyzTo709).value;
    struct Case {
        int width, height;
        double fov;
    };
    for (const Case& k : {Case{240, 160, 20}, Case{320, 200, 90}, Case{240, 160, 120}}) {
        const Frame f = wall(k.width, k.height, k.fov, 2.0, 0.5f);
        // an Airy radius of 14 pixels on the axis
        const double d = 1.22 * lambda * f.cam.film_distance / (14 * f.cam.pixel_pitch()), ka = M_PI * d / lambda;
        auto plan = ConvolutionPlan::create({f.cam, 0, {ApertureShape::Circle, d}, b, 1 / 2.0, {}});
        ASSERT_TRUE(plan.ok()) << plan.error;
        ASSERT_TRUE(plan.value->in_directions()) << k.fov << " deg";
        std::vector<float> xyz(3 * size_t(k.width) * k.height);
        ASSERT_TRUE(plan.value->apply(f.scene(), false, xyz.data()).ok());
        auto share = [&](double r) {
            const int n = 20000;
            const double top = 1 + r, step = top / n;
            double sum = 0;
            for (int q = 0; q < n; ++q) {
                const double rho = (q + 0.5) * step, x = ka * rho, airy = 2 * std::cyl_bessel_j(1.0, x) / x;
                const double A = 1 - r * r - rho * rho, B = 2 * r * rho;
                double ring = 0;  // integral of 1 / cos over the ring's angle
                if (B == 0)
                    ring = A > 0 ? 2 * M_PI / std::sqrt(A) : 0.0;
                else if (A > B)
                    ring = 4 * std::comp_ellint_1(std::sqrt(2 * B / (A + B))) / std::sqrt(A + B);
                else if (A + B > 0)
                    ring = 4 * std::comp_ellint_1(std::sqrt((A + B) / (2 * B))) / std::sqrt(2 * B);
                sum += rho * step * airy * airy * ring;
            }
            return std::sqrt(1 - r * r) * sum * ka * ka / (4 * M_PI);  // (pi a^2 / lambda^2 = (k a)^2 / (4 pi))
        };
        double worst = 0, low = INFINITY, high = 0;
        std::vector<std::pair<double, double>> table;  // r -> share, every 1/64 of the disc
        for (int q = 0; q <= 64; ++q) table.push_back({q / 64.0, share(q / 64.0)});
        for (int j = 0; j < k.height; j += 3)
            for (int i = 0; i < k.width; i += 3) {
                double u, v;
                f.cam.tangent(i + 0.5, j + 0.5, u, v);
                const double r = std::sqrt((u * u + v * v) / (1 + u * u + v * v)), t = r * 64;
                const int q = std::min(int(t), 63);
                const double expected = table[q].second + (t - q) * (table[q + 1].second - table[q].second);
                const double got = xyz[3 * (size_t(j) * k.width + i) + 1] / 0.5;
                worst = std::max(worst, std::abs(got / expected - 1));
                low = std::min(low, expected), high = std::max(high, expected);
            }
        std::printf("%3.0f deg, pinhole %.4f mm: the disc holds %.4f to %.4f of the PSF; worst pixel off by %.3f%%\n",
                    k.fov, d * 1e3, low, high, 100 * worst);
        EXPECT_LT(worst, 0.004) << k.fov << " deg";
    }
}

// A pupil without mirror symmetry keeps its orientation in direction cosines: a star through a
// triangle (a vertex toward +x, its far field a six-armed star that is not its own transpose), on
// the axis and a third of the way to a corner of a 30 deg frame, comes out as the field anchors'
// kernels put it (their orientation is checked against the exact PSF in test_aperture_optics.cpp)
// and far from its own transpose.
TEST(ConvolutionFrame, InDirectionCosinesATrianglePupilKeepsItsOrientation) {
    const double lambda = 550e-9;
    const SpectralBasis b = make_spectral_basis(explicit_sampling({lambda}).value, kXyzTo709).value;
    const int w = 160;
    Frame f = wall(w, w, 30, 1e10, 0.0f);
    const int stars[][2] = {{w / 2, w / 2}, {w / 2 - 27, w / 2 - 27}};
    for (const auto& s : stars)
        for (int k = 0; k < 3; ++k) f.rgb[3 * (size_t(s[1]) * w + s[0]) + k] = 1.0f;
    Aperture triangle{ApertureShape::Polygon, 1.22 * lambda * f.cam.film_distance / (14 * f.cam.pixel_pitch())};
    triangle.sides = 3;
    std::vector<float> directions(3 * w * w), anchors(3 * w * w);
    auto plan = ConvolutionPlan::create({f.cam, 0, triangle, b, 0, {}});
    ASSERT_TRUE(plan.ok()) << plan.error;
    ASSERT_TRUE(plan.value->in_directions());
    ASSERT_TRUE(plan.value->apply(f.scene(), true, directions.data()).ok());
    ConvolutionSettings tiles;
    tiles.tile = 64;  // (a tile size asks for the anchors)
    auto anchored = ConvolutionPlan::create({f.cam, 0, triangle, b, 0, tiles});
    ASSERT_TRUE(anchored.ok()) << anchored.error;
    ASSERT_FALSE(anchored.value->in_directions());
    ASSERT_TRUE(anchored.value->apply(f.scene(), true, anchors.data()).ok());
    for (const auto& s : stars) {
        const int half = 24;
        double peak = 0, same = 0, turned = 0;
        for (int dy = -half; dy <= half; ++dy)
            for (int dx = -half; dx <= half; ++dx)
                peak = std::max(peak, double(anchors[3 * (size_t(s[1] + dy) * w + s[0] + dx) + 1]));
        for (int dy = -half; dy <= half; ++dy)
            for (int dx = -half; dx <= half; ++dx) {
                const double a = anchors[3 * (size_t(s[1] + dy) * w + s[0] + dx) + 1];
                same += std::pow(directions[3 * (size_t(s[1] + dy) * w + s[0] + dx) + 1] - a, 2);
                turned += std::pow(directions[3 * (size_t(s[1] + dx) * w + s[0] + dy) + 1] - a, 2);
            }
        const double n = std::pow(2 * half + 1, 2);
        same = std::sqrt(same / n) / peak;
        turned = std::sqrt(turned / n) / peak;
        std::printf("star at (%d, %d): directions against anchors %.3f%% RMS of the peak; transposed %.2f%%\n", s[0],
                    s[1], 100 * same, 100 * turned);
        EXPECT_LT(same, 0.01);
        EXPECT_GT(turned, 5 * same);
    }
}
