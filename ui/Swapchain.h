#pragma once
// The window's swapchain: an sRGB format (the picture is blitted from the sRGB render target,
// so the colours pass unchanged), FIFO when vsync is on, else MAILBOX or IMMEDIATE. Acquire
// semaphores rotate and are reused only once the frame that waited on them is done; each image
// has its own "rendered" semaphore that presentation waits on. Out-of-date and suboptimal
// swapchains are rebuilt at the next acquire. Main thread only.

#include "engine/gpu/Image.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace orbis::gpu {
class Device;
}

namespace orbis::ui {

class Swapchain {
public:
    Swapchain(gpu::Device& device, VkSurfaceKHR surface, bool vsync);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    struct Acquired {
        uint32_t index = 0;
        gpu::Image* image = nullptr;        ///< borrowed; its use is tracked for barriers
        VkSemaphore acquired = VK_NULL_HANDLE;   ///< the frame's submit waits on it
        VkSemaphore rendered = VK_NULL_HANDLE;   ///< the frame's submit signals it; present waits
        uint32_t slot = 0;                       ///< the acquire semaphore's slot
    };
    /// The next image for a framebuffer of `width` x `height` pixels (the swapchain is rebuilt
    /// when the size changed or it went out of date); nothing while the window is minimised.
    std::optional<Acquired> acquire(uint32_t width, uint32_t height);
    /// Tells which timeline value the frame that used `a` signals (its acquire semaphore is
    /// reused only after it), then presents.
    void present(const Acquired& a, uint64_t timelineValue);

    void setVsync(bool on);
    bool vsync() const { return vsync_; }
    VkFormat format() const { return format_; }
    VkExtent2D extent() const { return extent_; }
    VkPresentModeKHR presentMode() const { return presentMode_; }
    uint32_t imageCount() const { return uint32_t(images_.size()); }

private:
    bool rebuild(uint32_t width, uint32_t height);
    uint32_t adoptImages(VkImageUsageFlags usage);
    void destroyImages();

    gpu::Device& device_;
    VkSurfaceKHR surface_;
    bool vsync_;
    bool stale_ = true;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkExtent2D extent_{0, 0};
    VkPresentModeKHR presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
    std::vector<gpu::Image> images_;
    std::vector<VkSemaphore> rendered_;   ///< one per image
    struct AcquireSlot {
        VkSemaphore semaphore = VK_NULL_HANDLE;
        uint64_t usedBy = 0;   ///< timeline value of the frame that waited on it
    };
    std::vector<AcquireSlot> acquireSlots_;
    uint32_t nextSlot_ = 0;
};

}  // namespace orbis::ui
