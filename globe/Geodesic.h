#pragma once
// Measures on the WGS84 ellipsoid: the geodesic length of a path, the geodesic area and
// perimeter of a polygon, and points along each geodesic to draw it (GeographicLib: Karney's
// algorithms, accurate to nanometres at any distance, across the antimeridian and over the
// poles). Angles in degrees, lengths in metres, areas in square metres. No Vulkan.
//
// A polygon is a ring of vertices joined by geodesics, closed by the last to the first (a
// repeated first vertex at the end is the same ring). Its area is that of the region on the
// left of the ring walked in order, or on its right: whichever is smaller than half the Earth,
// so that the order of the vertices does not matter; `area` is positive. A ring around a pole
// encloses that pole (GeographicLib counts the crossings of the prime meridian).

#include <glm/glm.hpp>

#include <span>
#include <vector>

namespace orbis::globe {

/// A place on the ellipsoid: x longitude, y latitude (degrees).
using LonLat = glm::dvec2;

struct PathLength {
    double metres = 0.0;
    /// The distance from the first vertex to each vertex (the first is 0).
    std::vector<double> along;
};

/// The length of a path of geodesics through `points`. Fewer than two points: 0.
PathLength geodesicLength(std::span<const LonLat> points);

/// The distance, the azimuths (degrees clockwise from north) at each end, from a to b.
struct GeodesicLeg {
    double metres = 0.0;
    double azimuthStartDeg = 0.0, azimuthEndDeg = 0.0;
};
GeodesicLeg geodesicBetween(const LonLat& a, const LonLat& b);

struct PolygonMeasure {
    double areaM2 = 0.0;      ///< the smaller of the two regions the ring bounds
    double perimeterM = 0.0;
    size_t vertices = 0;      ///< after dropping a closing repeat of the first
};

/// The geodesic polygon through `ring`. Fewer than three distinct vertices: all 0.
PolygonMeasure geodesicPolygon(std::span<const LonLat> ring);

/// Points along the geodesic from a to b, no more than `stepM` apart (and at most
/// `maxPoints`), a and b included; longitudes continue across the antimeridian from a's (they
/// may leave [-180, 180]) so that the points make a line without a jump.
std::vector<LonLat> geodesicPoints(const LonLat& a, const LonLat& b, double stepM, size_t maxPoints = 4096);

/// The surface area of the whole ellipsoid (m^2), for checks.
double ellipsoidArea();

}  // namespace orbis::globe
