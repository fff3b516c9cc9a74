// What a ComputeDevice handle holds (compute_device.h), shared by its copies. Internal to core.
#pragma once
#include <memory>
#include <string>

#include "wavecam/compute_device.h"
#include "wavecam/result.h"

namespace wavecam {

class GpuSums;
namespace gpu {
class Context;
}

struct ComputeDevice::Impl {
    Device setting = Device::Cpu;
    std::string error;                       // why no Vulkan device was opened
    std::shared_ptr<gpu::Context> context;   // null: the CPU
    std::shared_ptr<GpuSums> sums;           // the direct sums' pipelines on the context
    std::string description = "cpu";
};

namespace detail {

// A Vulkan context (vulkan_context.h): any device, a discrete GPU first, or only a discrete GPU.
// In a build without Vulkan, a failure that says so.
Result<std::shared_ptr<gpu::Context>> open_vulkan(bool discrete_only);

}  // namespace detail
}  // namespace wavecam
