#pragma once
// A viewpoint as geospatial users give it: the point looked at, and where the eye is from it
// (heading clockwise from north, pitch below the horizon negative, range in metres).

#include "globe/Ellipsoid.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace orbis::globe {

struct Viewpoint {
    double lonDeg = 0.0;
    double latDeg = 0.0;
    double height = 0.0;      ///< of the target point, above the ellipsoid
    double headingDeg = 0.0;  ///< 0 = looking north, 90 = east
    double pitchDeg = -90.0;  ///< -90 = looking straight down, 0 = level
    double range = 1.0e7;     ///< eye-to-target distance, metres
};

/// A camera pose in ECEF: position, and orientation camera-to-world. The camera looks along
/// its -Z axis with +Y up (the usual view-space convention).
struct Pose {
    glm::dvec3 position{0.0};
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
};

Pose poseFromViewpoint(const Viewpoint& vp, const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

/// Pose at `eye` (lon, lat, height) looking with the given heading and pitch (pilot view).
Pose poseFromEye(const Geodetic& eye, double headingDeg, double pitchDeg, double rollDeg = 0.0,
                 const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

}  // namespace orbis::globe
