#pragma once
// Move-only owner of one VkBuffer and its sub-allocated memory. The destructor retires both:
// they are freed once the GPU has finished the submits that may use them.

#include "engine/gpu/MemoryAllocator.h"

#include <vulkan/vulkan.h>

#include <cstddef>

namespace orbis::gpu {

class Device;

class Buffer {
public:
    Buffer() = default;
    Buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory, const char* name = nullptr);
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    VkBuffer vk() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

    /// Host pointer (Upload/Readback memory only), or null.
    void* mapped() const { return memory_.mapped; }
    /// Copies into host-visible memory and flushes it when the memory is not coherent.
    void write(const void* data, VkDeviceSize size, VkDeviceSize offset = 0);
    /// Makes GPU writes visible to the host (Readback memory that is not coherent).
    void invalidate();

private:
    void release();

    Device* device_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    Allocation memory_;
};

}  // namespace orbis::gpu
