#include "layers/vector/FeaturePick.h"

#include "layers/vector/FeatureClip.h"
#include "layers/vector/LonLatGeometry.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace orbis::vector {
namespace {

constexpr double kMetresPerDegree = 111320.0;

/// The query point's longitude moved by whole turns next to `lonDeg`.
double lonNear(double queryLon, double lonDeg) { return queryLon + 360.0 * std::round((lonDeg - queryLon) / 360.0); }

/// Distance in metres from the query to the segment a-b, in a plane tangent at the query
/// (longitudes scaled by the cosine of its latitude; the segment moved next to the query).
double segmentDistanceM(const PickQuery& q, const glm::dvec3& a, const glm::dvec3& b) {
    const double k = std::cos(glm::radians(q.latDeg));
    const double shift = lonNear(a.x, q.lonDeg) - a.x;   // move the segment by whole turns near the query
    const glm::dvec2 pa{(a.x + shift - q.lonDeg) * k, a.y - q.latDeg}, pb{(b.x + shift - q.lonDeg) * k, b.y - q.latDeg};
    return std::sqrt(segmentDistance2(glm::dvec2(0.0), pa, pb)) * kMetresPerDegree;
}

/// Even-odd crossings of the horizontal ray from (lon, lat) with a ring.
bool crossesOdd(std::span<const glm::dvec3> ring, double lon, double lat) {
    bool inside = false;
    for (size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
        const glm::dvec3 &a = ring[i], &b = ring[j];
        if ((a.y > lat) != (b.y > lat) && lon < (b.x - a.x) * (lat - a.y) / (b.y - a.y) + a.x) inside = !inside;
    }
    return inside;
}

bool polygonContains(const Feature& f, const PickQuery& q) {
    std::vector<glm::dvec3> closed;
    for (size_t k = 0; k < f.polygons.size(); ++k) {
        bool inside = false;
        for (size_t p = f.polygons[k]; p < f.polygonEnd(k); ++p) {
            std::span<const glm::dvec3> ring = f.part(p);
            if (ring.size() < 3) continue;
            const int8_t pole = p < f.containsPole.size() ? f.containsPole[p] : 0;
            if (pole != 0) {   // bounds the polar cap once closed through the pole
                closed.assign(ring.begin(), ring.end());
                closeThroughPole(closed, pole);
                ring = closed;
            }
            // The ring's longitudes are continuous: test the query at the turn nearest the ring.
            const double lon = lonNear(q.lonDeg, ring.front().x);
            bool odd = false;
            for (double shift : {-360.0, 0.0, 360.0}) odd = odd || crossesOdd(ring, lon + shift, q.latDeg);
            if (odd) inside = !inside;   // the outer ring, then each hole it falls in
        }
        if (inside) return true;
    }
    return false;
}

bool hits(const Feature& f, const FeatureStyle& s, const PickQuery& q) {
    const double slopM = q.slopPx * q.metresPerPixel;
    switch (f.kind) {
        case GeometryKind::Points: {
            const double reach = 0.5 * s.iconSizePx * q.metresPerPixel + slopM;
            for (const glm::dvec3& c : f.coords)
                if (segmentDistanceM(q, c, c) <= reach) return true;
            return false;
        }
        case GeometryKind::Lines: {
            const double reach = 0.5 * s.widthPx * q.metresPerPixel + slopM;
            for (size_t p = 0; p < f.parts.size(); ++p) {
                const auto part = f.part(p);
                for (size_t i = 1; i < part.size(); ++i)
                    if (segmentDistanceM(q, part[i - 1], part[i]) <= reach) return true;
            }
            return false;
        }
        case GeometryKind::Polygons:
            return polygonContains(f, q);
    }
    return false;
}

}  // namespace

std::optional<PickedFeature> pickFeature(const VectorContent& content, const ContentStyles& styles, const PickQuery& query) {
    if (!std::isfinite(query.lonDeg) || !std::isfinite(query.latDeg) || !(query.metresPerPixel > 0.0)) return std::nullopt;
    // Box test first: anything within the largest reach of the point.
    const double reachDeg = (64.0 + query.slopPx) * query.metresPerPixel / kMetresPerDegree /
                            std::max(std::cos(glm::radians(query.latDeg)), 1e-6);
    for (GeometryKind kind : {GeometryKind::Points, GeometryKind::Lines, GeometryKind::Polygons}) {
        for (size_t l = content.layers.size(); l-- > 0;) {
            const ContentLayer& layer = content.layers[l];
            for (size_t i = layer.data.features.size(); i-- > 0;) {
                const Feature& f = layer.data.features[i];
                if (f.kind != kind) continue;
                const FeatureStyle& s = styles[l][i];
                if (!s.visible || (layer.times.timed() && !layer.times.spans[i].shows(query.time))) continue;
                const LonLatBounds& b = f.bounds;
                if (b.empty || query.latDeg < b.south - reachDeg || query.latDeg > b.north + reachDeg) continue;
                if (!b.spansAllLongitudes()) {
                    const double lon = lonNear(query.lonDeg, 0.5 * (b.west + b.east));
                    if (lon < b.west - reachDeg || lon > b.east + reachDeg) continue;
                }
                if (hits(f, s, query)) return PickedFeature{l, i};
            }
        }
    }
    return std::nullopt;
}

}  // namespace orbis::vector
