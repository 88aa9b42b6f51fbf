#pragma once
// The viewer's Processes panel: a processing server (OGC WPS 1.0.0) picked or typed, its
// processes listed, a form built from the chosen one's description (formats/wps/WpsForm.h:
// numbers with their ranges, allowed values as combos, toggles, text, areas and shapes bound
// to the drawing tools of the Measure panel, files), Run, and a job list with progress bars,
// the server's messages, Stop (the wait ends; WPS 1.0.0 has no dismiss) and the outputs: a
// raster becomes an overlay layer, vectors a vector layer (both added to the scene and saved
// with it, with the job's server, process, inputs and the output's reference as the layer's
// "provenance"), a table a plot, literals text. Requests run on threads of their own (one per
// request or job, none until the user asks). Main thread only, between Gui::newFrame() and
// Gui::record().

#include "engine/scene/SceneDesc.h"
#include "formats/wps/WpsForm.h"
#include "formats/wps/WpsJob.h"
#include "ui/MeasurePanel.h"

#include <chrono>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::ui {

class ProcessesPanel {
public:
    ProcessesPanel();
    ~ProcessesPanel();

    /// The servers offered (the first is typed in); `resultsFolder` receives each job's outputs
    /// in a folder of its own (default: the user's cache, orbis/wps).
    void setUp(std::vector<std::string> servers, std::filesystem::path resultsFolder);
    /// A request or a job is under way (the viewer keeps drawing; scripts' "settle" waits).
    bool busy() const;

    /// Every frame, shown or not: answers that arrived; layers for the results of jobs that
    /// ended go to `addLayers`; `changed` is set while something moves (a job's progress).
    void update(std::vector<scene::LayerDesc>& addLayers, bool& changed);
    /// The panel's contents (in the Analysis window).
    /// The scene's layers' files are offered for file inputs (a layer's data sent to the server).
    void draw(const Sketch& sketch, const scene::SceneDesc& scene, const RememberItem& remember);
    /// The tables' plot windows.
    void drawPlots();
    /// Servers were given (the panel starts open).
    bool hasServers() const { return !servers_.empty(); }

    /// Jobs so far, oldest first (tests).
    size_t jobCount() const { return jobs_.size(); }
    /// When the user pressed Run for the last job whose results became layers.
    std::optional<std::chrono::steady_clock::time_point> lastResultRequested() const { return lastResultRequested_; }

private:
    struct Job {
        std::unique_ptr<wps::WpsJob> job;
        std::chrono::steady_clock::time_point started;
        bool collected = false;   ///< its outputs were turned into layers
        std::vector<std::string> layers;
        std::optional<wps::Table> table;
        std::string tableError;
        bool showTable = false;
    };
    void serverSection(const RememberItem& remember);
    void formSection(const Sketch& sketch, const scene::SceneDesc& scene, const RememberItem& remember);
    void jobsSection(const RememberItem& remember);
    void collect(Job& job, std::vector<scene::LayerDesc>& addLayers);
    void poll();

    std::vector<std::string> servers_;
    char url_[1024] = {};
    std::filesystem::path resultsFolder_;
    std::string connectedUrl_;
    std::future<Result<wps::Capabilities>> connecting_;
    std::optional<wps::Capabilities> capabilities_;
    std::future<Result<wps::ProcessDescription>> describing_;
    std::chrono::steady_clock::time_point describeAsked_;
    std::optional<wps::ProcessDescription> process_;
    std::vector<wps::FormField> form_;
    uint64_t boundRevision_ = ~0ull;
    bool synchronous_ = false;   ///< Run waits on the request instead of a stored job
    std::string error_;
    std::vector<Job> jobs_;
    std::optional<std::chrono::steady_clock::time_point> lastResultRequested_;
};

}  // namespace orbis::ui
