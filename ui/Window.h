#pragma once
// The viewer's GLFW window (no client API: Vulkan draws into it) and its surface. GLFW is
// initialised by the first Window and terminated with the last. Main thread only.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

struct GLFWwindow;

namespace orbis::ui {

class Window {
public:
    /// Opens a window of `width` x `height` screen coordinates. Throws std::runtime_error with
    /// a clear message when there is no display or GLFW cannot make a window.
    Window(const std::string& title, int width, int height);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    /// The instance extensions GLFW needs for a surface (call before creating the instance).
    static std::vector<std::string> requiredInstanceExtensions();

    /// Creates the surface once the instance exists; the window destroys it.
    VkSurfaceKHR createSurface(VkInstance instance);

    GLFWwindow* glfw() const { return window_; }
    bool shouldClose() const;
    void requestClose();
    /// Window size in screen coordinates (the units of input positions).
    void size(int& width, int& height) const;
    /// Framebuffer size in pixels (0 x 0 while minimised).
    void framebufferSize(uint32_t& width, uint32_t& height) const;
    /// HiDPI content scale (1 on a classic screen).
    float contentScale() const;
    void setTitle(const std::string& title);

    /// Handles pending events; waits up to `timeoutSeconds` for one when `wait` is set (the
    /// viewer sleeps while nothing moves).
    static void pollEvents(bool wait, double timeoutSeconds);
    /// Wakes a waiting pollEvents from another thread (a tile arrived).
    static void wake();

private:
    GLFWwindow* window_ = nullptr;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
};

}  // namespace orbis::ui
