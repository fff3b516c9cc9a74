// The evaluator the point sums' tests run their sums through: auto (the default) unless the test
// binary was started with --summation=WORD (direct, nufft or kernel: the evaluators' table), on the
// CPU unless --device=gpu (the Vulkan evaluator, through one device handle the binary creates).
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

// The largest difference, relative to the peak, of a one-source image from its point-source
// reference that the evaluator is held to: 1e-3 for the point sums; 3e-3 for the kernel summation, whose kernels
// are the sums' at anchors and depth layers with a far tail beyond them (docs/summation.md, "The
// error, stated and tested"; 1.5-2e-3 measured).
double one_source_bound();
