#pragma once
// The terrain's tile data on the GPU: tile meshes in pages of vertex buffer, elevation and
// imagery each in ONE array image whose layers are the slots (shader::kElevationMaxSlots,
// kImageryMaxSlots at most). A slot holds one tile's data, found by its DataKey. Capacity is
// added on demand while the GPU budget allows (a mesh page; an array image twice as large, the
// old layers copied into it while the frame's transfers are recorded); past it, the least
// recently used slot that the current frame does not use is given to new data. Before an
// image exists a small dummy stands in for it.
//
// One image per kind, not pages of them: a shader cannot index an array of samplers with a
// per-tile value on lavapipe (no dynamic indexing), and a switch over the pages made llvmpipe
// sample every page for every pixel (8 pages: the default scene's terrain took 186 ms a frame
// at 1920x1080, 111 ms with one).

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

    /// Tiles of `gridSize` samples and `imageSize` pixels a side; capacity within `budgetBytes` less
    /// the `reservedBytes` the layer holds besides (its index and draw buffers). Uploads the
    /// dummies before it returns. Main thread.
    TileSlotPool(gpu::Device& device, gpu::Uploader& uploader, int gridSize, int imageSize, uint64_t budgetBytes,
                 uint64_t reservedBytes);

    /// Slots found or acquired from now on are this frame's (number > 0). Main thread.
    void beginFrame(uint64_t frame) { frame_ = frame; }
    /// The slot holding `key`'s data, marked used this frame.
    std::optional<uint32_t> find(Kind kind, const globe::DataKey& key);
    /// A slot for `key`'s data, to be uploaded this frame: a free one, one of new capacity while
    /// within the budget, else the least recently used one this frame does not use. Only
    /// `mayExceedBudget` (a mesh, without which a tile would be a hole) adds capacity past the
    /// budget. Nothing when no slot can be had: the caller falls back to an ancestor.
    /// `generation`: which version of the key's data goes in (TerrainTiles::dataGeneration).
    std::optional<uint32_t> acquire(Kind kind, const globe::DataKey& key, bool mayExceedBudget, uint32_t generation = 0);
    /// The version of its key's data a slot holds; a newer one is uploaded into the same slot
    /// (setGeneration), the old image drawn until then.
    uint32_t generation(Kind kind, uint32_t slot) const { return pool(kind).slots[slot].generation; }
    void setGeneration(Kind kind, uint32_t slot, uint32_t generation) { pool(kind).slots[slot].generation = generation; }
    /// The bytes of one slot of `kind` (what uploading it costs).
    uint64_t slotBytes(Kind kind) const;

    /// Uploads into slots, while recording the frame's transfers: beginUploads (which first
    /// copies a grown image's old layers), the slots' data, then endUploads, which makes what
    /// was written visible to the draws. Needed whenever there are uploads or growing().
    void beginUploads(VkCommandBuffer cmd);
    /// An image grew this frame: its old layers are still to be copied (beginUploads).
    bool growing() const;
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
    /// The views the shaders bind (a dummy before the first slot).
    VkImageView elevationView() const;
    VkImageView imageryView() const;
    /// Changes whenever an image is replaced (descriptor sets naming the old views are stale).
    uint64_t version() const { return version_; }
    uint64_t allocatedBytes() const;

private:
    static constexpr uint32_t kMeshSlotsPerPage = 64;
    static constexpr uint32_t kMeshPagesMax = 64;
    static constexpr uint32_t kElevationFirstSlots = 128;
    static constexpr uint32_t kImageryFirstSlots = 32;
    struct Slot {
        globe::DataKey owner;
        uint64_t lastUsed = 0;
        bool taken = false;
        uint32_t generation = 0;
    };
    struct Pool {
        uint32_t growBy = 0;     ///< slots of the first page (meshes: of every page)
        uint32_t maxSlots = 0;
        uint64_t slotBytes = 0;
        std::vector<Slot> slots;   ///< the capacity
        std::vector<uint32_t> freeSlots;
        std::unordered_map<globe::DataKey, uint32_t, globe::DataKeyHash> resident;
    };
    /// An elevation or imagery array image, and while it grows the image its layers come from.
    struct SlotImage {
        gpu::Image image;
        gpu::Image copyFrom;       ///< valid until beginUploads copies its layers
        uint32_t copyLayers = 0;
        bool touched = false;      ///< written since beginUploads
    };
    Pool& pool(Kind kind) { return pools_[size_t(kind)]; }
    const Pool& pool(Kind kind) const { return pools_[size_t(kind)]; }
    /// The least recently used slot not used this frame, freed; nothing if every slot is in use.
    bool evictOne(Pool& pool);
    /// The capacity `kind` would have after growing (its current one when it cannot grow).
    uint32_t grownCapacity(Kind kind) const;
    void grow(Kind kind, uint32_t capacity);
    SlotImage& slotImage(Kind kind) { return kind == Kind::Elevation ? elevation_ : imagery_; }
    void copyGrown(VkCommandBuffer cmd, SlotImage& target);
    void createDummies(gpu::Uploader& uploader);

    gpu::Device* device_;
    int gridSize_, imageSize_;
    uint32_t meshVertices_;
    uint64_t budgetBytes_, reservedBytes_;
    uint64_t frame_ = 0, version_ = 1;
    bool warnedBudget_ = false;
    Pool pools_[3];
    std::vector<gpu::Buffer> meshPages_;
    SlotImage elevation_, imagery_;
    gpu::Image dummyElevation_, dummyImagery_;
    std::vector<bool> meshTouched_;   ///< mesh pages written since beginUploads
};

}  // namespace orbis::layers
