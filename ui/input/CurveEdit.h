#pragma once
// Editing a piecewise-linear curve with the mouse (the volume's opacity transfer function):
// the mapping between the curve's values and the editor's pixels, and the edits, kept apart
// from ImGui so that they are tested without a window. Points stay sorted by x; y stays in
// 0..1; there are always at least two points.

#include <glm/glm.hpp>

#include <cstddef>
#include <optional>
#include <vector>

namespace orbis::ui {

/// Where the curve is drawn: x over [xMin, xMax] left to right, y over 0..1 bottom to top.
struct CurveFrame {
    double xMin = 0.0, xMax = 1.0;
    glm::dvec2 topLeftPx{0.0};
    glm::dvec2 sizePx{1.0};
};

glm::dvec2 curveToPixels(const CurveFrame& frame, const glm::dvec2& point);
/// The curve point under a pixel, clamped to the frame.
glm::dvec2 pixelsToCurve(const CurveFrame& frame, const glm::dvec2& px);

/// The point whose handle is within `radiusPx` of `px` (the nearest), or nothing.
std::optional<std::size_t> pointUnder(const std::vector<glm::dvec2>& points, const CurveFrame& frame,
                                      const glm::dvec2& px, double radiusPx = 6.0);

/// Inserts `point` (y clamped to 0..1) where it keeps the points sorted; returns its index.
std::size_t insertPoint(std::vector<glm::dvec2>& points, glm::dvec2 point);

/// Moves point `i` to `to`: x kept between its neighbours (so the order never changes), y
/// clamped to 0..1. False when `i` is out of range.
bool movePoint(std::vector<glm::dvec2>& points, std::size_t i, glm::dvec2 to);

/// Removes point `i` unless only two are left. True when removed.
bool removePoint(std::vector<glm::dvec2>& points, std::size_t i);

}  // namespace orbis::ui
