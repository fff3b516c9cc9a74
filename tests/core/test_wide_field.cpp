// A star's image at every field, against an independent Rayleigh-Sommerfeld integral written in
// the test (tests/support/rs_reference.h): frames 5 to 120 deg wide, stars at the centre, mid
// field and corner, on the anchors and between them, Fresnel numbers 0.02 to 5, PSFs 1 to 30
// pixels wide, through every method and summation. The bounds: each image (its shape: both are
// scaled to the same total over the window) within 2% at its peak and 1% of its peak in RMS.
// docs/physics.md, "Wide fields", tabulates the figures this prints.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "rs_reference.h"
#include "summation_flag.h"
#include "wavecam/convolution_method.h"
#include "wavecam/scene_diffraction.h"

using namespace wavecam;

namespace {

const Matrix3 kXyzTo709{{{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};

// A square frame of `side` pixels across `fov_deg` at film distance f, a pinhole of diameter d,
// and a star at planar depth `depth` (inf: sky) at the pixel a fraction `along` of the way from
// the centre to the top-left corner (negative: to the bottom-right, where the convolution
// method's and the kernel summation's anchors take the top-left ones' kernels mirrored); 550 nm.
struct Case {
    int side;
    double fov_deg, f_mm, d_mm, depth, along;
    test::RsStar star() const {
        test::RsStar s;
        s.camera = {side, side, fov_deg * M_PI / 180, f_mm * 1e-3};
        s.diameter = d_mm * 1e-3;
        s.depth = depth;
        const int mid = side / 2;
        s.i = s.j = std::clamp(mid - int(std::lround(along * mid)), 0, side - 1);
        return s;
    }
    // the Airy radius 1.22 lambda f / d on the axis, in pixels
    double airy_px() const { return 1.22 * 550e-9 * f_mm / d_mm / star().camera.pixel_pitch(); }
    // Fresnel number a^2 / lambda (1/f + 1/z)
    double fresnel() const {
        return std::pow(0.5e-3 * d_mm, 2) / 550e-9 * (1e3 / f_mm + (std::isinf(depth) ? 0 : 1 / depth));
    }
    std::string name() const {
        char s[200];
        std::snprintf(s, sizeof s, "%dpx %gdeg f %gmm d %gmm %s (Airy %.1fpx, N %.2g), star %.2f to the corner", side,
                      fov_deg, f_mm, d_mm, std::isinf(depth) ? "sky" : (std::to_string(int(depth)) + "m").c_str(),
                      airy_px(), fresnel(), along);
        return s;
    }
};

struct Comparison {
    double peak = 0, rms = 0;  // of the test image against the reference: peak - 1, RMS / peak
};

// Both windows scaled to the same total over the pixels within the frame, then compared.
Comparison compare(const std::vector<double>& test, std::vector<double> reference, const test::RsStar& s, int half) {
    for (int j = s.j - half, p = 0; j <= s.j + half; ++j)
        for (int i = s.i - half; i <= s.i + half; ++i, ++p)
            if (i < 0 || j < 0 || i >= s.camera.width || j >= s.camera.height) reference[p] = 0;
    double st = 0, sr = 0, peak_t = 0, peak_r = 0;
    for (size_t p = 0; p < test.size(); ++p) {
        st += test[p];
        sr += reference[p];
    }
    for (size_t p = 0; p < test.size(); ++p) {
        peak_t = std::max(peak_t, test[p] / st);
        peak_r = std::max(peak_r, reference[p] / sr);
    }
    double e = 0;
    for (size_t p = 0; p < test.size(); ++p) e += std::pow(test[p] / st - reference[p] / sr, 2);
    return {peak_t / peak_r - 1, std::sqrt(e / test.size()) / peak_r};
}

// The window of `half` pixels round the star from a full frame (one value per pixel).
std::vector<double> window(const std::vector<float>& frame, int stride, int channels, int channel,
                           const test::RsStar& s, int half) {
    std::vector<double> w;
    for (int j = s.j - half; j <= s.j + half; ++j)
        for (int i = s.i - half; i <= s.i + half; ++i)
            w.push_back(i < 0 || j < 0 || i >= s.camera.width || j >= s.camera.height
                            ? 0.0
                            : frame[channels * (size_t(j) * stride + i) + channel]);
    return w;
}

// Half-width of the compared window: three Airy radii stretched as at the star's field (1/cos^3),
// film points per pixel: a quarter Airy radius apart at most.
int half_window(const Case& c, const test::RsStar& s) {
    double u, v;
    s.camera.tangent(s.i + 0.5, s.j + 0.5, u, v);
    const double stretch = std::pow(1 + u * u + v * v, 1.5);
    // the geometric shadow's radius a (1 + f / z), beyond the Airy pattern for large pinholes
    const double shadow = 0.5 * c.d_mm * 1e-3 * (1 + (std::isinf(c.depth) ? 0 : c.f_mm * 1e-3 / c.depth)) /
                          s.camera.pixel_pitch();
    return std::max(3, int(std::ceil(std::max(3 * c.airy_px(), 1.2 * shadow) * stretch)));
}
int film_points(const Case& c) { return std::clamp(int(std::ceil(16 / c.airy_px())), 2, 8); }

// One image of the stars (all on one camera and pinhole), white light of one wavelength each;
// `in_directions`: whether the plan convolved in direction cosines.
std::vector<float> convolution_image(const std::vector<test::RsStar>& stars, bool* in_directions = nullptr) {
    const test::RsStar& s = stars.front();
    const int w = s.camera.width, h = s.camera.height;
    const SpectralBasis basis = make_spectral_basis(explicit_sampling({s.wavelength}).value, kXyzTo709).value;
    std::vector<float> rgb(3 * size_t(w) * h, 0.0f), depth(size_t(w) * h, float(s.depth)), xyz(rgb.size());
    for (const test::RsStar& star : stars)
        for (int k = 0; k < 3; ++k) rgb[3 * (size_t(star.j) * w + star.i) + k] = 1.0f;
    auto plan = ConvolutionPlan::create({s.camera, 0, {ApertureShape::Circle, s.diameter}, basis, 1 / s.depth, {}});
    EXPECT_TRUE(plan.ok()) << plan.error;
    if (!plan.ok()) return xyz;
    if (in_directions) *in_directions = plan.value->in_directions();
    auto r = plan.value->apply({s.camera, rgb.data(), depth.data(), DepthMeaning::Planar}, true, xyz.data());
    EXPECT_TRUE(r.ok()) << r.error;
    return xyz;
}

// One image of the stars (all on one camera and pinhole), through the scene sums.
std::vector<float> exact_image(const std::vector<test::RsStar>& stars, Summation summation, int film_subsamples,
                               CoherenceMethod method = CoherenceMethod::Incoherent, int runs = 1) {
    const test::RsStar& s = stars.front();
    const int w = s.camera.width, h = s.camera.height;
    std::vector<float> power(size_t(w) * h, 0.0f), depth(power.size(), float(s.depth)), out(power.size(), 0.0f);
    for (const test::RsStar& star : stars) power[size_t(star.j) * w + star.i] = 1.0f;
    SceneSumSettings e;
    e.aperture = {ApertureShape::Circle, s.diameter};
    e.method = method;
    e.runs = runs;
    e.summation = summation;
    e.film_subsamples = film_subsamples;
    const MonochromeScene view{s.camera, power.data(), depth.data(), DepthMeaning::Planar};
    auto r = diffract_monochrome(view, s.wavelength, e, test_device(), out.data());
    EXPECT_TRUE(r.ok()) << r.error;
    return out;
}

// The runs [first, last) of neighbouring cases on one frame (the same camera, pinhole and depth)
// whose stars one image can hold; with `apart`, only while each star lies beyond the others'
// compared windows.
std::vector<std::pair<size_t, size_t>> frames(const Case* cases, size_t n, bool apart) {
    auto window_apart = [](const Case& a, const Case& b) {
        const test::RsStar sa = a.star(), sb = b.star();
        const int reach = half_window(a, sa) + half_window(b, sb);
        return std::abs(sa.i - sb.i) > reach || std::abs(sa.j - sb.j) > reach;
    };
    std::vector<std::pair<size_t, size_t>> runs;
    for (size_t first = 0, last; first < n; first = last) {
        const Case& a = cases[first];
        for (last = first + 1; last < n; ++last) {
            const Case& c = cases[last];
            bool joins = c.side == a.side && c.fov_deg == a.fov_deg && c.f_mm == a.f_mm && c.d_mm == a.d_mm &&
                         c.depth == a.depth;
            for (size_t k = first; joins && apart && k < last; ++k) joins = window_apart(cases[k], c);
            if (!joins) break;
        }
        runs.push_back({first, last});
    }
    return runs;
}

void expect_within(const Comparison& m, const std::string& what) {
    std::printf("%-90s peak %+6.2f%%  RMS %5.2f%% of peak\n", what.c_str(), 100 * m.peak, 100 * m.rms);
    EXPECT_LT(std::abs(m.peak), 0.02) << what;
    EXPECT_LT(m.rms, 0.01) << what;
}

// The stars of cases [first, last) (one image) through `summation` with n x n film points per
// pixel, each against the Rayleigh-Sommerfeld integral; where coded_runs(k), star k alone also
// through the random-phase method's 2 coded runs (one source: every run is its image, whatever
// its phase; two stars' coded runs of one class would not cancel).
// (`incoherent` false: the coded runs alone)
template <class CodedRuns>
void expect_stars_within(const Case* cases, size_t first, size_t last, Summation summation, int n,
                         CodedRuns coded_runs, bool incoherent = true) {
    std::vector<test::RsStar> stars;
    for (size_t k = first; k < last; ++k) stars.push_back(cases[k].star());
    const std::string by = summation == Summation::Kernel ? "kernel summation" : "point sums";
    const auto out = incoherent ? exact_image(stars, summation, n) : std::vector<float>();
    for (size_t k = first; k < last; ++k) {
        const test::RsStar& s = stars[k - first];
        const int half = half_window(cases[k], s);
        const auto reference = test::rs_window(s, half, n);
        if (incoherent)
            expect_within(compare(window(out, s.camera.width, 1, 0, s, half), reference, s, half),
                          by + ", " + cases[k].name());
        if (coded_runs(k)) {
            const auto runs = exact_image({s}, summation, n, CoherenceMethod::RandomPhase, 2);
            expect_within(compare(window(runs, s.camera.width, 1, 0, s, half), reference, s, half),
                          "random-phase, 2 runs, " + by + ", " + cases[k].name());
        }
    }
}

}  // namespace

// The convolution method (the default): frames of hundreds of pixels, where an anchor cell of
// several kernel radii would span the whole frame. Cases of one frame (the same camera and pinhole)
// are diffracted together, their stars in one image: the frame's kernels cost far more than its
// stars, and the stars lie tens of Airy radii apart (another star's tail moves a window's figures
// by 0.2 points at most: the 60 deg, 7.4 px star at 0.7 has its peak -0.57% alone, -0.74% so).
TEST(WideField, ConvolutionMethodMatchesTheRayleighSommerfeldIntegral) {
    const Case cases[] = {
        {256, 5, 50, 0.08, INFINITY, 0},     {512, 60, 50, 0.08, INFINITY, 0},   {512, 60, 50, 0.08, INFINITY, -0.5},
        {512, 60, 50, 0.08, INFINITY, 0.95}, {256, 60, 10, 0.02, INFINITY, 0},   {256, 60, 10, 0.02, INFINITY, 0.7},
        {256, 90, 50, 0.05, INFINITY, 0},    {512, 90, 20, 0.1, INFINITY, 0.37}, {512, 90, 20, 0.1, INFINITY, 0.93},
        {256, 60, 50, 0.315, 2.0, 0.3},      {256, 40, 50, 0.74, INFINITY, 0.7}, {128, 120, 10, 0.03, INFINITY, 0},
        {128, 120, 10, 0.03, INFINITY, -0.5}, {512, 20, 50, 0.05, INFINITY, 0.2},
    };
    for (const auto& [first, last] : frames(cases, sizeof cases / sizeof cases[0], false)) {
        std::vector<test::RsStar> stars;
        for (size_t k = first; k < last; ++k) stars.push_back(cases[k].star());
        const auto out = convolution_image(stars);
        for (size_t k = first; k < last; ++k) {
            const test::RsStar& s = stars[k - first];
            const int half = half_window(cases[k], s), n = film_points(cases[k]);
            expect_within(compare(window(out, s.camera.width, 3, 1, s, half), test::rs_window(s, half, n), s, half),
                          "convolution, " + cases[k].name());
        }
    }
}

// Pinholes far below the optimum (Airy cores of 14 px on the axis, Fresnel numbers of 0.0005-0.001)
// convolve in direction cosines, one kernel for every field: stars on the axis of 90 and 120 deg
// frames, 36 deg off it at 60 deg and 51 deg off it at 120 deg, where the PSF on the film is 1.9
// and 3.9 times wider radially. (Each off-axis star's window costs the integral tens of seconds.)
TEST(WideField, ConvolutionInDirectionCosinesMatchesTheRayleighSommerfeldIntegral) {
    const Case cases[] = {
        {256, 60, 50, 0.0106, INFINITY, 0.9}, {320, 90, 50, 0.0077, INFINITY, 0},
        {240, 120, 10, 0.0033, INFINITY, 0},  {240, 120, 10, 0.0033, INFINITY, -0.5},
    };
    // (a star apart from the others' windows shares their frame; these windows are wide)
    for (const auto& [first, last] : frames(cases, sizeof cases / sizeof cases[0], true)) {
        std::vector<test::RsStar> stars;
        for (size_t k = first; k < last; ++k) stars.push_back(cases[k].star());
        bool in_directions = false;
        const auto out = convolution_image(stars, &in_directions);
        EXPECT_TRUE(in_directions) << cases[first].name();
        for (size_t k = first; k < last; ++k) {
            const test::RsStar& s = stars[k - first];
            const int half = half_window(cases[k], s), n = film_points(cases[k]);
            expect_within(compare(window(out, s.camera.width, 3, 1, s, half), test::rs_window(s, half, n), s, half),
                          "convolution in directions, " + cases[k].name());
        }
    }
}

// The point sums (direct or nufft: the test binary's --summation) and the kernel summation, which
// convolves with amplitude kernels that those sums compute at field anchors, or, for coherent runs
// where the pinhole is Fraunhofer (the 60 and 90 deg frames here), with one kernel in direction
// cosines (core/src/summation/kernel/direction_runs.h): small frames (the point sums' cost grows
// with the frame), stars on the anchors and between them. Incoherent sums, and for the star between
// anchors at 60 deg, the 90 deg stars and the 10 deg star also the random-phase method's coded runs
// (one source: every run is its image, whatever its phase). The kernel summation's incoherent sums
// at 90 deg are left out: their anchors for this 2 px PSF, 138 x 138 over a margin that reaches
// 78 deg, each summed to (2R + 1)^2 film points (R = 62), take hours here (the next test takes a
// PSF of half a pixel there).
TEST(WideField, PointSumsAndKernelSummationMatchTheRayleighSommerfeldIntegral) {
    // (a PSF of two pixels on a frame of 32 at 90 deg takes a 5 um pinhole: few samples, cheap sums)
    const Case cases[] = {
        {64, 60, 10, 0.04, INFINITY, 0},   {64, 60, 10, 0.04, INFINITY, 0.45}, {64, 60, 10, 0.04, INFINITY, 0.9},
        {64, 60, 10, 0.04, INFINITY, -0.6},
        {32, 90, 1, 0.005, INFINITY, 0.2}, {32, 90, 1, 0.005, INFINITY, 0.6},  {48, 45, 2, 0.1, 1.0, 0.6},
        {64, 10, 20, 0.1, INFINITY, 0.5},
    };
    for (const auto& [first, last] : frames(cases, sizeof cases / sizeof cases[0], true)) {
        const Case& c = cases[first];
        // (at most 4 x 4 film points: the kernel summation's kernels sum to every one of them)
        const int n = std::min(4, film_points(c));
        for (const Summation summation : {test_summation(), Summation::Kernel}) {
            // (the kernel summation's coded runs: at 10 deg through anchors, at 60 and 90 deg in
            // directions; its runs of many stars: KernelRunsMatchThePointSumsWithTheSamePhases)
            const bool anchors_at_90 = summation == Summation::Kernel && c.fov_deg > 60;
            expect_stars_within(
                cases, first, last, summation, n,
                [&](size_t k) { return (c.fov_deg == 60 && cases[k].along == 0.45) || c.fov_deg >= 90 || c.fov_deg == 10; },
                !anchors_at_90);
        }
    }
}

// The kernel summation at the widest fields, 90 and 120 deg, and the point sums at 120 deg (at 90
// deg: above).
// There a kernel's radius is set by the PSF at the frame's corner, stretched 1/cos^3 (5.2 times
// the axis' at 90 deg, 18.5 times at 120), and the anchors follow the field's change over the
// frame and its margin, which reaches 60 to 78 deg: the kernels' sums, about anchors / 4 x
// (2R + 1)^2 film points x the pinhole lattice, are the job. PSFs of half a pixel on the axis
// (90 deg; 2.6 px at the corner) and of a sixth (120 deg; 2.9 px at the corner) keep each frame
// to about a minute here, with 2 x 2 film points per pixel at 90 deg and the pixel's centre at
// 120, in the image and the reference alike. At 90 deg also the random-phase method's coded runs
// for the mid-field star (one source: every run is its image).
TEST(WideField, KernelSummationAndPointSumsAtTheWidestFieldsMatchTheRayleighSommerfeldIntegral) {
    const Case cases[] = {
        {128, 90, 10, 0.086, INFINITY, 0},  {128, 90, 10, 0.086, INFINITY, 0.5}, {128, 90, 10, 0.086, INFINITY, 0.93},
        {128, 90, 10, 0.086, INFINITY, -0.37},
        {32, 120, 10, 0.041, INFINITY, 0},  {32, 120, 10, 0.041, INFINITY, -0.5}, {32, 120, 10, 0.041, INFINITY, 0.9},
    };
    for (const auto& [first, last] : frames(cases, sizeof cases / sizeof cases[0], true)) {
        const Case& c = cases[first];
        const int n = c.fov_deg > 100 ? 1 : 2;
        // (the point sums at 120 deg too: a second; at 90 deg they are above, on 32 px)
        std::vector<Summation> summations{Summation::Kernel};
        if (c.fov_deg > 100) summations.push_back(test_summation());
        for (const Summation summation : summations)
            expect_stars_within(cases, first, last, summation, n, [&](size_t k) {
                return summation == Summation::Kernel && c.fov_deg == 90 && cases[k].along == 0.5;
            });
    }
}

// Coded runs through the kernel summation against the point sums with the same phases: a textured frame at two
// depths, a PSF about two pixels wide, relative RMS over the frame within 1.5%. A run through the kernel summation
// lacks the cross terms of its kernels' far tails (docs/summation.md), about 0.8 sqrt(t / K) of
// the mean for a share t left out over K runs, so jobs of 64 runs or fewer take kernels holding
// more (t = 1.5%): 64 runs at 10 deg, measured 1.34% (1.75% with t = 3%). At 60 and 120 deg the
// pinhole that gives this PSF at f = 2 mm (9 and 3 um) is Fraunhofer, and the runs go through
// direction cosines, whole PSFs but for the margin's 1%: 60 deg, 128 runs, 0.97% (through the
// anchors it was 1.15%, 2.7% when the margin took the edge anchors' kernels, 8% when the anchors
// ignored the field). What is left there is the margin's: its sources are the edge continued pixel
// by pixel, each with its own phase, where the point sums' margin is cells of their own random
// numbers, so their cross terms differ run by run. With the frame's edge dark, and so its margin,
// the runs in directions are the point sums' to 0.07% (60 deg) and 0.06% (120 deg, where the lit
// margin's share made it 2.0%).
TEST(WideField, KernelRunsMatchThePointSumsWithTheSamePhases) {
    struct Frame {
        double fov;
        int runs;
        bool dark;  // the frame's outer 6 pixels dark: its margin (the edge continued) too
        double bound;
    };
    for (const auto& [fov, runs, dark, bound] :
         {Frame{10, 64, false, 0.015}, Frame{60, 128, false, 0.015}, Frame{60, 128, true, 0.005}, Frame{120, 96, true, 0.005}}) {
        const int side = 32;
        const PinholeCamera camera{side, side, fov * M_PI / 180, 2e-3};
        // a pinhole whose Airy radius is two pixels on the axis
        const double d = 1.22 * 550e-9 * camera.film_distance / (2 * camera.pixel_pitch());
        std::vector<float> power(size_t(side) * side), depth(power.size()), psf(power.size(), 0.0f),
            exact(power.size(), 0.0f);
        uint32_t state = 11;
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i) {
                state = state * 1664525u + 1013904223u;
                const bool near = ((i / 5 + j / 5) % 2) != 0;
                power[size_t(j) * side + i] = float((near ? 1.0 : 0.3) * (0.2 + 0.8 * (state >> 8) / double(1 << 24)));
                if (dark && (i < 6 || j < 6 || i >= side - 6 || j >= side - 6)) power[size_t(j) * side + i] = 0;
                depth[size_t(j) * side + i] = near ? 0.05f : 3.0f;
            }
        SceneSumSettings e;
        e.aperture = {ApertureShape::Circle, d};
        e.method = CoherenceMethod::RandomPhase;
        e.runs = runs;
        const MonochromeScene view{camera, power.data(), depth.data(), DepthMeaning::Planar};
        e.summation = Summation::Kernel;
        ASSERT_TRUE(diffract_monochrome(view, 550e-9, e, test_device(), psf.data()).ok());
        e.summation = test_summation();
        ASSERT_TRUE(diffract_monochrome(view, 550e-9, e, test_device(), exact.data()).ok());
        double diff = 0, mean = 0;
        for (size_t p = 0; p < psf.size(); ++p) {
            diff += std::pow(double(psf[p]) - exact[p], 2);
            mean += exact[p];
        }
        const double rms = std::sqrt(diff / psf.size()) / (mean / psf.size());
        std::printf("%g deg, pinhole %.4f mm, %d coded runs%s: the kernel summation against the point sums %.2f%% RMS\n", fov,
                    d * 1e3, e.runs, dark ? ", edges dark" : "", 100 * rms);
        EXPECT_LT(rms, bound) << fov << " deg" << (dark ? ", edges dark" : "");
    }
}
