// The evaluator the exact sums' tests run their sums through: auto (the default) unless the test
// binary was started with --summation=direct or --summation=nufft, on the CPU unless --device=gpu
// (the Vulkan evaluator of the direct terms, through one device handle the binary creates).
// tests/CMakeLists.txt registers every such test once more per evaluator, so the same physics
// checks hold through each; the flags are the only way in (no environment variable changes a
// default).
#pragma once
#include <string>

#include "wavecam/summation_plan.h"

wavecam::Summation test_summation();
const wavecam::ComputeDevice& test_device();

// " --summation WORD --device WORD" for a command the test runs, each left out at its default.
std::string test_summation_flag();
