#pragma once
// `orbis view SCENE`: the desktop viewer. A GLFW window with a Vulkan swapchain, the same
// frame as the headless renderer plus the ImGui panels, the earth manipulator on the mouse and
// keyboard, and rendering on demand: when nothing moves, plays or loads, the viewer sleeps in
// the event wait instead of drawing. Main thread only.
//
// The Viewer's members are spread over files by what they do: Viewer.cpp opens and runs it
// (the frame's steps), ViewerInput.cpp routes the frame's input, ViewerPins.cpp places pins,
// ViewerDraw.cpp draws and presents, ViewerFiles.cpp writes scenes and screenshots.

#include "base/Result.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Instance.h"
#include "engine/render/Renderer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/Scene.h"
#include "engine/scene/SceneDesc.h"
#include "ui/Gui.h"
#include "ui/InputSink.h"
#include "ui/Panels.h"
#include "ui/ScriptPlayer.h"
#include "ui/Swapchain.h"
#include "ui/Window.h"
#include "ui/input/MapTools.h"
#include "ui/input/NavigationController.h"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

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
    std::vector<std::string> wpsServers;    ///< offered in the Processes panel (the first filled in)
    std::filesystem::path resultsFolder;    ///< processing results; default the user's cache
};

/// Runs the viewer until its window closes (or the script quits). Returns a process exit code:
/// 0, or 1 with a message on stderr for a bad scene, script, display or device (and, with
/// validation on, when the layer reported anything).
int runViewer(const ViewerOptions& options);

/// The viewer's window, device, scene and panels, and its frame loop. Main thread only.
class Viewer {
public:
    /// Opens the window and a device that presents to it. Throws std::runtime_error (no
    /// display) or gpu::GpuError (no device).
    Viewer(const ViewerOptions& options, const std::string& title, std::optional<ScriptPlayer> script);
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    /// Builds the scene and what draws it. A layer that fails to load shows its error in the
    /// panels and the others load; an error only when the scene as a whole cannot be built.
    Result<void> load(scene::SceneDesc desc);

    /// Runs until the window closes, Escape or the panels' Quit, the script quits, or SIGINT /
    /// SIGTERM (handled as a closed window). Returns the exit code: 0, or 1 after a message on
    /// stderr (a script's file not written, a panel item it names not shown, validation
    /// messages), or kDeviceLostExit when the GPU device was lost (the view is saved first,
    /// where Ctrl+S saves it). Call after load() succeeded.
    int run();

    /// The exit code after the GPU device was lost.
    static constexpr int kDeviceLostExit = 3;

    /// "orbis: MESSAGE" on stderr, as every command reports a problem.
    static void printError(const std::string& message);

private:
    using Clock = std::chrono::steady_clock;

    /// What this frame must write besides the picture.
    struct FrameRequests {
        bool screenshot = false;
        bool saveScene = false;
        std::filesystem::path screenshotFile;   ///< empty: a stamped name in the screenshot folder
    };

    // The frame's steps (Viewer.cpp). runFrame() is false when the session must end with 1.
    bool runFrame();
    bool wantsFrame(bool playingScript) const;
    void advance();
    void updateReadout();
    void drawPanels(FrameRequests& requests);
    int finish();
    /// The GPU device is gone: says so, saves the view where Ctrl+S saves it, returns
    /// kDeviceLostExit. Nothing here touches the device.
    int deviceLost(const std::string& what);
    void setUpPanels();
    void setUpNavigation();

    // Input (ViewerInput.cpp).
    FrameInput takeWindowInput();
    void applyShortcuts(const FrameInput& input, FrameRequests& requests);
    void dispatch(const std::vector<InputEvent>& events);
    void route(const MouseButtonEvent& event);
    void route(const MouseMoveEvent& event);
    void route(const ScrollEvent& event);
    void route(const KeyEvent& event);
    void takeCameraBack();

    // Pins (ViewerPins.cpp).
    void pinClick(const MouseButtonEvent& event);
    void placePin(const std::string& name, glm::dvec2 atPx);
    std::optional<GroundPoint> groundAt(glm::dvec2 atPx) const;

    // Clicking features (ViewerPins.cpp): the feature under a click, its attributes in the
    // Feature panel and the feature highlighted; a click on nothing clears them.
    void featureClick(const MouseButtonEvent& event);
    // Shift + left drag (ViewerPins.cpp): the observer of every shown layer that has one (a
    // viewshed: live settings observerLon and observerLat) follows the ground under the pointer.
    // False when no shown layer has an observer: the press goes on to the camera.
    bool observerDrag(const MouseButtonEvent& event);
    bool moveObservers(glm::dvec2 atPx);
    // A click (not a drag) on the ground while a Measure tool is chosen adds a point to the
    // sketch (ViewerPins.cpp); drags still move the camera.
    void sketchClick(const MouseButtonEvent& event);
    /// A request, job or analysis of the panels is under way.
    bool analysisBusy() const;
    /// Processing results into the scene (PanelActions::addLayers).
    void addLayers(std::vector<scene::LayerDesc> layers);
    void pickFeature(glm::dvec2 atPx);
    void clearPicks();

    // Drawing and presenting (ViewerDraw.cpp).
    std::optional<render::FrameResult> drawFrame(bool readback);
    render::FrameHooks presentHooks(const Swapchain::Acquired& acquired);
    void recordFrameStats(const render::FrameResult& frame, Clock::time_point frameStart);

    // Files the user asks for (ViewerFiles.cpp): false when writing failed (message shown).
    bool saveScene();
    bool writeScreenshot(const render::FrameResult& frame, std::filesystem::path file);
    bool reportWritten(const Result<void>& written, const std::filesystem::path& file);

    // Declared in the order they are made; destroyed in reverse (the device outlives what it made).
    ViewerOptions options_;
    std::optional<ScriptPlayer> script_;
    gpu::Instance instance_;
    Window window_;
    InputSink sink_;
    VkSurfaceKHR surface_;   ///< the window's
    gpu::Device device_;
    scene::LayerRegistry registry_;
    std::unique_ptr<scene::Scene> scene_;
    std::unique_ptr<render::Renderer> renderer_;
    std::unique_ptr<Gui> gui_;
    std::unique_ptr<Swapchain> swapchain_;
    Panels panels_;
    NavigationController nav_;
    HeightQuery ground_;
    float uiScale_ = 1.0f;

    // The loop's state.
    int windowWidth_ = 0, windowHeight_ = 0;     ///< screen coordinates
    uint32_t fbWidth_ = 0, fbHeight_ = 0;        ///< pixels
    MapReadout readout_;
    ViewerStats stats_;
    std::optional<glm::dvec2> pinPress_;         ///< the press of the click that places a pin
    std::optional<glm::dvec2> pickPress_;        ///< the press of a click that may pick a feature
    std::optional<glm::dvec2> sketchPress_;      ///< the press of a click that may add a sketch point
    bool draggingObserver_ = false;              ///< a Shift + left drag is moving an observer
    std::optional<render::FrameResult> previous_;   ///< its GPU times arrive a frame later
    /// Run was pressed then for results now added as layers, not yet all on screen.
    std::optional<Clock::time_point> resultRequested_;
    uint64_t framesAtResult_ = 0;   ///< stats_.framesDrawn when the result's layer was added
    uint64_t drawnRevision_ = ~0ull;             ///< the navigation's revision last drawn
    int uiFrames_ = 2;                           ///< frames ImGui still needs after input
    bool dirty_ = true;
    bool quit_ = false;
    Clock::time_point last_{};
};

}  // namespace orbis::ui
