// What a ComputeDevice handle holds (compute_device.h), shared by its copies. Internal to core.
#pragma once
#include <atomic>
#include <memory>
#include <string>

#include "wavecam/compute_device.h"
#include "wavecam/result.h"

namespace wavecam {

class GpuSums;
namespace gpu {
class Context;
}

// What ran on a device, as bits (evaluators_run, ComputeDevice::ran_on).
enum RunBit : unsigned {
    kDirectToPinhole = 1,
    kNufftToPinhole = 2,
    kDirectToFilm = 4,
    kNufftToFilm = 8,
    kRanOnGpu = 16,
    kRanOnCpu = 32,
};

struct ComputeDevice::Impl {
    Device setting = Device::Cpu;
    std::string error;                       // why no Vulkan device was opened
    std::shared_ptr<gpu::Context> context;   // null: the CPU
    std::shared_ptr<GpuSums> sums;           // the direct sums' pipelines on the context
    std::string description = "cpu";
    mutable std::atomic<unsigned> ran{0};    // RunBits, as the sums commit and run
};

namespace detail {

// A Vulkan context (vulkan_context.h): any device, a discrete GPU first, or only a discrete GPU.
// In a build without Vulkan, a failure that says so.
Result<std::shared_ptr<gpu::Context>> open_vulkan(bool discrete_only);

// Notes what ran on `device` (RunBits); the default handle keeps nothing.
inline void note_run(const ComputeDevice& device, unsigned bits) {
    if (device.impl()) device.impl()->ran |= bits;
}

}  // namespace detail
}  // namespace wavecam
