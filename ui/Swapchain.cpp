#include "ui/Swapchain.h"

#include "base/Log.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/VkCheck.h"

#include <algorithm>
#include <stdexcept>

namespace orbis::ui {
namespace {

constexpr uint32_t kAcquireSlots = 4;

VkSemaphore makeSemaphore(VkDevice device) {
    VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkSemaphore s = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSemaphore(device, &info, nullptr, &s));
    return s;
}

/// An sRGB format when the surface has one (the picture is blitted from an sRGB target), else
/// its first with a warning.
VkSurfaceFormatKHR chooseFormat(VkPhysicalDevice pd, VkSurfaceKHR surface) {
    uint32_t n = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(n);
    vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data());
    if (formats.empty()) throw std::runtime_error("the window's surface offers no image format");
    VkSurfaceFormatKHR chosen = formats[0];
    for (VkFormat want : {VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R8G8B8A8_SRGB}) {
        auto it = std::find_if(formats.begin(), formats.end(), [&](const VkSurfaceFormatKHR& f) {
            return f.format == want && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
        });
        if (it != formats.end()) {
            chosen = *it;
            break;
        }
    }
    if (chosen.format != VK_FORMAT_B8G8R8A8_SRGB && chosen.format != VK_FORMAT_R8G8B8A8_SRGB)
        log::warn("the window offers no sRGB format; colours will look darker (format ", int(chosen.format), ")");
    return chosen;
}

/// FIFO with vsync (always there); without, MAILBOX or IMMEDIATE where the surface has them.
VkPresentModeKHR choosePresentMode(VkPhysicalDevice pd, VkSurfaceKHR surface, bool vsync) {
    uint32_t n = 0;
    vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr);
    std::vector<VkPresentModeKHR> modes(n);
    vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, modes.data());
    if (!vsync)
        for (VkPresentModeKHR want : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
            if (std::find(modes.begin(), modes.end(), want) != modes.end()) return want;
    return VK_PRESENT_MODE_FIFO_KHR;
}

}  // namespace

Swapchain::Swapchain(gpu::Device& device, VkSurfaceKHR surface, bool vsync)
    : device_(device), surface_(surface), vsync_(vsync) {
    for (uint32_t i = 0; i < kAcquireSlots; ++i) acquireSlots_.push_back({makeSemaphore(device.vk()), 0});
}

Swapchain::~Swapchain() {
    vkDeviceWaitIdle(device_.vk());
    destroyImages();
    if (swapchain_) vkDestroySwapchainKHR(device_.vk(), swapchain_, nullptr);
    for (auto& s : acquireSlots_) vkDestroySemaphore(device_.vk(), s.semaphore, nullptr);
}

void Swapchain::destroyImages() {
    images_.clear();
    for (VkSemaphore s : rendered_) vkDestroySemaphore(device_.vk(), s, nullptr);
    rendered_.clear();
}

void Swapchain::setVsync(bool on) {
    if (on == vsync_) return;
    vsync_ = on;
    stale_ = true;
}

bool Swapchain::rebuild(uint32_t width, uint32_t height) {
    VkPhysicalDevice pd = device_.physical();
    VkSurfaceCapabilitiesKHR caps{};
    VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface_, &caps));
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == UINT32_MAX) {   // the surface takes the swapchain's size
        extent.width = std::clamp(width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (extent.width == 0 || extent.height == 0) return false;   // minimised

    const VkSurfaceFormatKHR chosen = chooseFormat(pd, surface_);
    const VkPresentModeKHR mode = choosePresentMode(pd, surface_, vsync_);

    uint32_t count = std::max(caps.minImageCount + 1, 3u);
    if (caps.maxImageCount > 0) count = std::min(count, caps.maxImageCount);

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface_;
    info.minImageCount = count;
    info.imageFormat = chosen.format;
    info.imageColorSpace = chosen.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                              ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                              : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
    info.presentMode = mode;
    info.clipped = VK_TRUE;
    info.oldSwapchain = swapchain_;

    // Every frame that used the old images must be done before they go.
    vkDeviceWaitIdle(device_.vk());
    VkSwapchainKHR created = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSwapchainKHR(device_.vk(), &info, nullptr, &created));
    destroyImages();
    if (swapchain_) vkDestroySwapchainKHR(device_.vk(), swapchain_, nullptr);
    swapchain_ = created;
    format_ = chosen.format;
    extent_ = extent;
    presentMode_ = mode;

    const uint32_t n = adoptImages(info.imageUsage);
    log::debug("swapchain ", extent.width, "x", extent.height, ", ", n, " images, present mode ", int(mode));
    stale_ = false;
    return true;
}

/// Wraps the new swapchain's images (borrowed: the swapchain owns them), each with the
/// semaphore its presentation waits on. Returns how many there are.
uint32_t Swapchain::adoptImages(VkImageUsageFlags usage) {
    uint32_t n = 0;
    vkGetSwapchainImagesKHR(device_.vk(), swapchain_, &n, nullptr);
    std::vector<VkImage> images(n);
    vkGetSwapchainImagesKHR(device_.vk(), swapchain_, &n, images.data());
    gpu::ImageDesc desc;
    desc.format = format_;
    desc.extent = {extent_.width, extent_.height, 1};
    desc.usage = usage;
    desc.name = "swapchain";
    for (VkImage image : images) {
        images_.push_back(gpu::Image::borrowed(image, desc));
        rendered_.push_back(makeSemaphore(device_.vk()));
    }
    return n;
}

std::optional<Swapchain::Acquired> Swapchain::acquire(uint32_t width, uint32_t height) {
    if (width == 0 || height == 0) return std::nullopt;
    if (!stale_ && (width != extent_.width || height != extent_.height)) stale_ = true;
    for (int attempt = 0; attempt < 2; ++attempt) {
        if (stale_ && !rebuild(width, height)) return std::nullopt;
        AcquireSlot& slot = acquireSlots_[nextSlot_];
        device_.wait(slot.usedBy);   // its last waiter is done: the semaphore is free again
        uint32_t index = 0;
        const VkResult r = vkAcquireNextImageKHR(device_.vk(), swapchain_, UINT64_MAX, slot.semaphore, VK_NULL_HANDLE, &index);
        if (r == VK_ERROR_OUT_OF_DATE_KHR) {
            stale_ = true;
            continue;
        }
        if (r == VK_SUBOPTIMAL_KHR) stale_ = true;   // usable now, rebuilt next time
        else VK_CHECK(r);
        Acquired a;
        a.slot = nextSlot_;
        nextSlot_ = (nextSlot_ + 1) % uint32_t(acquireSlots_.size());
        a.index = index;
        a.image = &images_[index];
        a.image->setCurrentUse(gpu::ImageUse::Undefined);   // its contents are not kept
        a.acquired = slot.semaphore;
        a.rendered = rendered_[index];
        return a;
    }
    return std::nullopt;
}

void Swapchain::present(const Acquired& a, uint64_t timelineValue) {
    acquireSlots_[a.slot].usedBy = timelineValue;
    VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    info.waitSemaphoreCount = 1;
    info.pWaitSemaphores = &a.rendered;
    info.swapchainCount = 1;
    info.pSwapchains = &swapchain_;
    info.pImageIndices = &a.index;
    const VkResult r = vkQueuePresentKHR(device_.queue(), &info);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) stale_ = true;
    else VK_CHECK(r);
}

}  // namespace orbis::ui
