// Geodesic measures (globe/Geodesic.h) against values worked out here without GeographicLib:
// arcs of the equator (a times the angle), the quarter meridian (its integral), the area of the
// whole ellipsoid and of the cap above a parallel (closed forms); across the antimeridian, round
// a pole, in either order, and with degenerate input.
#include "globe/Geodesic.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace orbis::globe {
namespace {

constexpr double kA = 6378137.0;
constexpr double kF = 1.0 / 298.257223563;
const double kE2 = kF * (2.0 - kF);
const double kE = std::sqrt(kE2);
const double kB = kA * (1.0 - kF);
constexpr double kPi = std::numbers::pi;

/// The length of the meridian from the equator to latitude phi (Simpson's rule on its radius of
/// curvature).
double meridianArc(double phi) {
    const int n = 20000;
    const auto m = [](double p) { return kA * (1.0 - kE2) / std::pow(1.0 - kE2 * std::sin(p) * std::sin(p), 1.5); };
    double sum = m(0.0) + m(phi);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * m(phi * i / n);
    return sum * phi / (3.0 * n);
}

/// The area between the equator and latitude phi (closed form of the ellipsoid's zone).
double zoneArea(double phi) {
    const double s = std::sin(phi);
    return 2.0 * kPi * kB * kB * (s / (2.0 * (1.0 - kE2 * s * s)) + std::log((1.0 + kE * s) / (1.0 - kE * s)) / (4.0 * kE));
}

TEST(Geodesic, ArcsOfTheEquatorAndTheMeridianHaveTheirLengths) {
    EXPECT_NEAR(geodesicBetween({0.0, 0.0}, {90.0, 0.0}).metres, kA * kPi / 2.0, 1e-6);
    EXPECT_NEAR(geodesicBetween({-10.0, 0.0}, {25.0, 0.0}).metres, kA * 35.0 * kPi / 180.0, 1e-6);
    const double quarter = meridianArc(kPi / 2.0);
    EXPECT_NEAR(quarter, 10001965.7293, 1e-3);   // the textbook figure, as a check of the integral
    EXPECT_NEAR(geodesicBetween({0.0, 0.0}, {0.0, 90.0}).metres, quarter, 1e-4);
    EXPECT_NEAR(geodesicBetween({30.0, 10.0}, {30.0, 50.0}).metres, meridianArc(50.0 * kPi / 180.0) - meridianArc(10.0 * kPi / 180.0), 1e-4);
    // Azimuths: north along a meridian, east along the equator.
    EXPECT_NEAR(geodesicBetween({30.0, 10.0}, {30.0, 50.0}).azimuthStartDeg, 0.0, 1e-9);
    EXPECT_NEAR(geodesicBetween({0.0, 0.0}, {10.0, 0.0}).azimuthStartDeg, 90.0, 1e-9);
}

TEST(Geodesic, APathAcrossTheAntimeridianAndOverAPoleIsMeasuredTheShortWay) {
    const std::vector<LonLat> path{{179.5, 0.0}, {-179.5, 0.0}, {-178.5, 0.0}};
    const PathLength p = geodesicLength(path);
    ASSERT_EQ(p.along.size(), 3u);
    EXPECT_EQ(p.along[0], 0.0);
    EXPECT_NEAR(p.along[1], kA * kPi / 180.0, 1e-6);
    EXPECT_NEAR(p.metres, 2.0 * kA * kPi / 180.0, 1e-6);
    // From 89 N on one meridian to 89 N on the opposite one: over the pole, two degrees of meridian.
    EXPECT_NEAR(geodesicBetween({0.0, 89.0}, {180.0, 89.0}).metres, 2.0 * (meridianArc(kPi / 2.0) - meridianArc(89.0 * kPi / 180.0)), 1e-4);
}

TEST(Geodesic, DegeneratePathsAndPolygonsMeasureNothing) {
    EXPECT_EQ(geodesicLength({}).metres, 0.0);
    EXPECT_TRUE(geodesicLength({}).along.empty());
    const std::vector<LonLat> one{{5.0, 5.0}};
    EXPECT_EQ(geodesicLength(one).metres, 0.0);
    EXPECT_EQ(geodesicLength(one).along.size(), 1u);
    const std::vector<LonLat> two{{0.0, 0.0}, {1.0, 0.0}, {0.0, 0.0}};   // two vertices, closed
    EXPECT_EQ(geodesicPolygon(two).areaM2, 0.0);
    EXPECT_EQ(geodesicPolygon(two).vertices, 0u);
}

TEST(Geodesic, TheEquatorBoundsHalfTheEarthAndAParallelItsCap) {
    // Closed form of the whole ellipsoid: 2 pi a^2 (1 + (1 - e^2) / e atanh e).
    const double whole = 2.0 * kPi * kA * kA * (1.0 + (1.0 - kE2) / kE * std::atanh(kE));
    EXPECT_NEAR(ellipsoidArea() / whole, 1.0, 1e-12);
    EXPECT_NEAR(whole, 2.0 * zoneArea(kPi / 2.0), whole * 1e-12);
    // A ring along the equator: half the Earth (round either pole, the same).
    const std::vector<LonLat> equator{{0.0, 0.0}, {90.0, 0.0}, {180.0, 0.0}, {-90.0, 0.0}};
    const PolygonMeasure half = geodesicPolygon(equator);
    EXPECT_NEAR(half.areaM2 / (0.5 * whole), 1.0, 1e-9);
    EXPECT_NEAR(half.perimeterM, 2.0 * kPi * kA, 1e-5);
    EXPECT_EQ(half.vertices, 4u);
    // 3600 vertices on the parallel at 60 N round the pole: the cap above it (the geodesics
    // between neighbours bulge about a metre towards the pole).
    std::vector<LonLat> ring;
    for (int i = 0; i < 3600; ++i) ring.push_back({-180.0 + 0.1 * i, 60.0});
    const double cap = 0.5 * whole - zoneArea(60.0 * kPi / 180.0);
    const PolygonMeasure north = geodesicPolygon(ring);
    EXPECT_NEAR(north.areaM2 / cap, 1.0, 1e-5) << north.areaM2 << " against " << cap;
    EXPECT_NEAR(north.perimeterM / (2.0 * kPi * kA * std::cos(kPi / 3.0) / std::sqrt(1.0 - kE2 * 0.75)), 1.0, 1e-6);
    // The same ring round the south pole, walked the other way: the same cap.
    std::vector<LonLat> south;
    for (auto it = ring.rbegin(); it != ring.rend(); ++it) south.push_back({it->x, -it->y});
    EXPECT_NEAR(geodesicPolygon(south).areaM2 / cap, 1.0, 1e-5);
}

TEST(Geodesic, APolygonAcrossTheAntimeridianMeasuresAsTheSameOneElsewhereInEitherOrder) {
    const std::vector<LonLat> here{{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
    const std::vector<LonLat> there{{179.5, -0.5}, {-179.5, -0.5}, {-179.5, 0.5}, {179.5, 0.5}, {179.5, -0.5}};
    const std::vector<LonLat> backwards{{179.5, 0.5}, {-179.5, 0.5}, {-179.5, -0.5}, {179.5, -0.5}};
    const PolygonMeasure a = geodesicPolygon(here), b = geodesicPolygon(there), c = geodesicPolygon(backwards);
    // About a degree squared at the equator: 111.3 km x 110.6 km.
    EXPECT_NEAR(a.areaM2, 1.2308e10, 0.0005e10);
    EXPECT_NEAR(b.areaM2 / a.areaM2, 1.0, 1e-12);
    EXPECT_NEAR(c.areaM2 / a.areaM2, 1.0, 1e-12);
    EXPECT_EQ(b.vertices, 4u);   // the closing repeat dropped
    EXPECT_NEAR(b.perimeterM, a.perimeterM, 1e-6);
}

TEST(Geodesic, PointsAlongAGeodesicAreEvenlySpacedOnItAndContinueAcrossTheAntimeridian) {
    const LonLat a{170.0, 20.0}, b{-160.0, 40.0};
    const std::vector<LonLat> pts = geodesicPoints(a, b, 50000.0);
    const double total = geodesicBetween(a, b).metres;
    ASSERT_GE(pts.size(), size_t(std::ceil(total / 50000.0)) + 1);
    EXPECT_EQ(pts.front(), a);
    EXPECT_NEAR(pts.back().x, 200.0, 1e-9);   // -160 continued from 170
    EXPECT_NEAR(pts.back().y, 40.0, 1e-9);
    const double step = total / double(pts.size() - 1);
    EXPECT_LE(step, 50000.0);
    for (size_t i = 1; i < pts.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_LT(std::abs(pts[i].x - pts[i - 1].x), 5.0);   // no jump at the antimeridian
        // On the geodesic: as far from a as its place along it, and evenly spaced.
        EXPECT_NEAR(geodesicBetween(a, pts[i]).metres, step * double(i), 1e-3);
        EXPECT_NEAR(geodesicBetween(pts[i - 1], pts[i]).metres, step, 1e-3);
    }
    // Bounded: a short step over a long line gives at most maxPoints.
    EXPECT_EQ(geodesicPoints({0.0, 0.0}, {100.0, 10.0}, 1.0, 100).size(), 100u);
    // A and b the same: both ends.
    EXPECT_EQ(geodesicPoints(a, a, 1000.0).size(), 2u);
}

}  // namespace
}  // namespace orbis::globe
