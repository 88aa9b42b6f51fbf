// Terrain tile selection: coverage without overlap, refinement by screen-space error, culling
// that never hides visible ground, hysteresis and determinism.
#include "globe/Culling.h"
#include "globe/Ellipsoid.h"
#include "globe/TileSelector.h"
#include "globe/Viewpoint.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace orbis::globe {
namespace {

const Ellipsoid& wgs84() { return Ellipsoid::wgs84(); }

constexpr double kFov = 0.7853981633974483;   // 45 degrees
constexpr double kAspect = 16.0 / 9.0;
constexpr double kViewportPx = 1080.0;

TileHeightRange flat(const TileKey&) { return {0.0, 0.0}; }
TileHeightRange conservative(const TileKey&) { return {}; }   // [-500, 9000]

SelectorView viewOf(const Pose& pose, double nearPlane = 1.0) {
    return makeSelectorView(pose, kFov, kAspect, nearPlane, kViewportPx);
}
SelectorView lookingDownFrom(double lonDeg, double latDeg, double height) {
    return viewOf(poseFromViewpoint({lonDeg, latDeg, 0.0, 0.0, -90.0, height}));
}

// How many selected tiles contain the point (edges inclusive).
int coverCount(const std::vector<SelectedTile>& tiles, double lonDeg, double latDeg) {
    int n = 0;
    for (const auto& t : tiles) n += t.key.extent().contains(lonDeg, latDeg) ? 1 : 0;
    return n;
}

const SelectedTile* tileAt(const std::vector<SelectedTile>& tiles, double lonDeg, double latDeg) {
    for (const auto& t : tiles)
        if (t.key.extent().contains(lonDeg, latDeg)) return &t;
    return nullptr;
}

// The refined tiles: every strict ancestor of a selected tile.
std::set<TileKey> refinedSet(const std::vector<SelectedTile>& tiles) {
    std::set<TileKey> out;
    for (const auto& t : tiles)
        for (uint32_t l = 0; l < t.key.level; ++l) out.insert(t.key.ancestor(l));
    return out;
}

std::vector<TileKey> keysOf(const std::vector<SelectedTile>& tiles) {
    std::vector<TileKey> keys;
    for (const auto& t : tiles) keys.push_back(t.key);
    return keys;
}

::testing::AssertionResult disjoint(const std::vector<SelectedTile>& tiles) {
    for (size_t i = 0; i < tiles.size(); ++i)
        for (size_t j = i + 1; j < tiles.size(); ++j) {
            const TileKey &a = tiles[i].key, &b = tiles[j].key;
            if (a == b || a.isAncestorOf(b) || b.isAncestorOf(a) || a.extent().intersects(b.extent()))
                return ::testing::AssertionFailure() << a.toString() << " overlaps " << b.toString();
        }
    return ::testing::AssertionSuccess();
}

TEST(TileSelector, GeometricErrorIsAQuarterCellAtTheEquatorAndHalvesPerLevel) {
    // Level 0: 180 degrees over 64 cells of a 65-sample grid, x 0.25 (Cesium's heightmap quality).
    const double e0 = TileSelector::geometricError({0, 0, 0}, 65);
    EXPECT_NEAR(e0, 0.25 * 6378137.0 * 3.14159265358979323846 / 64.0, 1e-6);
    for (uint32_t l = 1; l <= 22; ++l)
        EXPECT_NEAR(TileSelector::geometricError({l, 0, 0}, 65), e0 / double(1u << l), 1e-9 * e0);
    EXPECT_NEAR(TileSelector::geometricError({0, 0, 0}, 33), 2.0 * e0, 1e-6);
}

TEST(TileSelector, BoundingSphereHoldsEveryPointOfTheTile) {
    // Dense samples (17 x 17 at three heights, GeographicLib) of tiles from whole hemispheres down
    // to metres, on the equator, at mid latitudes, in the pole rows and at the antimeridian,
    // must lie inside. Tolerance: 1e-9 of the radius (rounding only).
    std::vector<TileKey> keys;
    for (uint32_t l = 0; l <= 14; ++l) {
        const uint32_t nx = TileKey::tilesX(l), ny = TileKey::tilesY(l);
        keys.push_back({l, 0, 0});                      // north-west pole tile at the antimeridian
        keys.push_back({l, nx - 1, ny - 1});            // south-east pole tile at the antimeridian
        keys.push_back({l, nx / 2, ny / 2});            // touching the equator and lon 0
        keys.push_back({l, nx / 3, ny / 4});            // mid latitude
        keys.push_back(TileKey::containing(12.3, 67.8, l));
    }
    const TileHeightRange ranges[] = {{0.0, 0.0}, {-500.0, 9000.0}, {-11000.0, 100.0}};
    double worstRatio = 0.0, worstLoose = 0.0;
    for (const auto& key : keys) {
        for (const auto& range : ranges) {
            const BoundingSphere s = tileBoundingSphere(key, range);
            const GeoExtent e = key.extent();
            double farthest = 0.0;
            for (int i = 0; i <= 16; ++i)
                for (int j = 0; j <= 16; ++j)
                    for (double h : {range.minHeight, 0.5 * (range.minHeight + range.maxHeight), range.maxHeight}) {
                        const glm::dvec3 p = wgs84().toEcef(e.west + e.width() * i / 16.0, e.south + e.height() * j / 16.0, h);
                        farthest = std::max(farthest, glm::length(p - s.center));
                    }
            EXPECT_LE(farthest, s.radius * (1.0 + 1e-9)) << key.toString();
            worstRatio = std::max(worstRatio, farthest / s.radius);
            // Not absurdly loose either: the sphere is at most ~1 % bigger than what it holds.
            worstLoose = std::max(worstLoose, s.radius / std::max(farthest, 1e-3));
        }
    }
    EXPECT_LT(worstLoose, 1.05);
    std::printf("bounding spheres: farthest sample at %.6f of the radius at worst, radius %.4f x farthest at worst\n",
                worstRatio, worstLoose);
}

TEST(TileSelector, ClosestTilePointIsNoFartherThanAnyPointOfTheTile) {
    // Eyes all around (including over the tile, beyond the antimeridian and at a pole) against
    // dense samples. The closest point is inside the tile by construction, so it can only err by
    // being too far; allowed 1e-3 relative for the spherical approximation on the ellipsoid.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> lon(-180.0, 180.0), lat(-90.0, 90.0), h(-100.0, 2.0e7);
    const TileKey keys[] = {{3, 15, 0}, {3, 0, 5}, {6, 40, 20}, {10, 1100, 300}, {1, 2, 1}, {0, 1, 0}};
    const TileHeightRange range{-200.0, 3000.0};
    int checked = 0;
    for (const auto& key : keys) {
        const GeoExtent e = key.extent();
        for (int n = 0; n < 60; ++n) {
            Geodetic eye{lon(rng), lat(rng), h(rng)};
            if (n == 0) eye = {e.centerLon(), e.centerLat(), 500.0};   // right over the tile
            if (n == 1) eye = {0.0, 90.0, 100.0};
            if (n == 2) eye = {wrapLongitude(e.west - 0.1), e.centerLat(), 100.0};
            const glm::dvec3 eyeEcef = wgs84().toEcef(eye);
            const double d = glm::length(closestTilePoint(key, range, eye) - eyeEcef);
            double best = 1e300;
            for (int i = 0; i <= 32; ++i)
                for (int j = 0; j <= 32; ++j)
                    for (double hh : {range.minHeight, std::clamp(eye.height, range.minHeight, range.maxHeight), range.maxHeight})
                        best = std::min(best, glm::length(wgs84().toEcef(e.west + e.width() * i / 32.0,
                                                                         e.south + e.height() * j / 32.0, hh) - eyeEcef));
            EXPECT_LE(d, best * (1.0 + 1e-3) + 1e-6) << key.toString() << " eye " << eye.lonDeg << "," << eye.latDeg << "," << eye.height;
            ++checked;
        }
    }
    EXPECT_EQ(checked, 6 * 60);
}

TEST(TileSelector, SphereHorizonTestNeverHidesAVisiblePoint) {
    // Random eyes and spheres; whenever the test says "hidden", points on and in the sphere must
    // really be behind the ellipsoid (the segment to the eye crosses it).
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0), alt(10.0, 3.0e7), r(1.0, 3.0e5), hh(-500.0, 2.0e4);
    const double a = wgs84().equatorialRadius(), b = wgs84().polarRadius();
    int hidden = 0;
    for (int n = 0; n < 4000; ++n) {
        const Geodetic eyeG{180.0 * u(rng), 90.0 * u(rng), alt(rng)};
        const Geodetic cG{180.0 * u(rng), 90.0 * u(rng), hh(rng)};
        const glm::dvec3 eye = wgs84().toEcef(eyeG), c = wgs84().toEcef(cG);
        const double radius = r(rng);
        if (!sphereHiddenByEllipsoid(eye, c, radius, a, b)) continue;
        ++hidden;
        for (int k = 0; k < 26; ++k) {
            const glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + 1e-9);
            const glm::dvec3 p = c + dir * radius * (k % 2 ? 1.0 : 0.5);
            const glm::dvec3 toP = p - eye;
            const auto t = wgs84().intersectRay(eye, glm::normalize(toP));
            ASSERT_TRUE(t.has_value()) << "hidden point not behind the ellipsoid";
            EXPECT_LE(*t, glm::length(toP) + 1e-6);
        }
    }
    EXPECT_GT(hidden, 500);   // the test does cull
}

TEST(TileSelector, TileHorizonTestNeverHidesAVisiblePoint) {
    // Random eyes (some below the occluder) and tiles of all sizes; whenever a tile is called
    // hidden, dense samples of it at both heights must be behind the occluder (the ellipsoid
    // lowered by 500 m): the segment from the eye crosses it first.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    constexpr double kOccluder = -500.0;
    int hidden = 0, tested = 0;
    for (int n = 0; n < 3000; ++n) {
        const Geodetic eyeG{360.0 * u(rng) - 180.0, 180.0 * u(rng) - 90.0, std::pow(10.0, 7.5 * u(rng)) - 600.0};
        const uint32_t level = uint32_t(u(rng) * 9.0);
        const TileKey key = TileKey::containing(360.0 * u(rng) - 180.0, 180.0 * u(rng) - 90.0, level);
        const TileHeightRange range = n % 3 == 0 ? TileHeightRange{0.0, 0.0}
                                      : n % 3 == 1 ? TileHeightRange{-500.0, 9000.0} : TileHeightRange{-11000.0, 3000.0};
        const glm::dvec3 eye = wgs84().toEcef(eyeG);
        ++tested;
        if (!tileHiddenByEllipsoid(key, range, eye, kOccluder)) continue;
        ++hidden;
        const GeoExtent e = key.extent();
        for (int i = 0; i <= 8; ++i)
            for (int j = 0; j <= 8; ++j)
                for (double h : {std::max(range.minHeight, kOccluder), range.maxHeight}) {
                    const glm::dvec3 p = wgs84().toEcef(e.west + e.width() * i / 8.0, e.south + e.height() * j / 8.0, h);
                    const glm::dvec3 toP = p - eye;
                    const auto t = wgs84().intersectRay(eye, glm::normalize(toP), kOccluder);
                    ASSERT_TRUE(t.has_value()) << key.toString() << " from " << eyeG.lonDeg << "," << eyeG.latDeg << "," << eyeG.height;
                    ASSERT_LE(*t, glm::length(toP) + 1e-3) << key.toString();
                }
    }
    EXPECT_GT(hidden, tested / 10);   // it does cull
}

TEST(TileSelector, TileHorizonTestIsTightOnBigTiles) {
    // From 20 000 km over (0, 0) the horizon is 76 degrees away; the quarter-globe tile
    // [-180, -90] x [0, 90] starts at 90 degrees: hidden, although its bounding sphere is not.
    const glm::dvec3 eye = wgs84().toEcef(0.0, 0.0, 2.0e7);
    const TileKey farQuarter{1, 0, 0};
    EXPECT_TRUE(tileHiddenByEllipsoid(farQuarter, {}, eye, -500.0));
    const BoundingSphere s = tileBoundingSphere(farQuarter, {});
    EXPECT_FALSE(sphereHiddenByEllipsoid(eye, s.center, s.radius, wgs84().equatorialRadius(), wgs84().polarRadius()));
    EXPECT_FALSE(tileHiddenByEllipsoid({1, 1, 0}, {}, eye, -500.0));   // [-90, 0] x [0, 90] touches the view
    EXPECT_FALSE(tileHiddenByEllipsoid(farQuarter, {}, wgs84().toEcef(0.0, 0.0, -600.0), -500.0));   // eye underground
}

TEST(TileSelector, HorizonTestKeepsAMountainThatShowsOverTheHorizon) {
    // From 20 000 km over (0, 0) the horizon is at acos(a / (a + h)) ~ 76 degrees of longitude.
    // A 9 km summit 0.5 degrees past it stands 9 km above ground that the tangent ray clears by
    // only ~250 m: visible, although it lies behind the horizon plane.
    const glm::dvec3 eye = wgs84().toEcef(0.0, 0.0, 2.0e7);
    const double a = wgs84().equatorialRadius(), b = wgs84().polarRadius();
    const double horizonDeg = glm::degrees(std::acos(a / (a + 2.0e7)));
    const glm::dvec3 summit = wgs84().toEcef(horizonDeg + 0.5, 0.0, 9000.0);
    ASSERT_LT(glm::dot(summit / a, eye / a), 1.0);   // behind the horizon plane
    const glm::dvec3 toSummit = summit - eye;
    const auto t = wgs84().intersectRay(eye, glm::normalize(toSummit));
    ASSERT_FALSE(t.has_value() && *t < glm::length(toSummit));   // really visible
    EXPECT_FALSE(sphereHiddenByEllipsoid(eye, summit, 1.0, a, b));
    // And well past it, the same summit is hidden.
    EXPECT_TRUE(sphereHiddenByEllipsoid(eye, wgs84().toEcef(horizonDeg + 5.0, 0.0, 9000.0), 1.0, a, b));
}

TEST(TileSelector, DepthFirstCodeOrdersLikeQuadKeys) {
    std::vector<TileKey> keys;
    for (uint32_t l = 0; l <= 4; ++l)
        for (uint32_t x = 0; x < TileKey::tilesX(l); ++x)
            for (uint32_t y = 0; y < TileKey::tilesY(l); ++y) keys.push_back({l, x, y});
    keys.push_back({22, 123456, 54321});
    keys.push_back({30, (2u << 30) - 1, (1u << 30) - 1});
    for (const auto& a : keys)
        for (const auto& b : {keys[5], keys[17], keys[40], keys.back()}) {
            if (a.isAncestorOf(b) || b.isAncestorOf(a) || a == b) continue;
            EXPECT_EQ(depthFirstCode(a) < depthFirstCode(b), a.quadKey() < b.quadKey()) << a.toString() << " " << b.toString();
        }
}

TEST(TileSelector, SelectionIsDisjointAndCoversTheVisibleHemisphere) {
    TileSelector selector;
    const SelectorView view = lookingDownFrom(10.0, 20.0, 2.0e7);
    const auto& tiles = selector.select(view, conservative);
    ASSERT_FALSE(tiles.empty());
    EXPECT_TRUE(disjoint(tiles));
    EXPECT_EQ(selector.stats().selected, tiles.size());
    // Every ground point facing the eye is covered exactly once. Sample offsets avoid tile edges.
    int visible = 0;
    for (double lat = -89.71; lat < 90.0; lat += 1.13) {
        for (double lon = -179.83; lon < 180.0; lon += 1.07) {
            const glm::dvec3 p = wgs84().toEcef(lon, lat, 0.0);
            const bool facing = glm::dot(view.eye - p, wgs84().surfaceNormal(lon, lat)) > 0.0;
            if (!facing) continue;
            ++visible;
            EXPECT_EQ(coverCount(tiles, lon, lat), 1) << lon << "," << lat;
        }
    }
    EXPECT_GT(visible, 5000);
    // From 20 000 km a 1080 px view needs only coarse tiles.
    EXPECT_LT(tiles.size(), 300u);
    EXPECT_LE(selector.stats().maxLevelReached, 5u);
}

TEST(TileSelector, LowerErrorThresholdSelectsMoreAndDeeperTiles) {
    const SelectorView view = viewOf(poseFromViewpoint({8.0, 46.5, 0.0, 30.0, -35.0, 60000.0}));
    size_t lastCount = 0;
    uint32_t lastLevel = 0;
    for (double maxSse : {16.0, 8.0, 4.0, 2.0, 1.0}) {
        SelectorSettings s;
        s.maxScreenSpaceError = maxSse;
        TileSelector selector(s);
        const auto& tiles = selector.select(view, conservative);
        EXPECT_TRUE(disjoint(tiles));
        EXPECT_GT(tiles.size(), lastCount) << maxSse;
        EXPECT_GE(selector.stats().maxLevelReached, lastLevel) << maxSse;
        for (const auto& t : tiles)   // nothing left above the threshold unless at maxLevel
            EXPECT_TRUE(t.screenSpaceError <= maxSse || t.key.level == s.maxLevel) << t.key.toString();
        lastCount = tiles.size();
        lastLevel = selector.stats().maxLevelReached;
    }
    EXPECT_GT(lastLevel, 10u);
}

TEST(TileSelector, RefinementStopsAtTheDataDetailLevelUnlessCurvatureNeedsMore) {
    // A kilometre from a point in the Alps looking ahead: without a data limit the grid error
    // alone refines deep. With data no finer than level 9 the tiles stop at 9: past it only the
    // ellipsoid's curvature within a cell could show, and over a level-9 cell (610 m) that arc's
    // sagitta is 7 mm, under 2 px from anything farther than 5 m.
    const SelectorView view = viewOf(poseFromViewpoint({8.0, 46.5, 0.0, 30.0, -20.0, 1000.0}));
    TileSelector unlimited;
    unlimited.select(view, flat);
    ASSERT_GT(unlimited.stats().maxLevelReached, 12u);

    SelectorSettings s;
    s.detailLevel = 9;
    TileSelector limited(s);
    const auto& tiles = limited.select(view, flat);
    EXPECT_TRUE(disjoint(tiles));
    EXPECT_LT(tiles.size(), unlimited.selection().size() / 2);
    EXPECT_EQ(limited.stats().maxLevelReached, 9u);
    for (const auto& t : tiles) EXPECT_LE(t.screenSpaceError, s.maxScreenSpaceError) << t.key.toString();
    const double sagitta9 = TileSelector::curvatureError(TileKey{9, 0, 0}, 65);
    EXPECT_NEAR(sagitta9, 6378137.0 * (1.0 - std::cos(0.5 * (180.0 / 512.0 / 64.0) * 3.14159265358979 / 180.0)), 1e-12);
    EXPECT_NEAR(sagitta9, 0.0073, 0.0001);

    // No data at all (detailLevel 0): the ellipsoid alone, so a camera far out needs few tiles
    // but one 1 m above the ground still refines until the facets hug the ellipsoid.
    s.detailLevel = 0;
    TileSelector bare(s);
    bare.select(lookingDownFrom(8.0, 46.5, 1.0), flat);
    EXPECT_GT(bare.stats().maxLevelReached, 9u);
    for (const auto& t : bare.selection()) EXPECT_LE(t.screenSpaceError, s.maxScreenSpaceError) << t.key.toString();
}

TEST(TileSelector, LowViewWithConservativeHeightsIsFastAndBounded) {
    // 4.5 km up in the Alps looking toward the horizon. With the conservative [-500, 9000] m
    // ranges the eye is inside every nearby tile, so tiles under it go to maxLevel: more tiles
    // than with real ranges, which makes it a fair worst case for speed.
    TileSelector selector;
    const SelectorView view = viewOf(poseFromEye({7.6, 45.9, 4500.0}, 20.0, -15.0), 10.0);
    selector.select(view, conservative);
    const auto start = std::chrono::steady_clock::now();
    constexpr int kRuns = 20;
    for (int i = 0; i < kRuns; ++i) selector.select(view, conservative);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / kRuns;
    const auto& tiles = selector.selection();
    std::printf("typical view: %zu tiles, %u visited, max level %u, %.3f ms per select\n", tiles.size(),
                selector.stats().visited, selector.stats().maxLevelReached, ms);
    EXPECT_TRUE(disjoint(tiles));
    EXPECT_GT(tiles.size(), 50u);
    EXPECT_LT(tiles.size(), 2000u);
    EXPECT_FALSE(selector.stats().budgetLimited);
    EXPECT_LT(ms, 100.0);   // generous: a few ms in RelWithDebInfo on one core
}

TEST(TileSelector, CameraOneMetreAboveAPoleGoesDeepAndStaysBounded) {
    // Every pole-row tile touches the pole, so all of them are ~1 m away: the tile budget has to
    // hold the count, and the tiles facing the camera get the depth.
    for (double lat : {90.0, -90.0}) {
        TileSelector selector;
        const SelectorView view = viewOf(poseFromEye({0.0, lat, 1.0}, 0.0, -10.0), 0.5);
        const auto& tiles = selector.select(view, flat);
        ASSERT_FALSE(tiles.empty());
        EXPECT_TRUE(selector.stats().budgetLimited);
        EXPECT_LE(tiles.size(), size_t(selector.settings().maxTiles));
        EXPECT_GE(selector.stats().maxLevelReached, 10u);
        for (const auto& t : tiles) {
            EXPECT_TRUE(std::isfinite(t.screenSpaceError));
            EXPECT_TRUE(std::isfinite(t.distance));
        }
        // The ground just in front of the camera is covered, by a deep tile.
        const double ahead = lat > 0 ? 89.9999 : -89.9999;
        int covered = 0;
        for (double lon : {-170.0, -90.0, 0.0, 90.0, 179.0}) covered += coverCount(tiles, lon, ahead) > 0;
        EXPECT_GT(covered, 0);
        uint32_t deepest = 0;
        for (const auto& t : tiles)
            if (t.key.extent().north == 90.0 || t.key.extent().south == -90.0) deepest = std::max(deepest, t.key.level);
        EXPECT_GE(deepest, 10u);
        std::printf("pole %+.0f: %zu tiles, max level %u, visited %u\n", lat, tiles.size(),
                    selector.stats().maxLevelReached, selector.stats().visited);
    }
}

TEST(TileSelector, CameraAtTheAntimeridianSelectsDeepTilesOnBothSides) {
    TileSelector selector;
    // 1 m above lon 180, looking north and slightly down.
    const SelectorView view = viewOf(poseFromEye({180.0, 0.0, 1.0}, 0.0, -10.0), 0.5);
    const auto& tiles = selector.select(view, flat);
    ASSERT_FALSE(tiles.empty());
    EXPECT_TRUE(disjoint(tiles));
    EXPECT_FALSE(selector.stats().budgetLimited);
    const SelectedTile* west = tileAt(tiles, 179.99999, 0.00001);
    const SelectedTile* east = tileAt(tiles, -179.99999, 0.00001);
    ASSERT_NE(west, nullptr);
    ASSERT_NE(east, nullptr);
    EXPECT_EQ(west->key.extent().east, 180.0);
    EXPECT_EQ(east->key.extent().west, -180.0);
    EXPECT_GE(west->key.level, 18u);
    EXPECT_GE(east->key.level, 18u);
    std::printf("antimeridian: %zu tiles, max level %u\n", tiles.size(), selector.stats().maxLevelReached);
}

TEST(TileSelector, CameraFortyThousandKilometresOutSelectsOnlyCoarseTiles) {
    TileSelector selector;
    const auto& tiles = selector.select(lookingDownFrom(-60.0, 10.0, 4.0e7), conservative);
    EXPECT_TRUE(disjoint(tiles));
    EXPECT_LE(selector.stats().maxLevelReached, 2u);
    EXPECT_LE(tiles.size(), 32u);
}

TEST(TileSelector, HorizonCullingRemovesTheFarSide) {
    const SelectorView view = lookingDownFrom(0.0, 0.0, 2.0e7);
    TileSelector culled;
    const auto& tiles = culled.select(view, conservative);
    EXPECT_GT(culled.stats().culledHorizon, 0u);
    // The antipodal side is in the frustum (straight ahead, through the Earth): only the
    // horizon test can drop it.
    for (double lon : {180.0 - 30.0, 179.0, -179.0, -150.0})
        for (double lat : {-30.0, 0.0, 30.0}) EXPECT_EQ(coverCount(tiles, lon, lat), 0) << lon << "," << lat;

    SelectorSettings noHorizon;
    noHorizon.occluderHeight = -1.0e8;   // an occluder of negative size hides nothing
    TileSelector all(noHorizon);
    const auto& everything = all.select(view, conservative);
    EXPECT_EQ(all.stats().culledHorizon, 0u);
    EXPECT_GT(coverCount(everything, 179.0, 0.0), 0);
    EXPECT_GT(everything.size(), tiles.size());
}

TEST(TileSelector, FrustumCullingRemovesTilesBehindTheCamera) {
    // 1000 km above (0, 45), looking level toward the north: the ground behind (south) is out.
    TileSelector selector;
    const SelectorView view = viewOf(poseFromEye({0.0, 45.0, 1.0e6}, 0.0, -40.0));
    const auto& tiles = selector.select(view, conservative);
    EXPECT_GT(selector.stats().culledFrustum, 0u);
    EXPECT_TRUE(disjoint(tiles));
    EXPECT_EQ(coverCount(tiles, 0.3, 35.0), 0);     // behind and below
    EXPECT_EQ(coverCount(tiles, 0.3, 40.0), 0);
    EXPECT_GT(coverCount(tiles, 0.3, 60.0), 0);     // ahead, before the horizon (~30 degrees)
    // No selected tile lies wholly behind the eye.
    for (const auto& t : tiles) {
        const GeoExtent e = t.key.extent();
        bool anyInFront = false;
        for (int i = 0; i <= 8 && !anyInFront; ++i)
            for (int j = 0; j <= 8 && !anyInFront; ++j)
                for (double h : {-500.0, 9000.0}) {
                    const glm::dvec3 p = wgs84().toEcef(e.west + e.width() * i / 8.0, e.south + e.height() * j / 8.0, h);
                    anyInFront = anyInFront || (view.worldToView * (p - view.eye)).z < 0.0;
                }
        EXPECT_TRUE(anyInFront) << t.key.toString();
    }
}

TEST(TileSelector, MinLevelForcesRefinement) {
    SelectorSettings s;
    s.minLevel = 4;
    TileSelector selector(s);
    const auto& tiles = selector.select(lookingDownFrom(30.0, -10.0, 4.0e7), conservative);
    for (const auto& t : tiles) EXPECT_GE(t.key.level, 4u);
    EXPECT_TRUE(disjoint(tiles));
}

TEST(TileSelector, HysteresisKeepsTilesThroughJitterAtTheThreshold) {
    // Looking straight down at flat ground, the tile under the camera is exactly `height` away,
    // so its error crosses the 2 px threshold at a height known in closed form. Jitter the camera
    // by 1 ppm across it: without hysteresis the selection flips every frame; with it, it changes
    // at most once.
    const TileKey nadir = TileKey::containing(10.3, 20.7, 8);
    const double sseFactor = kViewportPx / (2.0 * std::tan(0.5 * kFov));
    const double threshold = TileSelector::geometricError(nadir, 65) * sseFactor / 2.0;
    const double lo = threshold * (1.0 - 1e-6), hi = threshold * (1.0 + 1e-6);
    auto select = [](double hysteresis, double height) {
        SelectorSettings s;
        s.hysteresis = hysteresis;
        TileSelector sel(s);
        return keysOf(sel.select(lookingDownFrom(10.3, 20.7, height), flat));
    };
    TileSelector below, above;
    ASSERT_TRUE(refinedSet(below.select(lookingDownFrom(10.3, 20.7, lo), flat)).count(nadir));
    ASSERT_FALSE(refinedSet(above.select(lookingDownFrom(10.3, 20.7, hi), flat)).count(nadir));
    ASSERT_NE(select(0.0, lo), select(0.0, hi));

    auto changes = [&](double hysteresis) {
        SelectorSettings s;
        s.hysteresis = hysteresis;
        TileSelector sel(s);
        std::vector<TileKey> last;
        int n = -1;
        for (int frame = 0; frame < 20; ++frame) {
            auto keys = keysOf(sel.select(lookingDownFrom(10.3, 20.7, frame % 2 ? hi : lo), flat));
            if (keys != last) ++n;
            last = std::move(keys);
        }
        return n;
    };
    EXPECT_EQ(changes(0.0), 19);
    EXPECT_LE(changes(0.15), 1);

    // Hysteresis only delays merging: a tile refined last frame stays refined while its error is
    // above 0.85 x the threshold, no longer. So the selection is never coarser than a fresh one
    // at threshold 2 nor finer than a fresh one at 1.7, here after moving well out of the band.
    auto fresh = [](double maxSse, double height) {
        SelectorSettings s;
        s.maxScreenSpaceError = maxSse;
        TileSelector sel(s);
        return keysOf(sel.select(lookingDownFrom(10.3, 20.7, height), flat));
    };
    auto noneAbove = [](const std::vector<TileKey>& finer, const std::vector<TileKey>& coarser) {
        for (const auto& c : coarser)
            for (const auto& f : finer)
                if (c.isAncestorOf(f)) return ::testing::AssertionFailure() << c.toString() << " above " << f.toString();
        return ::testing::AssertionSuccess();
    };
    TileSelector sel;
    const auto refined = keysOf(sel.select(lookingDownFrom(10.3, 20.7, lo), flat));
    for (double height : {lo * 1.1, lo * 1.5, lo * 2.0}) {
        const auto now = keysOf(sel.select(lookingDownFrom(10.3, 20.7, height), flat));
        EXPECT_TRUE(noneAbove(fresh(2.0, height), now)) << height;
        EXPECT_TRUE(noneAbove(now, fresh(2.0 * 0.85, height))) << height;
    }
    EXPECT_NE(keysOf(sel.selection()), refined);
    // reset() forgets the previous frame.
    sel.select(lookingDownFrom(10.3, 20.7, lo), flat);
    sel.reset();
    EXPECT_EQ(keysOf(sel.select(lookingDownFrom(10.3, 20.7, hi), flat)), select(0.0, hi));
}

TEST(TileSelector, HysteresisDoesNotHoldARefinementMadeOnHeightsSinceNarrowed) {
    // A still camera whose nadir tile, on the flat ground it has, errs by 0.9 x the threshold
    // (inside the hysteresis band). Judged first on wide padded heights (no data of its own
    // yet), the tile is nearer, errs more and refines; once the flat heights are known it merges, as a
    // fresh selection would: what is drawn does not depend on the order data came in.
    const TileKey nadir = TileKey::containing(10.3, 20.7, 8);
    const double sseFactor = kViewportPx / (2.0 * std::tan(0.5 * kFov));
    const double threshold = TileSelector::geometricError(nadir, 65) * sseFactor / 2.0;
    const double height = threshold / 0.9;
    const SelectorView view = lookingDownFrom(10.3, 20.7, height);
    // (Heights a coarse ancestor's padded range could give: up to a fifth of the way up.)
    const auto unknown = [height](const TileKey&) { return TileHeightRange{-500.0, 0.2 * height}; };
    TileSelector sel;
    ASSERT_TRUE(refinedSet(sel.select(view, unknown)).count(nadir));
    EXPECT_TRUE(refinedSet(sel.select(view, unknown)).count(nadir));   // the same heights: held
    TileSelector fresh;
    ASSERT_FALSE(refinedSet(fresh.select(view, flat)).count(nadir));
    EXPECT_FALSE(refinedSet(sel.select(view, flat)).count(nadir));
    EXPECT_EQ(keysOf(sel.selection()), keysOf(fresh.selection()));
}

TEST(TileSelector, IdenticalInputsGiveIdenticalOutputInDepthFirstOrder) {
    const SelectorView views[] = {viewOf(poseFromViewpoint({-122.4, 37.8, 0.0, 45.0, -30.0, 20000.0})),
                                  viewOf(poseFromViewpoint({-122.3, 37.7, 0.0, 50.0, -25.0, 18000.0})),
                                  lookingDownFrom(0.0, 0.0, 2.0e7)};
    TileSelector a, b;
    for (const auto& v : views) {
        const auto ta = a.select(v, conservative);
        const auto& tb = b.select(v, conservative);
        ASSERT_EQ(ta.size(), tb.size());
        for (size_t i = 0; i < ta.size(); ++i) {
            EXPECT_EQ(ta[i].key, tb[i].key);
            EXPECT_EQ(ta[i].screenSpaceError, tb[i].screenSpaceError);   // bit-identical
            EXPECT_EQ(ta[i].distance, tb[i].distance);
        }
        // Depth-first, NW NE SW SE: for disjoint tiles that is the order of their quadkeys.
        for (size_t i = 1; i < ta.size(); ++i) EXPECT_LT(ta[i - 1].key.quadKey(), ta[i].key.quadKey());
        EXPECT_EQ(a.stats().visited, b.stats().visited);
    }
}

TEST(TileSelector, CameraInsideATallTileNeverCullsIt) {
    // 50 m up, inside the conservative height range of every tile below, looking up at the sky:
    // the tiles around the eye stay (the camera is inside their volume).
    TileSelector selector;
    const SelectorView view = viewOf(poseFromEye({-70.0, -33.0, 50.0}, 0.0, 60.0));
    const auto& tiles = selector.select(view, conservative);
    EXPECT_GT(coverCount(tiles, -70.0, -33.0), 0);
    EXPECT_TRUE(disjoint(tiles));
}

TEST(GeoExtent, MeetsWithTurnsSeesABoxAcrossTheAntimeridian) {
    const GeoExtent eastEdge{170.0, -10.0, 180.0, 10.0};
    const GeoExtent westEdge{-180.0, -10.0, -170.0, 10.0};
    // A region written with continuous longitudes past +180 reaches the tile at the west edge.
    const GeoExtent across{175.0, 0.0, 185.0, 5.0};
    EXPECT_TRUE(eastEdge.meetsWithTurns(across));
    EXPECT_TRUE(westEdge.meetsWithTurns(across));
    EXPECT_TRUE(westEdge.meetsWithTurns({-190.0, 0.0, -175.0, 5.0}));
    // Closed boxes: touching edges meet; a latitude gap or a longitude gap does not.
    EXPECT_TRUE(eastEdge.meetsWithTurns({160.0, 10.0, 170.0, 20.0}));
    EXPECT_FALSE(eastEdge.meetsWithTurns({175.0, 10.5, 185.0, 20.0}));
    EXPECT_FALSE(westEdge.meetsWithTurns({0.0, 0.0, 10.0, 5.0}));
    EXPECT_FALSE(westEdge.meetsWithTurns({192.0, 0.0, 195.0, 5.0}));  // -168..-165
}

}  // namespace
}  // namespace orbis::globe
