#pragma once
// The viewer's input for one frame: events for the navigation (or ImGui) and the viewer's own
// shortcuts, as the window's GLFW callbacks collect them between frames. A script plays the
// same FrameInput (ScriptPlayer.h), so that both take one path through the viewer.

#include "ui/input/InputEvents.h"

#include <filesystem>
#include <variant>
#include <vector>

struct GLFWwindow;

namespace orbis::ui {

using InputEvent = std::variant<MouseButtonEvent, MouseMoveEvent, ScrollEvent, KeyEvent>;

/// One frame's input, from the window or a script.
struct FrameInput {
    std::vector<InputEvent> events;
    bool screenshot = false;     ///< F12
    bool saveScene = false;      ///< Ctrl+S
    bool togglePanels = false;   ///< F1
    bool escape = false;         ///< cancels placing a pin, else quits
    bool quit = false;           ///< a script's "quit"
    std::filesystem::path screenshotFile;   ///< a script's screenshot step; empty: a stamped name
};

/// What the GLFW callbacks collect between frames.
struct InputSink {
    FrameInput input;
    bool resized = false;
    bool focusLost = false;   ///< no key releases come while unfocused: forget held keys
};

/// Points the window's mouse, key, size and focus callbacks at `sink`, which must outlive the
/// window. Install before ImGui's, which chain to these. Main thread only.
void installInputCallbacks(GLFWwindow* window, InputSink& sink);

}  // namespace orbis::ui
