// Longitudes on a circle, for the vector reader: unwrapping across the antimeridian, rings around
// a pole, and the shortest interval covering several boxes. Exact arithmetic: the tolerances are
// only for floating-point sums (1e-9 degrees).
#include "layers/vector/LonLatGeometry.h"

#include <gtest/gtest.h>

#include <vector>

namespace orbis::vector {
namespace {

constexpr double kEps = 1e-9;

LonLatBounds box(double west, double east, double south = 0.0, double north = 1.0) {
    return LonLatBounds{west, south, east, north, false};
}

TEST(LonLatGeometry, NormalizeLonMovesByWholeTurns) {
    EXPECT_DOUBLE_EQ(normalizeLonDeg(181.0), -179.0);
    EXPECT_DOUBLE_EQ(normalizeLonDeg(180.0), -180.0);
    EXPECT_DOUBLE_EQ(normalizeLonDeg(-180.0), -180.0);
    EXPECT_DOUBLE_EQ(normalizeLonDeg(-541.0), 179.0);
    EXPECT_DOUBLE_EQ(normalizeLonDeg(359.5), -0.5);
}

TEST(LonLatGeometry, UnwrapMakesALineAcrossTheAntimeridianContinuous) {
    std::vector<glm::dvec3> line{{179.0, 0.0, 0.0}, {-179.0, 1.0, 0.0}, {-178.0, 2.0, 0.0}, {178.0, 3.0, 0.0}};
    unwrapLongitudes(line);
    EXPECT_DOUBLE_EQ(line[0].x, 179.0);
    EXPECT_DOUBLE_EQ(line[1].x, 181.0);
    EXPECT_DOUBLE_EQ(line[2].x, 182.0);
    EXPECT_DOUBLE_EQ(line[3].x, 178.0);   // back across
    const LonLatBounds b = partBounds(line);
    EXPECT_NEAR(b.west, 178.0, kEps);
    EXPECT_NEAR(b.east, 182.0, kEps);
    EXPECT_NEAR(b.widthDeg(), 4.0, kEps);
}

TEST(LonLatGeometry, UnwrapLeavesOrdinaryLinesAlone) {
    std::vector<glm::dvec3> line{{-10.0, 0.0, 5.0}, {170.0, 1.0, 6.0}, {-9.0, 2.0, 7.0}};   // jumps of exactly 180 and 179
    unwrapLongitudes(line);
    EXPECT_DOUBLE_EQ(line[1].x, 170.0);
    EXPECT_DOUBLE_EQ(line[2].x, -9.0);
    EXPECT_DOUBLE_EQ(line[2].z, 7.0);
}

TEST(LonLatGeometry, RingAroundTheSouthPoleIsFlagged) {
    // Antarctica's way: along the coast eastward, down the antimeridian to the pole and back.
    std::vector<glm::dvec3> ring;
    for (double lon = -180.0; lon <= 180.0; lon += 30.0) ring.push_back({lon, -70.0, 0.0});
    ring.push_back({180.0, -90.0, 0.0});
    ring.push_back({-180.0, -90.0, 0.0});
    ring.push_back({-180.0, -70.0, 0.0});
    unwrapLongitudes(ring);
    EXPECT_EQ(ringPoleWinding(ring), -1);
    const LonLatBounds cap = poleCapBounds(ring, -1);
    EXPECT_TRUE(cap.spansAllLongitudes());
    EXPECT_DOUBLE_EQ(cap.south, -90.0);
    EXPECT_DOUBLE_EQ(cap.north, -70.0);
}

TEST(LonLatGeometry, RingAroundTheNorthPoleWithoutTouchingItIsFlaggedNorth) {
    // An open ring (first vertex not repeated) at 80 N, in quarter turns across the antimeridian.
    std::vector<glm::dvec3> ring{{0.0, 80.0, 0.0}, {90.0, 80.0, 0.0}, {180.0, 81.0, 0.0}, {-90.0, 80.0, 0.0}};
    unwrapLongitudes(ring);
    EXPECT_EQ(ringPoleWinding(ring), 1);
    // A small ring across the antimeridian winds around nothing.
    std::vector<glm::dvec3> small{{179.0, -16.0, 0.0}, {-179.0, -16.0, 0.0}, {-179.0, -17.0, 0.0}, {179.0, -17.0, 0.0}, {179.0, -16.0, 0.0}};
    unwrapLongitudes(small);
    EXPECT_EQ(ringPoleWinding(small), 0);
}

TEST(LonLatGeometry, CoverOfPartsCutAtTheAntimeridianIsTight) {
    // Fiji in Natural Earth: parts on both sides of 180.
    const std::vector<LonLatBounds> fiji{box(178.596, 180.0), box(177.285, 178.718), box(-180.0, -179.793)};
    const LonLatBounds b = coverBounds(fiji);
    EXPECT_NEAR(b.west, 177.285, kEps);
    EXPECT_NEAR(b.east, 180.207, kEps);
    EXPECT_TRUE(b.contains(-179.9, 0.5));
    EXPECT_TRUE(b.contains(178.0, 0.5));
    EXPECT_FALSE(b.contains(0.0, 0.5));
}

TEST(LonLatGeometry, CoverCountsAnIntervalThatWrapsPast180) {
    // [170, 200] already covers -180 .. -160, so the widest gap is -160 .. 0, not -170 .. 0.
    const std::vector<LonLatBounds> parts{box(-180.0, -170.0), box(0.0, 10.0), box(170.0, 200.0)};
    const LonLatBounds b = coverBounds(parts);
    EXPECT_NEAR(b.west, 0.0, kEps);
    EXPECT_NEAR(b.east, 200.0, kEps);
}

TEST(LonLatGeometry, CoverOfOnePartIsThatPartAndEverythingCoveredIsTheWholeCircle) {
    const std::vector<LonLatBounds> one{box(-10.0, 20.0, -5.0, 7.0)};
    const LonLatBounds b = coverBounds(one);
    EXPECT_NEAR(b.west, -10.0, kEps);
    EXPECT_NEAR(b.east, 20.0, kEps);
    EXPECT_DOUBLE_EQ(b.south, -5.0);
    EXPECT_DOUBLE_EQ(b.north, 7.0);
    const std::vector<LonLatBounds> around{box(-180.0, -60.0), box(-70.0, 60.0), box(50.0, 181.0)};
    EXPECT_TRUE(coverBounds(around).spansAllLongitudes());
    EXPECT_TRUE(coverBounds(std::vector<LonLatBounds>{}).empty);
}

}  // namespace
}  // namespace orbis::vector
