// main() for the exact sums' tests: GoogleTest's, --summation=auto|direct|nufft and --device=cpu|gpu
// (summation_flag.h).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "summation_flag.h"

namespace {
wavecam::Summation g_summation = wavecam::Summation::Auto;
wavecam::ComputeDevice g_device;  // the CPU unless --device=gpu
}

wavecam::Summation test_summation() { return g_summation; }
const wavecam::ComputeDevice& test_device() { return g_device; }

std::string test_summation_flag() {
    std::string flags;
    if (g_summation != wavecam::Summation::Auto) flags += std::string(" --summation ") + summation_word(g_summation);
    if (g_device.gpu()) flags += " --device gpu";
    return flags;
}

int main(int argc, char** argv) {
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        const char* prefix = "--summation=";
        if (std::strcmp(argv[i], "--device=gpu") == 0) {
            g_device = wavecam::ComputeDevice::create(wavecam::Device::Gpu);
            if (!g_device.ok()) {
                std::fprintf(stderr, "--device=gpu: %s\n", g_device.error().c_str());
                return 2;
            }
            continue;
        }
        if (std::strncmp(argv[i], prefix, std::strlen(prefix)) != 0) {
            argv[kept++] = argv[i];
            continue;
        }
        const std::string word = argv[i] + std::strlen(prefix);
        if (word == "direct") g_summation = wavecam::Summation::Direct;
        else if (word == "nufft") g_summation = wavecam::Summation::Nufft;
        else if (word == "auto") g_summation = wavecam::Summation::Auto;
        else {
            std::fprintf(stderr, "--summation: expected auto, direct or nufft, got '%s'\n", word.c_str());
            return 2;
        }
    }
    argc = kept;
    ::testing::InitGoogleTest(&argc, argv);
    const int failed = RUN_ALL_TESTS();
    g_device.release();  // before the Vulkan loader may be unloaded at exit
    return failed;
}
