// Moving points glide from where they are shown to their new places (layers/vector/MarkerMotion.h):
// first seen, a point stands; moved, it glides at a constant speed over the time given or its
// own time between moves; moved again mid-glide, it turns from where it is; a tile built again
// with the point where it was goes on with the glide; a long jump is not glided; what is no
// longer drawn is forgotten after a while. The GPU's part (mix of from and position by the chunk's clock) is
// checked here on the CPU with the same formula, and in tests/render/PostgisRenderTest.cpp.
#include "layers/vector/MarkerMotion.h"

#include "globe/Ellipsoid.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace orbis::vector {
namespace {

/// The marker's place as marker.vert computes it, in ECEF.
glm::dvec3 drawnAt(const MeshChunk& chunk, const shader::VectorMarker& m, double now) {
    const double clock = chunk.glideEpoch > 0.0 ? double(float(now - chunk.glideEpoch)) : 0.0;
    const double along = m.glide.y > m.glide.x ? std::clamp((clock - m.glide.x) / double(m.glide.y - m.glide.x), 0.0, 1.0) : 1.0;
    return chunk.origin + glm::dvec3(m.from) + (glm::dvec3(m.position) - glm::dvec3(m.from)) * along;
}

/// A tile's mesh: one chunk at `origin` (ECEF) with markers at these offsets (m), of these ids.
FeatureMesh meshOf(const glm::dvec3& origin, std::initializer_list<std::pair<uint32_t, glm::dvec3>> markers) {
    FeatureMesh mesh;
    MeshChunk& c = mesh.chunks.emplace_back();
    c.origin = c.center = origin;
    c.radius = 10.0;
    for (const auto& [id, offset] : markers) {
        shader::VectorMarker m{};
        m.position = m.from = glm::vec3(offset);
        m.feature = id;
        m.sizePx = 8.0f;
        c.markers.push_back(m);
        c.radius = std::max(c.radius, glm::length(offset) + 1.0);
    }
    return mesh;
}

const glm::dvec3 kOrigin = globe::Ellipsoid::wgs84().toEcef(9.03, 46.02, 300.0);

TEST(MarkerMotion, AFirstSeenPointStandsWhereItIs) {
    MarkerMotion motion({.seconds = 1.0});
    FeatureMesh mesh = meshOf(kOrigin, {{7, {10.0, 0.0, 0.0}}});
    motion.arrive(mesh, 100.0);
    const MeshChunk& c = mesh.chunks[0];
    EXPECT_EQ(c.glideEpoch, 100.0);
    EXPECT_EQ(c.markers[0].from, c.markers[0].position);
    EXPECT_LE(c.markers[0].glide.y, c.markers[0].glide.x);
    EXPECT_FALSE(motion.moving(100.0));
    ASSERT_TRUE(motion.shownAt(7, 100.0));
    EXPECT_LT(glm::length(*motion.shownAt(7, 100.0) - (kOrigin + glm::dvec3(10.0, 0.0, 0.0))), 1e-6);
    EXPECT_FALSE(motion.shownAt(8, 100.0));
}

TEST(MarkerMotion, AMovedPointGlidesAtAConstantSpeedOverTheTimeGiven) {
    MarkerMotion motion({.seconds = 1.0});
    FeatureMesh first = meshOf(kOrigin, {{7, {0.0, 0.0, 0.0}}, {9, {50.0, 0.0, 0.0}}});
    motion.arrive(first, 100.0);
    FeatureMesh moved = meshOf(kOrigin, {{7, {100.0, 0.0, 0.0}}, {9, {50.0, 0.0, 0.0}}});
    motion.arrive(moved, 102.0);
    const MeshChunk& c = moved.chunks[0];
    EXPECT_EQ(motion.glides(), 1u);
    EXPECT_TRUE(motion.moving(102.5));
    EXPECT_FALSE(motion.moving(103.01));
    for (const double f : {0.0, 0.25, 0.5, 0.75, 1.0, 2.0}) {
        SCOPED_TRACE(f);
        const glm::dvec3 expected = kOrigin + glm::dvec3(100.0 * std::min(f, 1.0), 0.0, 0.0);
        EXPECT_LT(glm::length(drawnAt(c, c.markers[0], 102.0 + f) - expected), 1e-3);
        EXPECT_LT(glm::length(*motion.shownAt(7, 102.0 + f) - expected), 1e-6);
        // The point that did not move stays.
        EXPECT_LT(glm::length(drawnAt(c, c.markers[1], 102.0 + f) - (kOrigin + glm::dvec3(50.0, 0.0, 0.0))), 1e-3);
    }
    // Its chunk is culled by a sphere that holds where it glides from.
    EXPECT_GE(c.radius, glm::length(kOrigin - c.center));
}

TEST(MarkerMotion, AutoTakesThePointsOwnTimeBetweenMovesAndTurnsFromWhereItIs) {
    MarkerMotion motion;   // auto: [0.05, 2] s
    const auto at = [](double x) { return meshOf(kOrigin, {{3, {x, 0.0, 0.0}}}); };
    FeatureMesh a = at(0.0);
    motion.arrive(a, 10.0);
    FeatureMesh b = at(20.0);
    motion.arrive(b, 10.2);   // 0.2 s after it was first seen: a glide of 0.2 s
    EXPECT_LT(glm::length(*motion.shownAt(3, 10.3) - (kOrigin + glm::dvec3(10.0, 0.0, 0.0))), 1e-6);
    EXPECT_FALSE(motion.moving(10.41));
    // Moved again half-way (at x = 10 m): it turns from there, over the 0.1 s since its last move.
    FeatureMesh c = at(40.0);
    motion.arrive(c, 10.3);
    const MeshChunk& chunk = c.chunks[0];
    EXPECT_LT(glm::length(drawnAt(chunk, chunk.markers[0], 10.3) - (kOrigin + glm::dvec3(10.0, 0.0, 0.0))), 1e-3);
    EXPECT_LT(glm::length(drawnAt(chunk, chunk.markers[0], 10.35) - (kOrigin + glm::dvec3(25.0, 0.0, 0.0))), 1e-3);
    EXPECT_LT(glm::length(drawnAt(chunk, chunk.markers[0], 10.4) - (kOrigin + glm::dvec3(40.0, 0.0, 0.0))), 1e-3);
    // A long pause: the glide lasts the longest allowed, not the pause.
    FeatureMesh d = at(60.0);
    motion.arrive(d, 100.0);
    EXPECT_TRUE(motion.moving(101.9));
    EXPECT_FALSE(motion.moving(102.01));
}

TEST(MarkerMotion, ATileBuiltAgainWithThePointWhereItWasGoesOnWithTheGlide) {
    MarkerMotion motion({.seconds = 1.0});
    FeatureMesh a = meshOf(kOrigin, {{5, {0.0, 0.0, 0.0}}});
    motion.arrive(a, 1000.0);
    FeatureMesh b = meshOf(kOrigin, {{5, {0.0, 80.0, 0.0}}});
    motion.arrive(b, 1001.0);
    // Built again 0.5 s later (another feature of the tile changed): same target, the same glide.
    FeatureMesh again = meshOf(kOrigin, {{5, {0.0, 80.0, 0.0}}, {6, {5.0, 5.0, 0.0}}});
    motion.arrive(again, 1001.5);
    const MeshChunk& c = again.chunks[0];
    EXPECT_LT(glm::length(drawnAt(c, c.markers[0], 1001.5) - (kOrigin + glm::dvec3(0.0, 40.0, 0.0))), 1e-3);
    EXPECT_LT(glm::length(drawnAt(c, c.markers[0], 1001.75) - (kOrigin + glm::dvec3(0.0, 60.0, 0.0))), 1e-3);
    EXPECT_LT(glm::length(drawnAt(c, c.markers[0], 1002.0) - (kOrigin + glm::dvec3(0.0, 80.0, 0.0))), 1e-3);
    EXPECT_EQ(motion.glides(), 1u);
}

TEST(MarkerMotion, AJumpLongerThanTheLimitIsNotGlided) {
    MarkerMotion motion({.seconds = 1.0, .maxJumpM = 500.0});
    FeatureMesh a = meshOf(kOrigin, {{1, {0.0, 0.0, 0.0}}});
    motion.arrive(a, 5.0);
    FeatureMesh b = meshOf(kOrigin, {{1, {900.0, 0.0, 0.0}}});
    motion.arrive(b, 6.0);
    EXPECT_EQ(motion.jumps(), 1u);
    EXPECT_EQ(motion.glides(), 0u);
    EXPECT_FALSE(motion.moving(6.0));
    const MeshChunk& c = b.chunks[0];
    EXPECT_LT(glm::length(drawnAt(c, c.markers[0], 6.0) - (kOrigin + glm::dvec3(900.0, 0.0, 0.0))), 1e-3);
}

TEST(MarkerMotion, ZeroSecondsMakesPointsJump) {
    MarkerMotion motion({.seconds = 0.0});
    FeatureMesh a = meshOf(kOrigin, {{1, {0.0, 0.0, 0.0}}});
    motion.arrive(a, 5.0);
    FeatureMesh b = meshOf(kOrigin, {{1, {30.0, 0.0, 0.0}}});
    motion.arrive(b, 6.0);
    EXPECT_FALSE(motion.moving(6.0));
    EXPECT_LT(glm::length(drawnAt(b.chunks[0], b.chunks[0].markers[0], 6.0) - (kOrigin + glm::dvec3(30.0, 0.0, 0.0))), 1e-3);
}

TEST(MarkerMotion, AMultiPointsPointsAreTrackedApartAndAPointMayChangeTiles) {
    MarkerMotion motion({.seconds = 2.0});
    FeatureMesh a = meshOf(kOrigin, {{4, {0.0, 0.0, 0.0}}, {4, {0.0, 100.0, 0.0}}});
    motion.arrive(a, 1.0);
    // Into another tile, whose chunk has another origin 3 km away: glided across.
    const glm::dvec3 other = kOrigin + glm::dvec3(3000.0, 0.0, 0.0);
    FeatureMesh b = meshOf(other, {{4, {-3000.0, 20.0, 0.0}}, {4, {-3000.0, 100.0, 0.0}}});
    motion.arrive(b, 2.0);
    const MeshChunk& c = b.chunks[0];
    EXPECT_LT(glm::length(drawnAt(c, c.markers[0], 3.0) - (kOrigin + glm::dvec3(0.0, 10.0, 0.0))), 1e-3);
    EXPECT_LT(glm::length(drawnAt(c, c.markers[1], 3.0) - (kOrigin + glm::dvec3(0.0, 100.0, 0.0))), 1e-3);
    // Out of every mesh drawn: kept a while (it may be entering another tile), then forgotten.
    motion.drawing(b, 3.0);
    EXPECT_EQ(motion.tracked(), 2u);
    motion.drawing(FeatureMesh{}, 3.0 + MarkerMotion::kForgetSeconds - 0.5);
    EXPECT_EQ(motion.tracked(), 2u);
    motion.drawing(FeatureMesh{}, 3.0 + MarkerMotion::kForgetSeconds + 0.5);
    EXPECT_EQ(motion.tracked(), 0u);
    EXPECT_FALSE(motion.shownAt(4, 20.0));
}

TEST(MarkerMotion, FloatsOnTheGpuStayPreciseAtThePoleAndAfterDaysOfUptime) {
    // The chunk's clock is a float of seconds since its epoch: precise whatever the uptime. At
    // the pole the ECEF numbers are largest in z; positions stay relative to the chunk.
    MarkerMotion motion({.seconds = 1.0});
    const glm::dvec3 pole = globe::Ellipsoid::wgs84().toEcef(0.0, 89.9999, 10.0);
    const double uptime = 40.0 * 86400.0;
    FeatureMesh a = meshOf(pole, {{2, {0.0, 0.0, 0.0}}});
    motion.arrive(a, uptime);
    FeatureMesh b = meshOf(pole, {{2, {0.0, 1.0, 0.0}}});
    motion.arrive(b, uptime + 0.1);
    const MeshChunk& c = b.chunks[0];
    EXPECT_LT(glm::length(drawnAt(c, c.markers[0], uptime + 0.6) - (pole + glm::dvec3(0.0, 0.5, 0.0))), 1e-3);
}

}  // namespace
}  // namespace orbis::vector
