#pragma once
// Move-only owners for the simple Vulkan object kinds (pipelines, layouts, samplers, pools).
// Like Buffer and Image they retire their handle on destruction; the GPU may still use it.

#include "engine/gpu/Device.h"

#include <vulkan/vulkan.h>

#include <utility>

namespace orbis::gpu {

namespace detail {
inline void destroy(VkDevice d, VkPipeline h) { vkDestroyPipeline(d, h, nullptr); }
inline void destroy(VkDevice d, VkPipelineLayout h) { vkDestroyPipelineLayout(d, h, nullptr); }
inline void destroy(VkDevice d, VkDescriptorSetLayout h) { vkDestroyDescriptorSetLayout(d, h, nullptr); }
inline void destroy(VkDevice d, VkDescriptorPool h) { vkDestroyDescriptorPool(d, h, nullptr); }
inline void destroy(VkDevice d, VkSampler h) { vkDestroySampler(d, h, nullptr); }
inline void destroy(VkDevice d, VkShaderModule h) { vkDestroyShaderModule(d, h, nullptr); }
inline void destroy(VkDevice d, VkQueryPool h) { vkDestroyQueryPool(d, h, nullptr); }
inline void destroy(VkDevice d, VkCommandPool h) { vkDestroyCommandPool(d, h, nullptr); }
inline void destroy(VkDevice d, VkSemaphore h) { vkDestroySemaphore(d, h, nullptr); }
inline void destroy(VkDevice d, VkFence h) { vkDestroyFence(d, h, nullptr); }

template <typename T> inline void onCreate(Device&) {}
template <typename T> inline void onDestroy(Device&) {}
template <> inline void onCreate<VkPipeline>(Device& d) {
    ++d.counters().pipelines;
    ++d.counters().pipelinesEverCreated;
}
template <> inline void onDestroy<VkPipeline>(Device& d) { --d.counters().pipelines; }
}  // namespace detail

template <typename T>
class Handle {
public:
    Handle() = default;
    /// Takes ownership of `handle`, made from `device`.
    Handle(Device& device, T handle) : device_(&device), handle_(handle) {
        if (handle_ != VK_NULL_HANDLE) detail::onCreate<T>(device);
    }
    ~Handle() { release(); }
    Handle(Handle&& o) noexcept
        : device_(std::exchange(o.device_, nullptr)), handle_(std::exchange(o.handle_, VK_NULL_HANDLE)) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            release();
            device_ = std::exchange(o.device_, nullptr);
            handle_ = std::exchange(o.handle_, VK_NULL_HANDLE);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;

    T vk() const { return handle_; }
    explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }

private:
    void release() {
        if (handle_ == VK_NULL_HANDLE) return;
        Device* device = device_;
        T handle = handle_;
        detail::onDestroy<T>(*device);
        device->retire([device, handle] { detail::destroy(device->vk(), handle); });
        handle_ = VK_NULL_HANDLE;
    }

    Device* device_ = nullptr;
    T handle_ = VK_NULL_HANDLE;
};

using Pipeline = Handle<VkPipeline>;
using PipelineLayout = Handle<VkPipelineLayout>;
using DescriptorSetLayout = Handle<VkDescriptorSetLayout>;
using DescriptorPool = Handle<VkDescriptorPool>;
using Sampler = Handle<VkSampler>;
using ShaderModule = Handle<VkShaderModule>;
using QueryPool = Handle<VkQueryPool>;
using CommandPool = Handle<VkCommandPool>;
using Semaphore = Handle<VkSemaphore>;

}  // namespace orbis::gpu
