#pragma once
// Staging uploads recorded into a command buffer. Each upload gets a staging buffer from the
// sub-allocator; it is retired at once and so freed when the submit that copies from it is
// done. Counts bytes so callers can keep to a per-frame upload budget.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Image.h"

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <span>

namespace orbis::gpu {

class Device;

class Uploader {
public:
    explicit Uploader(Device& device) : device_(device) {}

    /// Copies `size` bytes into `dst` at `offset`. Add a bufferBarrier before the consumer.
    /// Called while recording.
    void toBuffer(VkCommandBuffer cmd, Buffer& dst, const void* data, VkDeviceSize size, VkDeviceSize offset = 0);

    /// Copies tightly packed texels into one layer (or a 3-D region) of `dst`, leaving it in
    /// TransferDst use: transition it to its sampled use afterwards. Called while recording.
    void toImage(VkCommandBuffer cmd, Image& dst, const void* data, VkDeviceSize size, uint32_t layer = 0,
                 VkOffset3D offset = {0, 0, 0}, VkExtent3D extent = {0, 0, 0});

    /// Copies one staging block into several subresources of `dst` (e.g. every mip level of
    /// one array layer); each region's bufferOffset is relative to `data`. Leaves `dst` in
    /// TransferDst use. Called while recording.
    void toImageRegions(VkCommandBuffer cmd, Image& dst, const void* data, VkDeviceSize size,
                        std::span<const VkBufferImageCopy> regions);

    uint64_t bytesUploaded() const { return bytes_; }
    void resetCounter() { bytes_ = 0; }

private:
    Device& device_;
    uint64_t bytes_ = 0;
};

}  // namespace orbis::gpu
