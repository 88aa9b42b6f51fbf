#include "engine/gpu/Uploader.h"

#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"

namespace orbis::gpu {

void Uploader::toBuffer(VkCommandBuffer cmd, Buffer& dst, const void* data, VkDeviceSize size, VkDeviceSize offset) {
    Buffer staging(device_, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::Upload, "staging");
    staging.write(data, size);
    VkBufferCopy region{0, offset, size};
    vkCmdCopyBuffer(cmd, staging.vk(), dst.vk(), 1, &region);
    bytes_ += size;
}   // `staging` retires here, keyed to the submit that carries `cmd`

void Uploader::toImage(VkCommandBuffer cmd, Image& dst, const void* data, VkDeviceSize size, uint32_t layer,
                       VkOffset3D offset, VkExtent3D extent) {
    if (extent.width == 0) extent = dst.extent();
    Buffer staging(device_, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::Upload, "staging");
    staging.write(data, size);
    transition(cmd, dst, ImageUse::TransferDst);
    VkBufferImageCopy region{};
    region.imageSubresource = {dst.aspect(), 0, layer, 1};
    region.imageOffset = offset;
    region.imageExtent = extent;
    vkCmdCopyBufferToImage(cmd, staging.vk(), dst.vk(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    bytes_ += size;
}

void Uploader::toImageRegions(VkCommandBuffer cmd, Image& dst, const void* data, VkDeviceSize size,
                              std::span<const VkBufferImageCopy> regions) {
    Buffer staging(device_, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::Upload, "staging");
    staging.write(data, size);
    transition(cmd, dst, ImageUse::TransferDst);
    vkCmdCopyBufferToImage(cmd, staging.vk(), dst.vk(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           static_cast<uint32_t>(regions.size()), regions.data());
    bytes_ += size;
}

}  // namespace orbis::gpu
