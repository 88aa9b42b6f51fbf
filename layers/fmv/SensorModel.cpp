#include "layers/fmv/SensorModel.h"

#include "globe/Ellipsoid.h"
#include "formats/fmv/St0601.h"

#include <algorithm>
#include <cmath>

namespace orbis::fmv {
namespace {

// Intrinsic rotations about x, y, z of a right-handed frame, angles in degrees.
glm::dmat3 rotX(double deg) {
    const double c = std::cos(glm::radians(deg)), s = std::sin(glm::radians(deg));
    return glm::dmat3(1, 0, 0, 0, c, s, 0, -s, c);   // columns
}
glm::dmat3 rotY(double deg) {
    const double c = std::cos(glm::radians(deg)), s = std::sin(glm::radians(deg));
    return glm::dmat3(c, 0, -s, 0, 1, 0, s, 0, c);
}
glm::dmat3 rotZ(double deg) {
    const double c = std::cos(glm::radians(deg)), s = std::sin(glm::radians(deg));
    return glm::dmat3(c, s, 0, -s, c, 0, 0, 0, 1);
}

// Columns: north, east, down in ECEF.
glm::dmat3 nedFrame(double lonDeg, double latDeg) {
    const glm::dmat3 enu = globe::Ellipsoid::wgs84().enuFrame(lonDeg, latDeg);
    return glm::dmat3(enu[1], enu[0], -enu[2]);
}

double heightAbove(const glm::dvec3& p, const TerrainHeights* terrain) {
    const globe::Geodetic g = globe::Ellipsoid::wgs84().toGeodetic(p);
    return g.height - (terrain ? terrain->at(g.lonDeg, g.latDeg) : 0.0);
}

}  // namespace

Result<SensorPose> sensorPoseFromPacket(const St0601Packet& p, double geoidHeight) {
    SensorPose pose;
    if (!p.sensorLatitudeDeg || !p.sensorLongitudeDeg) return makeError("ST 0601 packet without a sensor position (tags 13, 14)");
    pose.latDeg = *p.sensorLatitudeDeg;
    pose.lonDeg = *p.sensorLongitudeDeg;
    if (auto h = p.sensorHeightAboveEllipsoid()) pose.height = *h;
    else if (p.sensorTrueAltitude) pose.height = *p.sensorTrueAltitude + geoidHeight;
    else return makeError("ST 0601 packet without a sensor height (tags 15, 75 or 104)");
    if (!p.horizontalFovDeg || !p.verticalFovDeg) return makeError("ST 0601 packet without a field of view (tags 16, 17)");
    pose.hfovDeg = *p.horizontalFovDeg;
    pose.vfovDeg = *p.verticalFovDeg;
    if (!(pose.hfovDeg > 0.0 && pose.hfovDeg < 180.0 && pose.vfovDeg > 0.0 && pose.vfovDeg < 180.0))
        return makeError("ST 0601 packet with a field of view of " + std::to_string(pose.hfovDeg) + " x " +
                         std::to_string(pose.vfovDeg) + " degrees (each must be inside 0..180)");
    pose.platformHeadingDeg = p.platformHeadingDeg.value_or(0.0);
    pose.platformPitchDeg = p.pitchDeg().value_or(0.0);
    pose.platformRollDeg = p.rollDeg().value_or(0.0);
    pose.sensorAzimuthDeg = p.sensorRelativeAzimuthDeg.value_or(0.0);
    pose.sensorElevationDeg = p.sensorRelativeElevationDeg.value_or(0.0);
    pose.sensorRollDeg = p.sensorRelativeRollDeg.value_or(0.0);
    return pose;
}

SensorCamera::SensorCamera(const SensorPose& pose) : pose_(pose) {
    position_ = globe::Ellipsoid::wgs84().toEcef(pose.lonDeg, pose.latDeg, pose.height);
    axes_ = nedFrame(pose.lonDeg, pose.latDeg) * rotZ(pose.platformHeadingDeg) * rotY(pose.platformPitchDeg) *
            rotX(pose.platformRollDeg) * rotZ(pose.sensorAzimuthDeg) * rotY(pose.sensorElevationDeg) * rotX(pose.sensorRollDeg);
    tanHalfH_ = std::tan(glm::radians(std::clamp(pose.hfovDeg, 1e-6, 179.9)) * 0.5);
    tanHalfV_ = std::tan(glm::radians(std::clamp(pose.vfovDeg, 1e-6, 179.9)) * 0.5);
}

glm::dvec3 SensorCamera::ray(double u, double v) const {
    return glm::normalize(axes_[0] + u * tanHalfH_ * axes_[1] + v * tanHalfV_ * axes_[2]);
}

glm::dvec3 SensorCamera::cornerRay(int i) const {
    static constexpr double kU[4] = {-1, 1, 1, -1}, kV[4] = {-1, -1, 1, 1};
    return ray(kU[i & 3], kV[i & 3]);
}

glm::dvec3 SensorCamera::project(const glm::dvec3& ecef) const {
    const glm::dvec3 d = glm::transpose(axes_) * (ecef - position_);
    if (d.x <= 0.0) return {0.0, 0.0, d.x};
    return {d.y / (d.x * tanHalfH_), d.z / (d.x * tanHalfV_), d.x};
}

glm::dvec3 horizonPoint(const glm::dvec3& origin, const glm::dvec3& direction, double height) {
    const globe::Ellipsoid& e = globe::Ellipsoid::wgs84();
    const globe::Geodetic g = e.toGeodetic(origin);
    const glm::dvec3 up = e.surfaceNormal(g.lonDeg, g.latDeg);
    const glm::dvec3 ground = e.toEcef(g.lonDeg, g.latDeg, height);
    const double above = g.height - height;
    if (!(above > 0.0)) return ground;   // at or below the surface: the nadir point
    // The horizontal part of the direction (any horizontal one when looking straight up/down).
    glm::dvec3 h = direction - glm::dot(direction, up) * up;
    if (glm::length(h) < 1e-9) h = e.enuFrame(g.lonDeg, g.latDeg)[1];
    h = glm::normalize(h);
    // The tangent from the eye to a sphere of the local radius: dip below the horizontal, and
    // the distance to the point of tangency.
    const double r = glm::length(ground);
    const double dip = std::acos(std::clamp(r / (r + above), -1.0, 1.0));
    const double distance = std::sqrt(above * (2.0 * r + above));
    const glm::dvec3 p = origin + distance * (std::cos(dip) * h - std::sin(dip) * up);
    // On the surface (the sphere and the ellipsoid differ by metres at this scale).
    const globe::Geodetic q = e.toGeodetic(p);
    return e.toEcef(q.lonDeg, q.latDeg, height);
}

GroundHit intersectGround(const glm::dvec3& origin, const glm::dvec3& direction, const TerrainHeights* terrain, double step) {
    const globe::Ellipsoid& e = globe::Ellipsoid::wgs84();
    const double low = terrain ? terrain->minHeight : 0.0, high = terrain ? std::max(terrain->maxHeight, low) : 0.0;
    GroundHit out;
    // The ray meets the terrain between the shell at its highest point and the one at its
    // lowest (or the horizon, where the ray passes the low shell without touching it).
    const double start = heightAbove(origin, nullptr) <= high ? 0.0 : e.intersectRay(origin, direction, high).value_or(-1.0);
    const std::optional<double> end = e.intersectRay(origin, direction, low);
    if (start >= 0.0) {
        const double stop = end ? *end : start + 2.0 * std::sqrt(std::max(heightAbove(origin, nullptr) - low, 0.0) *
                                                                 (2.0 * e.equatorialRadius()));
        step = std::max(step, 1e-3);
        double t0 = start, h0 = heightAbove(origin + start * direction, terrain);
        if (h0 <= 1e-3) {   // on the terrain's top shell already (or a single shell: the ellipsoid)
            out.hit = true;
            out.distance = start;
            out.ecef = origin + start * direction;
            return out;
        }
        const int steps = int(std::min(std::ceil((stop - start) / step), 1e6));
        for (int i = 1; i <= steps; ++i) {
            const double t1 = std::min(start + (stop - start) * double(i) / double(steps), stop);
            const double h1 = heightAbove(origin + t1 * direction, terrain);
            if (h1 <= 0.0) {   // crossed: bisection down to a millimetre
                double a = t0, b = t1;
                while (b - a > 1e-3) {
                    const double m = 0.5 * (a + b);
                    (heightAbove(origin + m * direction, terrain) > 0.0 ? a : b) = m;
                }
                out.hit = true;
                out.distance = b;
                out.ecef = origin + b * direction;
                return out;
            }
            t0 = t1;
            h0 = h1;
        }
    }
    // A miss: the horizon in the ray's azimuth, on the terrain's mean shell.
    out.ecef = horizonPoint(origin, direction, 0.5 * (low + high));
    out.distance = glm::length(out.ecef - origin);
    return out;
}

Footprint footprint(const SensorCamera& camera, const TerrainHeights* terrain, double step) {
    Footprint f;
    for (int i = 0; i < 4; ++i) f.corners[size_t(i)] = intersectGround(camera.position(), camera.cornerRay(i), terrain, step);
    f.centre = intersectGround(camera.position(), camera.ray(0.0, 0.0), terrain, step);
    return f;
}

}  // namespace orbis::fmv
