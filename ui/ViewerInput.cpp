// The Viewer's input: the window's events and shortcuts, then where each event goes (ImGui,
// placing a pin, or the navigation).
#include "ui/Viewer.h"

#include <utility>

namespace orbis::ui {

/// This frame's input from the window, after a resize or a lost focus has been dealt with.
FrameInput Viewer::takeWindowInput() {
    FrameInput input = std::exchange(sink_.input, FrameInput{});
    if (std::exchange(sink_.resized, false)) {
        dirty_ = true;
        window_.size(windowWidth_, windowHeight_);
        nav_.handle(ViewportSize{double(windowWidth_), double(windowHeight_)});
    }
    if (std::exchange(sink_.focusLost, false)) nav_.releaseAll();
    return input;
}

/// The viewer's shortcuts, pressed on the keyboard or by a script.
void Viewer::applyShortcuts(const FrameInput& input, FrameRequests& requests) {
    requests.screenshot = requests.screenshot || input.screenshot;
    requests.saveScene = requests.saveScene || input.saveScene;
    if (!input.screenshotFile.empty()) requests.screenshotFile = input.screenshotFile;
    if (input.escape) {
        if (panels_.placingPin()) {
            panels_.stopPlacingPin(false);
            dirty_ = true;
        } else {
            quit_ = true;
        }
    }
    if (input.togglePanels) {
        panels_.toggleVisible();
        dirty_ = true;
    }
    if (input.quit) quit_ = true;
}

void Viewer::dispatch(const std::vector<InputEvent>& events) {
    for (const InputEvent& e : events) {
        dirty_ = true;
        uiFrames_ = 2;
        std::visit([this](const auto& event) { route(event); }, e);
    }
}

// Events go to the navigation unless ImGui has them; releases always pass, so that drags end.
void Viewer::route(const MouseButtonEvent& event) {
    if (event.pressed && gui_->wantsMouse()) return;
    if (event.button == MouseButton::Left && panels_.placingPin()) {   // the click places a pin instead
        pinClick(event);
        return;
    }
    if (event.button == MouseButton::Left && (event.modifiers.shift || draggingObserver_) && observerDrag(event)) return;
    if (event.button == MouseButton::Left && panels_.measure().drawing()) sketchClick(event);   // a click draws
    else if (event.button == MouseButton::Left) featureClick(event);   // a click (not a drag) picks
    takeCameraBack();
    nav_.handle(event);
}

void Viewer::route(const MouseMoveEvent& event) {
    if (draggingObserver_) {
        moveObservers(event.position);
        return;
    }
    nav_.handle(event);
}

void Viewer::route(const ScrollEvent& event) {
    if (gui_->wantsMouse()) return;
    takeCameraBack();
    nav_.handle(event);
}

void Viewer::route(const KeyEvent& event) {
    if (event.pressed && gui_->wantsKeyboard()) return;
    // A shortcut (a press with Ctrl or Alt: Ctrl+S saving the scene) or a key let go does not
    // move the camera: it stays with its mode (a sensor's view is saved as such).
    if (event.pressed && !event.modifiers.ctrl && !event.modifiers.alt) takeCameraBack();
    nav_.handle(event);
}

/// The user takes the camera from a mode that was moving it (following a track, a path).
void Viewer::takeCameraBack() {
    if (scene_->cameraMode().mode == scene::CameraMode::Free) return;
    nav_.setPose(scene_->camera().pose());
    scene_->setCameraMode(scene::CameraModeSettings{});
}

}  // namespace orbis::ui
