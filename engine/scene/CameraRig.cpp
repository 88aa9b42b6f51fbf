#include "engine/scene/CameraRig.h"

#include "globe/Ellipsoid.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

namespace orbis::scene {
namespace {

constexpr CameraMode kModes[] = {CameraMode::Free,   CameraMode::Overview, CameraMode::Follow, CameraMode::Pilot,
                                 CameraMode::Inside, CameraMode::Above,    CameraMode::Aside,  CameraMode::Below};

/// A camera at `eye` looking at `target` with `up` as the up hint (camera looks along -Z, +Y up).
globe::Pose looking(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up) {
    const glm::dvec3 f = glm::normalize(target - eye);
    glm::dvec3 r = glm::cross(f, up);
    if (glm::dot(r, r) < 1e-20) r = glm::cross(f, std::abs(f.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0));
    r = glm::normalize(r);
    return {eye, glm::normalize(glm::quat_cast(glm::dmat3(r, glm::cross(r, f), -f)))};
}

double sizeDistance(const CameraModeSettings& s, const TrackedPose& t, double radii) {
    return s.distance > 0.0 ? s.distance : radii * std::max(t.radius, 0.1) + 5.0;
}

}  // namespace

const char* toString(CameraMode mode) {
    switch (mode) {
        case CameraMode::Free: return "free";
        case CameraMode::Overview: return "overview";
        case CameraMode::Follow: return "follow";
        case CameraMode::Pilot: return "pilot";
        case CameraMode::Inside: return "inside";
        case CameraMode::Above: return "above";
        case CameraMode::Aside: return "aside";
        case CameraMode::Below: return "below";
    }
    return "free";
}

std::optional<CameraMode> parseCameraMode(std::string_view text) {
    for (CameraMode m : kModes)
        if (text == toString(m)) return m;
    return std::nullopt;
}

globe::Pose cameraForTarget(const CameraModeSettings& s, const TrackedPose& target, const glm::dvec3& travel) {
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    const globe::Geodetic g = wgs84.toGeodetic(target.position);
    const glm::dvec3 up = wgs84.surfaceNormal(g.lonDeg, g.latDeg);
    const glm::dmat3 body = glm::mat3_cast(target.bodyToEcef);
    const glm::dvec3 nose = body[0], right = body[1], down = body[2];
    switch (s.mode) {
        case CameraMode::Pilot:
        case CameraMode::Inside: {
            const glm::dvec3 eye = target.position + body * s.eye;
            // Camera axes: right = body y, up = -body z, looking along body x.
            return {eye, glm::normalize(glm::quat_cast(glm::dmat3(right, -down, -nose)))};
        }
        case CameraMode::Above: {
            // Looking straight down with the nose towards the top of the picture.
            const glm::dvec3 eye = target.position + up * sizeDistance(s, target, 6.0);
            glm::dvec3 forward = nose - up * glm::dot(nose, up);
            if (glm::dot(forward, forward) < 1e-12) forward = -down - up * glm::dot(-down, up);
            return looking(eye, target.position, forward);
        }
        case CameraMode::Below: {
            const glm::dvec3 eye = target.position - up * sizeDistance(s, target, 6.0);
            glm::dvec3 forward = nose - up * glm::dot(nose, up);
            if (glm::dot(forward, forward) < 1e-12) forward = right;
            return looking(eye, target.position, forward);
        }
        case CameraMode::Aside: {
            glm::dvec3 side = right - up * glm::dot(right, up);   // level, off the right wing
            if (glm::dot(side, side) < 1e-12) side = glm::cross(nose, up);
            const glm::dvec3 eye = target.position + glm::normalize(side) * sizeDistance(s, target, 6.0);
            return looking(eye, target.position, up);
        }
        case CameraMode::Follow:
        default: {
            glm::dvec3 ahead = travel - up * glm::dot(travel, up);
            if (glm::dot(ahead, ahead) < 1e-12) ahead = nose - up * glm::dot(nose, up);
            if (glm::dot(ahead, ahead) < 1e-12) ahead = -down - up * glm::dot(-down, up);   // nose straight up or down
            ahead = glm::normalize(ahead);
            const glm::dvec3 east = glm::normalize(glm::cross(ahead, up));   // right of the travel
            // Behind the target, turned by `heading` about the vertical and raised by -pitch.
            const double h = glm::radians(s.headingDeg), p = glm::radians(std::clamp(-s.pitchDeg, -89.0, 89.0));
            const glm::dvec3 horizontal = -ahead * std::cos(h) + east * std::sin(h);
            const glm::dvec3 back = horizontal * std::cos(p) + up * std::sin(p);
            const glm::dvec3 eye = target.position + back * sizeDistance(s, target, 4.0);
            return looking(eye, target.position, up);
        }
    }
}

globe::Pose cameraForOverview(const ContentBounds& bounds, double fovYRad, double aspect) {
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    const globe::Geodetic c = wgs84.toGeodetic(bounds.center);
    const double halfFov = 0.5 * std::min(fovYRad, 2.0 * std::atan(std::tan(0.5 * fovYRad) * aspect));
    const double distance = std::max(bounds.radius, 1.0) / std::sin(halfFov) * 1.05;
    const glm::dmat3 enu = wgs84.enuFrame(c.lonDeg, c.latDeg);
    const double pitch = glm::radians(60.0);   // looking down 60 degrees, from the south
    const glm::dvec3 back = -enu[1] * std::cos(pitch) + enu[2] * std::sin(pitch);
    return looking(bounds.center + back * distance, bounds.center, enu[2]);
}

globe::Pose blendPoses(const globe::Pose& from, const globe::Pose& to, double f) {
    f = std::clamp(f, 0.0, 1.0);
    const double s = f * f * (3.0 - 2.0 * f);   // ease in and out
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    const globe::Geodetic a = wgs84.toGeodetic(from.position), b = wgs84.toGeodetic(to.position);
    double dLon = b.lonDeg - a.lonDeg;
    if (dLon > 180.0) dLon -= 360.0;
    if (dLon < -180.0) dLon += 360.0;
    const double distance = glm::length(to.position - from.position);
    globe::Geodetic g;
    g.lonDeg = globe::wrapLongitude(a.lonDeg + dLon * s);
    g.latDeg = a.latDeg + (b.latDeg - a.latDeg) * s;
    g.height = a.height + (b.height - a.height) * s + distance / 3.0 * std::sin(glm::pi<double>() * s);
    return {wgs84.toEcef(g), glm::normalize(glm::slerp(from.orientation, to.orientation, s))};
}

}  // namespace orbis::scene
