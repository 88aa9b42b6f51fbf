#include "globe/Geodesic.h"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/GeodesicLine.hpp>
#include <GeographicLib/PolygonArea.hpp>

#include <algorithm>
#include <cmath>

namespace orbis::globe {
namespace {

const GeographicLib::Geodesic& wgs84() { return GeographicLib::Geodesic::WGS84(); }

}  // namespace

PathLength geodesicLength(std::span<const LonLat> points) {
    PathLength out;
    if (points.empty()) return out;
    out.along.reserve(points.size());
    out.along.push_back(0.0);
    for (size_t i = 1; i < points.size(); ++i) {
        double s12 = 0.0;
        wgs84().Inverse(points[i - 1].y, points[i - 1].x, points[i].y, points[i].x, s12);
        out.metres += s12;
        out.along.push_back(out.metres);
    }
    return out;
}

GeodesicLeg geodesicBetween(const LonLat& a, const LonLat& b) {
    GeodesicLeg leg;
    wgs84().Inverse(a.y, a.x, b.y, b.x, leg.metres, leg.azimuthStartDeg, leg.azimuthEndDeg);
    return leg;
}

PolygonMeasure geodesicPolygon(std::span<const LonLat> ring) {
    PolygonMeasure out;
    size_t n = ring.size();
    if (n > 1 && ring[n - 1] == ring[0]) --n;
    if (n < 3) return out;
    GeographicLib::PolygonArea polygon(wgs84());
    for (size_t i = 0; i < n; ++i) polygon.AddPoint(ring[i].y, ring[i].x);
    double perimeter = 0.0, area = 0.0;
    // reverse = false, sign = true: signed, counter-clockwise positive, within +-half the Earth.
    polygon.Compute(false, true, perimeter, area);
    out.areaM2 = std::abs(area);
    out.perimeterM = perimeter;
    out.vertices = n;
    return out;
}

std::vector<LonLat> geodesicPoints(const LonLat& a, const LonLat& b, double stepM, size_t maxPoints) {
    double s12 = 0.0, azi1 = 0.0, azi2 = 0.0;
    wgs84().Inverse(a.y, a.x, b.y, b.x, s12, azi1, azi2);
    maxPoints = std::max<size_t>(maxPoints, 2);
    const size_t steps = std::clamp<size_t>(size_t(std::ceil(s12 / std::max(stepM, 1e-3))), 1, maxPoints - 1);
    using G = GeographicLib::Geodesic;
    const GeographicLib::GeodesicLine line = wgs84().Line(a.y, a.x, azi1, G::LATITUDE | G::LONGITUDE | G::DISTANCE_IN);
    std::vector<LonLat> out;
    out.reserve(steps + 1);
    out.push_back(a);
    for (size_t i = 1; i < steps; ++i) {
        double lat = 0.0, lon = 0.0, unused = 0.0;
        // Unrolled: the longitude goes on from a's across the antimeridian.
        line.GenPosition(false, s12 * double(i) / double(steps), G::LATITUDE | G::LONGITUDE | G::LONG_UNROLL, lat, lon, unused,
                         unused, unused, unused, unused, unused);
        out.push_back({lon, lat});
    }
    // b, with its longitude on a's side of the antimeridian.
    double last = b.x;
    const double before = out.back().x;
    while (last - before > 180.0) last -= 360.0;
    while (before - last > 180.0) last += 360.0;
    out.push_back({last, b.y});
    return out;
}

double ellipsoidArea() { return wgs84().EllipsoidArea(); }

}  // namespace orbis::globe
