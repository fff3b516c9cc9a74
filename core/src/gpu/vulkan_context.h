// A small create/use/release layer over Vulkan compute for the GPU evaluators (gpu_sums.cpp,
// gpu_kernel_summation.cpp), which share one context through a device handle (compute_device.h): one
// device and queue, host-visible buffers, compute pipelines from embedded SPIR-V, one submission
// at a time (serialised here) waited for. Failures are values naming the Vulkan call and its
// result. Internal to core.
#pragma once
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "wavecam/result.h"

namespace wavecam::gpu {

// A storage buffer in host-visible, coherent memory, mapped for its whole life.
class Buffer {
public:
    Buffer() = default;
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;
    ~Buffer();
    void* data() const { return mapped_; }
    size_t bytes() const { return bytes_; }
    VkBuffer handle() const { return buffer_; }

private:
    friend class Context;
    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    void* mapped_ = nullptr;
    size_t bytes_ = 0;
};

// A compute pipeline whose bindings 0..n-1 are storage buffers, with push constants.
class Pipeline {
public:
    Pipeline() = default;
    Pipeline(Pipeline&& o) noexcept { *this = std::move(o); }
    Pipeline& operator=(Pipeline&& o) noexcept;
    ~Pipeline();
    uint32_t bindings() const { return bindings_; }

private:
    friend class Context;
    VkDevice device_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    uint32_t bindings_ = 0, push_bytes_ = 0;
};

class Context {
public:
    // discrete_only: only a discrete GPU will do (`auto`); else any device, a discrete GPU first,
    // then integrated, virtual, and CPU implementations such as lavapipe.
    static Result<std::unique_ptr<Context>> create(bool discrete_only);
    ~Context();

    const std::string& name() const { return name_; }
    const std::string& driver() const { return driver_; }
    // "discrete GPU", "integrated GPU", "virtual GPU", "software Vulkan on the CPU" (lavapipe,
    // whose device Mesa names llvmpipe) or "Vulkan device"
    const std::string& kind() const { return kind_; }
    bool float64() const { return float64_; }
    // The largest buffer a dispatch binds (the device's storage range, at most 64 MiB).
    size_t max_buffer_bytes() const { return max_buffer_; }

    Result<Buffer> buffer(size_t bytes);
    Result<Pipeline> pipeline(const unsigned char* spirv, size_t bytes, uint32_t bindings, uint32_t push_bytes);
    // The most shared memory one workgroup may use, in bytes.
    size_t shared_memory_bytes() const { return shared_memory_; }
    // Binds `buffers` to bindings 0.. in order, pushes `push`, dispatches groups_x x groups_y
    // workgroups and waits for them.
    Result<bool> dispatch(const Pipeline& p, const std::vector<const Buffer*>& buffers, const void* push,
                          uint32_t groups_x, uint32_t groups_y);
    // Several dispatches in one submission, each after the one before has written its buffers,
    // waited for as one (at most kMaxSteps).
    struct Step {
        const Pipeline* pipeline;
        std::vector<const Buffer*> buffers;
        std::array<unsigned char, 128> push;  // the pipeline's push constants (Vulkan's minimum 128 bytes)
        uint32_t groups_x, groups_y;
    };
    static constexpr uint32_t kMaxSteps = 256;
    Result<bool> submit(const std::vector<Step>& steps);

private:
    Context() = default;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queue_family_ = 0;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer commands_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptors_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    std::mutex submitting_;  // the command buffer, descriptor pool, queue and fence: one submission at a time
    std::string name_, driver_, kind_;
    bool float64_ = false;
    size_t max_buffer_ = 0, shared_memory_ = 0;
};

}  // namespace wavecam::gpu
