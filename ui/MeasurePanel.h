#pragma once
// The viewer's Measure panel and what it draws over the globe: the drawing tools (point, path,
// polygon, box, line of sight; ui/input/Sketch.h) picked in the panel and drawn by left clicks
// on the ground, their geodesic lengths and areas labelled on the globe, the terrain profile
// along a path as a plot, and a line of sight between two points drawn green up to where the
// ground blocks it and red past it. Profiles and sight lines read the finest data of the
// scene's DEM (the first terrain layer's first elevation source, through ElevationSampler), not
// the tiles the view has streamed; they are computed on a thread of their own, started only
// when one is asked for. The Processes panel takes its geometry inputs from the same sketch.
// Main thread only, between Gui::newFrame() and Gui::record().

#include "globe/TerrainAnalysis.h"
#include "ui/input/Sketch.h"

#include <glm/glm.hpp>

#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>

namespace orbis::scene {
class Scene;
}

namespace orbis::ui {

/// Window pixels of a place (lon, lat, height above the ellipsoid); nothing when not seen.
using Projector = std::function<std::optional<glm::dvec2>(const globe::Geodetic&)>;
/// Notes the last ImGui item under a label for scripted input.
using RememberItem = std::function<void(const std::string&)>;

class MeasurePanel {
public:
    MeasurePanel();
    ~MeasurePanel();

    Sketch& sketch() { return sketch_; }
    const Sketch& sketch() const { return sketch_; }
    /// A tool is chosen: left clicks on the globe go to the sketch.
    bool drawing() const { return sketch_.tool() != SketchTool::None; }
    /// A profile or a sight line is being computed.
    bool busy() const;

    /// The panel's contents (in the Analysis window); `changed` is set when the sketch changed
    /// (the picture needs drawing again).
    void draw(const scene::Scene& scene, const RememberItem& remember, bool& changed);
    /// The sketch, its labels and the sight line over the picture (ImGui's background list).
    /// `groundAt` gives the ground's height along the lines.
    void drawOverlay(const Projector& project, const std::function<std::optional<double>(double, double)>& groundAt) const;

    /// The last profile and line of sight computed (tests, the status line).
    const std::optional<globe::TerrainProfile>& profile() const { return profile_; }
    const std::optional<globe::LineOfSight>& sight() const { return sight_; }

private:
    void startAnalysis(const scene::Scene& scene);
    void collect();

    Sketch sketch_;
    double eyeHeight_ = 2.0, targetHeight_ = 0.0;
    uint64_t analysedRevision_ = ~0ull;
    std::string demSource_;   ///< "" none found in the scene
    globe::HeightAt dem_;     ///< opened by the first analysis, kept for the next
    struct Answer {
        globe::HeightAt dem;
        std::optional<globe::TerrainProfile> profile;
        std::optional<globe::LineOfSight> sight;
        globe::Geodetic from, to;   ///< the sight's ends, at the DEM's heights plus the eye and target
        std::string error;
    };
    std::future<Answer> running_;
    std::optional<globe::TerrainProfile> profile_;
    std::optional<globe::LineOfSight> sight_;
    globe::Geodetic sightFrom_{}, sightTo_{};
    std::string analysisError_;
};

}  // namespace orbis::ui
