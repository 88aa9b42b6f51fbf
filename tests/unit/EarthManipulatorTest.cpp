// Earth-manipulator maths: what the cursor grabs stays under it, the eye stays above the
// terrain, flights end exactly where asked and take the short way.
#include "globe/EarthManipulator.h"
#include "globe/Ellipsoid.h"

#include <gtest/gtest.h>

#include <cmath>

namespace orbis::globe {
namespace {

const Ellipsoid& wgs84() { return Ellipsoid::wgs84(); }

bool finite(const Pose& p) {
    return std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(p.position.z) &&
           std::isfinite(p.orientation.w) && std::isfinite(p.orientation.x) && std::isfinite(p.orientation.y) &&
           std::isfinite(p.orientation.z);
}

bool finite(const Viewpoint& v) {
    return std::isfinite(v.lonDeg) && std::isfinite(v.latDeg) && std::isfinite(v.height) &&
           std::isfinite(v.headingDeg) && std::isfinite(v.pitchDeg) && std::isfinite(v.range);
}

// Distance from `point` to the ray through `ndc`, relative to its distance from the eye.
double offRay(const EarthManipulator& m, const glm::dvec2& ndc, const glm::dvec3& point) {
    const glm::dvec3 toPoint = point - m.pose().position;
    return glm::length(glm::cross(toPoint, m.rayDirection(ndc))) / glm::length(toPoint);
}

double angleDiff(double a, double b) { return std::abs(wrapLongitude(a - b)); }

void expectViewpointNear(const Viewpoint& a, const Viewpoint& b, double degTol, double mTol) {
    EXPECT_NEAR(angleDiff(a.lonDeg, b.lonDeg), 0.0, degTol);
    EXPECT_NEAR(a.latDeg, b.latDeg, degTol);
    EXPECT_NEAR(a.height, b.height, mTol);
    EXPECT_NEAR(angleDiff(a.headingDeg, b.headingDeg), 0.0, degTol);
    EXPECT_NEAR(a.pitchDeg, b.pitchDeg, degTol);
    EXPECT_NEAR(a.range, b.range, mTol);
}

double eyeHeight(const EarthManipulator& m) { return wgs84().toGeodetic(m.pose().position).height; }

TEST(EarthManipulator, ViewpointRoundTripsThroughThePose) {
    // Tolerances: 1e-7 degrees (1 cm) and 1 mm, from double rounding through ECEF.
    EarthManipulator m;
    for (const Viewpoint& vp : {Viewpoint{10.0, 45.0, 0.0, 30.0, -40.0, 5000.0}, Viewpoint{-120.0, -33.0, 0.0, 200.0 - 360.0, -89.0, 2.0e6},
                                Viewpoint{179.5, 10.0, 0.0, -90.0, -10.0, 1.0e5}, Viewpoint{5.0, 5.0, 0.0, 45.0, -90.0, 1.0e4}}) {
        m.setViewpoint(vp);
        expectViewpointNear(m.viewpoint(), vp, 1e-7, 1e-3);
    }
}

TEST(EarthManipulator, GrabRotateKeepsTheGrabbedPointUnderTheCursor) {
    // Within 1e-6 of the eye distance (in practice ~1e-12: the rotation is exact).
    struct Case {
        Viewpoint vp;
        glm::dvec2 from, to;
    };
    const Case cases[] = {
        {{10.0, 40.0, 0.0, 30.0, -50.0, 2.0e5}, {0.2, 0.1}, {-0.3, 0.4}},
        {{0.0, 0.0, 0.0, 0.0, -90.0, 2.0e7}, {0.05, -0.05}, {-0.1, 0.12}},
        {{-75.0, 60.0, 0.0, 300.0, -20.0, 3000.0}, {0.0, 0.5}, {0.3, 0.9}},
        {{179.9, 0.0, 0.0, 90.0, -45.0, 1.0e5}, {-0.4, 0.2}, {0.6, 0.3}},   // across the antimeridian
        {{0.0, 89.5, 0.0, 0.0, -60.0, 2.0e5}, {0.0, 0.3}, {0.0, -0.2}},     // over the pole
    };
    for (const auto& c : cases) {
        EarthManipulator m;
        m.setViewpoint(c.vp);
        const auto grabbed = m.intersectGround(m.pose().position, m.rayDirection(c.from));
        ASSERT_TRUE(grabbed.has_value());
        m.rotate(c.from, c.to);
        ASSERT_TRUE(finite(m.pose()));
        EXPECT_LT(offRay(m, c.to, *grabbed), 1e-6);
        const auto under = m.intersectGround(m.pose().position, m.rayDirection(c.to));
        ASSERT_TRUE(under.has_value());
        EXPECT_LT(glm::length(*under - *grabbed) / c.vp.range, 1e-6);
    }
}

TEST(EarthManipulator, GrabRotateOnRaisedTerrainKeepsThePointUnderTheCursor) {
    // A 3000 m plateau: the grabbed point is on the terrain, not the ellipsoid.
    EarthManipulator m;
    m.setHeightQuery([](double, double) { return std::optional<double>(3000.0); });
    m.setViewpoint({-105.0, 39.0, 3000.0, 20.0, -35.0, 2.0e4});
    const glm::dvec2 from(0.1, 0.3), to(-0.2, 0.1);
    const auto grabbed = m.intersectGround(m.pose().position, m.rayDirection(from));
    ASSERT_TRUE(grabbed.has_value());
    // 1 cm: the ellipsoid with both axes raised by 3000 m is within ~5 mm of the true 3000 m
    // height surface (Ellipsoid::intersectRay).
    EXPECT_NEAR(wgs84().toGeodetic(*grabbed).height, 3000.0, 1e-2);
    m.rotate(from, to);
    EXPECT_LT(offRay(m, to, *grabbed), 1e-6);
}

TEST(EarthManipulator, GrabOffTheGlobeRotatesInProportionToTheDrag) {
    EarthManipulator m;
    m.setViewpoint({0.0, 0.0, 0.0, 0.0, -90.0, 3.0e7});
    const glm::dvec2 corner(0.95, 0.95);
    ASSERT_FALSE(m.intersectGround(m.pose().position, m.rayDirection(corner)).has_value());
    const Viewpoint before = m.viewpoint();
    m.rotate(corner, corner + glm::dvec2(-0.1, 0.0));   // drag left: the globe turns left, we go east
    ASSERT_TRUE(finite(m.pose()));
    const Viewpoint after = m.viewpoint();
    EXPECT_GT(after.lonDeg, before.lonDeg + 0.5);
    EXPECT_NEAR(after.latDeg, before.latDeg, 1e-6);
    EXPECT_NEAR(glm::length(m.pose().position), 3.0e7 + wgs84().equatorialRadius(), 1.0);
}

TEST(EarthManipulator, ZoomKeepsTheCursorPointFixed) {
    EarthManipulator m;
    m.setViewpoint({20.0, 30.0, 0.0, 10.0, -45.0, 1.0e5});
    const glm::dvec2 cursor(0.3, -0.2);
    const glm::dvec3 p = *m.intersectGround(m.pose().position, m.rayDirection(cursor));
    for (double factor : {0.5, 0.1, 3.0}) {
        const double before = glm::length(m.pose().position - p);
        m.zoom(factor, cursor);
        EXPECT_NEAR(glm::length(m.pose().position - p), before * factor, 1e-6 * before);
        EXPECT_LT(offRay(m, cursor, p), 1e-9);
        const auto under = m.intersectGround(m.pose().position, m.rayDirection(cursor));
        ASSERT_TRUE(under.has_value());
        EXPECT_LT(glm::length(*under - p), 1e-6 * before);
    }
    // At the screen centre the pivot range scales by the factor.
    const double range = m.viewpoint().range;
    m.zoom(0.25, {0.0, 0.0});
    EXPECT_NEAR(m.viewpoint().range, 0.25 * range, 1e-6 * range);
}

TEST(EarthManipulator, TiltIsClampedBetweenStraightDownAndJustBelowTheHorizon) {
    EarthManipulator m;
    m.setViewpoint({5.0, 50.0, 0.0, 0.0, -45.0, 1.0e4});
    const Viewpoint start = m.viewpoint();
    m.tilt(10.0);
    EXPECT_NEAR(m.viewpoint().pitchDeg, -35.0, 1e-7);
    EXPECT_NEAR(m.viewpoint().latDeg, start.latDeg, 1e-7);   // about the pivot
    EXPECT_NEAR(m.viewpoint().range, start.range, 1e-3);
    m.tilt(200.0);
    EXPECT_NEAR(m.viewpoint().pitchDeg, EarthManipulator::kMaxPitchDeg, 1e-7);
    m.tilt(-500.0);
    EXPECT_NEAR(m.viewpoint().pitchDeg, EarthManipulator::kMinPitchDeg, 1e-7);
    EXPECT_NEAR(m.viewpoint().headingDeg, 0.0, 1e-6);   // straight down keeps the heading
    m.setViewpoint({5.0, 50.0, 0.0, 0.0, 30.0, 1.0e4});   // looking up is not a globe view
    EXPECT_NEAR(m.viewpoint().pitchDeg, EarthManipulator::kMaxPitchDeg, 1e-7);
}

TEST(EarthManipulator, TurnChangesHeadingAboutThePivot) {
    EarthManipulator m;
    m.setViewpoint({-3.0, 40.0, 0.0, 170.0, -30.0, 2.0e4});
    m.turn(20.0);
    const Viewpoint v = m.viewpoint();
    EXPECT_NEAR(angleDiff(v.headingDeg, 190.0), 0.0, 1e-7);
    EXPECT_NEAR(v.lonDeg, -3.0, 1e-7);
    EXPECT_NEAR(v.latDeg, 40.0, 1e-7);
    EXPECT_NEAR(v.pitchDeg, -30.0, 1e-7);
    EXPECT_NEAR(v.range, 2.0e4, 1e-3);
}

TEST(EarthManipulator, PanMovesTheGroundWithTheCursor) {
    // The ground point under the centre ends (nearly: the tangent plane is not the ellipsoid)
    // under the cursor; heading, pitch and range stay.
    EarthManipulator m;
    m.setViewpoint({12.0, 41.0, 0.0, 60.0, -60.0, 5000.0});
    const glm::dvec3 centre = *m.intersectGround(m.pose().position, m.rayDirection({0.0, 0.0}));
    m.pan({0.0, 0.0}, {0.3, 0.2});
    EXPECT_LT(offRay(m, {0.3, 0.2}, centre), 1e-3);
    const Viewpoint v = m.viewpoint();
    EXPECT_NEAR(angleDiff(v.headingDeg, 60.0), 0.0, 0.01);
    EXPECT_NEAR(v.pitchDeg, -60.0, 0.01);
    EXPECT_NEAR(v.range, 5000.0, 5.0);
}

TEST(EarthManipulator, EyeNeverGoesUnderTheTerrain) {
    // Everest everywhere: the eye keeps at least the 1 m clearance above 8848 m, whatever it is
    // asked (tolerance 1 um for the push along the normal).
    EarthManipulator m;
    m.setHeightQuery([](double, double) { return std::optional<double>(8848.0); });
    const double floor = 8848.0 + m.minClearance() - 1e-6;
    m.setViewpoint({86.9, 27.98, 0.0, 0.0, -30.0, 50.0});
    EXPECT_GE(eyeHeight(m), floor);
    for (int i = 0; i < 40; ++i) {
        m.zoom(0.3, {0.1, 0.4});
        EXPECT_GE(eyeHeight(m), floor);
    }
    m.tilt(80.0);
    EXPECT_GE(eyeHeight(m), floor);
    m.rotate({0.0, 0.5}, {0.0, -0.5});
    EXPECT_GE(eyeHeight(m), floor);
    m.pan({0.0, 0.0}, {0.5, 0.5});
    EXPECT_GE(eyeHeight(m), floor);
    m.flyTo({-70.0, -33.0, 0.0, 0.0, -10.0, 10.0}, 2.0);
    while (m.flying()) {
        m.advance(0.05);
        EXPECT_GE(eyeHeight(m), floor);
    }
    // Below the ellipsoid (a query of -400 m) the ellipsoid is the floor.
    m.setHeightQuery([](double, double) { return std::optional<double>(-400.0); });
    m.setViewpoint({35.5, 31.5, -400.0, 0.0, -90.0, 10.0});
    EXPECT_GE(eyeHeight(m), m.minClearance() - 1e-6);
}

TEST(EarthManipulator, FlyToEndsExactlyAtTheTarget) {
    EarthManipulator m;
    const Viewpoint start{2.35, 48.85, 0.0, 0.0, -60.0, 3000.0};
    const Viewpoint target{-74.0, 40.7, 0.0, 250.0, -30.0, 1500.0};
    m.setViewpoint(start);
    m.flyTo(target, 5.0);
    EXPECT_TRUE(m.flying());
    m.advance(0.0);
    expectViewpointNear(m.viewpoint(), start, 1e-7, 1e-3);
    int steps = 0;
    while (m.flying() && steps < 1000) {
        m.advance(1.0 / 60.0);
        ASSERT_TRUE(finite(m.pose()));
        ++steps;
    }
    EXPECT_FALSE(m.flying());
    EXPECT_NEAR(steps, 300, 1);
    expectViewpointNear(m.viewpoint(), target, 1e-7, 1e-3);
    // The pure interpolation is exact at both ends.
    const Viewpoint a = interpolateFlight(start, target, 0.0), b = interpolateFlight(start, target, 1.0);
    EXPECT_EQ(a.lonDeg, start.lonDeg);
    EXPECT_EQ(a.range, start.range);
    EXPECT_EQ(b.lonDeg, target.lonDeg);
    EXPECT_EQ(b.headingDeg, target.headingDeg);
}

TEST(EarthManipulator, ZeroDurationFlyToJumps) {
    EarthManipulator m;
    const Viewpoint target{100.0, -10.0, 0.0, 45.0, -45.0, 1.0e4};
    m.flyTo(target, 0.0);
    EXPECT_FALSE(m.flying());
    expectViewpointNear(m.viewpoint(), target, 1e-7, 1e-3);
}

TEST(EarthManipulator, UserInputCancelsAFlight) {
    EarthManipulator m;
    m.flyTo({100.0, -10.0, 0.0, 45.0, -45.0, 1.0e4}, 3.0);
    m.advance(0.5);
    m.tilt(1.0);
    EXPECT_FALSE(m.flying());
}

TEST(EarthManipulator, LongFlightClimbsAtItsMidpoint) {
    const Viewpoint a{0.0, 0.0, 0.0, 0.0, -45.0, 1.0e5}, b{90.0, 30.0, 0.0, 0.0, -45.0, 2.0e5};
    const Viewpoint mid = interpolateFlight(a, b, 0.5);
    EXPECT_GT(mid.range, 3.0 * std::max(a.range, b.range));
    // The eye during a flight too.
    EarthManipulator m;
    m.setViewpoint(a);
    const double h0 = eyeHeight(m);
    m.flyTo(b, 10.0);
    m.advance(5.0);
    const double hMid = eyeHeight(m);
    m.advance(5.0);
    EXPECT_GT(hMid, 3.0 * std::max(h0, eyeHeight(m)));
    // The arc vanishes for a flight on the spot.
    const Viewpoint c{0.0, 0.0, 0.0, 0.0, -45.0, 5.0e5};
    EXPECT_NEAR(interpolateFlight(a, c, 0.5).range, 3.0e5, 1e-6);
}

TEST(EarthManipulator, AntimeridianFlightGoesTheShortWay) {
    const Viewpoint a{179.0, 10.0, 0.0, 0.0, -45.0, 1.0e4}, b{-179.0, 12.0, 0.0, 0.0, -45.0, 1.0e4};
    for (int i = 0; i <= 100; ++i) {
        const Viewpoint v = interpolateFlight(a, b, i / 100.0);
        EXPECT_GE(std::abs(v.lonDeg), 179.0 - 1e-9) << i;
        EXPECT_GE(v.latDeg, 10.0 - 1e-9);
        EXPECT_LE(v.latDeg, 12.0 + 1e-3);   // the great circle bulges a little poleward
    }
    // Ground distance of 2 degrees: the arc stays small.
    EXPECT_LT(interpolateFlight(a, b, 0.5).range, 1.0e4 + 0.6 * 2.0 * 111320.0 * 1.5);
}

TEST(EarthManipulator, HeadingTurnsTheShortWay) {
    const Viewpoint a{0.0, 0.0, 0.0, 350.0, -45.0, 1.0e4}, b{0.0, 0.0, 0.0, 10.0, -45.0, 1.0e4};
    EXPECT_NEAR(angleDiff(interpolateFlight(a, b, 0.5).headingDeg, 0.0), 0.0, 1e-9);
    EXPECT_NEAR(angleDiff(interpolateFlight(b, a, 0.25).headingDeg, 5.0), 0.0, 1e-9);
}

TEST(EarthManipulator, PoleViewpointsGiveFinitePoses) {
    EarthManipulator m;
    for (double lat : {90.0, -90.0})
        for (double pitch : {-90.0, -45.0, -1.0})
            for (double heading : {0.0, 135.0}) {
                const Viewpoint vp{30.0, lat, 0.0, heading, pitch, 1.0e6};
                m.setViewpoint(vp);
                ASSERT_TRUE(finite(m.pose()));
                const Viewpoint back = m.viewpoint();
                ASSERT_TRUE(finite(back));
                // The same view, whatever longitude it is expressed in at the pole.
                const Pose again = poseFromViewpoint(back);
                EXPECT_LT(glm::length(again.position - m.pose().position), 1e-3);
                EXPECT_GT(std::abs(glm::dot(again.orientation, m.pose().orientation)), 1.0 - 1e-9);
                m.tilt(5.0);
                m.turn(30.0);
                m.zoom(0.5, {0.2, 0.2});
                m.rotate({0.0, 0.0}, {0.1, 0.1});
                m.pan({0.0, 0.0}, {0.1, -0.1});
                ASSERT_TRUE(finite(m.pose()));
                ASSERT_TRUE(finite(m.viewpoint()));
            }
    // Flights to, from and between the poles.
    const Viewpoint north{0.0, 90.0, 0.0, 0.0, -60.0, 1.0e5}, south{45.0, -90.0, 0.0, 0.0, -60.0, 1.0e5},
        paris{2.35, 48.85, 0.0, 0.0, -60.0, 1.0e5};
    for (const auto& [from, to] : {std::pair{paris, north}, std::pair{north, paris}, std::pair{north, south}}) {
        for (int i = 0; i <= 50; ++i) {
            const Viewpoint v = interpolateFlight(from, to, i / 50.0);
            ASSERT_TRUE(finite(v)) << i;
            ASSERT_TRUE(finite(poseFromViewpoint(v))) << i;
        }
        EXPECT_EQ(interpolateFlight(from, to, 1.0).latDeg, to.latDeg);
    }
    // Leaving the pole, the view turns smoothly: the first step looks (nearly) the same way as
    // the start, although the longitude jumps to the path's meridian.
    const Pose p0 = poseFromViewpoint(interpolateFlight(north, paris, 0.0));
    const Pose p1 = poseFromViewpoint(interpolateFlight(north, paris, 1e-6));
    EXPECT_GT(glm::dot(p0.orientation * glm::dvec3(0, 0, -1), p1.orientation * glm::dvec3(0, 0, -1)), 1.0 - 1e-6);
}

}  // namespace
}  // namespace orbis::globe
