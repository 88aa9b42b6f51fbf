#include "ui/ScriptPlayer.h"

#include "base/Log.h"
#include "ui/Panels.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>

namespace orbis::ui {
namespace {

/// A settle step gives up (with a warning) after this long, so that a script always ends.
constexpr double kSettleTimeoutSeconds = 300.0;
/// A session keeps at most this many frame times for its summary.
constexpr size_t kMaxFrameTimes = 100000;

double processCpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

MouseButton buttonNamed(const std::string& name) {
    return name == "right" ? MouseButton::Right : name == "middle" ? MouseButton::Middle : MouseButton::Left;
}

}  // namespace

ScriptPlayer::ScriptPlayer(std::vector<ScriptStep> steps, std::filesystem::path file)
    : steps_(std::move(steps)), file_(std::move(file)) {}

Result<FrameInput> ScriptPlayer::play(const Panels& panels, const std::function<bool()>& settled) {
    const ScriptStep& step = steps_[index_];
    auto points = stepPoints(step, panels);
    if (!points) return points.error();
    FrameInput in;
    if (playStep(step, points->first, points->second, settled, in)) finishStep();
    else ++frame_;
    time_ += kFrameSeconds;
    return in;
}

/// Where a step acts, in window pixels: its own points, or on a panel item, fractions of the
/// item's rectangle (a drag) or its centre (a click).
Result<std::pair<glm::dvec2, glm::dvec2>> ScriptPlayer::stepPoints(const ScriptStep& step, const Panels& panels) const {
    glm::dvec2 from(step.from[0], step.from[1]), to(step.to[0], step.to[1]);
    if (step.item.empty()) return std::pair(from, to);
    const auto r = panels.itemRect(step.item);
    if (!r) return Error{file_.string() + ": the panels show no item \"" + step.item + "\""};
    if (step.kind == ScriptStep::Kind::Click) {
        from = {0.5 * ((*r)[0] + (*r)[2]), 0.5 * ((*r)[1] + (*r)[3])};
    } else {
        const glm::dvec2 lo((*r)[0], (*r)[1]), size((*r)[2] - (*r)[0], (*r)[3] - (*r)[1]);
        from = lo + from * size;
        to = lo + to * size;
    }
    return std::pair(from, to);
}

/// Plays one frame of `step`; true when the step is over.
bool ScriptPlayer::playStep(const ScriptStep& step, glm::dvec2 from, glm::dvec2 to, const std::function<bool()>& settled,
                            FrameInput& in) {
    using Kind = ScriptStep::Kind;
    switch (step.kind) {
        case Kind::Drag: return playDrag(step, from, to, in);
        case Kind::Key: return playKey(step, in);
        case Kind::Settle: return playSettle(settled);
        case Kind::Scroll:
            if (frame_ == 0) moveTo(in, from);
            else in.events.push_back(ScrollEvent{0.0, step.lines});
            return frame_ > 0;
        case Kind::DoubleClick:
            if (frame_ == 0) {
                moveTo(in, from);
                return false;
            }
            for (int i = 0; i < 2; ++i) {
                press(in, MouseButton::Left, true, from);
                press(in, MouseButton::Left, false, from);
            }
            return true;
        case Kind::Click:   // down on one frame, up on the next, as ImGui needs to see a click
            if (frame_ == 0) moveTo(in, from);
            else press(in, MouseButton::Left, frame_ == 1, from);
            return frame_ >= 2;
        case Kind::Screenshot:
            in.screenshot = true;
            in.screenshotFile = step.file;
            return true;
        case Kind::Quit: in.quit = true; return true;
        case Kind::Idle: return true;
    }
    return true;
}

bool ScriptPlayer::playDrag(const ScriptStep& step, glm::dvec2 from, glm::dvec2 to, FrameInput& in) {
    const MouseButton b = buttonNamed(step.button);
    const int f = frame_;
    if (f == 0) moveTo(in, from);
    else if (f == 1) press(in, b, true, from, step.shift);
    else if (f <= step.frames + 1) moveTo(in, from + (to - from) * (double(f - 1) / step.frames));
    else press(in, b, false, to, step.shift);
    return f > step.frames + 1;
}

bool ScriptPlayer::playKey(const ScriptStep& step, FrameInput& in) {
    if (step.key == "F12") in.screenshot = true;
    else if (step.key == "Ctrl+S") {   // as GLFW gives it: the shortcut, and S pressed and let go with Ctrl
        in.saveScene = true;
        in.events.push_back(KeyEvent{Key::S, true, {.ctrl = true}});
        in.events.push_back(KeyEvent{Key::S, false, {.ctrl = true}});
    }
    else if (step.key == "F1") in.togglePanels = true;
    else if (step.key == "Escape") in.escape = true;
    else if (auto k = navigationKey(step.key)) {
        if (frame_ == 0) in.events.push_back(KeyEvent{*k, true, {}});
        if (frame_ + 1 >= step.frames) in.events.push_back(KeyEvent{*k, false, {}});
        return frame_ + 1 >= step.frames;
    }
    return true;
}

bool ScriptPlayer::playSettle(const std::function<bool()>& settled) {
    if (frame_ == 0) settleStart_ = Clock::now();
    bool finished = frame_ >= 2 && settled();
    if (!finished && Clock::now() - settleStart_ > std::chrono::seconds(int(kSettleTimeoutSeconds))) {
        log::warn("script: still loading after ", kSettleTimeoutSeconds, " s");
        finished = true;
    }
    return finished;
}

void ScriptPlayer::press(FrameInput& in, MouseButton button, bool down, glm::dvec2 at, bool shift) {
    MouseButtonEvent e;
    e.button = button;
    e.pressed = down;
    e.position = at;
    e.modifiers.shift = shift;
    e.timeSeconds = time_;
    in.events.push_back(e);
    buttons_[int(button)] = down;
}

void ScriptPlayer::moveTo(FrameInput& in, glm::dvec2 at) {
    mouse_ = at;
    in.events.push_back(MouseMoveEvent{at});
}

void ScriptPlayer::finishStep() {
    ++index_;
    frame_ = 0;
}

void ScriptPlayer::idle() {
    const ScriptStep& step = steps_[index_];
    if (frame_ == 0) {
        idleUntil_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(step.seconds));
        idleCpuStart_ = processCpuSeconds();
        ++frame_;
    } else if (Clock::now() >= idleUntil_) {
        const double cpu = processCpuSeconds() - idleCpuStart_;
        std::printf("idle: %.3f s of CPU over %.1f s (%.1f %% of one core)\n", cpu, step.seconds, 100.0 * cpu / step.seconds);
        std::fflush(stdout);
        finishStep();
    }
}

Gui::MouseOverride ScriptPlayer::mouse() const {
    Gui::MouseOverride m{float(mouse_.x), float(mouse_.y)};
    for (int b = 0; b < 3; ++b) m.buttons[b] = buttons_[b];
    return m;
}

void ScriptPlayer::recordFrameMs(double ms) {
    if (frameMs_.size() < kMaxFrameTimes) frameMs_.push_back(ms);
}

void ScriptPlayer::printFrameTimes(uint64_t framesDrawn, uint32_t width, uint32_t height, const std::string& device) {
    if (frameMs_.empty()) return;
    std::sort(frameMs_.begin(), frameMs_.end());
    std::printf("frames: %llu drawn, %ux%u, frame ms median %.1f, p95 %.1f (%s)\n",
                static_cast<unsigned long long>(framesDrawn), width, height, frameMs_[frameMs_.size() / 2],
                frameMs_[frameMs_.size() * 95 / 100], device.c_str());
}

}  // namespace orbis::ui
