#include "engine/gpu/Buffer.h"

#include "engine/gpu/Device.h"
#include "engine/gpu/VkCheck.h"

#include <cassert>
#include <cstring>
#include <utility>

namespace orbis::gpu {

Buffer::Buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory, const char* name)
    : device_(&device), size_(size) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(device.vk(), &info, nullptr, &buffer_));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device.vk(), buffer_, &req);
    try {
        memory_ = device.allocator().allocate(req, memory, /*linearResource=*/true);
    } catch (...) {
        vkDestroyBuffer(device.vk(), buffer_, nullptr);
        throw;
    }
    VK_CHECK(vkBindBufferMemory(device.vk(), buffer_, memory_.memory, memory_.offset));
    device.setDebugName(reinterpret_cast<uint64_t>(buffer_), VK_OBJECT_TYPE_BUFFER, name);
    ++device.counters().buffers;
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& o) noexcept
    : device_(std::exchange(o.device_, nullptr)),
      buffer_(std::exchange(o.buffer_, VK_NULL_HANDLE)),
      size_(std::exchange(o.size_, 0)),
      memory_(std::exchange(o.memory_, Allocation{})) {}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        release();
        device_ = std::exchange(o.device_, nullptr);
        buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
        size_ = std::exchange(o.size_, 0);
        memory_ = std::exchange(o.memory_, Allocation{});
    }
    return *this;
}

void Buffer::release() {
    if (buffer_ == VK_NULL_HANDLE) return;
    Device* device = device_;
    VkBuffer buffer = buffer_;
    Allocation memory = memory_;
    --device->counters().buffers;
    device->retire([device, buffer, memory] {
        vkDestroyBuffer(device->vk(), buffer, nullptr);
        device->allocator().free(memory);
    });
    buffer_ = VK_NULL_HANDLE;
}

void Buffer::write(const void* data, VkDeviceSize size, VkDeviceSize offset) {
    assert(memory_.mapped && offset + size <= size_);
    std::memcpy(static_cast<char*>(memory_.mapped) + offset, data, size);
    if (!memory_.coherent) {
        VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
        range.memory = memory_.memory;
        const VkDeviceSize atom = device_->allocator().nonCoherentAtomSize();
        range.offset = (memory_.offset + offset) / atom * atom;
        range.size = VK_WHOLE_SIZE;
        VK_CHECK(vkFlushMappedMemoryRanges(device_->vk(), 1, &range));
    }
}

void Buffer::invalidate() {
    if (memory_.coherent || !memory_.mapped) return;
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
    range.memory = memory_.memory;
    const VkDeviceSize atom = device_->allocator().nonCoherentAtomSize();
    range.offset = memory_.offset / atom * atom;
    range.size = VK_WHOLE_SIZE;
    VK_CHECK(vkInvalidateMappedMemoryRanges(device_->vk(), 1, &range));
}

}  // namespace orbis::gpu
