#include "ui/input/MapTools.h"

#include "ui/input/InputEvents.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace orbis::ui {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The shell that can hold the ground: below the Challenger Deep (-10 935 m, for bathymetric
// DEMs) and above Everest (8 849 m). A query that reports more under the eye raises the top.
constexpr double kLowestGround = -12000.0;
constexpr double kHighestGround = 9000.0;
// March: steps of a quarter of the starting clearance, growing to 1/64 of the distance from
// the eye (a few pixels of depth at the usual fields of view), at most this many.
constexpr int kMaxMarchSteps = 1024;
constexpr double kRelativeStep = 1.0 / 64.0;
constexpr double kMinStep = 1e-3;
// Bisection down to 1e-12 of the distance (~1e-5 m at 4e7 m, well under a pixel anywhere).
constexpr int kMaxBisections = 64;
constexpr double kBisectionTolerance = 1e-12;
constexpr double kPoleEpsDeg = 1e-9;

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool finite(const glm::dquat& q) {
    return std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}

// The pose's orientation, normalised; nothing for a pose that is not finite.
std::optional<glm::dquat> validOrientation(const globe::Pose& pose) {
    if (!finite(pose.position) || !finite(pose.orientation)) return std::nullopt;
    const double len = glm::length(pose.orientation);
    if (!(len > 1e-12)) return std::nullopt;
    return pose.orientation / len;
}

double groundHeight(const HeightQuery& query, double lonDeg, double latDeg) {
    if (!query) return 0.0;
    const std::optional<double> h = query(lonDeg, latDeg);
    return h && std::isfinite(*h) ? *h : 0.0;
}

// Distances along the ray where it crosses the ellipsoid raised by `height` (first <= second),
// like Ellipsoid::intersectRay but both of them.
std::optional<std::pair<double, double>> shellCrossings(const globe::Ellipsoid& e, const glm::dvec3& origin,
                                                        const glm::dvec3& dir, double height) {
    const double a = e.equatorialRadius() + height, b = e.polarRadius() + height;
    const glm::dvec3 inv(1.0 / a, 1.0 / a, 1.0 / b);
    const glm::dvec3 o = origin * inv, d = dir * inv;
    const double A = glm::dot(d, d), B = 2.0 * glm::dot(o, d), C = glm::dot(o, o) - 1.0;
    const double disc = B * B - 4.0 * A * C;
    if (disc < 0.0 || !(A > 0.0)) return std::nullopt;
    const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
    double t0 = q / A, t1 = q != 0.0 ? C / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    return std::pair{t0, t1};
}

// One point of the march: where it is and how far above the ground.
struct Sample {
    double s = 0.0;
    double clearance = 0.0;
    GroundPoint point;
};

}  // namespace

std::optional<glm::dvec2> projectToWindow(const globe::Pose& pose, double fovYRad, const glm::dvec2& viewportPx, const glm::dvec3& ecef,
                                          double marginPx, const globe::Ellipsoid& ellipsoid) {
    const std::optional<glm::dquat> orientation = validOrientation(pose);
    if (!orientation || !(fovYRad > 0.0 && fovYRad < kPi) || !(viewportPx.x > 0.0) || !(viewportPx.y > 0.0) || !finite(ecef))
        return std::nullopt;
    // Behind the horizon: in the space where the ellipsoid is the unit sphere, a point is hidden
    // when it lies past the plane of the eye's horizon circle and inside the cone of it.
    const glm::dvec3 radii(ellipsoid.equatorialRadius(), ellipsoid.equatorialRadius(), ellipsoid.polarRadius());
    const glm::dvec3 eye = pose.position / radii, point = ecef / radii;
    const double beyond = glm::dot(eye, eye) - 1.0;
    if (beyond > 0.0) {
        const glm::dvec3 toPoint = point - eye;
        const double along = -glm::dot(toPoint, eye);
        if (along > beyond && along * along / glm::dot(toPoint, toPoint) > beyond) return std::nullopt;
    }
    const glm::dvec3 v = glm::conjugate(*orientation) * (ecef - pose.position);
    if (!(v.z < 0.0)) return std::nullopt;
    const double t = std::tan(0.5 * fovYRad), aspect = viewportPx.x / viewportPx.y;
    const glm::dvec2 ndc(v.x / (-v.z * t * aspect), -v.y / (-v.z * t));
    const glm::dvec2 px((ndc.x + 1.0) * 0.5 * viewportPx.x, (ndc.y + 1.0) * 0.5 * viewportPx.y);
    if (px.x < -marginPx || px.y < -marginPx || px.x > viewportPx.x + marginPx || px.y > viewportPx.y + marginPx || !finite(glm::dvec3(px, 0.0)))
        return std::nullopt;
    return px;
}

std::optional<GroundPoint> pick(const globe::Pose& pose, double fovYRad, double aspect, const glm::dvec2& ndc,
                                const HeightQuery& heightQuery, const globe::Ellipsoid& ellipsoid) {
    const std::optional<glm::dquat> orientation = validOrientation(pose);
    if (!orientation || !(fovYRad > 0.0 && fovYRad < kPi) || !(aspect > 0.0) || !std::isfinite(aspect) ||
        !std::isfinite(ndc.x) || !std::isfinite(ndc.y))
        return std::nullopt;
    const double t = std::tan(0.5 * fovYRad);
    const glm::dvec3 eye = pose.position;
    const glm::dvec3 dir = glm::normalize(*orientation * glm::dvec3(ndc.x * t * aspect, -ndc.y * t, -1.0));
    if (!finite(dir)) return std::nullopt;

    if (!heightQuery) {
        if (!(ellipsoid.toGeodetic(eye).height > 0.0)) return std::nullopt;
        const std::optional<double> s = ellipsoid.intersectRay(eye, dir, 0.0);
        if (!s) return std::nullopt;
        GroundPoint p{ellipsoid.toGeodetic(eye + dir * *s), eye + dir * *s, *s};
        p.geodetic.height = 0.0;
        return p;
    }

    auto sample = [&](double s) {
        Sample x;
        x.s = s;
        x.point.ecef = eye + dir * s;
        x.point.distance = s;
        x.point.geodetic = ellipsoid.toGeodetic(x.point.ecef);
        const double ground = groundHeight(heightQuery, x.point.geodetic.lonDeg, x.point.geodetic.latDeg);
        x.clearance = x.point.geodetic.height - ground;
        x.point.geodetic.height = ground;
        return x;
    };
    const Sample atEye = sample(0.0);
    if (!(atEye.clearance > 0.0)) return std::nullopt;

    // The part of the ray inside the shell that can hold the ground.
    const double top = std::max(kHighestGround, atEye.point.geodetic.height);
    const auto topCrossings = shellCrossings(ellipsoid, eye, dir, top);
    if (!topCrossings || !(topCrossings->second > 0.0)) return std::nullopt;
    const double sStart = std::max(topCrossings->first, 0.0);
    double sEnd = topCrossings->second;
    if (const auto bottom = shellCrossings(ellipsoid, eye, dir, kLowestGround); bottom && bottom->first > sStart)
        sEnd = std::min(sEnd, bottom->first);

    Sample a = sStart > 0.0 ? sample(sStart) : atEye;
    if (!(a.clearance > 0.0)) return a.point;   // ground above the assumed top where the ray enters
    const double minStep = std::max(0.25 * a.clearance, kMinStep);
    for (int i = 0; i < kMaxMarchSteps && a.s < sEnd; ++i) {
        const double next = i + 1 == kMaxMarchSteps ? sEnd : std::min(a.s + std::max(minStep, a.s * kRelativeStep), sEnd);
        Sample b = sample(next);
        if (!(b.clearance > 0.0)) {
            for (int k = 0; k < kMaxBisections && b.s - a.s > kBisectionTolerance * std::max(b.s, 1.0); ++k) {
                Sample mid = sample(0.5 * (a.s + b.s));
                (mid.clearance > 0.0 ? a : b) = std::move(mid);
            }
            return b.point;
        }
        a = std::move(b);
    }
    return std::nullopt;
}

std::optional<double> metresPerPixel(const globe::Pose& pose, double fovYRad, const glm::dvec2& viewportPx,
                                     const glm::dvec2& atPx, const HeightQuery& heightQuery,
                                     const globe::Ellipsoid& ellipsoid) {
    const ViewportSize viewport{viewportPx.x, viewportPx.y};
    const std::optional<glm::dvec2> ndcA = toNdc(atPx, viewport), ndcB = toNdc(atPx + glm::dvec2(1.0, 0.0), viewport);
    if (!ndcA || !ndcB || !(fovYRad > 0.0 && fovYRad < kPi) || !validOrientation(pose)) return std::nullopt;
    const double aspect = viewport.aspect();
    const auto a = pick(pose, fovYRad, aspect, *ndcA, heightQuery, ellipsoid);
    const auto b = a ? pick(pose, fovYRad, aspect, *ndcB, heightQuery, ellipsoid) : std::nullopt;
    if (a && b) {
        const double d = glm::length(a->ecef - b->ecef);
        if (d > 0.0 && std::isfinite(d)) return d;
    }
    // Off the globe (or on its rim): a pixel at the eye's height above the ground.
    const globe::Geodetic g = ellipsoid.toGeodetic(pose.position);
    const double range = g.height - groundHeight(heightQuery, g.lonDeg, g.latDeg);
    if (!(range > 0.0)) return std::nullopt;
    return 2.0 * range * std::tan(0.5 * fovYRad) / viewport.height;
}

std::optional<ScaleBar> niceScaleBar(double metresPerPixel, double maxWidthPx) {
    if (!(metresPerPixel > 0.0) || !std::isfinite(metresPerPixel) || !(maxWidthPx >= 1.0) || !std::isfinite(maxWidthPx))
        return std::nullopt;
    const double maxMetres = metresPerPixel * maxWidthPx;
    if (!std::isfinite(maxMetres) || !(maxMetres > 0.0)) return std::nullopt;
    // The power of ten at or below maxMetres; log10 may round either way, so check both sides.
    double decade = std::pow(10.0, std::floor(std::log10(maxMetres)));
    if (decade > maxMetres) decade /= 10.0;
    if (decade * 10.0 <= maxMetres) decade *= 10.0;
    double metres = decade;
    for (const double m : {5.0, 2.0}) {
        if (m * decade <= maxMetres) {
            metres = m * decade;
            break;
        }
    }
    ScaleBar bar;
    bar.metres = metres;
    bar.widthPx = std::min(metres / metresPerPixel, maxWidthPx);
    char text[32];
    if (metres >= 1000.0) std::snprintf(text, sizeof text, "%g km", metres / 1000.0);
    else std::snprintf(text, sizeof text, "%g m", metres);
    bar.label = text;
    return bar;
}

double compassHeadingDeg(const globe::Pose& pose, const globe::Ellipsoid& ellipsoid) {
    const std::optional<glm::dquat> orientation = validOrientation(pose);
    if (!orientation) return 0.0;
    const glm::dvec3 eye = pose.position;
    const glm::dvec3 forward = *orientation * glm::dvec3(0.0, 0.0, -1.0), up = *orientation * glm::dvec3(0.0, 1.0, 0.0);
    glm::dvec3 ground = eye;
    if (ellipsoid.toGeodetic(eye).height > 0.0)
        if (const auto s = ellipsoid.intersectRay(eye, forward, 0.0)) ground = eye + forward * *s;
    const globe::Geodetic g = ellipsoid.toGeodetic(ground);
    if (std::abs(g.latDeg) >= 90.0 - kPoleEpsDeg) return g.latDeg > 0.0 ? 0.0 : 180.0;
    const glm::dmat3 enuT = glm::transpose(ellipsoid.enuFrame(g.lonDeg, g.latDeg));
    const glm::dvec3 f = enuT * forward, u = enuT * up;
    // For an unrolled camera the horizontal parts of forward and of up (flipped when looking
    // up) both point along the heading, and their sum never vanishes: straight down the top of
    // the screen gives the heading, level the view direction does, with no switch between.
    const glm::dvec3 v = f + (f.z <= 0.0 ? u : -u);
    if (!(std::hypot(v.x, v.y) > 1e-12)) return 0.0;
    double heading = glm::degrees(std::atan2(v.x, v.y));
    if (heading < 0.0) heading += 360.0;
    return heading < 360.0 ? heading : 0.0;   // -1e-17 + 360 rounds to 360
}

}  // namespace orbis::ui
