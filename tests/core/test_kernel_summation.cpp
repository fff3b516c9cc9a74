// The `kernel` summation: the scene-sum methods' runs as convolutions with amplitude PSFs that the
// direct or nufft sums compute at field anchors and depth layers (kernel_summation.h),
// against the point sums themselves (direct, incoherent: no noise) and the random phases' own
// limit. Started with --device=gpu (tests/core/CMakeLists.txt), the same checks with the
// kernels' direct sums and the runs' transforms on the Vulkan device.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "summation_flag.h"
#include "wavecam/scene_diffraction.h"

using namespace wavecam;

namespace {

// A frame at f = 2 mm (for a 0.05 mm pinhole: pixels of about its image's size, a few film
// points each, where a wide field at f = 50 mm would make pixels many PSFs wide): `side` pixels
// across `fov_deg`, planar depth `z`.
struct Frame {
    PinholeCamera camera;
    std::vector<float> power, depth;
    Frame(int side, double fov_deg, double z)
        : camera{side, side, fov_deg * M_PI / 180, 2e-3},
          power(size_t(side) * side, 0.0f),
          depth(size_t(side) * side, float(z)) {}
    // uniform noise (a fixed generator) times a checker of `square` pixels, 0.2 and 1
    void texture(int square) {
        uint32_t state = 7;
        for (int j = 0; j < camera.height; ++j)
            for (int i = 0; i < camera.width; ++i) {
                state = state * 1664525u + 1013904223u;
                const double checker = ((i / square + j / square) % 2) ? 1.0 : 0.2;
                power[size_t(j) * camera.width + i] = float(checker * (state >> 8) / double(1 << 24));
            }
    }
    std::vector<float> diffract(const SceneSumSettings& s, double lambda = 550e-9) const {
        std::vector<float> out(power.size(), 0.0f);
        const MonochromeScene view{camera, power.data(), depth.data(), DepthMeaning::Planar};
        auto r = diffract_monochrome(view, lambda, s, test_device(), out.data());
        EXPECT_TRUE(r.ok()) << r.error;
        return out;
    }
};

SceneSumSettings settings(Summation summation, CoherenceMethod method, int runs = 1) {
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, 0.05e-3};
    s.method = method;
    s.runs = runs;
    s.summation = summation;
    return s;
}

// RMS of a - b over the frame, relative to b's mean.
double relative_rms(const std::vector<float>& a, const std::vector<float>& b) {
    double s = 0, mean = 0;
    for (size_t p = 0; p < a.size(); ++p) {
        s += std::pow(double(a[p]) - b[p], 2);
        mean += b[p];
    }
    return std::sqrt(s / a.size()) / (mean / a.size());
}

double total(const std::vector<float>& a) {
    double s = 0;
    for (const float x : a) s += x;
    return s;
}

}  // namespace

// One source on black, one run: its image is the point sums' (the kernels are those sums; a
// source between anchors gets their blend with its power kept), its light within 1%, its
// brightest pixel within 2%.
TEST(KernelSummation, OneSourceIsItsExactImage) {
    Frame frame(40, 30, 2.0);
    for (const int i0 : {20, 27, 33}) {
        std::fill(frame.power.begin(), frame.power.end(), 0.0f);
        frame.power[size_t(17) * 40 + i0] = 1.0f;
        const auto psf = frame.diffract(settings(Summation::Kernel, CoherenceMethod::RandomPhase));
        const auto direct = frame.diffract(settings(Summation::Direct, CoherenceMethod::RandomPhase));
        const size_t peak = size_t(17) * 40 + i0;
        std::printf("source at column %d: light %.4f of the direct sums', peak %.4f\n", i0, total(psf) / total(direct),
                    psf[peak] / direct[peak]);
        EXPECT_NEAR(total(psf) / total(direct), 1.0, 0.01) << i0;
        EXPECT_NEAR(psf[peak] / direct[peak], 1.0, 0.02) << i0;
    }
}

// The incoherent sum through |kernel|^2 against the exact incoherent sum (every source through
// the pinhole alone, no noise on either side): a textured frame at 30 degrees, RMS over every
// pixel relative to the mean within 1.5% (1.0% measured).
TEST(KernelSummation, IncoherentMatchesTheExactIncoherentSum) {
    Frame frame(16, 30, 1.0);
    frame.texture(4);
    const auto psf = frame.diffract(settings(Summation::Kernel, CoherenceMethod::Incoherent));
    const auto exact = frame.diffract(settings(Summation::Auto, CoherenceMethod::Incoherent));
    const double rms = relative_rms(psf, exact);
    std::printf("incoherent kernel summation vs point sums: %.3f%% RMS\n", 100 * rms);
    EXPECT_LT(rms, 0.015);
}

// The runs converge to their limit: 64 runs of coded phases against the incoherent sum of the
// same kernels' powers, on a textured frame at 50 degrees where neighbouring anchors' kernels
// differ most (1/cos^3 radially). What remains is the amplitudes' blend against the powers'
// (3.9% RMS measured, the same at 256 runs; 9.9% with anchors 6 R apart, without the power balance
// more).
TEST(KernelSummation, RunsConvergeToTheIncoherentSum) {
    Frame frame(24, 50, 1.0);
    frame.texture(4);
    const auto runs = frame.diffract(settings(Summation::Kernel, CoherenceMethod::RandomPhase, 64));
    const auto limit = frame.diffract(settings(Summation::Kernel, CoherenceMethod::Incoherent));
    const double rms = relative_rms(runs, limit);
    std::printf("64 runs vs their incoherent limit: %.3f%% RMS\n", 100 * rms);
    EXPECT_LT(rms, 0.05);
}

// A uniform wall comes back uniform to the last pixel (the edge continued, the far tail, the
// anchors' blends): 64 runs at 50 degrees against the wall's incoherent image through the same
// kernels (which holds its cos^4 fall-off), every pixel within 4%, RMS within 1% (2.0% and 0.69%
// measured, the runs' noise included).
TEST(KernelSummation, UniformWallIsUniform) {
    Frame frame(32, 50, 2.0);
    std::fill(frame.power.begin(), frame.power.end(), 1.0f);
    const auto img = frame.diffract(settings(Summation::Kernel, CoherenceMethod::RandomPhase, 64));
    const auto limit = frame.diffract(settings(Summation::Kernel, CoherenceMethod::Incoherent));
    double worst = 0, s = 0;
    for (size_t p = 0; p < img.size(); ++p) {
        worst = std::max(worst, std::abs(double(img[p]) / limit[p] - 1));
        s += std::pow(img[p] / limit[p] - 1, 2);
    }
    const double rms = std::sqrt(s / img.size());
    std::printf("wall: worst pixel %.3f%%, RMS %.3f%%\n", 100 * worst, 100 * rms);
    EXPECT_LT(worst, 0.04);
    EXPECT_LT(rms, 0.01);
}

// A job is the sum of its shares: runs [0, 2) and [2, 4) add up to the 4-run job bit for bit.
TEST(KernelSummation, SharesAddUpToTheJob) {
    Frame frame(16, 30, 1.0);
    frame.texture(4);
    SceneSumSettings s = settings(Summation::Kernel, CoherenceMethod::RandomPhase, 4);
    const auto job = frame.diffract(s);
    std::vector<float> shares(job.size(), 0.0f);
    for (const int first : {0, 2}) {
        s.run_begin = first;
        s.run_end = first + 2;
        const MonochromeScene view{frame.camera, frame.power.data(), frame.depth.data(), DepthMeaning::Planar};
        ASSERT_TRUE(diffract_monochrome(view, 550e-9, s, test_device(), shares.data()).ok());
    }
    for (size_t p = 0; p < job.size(); ++p) ASSERT_EQ(job[p], shares[p]) << p;
}

// What it cannot serve is refused, naming the setting: jittered sources (off their pixel
// centres), and depth ranges beyond its layers.
TEST(KernelSummation, RefusesWhatItCannotServe) {
    Frame frame(8, 30, 1.0);
    std::fill(frame.power.begin(), frame.power.end(), 1.0f);
    const MonochromeScene view{frame.camera, frame.power.data(), frame.depth.data(), DepthMeaning::Planar};
    std::vector<float> out(frame.power.size(), 0.0f);
    SceneSumSettings s = settings(Summation::Kernel, CoherenceMethod::RandomPhase);
    s.jitter = true;
    auto r = diffract_monochrome(view, 550e-9, s, test_device(), out.data());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error.find("jitter"), std::string::npos) << r.error;
    s.jitter = false;
    s.aperture.diameter = 0.5e-3;  // 0.5 mm at 1 cm: about 140 rad of defocus across the depths
    std::fill(frame.depth.begin(), frame.depth.end(), 0.01f);
    r = diffract_monochrome(view, 550e-9, s, test_device(), out.data());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.field, "summation") << r.error;
}


// What a job's `auto` runs (chosen_summation): the kernel summation for the wall-sized frames a user diffracts at
// the default 64 runs, where it applies; the point sums' own choice wherever the kernel summation does not apply
// (sources moved off their pixels' centres, a sieve's or zone plate's structure finer than the
// kernels' lattice) and for a single run of a tiny frame, whose few sources cost less than the
// kernels; a summation asked by name as it is.
TEST(AutoSummation, TakesTheKernelSummationWhereItAppliesAndCostsLess) {
    const PinholeCamera camera{128, 128, 50 * M_PI / 180, 50e-3};
    const ComputeDevice cpu;
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, 0.3e-3};
    s.nearest_depth = 0.3;
    EXPECT_EQ(s.runs, 64);
    EXPECT_EQ(chosen_summation(s, cpu, camera, 550e-9), Summation::Kernel);
    s.method = CoherenceMethod::Incoherent;
    EXPECT_EQ(chosen_summation(s, cpu, camera, 550e-9), Summation::Kernel);
    s.method = CoherenceMethod::RandomPhase;
    for (Summation asked : {Summation::Direct, Summation::Nufft, Summation::Kernel}) {
        SceneSumSettings named = s;
        named.summation = asked;
        EXPECT_EQ(chosen_summation(named, cpu, camera, 550e-9), asked);
    }
    SceneSumSettings jitter = s;
    jitter.jitter = true;
    EXPECT_EQ(chosen_summation(jitter, cpu, camera, 550e-9), Summation::Auto);
    for (ApertureShape shape : {ApertureShape::ZonePlate, ApertureShape::PhotonSieve}) {
        SceneSumSettings zones = s;
        zones.aperture.shape = shape;
        zones.aperture.zones = 8;
        EXPECT_EQ(chosen_summation(zones, cpu, camera, 550e-9), Summation::Auto);
    }
    SceneSumSettings tiny = s;
    tiny.runs = 1;
    EXPECT_EQ(chosen_summation(tiny, cpu, PinholeCamera{4, 4, 30 * M_PI / 180, 20e-3}, 550e-9), Summation::Auto);
}
