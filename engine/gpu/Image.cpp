#include "engine/gpu/Image.h"

#include "engine/gpu/Device.h"
#include "engine/gpu/VkCheck.h"

#include <utility>

namespace orbis::gpu {

bool isDepthFormat(VkFormat f) {
    return f == VK_FORMAT_D32_SFLOAT || f == VK_FORMAT_D16_UNORM || f == VK_FORMAT_D24_UNORM_S8_UINT ||
           f == VK_FORMAT_D32_SFLOAT_S8_UINT || f == VK_FORMAT_X8_D24_UNORM_PACK32;
}

VkImageAspectFlags Image::aspect() const {
    return isDepthFormat(desc_.format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

Image::Image(Device& device, const ImageDesc& desc) : device_(&device), desc_(desc) {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = desc.type;
    info.format = desc.format;
    info.extent = desc.extent;
    info.mipLevels = desc.mipLevels;
    info.arrayLayers = desc.layers;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = desc.usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(device.vk(), &info, nullptr, &image_));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device.vk(), image_, &req);
    try {
        memory_ = device.allocator().allocate(req, MemoryUsage::GpuOnly, /*linearResource=*/false);
        VK_CHECK(vkBindImageMemory(device.vk(), image_, memory_.memory, memory_.offset));
        VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        viewInfo.image = image_;
        viewInfo.viewType = desc.viewType;
        viewInfo.format = desc.format;
        viewInfo.subresourceRange = {aspect(), 0, desc.mipLevels, 0, desc.layers};
        VK_CHECK(vkCreateImageView(device.vk(), &viewInfo, nullptr, &view_));
    } catch (...) {
        if (memory_) device.allocator().free(memory_);
        vkDestroyImage(device.vk(), image_, nullptr);
        throw;
    }
    device.setDebugName(reinterpret_cast<uint64_t>(image_), VK_OBJECT_TYPE_IMAGE, desc.name);
    ++device.counters().images;
}

Image::~Image() { release(); }

Image::Image(Image&& o) noexcept
    : device_(std::exchange(o.device_, nullptr)),
      image_(std::exchange(o.image_, VK_NULL_HANDLE)),
      view_(std::exchange(o.view_, VK_NULL_HANDLE)),
      desc_(o.desc_),
      memory_(std::exchange(o.memory_, Allocation{})),
      use_(o.use_) {}

Image& Image::operator=(Image&& o) noexcept {
    if (this != &o) {
        release();
        device_ = std::exchange(o.device_, nullptr);
        image_ = std::exchange(o.image_, VK_NULL_HANDLE);
        view_ = std::exchange(o.view_, VK_NULL_HANDLE);
        desc_ = o.desc_;
        memory_ = std::exchange(o.memory_, Allocation{});
        use_ = o.use_;
    }
    return *this;
}

Image Image::borrowed(VkImage image, const ImageDesc& desc, ImageUse currentUse) {
    Image out;
    out.image_ = image;
    out.desc_ = desc;
    out.use_ = currentUse;
    return out;
}

void Image::release() {
    if (image_ == VK_NULL_HANDLE) return;
    if (device_ == nullptr) {   // borrowed: its owner destroys it
        image_ = VK_NULL_HANDLE;
        return;
    }
    Device* device = device_;
    VkImage image = image_;
    VkImageView view = view_;
    Allocation memory = memory_;
    --device->counters().images;
    device->retire([device, image, view, memory] {
        vkDestroyImageView(device->vk(), view, nullptr);
        vkDestroyImage(device->vk(), image, nullptr);
        device->allocator().free(memory);
    });
    image_ = VK_NULL_HANDLE;
}

}  // namespace orbis::gpu
