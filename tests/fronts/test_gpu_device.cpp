// The command line's device key on the Vulkan device the environment gives (ctest: lavapipe):
// `--device gpu` with every summation runs on the device or is refused, the output's header names
// the device and the evaluator that ran, and without a driver `gpu` is refused while `auto` says
// it runs on the CPU. The evaluators themselves: tests/core/test_gpu_sums.cpp.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>

#include <filesystem>
#include <string>
#include <vector>

#include "command_runner.h"
#include "vulkan_test.h"

using namespace wavecam;
using namespace wavecam::test;
namespace fs = std::filesystem;

// The command line with `--device gpu` and every summation: direct, kernel and auto run on the device
// (the CPU's image within float rounding, but not its bits) and the header names the device and
// the one evaluator that ran; nufft is refused before any work, named. On the CPU, `auto` names
// what it chose and why in the job line. With no Vulkan driver
// `gpu` is refused and writes nothing, and `auto` says in the job line that the CPU runs it.
TEST(GpuDevice, CommandLineDeviceKey) {
    REQUIRE_VULKAN();
    const fs::path dir = scratch("gpu_device");
    const std::string in = (dir / "in.exr").string();
    write_render(in, 10, 8, 2.0f, 30.0f);
    const std::string quick = " --film-distance 20mm --pinhole 0.2mm --wavelengths 550nm --runs 1 "
                              "--method random-phase --film-subsamples 1 ";
    auto apply = [&](const std::string& out, const std::string& extra, const std::string& env = "") {
        return run_command(env + std::string(WAVECAM_BINARY) + " apply " + in + " -o " + (dir / out).string() +
                           quick + extra);
    };
    auto pixels = [&](const std::string& name, std::string* device = nullptr, std::string* chosen = nullptr) {
        OIIO::ImageBuf b((dir / name).string());
        std::vector<float> p(10 * 8 * 3);
        EXPECT_TRUE(b.read()) << name;
        b.get_pixels(OIIO::ROI(0, 10, 0, 8, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, p.data());
        if (device) *device = b.spec().get_string_attribute("wavecam.device");
        if (chosen) *chosen = b.spec().get_string_attribute("wavecam.summation-chosen");
        return p;
    };
    const std::string gpu = gpu_device().description();
    ASSERT_FALSE(gpu.empty());
    for (const std::string summation : {"direct", "kernel", "auto"}) {
        const auto on_gpu = apply(summation + "_gpu.exr", "--summation " + summation + " --device gpu");
        ASSERT_EQ(on_gpu.status, 0) << on_gpu.output;
        EXPECT_NE(on_gpu.output.find("summation" + std::string(summation == "auto" ? " (" : " on ")),
                  std::string::npos) << on_gpu.output;
        EXPECT_NE(on_gpu.output.find(" on " + gpu), std::string::npos) << on_gpu.output;  // the estimate line
        std::string device, chosen;
        const auto g = pixels(summation + "_gpu.exr", &device, &chosen);
        EXPECT_EQ(device, gpu) << summation;
        // auto on the device: direct or kernel, named; the CPU then runs what the header names
        std::string ran = summation;
        if (summation == "auto") {
            EXPECT_TRUE(chosen == "direct" || chosen == "kernel") << chosen;
            ran = chosen;
        }
        const auto on_cpu = apply(summation + "_cpu.exr", "--summation " + ran + " --device cpu");
        ASSERT_EQ(on_cpu.status, 0) << on_cpu.output;
        const auto c = pixels(summation + "_cpu.exr", &device);
        EXPECT_EQ(device, "cpu");
        EXPECT_LE(relative_rms(g, c), 1e-4) << summation;
        EXPECT_NE(g, c) << summation << ": the CPU's bits, not the device's";
    }
    const auto nufft = apply("nufft_gpu.exr", "--summation nufft --device gpu");
    EXPECT_NE(nufft.status, 0);
    EXPECT_NE(nufft.output.find("device gpu: the nufft summation has no GPU evaluator"), std::string::npos)
        << nufft.output;
    EXPECT_EQ(nufft.output.find(" terms"), std::string::npos) << "refused before the estimate: " << nufft.output;
    EXPECT_FALSE(fs::exists(dir / "nufft_gpu.exr"));
    // on the CPU, auto names the one evaluator that ran: the same image as that evaluator asked for
    const auto cpu_auto = apply("auto_cpu_choice.exr", "--summation auto --device cpu");
    ASSERT_EQ(cpu_auto.status, 0) << cpu_auto.output;
    std::string device, chosen;
    const auto a = pixels("auto_cpu_choice.exr", &device, &chosen);
    EXPECT_EQ(device, "cpu");
    EXPECT_EQ(chosen.find(" or "), std::string::npos) << chosen;
    // the job line names it and says why: the chooser's estimate beside the one it weighed against
    EXPECT_NE(cpu_auto.output.find("auto summation (" + chosen + "; at "), std::string::npos) << cpu_auto.output;
    EXPECT_NE(cpu_auto.output.find(" terms estimated against "), std::string::npos) << cpu_auto.output;
    if (chosen == "direct" || chosen == "nufft" || chosen == "kernel") {
        const auto named = apply("named_cpu.exr", "--summation " + chosen + " --device cpu");
        ASSERT_EQ(named.status, 0) << named.output;
        EXPECT_EQ(pixels("named_cpu.exr"), a) << chosen;
    }
    const std::string no_driver = "VK_ICD_FILENAMES=/nonexistent/wavecam_icd.json ";
    const auto missing = apply("missing.exr", "--summation direct --device gpu", no_driver);
    EXPECT_NE(missing.status, 0);
    EXPECT_NE(missing.output.find("Vulkan"), std::string::npos) << missing.output;
    EXPECT_FALSE(fs::exists(dir / "missing.exr"));
    const auto fallback = apply("fallback.exr", "--summation direct --device auto", no_driver);
    ASSERT_EQ(fallback.status, 0) << fallback.output;
    EXPECT_NE(fallback.output.find("(GPU: none usable: "), std::string::npos) << fallback.output;
    EXPECT_NE(fallback.output.find("; on the CPU)"), std::string::npos) << fallback.output;
    pixels("fallback.exr", &device);
    EXPECT_EQ(device, "cpu");
    const auto bad = apply("bad.exr", "--summation direct --device tpu");
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.output.find("'cpu', 'gpu', 'auto'"), std::string::npos) << bad.output;
    fs::remove_all(dir);
}
