#include "ui/InputSink.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <optional>

namespace orbis::ui {
namespace {

std::optional<Key> keyFromGlfw(int key) {
    switch (key) {
        case GLFW_KEY_W: return Key::W;
        case GLFW_KEY_A: return Key::A;
        case GLFW_KEY_S: return Key::S;
        case GLFW_KEY_D: return Key::D;
        case GLFW_KEY_Q: return Key::Q;
        case GLFW_KEY_E: return Key::E;
        case GLFW_KEY_R: return Key::R;
        case GLFW_KEY_F: return Key::F;
        case GLFW_KEY_UP: return Key::Up;
        case GLFW_KEY_DOWN: return Key::Down;
        case GLFW_KEY_LEFT: return Key::Left;
        case GLFW_KEY_RIGHT: return Key::Right;
        case GLFW_KEY_PAGE_UP: return Key::PageUp;
        case GLFW_KEY_PAGE_DOWN: return Key::PageDown;
        case GLFW_KEY_HOME: return Key::Home;
        default: return std::nullopt;
    }
}

Modifiers modifiersFromGlfw(int mods) {
    return {bool(mods & GLFW_MOD_SHIFT), bool(mods & GLFW_MOD_CONTROL), bool(mods & GLFW_MOD_ALT)};
}

InputSink& sinkOf(GLFWwindow* w) { return *static_cast<InputSink*>(glfwGetWindowUserPointer(w)); }

void onMouseButton(GLFWwindow* w, int button, int action, int mods) {
    if (button > GLFW_MOUSE_BUTTON_MIDDLE || action == GLFW_REPEAT) return;
    double x = 0, y = 0;
    glfwGetCursorPos(w, &x, &y);
    MouseButtonEvent e;
    e.button = button == GLFW_MOUSE_BUTTON_LEFT    ? MouseButton::Left
               : button == GLFW_MOUSE_BUTTON_RIGHT ? MouseButton::Right
                                                   : MouseButton::Middle;
    e.pressed = action == GLFW_PRESS;
    e.position = {x, y};
    e.modifiers = modifiersFromGlfw(mods);
    e.timeSeconds = glfwGetTime();
    sinkOf(w).input.events.push_back(e);
}

void onKey(GLFWwindow* w, int key, int, int action, int mods) {
    FrameInput& in = sinkOf(w).input;
    if (action == GLFW_PRESS) {
        if (key == GLFW_KEY_F12) in.screenshot = true;
        if (key == GLFW_KEY_S && (mods & GLFW_MOD_CONTROL)) in.saveScene = true;
        if (key == GLFW_KEY_F1) in.togglePanels = true;
        if (key == GLFW_KEY_ESCAPE) in.escape = true;
    }
    if (action == GLFW_REPEAT) return;
    if (auto k = keyFromGlfw(key)) in.events.push_back(KeyEvent{*k, action == GLFW_PRESS, modifiersFromGlfw(mods)});
}

}  // namespace

void installInputCallbacks(GLFWwindow* window, InputSink& sink) {
    glfwSetWindowUserPointer(window, &sink);
    glfwSetMouseButtonCallback(window, onMouseButton);
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
        sinkOf(w).input.events.push_back(MouseMoveEvent{{x, y}});
    });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double x, double y) { sinkOf(w).input.events.push_back(ScrollEvent{x, y}); });
    glfwSetKeyCallback(window, onKey);
    glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int, int) { sinkOf(w).resized = true; });
    glfwSetWindowFocusCallback(window, [](GLFWwindow* w, int focused) {
        if (!focused) sinkOf(w).focusLost = true;
    });
    glfwSetWindowRefreshCallback(window, [](GLFWwindow* w) { sinkOf(w).resized = true; });
}

}  // namespace orbis::ui
