#include "globe/Viewpoint.h"

#include <cmath>

namespace orbis::globe {
namespace {

// Camera basis in ENU for a heading/pitch, built directly (no lookAt), so it stays defined when
// looking straight down (pitch -90) where forward is parallel to up.
glm::dmat3 basisEnu(double headingDeg, double pitchDeg, double rollDeg) {
    const double h = glm::radians(headingDeg), p = glm::radians(pitchDeg), r = glm::radians(rollDeg);
    const glm::dvec3 forward(std::sin(h) * std::cos(p), std::cos(h) * std::cos(p), std::sin(p));
    glm::dvec3 right(std::cos(h), -std::sin(h), 0.0);
    glm::dvec3 up = glm::cross(right, forward);
    if (rollDeg != 0.0) {   // positive roll: right wing down
        const glm::dvec3 r2 = right * std::cos(r) - up * std::sin(r);
        up = up * std::cos(r) + right * std::sin(r);
        right = r2;
    }
    return glm::dmat3(right, up, -forward);
}

Pose makePose(const glm::dvec3& position, const glm::dmat3& enu, const glm::dmat3& basis) {
    Pose pose;
    pose.position = position;
    pose.orientation = glm::normalize(glm::quat_cast(enu * basis));
    return pose;
}

}  // namespace

Pose poseFromViewpoint(const Viewpoint& vp, const Ellipsoid& ellipsoid) {
    const glm::dmat3 enu = ellipsoid.enuFrame(vp.lonDeg, vp.latDeg);
    const glm::dmat3 basis = basisEnu(vp.headingDeg, vp.pitchDeg, 0.0);
    const glm::dvec3 target = ellipsoid.toEcef(vp.lonDeg, vp.latDeg, vp.height);
    const glm::dvec3 forwardEcef = enu * (-basis[2]);
    return makePose(target - forwardEcef * vp.range, enu, basis);
}

Pose poseFromEye(const Geodetic& eye, double headingDeg, double pitchDeg, double rollDeg, const Ellipsoid& ellipsoid) {
    const glm::dmat3 enu = ellipsoid.enuFrame(eye.lonDeg, eye.latDeg);
    return makePose(ellipsoid.toEcef(eye), enu, basisEnu(headingDeg, pitchDeg, rollDeg));
}

}  // namespace orbis::globe
