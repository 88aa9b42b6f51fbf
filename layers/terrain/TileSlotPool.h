#pragma once
// The terrain's tile data on the GPU: tile meshes in pages of vertex buffer, elevation and
// imagery in pages of array images (at most shader::kElevationPages and kImageryPages, the
// arrays the shaders bind). A page has a fixed number of slots, each holding one tile's data,
// found by its DataKey. Pages are added on demand while the GPU budget allows; past it, the
// least recently used slot that the current frame does not use is given to new data. Image
// pages not made yet are stood in for by small dummies, so that the shaders' arrays are always
// full.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Image.h"
#include "globe/TerrainTiles.h"
#include "globe/TileMesh.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

namespace orbis::gpu {
class Device;
class Uploader;
}  // namespace orbis::gpu

namespace orbis::layers {

class TileSlotPool {
public:
    enum class Kind : uint32_t { Mesh, Elevation, Imagery };

    /// Tiles of `gridSize` samples and `imageSize` pixels a side; pages within `budgetBytes` less
    /// the `reservedBytes` the layer holds besides (its index and draw buffers). Uploads the
    /// dummies before it returns. Main thread.
    TileSlotPool(gpu::Device& device, gpu::Uploader& uploader, int gridSize, int imageSize, uint64_t budgetBytes,
                 uint64_t reservedBytes);

    /// Slots found or acquired from now on are this frame's (number > 0). Main thread.
    void beginFrame(uint64_t frame) { frame_ = frame; }
    /// The slot holding `key`'s data, marked used this frame.
    std::optional<uint32_t> find(Kind kind, const globe::DataKey& key);
    /// A slot for `key`'s data, to be uploaded this frame: a free one, one of a new page while
    /// within the budget, else the least recently used one this frame does not use. Only
    /// `mayExceedBudget` (a mesh, without which a tile would be a hole) adds pages past the
    /// budget. Nothing when no slot can be had: the caller falls back to an ancestor.
    /// `generation`: which version of the key's data goes in (TerrainTiles::dataGeneration).
    std::optional<uint32_t> acquire(Kind kind, const globe::DataKey& key, bool mayExceedBudget, uint32_t generation = 0);
    /// The version of its key's data a slot holds; a newer one is uploaded into the same slot
    /// (setGeneration), the old image drawn until then.
    uint32_t generation(Kind kind, uint32_t slot) const { return pool(kind).slots[slot].generation; }
    void setGeneration(Kind kind, uint32_t slot, uint32_t generation) { pool(kind).slots[slot].generation = generation; }
    /// The bytes of one slot of `kind` (what uploading it costs).
    uint64_t slotBytes(Kind kind) const;

    /// Uploads into slots, while recording the frame's transfers: beginUploads, the slots' data,
    /// then endUploads, which makes the pages written visible to the draws.
    void beginUploads(VkCommandBuffer cmd);
    void uploadMesh(VkCommandBuffer cmd, gpu::Uploader& uploader, uint32_t slot, std::span<const globe::TileVertex> vertices);
    /// Heights and their gradients per sample (the loader's): interpolating the gradient gives
    /// continuous normals.
    void uploadElevation(VkCommandBuffer cmd, gpu::Uploader& uploader, uint32_t slot, const globe::ElevationData& data);
    void uploadImagery(VkCommandBuffer cmd, gpu::Uploader& uploader, uint32_t slot, const globe::ImageryData& data);
    void endUploads(VkCommandBuffer cmd);

    /// The vertex buffer holding a mesh slot, and the slot's first vertex in it.
    VkBuffer meshBuffer(uint32_t slot) const { return meshPages_[slot / kMeshSlotsPerPage].vk(); }
    uint32_t meshPage(uint32_t slot) const { return slot / kMeshSlotsPerPage; }
    int32_t meshVertexOffset(uint32_t slot) const { return int32_t((slot % kMeshSlotsPerPage) * meshVertices_); }
    /// The views the shaders' page arrays bind: each page, then dummies.
    std::vector<VkImageView> elevationViews() const;
    std::vector<VkImageView> imageryViews() const;
    /// Changes whenever an image page is added (descriptor sets naming the old views are stale).
    uint64_t version() const { return version_; }
    uint64_t allocatedBytes() const;

private:
    static constexpr uint32_t kMeshSlotsPerPage = 64;
    static constexpr uint32_t kMeshPagesMax = 64;
    struct Slot {
        globe::DataKey owner;
        uint64_t lastUsed = 0;
        bool taken = false;
        uint32_t generation = 0;
    };
    struct Pool {
        uint32_t slotsPerPage = 0, maxPages = 0;
        uint64_t pageBytes = 0;
        std::vector<Slot> slots;
        std::vector<uint32_t> freeSlots;
        std::unordered_map<globe::DataKey, uint32_t, globe::DataKeyHash> resident;
        uint32_t pages() const { return slotsPerPage ? uint32_t(slots.size() / slotsPerPage) : 0; }
    };
    Pool& pool(Kind kind) { return pools_[size_t(kind)]; }
    const Pool& pool(Kind kind) const { return pools_[size_t(kind)]; }
    /// The least recently used slot not used this frame, freed; nothing if every slot is in use.
    bool evictOne(Pool& pool);
    void addPage(Kind kind);
    void createDummies(gpu::Uploader& uploader);

    gpu::Device* device_;
    int gridSize_, imageSize_;
    uint32_t meshVertices_;
    uint64_t budgetBytes_, reservedBytes_;
    uint64_t frame_ = 0, version_ = 1;
    bool warnedBudget_ = false;
    Pool pools_[3];
    std::vector<gpu::Buffer> meshPages_;
    std::vector<gpu::Image> elevationPages_, imageryPages_;
    gpu::Image dummyElevation_, dummyImagery_;
    // Pages written since beginUploads.
    std::vector<bool> meshTouched_, elevationTouched_, imageryTouched_;
};

}  // namespace orbis::layers
