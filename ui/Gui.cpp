#include "ui/Gui.h"

#include "base/Color.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/RenderTarget.h"
#include "engine/gpu/VkCheck.h"

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>

#include <stdexcept>
#include <string>

namespace orbis::ui {
namespace {

void checkVk(VkResult r) {
    if (r != VK_SUCCESS) throw std::runtime_error("Dear ImGui's Vulkan backend: VkResult " + std::to_string(int(r)));
}

/// The dark style, scaled for HiDPI screens, with its colours in linear light.
void applyStyle(float contentScale) {
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 4.0f;
    style.FrameRounding = 3.0f;
    style.ScaleAllSizes(contentScale);
    ImGui::GetIO().FontGlobalScale = contentScale;
    // The colours are meant as sRGB; the target blends in linear light.
    for (ImVec4& c : style.Colors) {
        c.x = float(srgbToLinear(c.x));
        c.y = float(srgbToLinear(c.y));
        c.z = float(srgbToLinear(c.z));
    }
}

/// The descriptor sets of ImGui's Vulkan backend (its font texture, with room to spare).
VkDescriptorPool makeDescriptorPool(VkDevice device) {
    const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16}};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    poolInfo.maxSets = 16;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = sizes;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool));
    return pool;
}

/// One subpass over the render target's colour: loaded and stored, so the UI lands on the picture.
VkRenderPass makeOverlayPass(VkDevice device) {
    VkAttachmentDescription color{};
    color.format = gpu::RenderTarget::kColorFormat;
    color.samples = VK_SAMPLE_COUNT_1_BIT;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    color.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &ref;
    VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rp.attachmentCount = 1;
    rp.pAttachments = &color;
    rp.subpassCount = 1;
    rp.pSubpasses = &subpass;
    VkRenderPass pass = VK_NULL_HANDLE;
    VK_CHECK(vkCreateRenderPass(device, &rp, nullptr, &pass));
    return pass;
}

}  // namespace

Gui::Gui(gpu::Device& device, GLFWwindow* window, float contentScale, std::filesystem::path layoutFile)
    : device_(device), layoutFile_(layoutFile.string()) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    // Never a file next to the binary (ImGui's default): the one given, or the code's layout.
    ImGui::GetIO().IniFilename = layoutFile_.empty() ? nullptr : layoutFile_.c_str();
    applyStyle(contentScale);
    pool_ = makeDescriptorPool(device.vk());
    renderPass_ = makeOverlayPass(device.vk());

    ImGui_ImplGlfw_InitForVulkan(window, true);
    ImGui_ImplVulkan_InitInfo init{};
    init.Instance = device.instance();
    init.PhysicalDevice = device.physical();
    init.Device = device.vk();
    init.QueueFamily = device.queueFamily();
    init.Queue = device.queue();
    init.DescriptorPool = pool_;
    init.MinImageCount = 2;
    init.ImageCount = 3;   // its vertex buffers rotate over 3 frames; 2 are in flight at most
    init.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    init.CheckVkResultFn = checkVk;
    ImGui_ImplVulkan_Init(&init, renderPass_);
    device.runOnce([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
}

Gui::~Gui() {
    vkDeviceWaitIdle(device_.vk());
    if (frameOpen_) ImGui::EndFrame();
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    if (framebuffer_) vkDestroyFramebuffer(device_.vk(), framebuffer_, nullptr);
    vkDestroyRenderPass(device_.vk(), renderPass_, nullptr);
    vkDestroyDescriptorPool(device_.vk(), pool_, nullptr);
}

void Gui::newFrame(const MouseOverride* mouse) {
    if (frameOpen_) ImGui::EndFrame();
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    if (mouse) {   // after the GLFW backend has read the real mouse, before ImGui uses it
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = ImVec2(mouse->x, mouse->y);
        for (int b = 0; b < 3; ++b) io.MouseDown[b] = mouse->buttons[b];
    }
    ImGui::NewFrame();
    frameOpen_ = true;
}

void Gui::endFrameWithoutDrawing() {
    if (!frameOpen_) return;
    ImGui::EndFrame();
    frameOpen_ = false;
}

void Gui::ensureFramebuffer(gpu::RenderTarget& target) {
    if (framebuffer_ && framebufferView_ == target.color().view() && fbWidth_ == target.width() &&
        fbHeight_ == target.height())
        return;
    if (framebuffer_) {
        VkDevice d = device_.vk();
        VkFramebuffer old = framebuffer_;
        device_.retire([d, old] { vkDestroyFramebuffer(d, old, nullptr); });
    }
    VkImageView view = target.color().view();
    VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    info.renderPass = renderPass_;
    info.attachmentCount = 1;
    info.pAttachments = &view;
    info.width = target.width();
    info.height = target.height();
    info.layers = 1;
    VK_CHECK(vkCreateFramebuffer(device_.vk(), &info, nullptr, &framebuffer_));
    framebufferView_ = view;
    fbWidth_ = target.width();
    fbHeight_ = target.height();
}

void Gui::record(VkCommandBuffer cmd, gpu::RenderTarget& target) {
    if (!frameOpen_) return;
    ImGui::Render();
    frameOpen_ = false;
    ensureFramebuffer(target);
    VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    begin.renderPass = renderPass_;
    begin.framebuffer = framebuffer_;
    begin.renderArea = {{0, 0}, {target.width(), target.height()}};
    vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
    ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
    vkCmdEndRenderPass(cmd);
}

bool Gui::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }
bool Gui::wantsKeyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

}  // namespace orbis::ui
