// The Viewer's picture: the renderer's frame with the panels drawn over it, blitted into the
// swapchain's image and presented, and the frame's figures for the statistics panel.
#include "ui/Viewer.h"

#include "engine/gpu/Barriers.h"

namespace orbis::ui {

/// Draws and presents one frame; nothing when the swapchain gives no image (the ImGui frame is
/// closed without drawing then).
std::optional<render::FrameResult> Viewer::drawFrame(bool readback) {
    auto acquired = swapchain_->acquire(fbWidth_, fbHeight_);
    if (!acquired) {
        gui_->endFrameWithoutDrawing();
        return std::nullopt;
    }
    renderer_->resize(fbWidth_, fbHeight_);
    const render::FrameHooks hooks = presentHooks(*acquired);
    const auto frameStart = Clock::now();
    const render::FrameResult frame = renderer_->render(*scene_, readback, hooks);
    swapchain_->present(*acquired, frame.timelineValue);
    drawnRevision_ = nav_.revision();
    dirty_ = false;
    if (uiFrames_ > 0) --uiFrames_;
    recordFrameStats(frame, frameStart);
    return frame;
}

/// The panels over the picture, then the picture into the swapchain image (scaled when the
/// sizes differ), waiting for the acquire and signalling what presentation waits on.
render::FrameHooks Viewer::presentHooks(const Swapchain::Acquired& acquired) {
    render::FrameHooks hooks;
    hooks.overlay = [this](VkCommandBuffer cmd, gpu::RenderTarget& target) { gui_->record(cmd, target); };
    hooks.finish = [image = acquired.image](VkCommandBuffer cmd, gpu::RenderTarget& target) {
        gpu::Image& dst = *image;
        const gpu::ImageTransition uses[] = {{&target.color(), gpu::ImageUse::TransferSrc},
                                             {&dst, gpu::ImageUse::TransferDst}};
        gpu::transition(cmd, uses);
        VkImageBlit region{};
        region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.dstSubresource = region.srcSubresource;
        region.srcOffsets[1] = {int32_t(target.width()), int32_t(target.height()), 1};
        region.dstOffsets[1] = {int32_t(dst.extent().width), int32_t(dst.extent().height), 1};
        const bool same = target.width() == dst.extent().width && target.height() == dst.extent().height;
        vkCmdBlitImage(cmd, target.color().vk(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst.vk(),
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region, same ? VK_FILTER_NEAREST : VK_FILTER_LINEAR);
        gpu::transition(cmd, dst, gpu::ImageUse::Present);
    };
    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait.semaphore = acquired.acquired;
    wait.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal.semaphore = acquired.rendered;
    signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    hooks.waits = {wait};
    hooks.signals = {signal};
    return hooks;
}

/// The statistics panel's figures; a frame's GPU times are read a frame later, when they are in.
void Viewer::recordFrameStats(const render::FrameResult& frame, Clock::time_point frameStart) {
    ++stats_.framesDrawn;
    stats_.cpuMs = frame.cpuMs;
    if (previous_) stats_.gpu = renderer_->gpuTimes(*previous_);
    previous_ = frame;
    stats_.frameMs = std::chrono::duration<double, std::milli>(Clock::now() - frameStart).count();
    if (script_) script_->recordFrameMs(stats_.frameMs);
}

}  // namespace orbis::ui
