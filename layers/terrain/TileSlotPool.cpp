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
    pool(Kind::Mesh) = {kMeshSlotsPerPage, kMeshPagesMax, uint64_t(kMeshSlotsPerPage) * meshVertices_ * sizeof(globe::TileVertex)};
    pool(Kind::Elevation) = {shader::kElevationSlotsPerPage, shader::kElevationPages,
                             uint64_t(shader::kElevationSlotsPerPage) * gridSize * gridSize * 4 * sizeof(float)};
    pool(Kind::Imagery) = {shader::kImagerySlotsPerPage, shader::kImageryPages,
                           uint64_t(shader::kImagerySlotsPerPage) * imageSize * imageSize * 4 * 4 / 3};
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

uint64_t TileSlotPool::slotBytes(Kind kind) const {
    switch (kind) {
        case Kind::Mesh: return pool(kind).pageBytes / pool(kind).slotsPerPage;
        case Kind::Elevation: return uint64_t(gridSize_) * gridSize_ * 4 * sizeof(float);
        case Kind::Imagery: break;
    }
    return uint64_t(imageSize_) * imageSize_ * 4 * 4 / 3;   // RGBA8 and its mip chain
}

uint64_t TileSlotPool::allocatedBytes() const {
    uint64_t bytes = 0;
    for (const Pool& p : pools_) bytes += uint64_t(p.pages()) * p.pageBytes;
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
        const bool fits = reservedBytes_ + allocatedBytes() + p.pageBytes <= budgetBytes_;
        const bool canGrow = p.pages() < p.maxPages;
        if (fits && canGrow) {
            addPage(kind);
        } else if (!evictOne(p)) {
            // Over the budget, only what would otherwise leave a hole (or the first page) grows.
            if (!canGrow || !(mayExceedBudget || p.pages() == 0)) return std::nullopt;
            if (!warnedBudget_) {
                warnedBudget_ = true;
                log::warn("terrain: this view needs more than the GPU tile budget (", budgetBytes_ >> 20,
                          " MB); raise \"gpuCacheMB\" or \"maxScreenSpaceError\"");
            }
            addPage(kind);
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

void TileSlotPool::addPage(Kind kind) {
    Pool& p = pool(kind);
    const uint32_t first = uint32_t(p.slots.size());
    p.slots.resize(p.slots.size() + p.slotsPerPage);
    for (uint32_t i = p.slotsPerPage; i-- > 0;) p.freeSlots.push_back(first + i);
    if (kind == Kind::Mesh) {
        meshPages_.emplace_back(*device_, p.pageBytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                gpu::MemoryUsage::GpuOnly, "terrain meshes");
        return;
    }
    gpu::ImageDesc d;
    d.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    d.layers = p.slotsPerPage;
    d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if (kind == Kind::Elevation) {
        d.format = VK_FORMAT_R32G32B32A32_SFLOAT;
        d.extent = {uint32_t(gridSize_), uint32_t(gridSize_), 1};
        d.name = "terrain elevation page";
        elevationPages_.emplace_back(*device_, d);
    } else {
        d.format = VK_FORMAT_R8G8B8A8_SRGB;
        d.extent = {uint32_t(imageSize_), uint32_t(imageSize_), 1};
        d.mipLevels = uint32_t(std::log2(imageSize_)) + 1;
        d.name = "terrain imagery page";
        imageryPages_.emplace_back(*device_, d);
    }
    ++version_;
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
    elevationTouched_.assign(elevationPages_.size(), false);
    imageryTouched_.assign(imageryPages_.size(), false);
}

void TileSlotPool::uploadMesh(VkCommandBuffer cmd, gpu::Uploader& uploader, uint32_t slot,
                              std::span<const globe::TileVertex> vertices) {
    const uint32_t page = slot / kMeshSlotsPerPage, index = slot % kMeshSlotsPerPage;
    const VkDeviceSize bytes = vertices.size() * sizeof(globe::TileVertex);
    uploader.toBuffer(cmd, meshPages_[page], vertices.data(), bytes, index * bytes);
    meshTouched_[page] = true;
}

void TileSlotPool::uploadElevation(VkCommandBuffer cmd, gpu::Uploader& uploader, uint32_t slot, const globe::ElevationData& data) {
    const uint32_t page = slot / shader::kElevationSlotsPerPage;
    const auto& h = data.heights;
    std::vector<float> texels(h.size() * 4);
    for (size_t i = 0; i < h.size(); ++i) {
        texels[i * 4] = h[i];
        texels[i * 4 + 1] = data.gradients[i * 2];
        texels[i * 4 + 2] = data.gradients[i * 2 + 1];
        texels[i * 4 + 3] = 0.0f;
    }
    uploader.toImage(cmd, elevationPages_[page], texels.data(), texels.size() * sizeof(float), slot % shader::kElevationSlotsPerPage);
    elevationTouched_[page] = true;
}

void TileSlotPool::uploadImagery(VkCommandBuffer cmd, gpu::Uploader& uploader, uint32_t slot, const globe::ImageryData& data) {
    const uint32_t page = slot / shader::kImagerySlotsPerPage;
    std::vector<VkBufferImageCopy> regions;
    for (int m = 0; m < data.mipLevels(); ++m) {
        const uint32_t size = uint32_t(std::max(data.size >> m, 1));
        VkBufferImageCopy r{};
        r.bufferOffset = data.mipOffsets[size_t(m)];
        r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), slot % shader::kImagerySlotsPerPage, 1};
        r.imageExtent = {size, size, 1};
        regions.push_back(r);
    }
    uploader.toImageRegions(cmd, imageryPages_[page], data.rgba.data(), data.rgba.size(), regions);
    imageryTouched_[page] = true;
}

void TileSlotPool::endUploads(VkCommandBuffer cmd) {
    for (size_t p = 0; p < meshPages_.size(); ++p)
        if (meshTouched_[p])
            gpu::bufferBarrier(cmd, meshPages_[p], VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT);
    for (size_t p = 0; p < elevationPages_.size(); ++p)
        if (elevationTouched_[p]) gpu::transition(cmd, elevationPages_[p], gpu::ImageUse::SampledGraphics);
    for (size_t p = 0; p < imageryPages_.size(); ++p)
        if (imageryTouched_[p]) gpu::transition(cmd, imageryPages_[p], gpu::ImageUse::SampledGraphics);
}

std::vector<VkImageView> TileSlotPool::elevationViews() const {
    std::vector<VkImageView> views(shader::kElevationPages);
    for (uint32_t i = 0; i < views.size(); ++i)
        views[i] = i < elevationPages_.size() ? elevationPages_[i].view() : dummyElevation_.view();
    return views;
}

std::vector<VkImageView> TileSlotPool::imageryViews() const {
    std::vector<VkImageView> views(shader::kImageryPages);
    for (uint32_t i = 0; i < views.size(); ++i) views[i] = i < imageryPages_.size() ? imageryPages_[i].view() : dummyImagery_.view();
    return views;
}

}  // namespace orbis::layers
