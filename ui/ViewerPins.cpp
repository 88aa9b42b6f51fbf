// The Viewer's clicks on the globe: while the panels' Annotations > Place pin is on, a left click
// drops a named annotation there and makes sure the scene has a layer that draws them; else a
// left click picks the feature under it (vector data): its attributes go to the Feature panel
// and the layer highlights it. Shift + left drag moves the observers of viewsheds.
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

void Viewer::featureClick(const MouseButtonEvent& event) {
    if (event.pressed) {
        pickPress_ = event.position;
    } else if (pickPress_ && glm::length(event.position - *pickPress_) <= kClickSlopPx) {
        pickFeature(event.position);
        pickPress_.reset();
    }
}

void Viewer::pickFeature(glm::dvec2 atPx) {
    const auto hit = groundAt(atPx);
    readout_.picked.reset();
    // Ground metres a window pixel spans there (the layers size their lines in pixels).
    const double metresPerPixel = hit ? hit->distance * scene_->camera().verticalFovRad() / std::max(windowHeight_, 1) : 0.0;
    auto& resources = scene_->resources();
    for (auto it = resources.rbegin(); it != resources.rend(); ++it) {   // the layer drawn last first
        scene::PickableContent* pickable = it->layer->asPickable();
        if (!pickable) continue;
        if (hit && it->visible && !readout_.picked) readout_.picked = pickable->pickAt(hit->geodetic.lonDeg, hit->geodetic.latDeg, metresPerPixel);
        else pickable->clearPick();
    }
    if (readout_.picked) readout_.message = "picked " + readout_.picked->layer + " " + readout_.picked->feature;
}

void Viewer::clearPicks() {
    readout_.picked.reset();
    for (auto& r : scene_->resources())
        if (auto* pickable = r.layer->asPickable()) pickable->clearPick();
    dirty_ = true;
}

void Viewer::sketchClick(const MouseButtonEvent& event) {
    if (event.pressed) {
        sketchPress_ = event.position;
        return;
    }
    if (!sketchPress_ || glm::length(event.position - *sketchPress_) > kClickSlopPx) return;
    sketchPress_.reset();
    const auto hit = groundAt(event.position);
    if (!hit) {
        readout_.message = "no ground there: the sketch needs a point on the globe";
        return;
    }
    panels_.measure().sketch().add(hit->geodetic);
    dirty_ = true;
}

bool Viewer::observerDrag(const MouseButtonEvent& event) {
    if (!event.pressed) {
        if (!draggingObserver_) return false;
        draggingObserver_ = false;
        return true;
    }
    if (!moveObservers(event.position)) return false;
    draggingObserver_ = true;
    return true;
}

bool Viewer::moveObservers(glm::dvec2 atPx) {
    std::vector<scene::LiveSettings*> observers;
    for (auto& r : scene_->resources()) {
        if (!r.visible) continue;
        scene::LiveSettings* live = r.layer->asLiveSettings();
        if (!live) continue;
        const auto settings = live->liveSettings();
        if (std::any_of(settings.begin(), settings.end(), [](const scene::LayerSetting& s) { return s.name == "observerLon"; }))
            observers.push_back(live);
    }
    if (observers.empty()) return false;
    const auto hit = groundAt(atPx);
    if (!hit) {
        readout_.message = "no ground there: the observer stays where it is";
        return true;
    }
    for (scene::LiveSettings* live : observers) {
        live->setParameter("observerLon", hit->geodetic.lonDeg);
        live->setParameter("observerLat", hit->geodetic.latDeg);
    }
    char text[120];
    std::snprintf(text, sizeof text, "observer at lon %.5f lat %.5f", hit->geodetic.lonDeg, hit->geodetic.latDeg);
    readout_.message = text;
    dirty_ = true;
    return true;
}

/// The ground under a window position, seen from the scene's camera.
std::optional<GroundPoint> Viewer::groundAt(glm::dvec2 atPx) const {
    const int w = std::max(windowWidth_, 1), h = std::max(windowHeight_, 1);
    const glm::dvec2 ndc(2.0 * atPx.x / w - 1.0, 2.0 * atPx.y / h - 1.0);
    return pick(scene_->camera().pose(), scene_->camera().verticalFovRad(), double(windowWidth_) / h, ndc, ground_);
}

}  // namespace orbis::ui
