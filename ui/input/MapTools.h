#pragma once
// Map tools for the viewer's overlay: picking the ground under the cursor, the scale bar and
// the compass. Pure functions of a camera pose, in double, in ECEF; no window library, no
// Vulkan. Screen positions are normalised device coordinates (x right, y DOWN, -1..1) like
// globe::EarthManipulator, or window pixels where named ...Px.
//
// Any thread; the height query is called on the caller's thread.

#include "globe/EarthManipulator.h"
#include "globe/Ellipsoid.h"
#include "globe/Viewpoint.h"

#include <glm/glm.hpp>

#include <optional>
#include <string>

namespace orbis::ui {

using HeightQuery = globe::EarthManipulator::HeightQuery;

/// A point on the ground found by pick().
struct GroundPoint {
    globe::Geodetic geodetic;   ///< lon, lat, and the terrain height there (0 without terrain)
    glm::dvec3 ecef{0.0};
    double distance = 0.0;      ///< from the eye along the ray, metres
};

/// The ground under `ndc` seen from `pose` (vertical field of view `fovYRad`, width/height
/// `aspect`): the ray is marched through the shell that can hold terrain (-12 km .. 9 km, or
/// higher where the query says so), from the eye outward in steps that grow with the distance
/// (at most 1024 steps), and the first crossing of the terrain is refined by bisection. Without
/// a height query the ray meets the ellipsoid exactly. Nothing when the ray looks into space,
/// when the eye is under the ground, or for bad input (no NaN out).
std::optional<GroundPoint> pick(const globe::Pose& pose, double fovYRad, double aspect, const glm::dvec2& ndc,
                                const HeightQuery& heightQuery,
                                const globe::Ellipsoid& ellipsoid = globe::Ellipsoid::wgs84());

/// Ground metres per window pixel at `atPx` along the screen's x axis: the distance between the
/// picks at `atPx` and one pixel to its right, or, where either misses the ground, the size of
/// a pixel at the eye's height above the ground. Nothing for bad input.
std::optional<double> metresPerPixel(const globe::Pose& pose, double fovYRad, const glm::dvec2& viewportPx,
                                     const glm::dvec2& atPx, const HeightQuery& heightQuery,
                                     const globe::Ellipsoid& ellipsoid = globe::Ellipsoid::wgs84());

/// Where `ecef` is drawn in a window of `viewportPx` seen from `pose` (the inverse of pick()'s
/// ray): window pixels, origin top left. Nothing behind the eye, outside the view by more than
/// `marginPx`, hidden behind the ellipsoid's horizon (the terrain does not hide it), or for bad
/// input. Overlays drawn over the picture (sketches, their labels) use it.
std::optional<glm::dvec2> projectToWindow(const globe::Pose& pose, double fovYRad, const glm::dvec2& viewportPx, const glm::dvec3& ecef,
                                          double marginPx = 0.0, const globe::Ellipsoid& ellipsoid = globe::Ellipsoid::wgs84());

/// A scale bar: a round length and how wide it is drawn.
struct ScaleBar {
    double metres = 0.0;        ///< 1, 2 or 5 x 10^n
    double widthPx = 0.0;       ///< at most the maximum width asked for
    std::string label;          ///< "500 m", "2 km", "0.2 m"
};

/// The longest 1/2/5 x 10^n length no wider than `maxWidthPx` at `metresPerPixel`; nothing for
/// a scale that is not finite and positive or a maximum width under one pixel.
std::optional<ScaleBar> niceScaleBar(double metresPerPixel, double maxWidthPx);

/// The heading of the view in degrees in [0, 360), 0 = north up, 90 = looking east: measured
/// at the ground point under the screen centre (the pivot of globe::EarthManipulator, so it
/// matches Viewpoint::headingDeg), or under the eye when the centre looks past the globe.
/// Straight down the top of the screen gives it; at a pole, where every way is south (north),
/// it reads 0 at the north pole and 180 at the south pole, as if the camera had come along
/// the meridian behind it. 0 for a pose that is not finite.
double compassHeadingDeg(const globe::Pose& pose, const globe::Ellipsoid& ellipsoid = globe::Ellipsoid::wgs84());

}  // namespace orbis::ui
