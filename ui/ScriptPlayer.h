#pragma once
// Plays an input script (InputScript.h) into the viewer: each frame, the current step's input
// as the same FrameInput the window produces, and the mouse that ImGui should see. Pointer
// steps move the mouse on their first frame and act from the next, as a hand does: ImGui
// decides whether it owns the mouse from where it was the frame before. Idle steps sleep as a
// user would and report the CPU used; a scripted session reports its frame times at the end.
// Main thread only.

#include "base/Result.h"
#include "ui/Gui.h"
#include "ui/InputScript.h"
#include "ui/InputSink.h"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace orbis::ui {

class Panels;

class ScriptPlayer {
public:
    /// A fixed frame time while a script plays: the same script gives the same pictures.
    static constexpr double kFrameSeconds = 1.0 / 30.0;

    /// `file` is the script's, for messages.
    ScriptPlayer(std::vector<ScriptStep> steps, std::filesystem::path file);

    bool done() const { return index_ >= steps_.size(); }
    /// The current step is an idle one: the viewer sleeps, and draws only what it must.
    bool idling() const { return !done() && steps_[index_].kind == ScriptStep::Kind::Idle; }
    /// A step other than idle is playing: it owns the input, one frame at a time.
    bool playing() const { return !done() && !idling(); }

    /// This frame of the current step (not an idle one); the script moves on when the step is
    /// over. `panels` has the rectangles of the items a step names; `settled` says that nothing
    /// loads or moves (a settle step waits for it). An error names the script and an item that
    /// the panels do not show.
    Result<FrameInput> play(const Panels& panels, const std::function<bool()>& settled);
    /// This frame of the current idle step: the first starts the clock and the CPU count; the
    /// first after the step's seconds prints the CPU used and ends the step.
    void idle();

    /// The mouse as the script has moved and pressed it.
    Gui::MouseOverride mouse() const;

    /// A drawn frame's wall time, for printFrameTimes().
    void recordFrameMs(double ms);
    /// "frames: N drawn, WxH, frame ms median M, p95 P (DEVICE)" on stdout, when any were drawn.
    void printFrameTimes(uint64_t framesDrawn, uint32_t width, uint32_t height, const std::string& device);

private:
    using Clock = std::chrono::steady_clock;

    Result<std::pair<glm::dvec2, glm::dvec2>> stepPoints(const ScriptStep& step, const Panels& panels) const;
    bool playStep(const ScriptStep& step, glm::dvec2 from, glm::dvec2 to, const std::function<bool()>& settled,
                  FrameInput& in);
    bool playDrag(const ScriptStep& step, glm::dvec2 from, glm::dvec2 to, FrameInput& in);
    bool playKey(const ScriptStep& step, FrameInput& in);
    bool playSettle(const std::function<bool()>& settled);
    void press(FrameInput& in, MouseButton button, bool down, glm::dvec2 at, bool shift = false);
    void moveTo(FrameInput& in, glm::dvec2 at);
    void finishStep();

    std::vector<ScriptStep> steps_;
    std::filesystem::path file_;
    size_t index_ = 0;
    int frame_ = 0;                 ///< frames the current step has played
    double time_ = 1000.0;          ///< press times for double clicks, on the script's own clock
    glm::dvec2 mouse_{0.0};
    bool buttons_[3] = {false, false, false};
    Clock::time_point settleStart_{}, idleUntil_{};
    double idleCpuStart_ = 0.0;
    std::vector<double> frameMs_;
};

}  // namespace orbis::ui
