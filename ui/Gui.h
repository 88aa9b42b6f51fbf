#pragma once
// Dear ImGui over the viewer's picture: the unmodified GLFW and Vulkan backends of Debian's
// libimgui (1.86). Its Vulkan backend needs a classic render pass, so the UI is drawn in one
// over the render target's sRGB colour image (load, store), after the scene's passes and before
// the blit to the window. The style's colours are converted to linear so that they look as
// designed on an sRGB target. Main thread only.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <filesystem>
#include <string>

struct GLFWwindow;

namespace orbis::gpu {
class Device;
class RenderTarget;
}  // namespace orbis::gpu

namespace orbis::ui {

class Gui {
public:
    /// Installs ImGui's GLFW callbacks after the window's own (ImGui chains to them). With a
    /// `layoutFile`, the panels' places and sizes are read from it and written back to it (ImGui's
    /// ini format); without, every session starts from the layout in the code.
    Gui(gpu::Device& device, GLFWwindow* window, float contentScale, std::filesystem::path layoutFile = {});
    ~Gui();
    Gui(const Gui&) = delete;
    Gui& operator=(const Gui&) = delete;

    /// The mouse as a script plays it, instead of the window's.
    struct MouseOverride {
        float x = 0.0f, y = 0.0f;
        bool buttons[3] = {false, false, false};   ///< left, right, middle
    };
    /// Starts an ImGui frame; build windows after it, then call record().
    void newFrame(const MouseOverride* mouse = nullptr);
    /// Ends the ImGui frame and records its draw lists over `target` (colour in
    /// ImageUse::ColorAttachment). Called from FrameHooks::overlay.
    void record(VkCommandBuffer cmd, gpu::RenderTarget& target);
    /// Ends the frame without drawing (a frame that is not shown).
    void endFrameWithoutDrawing();

    /// True while ImGui uses the mouse / keyboard (the globe must not move then).
    bool wantsMouse() const;
    bool wantsKeyboard() const;

private:
    void ensureFramebuffer(gpu::RenderTarget& target);

    gpu::Device& device_;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    VkRenderPass renderPass_ = VK_NULL_HANDLE;
    VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
    VkImageView framebufferView_ = VK_NULL_HANDLE;
    uint32_t fbWidth_ = 0, fbHeight_ = 0;
    bool frameOpen_ = false;
    std::string layoutFile_;   ///< ImGui keeps the pointer: it lives as long as the context
};

}  // namespace orbis::ui
