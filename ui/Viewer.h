#pragma once
// `orbis view SCENE`: the desktop viewer. A GLFW window with a Vulkan swapchain, the same
// frame as the headless renderer plus the ImGui panels, the earth manipulator on the mouse and
// keyboard, and rendering on demand: when nothing moves, plays or loads, the viewer sleeps in
// the event wait instead of drawing. Main thread only.

#include <cstdint>
#include <filesystem>
#include <string>

namespace orbis::ui {

struct ViewerOptions {
    std::filesystem::path scene;
    uint32_t width = 1280, height = 720;   ///< window size, screen coordinates
    bool vsync = true;
    std::string device;                     ///< gpu::DeviceOptions::select
    bool validation = false;
    std::filesystem::path script;           ///< InputScript.h; empty: interactive
    std::filesystem::path screenshotFolder = ".";
    std::filesystem::path saveTo;           ///< "Save scene" (Ctrl+S); default SCENE-view.json beside it
    bool panels = true;
};

/// Runs the viewer until its window closes (or the script quits). Returns a process exit code:
/// 0, or 1 with a message on stderr for a bad scene, script, display or device (and, with
/// validation on, when the layer reported anything).
int runViewer(const ViewerOptions& options);

}  // namespace orbis::ui
