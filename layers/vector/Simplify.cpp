#include "layers/vector/Simplify.h"

#include "layers/vector/LonLatGeometry.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace orbis::vector {
namespace {

/// Douglas-Peucker over [first, last] of `points` (kept: both ends), with an explicit stack so a
/// million-point line does not recurse a million deep.
void douglasPeucker(std::span<const glm::dvec3> points, uint32_t first, uint32_t last, double tolerance2, std::vector<char>& keep) {
    std::vector<std::pair<uint32_t, uint32_t>> stack{{first, last}};
    while (!stack.empty()) {
        const auto [a, b] = stack.back();
        stack.pop_back();
        if (b <= a + 1) continue;
        double worst = -1.0;
        uint32_t at = a;
        const glm::dvec2 pa(points[a]), pb(points[b]);
        for (uint32_t i = a + 1; i < b; ++i) {
            const double d = segmentDistance2(glm::dvec2(points[i]), pa, pb);
            if (d > worst) worst = d, at = i;
        }
        if (worst > tolerance2) {
            keep[at] = 1;
            stack.push_back({a, at});
            stack.push_back({at, b});
        }
    }
}

}  // namespace

std::vector<uint32_t> simplifyPart(std::span<const glm::dvec3> part, double toleranceDeg, bool ring) {
    std::vector<uint32_t> out;
    if (part.empty()) return out;
    const double tolerance2 = toleranceDeg > 0.0 ? toleranceDeg * toleranceDeg : 0.0;
    auto n = uint32_t(part.size());
    const bool closed = ring && n > 1 && part.front() == part.back();
    if (closed) --n;   // the repeated vertex is added back at the end
    std::vector<char> keep(n, 0);
    keep[0] = 1;
    if (!ring) {
        keep[n - 1] = 1;
        douglasPeucker(part, 0, n - 1, tolerance2, keep);
    } else {
        if (n < 3) return out;
        // A ring is split at its first vertex and the vertex farthest from it: two open lines.
        uint32_t far = 0;
        double farthest = -1.0;
        for (uint32_t i = 1; i < n; ++i) {
            const glm::dvec2 d = glm::dvec2(part[i]) - glm::dvec2(part[0]);
            if (glm::dot(d, d) > farthest) farthest = glm::dot(d, d), far = i;
        }
        keep[far] = 1;
        douglasPeucker(part, 0, far, tolerance2, keep);
        std::vector<glm::dvec3> tail(part.begin() + far, part.begin() + n);
        tail.push_back(part[0]);
        std::vector<char> keepTail(tail.size(), 0);
        douglasPeucker(tail, 0, uint32_t(tail.size() - 1), tolerance2, keepTail);
        for (size_t i = 1; i + 1 < tail.size(); ++i)
            if (keepTail[i]) keep[far + i] = 1;
    }
    for (uint32_t i = 0; i < n; ++i)
        if (keep[i]) out.push_back(i);
    if (ring) {
        if (out.size() < 3) return {};
        if (closed) out.push_back(n);
    }
    return out;
}

std::optional<Feature> simplifyFeature(const Feature& feature, double toleranceDeg) {
    if (feature.kind == GeometryKind::Points) return feature;
    Feature out = feature;
    out.coords.clear();
    out.parts.clear();
    out.polygons.clear();
    out.containsPole.clear();
    const auto addPart = [&](size_t p, bool ring) {
        const std::span<const glm::dvec3> part = feature.part(p);
        const auto kept = simplifyPart(part, toleranceDeg, ring);
        if (kept.size() < 2) return false;
        out.parts.push_back(uint32_t(out.coords.size()));
        for (uint32_t i : kept) out.coords.push_back(part[i]);
        if (ring) out.containsPole.push_back(p < feature.containsPole.size() ? feature.containsPole[p] : 0);
        return true;
    };
    if (feature.kind == GeometryKind::Lines) {
        for (size_t p = 0; p < feature.parts.size(); ++p) addPart(p, false);
    } else {
        for (size_t k = 0; k < feature.polygons.size(); ++k) {
            const auto polygonStart = uint32_t(out.parts.size());
            if (!addPart(feature.polygons[k], true)) continue;   // the outer ring went: so do its holes
            out.polygons.push_back(polygonStart);
            for (size_t p = feature.polygons[k] + 1; p < feature.polygonEnd(k); ++p) addPart(p, true);
        }
    }
    if (out.parts.empty()) return std::nullopt;
    return out;
}

}  // namespace orbis::vector
