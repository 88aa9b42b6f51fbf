#include "formats/motion/Attitude.h"

#include "globe/Ellipsoid.h"

#include <cmath>

namespace orbis::motion {
namespace {

constexpr glm::dvec3 kX(1.0, 0.0, 0.0), kY(0.0, 1.0, 0.0), kZ(0.0, 0.0, 1.0);

double degrees(double rad) { return rad * (180.0 / 3.14159265358979323846); }

}  // namespace

glm::dquat nedToEcef(double lonDeg, double latDeg) {
    // Rz(lon) * Ry(-(lat + 90)): x goes to north, y to east, z to down (the columns of
    // SensorModel's nedFrame(), without building the matrix).
    return glm::angleAxis(glm::radians(lonDeg), kZ) * glm::angleAxis(-glm::radians(latDeg + 90.0), kY);
}

glm::dquat bodyToNed(double headingDeg, double pitchDeg, double rollDeg) {
    return glm::angleAxis(glm::radians(headingDeg), kZ) * glm::angleAxis(glm::radians(pitchDeg), kY) *
           glm::angleAxis(glm::radians(rollDeg), kX);
}

glm::dquat bodyToEcef(double lonDeg, double latDeg, double headingDeg, double pitchDeg, double rollDeg) {
    return nedToEcef(lonDeg, latDeg) * bodyToNed(headingDeg, pitchDeg, rollDeg);
}

HeadingPitchRoll headingPitchRoll(const glm::dmat3& r) {
    // Columns of Rz(h) Ry(p) Rx(r): x = (cp ch, cp sh, -sp), y = (.., .., cp sr), z = (.., .., cp cr).
    HeadingPitchRoll a;
    const double horizontal = std::sqrt(r[0][0] * r[0][0] + r[0][1] * r[0][1]);   // unit vectors: no hypot needed
    a.pitchDeg = degrees(std::atan2(-r[0][2], horizontal));
    if (horizontal > 1e-12) {
        a.headingDeg = degrees(std::atan2(r[0][1], r[0][0]));
        a.rollDeg = degrees(std::atan2(r[1][2], r[2][2]));
    } else {   // nose straight up or down: y = (-sin(h - r), cos(h - r), 0) or similar; all turn is heading
        a.headingDeg = degrees(std::atan2(-r[1][0], r[1][1]));
        a.rollDeg = 0.0;
    }
    a.headingDeg = wrapHeadingDeg(a.headingDeg);
    if (a.rollDeg <= -180.0) a.rollDeg += 360.0;
    return a;
}

HeadingPitchRoll headingPitchRoll(const glm::dquat& q, double lonDeg, double latDeg) {
    // The body axes on the local north, east, down vectors (what conjugate(nedToEcef) * q
    // gives, with one sine and cosine each for lon and lat instead of half-angle quaternions).
    const double lon = glm::radians(lonDeg), lat = glm::radians(latDeg);
    const double sl = std::sin(lon), cl = std::cos(lon), sp = std::sin(lat), cp = std::cos(lat);
    const glm::dvec3 north(-sp * cl, -sp * sl, cp), east(-sl, cl, 0.0), down(-cp * cl, -cp * sl, -sp);
    const glm::dmat3 body = glm::mat3_cast(q);
    glm::dmat3 inNed;
    for (int c = 0; c < 3; ++c) inNed[c] = glm::dvec3(glm::dot(body[c], north), glm::dot(body[c], east), glm::dot(body[c], down));
    return headingPitchRoll(inNed);
}

HeadingPitchRoll headingPitchFromDirection(const glm::dvec3& d, double lonDeg, double latDeg) {
    const glm::dmat3 enu = globe::Ellipsoid::wgs84().enuFrame(lonDeg, latDeg);
    const double e = glm::dot(d, enu[0]), n = glm::dot(d, enu[1]), u = glm::dot(d, enu[2]);
    HeadingPitchRoll a;
    const double horizontal = std::hypot(e, n);
    if (horizontal == 0.0 && u == 0.0) return a;
    a.headingDeg = horizontal > 0.0 ? wrapHeadingDeg(degrees(std::atan2(e, n))) : 0.0;
    a.pitchDeg = degrees(std::atan2(u, horizontal));
    return a;
}

glm::dvec3 forwardAxis(const glm::dquat& q) { return q * kX; }
glm::dvec3 rightAxis(const glm::dquat& q) { return q * kY; }
glm::dvec3 upAxis(const glm::dquat& q) { return q * -kZ; }

glm::dmat3 gltfToBody() {
    // Columns: the images of glTF +X (left), +Y (up), +Z (front) in body axes (x forward, y right, z down).
    return glm::dmat3(-kY, -kZ, kX);
}

glm::dmat3 gltfToEcef(const glm::dquat& q) { return glm::mat3_cast(q) * gltfToBody(); }

glm::dquat slerpShortest(const glm::dquat& a, const glm::dquat& bIn, double f) {
    glm::dquat b = bIn;
    if (glm::dot(a, b) < 0.0) b = -b;
    // The angle between a and b in 4-D (half the rotation's angle), from the chord and its
    // complement: precise for every angle, where acos(dot) loses half the digits near 0.
    const glm::dquat diff = b - a, sum = b + a;
    const double half = 2.0 * std::atan2(std::sqrt(glm::dot(diff, diff)), std::sqrt(glm::dot(sum, sum)));
    if (half < 1e-9) return glm::normalize(a + f * diff);   // error ~ half^3: below 1e-27
    const double s = 1.0 / std::sin(half);
    return std::sin((1.0 - f) * half) * s * a + std::sin(f * half) * s * b;
}

double angleBetweenDeg(const glm::dquat& a, const glm::dquat& bIn) {
    glm::dquat b = bIn;
    if (glm::dot(a, b) < 0.0) b = -b;
    const glm::dquat diff = b - a, sum = b + a;
    return degrees(4.0 * std::atan2(std::sqrt(glm::dot(diff, diff)), std::sqrt(glm::dot(sum, sum))));
}

double wrapHeadingDeg(double deg) {
    double w = std::fmod(deg, 360.0);
    if (w < 0.0) w += 360.0;
    if (w >= 360.0) w = 0.0;   // -1e-17 + 360 rounds to 360
    return w;
}

}  // namespace orbis::motion
