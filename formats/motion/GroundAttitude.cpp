#include "formats/motion/GroundAttitude.h"

#include "globe/Ellipsoid.h"
#include "formats/motion/Attitude.h"

#include <cmath>

namespace orbis::motion {

std::optional<glm::dquat> groundAttitude(double lonDeg, double latDeg, double headingDeg, const Footprint& footprint,
                                         const GroundFn& ground) {
    if (!ground) return std::nullopt;
    // A footprint under 1 cm in one direction is sampled 1 cm out: the slope is still defined.
    const double length = std::max(footprint.halfLength, 0.01), width = std::max(footprint.halfWidth, 0.01);
    if (footprint.halfLength < 0.01 && footprint.halfWidth < 0.01) return std::nullopt;
    const globe::Ellipsoid& e = globe::Ellipsoid::wgs84();
    const glm::dmat3 enu = e.enuFrame(lonDeg, latDeg);   // columns east, north, up in ECEF
    const double h = glm::radians(headingDeg);
    // Forward and right in ENU (heading clockwise from north; forward x right = down).
    const glm::dvec3 f(std::sin(h), std::cos(h), 0.0), r(std::cos(h), -std::sin(h), 0.0), u(0.0, 0.0, 1.0);
    const glm::dvec3 origin = e.toEcef(lonDeg, latDeg, 0.0);
    auto heightAt = [&](const glm::dvec3& offsetEnu) -> std::optional<double> {
        const globe::Geodetic g = e.toGeodetic(origin + enu * offsetEnu);
        const std::optional<double> v = ground(g.lonDeg, g.latDeg);
        if (!v || !std::isfinite(*v)) return std::nullopt;
        return *v;
    };
    const auto ahead = heightAt(f * length), behind = heightAt(-f * length);
    const auto right = heightAt(r * width), left = heightAt(-r * width);
    if (!ahead || !behind || !right || !left) return std::nullopt;
    const double sx = (*ahead - *behind) / (2.0 * length), sy = (*right - *left) / (2.0 * width);
    // The plane z = sx x + sy y (x along f, y along r): forward lifted onto it, its normal.
    const glm::dvec3 forward = glm::normalize(f + sx * u);
    const glm::dvec3 down = -glm::normalize(u - sx * f - sy * r);
    const glm::dvec3 rightAxis = glm::cross(down, forward);   // (x, y, z) right-handed: y = z x x
    const glm::dmat3 bodyToEcef = enu * glm::dmat3(forward, rightAxis, down);
    return glm::normalize(glm::quat_cast(bodyToEcef));
}

void followGround(Pose& pose, const Footprint& footprint, const GroundFn& ground) {
    if (!pose.onGround) return;
    const auto q = groundAttitude(pose.lonDeg, pose.latDeg, pose.headingDeg, footprint, ground);
    if (!q) return;
    pose.orientation = *q;
    const HeadingPitchRoll a = headingPitchRoll(*q, pose.lonDeg, pose.latDeg);
    pose.pitchDeg = a.pitchDeg;
    pose.rollDeg = a.rollDeg;
}

}  // namespace orbis::motion
