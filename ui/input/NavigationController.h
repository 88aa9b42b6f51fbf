#pragma once
// The viewer's mouse and keyboard bindings: input events (InputEvents.h) in, a camera pose
// out, through a globe::EarthManipulator that the controller owns. No window library, no
// Vulkan: the window layer translates its callbacks into events, and tests drive it directly.
//
//   left drag              grab-rotate: the ground point grabbed stays under the cursor
//   right drag, wheel      zoom toward the ground point under the cursor (drag up / wheel up:
//                          in; one wheel notch scales the distance by 0.85 or 1/0.85)
//   middle or Ctrl+left    tilt (vertical: up raises the view toward the horizon) and turn
//                          (horizontal: right turns the view east) about the screen centre
//   double left click      fly to the ground point clicked, at half its distance, in 1.5 s
//   Home                   fly to the home viewpoint
//   W/S or Up/Down         forward/back along the ground    } speed: one height above the
//   A/D or Left/Right      strafe left/right                } ground per second
//   Q/E                    turn left/right in place (60 degrees per second)
//   R/F or PageUp/PageDown zoom in/out toward the screen centre (distance halves or doubles
//                          per second)
// Any button press cancels a flight (the user grabs the globe); so do the wheel and the keys
// that move the camera.
//
// A double click is two left presses at most 0.3 s and 4 px apart, from the times and
// positions the press events carry (there is no double-click event).
//
// Output: a globe::Pose (ECEF, double), like scene::Camera::setPose takes it: the viewer polls
// revision() and copies pose() into the scene's camera when it changed. The controller does
// not own the field of view; the viewer passes the camera's.
//
// Not thread-safe: main thread only (where the window's events arrive); the height query is
// called on that thread.

#include "globe/EarthManipulator.h"
#include "globe/Ellipsoid.h"
#include "globe/Viewpoint.h"
#include "ui/input/InputEvents.h"
#include "ui/input/MapTools.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <optional>

namespace orbis::ui {

class NavigationController {
public:
    static constexpr double kDoubleClickSeconds = 0.3;
    static constexpr double kDoubleClickPx = 4.0;
    static constexpr double kFlightSeconds = 1.5;
    static constexpr double kWheelZoomFactor = 0.85;      ///< per notch toward the cursor
    static constexpr double kDragZoomPxPerDoubling = 150.0;
    static constexpr double kTurnDegPerWidth = 180.0;     ///< a drag across the whole view
    static constexpr double kTiltDegPerHeight = 90.0;
    static constexpr double kKeyGroundSpeedPerHeight = 1.0;   ///< metres/s per metre of height
    static constexpr double kKeyTurnDegPerSecond = 60.0;
    static constexpr double kKeyZoomDoublingsPerSecond = 1.0;
    /// advance() moves the keyboard flight by at most this much time: a stalled frame does
    /// not throw the camera far.
    static constexpr double kMaxKeyStepSeconds = 0.1;

    explicit NavigationController(const globe::Ellipsoid& ellipsoid = globe::Ellipsoid::wgs84());

    /// Ground height where known (scene::Scene::heightAt): the camera stays above it, picks
    /// land on it and the keyboard speed follows the height above it.
    void setHeightQuery(HeightQuery query);
    /// Vertical field of view of the rendered camera; ignored unless in (0, pi).
    void setFovYRad(double fovYRad);
    /// Least height of the eye above the ground, metres (default 1); ignored when negative.
    void setMinClearance(double metres);
    void setHomeViewpoint(const globe::Viewpoint& home) { home_ = home; }
    const globe::Viewpoint& homeViewpoint() const { return home_; }

    /// Puts the camera at `pose` (the scene camera when the viewer starts, or after a camera
    /// mode moved it), lifted above the ground if needed. Cancels a flight.
    void setPose(const globe::Pose& pose);
    /// Puts the camera at `vp` at once (pitch clamped like the manipulator's). Cancels a flight.
    void setViewpoint(const globe::Viewpoint& vp);
    /// Flies from the current view to `target`; zero seconds jumps.
    void flyTo(const globe::Viewpoint& target, double seconds = kFlightSeconds);
    void flyHome() { flyTo(home_); }

    /// The view's size: send it first and on every resize. An empty or non-finite size makes
    /// mouse events be ignored until a valid one comes.
    void handle(const ViewportSize& size);
    void handle(const MouseButtonEvent& event);
    void handle(const MouseMoveEvent& event);
    void handle(const ScrollEvent& event);
    void handle(const KeyEvent& event);
    /// Forgets held keys and drags: call when the window loses focus (no release comes then).
    void releaseAll();

    /// Moves a flight and the keyboard flight on by `dtSeconds` of wall time. Call it every
    /// frame while animating(); at other times it only lifts the camera when the ground under
    /// it has risen (finer terrain loaded).
    void advance(double dtSeconds);

    const globe::Pose& pose() const { return manipulator_.pose(); }
    /// The view about the ground point under the screen centre.
    globe::Viewpoint viewpoint() const { return manipulator_.viewpoint(); }
    /// Goes up by one each time the pose changes; the viewer renders when it differs from the
    /// value it last drew.
    std::uint64_t revision() const { return revision_; }
    /// True while a flight runs or a navigation key is held: the viewer must keep calling
    /// advance() and rendering; otherwise it can sleep until the next event.
    bool animating() const;
    bool flying() const { return manipulator_.flying(); }
    const ViewportSize& viewport() const { return viewport_; }
    double fovYRad() const { return manipulator_.fovYRad(); }

    /// The ground under a window position (the status bar's lon/lat/height), or nothing.
    std::optional<GroundPoint> groundAt(const glm::dvec2& windowPx) const;
    /// The ground under the last known cursor position, or nothing.
    std::optional<GroundPoint> groundUnderCursor() const;

private:
    enum class Drag { None, Rotate, Zoom, TiltTurn };
    struct Press {
        double timeSeconds;
        glm::dvec2 px;
    };

    bool held(Key key) const { return held_[static_cast<int>(key)]; }
    double groundHeight(double lonDeg, double latDeg) const;
    /// Bumps the revision when the pose differs from `before`.
    void noteChange(const globe::Pose& before);
    bool isDoubleClick(const MouseButtonEvent& event) const;
    /// Starts the double-click flight; false when `ndc` looks into space.
    bool flyToGround(const glm::dvec2& ndc);
    void drag(const glm::dvec2& fromPx, const glm::dvec2& toPx);
    void flyWithKeys(double dtSeconds);
    void moveAlongGround(double forwardMetres, double rightMetres);
    void turnInPlace(double deltaDeg);
    void keepAboveGround();

    const globe::Ellipsoid* ellipsoid_;
    globe::EarthManipulator manipulator_;
    HeightQuery heightQuery_;
    globe::Viewpoint home_;
    ViewportSize viewport_;
    std::optional<glm::dvec2> cursorPx_;

    Drag drag_ = Drag::None;
    MouseButton dragButton_ = MouseButton::Left;
    glm::dvec2 dragLastPx_{0.0};
    glm::dvec2 dragAnchorNdc_{0.0};   ///< a zoom drag zooms toward where it started
    std::optional<Press> lastLeftPress_;

    std::array<bool, kKeyCount> held_{};
    std::uint64_t revision_ = 0;
};

}  // namespace orbis::ui
