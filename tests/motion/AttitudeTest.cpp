// The heading/pitch/roll convention (ST 0601, Attitude.h): which way each angle turns the body,
// agreement with the FMV sensor model, the angles' round trip, slerp the short way.
#include "layers/fmv/SensorModel.h"
#include "formats/motion/Attitude.h"
#include "MotionTestUtil.h"

#include <gtest/gtest.h>

#include <random>

namespace orbis::motion {
namespace {

using namespace test;

// Rotating unit vectors by a unit quaternion built from a few products of sines and cosines:
// rounding leaves ~1e-16 per component, so 1e-12 is a wide margin that still catches any wrong
// sign or axis (those are off by order 1).
constexpr double kVecTol = 1e-12;

void expectVecNear(const glm::dvec3& a, const glm::dvec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

const double kPlaces[][2] = {{0, 0}, {7.5, 46.2}, {-120, -33}, {179.9, 10}, {-179.9, -80}, {45, 90}, {45, -90}};

TEST(Attitude, HeadingZeroLooksNorth) {
    for (const auto& place : kPlaces) {
        const glm::dquat q = bodyToEcef(place[0], place[1], 0.0, 0.0, 0.0);
        const glm::dmat3 f = enu(place[0], place[1]);
        expectVecNear(forwardAxis(q), f[1], kVecTol);
        expectVecNear(rightAxis(q), f[0], kVecTol);
        expectVecNear(upAxis(q), f[2], kVecTol);
    }
}

TEST(Attitude, Heading90LooksEast) {
    for (const auto& place : kPlaces) {
        const glm::dquat q = bodyToEcef(place[0], place[1], 90.0, 0.0, 0.0);
        const glm::dmat3 f = enu(place[0], place[1]);
        expectVecNear(forwardAxis(q), f[0], kVecTol);    // east
        expectVecNear(rightAxis(q), -f[1], kVecTol);     // south
        expectVecNear(upAxis(q), f[2], kVecTol);
    }
}

TEST(Attitude, PositivePitchRaisesTheNose) {
    const glm::dmat3 f = enu(7.5, 46.2);
    const double c = std::cos(glm::radians(10.0)), s = std::sin(glm::radians(10.0));
    const glm::dquat q = bodyToEcef(7.5, 46.2, 0.0, 10.0, 0.0);
    expectVecNear(forwardAxis(q), c * f[1] + s * f[2], kVecTol);
    expectVecNear(rightAxis(q), f[0], kVecTol);
}

TEST(Attitude, PositiveRollLowersTheRightWing) {
    const glm::dmat3 f = enu(7.5, 46.2);
    const double c = std::cos(glm::radians(20.0)), s = std::sin(glm::radians(20.0));
    const glm::dquat q = bodyToEcef(7.5, 46.2, 0.0, 0.0, 20.0);
    expectVecNear(forwardAxis(q), f[1], kVecTol);
    expectVecNear(rightAxis(q), c * f[0] - s * f[2], kVecTol);   // right wing below the horizon
    expectVecNear(upAxis(q), c * f[2] + s * f[0], kVecTol);      // roof leans right
}

TEST(Attitude, HeadingPitchRollAppliedInThatOrder) {
    // Heading 90, pitch 10, roll 20: the nose east and 10 degrees up; rolling about the nose
    // then lowers the right wing (south side) by 20 degrees.
    const glm::dmat3 f = enu(-120.0, -33.0);
    const double cp = std::cos(glm::radians(10.0)), sp = std::sin(glm::radians(10.0));
    const double cr = std::cos(glm::radians(20.0)), sr = std::sin(glm::radians(20.0));
    const glm::dquat q = bodyToEcef(-120.0, -33.0, 90.0, 10.0, 20.0);
    const glm::dvec3 forward = cp * f[0] + sp * f[2];
    const glm::dvec3 levelRight = -f[1];
    const glm::dvec3 levelUp = glm::cross(levelRight, forward);   // body -z before the roll
    expectVecNear(forwardAxis(q), forward, kVecTol);
    expectVecNear(rightAxis(q), cr * levelRight - sr * levelUp, kVecTol);
}

TEST(Attitude, AgreesWithTheFmvSensorModel) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> lon(-180, 180), lat(-89, 89), heading(0, 360), pitch(-80, 80), roll(-180, 180);
    for (int i = 0; i < 200; ++i) {
        fmv::SensorPose p;
        p.lonDeg = lon(rng);
        p.latDeg = lat(rng);
        p.platformHeadingDeg = heading(rng);
        p.platformPitchDeg = pitch(rng);
        p.platformRollDeg = roll(rng);
        const fmv::SensorCamera camera(p);   // sensor angles 0: the camera's axes are the platform's
        const glm::dmat3 r = glm::mat3_cast(bodyToEcef(p.lonDeg, p.latDeg, p.platformHeadingDeg, p.platformPitchDeg, p.platformRollDeg));
        for (int c = 0; c < 3; ++c) expectVecNear(r[c], camera.axes()[c], 1e-12);
    }
}

TEST(Attitude, AnglesRoundTrip) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> lon(-180, 180), lat(-90, 90), heading(0, 360), pitch(-89.9, 89.9), roll(-179.9, 179.9);
    for (int i = 0; i < 1000; ++i) {
        const double lo = lon(rng), la = lat(rng), h = heading(rng), p = pitch(rng), r = roll(rng);
        const HeadingPitchRoll a = headingPitchRoll(bodyToEcef(lo, la, h, p, r), lo, la);
        // atan2 of products of rounded sines: ~1e-14 rad; the margin covers pitch near 90.
        EXPECT_NEAR(headingDiff(a.headingDeg, h), 0.0, 1e-9);
        EXPECT_NEAR(a.pitchDeg, p, 1e-9);
        EXPECT_NEAR(headingDiff(a.rollDeg, r), 0.0, 1e-9);
        EXPECT_GE(a.headingDeg, 0.0);
        EXPECT_LT(a.headingDeg, 360.0);
    }
}

TEST(Attitude, NoseStraightUpPutsTheWholeTurnInHeading) {
    const HeadingPitchRoll a = headingPitchRoll(bodyToEcef(10.0, 20.0, 30.0, 90.0, 0.0), 10.0, 20.0);
    EXPECT_NEAR(a.pitchDeg, 90.0, 1e-6);
    EXPECT_EQ(a.rollDeg, 0.0);
    EXPECT_NEAR(headingDiff(a.headingDeg, 30.0), 0.0, 1e-6);
}

TEST(Attitude, DirectionGivesCourseAndClimb) {
    const glm::dmat3 f = enu(7.5, 46.2);
    const HeadingPitchRoll a = headingPitchFromDirection(f[0] + f[1] + std::sqrt(2.0) * f[2], 7.5, 46.2);
    EXPECT_NEAR(a.headingDeg, 45.0, 1e-9);
    EXPECT_NEAR(a.pitchDeg, 45.0, 1e-9);
    EXPECT_EQ(a.rollDeg, 0.0);
    const HeadingPitchRoll west = headingPitchFromDirection(-f[0], 7.5, 46.2);
    EXPECT_NEAR(west.headingDeg, 270.0, 1e-9);
    const HeadingPitchRoll none = headingPitchFromDirection(glm::dvec3(0.0), 7.5, 46.2);
    EXPECT_EQ(none.headingDeg, 0.0);
    EXPECT_EQ(none.pitchDeg, 0.0);
}

TEST(Attitude, SlerpGoesTheShortWayThroughNorth) {
    const glm::dquat a = bodyToNed(350.0, 0.0, 0.0), b = bodyToNed(10.0, 0.0, 0.0);
    for (double f : {0.25, 0.5, 0.75}) {
        const HeadingPitchRoll m = headingPitchRoll(glm::mat3_cast(slerpShortest(a, b, f)));
        EXPECT_NEAR(headingDiff(m.headingDeg, 350.0 + 20.0 * f), 0.0, 1e-9);
    }
    // Also when the stored quaternions lie in opposite hemispheres.
    const HeadingPitchRoll m = headingPitchRoll(glm::mat3_cast(slerpShortest(a, -b, 0.5)));
    EXPECT_NEAR(headingDiff(m.headingDeg, 0.0), 0.0, 1e-9);
}

TEST(Attitude, SlerpIsExactInAngleForTinyAndLargeTurns) {
    for (double turn : {1e-7, 1e-3, 1.0, 90.0, 179.0}) {
        const glm::dquat a = bodyToNed(0.0, 0.0, 0.0), b = bodyToNed(0.0, 0.0, turn);
        const glm::dquat m = slerpShortest(a, b, 0.3);
        EXPECT_NEAR(angleBetweenDeg(a, m), 0.3 * turn, 1e-12 + 1e-12 * turn) << turn;
        EXPECT_NEAR(glm::length(m), 1.0, 1e-15);
    }
}

TEST(Attitude, GltfAxesMapYUpAndZForward) {
    const glm::dquat q = bodyToEcef(7.5, 46.2, 90.0, 0.0, 0.0);
    const glm::dmat3 g = gltfToEcef(q);
    const glm::dmat3 f = enu(7.5, 46.2);
    expectVecNear(g[2], f[0], kVecTol);    // +Z forward: east at heading 90
    expectVecNear(g[1], f[2], kVecTol);    // +Y up
    expectVecNear(g[0], f[1], kVecTol);    // +X left: north when facing east
    EXPECT_NEAR(glm::determinant(g), 1.0, 1e-12);
}

TEST(Attitude, GltfToEcefIsThePoseOnGltfToBody) {
    // One convention (gltfToBody), put on any pose: the columns are the body's left, up and
    // forward axes in ECEF.
    const glm::dquat q = bodyToEcef(-120.0, -33.0, 217.0, 12.0, -25.0);
    const glm::dmat3 g = gltfToEcef(q);
    expectVecNear(g[0], -rightAxis(q), 1e-15);
    expectVecNear(g[1], upAxis(q), 1e-15);
    expectVecNear(g[2], forwardAxis(q), 1e-15);
    EXPECT_EQ(gltfToBody() * glm::dvec3(0, 0, 1), glm::dvec3(1, 0, 0));   // glTF front: body forward
    EXPECT_DOUBLE_EQ(glm::determinant(gltfToBody()), 1.0);
}

TEST(Attitude, WrapHeading) {
    EXPECT_EQ(wrapHeadingDeg(360.0), 0.0);
    EXPECT_EQ(wrapHeadingDeg(-90.0), 270.0);
    EXPECT_EQ(wrapHeadingDeg(725.0), 5.0);
    EXPECT_LT(wrapHeadingDeg(-1e-17), 360.0);
}

}  // namespace
}  // namespace orbis::motion
