// Vulkan compute wrapper (vulkan_context.h).
#include "gpu/vulkan_context.h"

#include <algorithm>
#include <cstring>

#include "gpu/compute_device_impl.h"

namespace wavecam::gpu {
namespace {

std::string vk_error(VkResult r) {
    switch (r) {
        case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
        case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
        case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
        case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
        case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
        case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
        case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
        case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
        case VK_TIMEOUT: return "VK_TIMEOUT";
        default: return "VkResult " + std::to_string(int(r));
    }
}

template <class T>
Result<T> failed(const std::string& call, VkResult r) {
    return Result<T>::failure("Vulkan: " + call + " failed (" + vk_error(r) + ")");
}

// Lower is preferred: discrete, integrated, virtual, CPU (lavapipe), other.
int device_rank(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

std::string device_kind(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "software Vulkan on the CPU";
        default: return "Vulkan device";
    }
}

bool compute_family(VkPhysicalDevice d, uint32_t& family) {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &n, nullptr);
    std::vector<VkQueueFamilyProperties> q(n);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &n, q.data());
    for (uint32_t i = 0; i < n; ++i)
        if (q[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
            family = i;
            return true;
        }
    return false;
}

// The driver as its name and version string (Vulkan 1.2's driver properties), else the number.
std::string driver_of(VkPhysicalDevice d, const VkPhysicalDeviceProperties& p) {
    if (p.apiVersion >= VK_API_VERSION_1_2) {
        VkPhysicalDeviceDriverProperties drv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
        VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &drv, {}};
        vkGetPhysicalDeviceProperties2(d, &p2);
        return std::string(drv.driverName) + ", " + drv.driverInfo;
    }
    return "driver version " + std::to_string(p.driverVersion);
}

// The instance: fails where no Vulkan driver could be loaded.
Result<bool> create_instance(VkInstance& instance) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "wavecam";
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    if (VkResult r = vkCreateInstance(&ici, nullptr, &instance); r != VK_SUCCESS)
        return Result<bool>::failure(
            "no Vulkan driver could be loaded (vkCreateInstance: " + vk_error(r) +
            "): install one (a GPU vendor's driver, or mesa-vulkan-drivers) or check VK_ICD_FILENAMES");
    return Result<bool>::success(true);
}

// The preferred device with a compute queue (device_rank; only a discrete GPU where
// `discrete_only`), and its compute queue's family; fails naming the devices seen.
Result<bool> choose_device(VkInstance instance, bool discrete_only, VkPhysicalDevice& physical,
                           uint32_t& queue_family) {
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(instance, &n, devices.data());
    int best = 5;
    std::string seen;
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        seen += (seen.empty() ? "" : ", ") + std::string(p.deviceName);
        uint32_t family;
        const int rank = device_rank(p.deviceType);
        if (!compute_family(d, family) || rank >= best || (discrete_only && rank != 0)) continue;
        best = rank;
        physical = d;
        queue_family = family;
    }
    if (!physical) {
        if (devices.empty()) return Result<bool>::failure("the Vulkan driver found no device");
        return Result<bool>::failure(std::string(discrete_only ? "no discrete GPU" : "no device with a compute queue") +
                                     " among the Vulkan devices (" + seen + ")");
    }
    return Result<bool>::success(true);
}

// The logical device on `physical` (named `name` in its failure), one queue of `queue_family`,
// with double precision in shaders where the device has it.
Result<bool> create_device(VkPhysicalDevice physical, uint32_t queue_family, const VkPhysicalDeviceFeatures& have,
                           const std::string& name, VkDevice& device) {
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = queue_family;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkPhysicalDeviceFeatures want{};
    want.shaderFloat64 = have.shaderFloat64;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.pEnabledFeatures = &want;
    if (VkResult r = vkCreateDevice(physical, &dci, nullptr, &device); r != VK_SUCCESS)
        return failed<bool>("vkCreateDevice on " + name, r);
    return Result<bool>::success(true);
}

// What a submission takes: the command pool and its one command buffer, the descriptor pool
// (kMaxSteps sets of 8 storage buffers) and the fence.
Result<bool> create_submission(VkDevice device, uint32_t queue_family, VkCommandPool& pool, VkCommandBuffer& commands,
                               VkDescriptorPool& descriptors, VkFence& fence) {
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = queue_family;
    if (VkResult r = vkCreateCommandPool(device, &pci, nullptr, &pool); r != VK_SUCCESS)
        return failed<bool>("vkCreateCommandPool", r);
    VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cai.commandPool = pool;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    if (VkResult r = vkAllocateCommandBuffers(device, &cai, &commands); r != VK_SUCCESS)
        return failed<bool>("vkAllocateCommandBuffers", r);
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 8 * Context::kMaxSteps};
    VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpi.maxSets = Context::kMaxSteps;
    dpi.poolSizeCount = 1;
    dpi.pPoolSizes = &size;
    if (VkResult r = vkCreateDescriptorPool(device, &dpi, nullptr, &descriptors); r != VK_SUCCESS)
        return failed<bool>("vkCreateDescriptorPool", r);
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (VkResult r = vkCreateFence(device, &fci, nullptr, &fence); r != VK_SUCCESS)
        return failed<bool>("vkCreateFence", r);
    return Result<bool>::success(true);
}

}  // namespace

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    std::swap(device_, o.device_);
    std::swap(buffer_, o.buffer_);
    std::swap(memory_, o.memory_);
    std::swap(mapped_, o.mapped_);
    std::swap(bytes_, o.bytes_);
    return *this;
}

Buffer::~Buffer() {
    if (!device_) return;
    if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);  // unmaps
}

Pipeline& Pipeline::operator=(Pipeline&& o) noexcept {
    std::swap(device_, o.device_);
    std::swap(set_layout_, o.set_layout_);
    std::swap(layout_, o.layout_);
    std::swap(pipeline_, o.pipeline_);
    std::swap(bindings_, o.bindings_);
    std::swap(push_bytes_, o.push_bytes_);
    return *this;
}

Pipeline::~Pipeline() {
    if (!device_) return;
    if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
    if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
    if (set_layout_) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
}

Result<std::unique_ptr<Context>> Context::create(bool discrete_only) {
    using R = Result<std::unique_ptr<Context>>;
    std::unique_ptr<Context> c(new Context);
    if (auto r = create_instance(c->instance_); !r.ok()) return R::failure(r);
    if (auto r = choose_device(c->instance_, discrete_only, c->physical_, c->queue_family_); !r.ok())
        return R::failure(r);
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(c->physical_, &props);
    VkPhysicalDeviceFeatures have;
    vkGetPhysicalDeviceFeatures(c->physical_, &have);
    c->name_ = props.deviceName;
    c->driver_ = driver_of(c->physical_, props);
    c->kind_ = device_kind(props.deviceType);
    c->float64_ = have.shaderFloat64;
    c->max_buffer_ = std::min<size_t>(props.limits.maxStorageBufferRange, size_t(64) << 20);
    c->shared_memory_ = props.limits.maxComputeSharedMemorySize;
    if (auto r = create_device(c->physical_, c->queue_family_, have, c->name_, c->device_); !r.ok())
        return R::failure(r);
    vkGetDeviceQueue(c->device_, c->queue_family_, 0, &c->queue_);
    if (auto r = create_submission(c->device_, c->queue_family_, c->pool_, c->commands_, c->descriptors_, c->fence_);
        !r.ok())
        return R::failure(r);
    return R::success(std::move(c));
}

Context::~Context() {
    if (device_) {
        vkDeviceWaitIdle(device_);
        if (fence_) vkDestroyFence(device_, fence_, nullptr);
        if (descriptors_) vkDestroyDescriptorPool(device_, descriptors_, nullptr);
        if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
        vkDestroyDevice(device_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
}

Result<Buffer> Context::buffer(size_t bytes) {
    Buffer b;
    b.device_ = device_;
    b.bytes_ = bytes;
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = std::max<size_t>(bytes, 16);
    bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    if (VkResult r = vkCreateBuffer(device_, &bci, nullptr, &b.buffer_); r != VK_SUCCESS)
        return failed<Buffer>("vkCreateBuffer", r);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device_, b.buffer_, &req);
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(physical_, &mem);
    const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    uint32_t type = mem.memoryTypeCount;
    for (uint32_t i = 0; i < mem.memoryTypeCount && type == mem.memoryTypeCount; ++i)
        if ((req.memoryTypeBits & (1u << i)) && (mem.memoryTypes[i].propertyFlags & want) == want) type = i;
    if (type == mem.memoryTypeCount) return Result<Buffer>::failure("Vulkan: " + name_ + " has no host-visible memory");
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = type;
    if (VkResult r = vkAllocateMemory(device_, &mai, nullptr, &b.memory_); r != VK_SUCCESS)
        return failed<Buffer>("vkAllocateMemory of " + std::to_string(req.size) + " bytes", r);
    if (VkResult r = vkBindBufferMemory(device_, b.buffer_, b.memory_, 0); r != VK_SUCCESS)
        return failed<Buffer>("vkBindBufferMemory", r);
    if (VkResult r = vkMapMemory(device_, b.memory_, 0, VK_WHOLE_SIZE, 0, &b.mapped_); r != VK_SUCCESS)
        return failed<Buffer>("vkMapMemory", r);
    return Result<Buffer>::success(std::move(b));
}

Result<Pipeline> Context::pipeline(const unsigned char* spirv, size_t bytes, uint32_t bindings, uint32_t push_bytes) {
    Pipeline p;
    p.device_ = device_;
    p.bindings_ = bindings;
    p.push_bytes_ = push_bytes;
    std::vector<VkDescriptorSetLayoutBinding> b(bindings);
    for (uint32_t i = 0; i < bindings; ++i)
        b[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo sli{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    sli.bindingCount = bindings;
    sli.pBindings = b.data();
    if (VkResult r = vkCreateDescriptorSetLayout(device_, &sli, nullptr, &p.set_layout_); r != VK_SUCCESS)
        return failed<Pipeline>("vkCreateDescriptorSetLayout", r);
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
    VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pli.setLayoutCount = 1;
    pli.pSetLayouts = &p.set_layout_;
    pli.pushConstantRangeCount = 1;
    pli.pPushConstantRanges = &range;
    if (VkResult r = vkCreatePipelineLayout(device_, &pli, nullptr, &p.layout_); r != VK_SUCCESS)
        return failed<Pipeline>("vkCreatePipelineLayout", r);
    std::vector<uint32_t> words((bytes + 3) / 4);  // the code as aligned words
    std::memcpy(words.data(), spirv, bytes);
    VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    smi.codeSize = bytes;
    smi.pCode = words.data();
    VkShaderModule module;
    if (VkResult r = vkCreateShaderModule(device_, &smi, nullptr, &module); r != VK_SUCCESS)
        return failed<Pipeline>("vkCreateShaderModule", r);
    VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    cpi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpi.stage.module = module;
    cpi.stage.pName = "main";
    cpi.layout = p.layout_;
    const VkResult r = vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &cpi, nullptr, &p.pipeline_);
    vkDestroyShaderModule(device_, module, nullptr);
    if (r != VK_SUCCESS) return failed<Pipeline>("vkCreateComputePipelines", r);
    return Result<Pipeline>::success(std::move(p));
}

Result<bool> Context::dispatch(const Pipeline& p, const std::vector<const Buffer*>& buffers, const void* push,
                               uint32_t groups_x, uint32_t groups_y) {
    Step step{&p, buffers, {}, groups_x, groups_y};
    std::memcpy(step.push.data(), push, p.push_bytes_);
    return submit({step});
}

Result<bool> Context::submit(const std::vector<Step>& steps) {
    using R = Result<bool>;
    std::lock_guard<std::mutex> lock(submitting_);
    if (steps.size() > kMaxSteps) return R::failure("Vulkan: more dispatches in one submission than the pool holds");
    vkResetDescriptorPool(device_, descriptors_, 0);
    std::vector<VkDescriptorSet> sets(steps.size());
    for (size_t k = 0; k < steps.size(); ++k) {
        const Step& s = steps[k];
        if (s.buffers.size() != s.pipeline->bindings_) return R::failure("Vulkan: dispatch with the wrong number of buffers");
        VkDescriptorSetAllocateInfo dai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        dai.descriptorPool = descriptors_;
        dai.descriptorSetCount = 1;
        dai.pSetLayouts = &s.pipeline->set_layout_;
        if (VkResult r = vkAllocateDescriptorSets(device_, &dai, &sets[k]); r != VK_SUCCESS)
            return failed<bool>("vkAllocateDescriptorSets", r);
        std::vector<VkDescriptorBufferInfo> info(s.buffers.size());
        std::vector<VkWriteDescriptorSet> writes(s.buffers.size());
        for (size_t i = 0; i < s.buffers.size(); ++i) {
            info[i] = {s.buffers[i]->handle(), 0, VK_WHOLE_SIZE};
            writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            writes[i].dstSet = sets[k];
            writes[i].dstBinding = uint32_t(i);
            writes[i].descriptorCount = 1;
            writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            writes[i].pBufferInfo = &info[i];
        }
        vkUpdateDescriptorSets(device_, uint32_t(writes.size()), writes.data(), 0, nullptr);
    }

    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vkResetCommandBuffer(commands_, 0);
    if (VkResult r = vkBeginCommandBuffer(commands_, &begin); r != VK_SUCCESS)
        return failed<bool>("vkBeginCommandBuffer", r);
    for (size_t k = 0; k < steps.size(); ++k) {
        const Step& s = steps[k];
        if (k > 0) {  // each step reads what the one before wrote
            VkMemoryBarrier between{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_SHADER_WRITE_BIT,
                                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT};
            vkCmdPipelineBarrier(commands_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                 0, 1, &between, 0, nullptr, 0, nullptr);
        }
        vkCmdBindPipeline(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, s.pipeline->pipeline_);
        vkCmdBindDescriptorSets(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, s.pipeline->layout_, 0, 1, &sets[k], 0,
                                nullptr);
        if (s.pipeline->push_bytes_)
            vkCmdPushConstants(commands_, s.pipeline->layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                               s.pipeline->push_bytes_, s.push.data());
        vkCmdDispatch(commands_, s.groups_x, s.groups_y, 1);
    }
    // the shaders' writes made visible to the host's reads of the mapped memory
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_SHADER_WRITE_BIT,
                            VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(commands_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier,
                         0, nullptr, 0, nullptr);
    if (VkResult r = vkEndCommandBuffer(commands_); r != VK_SUCCESS) return failed<bool>("vkEndCommandBuffer", r);
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &commands_;
    vkResetFences(device_, 1, &fence_);
    if (VkResult r = vkQueueSubmit(queue_, 1, &si, fence_); r != VK_SUCCESS) return failed<bool>("vkQueueSubmit", r);
    if (VkResult r = vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX); r != VK_SUCCESS)
        return failed<bool>("vkWaitForFences", r);
    return R::success(true);
}

}  // namespace wavecam::gpu

namespace wavecam::detail {

Result<std::shared_ptr<gpu::Context>> open_vulkan(bool discrete_only) {
    using R = Result<std::shared_ptr<gpu::Context>>;
    auto c = gpu::Context::create(discrete_only);
    if (!c.ok()) return R::failure(c);
    return R::success(std::move(c.value));
}

}  // namespace wavecam::detail
