#pragma once
// The one place where image layouts and pipeline barriers are decided. Passes declare how
// they use each image (ImageUse); this file turns the change of use into a synchronization2
// barrier. No other file writes VkImageMemoryBarrier2 by hand.

#include "engine/gpu/Image.h"

#include <vulkan/vulkan.h>

#include <span>

namespace orbis::gpu {

class Buffer;

/// Records the barrier that moves `image` from its current use to `use`. Called while recording.
void transition(VkCommandBuffer cmd, Image& image, ImageUse use);

/// Several transitions in one vkCmdPipelineBarrier2. Called while recording.
struct ImageTransition {
    Image* image;
    ImageUse use;
};
void transition(VkCommandBuffer cmd, std::span<const ImageTransition> transitions);

/// Transfer writes to a buffer become visible to the given stages/access (after uploads).
void bufferBarrier(VkCommandBuffer cmd, const Buffer& buffer, VkPipelineStageFlags2 srcStage,
                   VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);

VkImageLayout layoutFor(ImageUse use);

}  // namespace orbis::gpu
