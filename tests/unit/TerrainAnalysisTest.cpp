// Line of sight and terrain profiles (globe/TerrainAnalysis.h) over grounds with known answers:
// a wall between two points (seen over it by a few centimetres more than the Earth's curve
// takes, or not), the bare ellipsoid's horizon (2 sqrt(2 R h) between two masts, further with
// refraction), ground that is missing; a profile over a slope, across the antimeridian, bounded.
#include "globe/TerrainAnalysis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace orbis::globe {
namespace {

/// A wall 100 m high and about 80 m thick across lon 10.01; flat ground at 0 elsewhere.
std::optional<double> wall(double lon, double) { return std::abs(lon - 10.01) < 0.0005 ? 100.0 : 0.0; }

TEST(LineOfSight, AWallHidesWhatIsBehindItUnlessTheLinePassesOverIt) {
    SightOptions geometric{.stepM = 2.0, .refraction = 0.0};
    // Observers 1.57 km apart at 45 N, the wall half-way: the straight line sags d1 d2 / 2R =
    // 4.8 cm below the heights of its ends there.
    const LineOfSight low = lineOfSight({10.0, 45.0, 50.0}, {10.02, 45.0, 50.0}, wall, geometric);
    EXPECT_FALSE(low.visible);
    EXPECT_NEAR(low.blockedAt.x, 10.01 - 0.0005, 0.0001);   // its near face
    EXPECT_NEAR(low.blockedAtM, 0.0095 * 111319.5 * std::cos(45.0 * M_PI / 180.0), 15.0);
    EXPECT_NEAR(low.blockingHeight, 100.0, 1e-9);
    EXPECT_NEAR(low.aboveLineM, 50.0, 0.1);
    EXPECT_LT(low.clearanceM, -49.9);
    EXPECT_EQ(low.unknown, 0u);
    const double sag = 785.0 * 785.0 / (2.0 * 6371008.8);
    EXPECT_TRUE(lineOfSight({10.0, 45.0, 100.0 + sag + 0.01}, {10.02, 45.0, 100.0 + sag + 0.01}, wall, geometric).visible);
    const LineOfSight grazing = lineOfSight({10.0, 45.0, 100.0 + sag - 0.01}, {10.02, 45.0, 100.0 + sag - 0.01}, wall, geometric);
    EXPECT_FALSE(grazing.visible);
    EXPECT_LT(grazing.aboveLineM, 0.02);
    // Seen from above, the other way round too.
    EXPECT_TRUE(lineOfSight({10.02, 45.0, 300.0}, {10.0, 45.0, 2.0}, wall, geometric).visible);
    // A point on the ground is seen by an eye 1.7 m up (the ground it stands on does not hide
    // it); two points both on the ground are not: the ellipsoid bulges 3 mm between them.
    EXPECT_TRUE(lineOfSight({10.0, 45.0, 1.7}, {10.005, 45.0, 0.0}, wall, {.stepM = 1.0, .refraction = 0.0}).visible);
    EXPECT_FALSE(lineOfSight({10.0, 45.0, 0.0}, {10.005, 45.0, 0.0}, wall, {.stepM = 1.0, .refraction = 0.0}).visible);
}

TEST(LineOfSight, TwoMastsOnTheBareEllipsoidSeeEachOtherUpToTheirHorizonsAndFurtherWithRefraction) {
    const HeightAt sea = [](double, double) { return std::optional<double>(0.0); };
    // 10 m masts along the equator: the horizons meet at 2 sqrt(2 R h), about 22.6 km (R the
    // equator's radius of curvature along it, a).
    const double horizon = 2.0 * std::sqrt(2.0 * 6378137.0 * 10.0);
    const double degree = 111319.49;
    const auto seen = [&](double metres, double k) {
        return lineOfSight({0.0, 0.0, 10.0}, {metres / degree, 0.0, 10.0}, sea, {.stepM = 20.0, .refraction = k}).visible;
    };
    EXPECT_TRUE(seen(0.98 * horizon, 0.0));
    EXPECT_FALSE(seen(1.02 * horizon, 0.0));
    // Refraction of 1/7: the Earth looks 7/6 as large, the horizons 8 % further.
    EXPECT_TRUE(seen(1.05 * horizon, 1.0 / 7.0));
    EXPECT_FALSE(seen(1.1 * horizon, 1.0 / 7.0));
}

TEST(LineOfSight, MissingGroundIsCountedAndHidesNothing) {
    const HeightAt none = [](double, double) { return std::optional<double>(); };
    const LineOfSight s = lineOfSight({0.0, 0.0, 1.0}, {0.01, 0.0, 1.0}, none, {.stepM = 10.0});
    EXPECT_TRUE(s.visible);
    EXPECT_EQ(s.unknown, s.samples);
    EXPECT_GT(s.samples, 100u);
    // No ground function, or two points at one place: visible, nothing sampled.
    EXPECT_TRUE(lineOfSight({0.0, 0.0, 1.0}, {0.01, 0.0, 1.0}, HeightAt{}).visible);
    EXPECT_EQ(lineOfSight({0.0, 0.0, 1.0}, {0.0, 0.0, 1.5}, none).samples, 0u);
    // A huge distance is sampled within the bound.
    EXPECT_LE(lineOfSight({0.0, 0.0, 1e7}, {90.0, 0.0, 1e7}, none, {.stepM = 0.001, .maxSamples = 1000}).samples, 1000u);
}

TEST(TerrainProfile, FollowsTheGroundAlongThePathWithItsRisesAndFalls) {
    // A slope rising 1 m per 0.001 degree of longitude east of 10, and a step down at 10.02.
    const HeightAt slope = [](double lon, double) { return std::optional<double>(lon < 10.02 ? 1000.0 * (lon - 10.0) : 0.0); };
    const std::vector<LonLat> path{{10.0, 45.0}, {10.03, 45.0}};
    const TerrainProfile p = terrainProfile(path, slope, 10.0);
    EXPECT_NEAR(p.lengthM, 0.03 * 78846.8, 5.0);
    ASSERT_GE(p.samples.size(), size_t(p.lengthM / 10.0));
    EXPECT_EQ(p.samples.front().distanceM, 0.0);
    EXPECT_NEAR(p.samples.back().distanceM, p.lengthM, 1e-6);
    for (const ProfileSample& s : p.samples) {
        ASSERT_TRUE(s.height);
        EXPECT_NEAR(*s.height, *slope(s.at.x, s.at.y), 1e-9);
        EXPECT_NEAR(s.at.y, 45.0, 1e-3);
    }
    EXPECT_NEAR(*p.maxHeight, 20.0, 0.2);
    EXPECT_EQ(*p.minHeight, 0.0);
    EXPECT_NEAR(p.ascentM, 20.0, 0.2);
    EXPECT_NEAR(p.descentM, 20.0, 0.2);
    EXPECT_EQ(p.unknown, 0u);
}

TEST(TerrainProfile, CrossesTheAntimeridianAndStaysWithinItsBound) {
    const HeightAt sides = [](double lon, double) -> std::optional<double> {
        if (lon < -180.0 || lon >= 180.0) return std::nullopt;   // the ground wants wrapped longitudes
        return lon > 0.0 ? 50.0 : 70.0;
    };
    const std::vector<LonLat> path{{179.9, -10.0}, {-179.9, -10.0}};
    const TerrainProfile p = terrainProfile(path, sides, 500.0);
    EXPECT_EQ(p.unknown, 0u);
    EXPECT_EQ(*p.samples.front().height, 50.0);
    EXPECT_EQ(*p.samples.back().height, 70.0);
    EXPECT_NEAR(p.ascentM, 20.0, 1e-9);
    // 20 000 km at a 1 m step, bounded to 1000 samples.
    const std::vector<LonLat> far{{0.0, 0.0}, {179.0, 0.0}};
    const TerrainProfile bounded = terrainProfile(far, sides, 1.0, 1000);
    EXPECT_LE(bounded.samples.size(), 1000u);
    EXPECT_GT(bounded.samples.size(), 900u);
    EXPECT_TRUE(terrainProfile({}, sides, 1.0).samples.empty());
}

}  // namespace
}  // namespace orbis::globe
