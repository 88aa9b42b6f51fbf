#pragma once
// The viewer's ImGui panels: resources (visibility, fly to, progress and errors), each layer's
// live settings (drawn generically from Layer::liveSettings(), so a new layer kind brings its
// own section without touching this file), the media player of the TimeServer, frame and
// memory statistics, and the status line. The panels change the scene directly and report
// the actions that the viewer carries out (screenshot, save, fly to). Main thread only, between
// Gui::newFrame() and Gui::record().

#include "engine/gpu/GpuTimer.h"
#include "engine/scene/SceneDesc.h"
#include "engine/scene/LayerCapabilities.h"
#include "globe/Viewpoint.h"
#include "ui/MeasurePanel.h"
#include "ui/ProcessesPanel.h"

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace orbis::scene {
class Scene;
}

namespace orbis::ui {

/// What the panels ask the viewer to do this frame.
struct PanelActions {
    bool screenshot = false;
    bool saveScene = false;   ///< to savePath()
    bool home = false;
    bool quit = false;
    bool changed = false;   ///< a setting, visibility or the time changed: draw a new frame
    bool clearPick = false;   ///< the Feature panel was closed: end the highlight
    std::optional<globe::Viewpoint> flyTo;
    /// Layers to add to the scene (processing results), in order.
    std::vector<scene::LayerDesc> addLayers;
};

/// Figures the viewer measures and the panels show.
struct ViewerStats {
    double frameMs = 0.0;   ///< wall time of the last drawn frame
    double cpuMs = 0.0;     ///< update + record + submit
    std::vector<gpu::PassTime> gpu;   ///< per pass, of the last frame whose times arrived
    uint64_t framesDrawn = 0;
    bool vsync = true;
    std::string device;
};

/// Cursor read-outs for the status line and the map furniture.
struct MapReadout {
    std::optional<double> lonDeg, latDeg, heightM;   ///< ground under the cursor
    double headingDeg = 0.0;                          ///< of the view, 0 = north up
    double scaleBarMetres = 0.0;                      ///< 0: no scale bar
    double scaleBarPixels = 0.0;
    double eyeHeightM = 0.0;
    std::string message;                              ///< last screenshot / save, or an error
    /// The feature the last click picked (vector data), shown in the Feature panel.
    std::optional<scene::PickedAttributes> picked;
};

class Panels {
public:
    /// Builds this frame's windows (none while hidden). `uiScale` is the HiDPI content scale.
    PanelActions draw(scene::Scene& scene, const ViewerStats& stats, const MapReadout& map, float uiScale);
    bool visible() const { return visible_; }
    /// Where "Save scene" writes (editable in File > Save scene as...).
    void setSavePath(const std::string& path);
    std::string savePath() const { return savePath_; }
    void toggleVisible() { visible_ = !visible_; }

    /// The name for the pin the next click on the globe places, while the user is placing one
    /// (Annotations > Place pin); nothing otherwise.
    std::optional<std::string> placingPin() const;
    /// Ends the placing: `placed` after a pin was placed (the next one gets a new default
    /// name), else cancelled (Escape).
    void stopPlacingPin(bool placed) {
        placing_ = false;
        if (placed) pinName_[0] = '\0';
    }

    /// The Measure panel (drawing tools, measures, profile, line of sight) and the Processes
    /// panel (WPS servers, forms, jobs); built on first use of their windows' contents.
    MeasurePanel& measure() { return measure_; }
    const MeasurePanel& measure() const { return measure_; }
    ProcessesPanel& processes() { return processes_; }
    const ProcessesPanel& processes() const { return processes_; }

    /// Where ImGui drew the item with this label in the last frame, in window pixels: its
    /// rectangle (min x, min y, max x, max y). Scripted input clicks and drags there
    /// ("Visible##Terrain", "opacity##Plume" for a curve editor).
    std::optional<std::array<float, 4>> itemRect(const std::string& label) const;

private:
    void resourcesPanel(scene::Scene& scene, PanelActions& actions);
    void timePanel(scene::Scene& scene, PanelActions& actions);
    void statsPanel(const ViewerStats& stats, const scene::Scene& scene);
    /// Live video feeds (only when the scene has any): state, bitrate, latency, loss; fly to
    /// the sensor, look through it.
    void feedsPanel(scene::Scene& scene, PanelActions& actions);
    void annotationsPanel(scene::Scene& scene, PanelActions& actions);
    void featurePanel(const scene::PickedAttributes& picked, PanelActions& actions);
    void analysisPanel(scene::Scene& scene, PanelActions& actions);
    void mapFurniture(const MapReadout& map, float uiScale);
    void remember(const std::string& label);

    bool visible_ = true;
    char savePath_[1024] = {};
    std::string feedMessage_;   // the Feeds panel's last recording started or stopped, or why not
    bool openSaveAs_ = false;
    bool placing_ = false;
    char pinName_[128] = {};
    std::deque<float> history_;   ///< frame ms, newest last
    struct Item {
        std::string label;
        std::array<float, 4> rect;
    };
    std::vector<Item> items_;
    MeasurePanel measure_;
    ProcessesPanel processes_;
};

}  // namespace orbis::ui
