// The Vulkan context with a window surface: an instance made with GLFW's required extensions and
// a device whose queue presents to a real GLFW window's surface. Runs under Xvfb (tools/test.sh
// starts one when no display is set); without any display it skips with a message.
#include "engine/gpu/Device.h"
#include "engine/gpu/Instance.h"
#include "tests/support/GpuTest.h"

#define GLFW_INCLUDE_NONE
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <cstdlib>

namespace orbis::test {
namespace {

TEST(Surface, DeviceCreatedForAGlfwWindowPresentsToIt) {
    if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
        GTEST_SKIP() << "no display: run under Xvfb (tools/test.sh does)";
    ASSERT_TRUE(glfwInit()) << "glfwInit failed";
    ASSERT_TRUE(glfwVulkanSupported()) << "GLFW finds no Vulkan loader";
    uint32_t count = 0;
    const char** required = glfwGetRequiredInstanceExtensions(&count);
    ASSERT_NE(required, nullptr);
    gpu::InstanceOptions io;
    io.validation = true;
    for (uint32_t i = 0; i < count; ++i) io.extensions.emplace_back(required[i]);
    {
        gpu::Instance instance(io);
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        GLFWwindow* window = glfwCreateWindow(320, 240, "orbis surface test", nullptr, nullptr);
        ASSERT_NE(window, nullptr);
        VkSurfaceKHR surface = VK_NULL_HANDLE;
        ASSERT_EQ(glfwCreateWindowSurface(instance.vk(), window, nullptr, &surface), VK_SUCCESS);
        {
            gpu::DeviceOptions dopt;
            dopt.select = "llvmpipe";
            dopt.surface = surface;
            gpu::Device device(instance, dopt);
            VkBool32 presents = VK_FALSE;
            vkGetPhysicalDeviceSurfaceSupportKHR(device.physical(), device.queueFamily(), surface, &presents);
            EXPECT_TRUE(presents);
            VkSurfaceCapabilitiesKHR caps;
            EXPECT_EQ(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(device.physical(), surface, &caps), VK_SUCCESS);
            EXPECT_GE(caps.maxImageCount == 0 ? 3u : caps.maxImageCount, caps.minImageCount);
        }
        vkDestroySurfaceKHR(instance.vk(), surface, nullptr);
        glfwDestroyWindow(window);
        EXPECT_EQ(instance.validationMessages(), 0) << instance.firstValidationMessage();
    }
    glfwTerminate();
}

}  // namespace
}  // namespace orbis::test
