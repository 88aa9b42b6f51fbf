// The transfer-function editor's edits: pixels to values and back, picking a handle, adding,
// moving (order kept, alpha clamped) and removing points (never fewer than two).
#include "ui/input/CurveEdit.h"

#include <gtest/gtest.h>

namespace orbis::ui {
namespace {

const CurveFrame kFrame{200.0, 300.0, {10.0, 20.0}, {100.0, 50.0}};

TEST(CurveEdit, PixelsAndValuesRoundTrip) {
    EXPECT_EQ(curveToPixels(kFrame, {200.0, 0.0}), glm::dvec2(10.0, 70.0));   // bottom left
    EXPECT_EQ(curveToPixels(kFrame, {300.0, 1.0}), glm::dvec2(110.0, 20.0));  // top right
    const glm::dvec2 p = pixelsToCurve(kFrame, curveToPixels(kFrame, {237.5, 0.25}));
    EXPECT_NEAR(p.x, 237.5, 1e-9);
    EXPECT_NEAR(p.y, 0.25, 1e-9);
    // Outside the frame: clamped to its edges.
    EXPECT_EQ(pixelsToCurve(kFrame, {-50.0, 500.0}), glm::dvec2(200.0, 0.0));
    // A frame with no width or span gives no NaN.
    const CurveFrame flat{5.0, 5.0, {0.0, 0.0}, {0.0, 0.0}};
    const glm::dvec2 q = pixelsToCurve(flat, {3.0, 3.0});
    EXPECT_TRUE(std::isfinite(q.x) && std::isfinite(q.y));
    EXPECT_TRUE(std::isfinite(curveToPixels(flat, {5.0, 0.5}).x));
}

TEST(CurveEdit, PicksTheNearestHandleWithinReach) {
    const std::vector<glm::dvec2> points = {{200.0, 0.0}, {250.0, 0.5}, {252.0, 0.5}, {300.0, 1.0}};
    EXPECT_EQ(pointUnder(points, kFrame, {60.0, 45.0}), std::optional<std::size_t>(1));
    EXPECT_EQ(pointUnder(points, kFrame, {62.0, 45.0}), std::optional<std::size_t>(2));
    EXPECT_FALSE(pointUnder(points, kFrame, {80.0, 45.0}).has_value());
}

TEST(CurveEdit, InsertKeepsOrderAndClampsAlpha) {
    std::vector<glm::dvec2> points = {{200.0, 0.0}, {300.0, 1.0}};
    EXPECT_EQ(insertPoint(points, {250.0, 1.7}), 1u);
    EXPECT_EQ(points[1], glm::dvec2(250.0, 1.0));
    EXPECT_EQ(insertPoint(points, {100.0, 0.5}), 0u);
    EXPECT_EQ(insertPoint(points, {400.0, -1.0}), 4u);
    EXPECT_EQ(points[4].y, 0.0);
    for (size_t i = 1; i < points.size(); ++i) EXPECT_LE(points[i - 1].x, points[i].x);
}

TEST(CurveEdit, MoveStaysBetweenNeighbours) {
    std::vector<glm::dvec2> points = {{200.0, 0.0}, {250.0, 0.5}, {300.0, 1.0}};
    ASSERT_TRUE(movePoint(points, 1, {320.0, 2.0}));
    EXPECT_EQ(points[1], glm::dvec2(300.0, 1.0)) << "x stops at the next point, alpha at 1";
    ASSERT_TRUE(movePoint(points, 1, {100.0, -3.0}));
    EXPECT_EQ(points[1], glm::dvec2(200.0, 0.0));
    ASSERT_TRUE(movePoint(points, 0, {150.0, 0.3}));
    EXPECT_EQ(points[0], glm::dvec2(150.0, 0.3)) << "the ends move freely outward";
    EXPECT_FALSE(movePoint(points, 3, {0.0, 0.0}));
}

TEST(CurveEdit, NeverFewerThanTwoPoints) {
    std::vector<glm::dvec2> points = {{200.0, 0.0}, {250.0, 0.5}, {300.0, 1.0}};
    EXPECT_FALSE(removePoint(points, 5));
    EXPECT_TRUE(removePoint(points, 1));
    EXPECT_FALSE(removePoint(points, 0));
    EXPECT_EQ(points.size(), 2u);
}

}  // namespace
}  // namespace orbis::ui
