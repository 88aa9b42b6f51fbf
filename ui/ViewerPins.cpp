// The Viewer's pins: while the panels' Annotations > Place pin is on, a left click on the globe
// drops a named annotation there and makes sure the scene has a layer that draws them.
#include "ui/Viewer.h"

#include <algorithm>
#include <cstdio>

namespace orbis::ui {
namespace {

/// A press and release further apart than this is a drag, not a click that places a pin.
constexpr double kClickSlopPx = 4.0;

}  // namespace

void Viewer::pinClick(const MouseButtonEvent& event) {
    if (event.pressed) {
        pinPress_ = event.position;
    } else if (pinPress_ && glm::length(event.position - *pinPress_) <= kClickSlopPx) {
        placePin(*panels_.placingPin(), event.position);
        pinPress_.reset();
    }
}

void Viewer::placePin(const std::string& name, glm::dvec2 atPx) {
    const auto hit = groundAt(atPx);
    if (!hit) {
        readout_.message = "no ground there: the pin needs a point on the globe";
        return;
    }
    scene::Annotation a;
    a.name = name.empty() ? "Pin " + std::to_string(scene_->annotations().size() + 1) : name;
    a.lonDeg = hit->geodetic.lonDeg;
    a.latDeg = hit->geodetic.latDeg;
    a.height = hit->geodetic.height;
    scene_->annotations().push_back(a);
    if (auto ok = scene_->ensureAnnotationLayer(registry_); !ok) {
        readout_.message = ok.message();
        printError(ok.message());
    } else {
        char text[160];
        std::snprintf(text, sizeof text, "placed \"%s\" at lon %.5f lat %.5f", a.name.c_str(), a.lonDeg, a.latDeg);
        readout_.message = text;
    }
    panels_.stopPlacingPin(true);
}

/// The ground under a window position, seen from the scene's camera.
std::optional<GroundPoint> Viewer::groundAt(glm::dvec2 atPx) const {
    const int w = std::max(windowWidth_, 1), h = std::max(windowHeight_, 1);
    const glm::dvec2 ndc(2.0 * atPx.x / w - 1.0, 2.0 * atPx.y / h - 1.0);
    return pick(scene_->camera().pose(), scene_->camera().verticalFovRad(), double(windowWidth_) / h, ndc, ground_);
}

}  // namespace orbis::ui
