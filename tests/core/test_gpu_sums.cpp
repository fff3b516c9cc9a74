// The Vulkan evaluators (wavecam/gpu_sums.h, the kernel summation's runs) and the device handle that
// holds them (wavecam/compute_device.h), run on whatever Vulkan device the environment gives:
// ctest points VK_ICD_FILENAMES at Mesa's lavapipe, so the GPU code runs on the CPU in CI.
// Checked against the CPU's direct sums (relative RMS <= 1e-4, both float), against analytic
// optics as the CPU is (the Airy pattern's first dark ring, Fresnel zones on axis), and through
// scene frames; the device handles' settings and failures. The command line's device key:
// tests/fronts/test_gpu_device.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "gpu/gpu_kernel_summation.h"
#include "vulkan_test.h"
#include "wavecam/compute_device.h"
#include "wavecam/gpu_sums.h"
#include "wavecam/propagation.h"
#include "wavecam/scene_diffraction.h"
#include "wavecam/summation_plan.h"

using namespace wavecam;
using wavecam::test::gpu_device;
using wavecam::test::relative_rms;

namespace {

// Direct sums on a device of their own: the handle is let go at once, the sums keep its context.
std::shared_ptr<GpuSums> device(bool double_blocks = true) {
    auto g = GpuSums::create(gpu_device(), double_blocks);
    EXPECT_TRUE(g.ok()) << g.error;
    return g.value;
}

// VK_ICD_FILENAMES pointed at no driver while it lives, then as it was.
struct NoVulkanDriver {
    const char* icd = std::getenv("VK_ICD_FILENAMES");
    const std::string saved = icd ? icd : "";
    NoVulkanDriver() { setenv("VK_ICD_FILENAMES", "/nonexistent/wavecam_icd.json", 1); }
    ~NoVulkanDriver() {
        if (icd) setenv("VK_ICD_FILENAMES", saved.c_str(), 1);
        else unsetenv("VK_ICD_FILENAMES");
    }
};

std::vector<std::complex<float>> as_complex(const PinholeField& f) {
    std::vector<std::complex<float>> v(f.re.size());
    for (size_t i = 0; i < v.size(); ++i) v[i] = {f.re[i], f.im[i]};
    return v;
}

// Sources within 10 degrees of the axis, 0.3 m to 3 m away (finite) or at infinity, with random
// amplitudes and phases.
std::vector<PointSource> random_sources(int finite, int plane, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<PointSource> s;
    for (int k = 0; k < finite + plane; ++k) {
        const double ax = 0.17 * (2 * u(rng) - 1), ay = 0.17 * (2 * u(rng) - 1);
        PointSource p;
        p.at_infinity = k >= finite;
        const double d = p.at_infinity ? 1.0 : 0.3 + 2.7 * u(rng);
        const double n = std::sqrt(1 + ax * ax + ay * ay);
        p.x = d * ax / n;
        p.y = d * ay / n;
        p.z = d / n;
        p.amplitude = 0.2 + u(rng);
        p.phase = 2 * M_PI * u(rng);
        s.push_back(p);
    }
    return s;
}

// A 0.1 mm circular pinhole sampled for rays within 0.2 of the axis: about 3000-6000 samples.
ApertureSamples pinhole(double lambda) { return sample_aperture({ApertureShape::Circle, 0.1e-3}, sample_pitch(lambda, 0.2)); }

FilmPoints film_grid(int n, double half_width, double f) {
    FilmPoints film;
    film.film_distance = f;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            film.x.push_back(float(half_width * (2.0 * i / (n - 1) - 1)));
            film.y.push_back(float(half_width * (2.0 * j / (n - 1) - 1)));
        }
    return film;
}

}  // namespace

TEST(GpuSums, NamesItsDeviceAndDriver) {
    REQUIRE_VULKAN();
    auto g = device();
    ASSERT_TRUE(g);
    EXPECT_FALSE(g->device_name().empty());
    EXPECT_FALSE(g->driver().empty());
    EXPECT_NE(g->description().find(g->device_name()), std::string::npos);
    // Mesa's software Vulkan (its device is named llvmpipe) is called what it is
    if (g->device_name().find("llvmpipe") != std::string::npos) {
        EXPECT_NE(g->description().find("software Vulkan on the CPU"), std::string::npos) << g->description();
    }
}

// Sum 1, sources -> pinhole: finite sources, plane waves and both together, three wavelengths;
// the blocks added in double and as a compensated float pair.
TEST(GpuSums, PinholeSumMatchesTheCpu) {
    REQUIRE_VULKAN();
    for (bool f64 : {true, false})
    for (double lambda : {450e-9, 550e-9, 650e-9}) {
        auto g = device(f64);
        ASSERT_TRUE(g);
        if (!f64) {
            EXPECT_FALSE(g->double_blocks());  // the compensated float pair is what runs
        }
        const ApertureSamples s = pinhole(lambda);
        ASSERT_GT(s.size(), 2000u);
        for (auto [finite, plane] : {std::pair{300, 0}, {0, 200}, {150, 100}}) {
            const auto sources = random_sources(finite, plane, uint32_t(finite + 7 * plane));
            PinholeField cpu, gpu;
            illuminate_pinhole(s, sources, lambda, cpu);
            auto r = g->illuminate_pinhole(s, sources, lambda, gpu);
            ASSERT_TRUE(r.ok()) << r.error;
            EXPECT_LE(relative_rms(as_complex(gpu), as_complex(cpu)), 1e-4)
                << lambda << " m, " << finite << " finite, " << plane << " plane, double " << f64;
        }
    }
}

// Sum 2, pinhole -> film, from the CPU's pinhole field, three wavelengths.
TEST(GpuSums, FilmSumMatchesTheCpu) {
    REQUIRE_VULKAN();
    for (bool f64 : {true, false})
    for (double lambda : {450e-9, 550e-9, 650e-9}) {
        auto g = device(f64);
        ASSERT_TRUE(g);
        const ApertureSamples s = pinhole(lambda);
        PinholeField field;
        illuminate_pinhole(s, random_sources(60, 20, 3), lambda, field);
        const FilmPoints film = film_grid(24, 1e-3, 20e-3);
        std::vector<std::complex<double>> cpu(film.size(), 0.0), gpu(film.size(), 0.0);
        add_film_field({s, field, film, lambda}, cpu.data());
        auto r = g->add_film_field(s, field, film, lambda, gpu.data());
        ASSERT_TRUE(r.ok()) << r.error;
        EXPECT_LE(relative_rms(gpu, cpu), 1e-4) << lambda << " m, double " << f64;
    }
}

// A sum of more terms than one invocation may loop over on every device (lavapipe stops a loop
// after 65535 iterations): a 0.1 mm pinhole sampled at lambda / 2, 104517 samples, to a row of
// film points, and to them from one plane wave.
TEST(GpuSums, SumsOfMoreThanSixtyFiveThousandTermsMatchTheCpu) {
    REQUIRE_VULKAN();
    const double lambda = 550e-9;
    auto g = device();
    ASSERT_TRUE(g);
    const ApertureSamples s = sample_aperture({ApertureShape::Circle, 0.1e-3}, sample_pitch(lambda, 1.0));
    ASSERT_GT(s.size(), 100000u);
    const std::vector<PointSource> sources = random_sources(0, 1, 5);
    PinholeField cpu_field, gpu_field;
    illuminate_pinhole(s, sources, lambda, cpu_field);
    ASSERT_TRUE(g->illuminate_pinhole(s, sources, lambda, gpu_field).ok());
    EXPECT_LE(relative_rms(as_complex(gpu_field), as_complex(cpu_field)), 1e-4);
    FilmPoints film;
    film.film_distance = 50e-3;
    for (int i = 0; i < 64; ++i) film.x.push_back(float(i * 2e-6)), film.y.push_back(0.0f);
    std::vector<std::complex<double>> cpu(film.size(), 0.0), gpu(film.size(), 0.0);
    add_film_field({s, cpu_field, film, lambda}, cpu.data());
    ASSERT_TRUE(g->add_film_field(s, cpu_field, film, lambda, gpu.data()).ok());
    EXPECT_LE(relative_rms(gpu, cpu), 1e-4);
}

// Several weight vectors in one dispatch (more runs than a workgroup sums together): each run
// as the CPU computes it alone.
TEST(GpuSums, RunsAtOnceMatchTheCpuRunByRun) {
    REQUIRE_VULKAN();
    auto g = device();
    ASSERT_TRUE(g);
    const double lambda = 550e-9;
    const ApertureSamples s = pinhole(lambda);
    std::vector<PointSource> sources = random_sources(100, 30, 11);
    const int runs = 6;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 2 * M_PI);
    std::vector<std::complex<double>> w;
    std::vector<std::vector<PointSource>> each(runs, sources);
    for (int r = 0; r < runs; ++r)
        for (PointSource& p : each[r]) {
            p.phase = u(rng);
            w.push_back(std::polar(p.amplitude, p.phase));
        }
    std::vector<PinholeField> fields;
    auto r1 = g->illuminate_pinhole_runs(s, sources, {w, runs}, lambda, fields);
    ASSERT_TRUE(r1.ok()) << r1.error;
    ASSERT_EQ(fields.size(), size_t(runs));
    const FilmPoints film = film_grid(12, 0.5e-3, 20e-3);
    std::vector<std::vector<std::complex<double>>> gpu(runs, std::vector<std::complex<double>>(film.size()));
    std::vector<std::complex<double>*> out;
    for (auto& v : gpu) out.push_back(v.data());
    auto r2 = g->add_film_field_runs(s, fields, film, lambda, out);
    ASSERT_TRUE(r2.ok()) << r2.error;
    for (int r = 0; r < runs; ++r) {
        PinholeField cpu;
        illuminate_pinhole(s, each[r], lambda, cpu);
        EXPECT_LE(relative_rms(as_complex(fields[r]), as_complex(cpu)), 1e-4) << "run " << r;
        std::vector<std::complex<double>> film_cpu(film.size(), 0.0);
        add_film_field({s, cpu, film, lambda}, film_cpu.data());
        EXPECT_LE(relative_rms(gpu[r], film_cpu), 1e-4) << "run " << r;
    }
}

// A point source's image by the GPU against analytic optics, with the CPU's own bounds
// (test_psf_analytic.cpp): the Airy pattern's first dark ring at 1.22 lambda f / d (N = 0.02),
// and the on-axis irradiance 4 sin^2(pi N / 2) of N Fresnel zones.
TEST(GpuSums, PointSourceImageIsTheAiryPattern) {
    REQUIRE_VULKAN();
    auto g = device();
    ASSERT_TRUE(g);
    const double f = 50e-3, lambda = 550e-9, d = 47e-6;
    const double ring = 1.22 * lambda * f / d;
    const ApertureSamples s = sample_aperture({ApertureShape::Circle, d}, sample_pitch(lambda));
    const PointSource src = source_at_field_angle(INFINITY, 0);
    PinholeField field;
    ASSERT_TRUE(g->illuminate_pinhole(s, {src}, lambda, field).ok());
    FilmPoints film;
    film.film_distance = f;
    std::vector<double> xs;
    for (int i = 0; i <= 400; ++i) {
        xs.push_back(1.5 * ring * i / 400);
        film.x.push_back(float(xs.back()));
        film.y.push_back(0.0f);
    }
    std::vector<std::complex<double>> u(film.size(), 0.0);
    ASSERT_TRUE(g->add_film_field(s, field, film, lambda, u.data()).ok());
    std::vector<double> prof;
    for (auto v : u) prof.push_back(std::norm(v));
    size_t m = 1;
    while (m + 1 < prof.size() && !(prof[m] <= prof[m - 1] && prof[m] <= prof[m + 1])) ++m;
    ASSERT_LT(m + 1, prof.size());
    const double y0 = prof[m - 1], y1 = prof[m], y2 = prof[m + 1];
    const double radius = xs[m] + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2) * (xs[1] - xs[0]);
    EXPECT_NEAR(radius / ring, 1.0, 0.02);
    EXPECT_LT(prof[m] / prof[0], 1e-3);
    // Fresnel zones on axis, the zone count from its definition (plane wave: film side only)
    for (double n_target : {0.5, 1.0, 2.0, 3.0}) {
        const double a = std::sqrt(n_target * lambda * f);
        const double n = 2 * (std::sqrt(f * f + a * a) - f) / lambda;
        const ApertureSamples big = sample_aperture({ApertureShape::Circle, 2 * a}, sample_pitch(lambda, 0.1));
        PinholeField w;
        ASSERT_TRUE(g->illuminate_pinhole(big, {src}, lambda, w).ok());
        FilmPoints centre;
        centre.film_distance = f;
        centre.x = centre.y = {0.0f};
        std::complex<double> c = 0;
        ASSERT_TRUE(g->add_film_field(big, w, centre, lambda, &c).ok());
        const double expected = 4 * std::pow(std::sin(M_PI * n / 2), 2);
        EXPECT_NEAR(std::norm(c), expected, std::max(0.01 * expected, 0.01)) << "N = " << n;
    }
}

// A small scene-sum frame through the scene path with the device set: GPU and CPU agree.
TEST(GpuSums, SceneFrameMatchesTheCpu) {
    REQUIRE_VULKAN();
    // the incoherent sum dispatches each source alone: a smaller frame (lavapipe is slow)
    for (CoherenceMethod method : {CoherenceMethod::RandomPhase, CoherenceMethod::Incoherent}) {
        const bool incoherent = method == CoherenceMethod::Incoherent;
        PinholeCamera c;
        c.width = incoherent ? 5 : 12;
        c.height = incoherent ? 4 : 10;
        c.film_distance = 10e-3;
        c.fov_h = 2 * std::atan(c.width * 50e-6 / (2 * c.film_distance));
        std::vector<float> power(c.width * c.height), depth(power.size(), 2.0f);
        for (size_t p = 0; p < power.size(); ++p) power[p] = (p % 7) * 0.3f + 0.1f;
        SceneSumSettings s;
        s.aperture = {ApertureShape::Circle, 0.1e-3};
        s.method = method;
        s.runs = 2;
        s.film_subsamples = 1;
        s.summation = Summation::Direct;
        s.sin_theta_max = 550e-9 * 36 / 0.1e-3;
        std::vector<float> cpu(power.size(), 0.0f), gpu(power.size(), 0.0f), fallback(power.size(), 0.0f);
        const MonochromeScene scene{c, power.data(), depth.data(), DepthMeaning::Planar};
        SumReport on_cpu, on_gpu;  // what ran, as the job's report has it
        ASSERT_TRUE(diffract_monochrome(scene, 550e-9, s, ComputeDevice{}, cpu.data(), {}, &on_cpu).ok());
        auto r = diffract_monochrome(scene, 550e-9, s, gpu_device(), gpu.data(), {}, &on_gpu);
        ASSERT_TRUE(r.ok()) << r.error;
        EXPECT_EQ(on_cpu.evaluators().words(), "direct");
        EXPECT_EQ(on_cpu.ran_on(gpu_device()), "cpu");
        EXPECT_EQ(on_gpu.evaluators().words(), "direct");
        EXPECT_EQ(on_gpu.ran_on(gpu_device()), gpu_device().description());
        EXPECT_LE(relative_rms(gpu, cpu), 1e-4);
        EXPECT_NE(gpu, cpu);  // the device's own float sums, not the CPU's
        // `auto` with no discrete GPU (lavapipe is a CPU device): the CPU's image, bit for bit
        const ComputeDevice automatic = ComputeDevice::create(Device::Auto);
        ASSERT_TRUE(diffract_monochrome(scene, 550e-9, s, automatic, fallback.data()).ok());
        if (!automatic.gpu()) {
            EXPECT_EQ(fallback, cpu);
        }
    }
}

// The kernel summation's runs on the device (transforms, products and film powers in its shaders,
// the kernels' one-source sums through its direct terms) against the same runs on the CPU: a
// textured 12 x 10 frame at 30 deg over two depths (two layers), random-phase and incoherent; `auto`
// without a discrete GPU gives the CPU's image bit for bit.
TEST(GpuSums, KernelSummationRunsMatchTheCpu) {
    REQUIRE_VULKAN();
    PinholeCamera c{12, 10, 30 * M_PI / 180, 2e-3};
    std::vector<float> power(size_t(c.width) * c.height), depth(power.size());
    uint32_t state = 11;
    for (size_t p = 0; p < power.size(); ++p) {
        state = state * 1664525u + 1013904223u;
        power[p] = float((state >> 8) / double(1 << 24));
        depth[p] = (p % c.width) < size_t(c.width / 2) ? 0.05f : 2.0f;
    }
    for (CoherenceMethod method : {CoherenceMethod::RandomPhase, CoherenceMethod::Incoherent}) {
        SceneSumSettings s;
        s.aperture = {ApertureShape::Circle, 0.04e-3};
        s.method = method;
        s.runs = 3;
        s.summation = Summation::Kernel;
        std::vector<float> cpu(power.size(), 0.0f), gpu(power.size(), 0.0f), fallback(power.size(), 0.0f);
        const MonochromeScene scene{c, power.data(), depth.data(), DepthMeaning::Planar};
        auto r = diffract_monochrome(scene, 550e-9, s, ComputeDevice{}, cpu.data());
        ASSERT_TRUE(r.ok()) << r.error;
        SumReport report;  // the runs' device, as the job's report has it
        r = diffract_monochrome(scene, 550e-9, s, gpu_device(), gpu.data(), {}, &report);
        ASSERT_TRUE(r.ok()) << r.error;
        EXPECT_EQ(report.ran_on(gpu_device()), gpu_device().description());
        EXPECT_EQ(report.evaluators().words(), "");  // the kernels' own sums are no sum of the frame's
        EXPECT_NE(gpu, cpu);  // the runs on the device
        double light = 0;
        for (const float x : cpu) light += x;
        EXPECT_GT(light, 0);
        const double rms = relative_rms(gpu, cpu);
        EXPECT_LE(rms, 1e-4) << (method == CoherenceMethod::Incoherent ? "incoherent" : "runs");
        std::printf("the kernel summation on the device vs the CPU (%s): relative RMS %.2e\n",
                    method == CoherenceMethod::Incoherent ? "incoherent" : "3 runs", rms);
        const ComputeDevice automatic = ComputeDevice::create(Device::Auto);
        ASSERT_TRUE(diffract_monochrome(scene, 550e-9, s, automatic, fallback.data()).ok());
        if (!automatic.gpu()) {
            EXPECT_EQ(fallback, cpu);
        }
    }
}

// A kernel of more sub-points than one submission holds dispatches (a product each: 300 here,
// as a large pinhole's Fresnel structure gives): every sub-point's product reaches the film.
// With every spectrum 1 each sub-point's film is the sources transformed there and back, N x the
// sources, so a pixel's sum over the sub-points is points x N^2 x |source|^2.
TEST(GpuSums, KernelSummationTakesMoreSubPointsThanOneSubmission) {
    REQUIRE_VULKAN();
    const int n = 8, points = 300;
    auto made = detail::GpuKernelSummation::create(gpu_device(), n, n, 1, points);
    ASSERT_TRUE(made.ok()) << made.error;
    detail::GpuKernelSummation& gpu = *made.value;
    const std::vector<std::complex<float>> ones(size_t(n) * n, 1.0f);
    for (int p = 0; p < points; ++p) ASSERT_TRUE(gpu.set_spectrum(0, p, ones.data()).ok());
    gpu.begin_run();
    std::complex<float>* sources = gpu.sources();
    for (int q = 0; q < n * n; ++q) sources[q] = {float(q % 5) / 4, 0.0f};
    auto added = gpu.add_sources(0);
    ASSERT_TRUE(added.ok()) << added.error;
    std::vector<float> sum;
    ASSERT_TRUE(gpu.finish_run(false, sum).ok());
    ASSERT_EQ(sum.size(), size_t(n) * n);
    const double N = double(n) * n;
    for (int q = 0; q < n * n; ++q) {
        const double expected = points * N * N * std::pow((q % 5) / 4.0, 2);
        EXPECT_NEAR(sum[q], expected, 1e-4 * points * N * N) << q;
    }
}

// The device setting's handles: `cpu` is no GPU, `auto` takes only a discrete GPU (else the CPU,
// the reason kept), and a build without Vulkan says so; a released handle is the CPU, its copies
// keep the device.
TEST(ComputeDevice, SettingsGiveTheirHandles) {
    const ComputeDevice cpu = ComputeDevice::create(Device::Cpu);
    EXPECT_TRUE(cpu.ok());
    EXPECT_FALSE(cpu.gpu());
    EXPECT_EQ(cpu.description(), "cpu");
    auto no_sums = GpuSums::create(cpu);
    EXPECT_FALSE(no_sums.ok());
    EXPECT_EQ(no_sums.field, "device");
#ifndef WAVECAM_HAVE_VULKAN
    const ComputeDevice absent = ComputeDevice::create(Device::Gpu);
    EXPECT_FALSE(absent.ok());
    EXPECT_NE(absent.error().find("built without"), std::string::npos) << absent.error();
    return;
#endif
    const ComputeDevice any = gpu_device();
    ASSERT_TRUE(any.ok());
    EXPECT_TRUE(any.error().empty());
    const ComputeDevice discrete = ComputeDevice::create(Device::Auto);
    EXPECT_TRUE(discrete.ok());
    if (!discrete.gpu()) {
        EXPECT_NE(discrete.error().find("no discrete GPU"), std::string::npos) << discrete.error();
        EXPECT_EQ(discrete.description(), "cpu");
    }
    ComputeDevice copy = any;
    copy.release();
    EXPECT_FALSE(copy.gpu());
    EXPECT_TRUE(any.gpu());
}

// A creation that fails is a handle holding why (`gpu`: not ok; `auto`: the CPU, the reason
// kept), plans refuse a failed `gpu` handle rather than run on the CPU, and once the cause is gone
// the next creation in the same process opens the device: nothing remembers the failure.
TEST(ComputeDevice, AFailedCreationIsHeldAndTheNextTriesAgain) {
    REQUIRE_VULKAN();
    ComputeDevice failed, fallback;
    {
        NoVulkanDriver none;
        failed = ComputeDevice::create(Device::Gpu);
        fallback = ComputeDevice::create(Device::Auto);
    }
    EXPECT_FALSE(failed.ok());
    EXPECT_FALSE(failed.gpu());
    EXPECT_NE(failed.error().find("Vulkan"), std::string::npos) << failed.error();
    EXPECT_TRUE(fallback.ok());
    EXPECT_FALSE(fallback.gpu());
    EXPECT_NE(fallback.error().find("Vulkan"), std::string::npos) << fallback.error();
    const double lambda = 550e-9;
    SummationPlan plan = SummationPlan::create(failed, SumKind::SourcesToPinhole, pinhole(lambda), lambda,
                                               {Summation::Direct, kSummationTolerance, 0});
    auto refused = plan.set_points(random_sources(3, 1, 5));
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.field, "device");
    EXPECT_NE(refused.error.find("Vulkan"), std::string::npos) << refused.error;
    const ComputeDevice again = ComputeDevice::create(Device::Gpu);
    EXPECT_TRUE(again.ok() && again.gpu()) << again.error();
}

// On a GPU a plan takes the direct terms where `auto` on the CPU takes the NUFFTs (many sources),
// and refuses nufft naming it.
TEST(ComputeDevice, AGpuRunsTheDirectTermsAndRefusesTheNufft) {
    REQUIRE_VULKAN();
    const double lambda = 550e-9;
    const ApertureSamples samples = pinhole(lambda);
    const std::vector<PointSource> many = random_sources(20000, 0, 9);
    const ComputeDevice cpu = ComputeDevice::create(Device::Cpu), gpu = gpu_device();
    SummationPlan on_cpu = SummationPlan::create(cpu, SumKind::SourcesToPinhole, samples, lambda,
                                                 {Summation::Auto, kSummationTolerance, 0});
    ASSERT_TRUE(on_cpu.set_points(many).ok());
    EXPECT_EQ(on_cpu.choice().evaluator, Evaluator::Nufft);  // the case this test is about
    EXPECT_FALSE(on_cpu.choice().gpu);
    SummationPlan on_gpu = SummationPlan::create(gpu, SumKind::SourcesToPinhole, samples, lambda,
                                                 {Summation::Auto, kSummationTolerance, 0});
    ASSERT_TRUE(on_gpu.set_points(many).ok());
    EXPECT_EQ(on_gpu.choice().evaluator, Evaluator::Direct);
    EXPECT_TRUE(on_gpu.choice().gpu);
    SummationPlan nufft = SummationPlan::create(gpu, SumKind::SourcesToPinhole, samples, lambda,
                                                {Summation::Nufft, kSummationTolerance, 0});
    auto refused = nufft.set_points(many);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.field, "summation");
    EXPECT_NE(refused.error.find("device gpu: the nufft summation has no GPU evaluator"), std::string::npos)
        << refused.error;
}
