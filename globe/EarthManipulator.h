#pragma once
// Earth-manipulator maths: grab-rotate, zoom to the cursor, pan, tilt and turn about the point
// at the screen centre, and fly-to. No input library: the viewer maps its mouse and keyboard
// events to these calls. All in double, in ECEF. No Vulkan, no engine/scene.
//
// Screen positions are normalised device coordinates like scene::Camera::rayDirection: x right,
// y DOWN, both -1..1 across the viewport.
//
// Not thread-safe: one manipulator per view, used from the thread that handles input (the main
// thread). The height query is called on that thread.

#include "globe/Ellipsoid.h"
#include "globe/Viewpoint.h"

#include <glm/glm.hpp>

#include <functional>
#include <optional>
#include <utility>

namespace orbis::globe {

/// Smoothstep ease-in/ease-out of t in [0, 1] (clamped): zero speed at both ends.
double easeInOut(double t);

/// The viewpoint a fraction `t` (already eased, 0..1) of the way from `a` to `b`: the target
/// moves along the great circle (slerp of the targets' unit normals), target height, pitch and
/// range are lerped, the heading turns the short way round, and the range rises in an arc with
/// the ground distance so that long flights climb and come down:
///     range(t) = lerp(a.range, b.range, t) + min(0.5 * distance, 1.5e7 m) * 4 t (1 - t).
/// t <= 0 gives exactly `a`, t >= 1 exactly `b`.
Viewpoint interpolateFlight(const Viewpoint& a, const Viewpoint& b, double t);

class EarthManipulator {
public:
    /// Terrain height above the ellipsoid at a place, where known (nothing: 0 is assumed).
    using HeightQuery = std::function<std::optional<double>(double lonDeg, double latDeg)>;

    static constexpr double kMinPitchDeg = -90.0;
    static constexpr double kMaxPitchDeg = -1.0;

    explicit EarthManipulator(const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

    void setHeightQuery(HeightQuery query) { heightQuery_ = std::move(query); }
    void setFovYRad(double fovYRad) { fovYRad_ = fovYRad; }
    void setAspect(double aspect) { aspect_ = aspect; }
    double fovYRad() const { return fovYRad_; }
    double aspect() const { return aspect_; }
    /// Least height of the eye above the terrain (and above the ellipsoid), metres.
    void setMinClearance(double metres) { minClearance_ = metres; }
    double minClearance() const { return minClearance_; }

    const Pose& pose() const { return pose_; }
    /// Sets the pose as given (then lifted above the terrain when needed). Cancels a flight.
    void setPose(const Pose& pose);
    /// Pitch is clamped to [kMinPitchDeg, kMaxPitchDeg]. Cancels a flight.
    void setViewpoint(const Viewpoint& vp);
    /// The current pose as a viewpoint about the pivot: the ground under the screen centre (or,
    /// when the centre looks past the globe, the point of the centre ray nearest to it).
    Viewpoint viewpoint() const;

    /// Grab-drag: the ground point under `fromNdc` ends under `toNdc`, by a rotation about the
    /// Earth's centre. When either cursor misses the globe, rotates in proportion to the drag.
    void rotate(const glm::dvec2& fromNdc, const glm::dvec2& toNdc);
    /// Moves toward (factor < 1) or away from (factor > 1) the ground point under the cursor,
    /// which stays under the cursor; the distance to it scales by `factor`.
    void zoom(double factor, const glm::dvec2& cursorNdc);
    /// Slides the pivot over the ground so that the point under `fromNdc` (on the pivot's
    /// tangent plane) ends under `toNdc`; heading, pitch and range are kept.
    void pan(const glm::dvec2& fromNdc, const glm::dvec2& toNdc);
    /// Pitch about the pivot; positive raises the view toward the horizon. Clamped.
    void tilt(double deltaDeg);
    /// Heading about the pivot; positive turns clockwise seen from above (view turns east).
    void turn(double deltaDeg);

    /// Starts a flight from the current viewpoint; zero or negative duration jumps at once.
    void flyTo(const Viewpoint& target, double durationSeconds);
    /// Moves a flight on by dt seconds; does nothing when not flying.
    void advance(double dtSeconds);
    bool flying() const { return flying_; }
    void cancelFlight() { flying_ = false; }

    /// World direction of the ray through `ndc`, from the current pose, fov and aspect.
    glm::dvec3 rayDirection(const glm::dvec2& ndc) const;
    /// First hit of a ray with the ground (the ellipsoid raised by the terrain height where the
    /// ray lands, refined a few times: exact on flat terrain, approximate on slopes).
    std::optional<glm::dvec3> intersectGround(const glm::dvec3& origin, const glm::dvec3& direction) const;

private:
    double terrainHeight(double lonDeg, double latDeg) const;
    void applyViewpoint(const Viewpoint& vp);
    void keepAboveTerrain();
    void rotateAboutCentre(const glm::dquat& q);
    glm::dvec3 pivot() const;

    const Ellipsoid* ellipsoid_;
    HeightQuery heightQuery_;
    Pose pose_;
    double fovYRad_ = 0.7853981633974483;   // 45 degrees
    double aspect_ = 16.0 / 9.0;
    double minClearance_ = 1.0;

    bool flying_ = false;
    Viewpoint flightFrom_, flightTo_;
    double flightDuration_ = 0.0, flightElapsed_ = 0.0;
};

}  // namespace orbis::globe
