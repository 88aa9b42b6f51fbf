#include "layers/vector/FeatureClip.h"

#include <algorithm>
#include <cmath>
#include <span>

namespace orbis::vector {
namespace {

using Ring = std::vector<glm::dvec3>;

/// One Sutherland-Hodgman pass: keeps the side where coord(axis) * sign >= limit * sign.
Ring clipRing(const Ring& ring, int axis, double limit, double sign) {
    Ring out;
    if (ring.empty()) return out;
    const auto inside = [&](const glm::dvec3& p) { return p[axis] * sign >= limit * sign; };
    const auto cross = [&](const glm::dvec3& a, const glm::dvec3& b) {
        const double t = (limit - a[axis]) / (b[axis] - a[axis]);
        glm::dvec3 p = a + (b - a) * t;
        p[axis] = limit;   // exactly on the edge
        return p;
    };
    for (size_t i = 0; i < ring.size(); ++i) {
        const glm::dvec3& a = ring[i];
        const glm::dvec3& b = ring[(i + 1) % ring.size()];
        const bool ina = inside(a), inb = inside(b);
        if (ina) out.push_back(a);
        if (ina != inb) out.push_back(cross(a, b));
    }
    return out;
}

/// Twice the signed area in the lon/lat plane.
double area2(const Ring& ring) {
    double sum = 0.0;
    for (size_t i = 0; i < ring.size(); ++i) {
        const glm::dvec3 &a = ring[i], &b = ring[(i + 1) % ring.size()];
        sum += (a.x - ring[0].x) * (b.y - ring[0].y) - (b.x - ring[0].x) * (a.y - ring[0].y);
    }
    return sum;
}

Ring clipRingToExtent(Ring ring, const globe::GeoExtent& e) {
    ring = clipRing(ring, 0, e.west, 1.0);
    ring = clipRing(ring, 0, e.east, -1.0);
    ring = clipRing(ring, 1, e.south, 1.0);
    ring = clipRing(ring, 1, e.north, -1.0);
    return ring;
}

/// Liang-Barsky: the part of segment ab inside the extent, as parameters t0 <= t1.
bool clipSegment(const glm::dvec3& a, const glm::dvec3& b, const globe::GeoExtent& e, double& t0, double& t1) {
    t0 = 0.0;
    t1 = 1.0;
    const glm::dvec2 d{b.x - a.x, b.y - a.y};
    const double p[4] = {-d.x, d.x, -d.y, d.y};
    const double q[4] = {a.x - e.west, e.east - a.x, a.y - e.south, e.north - a.y};
    for (int i = 0; i < 4; ++i) {
        if (p[i] == 0.0) {
            if (q[i] < 0.0) return false;
            continue;
        }
        const double t = q[i] / p[i];
        if (p[i] < 0.0) t0 = std::max(t0, t);
        else t1 = std::min(t1, t);
        if (t0 > t1) return false;
    }
    return true;
}

void clipLine(std::span<const glm::dvec3> line, const globe::GeoExtent& e, Feature& out) {
    std::vector<glm::dvec3> current;
    const auto flush = [&] {
        if (current.size() >= 2) {
            out.parts.push_back(uint32_t(out.coords.size()));
            out.coords.insert(out.coords.end(), current.begin(), current.end());
        }
        current.clear();
    };
    for (size_t i = 0; i + 1 < line.size(); ++i) {
        double t0 = 0.0, t1 = 0.0;
        if (!clipSegment(line[i], line[i + 1], e, t0, t1) || t0 == t1) {   // outside, or touching a corner
            flush();
            continue;
        }
        const glm::dvec3 a = line[i] + (line[i + 1] - line[i]) * t0, b = line[i] + (line[i + 1] - line[i]) * t1;
        if (current.empty() || current.back() != a) {
            flush();
            current.push_back(a);
        }
        current.push_back(b);
        if (t1 < 1.0) flush();
    }
    flush();
}

/// Shifts of a whole turn that bring the feature's longitudes (as stored, unwrapped) onto the
/// extent.
std::vector<double> shiftsFor(const Feature& f, const globe::GeoExtent& e) {
    std::vector<double> out;
    if (f.coords.empty() || f.bounds.south > e.north || f.bounds.north < e.south) return out;
    double west = f.coords[0].x, east = west;
    for (const glm::dvec3& c : f.coords) west = std::min(west, c.x), east = std::max(east, c.x);
    for (double shift : {-720.0, -360.0, 0.0, 360.0, 720.0})
        if (west + shift <= e.east && east + shift >= e.west) out.push_back(shift);
    return out;
}

Ring shifted(std::span<const glm::dvec3> part, double shift) {
    Ring out(part.begin(), part.end());
    for (glm::dvec3& p : out) p.x += shift;
    return out;
}

}  // namespace

void closeThroughPole(std::vector<glm::dvec3>& ring, int8_t pole) {
    if (pole == 0 || ring.size() < 2) return;
    const glm::dvec3 first = ring.front();
    const double turns = std::round((ring.back().x - first.x) / 360.0);
    if (turns == 0.0) return;   // it does not wind around in the lon/lat plane as stored
    // The closing edge, unwrapped, then down to the pole and back along it.
    const double closeX = first.x + turns * 360.0;
    if (ring.back().x != closeX || ring.back().y != first.y) ring.push_back({closeX, first.y, first.z});
    const double lat = pole > 0 ? 90.0 : -90.0;
    ring.push_back({closeX, lat, first.z});
    ring.push_back({first.x, lat, first.z});
}

std::optional<Feature> clipFeature(const Feature& feature, const globe::GeoExtent& extent) {
    Feature out;
    out.fid = feature.fid;
    out.kind = feature.kind;
    out.attributes = feature.attributes;
    out.style = feature.style;
    out.hasZ = feature.hasZ;
    for (double shift : shiftsFor(feature, extent)) {
        if (feature.kind == GeometryKind::Points) {
            for (size_t p = 0; p < feature.parts.size(); ++p) {
                glm::dvec3 q = feature.coords[feature.parts[p]];
                q.x += shift;
                if (q.x >= extent.west && q.x <= extent.east && q.y >= extent.south && q.y <= extent.north) {
                    out.parts.push_back(uint32_t(out.coords.size()));
                    out.coords.push_back(q);
                }
            }
        } else if (feature.kind == GeometryKind::Lines) {
            for (size_t p = 0; p < feature.parts.size(); ++p) {
                const Ring line = shifted(std::span(feature.coords).subspan(feature.parts[p], feature.partEnd(p) - feature.parts[p]), shift);
                clipLine(line, extent, out);
            }
        } else {
            for (size_t k = 0; k < feature.polygons.size(); ++k) {
                bool outerKept = false;
                for (size_t p = feature.polygons[k]; p < feature.polygonEnd(k); ++p) {
                    Ring ring = shifted(std::span(feature.coords).subspan(feature.parts[p], feature.partEnd(p) - feature.parts[p]), shift);
                    const int8_t pole = p < feature.containsPole.size() ? feature.containsPole[p] : 0;
                    closeThroughPole(ring, pole);
                    ring = clipRingToExtent(std::move(ring), extent);
                    const bool isOuter = p == feature.polygons[k];
                    if (ring.size() < 3 || area2(ring) == 0.0 || (!isOuter && !outerKept)) {
                        if (isOuter) break;   // nothing of this polygon here: its holes go too
                        continue;
                    }
                    if (isOuter) {
                        outerKept = true;
                        out.polygons.push_back(uint32_t(out.parts.size()));
                    }
                    out.parts.push_back(uint32_t(out.coords.size()));
                    out.containsPole.push_back(0);   // closed through the pole: a plain ring now
                    out.coords.insert(out.coords.end(), ring.begin(), ring.end());
                }
            }
        }
    }
    if (out.parts.empty()) return std::nullopt;
    out.bounds = LonLatBounds{extent.west, extent.south, extent.east, extent.north, false};
    return out;
}

std::vector<globe::TileKey> tilesCovering(const Feature& feature, uint32_t level) {
    std::vector<globe::TileKey> out;
    const LonLatBounds& b = feature.bounds;
    // The reader keeps latitudes within +-90 and longitudes finite (unwrapped lines may wind past +-180).
    if (b.empty || !(std::abs(b.west) < 1e12 && std::abs(b.east) < 1e12 && std::abs(b.south) <= 90.0 && std::abs(b.north) <= 90.0))
        return out;
    const double size = 180.0 / double(1u << level);
    const auto nx = int64_t(globe::TileKey::tilesX(level)), ny = int64_t(globe::TileKey::tilesY(level));
    const auto y0 = std::clamp(int64_t(std::floor((90.0 - b.north) / size)), int64_t(0), ny - 1);
    const auto y1 = std::clamp(int64_t(std::floor((90.0 - b.south) / size)), int64_t(0), ny - 1);
    int64_t x0 = int64_t(std::floor((b.west + 180.0) / size)), x1 = int64_t(std::floor((b.east + 180.0) / size));
    if (x1 - x0 + 1 >= nx) x0 = 0, x1 = nx - 1;   // every longitude
    for (int64_t y = y0; y <= y1; ++y)
        for (int64_t x = x0; x <= x1; ++x) out.push_back(globe::TileKey{level, uint32_t(((x % nx) + nx) % nx), uint32_t(y)});
    return out;
}

}  // namespace orbis::vector
