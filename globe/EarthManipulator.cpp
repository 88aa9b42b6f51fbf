#include "globe/EarthManipulator.h"

#include <algorithm>
#include <cmath>

namespace orbis::globe {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kPoleEpsDeg = 1e-9;
// Flight arc: the range rises by half the ground distance at mid-flight (a 45-degree view then
// still holds both ends of most flights), capped so that antipodal flights stay near the Moon's
// side of sanity (15 000 km up).
constexpr double kArcPerDistance = 0.5;
constexpr double kMaxArc = 1.5e7;
// Zooming out stops this far from the ground point (beyond it the globe is a few pixels).
constexpr double kMaxZoomDistance = 1.0e9;

// Unit normal ("n-vector") of a geodetic lon/lat: the great-circle arithmetic of navigation.
glm::dvec3 nVector(double lonDeg, double latDeg) {
    const double lon = glm::radians(lonDeg), lat = glm::radians(latDeg);
    return {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
}

// At a pole every longitude names the same point but a different "north"; re-expresses `v` with
// longitude `lon`, turning the heading so that the camera looks the same way.
Viewpoint reexpressAtPole(Viewpoint v, double lon) {
    if (v.latDeg >= 90.0 - kPoleEpsDeg) v.headingDeg += lon - v.lonDeg;
    else if (v.latDeg <= -90.0 + kPoleEpsDeg) v.headingDeg -= lon - v.lonDeg;
    else return v;
    v.lonDeg = lon;
    return v;
}

bool atPole(const Viewpoint& v) { return std::abs(v.latDeg) >= 90.0 - kPoleEpsDeg; }

// The rotation taking unit vector `from` to unit vector `to` about their common normal.
glm::dquat rotationBetween(const glm::dvec3& from, const glm::dvec3& to) {
    const glm::dvec3 axis = glm::cross(from, to);
    const double s = glm::length(axis);
    if (s < 1e-15) return glm::dquat(1.0, 0.0, 0.0, 0.0);
    return glm::angleAxis(std::atan2(s, glm::dot(from, to)), axis / s);
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

double easeInOut(double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

Viewpoint interpolateFlight(const Viewpoint& a0, const Viewpoint& b0, double t) {
    if (!(t > 0.0)) return a0;
    if (t >= 1.0) return b0;
    // A pole endpoint takes the longitude of the meridian the path leaves or reaches it by, so
    // the heading does not jump when the longitude becomes meaningful again.
    Viewpoint a = a0, b = b0;
    if (atPole(a) && !atPole(b)) a = reexpressAtPole(a, b.lonDeg);
    if (atPole(b) && !atPole(a)) b = reexpressAtPole(b, a.lonDeg);

    const glm::dvec3 na = nVector(a.lonDeg, a.latDeg), nb = nVector(b.lonDeg, b.latDeg);
    const double omega = std::atan2(glm::length(glm::cross(na, nb)), glm::dot(na, nb));
    glm::dvec3 n;
    if (omega < 1e-12) {
        n = na;
    } else if (kPi - omega < 1e-9) {
        // Antipodes: every great circle joins them; take the one through the poles (or, from a
        // pole, along a's meridian) so the choice is deterministic.
        glm::dvec3 axis = glm::cross(na, glm::dvec3(0.0, 0.0, 1.0));
        if (glm::length(axis) < 1e-9) axis = glm::dvec3(-std::sin(glm::radians(a.lonDeg)), std::cos(glm::radians(a.lonDeg)), 0.0);
        n = glm::angleAxis(t * omega, glm::normalize(axis)) * na;
    } else {
        n = (std::sin((1.0 - t) * omega) * na + std::sin(t * omega) * nb) / std::sin(omega);
    }
    Viewpoint v;
    v.latDeg = glm::degrees(std::atan2(n.z, std::hypot(n.x, n.y)));
    v.lonDeg = std::hypot(n.x, n.y) > 1e-15 ? glm::degrees(std::atan2(n.y, n.x)) : a.lonDeg;
    v.height = a.height + (b.height - a.height) * t;
    v.headingDeg = a.headingDeg + wrapLongitude(b.headingDeg - a.headingDeg) * t;   // short way round
    v.pitchDeg = a.pitchDeg + (b.pitchDeg - a.pitchDeg) * t;
    const double groundDistance = Ellipsoid::wgs84().equatorialRadius() * omega;
    v.range = a.range + (b.range - a.range) * t +
              std::min(kArcPerDistance * groundDistance, kMaxArc) * 4.0 * t * (1.0 - t);
    return v;
}

EarthManipulator::EarthManipulator(const Ellipsoid& ellipsoid) : ellipsoid_(&ellipsoid) {
    pose_ = poseFromViewpoint(Viewpoint{}, ellipsoid);
}

double EarthManipulator::terrainHeight(double lonDeg, double latDeg) const {
    if (!heightQuery_) return 0.0;
    const std::optional<double> h = heightQuery_(lonDeg, latDeg);
    return h && std::isfinite(*h) ? *h : 0.0;
}

glm::dvec3 EarthManipulator::rayDirection(const glm::dvec2& ndc) const {
    const double t = std::tan(0.5 * fovYRad_);
    return glm::normalize(pose_.orientation * glm::dvec3(ndc.x * t * aspect_, -ndc.y * t, -1.0));
}

std::optional<glm::dvec3> EarthManipulator::intersectGround(const glm::dvec3& origin, const glm::dvec3& direction) const {
    const double eyeHeight = ellipsoid_->toGeodetic(origin).height;
    std::optional<glm::dvec3> hit;
    double h = 0.0;
    // Fixed-point on the terrain height at the hit: converges in a step or two unless the ray
    // grazes a slope, and never returns a surface above the eye (intersectRay would give the
    // exit point from inside).
    for (int i = 0; i < 4 && h < eyeHeight; ++i) {
        const std::optional<double> t = ellipsoid_->intersectRay(origin, direction, h);
        if (!t) break;
        hit = origin + direction * *t;
        const Geodetic g = ellipsoid_->toGeodetic(*hit);
        const double hNext = terrainHeight(g.lonDeg, g.latDeg);
        if (std::abs(hNext - h) < 1e-3) break;
        h = hNext;
    }
    return hit;
}

glm::dvec3 EarthManipulator::pivot() const {
    const glm::dvec3 eye = pose_.position, forward = pose_.orientation * glm::dvec3(0.0, 0.0, -1.0);
    if (auto hit = intersectGround(eye, forward)) return *hit;
    // Looking past the globe: the point of the centre ray nearest the Earth's centre (or, when
    // looking away from it, a point at the horizon distance), in the air. The viewpoint then
    // still reproduces the pose exactly.
    const double nearest = -glm::dot(eye, forward);
    const double horizon = std::sqrt(std::max(glm::dot(eye, eye) - std::pow(ellipsoid_->equatorialRadius(), 2), 1.0));
    return eye + forward * (nearest > 0.0 ? nearest : horizon);
}

Viewpoint EarthManipulator::viewpoint() const {
    const glm::dvec3 target = pivot();
    const Geodetic g = ellipsoid_->toGeodetic(target);
    const glm::dmat3 enuT = glm::transpose(ellipsoid_->enuFrame(g.lonDeg, g.latDeg));
    const glm::dvec3 f = enuT * (pose_.orientation * glm::dvec3(0.0, 0.0, -1.0));
    const glm::dvec3 r = enuT * (pose_.orientation * glm::dvec3(1.0, 0.0, 0.0));
    Viewpoint vp;
    vp.lonDeg = g.lonDeg;
    vp.latDeg = g.latDeg;
    vp.height = g.height;
    vp.pitchDeg = glm::degrees(std::asin(std::clamp(f.z, -1.0, 1.0)));
    // The heading of the view direction keeps what is looked at; straight down it is undefined
    // and the right vector (horizontal for an unrolled camera: (cos h, -sin h, 0)) gives it.
    vp.headingDeg = std::hypot(f.x, f.y) > 0.1 ? glm::degrees(std::atan2(f.x, f.y)) : glm::degrees(std::atan2(-r.y, r.x));
    vp.range = glm::length(pose_.position - target);
    return vp;
}

void EarthManipulator::keepAboveTerrain() {
    const Geodetic g = ellipsoid_->toGeodetic(pose_.position);
    const double floor = std::max(terrainHeight(g.lonDeg, g.latDeg), 0.0) + minClearance_;
    // Geodetic height is measured along the normal, so a step along it raises it exactly.
    if (g.height < floor) pose_.position += ellipsoid_->surfaceNormal(g.lonDeg, g.latDeg) * (floor - g.height);
}

void EarthManipulator::applyViewpoint(const Viewpoint& vp) {
    const Pose p = poseFromViewpoint(vp, *ellipsoid_);
    if (!finite(p.position)) return;   // a bad viewpoint leaves the camera where it was
    pose_ = p;
    keepAboveTerrain();
}

void EarthManipulator::setPose(const Pose& pose) {
    flying_ = false;
    if (!finite(pose.position)) return;
    pose_.position = pose.position;
    pose_.orientation = glm::normalize(pose.orientation);
    keepAboveTerrain();
}

void EarthManipulator::setViewpoint(const Viewpoint& vp) {
    flying_ = false;
    Viewpoint v = vp;
    v.pitchDeg = std::clamp(v.pitchDeg, kMinPitchDeg, kMaxPitchDeg);
    applyViewpoint(v);
}

void EarthManipulator::rotateAboutCentre(const glm::dquat& q) {
    pose_.position = q * pose_.position;
    pose_.orientation = glm::normalize(q * pose_.orientation);
}

void EarthManipulator::rotate(const glm::dvec2& fromNdc, const glm::dvec2& toNdc) {
    flying_ = false;
    const glm::dvec3 eye = pose_.position;
    if (const auto p0 = intersectGround(eye, rayDirection(fromNdc))) {
        // Where the ray through `toNdc` meets the sphere through the grabbed point: rotating the
        // camera by the rotation taking that point to the grabbed one puts the grabbed point on
        // the new ray (rotations about the centre keep the sphere).
        const glm::dvec3 d = rayDirection(toNdc);
        const double b = glm::dot(eye, d);
        const double c = glm::dot(eye, eye) - glm::dot(*p0, *p0);
        const double disc = b * b - c;
        if (disc >= 0.0) {
            const double root = std::sqrt(disc);
            const double t = c > 0.0 ? -b - root : -b + root;   // eye inside the sphere: the far side
            if (t > 0.0) {
                rotateAboutCentre(rotationBetween(glm::normalize(eye + d * t), glm::normalize(*p0)));
                keepAboveTerrain();
                return;
            }
        }
    }
    // A cursor off the globe: turn the globe in proportion to the drag, at the rate that moves
    // the ground below the camera with the cursor.
    const glm::dvec2 drag = toNdc - fromNdc;
    const double height = std::max(ellipsoid_->toGeodetic(eye).height, 1.0);
    const double k = std::tan(0.5 * fovYRad_) * height / ellipsoid_->equatorialRadius();
    const double yaw = std::clamp(-drag.x * aspect_ * k, -0.5 * kPi, 0.5 * kPi);
    const double pitch = std::clamp(-drag.y * k, -0.5 * kPi, 0.5 * kPi);
    const glm::dvec3 upW = pose_.orientation * glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 rightW = pose_.orientation * glm::dvec3(1.0, 0.0, 0.0);
    rotateAboutCentre(glm::angleAxis(yaw, upW) * glm::angleAxis(pitch, rightW));
    keepAboveTerrain();
}

void EarthManipulator::zoom(double factor, const glm::dvec2& cursorNdc) {
    flying_ = false;
    if (!(factor > 0.0) || !std::isfinite(factor)) return;
    const glm::dvec3 eye = pose_.position;
    std::optional<glm::dvec3> p = intersectGround(eye, rayDirection(cursorNdc));
    if (!p) p = intersectGround(eye, rayDirection({0.0, 0.0}));
    if (!p) {
        // Nothing under the cursor or the centre: scale the height instead.
        const Geodetic g = ellipsoid_->toGeodetic(eye);
        pose_.position += ellipsoid_->surfaceNormal(g.lonDeg, g.latDeg) * (g.height * (factor - 1.0));
    } else {
        const double dist = glm::length(eye - *p);
        if (dist * factor > kMaxZoomDistance) factor = std::max(kMaxZoomDistance / dist, 1.0);
        pose_.position = *p + (eye - *p) * factor;   // along the cursor ray: the point stays put
    }
    keepAboveTerrain();
}

void EarthManipulator::pan(const glm::dvec2& fromNdc, const glm::dvec2& toNdc) {
    flying_ = false;
    const glm::dvec3 eye = pose_.position, target = pivot();
    const Geodetic g = ellipsoid_->toGeodetic(target);
    const glm::dvec3 up = ellipsoid_->surfaceNormal(g.lonDeg, g.latDeg);
    const double range = std::max(glm::length(target - eye), 1.0);
    // Hits of both cursor rays on the pivot's tangent plane; when either misses (a ray at or
    // above the horizon), the drag is scaled by the range instead.
    auto onPlane = [&](const glm::dvec2& ndc) -> std::optional<glm::dvec3> {
        const glm::dvec3 d = rayDirection(ndc);
        const double denom = glm::dot(d, up);
        if (denom > -1e-6) return std::nullopt;
        const double t = glm::dot(target - eye, up) / denom;
        if (t <= 0.0 || t > 100.0 * range) return std::nullopt;
        return eye + d * t;
    };
    glm::dvec3 shift;
    const auto a = onPlane(fromNdc), b = onPlane(toNdc);
    if (a && b) {
        shift = *a - *b;
    } else {
        const double s = range * std::tan(0.5 * fovYRad_);
        const glm::dvec2 drag = toNdc - fromNdc;
        shift = (pose_.orientation * glm::dvec3(-drag.x * aspect_ * s, drag.y * s, 0.0));
        shift -= up * glm::dot(shift, up);
    }
    // Moving the pivot by a rotation about the centre keeps the view's heading and pitch
    // relative to the local horizon (exactly on a sphere) and never flips heading at a pole.
    rotateAboutCentre(rotationBetween(glm::normalize(target), glm::normalize(target + shift)));
    keepAboveTerrain();
}

void EarthManipulator::tilt(double deltaDeg) {
    flying_ = false;
    Viewpoint vp = viewpoint();
    vp.pitchDeg = std::clamp(vp.pitchDeg + deltaDeg, kMinPitchDeg, kMaxPitchDeg);
    applyViewpoint(vp);
}

void EarthManipulator::turn(double deltaDeg) {
    flying_ = false;
    Viewpoint vp = viewpoint();
    vp.headingDeg = wrapLongitude(vp.headingDeg + deltaDeg);
    vp.pitchDeg = std::clamp(vp.pitchDeg, kMinPitchDeg, kMaxPitchDeg);
    applyViewpoint(vp);
}

void EarthManipulator::flyTo(const Viewpoint& target, double durationSeconds) {
    Viewpoint to = target;
    to.pitchDeg = std::clamp(to.pitchDeg, kMinPitchDeg, kMaxPitchDeg);
    if (!(durationSeconds > 0.0) || !std::isfinite(durationSeconds)) {
        setViewpoint(to);
        return;
    }
    flightFrom_ = viewpoint();
    flightTo_ = to;
    flightDuration_ = durationSeconds;
    flightElapsed_ = 0.0;
    flying_ = true;
}

void EarthManipulator::advance(double dtSeconds) {
    if (!flying_) return;
    flightElapsed_ += std::max(dtSeconds, 0.0);
    const double t = flightElapsed_ / flightDuration_;
    if (t >= 1.0) {
        flying_ = false;
        applyViewpoint(flightTo_);
        return;
    }
    applyViewpoint(interpolateFlight(flightFrom_, flightTo_, easeInOut(t)));
}

}  // namespace orbis::globe
