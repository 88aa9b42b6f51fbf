#pragma once
// The offscreen target every frame renders into: RGBA8 sRGB colour + D32_SFLOAT reversed-Z
// depth (cleared to 0 = infinitely far). The headless renderer reads the colour back; the
// viewer blits it to the swapchain.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Image.h"

#include <cstdint>
#include <vector>

namespace orbis::gpu {

class Device;

class RenderTarget {
public:
    static constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_SRGB;
    static constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

    RenderTarget(Device& device, uint32_t width, uint32_t height);

    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    Image& color() { return color_; }
    Image& depth() { return depth_; }

    /// Records the copy of the colour image into the readback buffer. Called while recording.
    void recordReadback(VkCommandBuffer cmd);
    /// The pixels copied by the last recordReadback, as tightly packed RGBA8 (sRGB-encoded),
    /// top row first. Its submit must have completed.
    std::vector<uint8_t> readPixels();

private:
    Device& device_;
    uint32_t width_, height_;
    Image color_;
    Image depth_;
    Buffer readback_;
};

}  // namespace orbis::gpu
