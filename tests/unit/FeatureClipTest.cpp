#include "layers/vector/FeatureClip.h"
#include "layers/vector/Triangulate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace orbis::vector {
namespace {

namespace fs = std::filesystem;
using globe::GeoExtent;
using globe::TileKey;

Feature polygon(const std::vector<std::vector<glm::dvec2>>& rings) {
    Feature f;
    f.kind = GeometryKind::Polygons;
    f.polygons.push_back(0);
    f.bounds = {.west = 1e9, .south = 1e9, .east = -1e9, .north = -1e9, .empty = false};
    for (const auto& ring : rings) {
        f.parts.push_back(uint32_t(f.coords.size()));
        f.containsPole.push_back(0);
        for (glm::dvec2 p : ring) {
            f.coords.emplace_back(p.x, p.y, 0.0);
            f.bounds.west = std::min(f.bounds.west, p.x), f.bounds.east = std::max(f.bounds.east, p.x);
            f.bounds.south = std::min(f.bounds.south, p.y), f.bounds.north = std::max(f.bounds.north, p.y);
        }
    }
    return f;
}

/// Twice the area a polygon feature covers in the lon/lat plane: outer rings less their holes.
double area2(const Feature& f, bool closePoles = false) {
    double sum = 0.0;
    for (size_t k = 0; k < f.polygons.size(); ++k)
        for (size_t p = f.polygons[k]; p < f.polygonEnd(k); ++p) {
            std::vector<glm::dvec3> ring(f.coords.begin() + f.parts[p], f.coords.begin() + f.partEnd(p));
            if (closePoles) closeThroughPole(ring, f.containsPole[p]);
            double a = 0.0;
            for (size_t i = 0; i < ring.size(); ++i) {
                const glm::dvec3 &u = ring[i], &v = ring[(i + 1) % ring.size()];
                a += u.x * v.y - v.x * u.y;
            }
            sum += p == f.polygons[k] ? std::abs(a) : -std::abs(a);
        }
    return sum;
}

TEST(FeatureClip, APolygonWithAHoleKeepsTheAreaInsideTheTile) {
    const Feature f = polygon({{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {{2, 2}, {2, 4}, {4, 4}, {4, 2}}});
    auto east = clipFeature(f, GeoExtent{5, -5, 15, 5});
    ASSERT_TRUE(east);
    EXPECT_DOUBLE_EQ(area2(*east), 2 * 25.0);
    ASSERT_EQ(east->parts.size(), 1u);   // the hole is outside
    auto corner = clipFeature(f, GeoExtent{0, 0, 3, 3});
    ASSERT_TRUE(corner);
    EXPECT_DOUBLE_EQ(area2(*corner), 2 * (9.0 - 1.0));
    EXPECT_FALSE(clipFeature(f, GeoExtent{20, 20, 30, 30}));
    EXPECT_FALSE(clipFeature(f, GeoExtent{10, 0, 20, 10}));   // touching an edge only
}

TEST(FeatureClip, APolygonAcrossTheAntimeridianIsSharedByTheTilesOnBothSides) {
    const Feature f = polygon({{{170, 0}, {190, 0}, {190, 10}, {170, 10}}});   // unwrapped, as the reader gives it
    const auto tiles = tilesCovering(f, 3);
    double total = 0.0;
    bool west = false, east = false;
    for (const TileKey& key : tiles) {
        const GeoExtent e = key.extent();
        auto piece = clipFeature(f, e);
        if (!piece) continue;
        for (const glm::dvec3& c : piece->coords) ASSERT_TRUE(c.x >= e.west && c.x <= e.east) << key.toString();
        west = west || e.west == -180.0;
        east = east || e.east == 180.0;
        total += area2(*piece);
    }
    EXPECT_TRUE(west && east);
    EXPECT_NEAR(total, 2 * 200.0, 1e-9);
}

TEST(FeatureClip, LinesAreCutWhereTheyLeaveAndReenter) {
    Feature line;
    line.kind = GeometryKind::Lines;
    line.parts = {0};
    line.coords = {{-10, 1, 5}, {10, 1, 5}, {10, 3, 5}, {-10, 3, 5}, {-10, 5, 5}, {5, 5, 5}};
    line.bounds = {.west = -10, .south = 1, .east = 10, .north = 5, .empty = false};
    auto piece = clipFeature(line, GeoExtent{0, 0, 20, 10});
    ASSERT_TRUE(piece);
    ASSERT_EQ(piece->parts.size(), 2u);
    EXPECT_EQ(piece->coords[piece->parts[0]], glm::dvec3(0, 1, 5));   // entered at the west edge
    EXPECT_EQ(piece->coords[piece->parts[0] + 1], glm::dvec3(10, 1, 5));
    EXPECT_EQ(piece->coords[piece->parts[0] + 2], glm::dvec3(10, 3, 5));
    EXPECT_EQ(piece->coords[piece->parts[0] + 3], glm::dvec3(0, 3, 5));   // left again
    EXPECT_EQ(piece->coords[piece->parts[1]], glm::dvec3(0, 5, 5));   // and came back
    EXPECT_EQ(piece->coords.back(), glm::dvec3(5, 5, 5));
}

TEST(FeatureClip, PointsAcrossTheAntimeridianLandInTheRightTile) {
    Feature points;
    points.kind = GeometryKind::Points;
    points.parts = {0, 1};
    points.coords = {{179, 10, 0}, {181, 10, 0}};   // a multipoint unwrapped across 180
    points.bounds = {.west = 179, .south = 10, .east = 181, .north = 10, .empty = false};
    const TileKey tile = TileKey::containing(-179.0, 10.0, 4);
    auto piece = clipFeature(points, tile.extent());
    ASSERT_TRUE(piece);
    ASSERT_EQ(piece->coords.size(), 1u);
    EXPECT_DOUBLE_EQ(piece->coords[0].x, -179.0);
    const auto tiles = tilesCovering(points, 4);
    EXPECT_EQ(tiles.size(), 2u);   // one on each side of 180
}

TEST(FeatureClip, NaturalEarthCutIntoTilesKeepsItsAreaTriangulatesCleanlyAndAntarcticaCoversThePole) {
    const fs::path file = fs::path(ORBIS_SHARED_DATA_DIR) / "vector" / "naturalearth_lowres.shp";
    if (!fs::exists(file)) GTEST_SKIP() << "../shared/data is absent: no " << file;
    VectorReadOptions o;
    o.source = file.string();
    auto data = readVector(o);
    ASSERT_TRUE(data) << data.message();
    size_t pieces = 0;
    for (const Feature& f : data->layers[0].features) {
        double total = 0.0, polar = 0.0;
        for (const TileKey& key : tilesCovering(f, 2)) {
            auto piece = clipFeature(f, key.extent());
            if (!piece) continue;
            ++pieces;
            total += area2(*piece);
            // Each piece triangulates to its own area (the clip's seams along the tile's edges
            // drop out).
            for (size_t k = 0; k < piece->polygons.size(); ++k) {
                std::vector<glm::dvec2> points;
                std::vector<uint32_t> starts;
                for (size_t p = piece->polygons[k]; p < piece->polygonEnd(k); ++p) {
                    starts.push_back(uint32_t(points.size()));
                    for (uint32_t i = piece->parts[p]; i < piece->partEnd(p); ++i) points.emplace_back(piece->coords[i]);
                }
                TriangulateStats stats;
                auto tris = triangulate(points, starts, 1'000'000, &stats);
                ASSERT_TRUE(tris) << tris.message();
                double covered = 0.0, expected = 0.0;
                for (size_t t = 0; t < tris->size(); t += 3) {
                    const glm::dvec2 a = points[(*tris)[t]], b = points[(*tris)[t + 1]], c = points[(*tris)[t + 2]];
                    const double t2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
                    EXPECT_GT(t2, 0.0) << "feature " << f.fid << " in " << key.toString() << " triangle " << t / 3;
                    covered += t2;
                }
                for (size_t r = 0; r < starts.size(); ++r) {
                    const size_t end = r + 1 < starts.size() ? starts[r + 1] : points.size();
                    const double a = std::abs(ringArea2(std::span(points).subspan(starts[r], end - starts[r])));
                    expected += r == 0 ? a : -a;
                }
                EXPECT_NEAR(covered, expected, 1e-9 * expected + 1e-12) << "feature " << f.fid << " in " << key.toString();
                EXPECT_EQ(stats.forced, 0u) << "feature " << f.fid << " in " << key.toString();
                EXPECT_GT(covered, 0.0);
            }
            if (auto cap = clipFeature(*piece, GeoExtent{-180, -90, 180, -86})) polar += area2(*cap);
        }
        EXPECT_NEAR(total, area2(f, true), 1e-9 * area2(f, true)) << "feature " << f.fid;
        const bool antarctica = std::any_of(f.containsPole.begin(), f.containsPole.end(), [](int8_t p) { return p != 0; });
        // The cap south of 86 degrees is all Antarctica's, and nobody else's.
        EXPECT_NEAR(polar, antarctica ? 2 * 360.0 * 4.0 : 0.0, 1e-6) << "feature " << f.fid;
    }
    EXPECT_GT(pieces, 177u);   // more pieces than countries: many are cut
}

}  // namespace
}  // namespace orbis::vector
