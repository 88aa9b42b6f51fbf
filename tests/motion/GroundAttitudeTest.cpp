// Ground vehicles pitch and roll with the terrain (formats/motion/GroundAttitude.h), on a
// synthetic ground that rises 10 % towards the north.
#include "formats/motion/GroundAttitude.h"

#include "globe/Ellipsoid.h"
#include "formats/motion/Attitude.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace orbis;
using namespace orbis::motion;

namespace {

constexpr double kLon = 9.0, kLat = 46.0;
// The slope's answer is exact up to the Earth's curvature across the footprint (L / R ~ 1e-6
// rad for 5 m): 1e-5 degrees.
constexpr double kTolDeg = 1e-5;
const double kSlopeDeg = glm::degrees(std::atan(0.1));

/// 10 % up towards the north: the height is 0.1 x the distance north of (kLon, kLat), measured
/// along the local north there.
GroundFn tiltedGround(double base = 300.0) {
    const auto& e = globe::Ellipsoid::wgs84();
    const glm::dvec3 origin = e.toEcef(kLon, kLat, 0.0);
    const glm::dvec3 north = e.enuFrame(kLon, kLat)[1];
    return [=](double lon, double lat) -> std::optional<double> {
        return base + 0.1 * glm::dot(globe::Ellipsoid::wgs84().toEcef(lon, lat, 0.0) - origin, north);
    };
}

Trajectory groundTrack(double headingDeg, double agl = 0.0) {
    // Two samples 100 m apart along the heading, on the ground, the heading given.
    const auto& e = globe::Ellipsoid::wgs84();
    const glm::dmat3 enu = e.enuFrame(kLon, kLat);
    const double h = glm::radians(headingDeg);
    std::vector<TrajectorySample> samples(2);
    for (int i = 0; i < 2; ++i) {
        const globe::Geodetic g = e.toGeodetic(e.toEcef(kLon, kLat, 0.0) + enu * (glm::dvec3(std::sin(h), std::cos(h), 0.0) * (100.0 * i - 50.0)));
        samples[size_t(i)].t = fromSeconds(10.0 * i);
        samples[size_t(i)].lonDeg = g.lonDeg;
        samples[size_t(i)].latDeg = g.latDeg;
        samples[size_t(i)].alt = agl;
        samples[size_t(i)].altRef = AltitudeRef::Ground;
        samples[size_t(i)].headingDeg = headingDeg;
        samples[size_t(i)].pitchDeg = 0.0;
        samples[size_t(i)].rollDeg = 0.0;
    }
    return Trajectory::create(samples, {}, "ground track").value();
}

}  // namespace

TEST(GroundAttitude, UpTheSlopePitchesByItsAngle) {
    const GroundFn ground = tiltedGround();
    const auto q = groundAttitude(kLon, kLat, 0.0, {9.0, 1.5}, ground);
    ASSERT_TRUE(q);
    const HeadingPitchRoll a = headingPitchRoll(*q, kLon, kLat);
    EXPECT_NEAR(a.pitchDeg, kSlopeDeg, kTolDeg);
    EXPECT_NEAR(a.rollDeg, 0.0, kTolDeg);
    EXPECT_NEAR(a.headingDeg, 0.0, kTolDeg);
    // Down the slope: nose down.
    const HeadingPitchRoll down = headingPitchRoll(*groundAttitude(kLon, kLat, 180.0, {9.0, 1.5}, ground), kLon, kLat);
    EXPECT_NEAR(down.pitchDeg, -kSlopeDeg, kTolDeg);
    EXPECT_NEAR(down.headingDeg, 180.0, kTolDeg);
}

TEST(GroundAttitude, AcrossTheSlopeRolls) {
    const GroundFn ground = tiltedGround();
    // Heading east the rising north is on the left: right wing down, positive roll.
    const HeadingPitchRoll east = headingPitchRoll(*groundAttitude(kLon, kLat, 90.0, {9.0, 1.5}, ground), kLon, kLat);
    EXPECT_NEAR(east.rollDeg, kSlopeDeg, kTolDeg);
    EXPECT_NEAR(east.pitchDeg, 0.0, kTolDeg);
    EXPECT_NEAR(east.headingDeg, 90.0, kTolDeg);
    const HeadingPitchRoll west = headingPitchRoll(*groundAttitude(kLon, kLat, 270.0, {9.0, 1.5}, ground), kLon, kLat);
    EXPECT_NEAR(west.rollDeg, -kSlopeDeg, kTolDeg);
    // Diagonally: the heading stays, pitch and roll share the slope (the steepest descent's
    // angle is still atan(0.1): the down axis is the plane's normal).
    const glm::dquat q = *groundAttitude(kLon, kLat, 45.0, {9.0, 1.5}, ground);
    const HeadingPitchRoll d = headingPitchRoll(q, kLon, kLat);
    EXPECT_NEAR(d.headingDeg, 45.0, kTolDeg);
    EXPECT_NEAR(d.pitchDeg, glm::degrees(std::atan(0.1 * std::sqrt(0.5))), kTolDeg);
    const glm::dvec3 up = globe::Ellipsoid::wgs84().enuFrame(kLon, kLat)[2];
    EXPECT_NEAR(glm::degrees(std::acos(glm::dot(upAxis(q), up))), kSlopeDeg, kTolDeg);
}

TEST(GroundAttitude, TrajectoryOnTheGroundFollowsItsSlope) {
    const GroundFn ground = tiltedGround();
    for (double heading : {0.0, 90.0}) {
        auto p = groundTrack(heading).pose(fromSeconds(5.0), &ground);
        ASSERT_TRUE(p);
        EXPECT_TRUE(p->onGround);
        EXPECT_NEAR(p->pitchDeg, 0.0, kTolDeg) << "the track's own attitude is level";
        followGround(*p, {9.0, 1.5}, ground);
        EXPECT_NEAR(p->pitchDeg, heading == 0.0 ? kSlopeDeg : 0.0, kTolDeg) << heading;
        EXPECT_NEAR(p->rollDeg, heading == 0.0 ? 0.0 : kSlopeDeg, kTolDeg) << heading;
        EXPECT_NEAR(p->headingDeg, heading, 1e-9);
        EXPECT_NEAR(headingPitchRoll(p->orientation, p->lonDeg, p->latDeg).pitchDeg, p->pitchDeg, 1e-9);
    }
}

TEST(GroundAttitude, FlyingOrUnknownGroundKeepsTheTrackAttitude) {
    const GroundFn ground = tiltedGround();
    // 50 m above the ground: a drone, not a car.
    auto flying = groundTrack(0.0, 50.0).pose(fromSeconds(5.0), &ground);
    ASSERT_TRUE(flying);
    EXPECT_FALSE(flying->onGround);
    followGround(*flying, {9.0, 1.5}, ground);
    EXPECT_NEAR(flying->pitchDeg, 0.0, kTolDeg);
    // Ground known under the vehicle but not ahead of it: the track's attitude.
    const GroundFn patchy = [&](double lon, double lat) -> std::optional<double> {
        if (lat > kLat + 1e-5) return std::nullopt;
        return ground(lon, lat);
    };
    auto p = groundTrack(0.0).pose(fromSeconds(5.0), &patchy);
    ASSERT_TRUE(p);
    EXPECT_TRUE(p->onGround);
    followGround(*p, {9.0, 1.5}, patchy);
    EXPECT_NEAR(p->pitchDeg, 0.0, kTolDeg);
    EXPECT_FALSE(groundAttitude(kLon, kLat, 0.0, {0.0, 0.0}, ground)) << "no footprint, no slope";
    EXPECT_FALSE(groundAttitude(kLon, kLat, 0.0, {9.0, 1.5}, GroundFn{}));
}
