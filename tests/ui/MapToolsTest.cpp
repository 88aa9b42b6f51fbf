// Map tools: picking lands on the ground the ray meets first (ellipsoid or terrain), across
// the antimeridian and at the poles, and nowhere above the horizon; the scale bar is round and
// fits; the compass reads the heading however the camera looks.
#include "ui/input/MapTools.h"

#include "globe/Ellipsoid.h"
#include "globe/Viewpoint.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace orbis::ui {
namespace {

using globe::Pose;
using globe::Viewpoint;

const globe::Ellipsoid& wgs84() { return globe::Ellipsoid::wgs84(); }
const double kFov = glm::radians(45.0);
constexpr double kAspect = 16.0 / 9.0;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

glm::dvec3 rayDir(const Pose& pose, const glm::dvec2& ndc) {
    const double t = std::tan(0.5 * kFov);
    return glm::normalize(pose.orientation * glm::dvec3(ndc.x * t * kAspect, -ndc.y * t, -1.0));
}

// A 4000 m Gaussian mountain (sigma 0.02 degrees, ~2 km) on a 100 m plain.
std::optional<double> mountain(double lonDeg, double latDeg) {
    const double r2 = (lonDeg * lonDeg + latDeg * latDeg) / (0.02 * 0.02);
    return 100.0 + 4000.0 * std::exp(-0.5 * r2);
}

TEST(MapToolsPick, WithoutTerrainMeetsTheEllipsoidExactly) {
    const Pose pose = globe::poseFromViewpoint({10.0, 45.0, 0.0, 30.0, -40.0, 5.0e4});
    for (const glm::dvec2 ndc : {glm::dvec2(0.0, 0.0), glm::dvec2(0.7, 0.6), glm::dvec2(-0.9, 0.2)}) {
        const auto expected = wgs84().intersectRay(pose.position, rayDir(pose, ndc), 0.0);
        ASSERT_TRUE(expected.has_value());
        const auto hit = pick(pose, kFov, kAspect, ndc, {});
        ASSERT_TRUE(hit.has_value());
        EXPECT_NEAR(hit->distance, *expected, 1e-6);
        EXPECT_EQ(hit->geodetic.height, 0.0);
        // The marching path with a flat query agrees (1e-6 m: bisection stops at 1e-12 of the
        // distance, the geodetic height is good to ~1e-9 m).
        const auto marched = pick(pose, kFov, kAspect, ndc, [](double, double) { return std::optional<double>(0.0); });
        ASSERT_TRUE(marched.has_value());
        EXPECT_LT(glm::length(marched->ecef - hit->ecef), 1e-6);
    }
}

TEST(MapToolsPick, LandsOnTheFirstTerrainTheRayMeets) {
    // Looking at the mountain's east face from the east: the ray through the summit's side hits
    // the mountain, not the plain behind it.
    const Pose pose = globe::poseFromEye({0.2, 0.0, 2000.0}, -90.0, -5.0);
    for (const glm::dvec2 ndc : {glm::dvec2(0.0, 0.0), glm::dvec2(0.05, -0.1), glm::dvec2(0.0, 0.4)}) {
        const auto hit = pick(pose, kFov, kAspect, ndc, mountain);
        ASSERT_TRUE(hit.has_value());
        // On the ray (1e-9 relative: double rounding) and on the terrain (1 mm).
        const glm::dvec3 d = rayDir(pose, ndc);
        EXPECT_LT(glm::length(glm::cross(hit->ecef - pose.position, d)) / hit->distance, 1e-9);
        EXPECT_NEAR(hit->geodetic.height, *mountain(hit->geodetic.lonDeg, hit->geodetic.latDeg), 1e-9);
        EXPECT_NEAR(wgs84().toGeodetic(hit->ecef).height, hit->geodetic.height, 1e-3);
        // The first crossing: a metre before it the ray is still above the ground.
        const globe::Geodetic before = wgs84().toGeodetic(pose.position + d * (hit->distance - 1.0));
        EXPECT_GT(before.height, *mountain(before.lonDeg, before.latDeg));
    }
    // The centre ray at pitch -5 from 2000 m would meet the plain only past the summit; it
    // meets the mountain's east flank first.
    const auto centre = pick(pose, kFov, kAspect, {0.0, 0.0}, mountain);
    ASSERT_TRUE(centre.has_value());
    EXPECT_GT(centre->geodetic.height, 150.0);
    EXPECT_GT(centre->geodetic.lonDeg, 0.02);
    EXPECT_LT(centre->geodetic.lonDeg, 0.1);
}

TEST(MapToolsPick, AcrossTheAntimeridian) {
    // Straight down over lon 180: the west half of the screen is at +179.x, the east at -179.x;
    // the heights come from the right side of the line.
    const Pose pose = globe::poseFromViewpoint({180.0, 20.0, 0.0, 0.0, -90.0, 2.0e5});
    auto sided = [](double lonDeg, double) { return std::optional<double>(lonDeg > 0.0 ? 100.0 : 300.0); };
    const auto west = pick(pose, kFov, kAspect, {-0.5, 0.0}, sided);
    const auto east = pick(pose, kFov, kAspect, {0.5, 0.0}, sided);
    ASSERT_TRUE(west.has_value());
    ASSERT_TRUE(east.has_value());
    EXPECT_GT(west->geodetic.lonDeg, 179.0);
    EXPECT_LT(east->geodetic.lonDeg, -179.0);
    EXPECT_NEAR(west->geodetic.height, 100.0, 1e-9);
    EXPECT_NEAR(east->geodetic.height, 300.0, 1e-9);
    // 0.01 degrees: the screen's horizontal line is a great circle, not the parallel.
    EXPECT_NEAR(west->geodetic.latDeg, 20.0, 1e-2);
    EXPECT_NEAR(east->geodetic.latDeg, 20.0, 1e-2);
}

TEST(MapToolsPick, AtThePoles) {
    for (const double lat : {90.0, -90.0}) {
        const Pose pose = globe::poseFromViewpoint({30.0, lat, 0.0, 0.0, -90.0, 1.0e5});
        auto plateau = [](double, double) { return std::optional<double>(2800.0); };
        const auto centre = pick(pose, kFov, kAspect, {0.0, 0.0}, plateau);
        ASSERT_TRUE(centre.has_value());
        EXPECT_NEAR(std::abs(centre->geodetic.latDeg), 90.0, 1e-9);   // 1e-9 deg ~ 0.1 mm
        EXPECT_EQ(std::signbit(centre->geodetic.latDeg), lat < 0.0);
        EXPECT_NEAR(centre->geodetic.height, 2800.0, 1e-9);
        EXPECT_NEAR(centre->distance, 1.0e5 - 2800.0, 1e-3);
        for (const glm::dvec2 ndc : {glm::dvec2(0.5, 0.5), glm::dvec2(-0.8, 0.1), glm::dvec2(0.0, -0.9)}) {
            const auto hit = pick(pose, kFov, kAspect, ndc, plateau);
            ASSERT_TRUE(hit.has_value());
            EXPECT_TRUE(std::isfinite(hit->geodetic.lonDeg));
            EXPECT_LT(std::abs(hit->geodetic.latDeg), 90.0);
            EXPECT_GT(std::abs(hit->geodetic.latDeg), 89.0);
        }
    }
}

TEST(MapToolsPick, ReturnsNothingAboveTheHorizon) {
    // Pitch -5 from 1 km: the top of a 45-degree view looks 17.5 degrees up.
    const Pose low = globe::poseFromEye({5.0, 45.0, 1000.0}, 0.0, -5.0);
    EXPECT_FALSE(pick(low, kFov, kAspect, {0.0, -1.0}, {}).has_value());
    EXPECT_FALSE(pick(low, kFov, kAspect, {0.0, -1.0}, mountain).has_value());
    EXPECT_TRUE(pick(low, kFov, kAspect, {0.0, 1.0}, mountain).has_value());
    // From 40 000 km the corners of the view are in space.
    const Pose far = globe::poseFromViewpoint({0.0, 0.0, 0.0, 0.0, -90.0, 4.0e7});
    EXPECT_FALSE(pick(far, kFov, kAspect, {1.0, 1.0}, {}).has_value());
    EXPECT_FALSE(pick(far, kFov, kAspect, {1.0, 1.0}, mountain).has_value());
    EXPECT_TRUE(pick(far, kFov, kAspect, {0.0, 0.0}, mountain).has_value());
}

TEST(MapToolsPick, BadInputGivesNothing) {
    const Pose pose = globe::poseFromViewpoint({0.0, 0.0, 0.0, 0.0, -90.0, 1.0e4});
    EXPECT_FALSE(pick(pose, kFov, kAspect, {kNaN, 0.0}, {}).has_value());
    EXPECT_FALSE(pick(pose, 0.0, kAspect, {0.0, 0.0}, {}).has_value());
    EXPECT_FALSE(pick(pose, kNaN, kAspect, {0.0, 0.0}, {}).has_value());
    EXPECT_FALSE(pick(pose, kFov, 0.0, {0.0, 0.0}, {}).has_value());
    Pose bad = pose;
    bad.position.x = kNaN;
    EXPECT_FALSE(pick(bad, kFov, kAspect, {0.0, 0.0}, {}).has_value());
    bad = pose;
    bad.orientation = glm::dquat(0.0, 0.0, 0.0, 0.0);
    EXPECT_FALSE(pick(bad, kFov, kAspect, {0.0, 0.0}, mountain).has_value());
    // An eye under the ground sees nothing; a query answering NaN is flat ground.
    const Pose buried = globe::poseFromEye({0.0, 0.0, 50.0}, 0.0, -30.0);
    EXPECT_FALSE(pick(buried, kFov, kAspect, {0.0, 0.0}, mountain).has_value());
    const auto nanGround = pick(pose, kFov, kAspect, {0.0, 0.0}, [](double, double) { return std::optional<double>(kNaN); });
    ASSERT_TRUE(nanGround.has_value());
    EXPECT_EQ(nanGround->geodetic.height, 0.0);
}

TEST(MapToolsScaleBar, PicksRoundLengthsWithinTheMaximumWidth) {
    struct Case {
        double mpp, maxPx, metres;
        const char* label;
    };
    const Case cases[] = {{1.0, 150.0, 100.0, "100 m"},   {3.0, 150.0, 200.0, "200 m"},  {0.01, 100.0, 1.0, "1 m"},
                          {0.003, 100.0, 0.2, "0.2 m"}, {37.0, 200.0, 5000.0, "5 km"}, {10.0, 100.0, 1000.0, "1 km"},
                          {1.0e5, 150.0, 1.0e7, "10000 km"}};
    for (const Case& c : cases) {
        const auto bar = niceScaleBar(c.mpp, c.maxPx);
        ASSERT_TRUE(bar.has_value());
        EXPECT_DOUBLE_EQ(bar->metres, c.metres) << c.mpp;
        EXPECT_EQ(bar->label, c.label);
        EXPECT_NEAR(bar->widthPx, c.metres / c.mpp, 1e-9 * c.maxPx);
    }
    // Over seven decades: a 1/2/5 mantissa, never wider than asked, never narrower than 2/5 of
    // it (the largest gap between round lengths is 2 to 5).
    for (double mpp = 1e-3; mpp < 1e4; mpp *= 1.037) {
        const auto bar = niceScaleBar(mpp, 120.0);
        ASSERT_TRUE(bar.has_value());
        const double mantissa = bar->metres / std::pow(10.0, std::floor(std::log10(bar->metres) + 1e-9));
        EXPECT_TRUE(std::abs(mantissa - 1.0) < 1e-9 || std::abs(mantissa - 2.0) < 1e-9 || std::abs(mantissa - 5.0) < 1e-9)
            << bar->metres;
        EXPECT_LE(bar->widthPx, 120.0);
        EXPECT_GE(bar->widthPx, 0.4 * 120.0 - 1e-9);
    }
    EXPECT_FALSE(niceScaleBar(0.0, 100.0).has_value());
    EXPECT_FALSE(niceScaleBar(kNaN, 100.0).has_value());
    EXPECT_FALSE(niceScaleBar(1.0, 0.5).has_value());
    EXPECT_FALSE(niceScaleBar(std::numeric_limits<double>::infinity(), 100.0).has_value());
}

TEST(MapToolsScaleBar, MetresPerPixelFromPicksOrFromTheHeight) {
    const glm::dvec2 viewport(1280.0, 720.0);
    // Straight down from 1 km (and from 1 m): a pixel at the centre is 2 h tan(fov/2) / 720
    // (0.1 %: the ground is curved and the pixel pair is off-centre by one pixel).
    for (const double h : {1000.0, 1.0}) {
        const Pose down = globe::poseFromViewpoint({8.0, 47.0, 0.0, 0.0, -90.0, h});
        const auto mpp = metresPerPixel(down, kFov, viewport, viewport * 0.5, {});
        ASSERT_TRUE(mpp.has_value());
        EXPECT_NEAR(*mpp, 2.0 * h * std::tan(0.5 * kFov) / 720.0, 1e-3 * *mpp);
    }
    // On a plateau the height above it counts, not the height above the ellipsoid.
    const Pose overPlateau = globe::poseFromViewpoint({8.0, 47.0, 2000.0, 0.0, -90.0, 1000.0});
    const auto plateau = metresPerPixel(overPlateau, kFov, viewport, viewport * 0.5,
                                        [](double, double) { return std::optional<double>(2000.0); });
    ASSERT_TRUE(plateau.has_value());
    EXPECT_NEAR(*plateau, 2.0 * 1000.0 * std::tan(0.5 * kFov) / 720.0, 1e-3 * *plateau);
    // A corner in space: the size of a pixel at the eye's height (exact formula).
    const Pose far = globe::poseFromViewpoint({0.0, 0.0, 0.0, 0.0, -90.0, 4.0e7});
    const auto space = metresPerPixel(far, kFov, viewport, {0.0, 0.0}, {});
    ASSERT_TRUE(space.has_value());
    const double eyeHeight = wgs84().toGeodetic(far.position).height;
    EXPECT_NEAR(*space, 2.0 * eyeHeight * std::tan(0.5 * kFov) / 720.0, 1e-9 * *space);
    // Bad input.
    EXPECT_FALSE(metresPerPixel(far, kFov, {0.0, 720.0}, {0.0, 0.0}, {}).has_value());
    EXPECT_FALSE(metresPerPixel(far, kFov, viewport, {kNaN, 0.0}, {}).has_value());
    EXPECT_FALSE(metresPerPixel(far, 0.0, viewport, {0.0, 0.0}, {}).has_value());
}

TEST(MapToolsCompass, ReadsTheHeadingOfTheView) {
    // 1e-9 degrees: the heading goes through a quaternion and back.
    for (const double heading : {0.0, 90.0, -90.0, 135.0}) {
        for (const double pitch : {-45.0, -90.0, -1.0}) {
            const Pose pose = globe::poseFromViewpoint({-20.0, 45.0, 0.0, heading, pitch, 1.0e5});
            const double expected = heading < 0.0 ? heading + 360.0 : heading;
            EXPECT_NEAR(compassHeadingDeg(pose), expected, 1e-9) << heading << " " << pitch;
        }
    }
    // Across the antimeridian, and looking up from the ground (a pilot view).
    EXPECT_NEAR(compassHeadingDeg(globe::poseFromViewpoint({180.0, -10.0, 0.0, 200.0, -30.0, 1.0e4})), 200.0, 1e-9);
    EXPECT_NEAR(compassHeadingDeg(globe::poseFromEye({10.0, 10.0, 100.0}, 45.0, 30.0)), 45.0, 1e-9);
}

TEST(MapToolsCompass, StableStraightDownAndAtThePoles) {
    // Near straight down the reading does not jump: pitch -90 and -89.999 agree (1e-6 deg).
    for (const double heading : {0.0, 30.0, 300.0}) {
        const double a = compassHeadingDeg(globe::poseFromViewpoint({3.0, 3.0, 0.0, heading, -90.0, 1.0e3}));
        const double b = compassHeadingDeg(globe::poseFromViewpoint({3.0, 3.0, 0.0, heading, -89.999, 1.0e3}));
        EXPECT_NEAR(a, heading, 1e-9);
        EXPECT_NEAR(b, heading, 1e-6);
    }
    // Looking at a pole, whatever longitude and heading the viewpoint was written with.
    for (const double lon : {0.0, 30.0, -150.0})
        for (const double heading : {0.0, 135.0}) {
            EXPECT_EQ(compassHeadingDeg(globe::poseFromViewpoint({lon, 90.0, 0.0, heading, -90.0, 1.0e6})), 0.0);
            EXPECT_EQ(compassHeadingDeg(globe::poseFromViewpoint({lon, -90.0, 0.0, heading, -60.0, 1.0e6})), 180.0);
        }
    // Just off the pole the reading is finite and in range.
    const double near = compassHeadingDeg(globe::poseFromViewpoint({30.0, 89.99999, 0.0, 45.0, -90.0, 1.0e6}));
    EXPECT_TRUE(near >= 0.0 && near < 360.0);
    Pose bad;
    bad.position = glm::dvec3(kNaN);
    EXPECT_EQ(compassHeadingDeg(bad), 0.0);
}

}  // namespace
}  // namespace orbis::ui
