#include "engine/gpu/MemoryAllocator.h"

#include "engine/gpu/VkCheck.h"

#include <algorithm>

namespace orbis::gpu {
namespace {
VkDeviceSize alignUp(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }
}  // namespace

MemoryAllocator::MemoryAllocator(VkPhysicalDevice physical, VkDevice device, VkDeviceSize blockSize)
    : device_(device), blockSize_(blockSize) {
    vkGetPhysicalDeviceMemoryProperties(physical, &props_);
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(physical, &p);
    atomSize_ = std::max<VkDeviceSize>(1, p.limits.nonCoherentAtomSize);
}

MemoryAllocator::~MemoryAllocator() {
    for (auto& b : blocks_)
        if (b && b->memory) vkFreeMemory(device_, b->memory, nullptr);
}

uint32_t MemoryAllocator::findType(uint32_t typeBits, MemoryUsage usage, bool& coherent) const {
    VkMemoryPropertyFlags required = 0, preferred = 0, avoided = 0;
    switch (usage) {
        case MemoryUsage::GpuOnly:
            preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
            break;
        case MemoryUsage::Upload:
            required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
            preferred = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
            avoided = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
            break;
        case MemoryUsage::Readback:
            required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
            preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
            break;
    }
    int best = -1, bestScore = -1;
    for (uint32_t i = 0; i < props_.memoryTypeCount; ++i) {
        if (!(typeBits & (1u << i))) continue;
        const VkMemoryPropertyFlags f = props_.memoryTypes[i].propertyFlags;
        if ((f & required) != required) continue;
        int score = 1;
        score += 4 * __builtin_popcount(f & preferred);
        score -= 2 * __builtin_popcount(f & avoided);
        if (score > bestScore) bestScore = score, best = static_cast<int>(i);
    }
    if (best < 0) throw GpuError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "no Vulkan memory type fits the request");
    coherent = props_.memoryTypes[best].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    return static_cast<uint32_t>(best);
}

VkDeviceMemory MemoryAllocator::allocateDeviceMemory(VkDeviceSize size, uint32_t typeIndex, void** mapped) {
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = size;
    info.memoryTypeIndex = typeIndex;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateMemory(device_, &info, nullptr, &memory));
    *mapped = nullptr;
    if (props_.memoryTypes[typeIndex].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
        VK_CHECK(vkMapMemory(device_, memory, 0, VK_WHOLE_SIZE, 0, mapped));
    ++stats_.driverAllocations;
    stats_.bytesReserved += size;
    return memory;
}

bool MemoryAllocator::tryAllocateFrom(Block& block, const VkMemoryRequirements& req, Allocation& out) {
    // Host-visible non-coherent memory is flushed in atoms: keep allocations atom-aligned.
    const VkDeviceSize align = std::max(req.alignment, block.coherent ? VkDeviceSize(1) : atomSize_);
    for (auto it = block.freeRanges.begin(); it != block.freeRanges.end(); ++it) {
        const VkDeviceSize start = alignUp(it->first, align);
        const VkDeviceSize end = it->first + it->second;
        if (start + req.size > end) continue;
        const VkDeviceSize rangeStart = it->first;
        block.freeRanges.erase(it);
        if (start > rangeStart) block.freeRanges.emplace(rangeStart, start - rangeStart);
        if (start + req.size < end) block.freeRanges.emplace(start + req.size, end - start - req.size);
        out.memory = block.memory;
        out.offset = start;
        out.size = req.size;
        out.coherent = block.coherent;
        out.mapped = block.mapped ? static_cast<char*>(block.mapped) + start : nullptr;
        ++block.liveCount;
        return true;
    }
    return false;
}

Allocation MemoryAllocator::allocate(const VkMemoryRequirements& req, MemoryUsage usage, bool linear) {
    std::lock_guard lock(mutex_);
    bool coherent = true;
    const uint32_t type = findType(req.memoryTypeBits, usage, coherent);
    Allocation out;
    // Large resources get their own block: they would fragment shared ones.
    if (req.size > blockSize_ / 2) {
        auto block = std::make_unique<Block>();
        block->memory = allocateDeviceMemory(req.size, type, &block->mapped);
        block->size = req.size;
        block->typeIndex = type;
        block->linear = linear;
        block->coherent = coherent;
        block->liveCount = 1;
        block->dedicated = true;
        out = Allocation{block->memory, 0, req.size, block->mapped, coherent, -1};
        blocks_.push_back(std::move(block));
        out.block = static_cast<int>(blocks_.size() - 1);
        stats_.bytesInUse += req.size;
        ++stats_.liveAllocations;
        return out;
    }
    for (size_t i = 0; i < blocks_.size(); ++i) {
        Block* b = blocks_[i].get();
        if (!b || b->typeIndex != type || b->linear != linear || b->freeRanges.empty()) continue;
        if (tryAllocateFrom(*b, req, out)) {
            out.block = static_cast<int>(i);
            stats_.bytesInUse += out.size;
            ++stats_.liveAllocations;
            return out;
        }
    }
    auto block = std::make_unique<Block>();
    block->memory = allocateDeviceMemory(blockSize_, type, &block->mapped);
    block->size = blockSize_;
    block->typeIndex = type;
    block->linear = linear;
    block->coherent = coherent;
    block->freeRanges.emplace(0, blockSize_);
    tryAllocateFrom(*block, req, out);
    // Reuse an empty slot so indices stay small.
    auto slot = std::find(blocks_.begin(), blocks_.end(), nullptr);
    if (slot == blocks_.end()) slot = blocks_.insert(blocks_.end(), nullptr);
    *slot = std::move(block);
    out.block = static_cast<int>(slot - blocks_.begin());
    stats_.bytesInUse += out.size;
    ++stats_.liveAllocations;
    return out;
}

void MemoryAllocator::free(const Allocation& a) {
    if (!a) return;
    std::lock_guard lock(mutex_);
    Block* b = blocks_.at(a.block).get();
    stats_.bytesInUse -= a.size;
    --stats_.liveAllocations;
    if (!b->dedicated) {
        // Insert and merge with neighbours.
        VkDeviceSize offset = a.offset, size = a.size;
        auto next = b->freeRanges.lower_bound(offset);
        if (next != b->freeRanges.end() && offset + size == next->first) {
            size += next->second;
            next = b->freeRanges.erase(next);
        }
        if (next != b->freeRanges.begin()) {
            auto prev = std::prev(next);
            if (prev->first + prev->second == offset) {
                offset = prev->first;
                size += prev->second;
                b->freeRanges.erase(prev);
            }
        }
        b->freeRanges.emplace(offset, size);
    }
    if (--b->liveCount > 0) return;
    // Keep one empty shared block per kind so a staging buffer made and dropped every frame
    // does not call vkAllocateMemory every frame.
    if (!b->dedicated) {
        const bool anotherEmpty = std::any_of(blocks_.begin(), blocks_.end(), [&](const auto& o) {
            return o && o.get() != b && !o->dedicated && o->liveCount == 0 && o->typeIndex == b->typeIndex &&
                   o->linear == b->linear;
        });
        if (!anotherEmpty) return;
    }
    {
        vkFreeMemory(device_, b->memory, nullptr);
        --stats_.driverAllocations;
        stats_.bytesReserved -= b->size;
        blocks_[a.block].reset();
    }
}

MemoryStats MemoryAllocator::stats() const {
    std::lock_guard lock(mutex_);
    return stats_;
}

}  // namespace orbis::gpu
