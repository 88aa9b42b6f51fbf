#include "layers/terrain/TileSlotPool.h"

#include "base/Log.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Uploader.h"
#include "shared/TerrainTypes.h"

#include <algorithm>
#include <cmath>

namespace orbis::layers {

TileSlotPool::TileSlotPool(gpu::Device& device, gpu::Uploader& uploader, int gridSize, int imageSize, uint64_t budgetBytes,
                           uint64_t reservedBytes)
    : device_(&device),
      gridSize_(gridSize),
      imageSize_(imageSize),
      meshVertices_(globe::tileVertexCount(gridSize)),
      budgetBytes_(budgetBytes),
      reservedBytes_(reservedBytes) {
    const uint32_t maxLayers = device.properties().limits.maxImageArrayLayers;
    pool(Kind::Mesh) = {kMeshSlotsPerPage, kMeshSlotsPerPage * kMeshPagesMax, uint64_t(meshVertices_) * sizeof(globe::TileVertex)};
    pool(Kind::Elevation) = {kElevationFirstSlots, std::min(shader::kElevationMaxSlots, maxLayers),
                             uint64_t(gridSize) * gridSize * 4 * sizeof(float)};
    // RGBA8 and its mip chain.
    pool(Kind::Imagery) = {kImageryFirstSlots, std::min(shader::kImageryMaxSlots, maxLayers),
                           uint64_t(imageSize) * imageSize * 4 * 4 / 3};
    createDummies(uploader);
}

void TileSlotPool::createDummies(gpu::Uploader& uploader) {
    gpu::ImageDesc de;
    de.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    de.format = VK_FORMAT_R32G32B32A32_SFLOAT;   // height, gradient east, gradient south
    de.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    de.extent = {uint32_t(gridSize_), uint32_t(gridSize_), 1};
    de.name = "terrain elevation (unused page)";
    dummyElevation_ = gpu::Image(*device_, de);
    gpu::ImageDesc di = de;
    di.format = VK_FORMAT_R8G8B8A8_SRGB;
    di.extent = {1, 1, 1};
    di.name = "terrain imagery (unused page)";
    dummyImagery_ = gpu::Image(*device_, di);
    device_->runOnce([&](VkCommandBuffer cmd) {
        const std::vector<float> zeros(size_t(gridSize_) * size_t(gridSize_) * 4, 0.0f);
        uploader.toImage(cmd, dummyElevation_, zeros.data(), zeros.size() * sizeof(float));
        const uint8_t clear[4] = {0, 0, 0, 0};
        uploader.toImage(cmd, dummyImagery_, clear, 4);
        gpu::transition(cmd, dummyElevation_, gpu::ImageUse::SampledGraphics);
        gpu::transition(cmd, dummyImagery_, gpu::ImageUse::SampledGraphics);
    });
}

uint64_t TileSlotPool::slotBytes(Kind kind) const { return pool(kind).slotBytes; }

uint64_t TileSlotPool::allocatedBytes() const {
    uint64_t bytes = 0;
    for (const Pool& p : pools_) bytes += uint64_t(p.slots.size()) * p.slotBytes;
    return bytes;
}

std::optional<uint32_t> TileSlotPool::find(Kind kind, const globe::DataKey& key) {
    Pool& p = pool(kind);
    const auto it = p.resident.find(key);
    if (it == p.resident.end()) return std::nullopt;
    p.slots[it->second].lastUsed = frame_;
    return it->second;
}

std::optional<uint32_t> TileSlotPool::acquire(Kind kind, const globe::DataKey& key, bool mayExceedBudget, uint32_t generation) {
    Pool& p = pool(kind);
    if (p.freeSlots.empty()) {
        const uint32_t now = uint32_t(p.slots.size());
        const uint32_t capacity = grownCapacity(kind);
        const bool canGrow = capacity > now;
        // An image grows by what the budget leaves when that is less than twice; a mesh page is whole.
        const uint64_t used = reservedBytes_ + allocatedBytes();
        const uint64_t room = used < budgetBytes_ ? (budgetBytes_ - used) / p.slotBytes : 0;
        const uint32_t fitting = uint32_t(std::min<uint64_t>(capacity, now + room));
        if (fitting > now && (kind != Kind::Mesh || fitting == capacity)) {
            grow(kind, fitting);
        } else if (!evictOne(p)) {
            // Over the budget, only what would otherwise leave a hole (or the first slots) grows.
            if (!canGrow || !(mayExceedBudget || p.slots.empty())) return std::nullopt;
            if (!warnedBudget_) {
                warnedBudget_ = true;
                log::warn("terrain: this view needs more than the GPU tile budget (", budgetBytes_ >> 20,
                          " MB); raise \"gpuCacheMB\" or \"maxScreenSpaceError\"");
            }
            grow(kind, capacity);
        }
    }
    const uint32_t slot = p.freeSlots.back();
    p.freeSlots.pop_back();
    p.slots[slot] = Slot{key, frame_, true, generation};
    p.resident[key] = slot;
    return slot;
}

bool TileSlotPool::evictOne(Pool& p) {
    uint32_t victim = UINT32_MAX;
    uint64_t oldest = UINT64_MAX;
    for (uint32_t i = 0; i < p.slots.size(); ++i) {
        const Slot& slot = p.slots[i];
        if (slot.lastUsed < frame_ && slot.lastUsed < oldest) victim = i, oldest = slot.lastUsed;
    }
    if (victim == UINT32_MAX) return false;
    p.resident.erase(p.slots[victim].owner);
    p.slots[victim].taken = false;
    p.freeSlots.push_back(victim);
    return true;
}

uint32_t TileSlotPool::grownCapacity(Kind kind) const {
    const Pool& p = pool(kind);
    const uint32_t now = uint32_t(p.slots.size());
    if (kind == Kind::Mesh) return std::min(now + p.growBy, p.maxSlots);   // one more vertex buffer
    return std::min(std::max(now * 2, p.growBy), p.maxSlots);              // an image twice as large
}

void TileSlotPool::grow(Kind kind, uint32_t capacity) {
    Pool& p = pool(kind);
    const uint32_t first = uint32_t(p.slots.size());
    p.slots.resize(capacity);
    for (uint32_t i = capacity; i-- > first;) p.freeSlots.push_back(i);
    if (kind == Kind::Mesh) {
        meshPages_.emplace_back(*device_, uint64_t(kMeshSlotsPerPage) * p.slotBytes,
                                VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                gpu::MemoryUsage::GpuOnly, "terrain meshes");
        return;
    }
    gpu::ImageDesc d;
    d.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    d.layers = capacity;
    d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    if (kind == Kind::Elevation) {
        d.format = VK_FORMAT_R32G32B32A32_SFLOAT;   // height, gradient east, gradient south
        d.extent = {uint32_t(gridSize_), uint32_t(gridSize_), 1};
        d.name = "terrain elevation";
    } else {
        d.format = VK_FORMAT_R8G8B8A8_SRGB;
        d.extent = {uint32_t(imageSize_), uint32_t(imageSize_), 1};
        d.mipLevels = uint32_t(std::log2(imageSize_)) + 1;
        d.name = "terrain imagery";
    }
    SlotImage& target = slotImage(kind);
    // The layers with data come from the image that had them: grown twice before the frame's
    // transfers, the one in between never held any.
    if (!target.copyFrom && target.image) {
        target.copyFrom = std::move(target.image);
        target.copyLayers = first;
    }
    target.image = gpu::Image(*device_, d);
    ++version_;
}

bool TileSlotPool::growing() const { return bool(elevation_.copyFrom) || bool(imagery_.copyFrom); }

void TileSlotPool::copyGrown(VkCommandBuffer cmd, SlotImage& target) {
    if (!target.copyFrom) return;
    const gpu::ImageTransition uses[] = {{&target.copyFrom, gpu::ImageUse::TransferSrc},
                                         {&target.image, gpu::ImageUse::TransferDst}};
    gpu::transition(cmd, uses);
    std::vector<VkImageCopy> regions;
    const VkExtent3D extent = target.image.extent();
    for (uint32_t m = 0; m < target.image.desc().mipLevels; ++m) {
        VkImageCopy r{};
        r.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m, 0, target.copyLayers};
        r.dstSubresource = r.srcSubresource;
        r.extent = {std::max(extent.width >> m, 1u), std::max(extent.height >> m, 1u), 1};
        regions.push_back(r);
    }
    vkCmdCopyImage(cmd, target.copyFrom.vk(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target.image.vk(),
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(regions.size()), regions.data());
    target.copyFrom = gpu::Image();   // retired: freed once this frame's submit completes
    target.copyLayers = 0;
    target.touched = true;
}

void TileSlotPool::beginUploads(VkCommandBuffer cmd) {
    // Slots may be reused: earlier frames' reads of them come before these writes.
    VkMemoryBarrier2 before{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    before.srcStageMask = VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT;
    before.dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = 1;
    dep.pMemoryBarriers = &before;
    vkCmdPipelineBarrier2(cmd, &dep);
    meshTouched_.assign(meshPages_.size(), false);
    elevation_.touched = imagery_.touched = false;
    copyGrown(cmd, elevation_);
    copyGrown(cmd, imagery_);
}

void TileSlotPool::uploadMesh(VkCommandBuffer cmd, gpu::Uploader& uploader, uint32_t slot,
                              std::span<const globe::TileVertex> vertices) {
    const uint32_t page = slot / kMeshSlotsPerPage, index = slot % kMeshSlotsPerPage;
    const VkDeviceSize bytes = vertices.size() * sizeof(globe::TileVertex);
    uploader.toBuffer(cmd, meshPages_[page], vertices.data(), bytes, index * bytes);
    meshTouched_[page] = true;
}

void TileSlotPool::uploadElevation(VkCommandBuffer cmd, gpu::Uploader& uploader, uint32_t slot, const globe::ElevationData& data) {
    const auto& h = data.heights;
    std::vector<float> texels(h.size() * 4);
    for (size_t i = 0; i < h.size(); ++i) {
        texels[i * 4] = h[i];
        texels[i * 4 + 1] = data.gradients[i * 2];
        texels[i * 4 + 2] = data.gradients[i * 2 + 1];
        texels[i * 4 + 3] = 0.0f;
    }
    uploader.toImage(cmd, elevation_.image, texels.data(), texels.size() * sizeof(float), slot);
    elevation_.touched = true;
}

void TileSlotPool::uploadImagery(VkCommandBuffer cmd, gpu::Uploader& uploader, uint32_t slot, const globe::ImageryData& data) {
    std::vector<VkBufferImageCopy> regions;
    for (int m = 0; m < data.mipLevels(); ++m) {
        const uint32_t size = uint32_t(std::max(data.size >> m, 1));
        VkBufferImageCopy r{};
        r.bufferOffset = data.mipOffsets[size_t(m)];
        r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), slot, 1};
        r.imageExtent = {size, size, 1};
        regions.push_back(r);
    }
    uploader.toImageRegions(cmd, imagery_.image, data.rgba.data(), data.rgba.size(), regions);
    imagery_.touched = true;
}

void TileSlotPool::endUploads(VkCommandBuffer cmd) {
    for (size_t p = 0; p < meshPages_.size(); ++p)
        if (meshTouched_[p])
            gpu::bufferBarrier(cmd, meshPages_[p], VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT);
    if (elevation_.touched) gpu::transition(cmd, elevation_.image, gpu::ImageUse::SampledGraphics);
    if (imagery_.touched) gpu::transition(cmd, imagery_.image, gpu::ImageUse::SampledGraphics);
}

VkImageView TileSlotPool::elevationView() const {
    return elevation_.image ? elevation_.image.view() : dummyElevation_.view();
}

VkImageView TileSlotPool::imageryView() const { return imagery_.image ? imagery_.image.view() : dummyImagery_.view(); }

}  // namespace orbis::layers
