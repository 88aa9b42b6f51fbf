#include "globe/TerrainAnalysis.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::globe {
namespace {

/// The Earth's mean radius (IUGG), for refraction: its effect is a small correction.
constexpr double kMeanRadiusM = 6371008.8;

}  // namespace

TerrainProfile terrainProfile(std::span<const LonLat> path, const HeightAt& ground, double stepM, size_t maxSamples) {
    TerrainProfile out;
    if (path.empty()) return out;
    const PathLength length = geodesicLength(path);
    out.lengthM = length.metres;
    // The step grows so that the samples fit (each segment adds its end vertex).
    maxSamples = std::max<size_t>(maxSamples, path.size() + 1);
    stepM = std::max({stepM, 1e-3, length.metres / double(maxSamples - path.size())});
    std::optional<double> lastKnown;   // rises and falls are between neighbouring known samples
    const auto add = [&](const LonLat& at, double distance) {
        ProfileSample s{distance, {wrapLongitude(at.x), at.y}, ground ? ground(wrapLongitude(at.x), at.y) : std::nullopt};
        if (s.height && !std::isfinite(*s.height)) s.height.reset();
        if (!s.height) ++out.unknown;
        else {
            out.minHeight = std::min(out.minHeight.value_or(*s.height), *s.height);
            out.maxHeight = std::max(out.maxHeight.value_or(*s.height), *s.height);
            if (lastKnown) {
                const double dh = *s.height - *lastKnown;
                (dh > 0.0 ? out.ascentM : out.descentM) += std::abs(dh);
            }
            lastKnown = s.height;
        }
        out.samples.push_back(s);
    };
    add(path[0], 0.0);
    for (size_t i = 1; i < path.size(); ++i) {
        const double segment = length.along[i] - length.along[i - 1];
        const std::vector<LonLat> points = geodesicPoints(path[i - 1], path[i], stepM, maxSamples);
        for (size_t k = 1; k < points.size(); ++k)
            add(points[k], length.along[i - 1] + segment * double(k) / double(points.size() - 1));
    }
    return out;
}

LineOfSight lineOfSight(const Geodetic& observer, const Geodetic& target, const HeightAt& ground, const SightOptions& options) {
    const Ellipsoid& ell = Ellipsoid::wgs84();
    const glm::dvec3 o = ell.toEcef(observer), t = ell.toEcef(target);
    LineOfSight out;
    out.distanceM = glm::length(t - o);
    out.clearanceM = std::numeric_limits<double>::infinity();
    if (!ground || out.distanceM < 2.0) return out;
    const size_t n = std::clamp<size_t>(size_t(std::ceil(out.distanceM / std::max(options.stepM, 1e-3))), 2, std::max<size_t>(options.maxSamples, 2));
    for (size_t i = 1; i < n; ++i) {
        const double f = double(i) / double(n);
        const double d1 = f * out.distanceM, d2 = (1.0 - f) * out.distanceM;
        if (d1 < 1.0 || d2 < 1.0) continue;
        const Geodetic on = ell.toGeodetic(o + (t - o) * f);
        const double line = on.height + options.refraction * d1 * d2 / (2.0 * kMeanRadiusM);
        ++out.samples;
        const std::optional<double> g = ground(on.lonDeg, on.latDeg);
        if (!g || !std::isfinite(*g)) {
            ++out.unknown;
            continue;
        }
        out.clearanceM = std::min(out.clearanceM, line - *g);
        if (*g > line && out.visible) {
            out.visible = false;
            out.blockedAt = {on.lonDeg, on.latDeg};
            out.blockedAtM = geodesicBetween({observer.lonDeg, observer.latDeg}, out.blockedAt).metres;
            out.blockingHeight = *g;
            out.aboveLineM = *g - line;
        }
    }
    if (!std::isfinite(out.clearanceM)) out.clearanceM = 0.0;
    return out;
}

}  // namespace orbis::globe
