#pragma once
// Move-only owner of one VkImage, its default view and its memory. It remembers how it was
// last used so that transitions (engine/gpu/Barriers) are computed in one place.

#include "engine/gpu/MemoryAllocator.h"

#include <vulkan/vulkan.h>

namespace orbis::gpu {

class Device;

/// How a pass uses an image. Barriers.cpp maps each to (layout, stages, access).
enum class ImageUse {
    Undefined,
    ColorAttachment,
    DepthAttachment,      ///< depth test + write
    DepthRead,            ///< depth test only, or sampled as depth
    SampledFragment,
    SampledGraphics,      ///< sampled from vertex and fragment shaders (e.g. terrain heights)
    SampledCompute,
    StorageCompute,       ///< read/write from compute shaders
    TransferSrc,
    TransferDst,
    Present,
};

struct ImageDesc {
    VkImageType type = VK_IMAGE_TYPE_2D;
    VkImageViewType viewType = VK_IMAGE_VIEW_TYPE_2D;
    VkFormat format = VK_FORMAT_R8G8B8A8_SRGB;
    VkExtent3D extent{1, 1, 1};
    uint32_t mipLevels = 1;
    uint32_t layers = 1;
    VkImageUsageFlags usage = VK_IMAGE_USAGE_SAMPLED_BIT;
    const char* name = nullptr;
};

class Image {
public:
    Image() = default;
    Image(Device& device, const ImageDesc& desc);
    ~Image();
    Image(Image&& other) noexcept;
    Image& operator=(Image&& other) noexcept;
    Image(const Image&) = delete;
    Image& operator=(const Image&) = delete;
    /// An image owned by someone else (a swapchain's): tracked for barriers, never destroyed.
    static Image borrowed(VkImage image, const ImageDesc& desc, ImageUse currentUse = ImageUse::Undefined);

    VkImage vk() const { return image_; }
    VkImageView view() const { return view_; }
    VkFormat format() const { return desc_.format; }
    VkExtent3D extent() const { return desc_.extent; }
    const ImageDesc& desc() const { return desc_; }
    VkImageAspectFlags aspect() const;
    explicit operator bool() const { return image_ != VK_NULL_HANDLE; }

    ImageUse currentUse() const { return use_; }
    /// Only Barriers.cpp changes this, when it records the matching barrier.
    void setCurrentUse(ImageUse use) { use_ = use; }

private:
    void release();

    Device* device_ = nullptr;
    VkImage image_ = VK_NULL_HANDLE;
    VkImageView view_ = VK_NULL_HANDLE;
    ImageDesc desc_;
    Allocation memory_;
    ImageUse use_ = ImageUse::Undefined;
};

bool isDepthFormat(VkFormat format);

}  // namespace orbis::gpu
