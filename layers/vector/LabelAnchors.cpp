#include "layers/vector/LabelAnchors.h"

#include "layers/vector/LonLatGeometry.h"
#include "layers/vector/VectorContent.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>

namespace orbis::vector {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
/// Metres per degree of arc on the mean sphere (IUGG R1 = 6 371 008.8 m): sizes for ranking.
constexpr double kMetresPerDegree = 6371008.8 * kDegToRad;

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

/// Twice the signed area of a ring (closed or not), by the shoelace formula.
double twiceArea(const std::vector<glm::dvec2>& ring) {
    double sum = 0.0;
    for (size_t i = 0, n = ring.size(); i < n; ++i) sum += cross(ring[i], ring[(i + 1) % n]);
    return sum;
}

glm::dvec2 ringCentroid(const std::vector<glm::dvec2>& ring) {
    double a = 0.0;
    glm::dvec2 c(0.0);
    for (size_t i = 0, n = ring.size(); i < n; ++i) {
        const double k = cross(ring[i], ring[(i + 1) % n]);
        a += k;
        c += (ring[i] + ring[(i + 1) % n]) * k;
    }
    if (std::abs(a) > 0.0) return c / (3.0 * a);
    glm::dvec2 mean(0.0);
    for (const glm::dvec2& p : ring) mean += p;
    return ring.empty() ? mean : mean / double(ring.size());
}

/// The middle of the widest stretch inside the polygon along the horizontal line through the
/// middle of its box: inside by construction, for shapes too thin for the cell search.
std::optional<glm::dvec2> scanlinePoint(std::span<const std::vector<glm::dvec2>> rings, double y) {
    std::vector<double> xs;
    for (const auto& ring : rings)
        for (size_t i = 0, n = ring.size(); i < n; ++i) {
            const glm::dvec2 a = ring[i], b = ring[(i + 1) % n];
            if ((a.y > y) != (b.y > y)) xs.push_back(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
        }
    std::sort(xs.begin(), xs.end());
    double widest = -1.0;
    std::optional<glm::dvec2> best;
    for (size_t i = 0; i + 1 < xs.size(); i += 2)   // even-odd: every other stretch is inside
        if (xs[i + 1] - xs[i] > widest) {
            widest = xs[i + 1] - xs[i];
            best = glm::dvec2(0.5 * (xs[i] + xs[i + 1]), y);
        }
    return best;
}

/// The plane a polygon is searched in, and back.
struct PolygonPlane {
    int8_t pole = 0;       ///< around a pole: polar coordinates (degrees from the pole)
    double cosLat = 1.0;   ///< else lon/lat with longitudes scaled by the middle latitude's cosine

    glm::dvec2 toPlane(const glm::dvec3& lonLat) const {
        if (pole == 0) return {lonLat.x * cosLat, lonLat.y};
        const double r = 90.0 - pole * lonLat.y;
        return {r * std::cos(lonLat.x * kDegToRad), r * std::sin(lonLat.x * kDegToRad)};
    }
    glm::dvec2 toLonLat(glm::dvec2 p) const {
        if (pole == 0) return {p.x / cosLat, p.y};
        return {std::atan2(p.y, p.x) / kDegToRad, pole * (90.0 - glm::length(p))};
    }
};

struct Polygon {
    std::vector<std::vector<glm::dvec2>> rings;
    PolygonPlane plane;
    double areaM2 = 0.0;
};

Polygon planePolygon(const Feature& f, size_t k) {
    Polygon out;
    const uint32_t first = f.polygons[k], end = f.polygonEnd(k);
    out.plane.pole = first < f.containsPole.size() ? f.containsPole[first] : 0;
    if (out.plane.pole == 0) {
        double lo = 90.0, hi = -90.0;
        for (uint32_t i = f.parts[first]; i < f.partEnd(first); ++i) {
            lo = std::min(lo, f.coords[i].y);
            hi = std::max(hi, f.coords[i].y);
        }
        out.plane.cosLat = std::max(0.05, std::cos(0.5 * (lo + hi) * kDegToRad));
    }
    for (uint32_t part = first; part < end; ++part) {
        std::vector<glm::dvec2>& ring = out.rings.emplace_back();
        for (uint32_t i = f.parts[part]; i < f.partEnd(part); ++i) ring.push_back(out.plane.toPlane(f.coords[i]));
    }
    double twice = out.rings.empty() ? 0.0 : std::abs(twiceArea(out.rings[0]));
    for (size_t r = 1; r < out.rings.size(); ++r) twice -= std::abs(twiceArea(out.rings[r]));
    out.areaM2 = std::max(0.0, 0.5 * twice) * kMetresPerDegree * kMetresPerDegree;
    return out;
}

double arcMetres(glm::dvec2 a, glm::dvec2 b) {
    const auto unit = [](glm::dvec2 p) {
        const double lon = p.x * kDegToRad, lat = p.y * kDegToRad;
        return glm::dvec3(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
    };
    const double chord = glm::length(unit(a) - unit(b));
    return 2.0 * std::asin(std::min(1.0, 0.5 * chord)) / kDegToRad * kMetresPerDegree;
}

LabelAnchor pointAnchor(const Feature& f) {
    LabelAnchor a;
    if (f.coords.empty()) return a;
    a.valid = true;
    a.kind = GeometryKind::Points;
    a.lonLat = glm::dvec2(f.coords[0]);
    return a;
}

LabelAnchor polygonAnchor(const Feature& f) {
    LabelAnchor a;
    a.kind = GeometryKind::Polygons;
    double total = 0.0, largest = -1.0;
    Polygon best;
    for (size_t k = 0; k < f.polygons.size(); ++k) {
        Polygon p = planePolygon(f, k);
        if (p.rings.empty() || p.rings[0].size() < 3) continue;
        total += p.areaM2;
        if (p.areaM2 > largest) {
            largest = p.areaM2;
            best = std::move(p);
        }
    }
    if (largest < 0.0) return a;
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (const glm::dvec2& p : best.rings[0]) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const double precision = std::max(1e-9, std::max(hi.x - lo.x, hi.y - lo.y) / 500.0);
    a.lonLat = best.plane.toLonLat(poleOfInaccessibility(best.rings, precision));
    a.sizeM = std::sqrt(total);
    a.valid = true;
    return a;
}

/// The point `at` metres along `part` (cumulative lengths `along`), and its segment.
glm::dvec2 pointAlong(std::span<const glm::dvec3> part, std::span<const double> along, double at, size_t* segment) {
    size_t i = 1;
    while (i + 1 < part.size() && along[i] < at) ++i;
    const double len = along[i] - along[i - 1];
    const double t = len > 0.0 ? std::clamp((at - along[i - 1]) / len, 0.0, 1.0) : 0.0;
    if (segment) *segment = i - 1;
    return glm::mix(glm::dvec2(part[i - 1]), glm::dvec2(part[i]), t);
}

LabelAnchor lineAnchor(const Feature& f) {
    LabelAnchor a;
    a.kind = GeometryKind::Lines;
    // The longest part is the one labelled.
    std::vector<double> along, bestAlong;
    size_t bestPart = 0;
    double bestLength = -1.0;
    for (size_t p = 0; p < f.parts.size(); ++p) {
        const std::span<const glm::dvec3> part = f.part(p);
        if (part.size() < 2) continue;
        along.assign(1, 0.0);
        for (size_t i = 1; i < part.size(); ++i) along.push_back(along.back() + arcMetres(glm::dvec2(part[i - 1]), glm::dvec2(part[i])));
        if (along.back() > bestLength) {
            bestLength = along.back();
            bestPart = p;
            bestAlong.swap(along);
        }
    }
    if (bestLength < 0.0) return a;
    const std::span<const glm::dvec3> part = f.part(bestPart);
    size_t segment = 0;
    a.lonLat = pointAlong(part, bestAlong, 0.5 * bestLength, &segment);
    // The direction of the segment under the middle (skipping repeated vertices).
    glm::dvec2 dir(0.0);
    for (size_t s = segment; s + 1 < part.size() && glm::length(dir) == 0.0; ++s) dir = glm::dvec2(part[s + 1] - part[s]);
    for (size_t s = segment; s > 0 && glm::length(dir) == 0.0; --s) dir = glm::dvec2(part[s] - part[s - 1]);
    a.ahead = a.lonLat + (glm::length(dir) > 0.0 ? glm::normalize(dir) * 1e-3 : glm::dvec2(1e-3, 0.0));
    for (size_t k = 0; k < LabelAnchor::kPathSamples; ++k)
        a.path.push_back(pointAlong(part, bestAlong, bestLength * double(k) / double(LabelAnchor::kPathSamples - 1), nullptr));
    a.sizeM = bestLength;
    a.valid = true;
    return a;
}

}  // namespace

double signedDistanceToPolygon(glm::dvec2 p, std::span<const std::vector<glm::dvec2>> rings) {
    bool inside = false;
    double best = std::numeric_limits<double>::infinity();
    for (const auto& ring : rings)
        for (size_t i = 0, n = ring.size(), j = n - 1; i < n; j = i++) {
            const glm::dvec2 a = ring[i], b = ring[j];
            if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
            best = std::min(best, segmentDistance2(p, a, b));
        }
    const double d = std::sqrt(best);
    return inside ? d : -d;
}

glm::dvec2 poleOfInaccessibility(std::span<const std::vector<glm::dvec2>> rings, double precision, int maxCells) {
    if (rings.empty() || rings[0].empty()) return glm::dvec2(0.0);
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (const glm::dvec2& p : rings[0]) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const glm::dvec2 size = hi - lo;
    // Square cells as large as the box's short side; no more than 64 along the long side, so a
    // long thin shape does not start with a million cells.
    const double cellSize = std::max(std::min(size.x, size.y), std::max(size.x, size.y) / 64.0);
    if (!(cellSize > 0.0)) return rings[0][0];

    struct Cell {
        glm::dvec2 centre;
        double half, distance, potential;   ///< the best distance any point of the cell could have
    };
    int evaluated = 0;
    const auto cell = [&](glm::dvec2 c, double half) {
        ++evaluated;
        const double d = signedDistanceToPolygon(c, rings);
        return Cell{c, half, d, d + half * std::sqrt(2.0)};
    };
    const auto lower = [](const Cell& a, const Cell& b) { return a.potential < b.potential; };
    std::priority_queue<Cell, std::vector<Cell>, decltype(lower)> queue(lower);
    for (double x = lo.x; x < hi.x; x += cellSize)
        for (double y = lo.y; y < hi.y; y += cellSize) queue.push(cell({x + 0.5 * cellSize, y + 0.5 * cellSize}, 0.5 * cellSize));

    Cell best = cell(ringCentroid(rings[0]), 0.0);
    if (const Cell middle = cell(lo + 0.5 * size, 0.0); middle.distance > best.distance) best = middle;
    while (!queue.empty()) {
        const Cell c = queue.top();
        queue.pop();
        if (c.distance > best.distance) best = c;
        if (c.potential - best.distance <= precision || evaluated + 4 > maxCells) continue;
        const double h = 0.5 * c.half;
        for (const glm::dvec2 offset : {glm::dvec2(-h, -h), glm::dvec2(h, -h), glm::dvec2(-h, h), glm::dvec2(h, h)})
            queue.push(cell(c.centre + offset, h));
    }
    if (best.distance > 0.0) return best.centre;
    // Nothing found inside (a sliver thinner than the cells): the middle of the widest stretch
    // inside along the box's middle row, or of a row through a vertex.
    if (auto p = scanlinePoint(rings, lo.y + 0.5 * size.y)) return *p;
    for (const glm::dvec2& v : rings[0])
        if (auto p = scanlinePoint(rings, v.y + 1e-7 * size.y)) return *p;
    return best.centre;
}

double labelPriority(GeometryKind kind, double sizeM, int32_t rule) {
    // Three tiers in one double, each below the next tier's step: the rule (0..4095), the size
    // (at most 16 * log2(4e7) ~ 404 steps, times 4096), the kind (1e7).
    const double ruleRank = double(std::clamp(rule + 1, 0, 4095));
    const double sizeSteps = std::floor(16.0 * std::log2(1.0 + std::max(0.0, sizeM)));
    const double kindRank = kind == GeometryKind::Points ? 1.0 : 0.0;
    return kindRank * 1e7 + sizeSteps * 4096.0 + ruleRank;
}

LabelAnchor labelAnchor(const Feature& feature) {
    switch (feature.kind) {
        case GeometryKind::Points: return pointAnchor(feature);
        case GeometryKind::Lines: return lineAnchor(feature);
        case GeometryKind::Polygons: return polygonAnchor(feature);
    }
    return {};
}

ContentAnchors labelAnchors(const VectorContent& content) {
    ContentAnchors out(content.layers.size());
    for (size_t l = 0; l < content.layers.size(); ++l) {
        out[l].reserve(content.layers[l].data.features.size());
        for (const Feature& f : content.layers[l].data.features) out[l].push_back(labelAnchor(f));
    }
    return out;
}

}  // namespace orbis::vector
