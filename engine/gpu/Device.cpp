#include "engine/gpu/Device.h"

#include "base/Log.h"
#include "engine/gpu/VkCheck.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

namespace orbis::gpu {
namespace {

std::string typeName(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
        default: return "other";
    }
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool hasExtension(VkPhysicalDevice pd, const char* name) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> props(count);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &count, props.data());
    return std::any_of(props.begin(), props.end(),
                       [&](const VkExtensionProperties& p) { return std::strcmp(p.extensionName, name) == 0; });
}

// The family that does graphics + compute (and presents to `surface` when given).
int findQueueFamily(VkPhysicalDevice pd, VkSurfaceKHR surface) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, families.data());
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    for (uint32_t i = 0; i < count; ++i) {
        if ((families[i].queueFlags & need) != need) continue;
        if (surface != VK_NULL_HANDLE) {
            VkBool32 present = VK_FALSE;
            vkGetPhysicalDeviceSurfaceSupportKHR(pd, i, surface, &present);
            if (!present) continue;
        }
        return static_cast<int>(i);
    }
    return -1;
}

}  // namespace

std::vector<PhysicalDeviceInfo> Device::enumerate(const Instance& instance) {
    uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance.vk(), &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance.vk(), &count, devices.data());
    std::vector<PhysicalDeviceInfo> out;
    for (VkPhysicalDevice pd : devices) {
        VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
        VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        props.pNext = &driver;
        vkGetPhysicalDeviceProperties2(pd, &props);
        PhysicalDeviceInfo info;
        info.handle = pd;
        info.name = props.properties.deviceName;
        info.type = typeName(props.properties.deviceType);
        info.apiVersion = props.properties.apiVersion;
        info.driverInfo = std::string(driver.driverName) + " " + driver.driverInfo;
        out.push_back(info);
    }
    return out;
}

void Device::pickPhysicalDevice(const std::string& select, VkSurfaceKHR surface) {
    const auto all = enumerate(instance_);
    if (all.empty()) throw GpuError(VK_ERROR_INITIALIZATION_FAILED, "no Vulkan device found");
    std::vector<PhysicalDeviceInfo> usable;
    for (const auto& d : all) {
        if (d.apiVersion < VK_API_VERSION_1_3) {
            log::debug("skipping device '", d.name, "': Vulkan ", VK_API_VERSION_MAJOR(d.apiVersion), ".",
                       VK_API_VERSION_MINOR(d.apiVersion), " < 1.3");
            continue;
        }
        if (findQueueFamily(d.handle, surface) < 0) continue;
        if (surface != VK_NULL_HANDLE && !hasExtension(d.handle, VK_KHR_SWAPCHAIN_EXTENSION_NAME)) continue;
        usable.push_back(d);
    }
    std::string names;
    for (const auto& d : all) names += (names.empty() ? "" : ", ") + ("'" + d.name + "' (" + d.type + ")");
    if (usable.empty())
        throw GpuError(VK_ERROR_INCOMPATIBLE_DRIVER, "no device supports Vulkan 1.3 with a graphics+compute queue; found: " + names);

    const PhysicalDeviceInfo* chosen = nullptr;
    auto firstOfType = [&](const char* type) -> const PhysicalDeviceInfo* {
        for (const auto& d : usable)
            if (d.type == type) return &d;
        return nullptr;
    };
    if (select.empty()) {
        chosen = firstOfType("discrete");
        if (!chosen) chosen = firstOfType("cpu");
        if (!chosen) chosen = &usable.front();
    } else if (select == "discrete" || select == "integrated" || select == "cpu" || select == "virtual") {
        chosen = firstOfType(select.c_str());
    } else if (std::all_of(select.begin(), select.end(), [](unsigned char c) { return std::isdigit(c); })) {
        const size_t index = std::stoul(select);
        if (index < all.size())
            for (const auto& d : usable)
                if (d.handle == all[index].handle) chosen = &d;
    } else {
        for (const auto& d : usable)
            if (lower(d.name).find(lower(select)) != std::string::npos) {
                chosen = &d;
                break;
            }
    }
    if (!chosen)
        throw GpuError(VK_ERROR_INITIALIZATION_FAILED, "no usable Vulkan device matches '" + select + "'; found: " + names);
    info_ = *chosen;
    physical_ = chosen->handle;
}

Device::Device(Instance& instance, const DeviceOptions& options) : instance_(instance) {
    loseAfterSubmits_ = options.loseAfterSubmits;
    if (const char* fault = std::getenv("ORBIS_FAULT_DEVICE_LOST_AFTER"); fault && loseAfterSubmits_ == 0) {
        loseAfterSubmits_ = std::strtoull(fault, nullptr, 10);
        log::warn("device: fault injection: the device is lost after ", loseAfterSubmits_, " submits");
    }
    pickPhysicalDevice(options.select, options.surface);
    vkGetPhysicalDeviceProperties(physical_, &properties_);
    queueFamily_ = static_cast<uint32_t>(findQueueFamily(physical_, options.surface));

    // Query what exists, then enable what we require plus the optional features we use.
    VkPhysicalDeviceVulkan13Features have13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceVulkan12Features have12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    have12.pNext = &have13;
    VkPhysicalDeviceFeatures2 have{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    have.pNext = &have12;
    vkGetPhysicalDeviceFeatures2(physical_, &have);
    if (!have12.timelineSemaphore || !have13.dynamicRendering || !have13.synchronization2)
        throw GpuError(VK_ERROR_FEATURE_NOT_PRESENT,
                       "device '" + info_.name + "' lacks timeline semaphores, dynamic rendering or synchronization2");

    VkPhysicalDeviceVulkan13Features use13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    use13.dynamicRendering = VK_TRUE;
    use13.synchronization2 = VK_TRUE;
    VkPhysicalDeviceVulkan12Features use12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    use12.pNext = &use13;
    use12.timelineSemaphore = VK_TRUE;
    use12.hostQueryReset = have12.hostQueryReset;
    use12.shaderBufferInt64Atomics = have12.shaderBufferInt64Atomics;
    use12.scalarBlockLayout = have12.scalarBlockLayout;
    VkPhysicalDeviceFeatures2 use{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    use.pNext = &use12;
    use.features.shaderInt64 = have.features.shaderInt64;
    use.features.shaderFloat64 = have.features.shaderFloat64;
    use.features.samplerAnisotropy = have.features.samplerAnisotropy;
    use.features.fillModeNonSolid = have.features.fillModeNonSolid;
    use.features.wideLines = have.features.wideLines;

    features_.shaderInt64 = have.features.shaderInt64;
    features_.shaderFloat64 = have.features.shaderFloat64;
    features_.bufferInt64Atomics = have12.shaderBufferInt64Atomics;
    features_.samplerAnisotropy = have.features.samplerAnisotropy;
    features_.fillModeNonSolid = have.features.fillModeNonSolid;
    features_.wideLines = have.features.wideLines;

    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &familyCount, families.data());
    features_.timestamps = families[queueFamily_].timestampValidBits > 0 && properties_.limits.timestampPeriod > 0;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = queueFamily_;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;

    std::vector<const char*> extensions;
    if (options.surface != VK_NULL_HANDLE) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);

    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.pNext = &use;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queueInfo;
    info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VK_CHECK(vkCreateDevice(physical_, &info, nullptr, &device_));
    vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);

    VkSemaphoreTypeCreateInfo timelineInfo{VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO};
    timelineInfo.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
    VkSemaphoreCreateInfo semInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    semInfo.pNext = &timelineInfo;
    VK_CHECK(vkCreateSemaphore(device_, &semInfo, nullptr, &timeline_));

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT | VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = queueFamily_;
    VK_CHECK(vkCreateCommandPool(device_, &poolInfo, nullptr, &oneShotPool_));

    allocator_ = std::make_unique<MemoryAllocator>(physical_, device_);
    if (instance_.debugUtilsEnabled())
        setObjectName_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(instance_.vk(), "vkSetDebugUtilsObjectNameEXT"));
    log::info("device: ", info_.name, " (", info_.type, ", ", info_.driverInfo, ")");
}

Device::~Device() {
    if (device_ == VK_NULL_HANDLE) return;
    try {
        waitIdle();
    } catch (const GpuError& e) {   // lost while waiting: destroy what is left all the same
        log::error("device: ", e.what());
        lost_ = true;
        waitIdle();
    }
    allocator_.reset();
    vkDestroyCommandPool(device_, oneShotPool_, nullptr);
    vkDestroySemaphore(device_, timeline_, nullptr);
    vkDestroyDevice(device_, nullptr);
}

uint64_t Device::submit(VkCommandBuffer cmd, std::span<const VkSemaphoreSubmitInfo> waits,
                        std::span<const VkSemaphoreSubmitInfo> signals) {
    const uint64_t value = lastSubmitted_ + 1;
    std::vector<VkSemaphoreSubmitInfo> allSignals(signals.begin(), signals.end());
    VkSemaphoreSubmitInfo timelineSignal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    timelineSignal.semaphore = timeline_;
    timelineSignal.value = value;
    timelineSignal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    allSignals.push_back(timelineSignal);

    VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmdInfo.commandBuffer = cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.waitSemaphoreInfoCount = static_cast<uint32_t>(waits.size());
    submit.pWaitSemaphoreInfos = waits.data();
    submit.commandBufferInfoCount = cmd != VK_NULL_HANDLE ? 1 : 0;
    submit.pCommandBufferInfos = &cmdInfo;
    submit.signalSemaphoreInfoCount = static_cast<uint32_t>(allSignals.size());
    submit.pSignalSemaphoreInfos = allSignals.data();
    if (lost_) check(VK_ERROR_DEVICE_LOST, "vkQueueSubmit2 (the device was lost before)");
    if (loseAfterSubmits_ > 0 && value > loseAfterSubmits_)
        check(VK_ERROR_DEVICE_LOST, "vkQueueSubmit2 (injected: ORBIS_FAULT_DEVICE_LOST_AFTER)");
    check(vkQueueSubmit2(queue_, 1, &submit, VK_NULL_HANDLE), "vkQueueSubmit2");
    lastSubmitted_ = value;
    return value;
}

void Device::check(VkResult result, const char* what) const {
    if (result >= 0) return;
    if (result == VK_ERROR_DEVICE_LOST) lost_ = true;
    throw GpuError(result, std::string(what) + " failed on " + info_.name);
}

void Device::wait(uint64_t value) {
    if (value == 0 || lost_) return;
    VkSemaphoreWaitInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO};
    info.semaphoreCount = 1;
    info.pSemaphores = &timeline_;
    info.pValues = &value;
    check(vkWaitSemaphores(device_, &info, UINT64_MAX), "vkWaitSemaphores");
}

uint64_t Device::completedValue() const {
    if (lost_) return lastSubmitted_;   // nothing runs any more: everything retired may go
    uint64_t value = 0;
    check(vkGetSemaphoreCounterValue(device_, timeline_, &value), "vkGetSemaphoreCounterValue");
    return value;
}

void Device::runOnce(const std::function<void(VkCommandBuffer)>& record) {
    if (recordingFrame_)
        throw GpuError(VK_ERROR_UNKNOWN, "Device::runOnce called while a frame is being recorded");
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = oneShotPool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(device_, &alloc, &cmd));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    record(cmd);
    VK_CHECK(vkEndCommandBuffer(cmd));
    wait(submit(cmd));
    vkFreeCommandBuffers(device_, oneShotPool_, 1, &cmd);
    collectRetired();
}

void Device::retire(std::function<void()> destroy) {
    std::lock_guard lock(retireMutex_);
    retired_.push_back({lastSubmitted_.load() + 1, std::move(destroy)});
}

void Device::collectRetired() {
    const uint64_t done = completedValue();
    std::vector<std::function<void()>> ready;
    {
        std::lock_guard lock(retireMutex_);
        while (!retired_.empty() && retired_.front().value <= done) {
            ready.push_back(std::move(retired_.front().destroy));
            retired_.pop_front();
        }
    }
    for (auto& f : ready) f();
}

void Device::waitIdle() {
    if (!lost_) check(vkDeviceWaitIdle(device_), "vkDeviceWaitIdle");
    // Destroying an object may retire another (a buffer owning a view): loop until empty.
    for (;;) {
        std::deque<Retired> all;
        {
            std::lock_guard lock(retireMutex_);
            all.swap(retired_);
        }
        if (all.empty()) break;
        for (auto& r : all) r.destroy();
    }
}

void Device::setDebugName(uint64_t handle, VkObjectType type, const char* name) {
    if (!setObjectName_ || !name) return;
    VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    info.objectType = type;
    info.objectHandle = handle;
    info.pObjectName = name;
    setObjectName_(device_, &info);
}

}  // namespace orbis::gpu
