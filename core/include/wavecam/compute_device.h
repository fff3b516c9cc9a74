// Where a job's point sums run (docs/gpu.md): a handle on the CPU or on one Vulkan device,
// created for a job (or for as long as a host runs) from the `device` setting and passed down
// to every evaluator, as Embree passes its RTCDevice:
//   cpu   the CPU;
//   gpu   any Vulkan device, a discrete GPU first; none is a failed handle (ok() false, error());
//   auto  a discrete GPU, else the CPU, the reason kept (error()).
// A GPU handle holds one Vulkan context that both GPU evaluators share: the direct sums
// (gpu_sums.h) and the kernel summation's runs. The context lives while a handle, or an evaluator
// made from one, holds it; release() lets this handle's hold go. Nothing outlives the handles:
// a failure belongs to the handle that met it, and the next create() tries afresh.
// The handle is passed explicitly to what runs on it (SummationPlan::create, diffract_monochrome);
// what ran is the job's report (summation_plan.h, SumReport), not the handle's.
#pragma once
#include <memory>
#include <string>

namespace wavecam {

// The `device` setting.
enum class Device { Cpu, Gpu, Auto };
const char* device_word(Device d);  // "cpu", "gpu", "auto"

class ComputeDevice {
public:
    ComputeDevice() = default;  // the CPU, made by no setting (records nothing)
    static ComputeDevice create(Device setting);
    void release() { impl_.reset(); }  // this handle becomes the default: the CPU

    Device setting() const;
    bool gpu() const;                  // the sums run on a Vulkan device
    bool ok() const;                   // false: `gpu` was asked for and none could be opened
    const std::string& error() const;  // why no Vulkan device was opened ("" when one was or none was asked)
    // "cpu", or the Vulkan device, its kind and driver: "NVIDIA ..., discrete GPU (driver ...)",
    // "llvmpipe (LLVM 15.0.6, 256 bits), software Vulkan on the CPU (llvmpipe, Mesa 22.3.6 ...)".
    std::string description() const;

    struct Impl;
    const Impl* impl() const { return impl_.get(); }

private:
    std::shared_ptr<Impl> impl_;
};

}  // namespace wavecam
