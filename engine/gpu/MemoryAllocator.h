#pragma once
// A small sub-allocator: resources share large VkDeviceMemory blocks (no vkAllocateMemory per
// resource; drivers limit the count and each call is slow). First-fit free lists per block,
// buffers and optimal-tiling images in separate blocks so bufferImageGranularity never matters.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace orbis::gpu {

enum class MemoryUsage {
    GpuOnly,   ///< device-local; written by transfers or shaders
    Upload,    ///< host-visible, written sequentially by the CPU (staging, per-frame constants)
    Readback,  ///< host-visible, cached if possible: read by the CPU
};

struct Allocation {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
    VkDeviceSize size = 0;
    void* mapped = nullptr;      ///< host pointer at offset, or null
    bool coherent = true;
    int block = -1;              ///< index into the allocator's blocks; -1 = dedicated
    explicit operator bool() const { return memory != VK_NULL_HANDLE; }
};

struct MemoryStats {
    uint64_t driverAllocations = 0;   ///< live vkAllocateMemory blocks
    uint64_t bytesReserved = 0;       ///< bytes in those blocks
    uint64_t bytesInUse = 0;          ///< bytes handed out to resources
    uint64_t liveAllocations = 0;
};

class MemoryAllocator {
public:
    MemoryAllocator(VkPhysicalDevice physical, VkDevice device, VkDeviceSize blockSize = 64ull << 20);
    ~MemoryAllocator();
    MemoryAllocator(const MemoryAllocator&) = delete;
    MemoryAllocator& operator=(const MemoryAllocator&) = delete;

    /// Any thread. Throws GpuError when no memory type fits or the driver is out of memory.
    Allocation allocate(const VkMemoryRequirements& requirements, MemoryUsage usage, bool linearResource);
    /// Any thread.
    void free(const Allocation& allocation);

    MemoryStats stats() const;
    VkDeviceSize nonCoherentAtomSize() const { return atomSize_; }

private:
    struct Block {
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkDeviceSize size = 0;
        uint32_t typeIndex = 0;
        bool linear = true;
        bool coherent = true;
        void* mapped = nullptr;
        std::map<VkDeviceSize, VkDeviceSize> freeRanges;   // offset -> size
        int liveCount = 0;
        bool dedicated = false;
    };

    uint32_t findType(uint32_t typeBits, MemoryUsage usage, bool& coherent) const;
    bool tryAllocateFrom(Block& block, const VkMemoryRequirements& req, Allocation& out);
    VkDeviceMemory allocateDeviceMemory(VkDeviceSize size, uint32_t typeIndex, void** mapped);

    VkDevice device_;
    VkPhysicalDeviceMemoryProperties props_{};
    VkDeviceSize blockSize_;
    VkDeviceSize atomSize_ = 1;
    mutable std::mutex mutex_;
    std::vector<std::unique_ptr<Block>> blocks_;
    MemoryStats stats_;
};

}  // namespace orbis::gpu
