#include "ui/input/NavigationController.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace orbis::ui {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The keyboard speed never drops below that of this height, so that it still moves with a
// clearance of zero.
constexpr double kMinSpeedHeight = 1.0;
// A burst of scroll lines (a flung trackpad) zooms at most this many notches at once.
constexpr double kMaxScrollLines = 10.0;
// A resting camera is lifted only when it is this far under its floor: rounding through ECEF
// must not move it (and wake the viewer) every frame.
constexpr double kLiftToleranceMetres = 1e-6;

bool finite(const glm::dvec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }

bool samePose(const globe::Pose& a, const globe::Pose& b) {
    return a.position == b.position && a.orientation == b.orientation;
}

}  // namespace

NavigationController::NavigationController(const globe::Ellipsoid& ellipsoid)
    : ellipsoid_(&ellipsoid), manipulator_(ellipsoid) {
    home_ = manipulator_.viewpoint();
}

void NavigationController::setHeightQuery(HeightQuery query) {
    heightQuery_ = query;
    manipulator_.setHeightQuery(std::move(query));
}

void NavigationController::setFovYRad(double fovYRad) {
    if (fovYRad > 0.0 && fovYRad < kPi) manipulator_.setFovYRad(fovYRad);
}

void NavigationController::setMinClearance(double metres) {
    if (metres >= 0.0 && std::isfinite(metres)) manipulator_.setMinClearance(metres);
}

double NavigationController::groundHeight(double lonDeg, double latDeg) const {
    if (!heightQuery_) return 0.0;
    const std::optional<double> h = heightQuery_(lonDeg, latDeg);
    return h && std::isfinite(*h) ? *h : 0.0;
}

void NavigationController::noteChange(const globe::Pose& before) {
    if (!samePose(before, pose())) ++revision_;
}

void NavigationController::setPose(const globe::Pose& pose) {
    const globe::Pose before = this->pose();
    manipulator_.setPose(pose);
    noteChange(before);
}

void NavigationController::setViewpoint(const globe::Viewpoint& vp) {
    const globe::Pose before = pose();
    manipulator_.setViewpoint(vp);
    noteChange(before);
}

void NavigationController::flyTo(const globe::Viewpoint& target, double seconds) {
    const globe::Pose before = pose();
    manipulator_.flyTo(target, seconds);   // jumps (a change) when seconds <= 0
    noteChange(before);
}

void NavigationController::handle(const ViewportSize& size) {
    viewport_ = size;
    if (size.valid()) manipulator_.setAspect(size.aspect());
}

bool NavigationController::isDoubleClick(const MouseButtonEvent& event) const {
    if (!lastLeftPress_) return false;
    const double dt = event.timeSeconds - lastLeftPress_->timeSeconds;
    return dt >= 0.0 && dt <= kDoubleClickSeconds && glm::length(event.position - lastLeftPress_->px) <= kDoubleClickPx;
}

void NavigationController::handle(const MouseButtonEvent& event) {
    if (!event.pressed) {
        if (drag_ != Drag::None && event.button == dragButton_) drag_ = Drag::None;
        return;
    }
    const std::optional<glm::dvec2> ndc = toNdc(event.position, viewport_);
    if (!ndc) return;
    cursorPx_ = event.position;
    if (event.button == MouseButton::Left) {
        const bool doubleClick = isDoubleClick(event);
        // The second press of a double click does not start a third-click pair.
        lastLeftPress_.reset();
        if (!doubleClick && std::isfinite(event.timeSeconds)) lastLeftPress_ = Press{event.timeSeconds, event.position};
        // A double click on the ground flies there, with no grab while the flight starts; one
        // into space is an ordinary press.
        if (doubleClick && flyToGround(*ndc)) {
            if (dragButton_ == MouseButton::Left) drag_ = Drag::None;
            return;
        }
    }
    if (drag_ != Drag::None) return;   // one drag at a time: the first button held leads
    manipulator_.cancelFlight();       // grabbing the globe stops a flight
    switch (event.button) {
    case MouseButton::Left: drag_ = event.modifiers.ctrl ? Drag::TiltTurn : Drag::Rotate; break;
    case MouseButton::Right: drag_ = Drag::Zoom; break;
    case MouseButton::Middle: drag_ = Drag::TiltTurn; break;
    }
    dragButton_ = event.button;
    dragLastPx_ = event.position;
    dragAnchorNdc_ = *ndc;
}

void NavigationController::handle(const MouseMoveEvent& event) {
    if (!finite(event.position) || !viewport_.valid()) return;
    cursorPx_ = event.position;
    if (drag_ == Drag::None) return;
    const glm::dvec2 from = std::exchange(dragLastPx_, event.position);
    if (from == event.position) return;
    const globe::Pose before = pose();
    drag(from, event.position);
    noteChange(before);
}

void NavigationController::drag(const glm::dvec2& fromPx, const glm::dvec2& toPx) {
    const glm::dvec2 deltaPx = toPx - fromPx;
    switch (drag_) {
    case Drag::Rotate: manipulator_.rotate(*toNdc(fromPx, viewport_), *toNdc(toPx, viewport_)); break;
    case Drag::Zoom:
        // Screen y grows downward: dragging up shrinks the distance.
        manipulator_.zoom(std::exp2(deltaPx.y / kDragZoomPxPerDoubling), dragAnchorNdc_);
        break;
    case Drag::TiltTurn:
        if (deltaPx.x != 0.0) manipulator_.turn(deltaPx.x / viewport_.width * kTurnDegPerWidth);
        if (deltaPx.y != 0.0) manipulator_.tilt(-deltaPx.y / viewport_.height * kTiltDegPerHeight);
        break;
    case Drag::None: break;
    }
}

void NavigationController::handle(const ScrollEvent& event) {
    if (!std::isfinite(event.y) || event.y == 0.0 || !viewport_.valid()) return;
    const glm::dvec2 ndc = cursorPx_ ? toNdc(*cursorPx_, viewport_).value_or(glm::dvec2(0.0)) : glm::dvec2(0.0);
    const double lines = std::clamp(event.y, -kMaxScrollLines, kMaxScrollLines);
    const globe::Pose before = pose();
    manipulator_.zoom(std::pow(kWheelZoomFactor, lines), ndc);
    noteChange(before);
}

void NavigationController::handle(const KeyEvent& event) {
    const int index = static_cast<int>(event.key);
    if (index < 0 || index >= kKeyCount) return;
    if (!event.pressed) {
        held_[index] = false;
        return;
    }
    if (event.modifiers.ctrl || event.modifiers.alt) return;   // a shortcut for the application
    if (event.key == Key::Home) {
        flyHome();
        return;
    }
    held_[index] = true;
}

void NavigationController::releaseAll() {
    held_.fill(false);
    drag_ = Drag::None;
    lastLeftPress_.reset();
}

bool NavigationController::animating() const {
    return manipulator_.flying() || std::any_of(held_.begin(), held_.end(), [](bool h) { return h; });
}

void NavigationController::advance(double dtSeconds) {
    if (!(dtSeconds >= 0.0) || !std::isfinite(dtSeconds)) return;
    const globe::Pose before = pose();
    if (manipulator_.flying()) manipulator_.advance(dtSeconds);   // keeps above the ground itself
    else keepAboveGround();
    const double keyStep = std::min(dtSeconds, kMaxKeyStepSeconds);
    if (keyStep > 0.0) flyWithKeys(keyStep);
    noteChange(before);
}

void NavigationController::keepAboveGround() {
    const globe::Geodetic eye = ellipsoid_->toGeodetic(pose().position);
    // The manipulator's floor: the ground, never below the ellipsoid, plus the clearance.
    const double floor = std::max(groundHeight(eye.lonDeg, eye.latDeg), 0.0) + manipulator_.minClearance();
    if (eye.height < floor - kLiftToleranceMetres) manipulator_.setPose(pose());   // setPose lifts it
}

void NavigationController::flyWithKeys(double dtSeconds) {
    auto axis = [this](Key plusA, Key plusB, Key minusA, Key minusB) {
        return (held(plusA) || held(plusB) ? 1.0 : 0.0) - (held(minusA) || held(minusB) ? 1.0 : 0.0);
    };
    const double forward = axis(Key::W, Key::Up, Key::S, Key::Down);
    const double right = axis(Key::D, Key::Right, Key::A, Key::Left);
    const double turn = (held(Key::E) ? 1.0 : 0.0) - (held(Key::Q) ? 1.0 : 0.0);
    const double zoomOut = axis(Key::F, Key::PageDown, Key::R, Key::PageUp);
    if (forward != 0.0 || right != 0.0) {
        const globe::Geodetic eye = ellipsoid_->toGeodetic(pose().position);
        const double height = std::max(eye.height - groundHeight(eye.lonDeg, eye.latDeg), kMinSpeedHeight);
        const double metres = kKeyGroundSpeedPerHeight * height * dtSeconds;
        moveAlongGround(forward * metres, right * metres);
    }
    if (turn != 0.0) turnInPlace(turn * kKeyTurnDegPerSecond * dtSeconds);
    if (zoomOut != 0.0) manipulator_.zoom(std::exp2(zoomOut * kKeyZoomDoublingsPerSecond * dtSeconds), {0.0, 0.0});
}

void NavigationController::moveAlongGround(double forwardMetres, double rightMetres) {
    const globe::Pose p = pose();
    const globe::Geodetic eye = ellipsoid_->toGeodetic(p.position);
    const glm::dvec3 up = ellipsoid_->surfaceNormal(eye.lonDeg, eye.latDeg);
    const glm::dvec3 f = p.orientation * glm::dvec3(0.0, 0.0, -1.0), u = p.orientation * glm::dvec3(0.0, 1.0, 0.0);
    // "Forward" is the view's heading: the horizontal part of the view direction plus that of
    // the screen's up (flipped when looking up); it never vanishes, straight down included.
    glm::dvec3 ahead = f + (glm::dot(f, up) <= 0.0 ? u : -u);
    ahead -= up * glm::dot(ahead, up);
    if (!(glm::length(ahead) > 1e-12)) return;
    ahead = glm::normalize(ahead);
    const glm::dvec3 step = ahead * forwardMetres + glm::cross(ahead, up) * rightMetres;
    const double radius = glm::length(p.position);
    const glm::dvec3 axis = glm::cross(p.position, step);
    if (!(glm::length(axis) > 0.0) || !(radius > 0.0)) return;
    // A rotation about the Earth's centre moves the eye `step` along the sphere through it and
    // turns the view with it (heading and pitch kept); the height above the ellipsoid is then
    // put back, as the ellipsoid's radius changes with latitude.
    const glm::dquat q = glm::angleAxis(glm::length(step) / radius, glm::normalize(axis));
    globe::Geodetic moved = ellipsoid_->toGeodetic(q * p.position);
    moved.height = eye.height;
    manipulator_.setPose({ellipsoid_->toEcef(moved), q * p.orientation});
}

void NavigationController::turnInPlace(double deltaDeg) {
    const globe::Pose p = pose();
    const globe::Geodetic eye = ellipsoid_->toGeodetic(p.position);
    // Clockwise seen from above is a negative turn about the local up.
    const glm::dquat q = glm::angleAxis(-glm::radians(deltaDeg), ellipsoid_->surfaceNormal(eye.lonDeg, eye.latDeg));
    manipulator_.setPose({p.position, q * p.orientation});
}

bool NavigationController::flyToGround(const glm::dvec2& ndc) {
    const std::optional<GroundPoint> ground =
        pick(pose(), manipulator_.fovYRad(), manipulator_.aspect(), ndc, heightQuery_, *ellipsoid_);
    if (!ground) return false;
    const globe::Viewpoint now = manipulator_.viewpoint();
    const globe::Viewpoint target{ground->geodetic.lonDeg, ground->geodetic.latDeg, ground->geodetic.height,
                                  now.headingDeg, now.pitchDeg, 0.5 * ground->distance};
    flyTo(target, kFlightSeconds);
    return true;
}

std::optional<GroundPoint> NavigationController::groundAt(const glm::dvec2& windowPx) const {
    const std::optional<glm::dvec2> ndc = toNdc(windowPx, viewport_);
    if (!ndc) return std::nullopt;
    return pick(pose(), manipulator_.fovYRad(), manipulator_.aspect(), *ndc, heightQuery_, *ellipsoid_);
}

std::optional<GroundPoint> NavigationController::groundUnderCursor() const {
    return cursorPx_ ? groundAt(*cursorPx_) : std::nullopt;
}

}  // namespace orbis::ui
