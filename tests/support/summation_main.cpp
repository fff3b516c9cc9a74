// main() for the point sums' tests: GoogleTest's, --summation=WORD (any of the evaluators' table) and --device=cpu|gpu
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

double one_source_bound() { return g_summation == wavecam::Summation::Kernel ? 3e-3 : 1e-3; }

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
        bool known = false;
        std::string words;
        for (const auto& [choice, summation] : wavecam::summation_choices()) {
            if (word == choice) {
                g_summation = summation;
                known = true;
            }
            words += std::string(words.empty() ? "" : ", ") + choice;
        }
        if (!known) {
            std::fprintf(stderr, "--summation: expected one of %s, got '%s'\n", words.c_str(), word.c_str());
            return 2;
        }
    }
    argc = kept;
    ::testing::InitGoogleTest(&argc, argv);
    const int failed = RUN_ALL_TESTS();
    g_device.release();  // before the Vulkan loader may be unloaded at exit
    return failed;
}
