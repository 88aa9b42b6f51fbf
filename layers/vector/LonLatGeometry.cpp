#include "layers/vector/LonLatGeometry.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace orbis::vector {
namespace {

// A vertex this close to ±90 degrees is on the pole (about 1 mm).
constexpr double kPoleLatDeg = 90.0 - 1e-8;

/// `deltaDeg` moved by whole turns into (-180, 180].
double wrapDeltaDeg(double deltaDeg) {
    if (deltaDeg > 180.0 || deltaDeg <= -180.0) deltaDeg -= 360.0 * std::ceil((deltaDeg - 180.0) / 360.0);
    return deltaDeg;
}

LonLatBounds allLongitudes(double south, double north) { return LonLatBounds{-180.0, south, 180.0, north, false}; }

}  // namespace

bool LonLatBounds::contains(double lonDeg, double latDeg) const {
    if (empty || latDeg < south || latDeg > north) return false;
    if (spansAllLongitudes()) return true;
    const double turned = west + std::fmod(std::fmod(lonDeg - west, 360.0) + 360.0, 360.0);
    return turned <= east;
}

double normalizeLonDeg(double lonDeg) {
    if (lonDeg >= -180.0 && lonDeg < 180.0) return lonDeg;
    const double r = std::fmod(lonDeg + 180.0, 360.0);
    return (r < 0.0 ? r + 360.0 : r) - 180.0;
}

void unwrapLongitudes(std::span<glm::dvec3> part) {
    if (part.empty()) return;
    if (part[0].x > 180.0 || part[0].x < -180.0) part[0].x = normalizeLonDeg(part[0].x);
    for (size_t i = 1; i < part.size(); ++i) {
        const double delta = part[i].x - part[i - 1].x;
        // Only jumps of more than half a turn are crossings; ±180 exactly stays as it is.
        if (std::abs(delta) > 180.0) part[i].x -= 360.0 * std::round(delta / 360.0);
    }
}

double lonMidpoint(std::span<const glm::dvec3> part) {
    if (part.empty()) return 0.0;
    const auto [lo, hi] = std::minmax_element(part.begin(), part.end(),
                                              [](const glm::dvec3& a, const glm::dvec3& b) { return a.x < b.x; });
    return 0.5 * (lo->x + hi->x);
}

void moveNextTo(std::span<glm::dvec3> part, double lonDeg) {
    if (part.empty()) return;
    const double turns = std::round((lonDeg - part[0].x) / 360.0);
    if (turns == 0.0) return;
    for (glm::dvec3& v : part) v.x += 360.0 * turns;
}

int8_t ringPoleWinding(std::span<const glm::dvec3> ring) {
    if (ring.size() < 3) return 0;
    // The unwrapped ring's change in longitude, plus the step that closes it (if the source did
    // not repeat the first vertex, or the closing step crossed the antimeridian).
    const double turn = (ring.back().x - ring.front().x) + wrapDeltaDeg(ring.front().x - ring.back().x);
    if (std::abs(turn) < 180.0) return 0;
    bool north = false, south = false;
    double latSum = 0.0;
    for (const glm::dvec3& v : ring) {
        north |= v.y >= kPoleLatDeg;
        south |= v.y <= -kPoleLatDeg;
        latSum += v.y;
    }
    if (north != south) return north ? 1 : -1;
    return latSum >= 0.0 ? 1 : -1;
}

LonLatBounds partBounds(std::span<const glm::dvec3> part) {
    LonLatBounds b;
    if (part.empty()) return b;
    double lo = part[0].x, hi = part[0].x;
    b.south = b.north = part[0].y;
    for (const glm::dvec3& v : part) {
        lo = std::min(lo, v.x);
        hi = std::max(hi, v.x);
        b.south = std::min(b.south, v.y);
        b.north = std::max(b.north, v.y);
    }
    b.empty = false;
    if (hi - lo >= 360.0) return allLongitudes(b.south, b.north);
    b.west = normalizeLonDeg(lo);
    b.east = b.west + (hi - lo);
    return b;
}

LonLatBounds poleCapBounds(std::span<const glm::dvec3> ring, int8_t pole) {
    const LonLatBounds b = partBounds(ring);
    return pole > 0 ? allLongitudes(b.south, 90.0) : allLongitudes(-90.0, b.north);
}

LonLatBounds coverBounds(std::span<const LonLatBounds> boxes) {
    struct Interval {
        double west, east;
    };
    std::vector<Interval> intervals;
    LonLatBounds out;
    bool everyLongitude = false;
    for (const LonLatBounds& b : boxes) {
        if (b.empty) continue;
        out.south = out.empty ? b.south : std::min(out.south, b.south);
        out.north = out.empty ? b.north : std::max(out.north, b.north);
        out.empty = false;
        everyLongitude |= b.spansAllLongitudes();
        if (!everyLongitude) intervals.push_back({normalizeLonDeg(b.west), normalizeLonDeg(b.west) + b.widthDeg()});
    }
    if (out.empty) return out;
    if (everyLongitude) return allLongitudes(out.south, out.north);
    std::sort(intervals.begin(), intervals.end(), [](const Interval& a, const Interval& b) { return a.west < b.west; });
    // Sweep twice around the circle; only gaps seen on the second lap count, when everything
    // that wraps past 180 from the first lap has already extended the reach.
    const size_t n = intervals.size();
    double reach = intervals[0].east, gapStart = 0.0, gapWidth = 0.0;
    bool gap = false;
    for (size_t k = 1; k < 2 * n; ++k) {
        const Interval& i = intervals[k % n];
        const double turn = k >= n ? 360.0 : 0.0;
        if (k >= n && i.west + turn > reach && i.west + turn - reach > gapWidth) {
            gap = true;
            gapStart = reach;
            gapWidth = i.west + turn - reach;
        }
        reach = std::max(reach, i.east + turn);
    }
    if (!gap) return allLongitudes(out.south, out.north);
    out.west = normalizeLonDeg(gapStart + gapWidth);
    out.east = out.west + (360.0 - gapWidth);
    return out;
}

double segmentDistance2(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    const glm::dvec2 d = p - (a + t * ab);
    return glm::dot(d, d);
}

}  // namespace orbis::vector
