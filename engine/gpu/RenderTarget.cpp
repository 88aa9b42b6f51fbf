#include "engine/gpu/RenderTarget.h"

#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"

#include <cstring>

namespace orbis::gpu {

RenderTarget::RenderTarget(Device& device, uint32_t width, uint32_t height)
    : device_(device), width_(width), height_(height) {
    ImageDesc color;
    color.format = kColorFormat;
    color.extent = {width, height, 1};
    color.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                  VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    color.name = "frame colour";
    color_ = Image(device, color);
    ImageDesc depth;
    depth.format = kDepthFormat;
    depth.extent = {width, height, 1};
    depth.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    depth.name = "frame depth";
    depth_ = Image(device, depth);
}

void RenderTarget::recordReadback(VkCommandBuffer cmd) {
    const VkDeviceSize size = VkDeviceSize(width_) * height_ * 4;
    if (!readback_ || readback_.size() < size)
        readback_ = Buffer(device_, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::Readback, "readback");
    transition(cmd, color_, ImageUse::TransferSrc);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {width_, height_, 1};
    vkCmdCopyImageToBuffer(cmd, color_.vk(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.vk(), 1, &region);
    // Make the transfer write visible to the host read that follows the wait.
    bufferBarrier(cmd, readback_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

std::vector<uint8_t> RenderTarget::readPixels() {
    std::vector<uint8_t> pixels(size_t(width_) * height_ * 4);
    if (!readback_) return pixels;
    readback_.invalidate();
    std::memcpy(pixels.data(), readback_.mapped(), pixels.size());
    return pixels;
}

}  // namespace orbis::gpu
