#include "globe/Ellipsoid.h"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Geocentric.hpp>

#include <cmath>

namespace orbis::globe {

Ellipsoid::Ellipsoid(double a, double f) : a_(a), f_(f), b_(a * (1.0 - f)) {}

const Ellipsoid& Ellipsoid::wgs84() {
    static const Ellipsoid e(GeographicLib::Constants::WGS84_a(), GeographicLib::Constants::WGS84_f());
    return e;
}

glm::dvec3 Ellipsoid::toEcef(double lonDeg, double latDeg, double height) const {
    glm::dvec3 out;
    GeographicLib::Geocentric::WGS84().Forward(latDeg, lonDeg, height, out.x, out.y, out.z);
    return out;
}

Geodetic Ellipsoid::toGeodetic(const glm::dvec3& ecef) const {
    Geodetic g;
    GeographicLib::Geocentric::WGS84().Reverse(ecef.x, ecef.y, ecef.z, g.latDeg, g.lonDeg, g.height);
    return g;
}

glm::dmat3 Ellipsoid::enuFrame(double lonDeg, double latDeg) const {
    const double lon = glm::radians(lonDeg), lat = glm::radians(latDeg);
    const double sl = std::sin(lon), cl = std::cos(lon), sp = std::sin(lat), cp = std::cos(lat);
    const glm::dvec3 east(-sl, cl, 0.0);
    const glm::dvec3 north(-sp * cl, -sp * sl, cp);
    const glm::dvec3 up(cp * cl, cp * sl, sp);
    return glm::dmat3(east, north, up);
}

glm::dvec3 Ellipsoid::surfaceNormal(double lonDeg, double latDeg) const { return enuFrame(lonDeg, latDeg)[2]; }

std::optional<double> Ellipsoid::intersectRay(const glm::dvec3& origin, const glm::dvec3& direction,
                                              double height) const {
    // Scale space so the (raised) ellipsoid becomes the unit sphere, then solve the quadratic
    // in the numerically stable form (no cancellation when the ray grazes the surface).
    const glm::dvec3 inv(1.0 / (a_ + height), 1.0 / (a_ + height), 1.0 / (b_ + height));
    const glm::dvec3 o = origin * inv, d = direction * inv;
    const double A = glm::dot(d, d), B = 2.0 * glm::dot(o, d), C = glm::dot(o, o) - 1.0;
    const double disc = B * B - 4.0 * A * C;
    if (disc < 0.0 || A <= 0.0) return std::nullopt;
    const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
    double t0 = q / A, t1 = q != 0.0 ? C / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    if (t1 < 0.0) return std::nullopt;
    return t0 >= 0.0 ? t0 : t1;   // origin inside: the exit point
}

double wrapLongitude(double lonDeg) {
    double w = std::fmod(lonDeg + 180.0, 360.0);
    if (w < 0.0) w += 360.0;
    return w - 180.0;
}

}  // namespace orbis::globe
