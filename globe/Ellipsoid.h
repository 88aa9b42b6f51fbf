#pragma once
// The WGS84 ellipsoid: geodetic <-> ECEF through GeographicLib (exact, stable at the poles),
// local east-north-up frames and ray intersection. Angles in degrees where named ...Deg,
// distances in metres. No Vulkan.

#include <glm/glm.hpp>

#include <optional>

namespace orbis::globe {

struct Geodetic {
    double lonDeg = 0.0;
    double latDeg = 0.0;
    double height = 0.0;   ///< above the ellipsoid, metres
};

class Ellipsoid {
public:
    static const Ellipsoid& wgs84();

    double equatorialRadius() const { return a_; }
    double polarRadius() const { return b_; }
    double flattening() const { return f_; }

    glm::dvec3 toEcef(double lonDeg, double latDeg, double height = 0.0) const;
    glm::dvec3 toEcef(const Geodetic& g) const { return toEcef(g.lonDeg, g.latDeg, g.height); }
    Geodetic toGeodetic(const glm::dvec3& ecef) const;

    /// Columns: east, north, up (geodetic normal) in ECEF. Well defined at the poles: east is
    /// taken from the given longitude.
    glm::dmat3 enuFrame(double lonDeg, double latDeg) const;
    glm::dvec3 surfaceNormal(double lonDeg, double latDeg) const;

    /// Distance along `direction` (unit) from `origin` to the first hit with the ellipsoid
    /// raised by `height`; nothing when the ray misses or points away.
    std::optional<double> intersectRay(const glm::dvec3& origin, const glm::dvec3& direction,
                                       double height = 0.0) const;

private:
    Ellipsoid(double a, double f);
    double a_, f_, b_;
};

/// Wraps a longitude into [-180, 180).
double wrapLongitude(double lonDeg);

}  // namespace orbis::globe
