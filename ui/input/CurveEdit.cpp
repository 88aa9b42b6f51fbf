#include "ui/input/CurveEdit.h"

#include <algorithm>

namespace orbis::ui {

glm::dvec2 curveToPixels(const CurveFrame& f, const glm::dvec2& p) {
    const double span = f.xMax - f.xMin;
    const double u = span > 0.0 ? (p.x - f.xMin) / span : 0.5;
    return {f.topLeftPx.x + u * f.sizePx.x, f.topLeftPx.y + (1.0 - p.y) * f.sizePx.y};
}

glm::dvec2 pixelsToCurve(const CurveFrame& f, const glm::dvec2& px) {
    const double u = f.sizePx.x > 0.0 ? std::clamp((px.x - f.topLeftPx.x) / f.sizePx.x, 0.0, 1.0) : 0.5;
    const double v = f.sizePx.y > 0.0 ? std::clamp((px.y - f.topLeftPx.y) / f.sizePx.y, 0.0, 1.0) : 0.5;
    return {f.xMin + u * (f.xMax - f.xMin), 1.0 - v};
}

std::optional<std::size_t> pointUnder(const std::vector<glm::dvec2>& points, const CurveFrame& frame,
                                      const glm::dvec2& px, double radiusPx) {
    std::optional<std::size_t> best;
    double bestDistance = radiusPx;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double d = glm::length(curveToPixels(frame, points[i]) - px);
        if (d <= bestDistance) {
            bestDistance = d;
            best = i;
        }
    }
    return best;
}

std::size_t insertPoint(std::vector<glm::dvec2>& points, glm::dvec2 point) {
    point.y = std::clamp(point.y, 0.0, 1.0);
    const auto at = std::upper_bound(points.begin(), points.end(), point.x,
                                     [](double x, const glm::dvec2& p) { return x < p.x; });
    const auto inserted = points.insert(at, point);
    return std::size_t(inserted - points.begin());
}

bool movePoint(std::vector<glm::dvec2>& points, std::size_t i, glm::dvec2 to) {
    if (i >= points.size()) return false;
    if (i > 0) to.x = std::max(to.x, points[i - 1].x);
    if (i + 1 < points.size()) to.x = std::min(to.x, points[i + 1].x);
    to.y = std::clamp(to.y, 0.0, 1.0);
    points[i] = to;
    return true;
}

bool removePoint(std::vector<glm::dvec2>& points, std::size_t i) {
    if (i >= points.size() || points.size() <= 2) return false;
    points.erase(points.begin() + std::ptrdiff_t(i));
    return true;
}

}  // namespace orbis::ui
