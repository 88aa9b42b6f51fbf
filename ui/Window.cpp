#include "ui/Window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <cstdlib>
#include <stdexcept>

namespace orbis::ui {
namespace {

int g_windows = 0;
std::string g_glfwError;

void onGlfwError(int code, const char* message) {
    g_glfwError = std::string(message ? message : "unknown") + " (GLFW error " + std::to_string(code) + ")";
}

void initGlfw() {
    if (g_windows++ > 0) return;
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
        --g_windows;
        const char* display = std::getenv("DISPLAY");
        const char* wayland = std::getenv("WAYLAND_DISPLAY");
        std::string why = g_glfwError.empty() ? "GLFW could not start" : g_glfwError;
        if ((!display || !*display) && (!wayland || !*wayland))
            why += "; no display: DISPLAY is not set (run under X11, or xvfb-run for a virtual one)";
        throw std::runtime_error("cannot open a window: " + why);
    }
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        --g_windows;
        throw std::runtime_error("cannot open a window: GLFW finds no Vulkan loader");
    }
}

void releaseGlfw() {
    if (--g_windows == 0) glfwTerminate();
}

}  // namespace

std::vector<std::string> Window::requiredInstanceExtensions() {
    initGlfw();
    uint32_t n = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&n);
    std::vector<std::string> out(names, names + n);
    releaseGlfw();
    if (out.empty()) throw std::runtime_error("cannot open a window: GLFW lists no Vulkan surface extensions");
    return out;
}

Window::Window(const std::string& title, int width, int height) {
    initGlfw();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
        releaseGlfw();
        throw std::runtime_error("cannot open a window: " + (g_glfwError.empty() ? "glfwCreateWindow failed" : g_glfwError));
    }
}

Window::~Window() {
    if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
    glfwDestroyWindow(window_);
    releaseGlfw();
}

VkSurfaceKHR Window::createSurface(VkInstance instance) {
    if (surface_) return surface_;
    const VkResult r = glfwCreateWindowSurface(instance, window_, nullptr, &surface_);
    if (r != VK_SUCCESS)
        throw std::runtime_error("cannot make a Vulkan surface for the window (VkResult " + std::to_string(int(r)) + ")");
    instance_ = instance;
    return surface_;
}

bool Window::shouldClose() const { return glfwWindowShouldClose(window_); }
void Window::requestClose() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }

void Window::size(int& width, int& height) const { glfwGetWindowSize(window_, &width, &height); }

void Window::framebufferSize(uint32_t& width, uint32_t& height) const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    width = uint32_t(w > 0 ? w : 0);
    height = uint32_t(h > 0 ? h : 0);
}

float Window::contentScale() const {
    float x = 1.0f, y = 1.0f;
    glfwGetWindowContentScale(window_, &x, &y);
    return x > 0.0f ? x : 1.0f;
}

void Window::setTitle(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }

void Window::pollEvents(bool wait, double timeoutSeconds) {
    if (wait) glfwWaitEventsTimeout(timeoutSeconds);
    else glfwPollEvents();
}

void Window::wake() { glfwPostEmptyEvent(); }

}  // namespace orbis::ui
