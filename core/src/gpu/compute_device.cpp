// The device handle (compute_device.h): the CPU, or a Vulkan context and the direct sums'
// pipelines on it, opened afresh at every create().
#include "wavecam/compute_device.h"

#include "gpu/compute_device_impl.h"
#include "wavecam/gpu_sums.h"

namespace wavecam {

const char* device_word(Device d) { return d == Device::Cpu ? "cpu" : d == Device::Gpu ? "gpu" : "auto"; }

ComputeDevice ComputeDevice::create(Device setting) {
    ComputeDevice d;
    d.impl_ = std::make_shared<Impl>();
    Impl& m = *d.impl_;
    m.setting = setting;
    if (setting == Device::Cpu) return d;
    auto context = detail::open_vulkan(setting == Device::Auto);
    if (!context.ok()) {
        m.error = context.error;
        return d;
    }
    m.context = std::move(context.value);
    auto sums = GpuSums::create(d);
    if (!sums.ok()) {  // the pipelines: the context is of no use without them
        m.error = sums.error;
        m.context.reset();
        return d;
    }
    m.sums = std::move(sums.value);
    m.description = m.sums->description();
    return d;
}

Device ComputeDevice::setting() const { return impl_ ? impl_->setting : Device::Cpu; }
bool ComputeDevice::gpu() const { return impl_ && impl_->context; }
bool ComputeDevice::ok() const { return !impl_ || impl_->setting != Device::Gpu || impl_->context; }

const std::string& ComputeDevice::error() const {
    static const std::string none;
    return impl_ ? impl_->error : none;
}

std::string ComputeDevice::description() const { return impl_ ? impl_->description : "cpu"; }

}  // namespace wavecam
