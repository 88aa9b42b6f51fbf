#include "engine/gpu/FrameRing.h"

#include "engine/gpu/VkCheck.h"

namespace orbis::gpu {

FrameRing::FrameRing(Device& device, uint32_t framesInFlight) : device_(device) {
    slots_.resize(framesInFlight);
    for (uint32_t i = 0; i < framesInFlight; ++i) {
        VkCommandPoolCreateInfo info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        info.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
        info.queueFamilyIndex = device.queueFamily();
        VkCommandPool pool = VK_NULL_HANDLE;
        VK_CHECK(vkCreateCommandPool(device.vk(), &info, nullptr, &pool));
        slots_[i].pool = CommandPool(device, pool);
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = pool;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        VK_CHECK(vkAllocateCommandBuffers(device.vk(), &alloc, &slots_[i].frame.cmd));
        slots_[i].frame.slot = i;
    }
}

FrameRing::~FrameRing() {
    for (auto& s : slots_) device_.wait(s.frame.submitted);
}

FrameRing::Frame& FrameRing::begin() {
    Slot& slot = slots_[frameNumber_ % slots_.size()];
    device_.wait(slot.frame.submitted);
    device_.collectRetired();
    VK_CHECK(vkResetCommandPool(device_.vk(), slot.pool.vk(), 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(slot.frame.cmd, &begin));
    slot.frame.number = ++frameNumber_;
    device_.setRecordingFrame(true);
    return slot.frame;
}

uint64_t FrameRing::submit(Frame& frame, std::span<const VkSemaphoreSubmitInfo> waits,
                           std::span<const VkSemaphoreSubmitInfo> signals) {
    VK_CHECK(vkEndCommandBuffer(frame.cmd));
    device_.setRecordingFrame(false);
    frame.submitted = device_.submit(frame.cmd, waits, signals);
    return frame.submitted;
}

}  // namespace orbis::gpu
