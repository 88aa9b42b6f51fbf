#pragma once
// Input events as the viewer's window layer hands them to the navigation controller: plain
// structs with no window library behind them, so that bindings are unit-testable. The window
// layer translates its callbacks (GLFW) into these and drops what Dear ImGui wants for itself.
//
// Positions are in window pixels, x right, y down, origin at the top-left corner, in the same
// units as the viewport size (on HiDPI screens: GLFW's window coordinates for both, not
// framebuffer pixels). Double clicks are derived by the controller from two left presses (see
// NavigationController), so there is no double-click event: each press carries its time.

#include <glm/glm.hpp>

#include <cmath>
#include <optional>

namespace orbis::ui {

enum class MouseButton { Left, Right, Middle };

struct Modifiers {
    bool shift = false;
    bool ctrl = false;
    bool alt = false;
};

struct MouseButtonEvent {
    MouseButton button = MouseButton::Left;
    bool pressed = true;                ///< false: released
    glm::dvec2 position{0.0};           ///< window pixels
    Modifiers modifiers;
    double timeSeconds = 0.0;           ///< any monotonic clock (glfwGetTime); for double clicks
};

struct MouseMoveEvent {
    glm::dvec2 position{0.0};           ///< window pixels
};

/// Wheel or trackpad scroll, in "lines" (one wheel notch = 1); positive y scrolls up/away.
struct ScrollEvent {
    double x = 0.0;                     ///< horizontal: not bound
    double y = 0.0;
};

/// The keys the controller binds; the window layer maps its key codes to these and drops the
/// rest. Auto-repeat needs no event: a key counts as held from press to release.
enum class Key { W, A, S, D, Q, E, R, F, Up, Down, Left, Right, PageUp, PageDown, Home };
inline constexpr int kKeyCount = static_cast<int>(Key::Home) + 1;

struct KeyEvent {
    Key key = Key::W;
    bool pressed = true;                ///< false: released
    Modifiers modifiers;                ///< a press with Ctrl or Alt is a shortcut, not a move
};

/// The size of the view in window pixels (a resize, or the first size of the window).
struct ViewportSize {
    double width = 0.0;
    double height = 0.0;

    bool valid() const { return std::isfinite(width) && std::isfinite(height) && width >= 1.0 && height >= 1.0; }
    double aspect() const { return width / height; }
};

/// Normalised device coordinates of a window position (x right, y down, -1..1 across the
/// viewport, as globe::EarthManipulator takes them); nothing for an empty viewport or a
/// position that is not finite.
inline std::optional<glm::dvec2> toNdc(const glm::dvec2& windowPx, const ViewportSize& viewport) {
    if (!viewport.valid() || !std::isfinite(windowPx.x) || !std::isfinite(windowPx.y)) return std::nullopt;
    return glm::dvec2(2.0 * windowPx.x / viewport.width - 1.0, 2.0 * windowPx.y / viewport.height - 1.0);
}

}  // namespace orbis::ui
