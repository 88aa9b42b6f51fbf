#include "layers/vector/DrapeRaster.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

namespace orbis::vector {
namespace {

using globe::GeoExtent;

/// Most tests draw on a 100 px tile over 0..100 degrees, so that a degree is a pixel: pixel
/// coordinate (x, y) is lon x, lat 100 - y.
constexpr int kSize = 100;
// On the equator, where a pixel is as wide as it is high on the ground.
const GeoExtent kUnitExtent{0.0, -50.0, 100.0, 50.0};

glm::dvec3 px(double x, double y) { return {x, 50.0 - y, 0.0}; }

std::vector<glm::dvec3> box(double x0, double y0, double x1, double y1, bool reversed = false) {
    std::vector<glm::dvec3> r{px(x0, y0), px(x1, y0), px(x1, y1), px(x0, y1), px(x0, y0)};
    if (reversed) std::reverse(r.begin(), r.end());
    return r;
}

/// A feature of `kind` whose parts are `parts`; for polygons, `polygonStarts` groups them
/// (default: one polygon).
Feature feature(GeometryKind kind, const std::vector<std::vector<glm::dvec3>>& parts, std::vector<uint32_t> polygonStarts = {0},
                std::vector<int8_t> poles = {}) {
    Feature f;
    f.kind = kind;
    for (const auto& part : parts) {
        f.parts.push_back(uint32_t(f.coords.size()));
        f.coords.insert(f.coords.end(), part.begin(), part.end());
    }
    if (kind == GeometryKind::Polygons) {
        f.polygons = std::move(polygonStarts);
        f.containsPole = poles.empty() ? std::vector<int8_t>(parts.size(), 0) : std::move(poles);
    }
    return f;
}

FeatureStyle fillStyle(glm::dvec3 fill = {0, 0, 1}, double fillOpacity = 1.0) {
    FeatureStyle s;
    s.fill = fill;
    s.fillOpacity = fillOpacity;
    s.outline = false;
    return s;
}

FeatureStyle lineStyle(double widthPx, double opacity = 1.0, glm::dvec3 color = {1, 0, 0}) {
    FeatureStyle s;
    s.color = color;
    s.opacity = opacity;
    s.widthPx = widthPx;
    return s;
}

struct Tile {
    std::vector<uint8_t> rgba;
    int size = kSize;
    bool painted = false;
    DrapeTileStats stats;

    const uint8_t* at(int x, int y) const { return &rgba[(size_t(y) * size + x) * 4]; }
    double alpha(int x, int y) const { return at(x, y)[3] / 255.0; }
    double alphaSum() const {
        double sum = 0.0;
        for (size_t i = 3; i < rgba.size(); i += 4) sum += rgba[i] / 255.0;
        return sum;
    }
    double columnSum(int x) const {
        double sum = 0.0;
        for (int y = 0; y < size; ++y) sum += alpha(x, y);
        return sum;
    }
    int maxAlpha() const {
        int m = 0;
        for (size_t i = 3; i < rgba.size(); i += 4) m = std::max(m, int(rgba[i]));
        return m;
    }
};

Tile draw(const std::vector<DrapeItem>& items, const GeoExtent& extent = kUnitExtent, int size = kSize, double pixelScale = 1.0) {
    Tile t;
    t.size = size;
    t.painted = rasterizeDrapeTile(items, {.extent = extent, .size = size, .pixelScale = pixelScale}, t.rgba, &t.stats);
    return t;
}

Tile draw(const Feature& f, const FeatureStyle& s, const GeoExtent& extent = kUnitExtent, int size = kSize, double pixelScale = 1.0) {
    return draw(std::vector<DrapeItem>{{&f, &s}}, extent, size, pixelScale);
}

// --- polygons -------------------------------------------------------------------------------

// The accumulation is exact up to float rounding and 8-bit alpha (half a step per edge pixel):
// 0.5% of the area is several times that.
TEST(DrapeRasterFill, ASquareCoversItsAreaInPixels) {
    const Feature f = feature(GeometryKind::Polygons, {box(10.3, 20.7, 60.1, 55.6)});
    const Tile t = draw(f, fillStyle());
    ASSERT_TRUE(t.painted);
    EXPECT_NEAR(t.alphaSum(), 49.8 * 34.9, 0.005 * 49.8 * 34.9);
    EXPECT_EQ(t.at(30, 40)[3], 255);
    EXPECT_EQ(t.at(30, 40)[2], 255);   // the fill colour, blue
    EXPECT_EQ(t.at(5, 40)[3], 0);
    EXPECT_EQ(t.at(30, 60)[3], 0);
    EXPECT_EQ(t.stats.featuresPainted, 1u);
}

TEST(DrapeRasterFill, AnEdgeThroughPixelCentresHalfCoversThem) {
    const Feature f = feature(GeometryKind::Polygons, {box(10.5, 10.0, 30.0, 30.0)});
    const Tile t = draw(f, fillStyle());
    for (int y = 10; y < 30; ++y) {
        EXPECT_NEAR(t.alpha(10, y), 0.5, 1.0 / 255) << y;   // one 8-bit step
        EXPECT_EQ(t.at(11, y)[3], 255) << y;
        EXPECT_EQ(t.at(9, y)[3], 0) << y;
    }
}

TEST(DrapeRasterFill, FillOpacityScalesTheCoverage) {
    const Feature f = feature(GeometryKind::Polygons, {box(10, 10, 20, 20)});
    const Tile t = draw(f, fillStyle({0, 1, 0}, 0.4));
    EXPECT_NEAR(t.alpha(15, 15), 0.4, 1.0 / 255);
    EXPECT_NEAR(t.alphaSum(), 0.4 * 100, 0.005 * 40);
}

TEST(DrapeRasterFill, AHoleIsEmptyWhateverWayItsRingsWereStored) {
    for (bool outerReversed : {false, true})
        for (bool holeReversed : {false, true}) {
            const Feature f = feature(GeometryKind::Polygons, {box(10, 10, 90, 90, outerReversed), box(30.5, 30.5, 70.5, 70.5, holeReversed)});
            const Tile t = draw(f, fillStyle());
            SCOPED_TRACE(testing::Message() << "outer reversed " << outerReversed << ", hole reversed " << holeReversed);
            EXPECT_EQ(t.at(50, 50)[3], 0);
            EXPECT_EQ(t.at(31, 31)[3], 0);
            EXPECT_EQ(t.at(69, 69)[3], 0);
            EXPECT_EQ(t.at(20, 50)[3], 255);
            EXPECT_NEAR(t.alphaSum(), 80 * 80 - 40 * 40, 0.005 * 4800);
        }
}

TEST(DrapeRasterFill, ThePolygonsOfOneFeatureUnionAndCompositeOnce) {
    // Two overlapping squares, one feature, half opacity: the overlap is no darker.
    const Feature f = feature(GeometryKind::Polygons, {box(10, 10, 50, 50), box(30, 30, 70, 70, true)}, {0, 1});
    const Tile t = draw(f, fillStyle({0, 0, 1}, 0.5));
    EXPECT_EQ(t.at(40, 40)[3], t.at(20, 20)[3]);
    EXPECT_EQ(t.at(60, 60)[3], t.at(20, 20)[3]);
    EXPECT_NEAR(t.alphaSum(), 0.5 * (1600 + 1600 - 400), 0.005 * 1400);
}

TEST(DrapeRasterFill, APolygonLargerThanTheTileCoversAllOfIt) {
    // Its edges lie off every side: west of the tile they still count, east and beyond the
    // rows they do not.
    const Feature f = feature(GeometryKind::Polygons, {{px(-500, -300), px(700, -200), px(650, 900), px(-400, 800)}});
    const Tile t = draw(f, fillStyle());
    EXPECT_EQ(t.alphaSum(), double(kSize * kSize));
    const Feature away = feature(GeometryKind::Polygons, {box(-50, 10, -10, 90)});
    EXPECT_FALSE(draw(away, fillStyle()).painted);
}

TEST(DrapeRasterFill, AnOutlineIsStrokedOverTheFill) {
    FeatureStyle s = fillStyle({0, 0, 1}, 1.0);
    s.outline = true;
    s.color = {1, 0, 0};
    s.widthPx = 2.0;
    const Feature f = feature(GeometryKind::Polygons, {box(20, 20, 80, 80)});
    const Tile t = draw(f, s);
    EXPECT_EQ(t.at(20, 50)[0], 255);   // on the west edge: red
    EXPECT_EQ(t.at(20, 50)[2], 0);
    EXPECT_EQ(t.at(50, 50)[0], 0);     // inside: blue
    EXPECT_EQ(t.at(50, 50)[2], 255);
    EXPECT_EQ(t.at(17, 50)[3], 0);     // past the stroke's reach (1.5 px + the ramp)
}

// --- lines ----------------------------------------------------------------------------------

// A horizontal line's coverage across is a trapezoid with 1 px ramps sampled at pixel centres,
// which sums to the width exactly; 5% (and the 8-bit alpha) is the allowance.
TEST(DrapeRasterLines, AThreePixelLineSumsToThreeAcross) {
    const Feature f = feature(GeometryKind::Lines, {{px(5, 50.3), px(95, 50.3)}});
    const Tile t = draw(f, lineStyle(3.0));
    for (int x = 10; x <= 90; x += 5) EXPECT_NEAR(t.columnSum(x), 3.0, 0.05 * 3) << x;
    // At 30 degrees a column crosses it over 3 / cos(30 deg).
    const double angle = std::numbers::pi / 6;
    const Feature slanted = feature(GeometryKind::Lines, {{px(5, 20), px(95, 20 + 90 * std::tan(angle))}});
    const Tile u = draw(slanted, lineStyle(3.0));
    for (int x = 20; x <= 80; x += 10) EXPECT_NEAR(u.columnSum(x), 3.0 / std::cos(angle), 0.05 * 3.0 / std::cos(angle)) << x;
}

TEST(DrapeRasterLines, PixelScaleWidensTheLine) {
    const Feature f = feature(GeometryKind::Lines, {{px(5, 50), px(95, 50)}});
    EXPECT_NEAR(draw(f, lineStyle(2.0), kUnitExtent, kSize, 2.0).columnSum(50), 4.0, 0.05 * 4);
}

TEST(DrapeRasterLines, AOnePixelLineCoversExactlyOnePixelAcross) {
    const Feature centred = feature(GeometryKind::Lines, {{px(5, 40.5), px(95, 40.5)}});
    const Tile t = draw(centred, lineStyle(1.0));
    EXPECT_EQ(t.at(50, 40)[3], 255);
    EXPECT_EQ(t.at(50, 39)[3], 0);
    EXPECT_EQ(t.at(50, 41)[3], 0);
    EXPECT_NEAR(t.columnSum(50), 1.0, 1.0 / 255);
    // Between two rows it shares itself between them.
    const Feature between = feature(GeometryKind::Lines, {{px(5, 40), px(95, 40)}});
    const Tile u = draw(between, lineStyle(1.0));
    EXPECT_NEAR(u.alpha(50, 39), 0.5, 1.0 / 255);
    EXPECT_NEAR(u.alpha(50, 40), 0.5, 1.0 / 255);
    EXPECT_NEAR(u.columnSum(50), 1.0, 2.0 / 255);
}

TEST(DrapeRasterLines, AHairlineDrawsOnePixelAtItsWidthAsAlpha) {
    const Feature f = feature(GeometryKind::Lines, {{px(5, 40.5), px(95, 40.5)}});
    const Tile t = draw(f, lineStyle(0.4));
    EXPECT_NEAR(t.alpha(50, 40), 0.4, 1.0 / 255);
    EXPECT_NEAR(t.columnSum(50), 0.4, 0.05 * 0.4);
}

TEST(DrapeRasterLines, JointsAndOverlapsAreNoDarkerThanTheLine) {
    // A V, and a line that doubles back over itself, at 60% opacity: max, not a sum.
    const Feature v = feature(GeometryKind::Lines, {{px(10, 10), px(50, 80), px(90, 10)}});
    const Tile t = draw(v, lineStyle(6.0, 0.6));
    const int full = int(std::lround(0.6 * 255));
    EXPECT_LE(t.maxAlpha(), full);
    EXPECT_EQ(t.at(50, 78)[3], full);   // at the joint
    const Feature back = feature(GeometryKind::Lines, {{px(10, 50), px(90, 50), px(30, 50.5)}, {px(50, 20), px(50, 90)}});
    EXPECT_LE(draw(back, lineStyle(4.0, 0.6)).maxAlpha(), full);
}

// Widths and markers are on the ground: at 60 degrees a pixel of the tile is half as wide on the
// ground as it is high, so a line running north is twice as many pixels wide as one running
// east, and a marker twice as wide as it is high.
TEST(DrapeRasterLines, WidthsAreOnTheGroundAtAnyLatitude) {
    const GeoExtent north{0.0, 59.5, 1.0, 60.5};   // centred on 60 degrees: cos = 0.5
    const double d = 1.0 / 100.0;                  // degrees a pixel
    const auto at = [&](double x, double y) { return glm::dvec3(x * d, 60.5 - y * d, 0.0); };
    const Tile east = draw(feature(GeometryKind::Lines, {{at(5, 50.3), at(95, 50.3)}}), lineStyle(3.0), north);
    const Tile up = draw(feature(GeometryKind::Lines, {{at(50.3, 5), at(50.3, 95)}}), lineStyle(3.0), north);
    for (int k = 20; k <= 80; k += 20) {
        EXPECT_NEAR(east.columnSum(k), 3.0, 0.05 * 3.0) << k;
        double across = 0.0;
        for (int x = 0; x < kSize; ++x) across += up.at(x, k)[3] / 255.0;
        EXPECT_NEAR(across, 6.0, 0.05 * 6.0) << k;
    }
    FeatureStyle s = lineStyle(1.0, 1.0, {1, 1, 0});
    s.iconSizePx = 16.0;
    const Tile m = draw(feature(GeometryKind::Points, {{at(50, 50)}}), s, north);
    EXPECT_NEAR(m.alphaSum(), std::numbers::pi * 64 * 2.0, 0.03 * std::numbers::pi * 64 * 2.0);
    EXPECT_GT(m.at(64, 50)[3], 200);   // 14 px east: inside (the disk reaches 16 px across)
    EXPECT_EQ(m.at(50, 64)[3], 0);     // 14 px south: outside (8 px down)
}

// --- points ---------------------------------------------------------------------------------

// A disk's coverage is a 1 px ramp around its radius, which sums to pi r^2 up to the lattice's
// error: 2% is many times that at these radii.
TEST(DrapeRasterPoints, AMarkerIsADiskOfItsSize) {
    FeatureStyle s = lineStyle(1.0, 1.0, {1, 1, 0});
    s.iconSizePx = 16.0;
    const Feature f = feature(GeometryKind::Points, {{px(50, 50)}});
    const Tile t = draw(f, s);
    ASSERT_TRUE(t.painted);
    EXPECT_NEAR(t.alphaSum(), std::numbers::pi * 64, 0.02 * std::numbers::pi * 64);
    EXPECT_EQ(t.at(50, 50)[0], 255);   // yellow inside
    EXPECT_EQ(t.at(50, 50)[1], 255);
    EXPECT_LT(t.at(57, 50)[0], 128);   // the dark outline at its edge
    EXPECT_EQ(t.at(50, 60)[3], 0);
    const Tile twice = draw(f, s, kUnitExtent, kSize, 2.0);
    EXPECT_NEAR(twice.alphaSum(), std::numbers::pi * 256, 0.02 * std::numbers::pi * 256);
}

TEST(DrapeRasterPoints, AMarkerScalesWithTheRangeTheTileIsDrawnFrom) {
    FeatureStyle s = lineStyle(1.0, 1.0, {1, 1, 0});
    s.iconSizePx = 16.0;
    s.iconNearM = 1000.0, s.iconFarM = 2000.0, s.iconFarScale = 0.5;
    const Feature f = feature(GeometryKind::Points, {{px(50, 50)}});
    const DrapeItem item{&f, &s};
    for (const auto& [range, radius] : {std::pair{500.0, 8.0}, std::pair{1500.0, 6.0}, std::pair{5000.0, 4.0}}) {
        Tile t;
        ASSERT_TRUE(rasterizeDrapeTile({&item, 1}, {.extent = kUnitExtent, .size = kSize, .rangeM = range}, t.rgba));
        EXPECT_NEAR(t.alphaSum(), std::numbers::pi * radius * radius, 0.05 * std::numbers::pi * radius * radius) << range;
    }
}

TEST(DrapeRasterPoints, AnIconIsDrawnItsSizeHighInsteadOfTheMarker) {
    // 8 x 4 texels: the left half opaque red, the right half transparent; drawn 16 px high it is
    // 32 px wide, the red half on [34, 50) x [42, 58).
    ImageRgba8 icon{8, 4, std::vector<uint8_t>(8 * 4 * 4, 0)};
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            uint8_t* t = &icon.pixels[(size_t(y) * 8 + x) * 4];
            t[0] = 255, t[3] = 255;
        }
    FeatureStyle s = lineStyle(1.0, 1.0, {1, 1, 0});
    s.iconSizePx = 16.0;
    const Feature f = feature(GeometryKind::Points, {{px(50, 50)}});
    const DrapeItem item{&f, &s, &icon};
    Tile t;
    t.painted = rasterizeDrapeTile({&item, 1}, {.extent = kUnitExtent, .size = kSize}, t.rgba);
    ASSERT_TRUE(t.painted);
    EXPECT_NEAR(t.alphaSum(), 16.0 * 16.0, 16.0) << "the red half, edges antialiased";
    EXPECT_EQ(t.at(40, 50)[0], 255);
    EXPECT_EQ(t.at(40, 50)[1], 0) << "the icon's colour, not the style's yellow";
    EXPECT_EQ(t.at(40, 50)[3], 255);
    EXPECT_EQ(t.at(55, 50)[3], 0) << "the transparent half";
    EXPECT_EQ(t.at(40, 40)[3], 0) << "above the icon";
    // A large icon drawn small is averaged, not sampled: a 64 x 64 checkerboard of black and
    // white texels at 8 px is an even grey.
    ImageRgba8 checker{64, 64, std::vector<uint8_t>(64 * 64 * 4, 255)};
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            if ((x + y) % 2) std::fill_n(&checker.pixels[(size_t(y) * 64 + x) * 4], 3, uint8_t(0));
    s.iconSizePx = 8.0;
    const DrapeItem small{&f, &s, &checker};
    Tile g;
    ASSERT_TRUE(rasterizeDrapeTile({&small, 1}, {.extent = kUnitExtent, .size = kSize}, g.rgba));
    for (int y = 47; y < 53; ++y)
        for (int x = 47; x < 53; ++x) EXPECT_NEAR(g.at(x, y)[0], 128, 12) << x << ", " << y;
}

// --- the antimeridian and the poles -----------------------------------------------------------

TEST(DrapeRasterWrap, AnUnwrappedPolygonPaintsTheTilesOnBothSidesOfTheSeam) {
    // 179 .. 181 east, 0 .. 1 north: a degree on each side, 10 x 10 px on these tiles.
    const Feature f = feature(GeometryKind::Polygons, {{{179, 0, 0}, {181, 0, 0}, {181, 1, 0}, {179, 1, 0}}});
    const Tile east = draw(f, fillStyle(), GeoExtent{-180, -5, -170, 5});
    const Tile west = draw(f, fillStyle(), GeoExtent{170, -5, 180, 5});
    EXPECT_NEAR(east.alphaSum(), 100.0, 0.5);
    EXPECT_NEAR(west.alphaSum(), 100.0, 0.5);
    EXPECT_EQ(east.at(5, 45)[3], 255);   // its west end, at -180
    EXPECT_EQ(east.at(15, 45)[3], 0);
    EXPECT_EQ(west.at(95, 45)[3], 255);  // its east end, at 180
    EXPECT_EQ(west.at(85, 45)[3], 0);
    EXPECT_FALSE(draw(f, fillStyle(), GeoExtent{0, -5, 10, 5}).painted);
    // A line across, too.
    const Feature line = feature(GeometryKind::Lines, {{{178, 0.5, 0}, {182, 0.5, 0}}});
    EXPECT_TRUE(draw(line, lineStyle(2.0), GeoExtent{-180, -5, -170, 5}).painted);
    EXPECT_TRUE(draw(line, lineStyle(2.0), GeoExtent{170, -5, 180, 5}).painted);
}

TEST(DrapeRasterWrap, ASouthPoleRingFillsDownToThePoleWithoutAnOutlineThereOrAlongTheSeam) {
    // Antarctica-like: the coast at -60, -180 .. 180 as the reader unwraps it, -1: around the
    // South Pole.
    std::vector<glm::dvec3> coast;
    for (int lon = -180; lon <= 180; ++lon) coast.push_back({double(lon), -60.0 + 2.0 * std::sin(lon * 0.1), 0.0});
    const Feature f = feature(GeometryKind::Polygons, {coast}, {0}, {-1});
    FeatureStyle s = fillStyle({0, 0, 1}, 1.0);
    s.outline = true;
    s.color = {1, 0, 0};
    s.widthPx = 2.0;
    for (const GeoExtent& e : {GeoExtent{0, -90, 90, 0}, GeoExtent{90, -90, 180, 0}, GeoExtent{-180, -90, -90, 0}}) {
        SCOPED_TRACE(testing::Message() << e.west << " .. " << e.east);
        const Tile t = draw(f, s, e, 90);   // a pixel a degree
        for (int x = 0; x < 90; ++x) {
            const uint8_t* p = t.at(x, 89);
            EXPECT_EQ(p[3], 255) << x;   // opaque at the pole's row
            EXPECT_EQ(p[0], 0) << x;     // and no outline there
        }
        for (int y = 65; y < 90; ++y) {   // south of the coast: pure fill, on the 180 seam too
            EXPECT_EQ(t.at(0, y)[0], 0) << y;
            EXPECT_EQ(t.at(89, y)[0], 0) << y;
            EXPECT_EQ(t.at(45, y)[3], 255) << y;
        }
        bool coastline = false;
        for (int y = 55; y < 65; ++y) coastline = coastline || t.at(45, y)[0] == 255;
        EXPECT_TRUE(coastline);
        EXPECT_EQ(t.at(45, 20)[3], 0);   // north of the coast: nothing
    }
    EXPECT_FALSE(draw(f, s, GeoExtent{0, 0, 90, 90}, 90).painted);
}

// --- order, bad input, cost -----------------------------------------------------------------

TEST(DrapeRaster, ItemsCompositeInOrderEachOverTheOnesBefore) {
    const Feature a = feature(GeometryKind::Polygons, {box(10, 10, 60, 60)});
    const Feature b = feature(GeometryKind::Polygons, {box(40, 40, 90, 90)});
    const FeatureStyle red = fillStyle({1, 0, 0}, 1.0), halfBlue = fillStyle({0, 0, 1}, 0.5);
    const Tile t = draw({{&a, &red}, {&b, &halfBlue}});
    const uint8_t* p = t.at(50, 50);
    EXPECT_NEAR(p[0], 128, 1);   // half blue over opaque red
    EXPECT_NEAR(p[2], 128, 1);
    EXPECT_EQ(p[3], 255);
    const uint8_t* q = t.at(80, 80);   // half blue over nothing: straight alpha keeps the colour
    EXPECT_EQ(q[2], 255);
    EXPECT_NEAR(q[3], 128, 1);
    const Tile reversed = draw({{&b, &halfBlue}, {&a, &red}});
    EXPECT_EQ(reversed.at(50, 50)[0], 255);   // opaque red over it
    EXPECT_EQ(reversed.at(50, 50)[2], 0);
    EXPECT_EQ(t.stats.featuresPainted, 2u);
}

TEST(DrapeRaster, NothingToPaintReturnsFalseAndAClearTile) {
    const Tile empty = draw(std::vector<DrapeItem>{});
    EXPECT_FALSE(empty.painted);
    ASSERT_EQ(empty.rgba.size(), size_t(kSize * kSize * 4));
    EXPECT_EQ(empty.maxAlpha(), 0);
    for (uint8_t v : empty.rgba) ASSERT_EQ(v, 0);
    const Feature f = feature(GeometryKind::Polygons, {box(10, 10, 60, 60)});
    FeatureStyle hidden = fillStyle();
    hidden.visible = false;
    EXPECT_FALSE(draw({{&f, &hidden}, {&f, nullptr}, {nullptr, &hidden}}).painted);
    std::vector<uint8_t> rgba(7, 1);
    EXPECT_FALSE(rasterizeDrapeTile({}, {.extent = kUnitExtent, .size = 0}, rgba));
    EXPECT_TRUE(rgba.empty());
    EXPECT_FALSE(rasterizeDrapeTile({}, {.extent = GeoExtent{10, 0, 10, 5}, .size = 64}, rgba));
    EXPECT_TRUE(rgba.empty());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<DrapeItem> items{{&f, &hidden}};
    EXPECT_FALSE(rasterizeDrapeTile(items, {.extent = GeoExtent{nan, 0, 10, 5}, .size = 64}, rgba));
    EXPECT_FALSE(rasterizeDrapeTile(items, {.extent = kUnitExtent, .size = kMaxDrapeTileSize + 1}, rgba));
    EXPECT_TRUE(rgba.empty());
}

TEST(DrapeRaster, NonFiniteVerticesAreSkipped) {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    std::vector<glm::dvec3> ring = box(10, 10, 50, 50);
    ring.insert(ring.begin() + 2, {nan, 30, 0});
    ring.insert(ring.begin() + 4, {20, inf, 0});
    const Feature polygon = feature(GeometryKind::Polygons, {ring, {{nan, nan, 0}, {1, nan, 0}}}, {0, 1});
    FeatureStyle s = fillStyle();
    s.outline = true;
    const Tile t = draw(polygon, s);
    EXPECT_TRUE(t.painted);
    s.outline = false;
    EXPECT_NEAR(draw(polygon, s).alphaSum(), 1600, 0.005 * 1600);
    const Feature line = feature(GeometryKind::Lines, {{px(10, 10), {nan, 5, 0}, px(90, 10), {-inf, inf, 0}}, {{nan, nan, 0}}});
    EXPECT_TRUE(draw(line, lineStyle(2.0)).painted);
    const Feature points = feature(GeometryKind::Points, {{{nan, 0, 0}}, {px(50, 50)}});
    EXPECT_TRUE(draw(points, lineStyle(2.0)).painted);
    // Indices past the coordinates or the parts paint what they can and nothing else.
    Feature broken = feature(GeometryKind::Polygons, {box(10, 10, 50, 50)});
    broken.parts.push_back(99);
    broken.polygons.push_back(7);
    broken.containsPole.clear();
    EXPECT_NEAR(draw(broken, fillStyle()).alphaSum(), 1600, 0.005 * 1600);
    FeatureStyle badStyle = lineStyle(nan, nan);
    badStyle.fillOpacity = nan;
    EXPECT_FALSE(draw(polygon, badStyle).painted);
}

TEST(DrapeRasterLines, ADashedLineIsOnAndOffAlongItsLengthAndJoinsAcrossTiles) {
    // From x = 10 in this tile to x = 190 in the next one east, 2 px wide, dashes of 6 on, 4 off:
    // a column is painted where (x - 10) mod 10 < 6, whichever tile it is in.
    const Feature line = feature(GeometryKind::Lines, {{px(10, 50), px(190, 50)}});
    FeatureStyle s = lineStyle(2.0);
    s.dashPx = {6.0, 4.0};
    const Tile west = draw(line, s);
    const Tile east = draw(line, s, GeoExtent{100.0, -50.0, 200.0, 50.0});
    const FeatureStyle solid = lineStyle(2.0);
    EXPECT_NEAR(west.alphaSum(), 0.6 * draw(line, solid).alphaSum(), 0.08 * draw(line, solid).alphaSum());
    for (int g = 12; g < 188; ++g) {
        const double phase = std::fmod(g + 0.5 - 10.0, 10.0);
        if (phase < 1.5 || (phase > 4.5 && phase < 7.5) || phase > 8.5) continue;   // near a dash's end: round caps
        const Tile& t = g < 100 ? west : east;
        const double column = t.columnSum(g % 100);
        if (phase < 6.0) EXPECT_NEAR(column, 2.0, 0.1) << "column " << g << " is on";
        else EXPECT_NEAR(column, 0.0, 0.01) << "column " << g << " is off";
    }
}

TEST(DrapeRasterLines, ALargerSimplificationToleranceStrokesFewerSegmentsNearTheLine) {
    // A zigzag of 1.5 px amplitude every 3 px across the tile: at 0.5 px every bend is kept; at
    // 2 px the line is nearly straight, fewer segments, and no pixel strays more than 2 px.
    std::vector<glm::dvec3> zigzag;
    for (int i = 0; i <= 33; ++i) zigzag.push_back(px(1.0 + i * 1.5, 25.0 + ((i % 2) ? 1.5 : 0.0)));
    const Feature line = feature(GeometryKind::Lines, {zigzag});
    const FeatureStyle s = lineStyle(1.0);
    const auto drawAt = [&](double tolerance) {
        Tile t;
        const DrapeItem item{&line, &s};
        t.painted = rasterizeDrapeTile({&item, 1}, {.extent = kUnitExtent, .size = kSize, .simplifyPx = tolerance}, t.rgba, &t.stats);
        return t;
    };
    const Tile exact = drawAt(0.5), simple = drawAt(2.0);
    ASSERT_TRUE(exact.painted && simple.painted);
    EXPECT_EQ(exact.stats.segments, 33u);
    EXPECT_LT(simple.stats.segments, 8u);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            EXPECT_TRUE(simple.alpha(x, y) == 0.0 || (y >= 22 && y <= 28)) << x << ", " << y;
}

TEST(DrapeRaster, ATwoMillionVertexRingRasterizesInBoundedTime) {
    // A wiggly circle of radius 40 px: far denser than the tile shows, thinned before filling.
    constexpr int kVertices = 2'000'000;
    std::vector<glm::dvec3> ring;
    ring.reserve(kVertices);
    for (int i = 0; i < kVertices; ++i) {
        const double a = 2.0 * std::numbers::pi * i / kVertices;
        const double r = 40.0 + 0.3 * std::sin(i * 0.37);
        ring.push_back(px(50 + r * std::cos(a), 50 + r * std::sin(a)));
    }
    const Feature f = feature(GeometryKind::Polygons, {ring});
    FeatureStyle s = fillStyle();
    for (bool outline : {false, true}) {
        s.outline = outline;
        const auto start = std::chrono::steady_clock::now();
        const Tile t = draw(f, s);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        std::printf("[          ] %d-vertex ring%s: %.1f ms, %zu segments\n", kVertices, outline ? " and its outline" : "", ms,
                    t.stats.segments);
        ASSERT_TRUE(t.painted);
        EXPECT_LT(t.stats.segments, size_t(kVertices) / 100);   // thinned to what the tile shows
        // The fill's area: the wiggle (0.3 px) averages out, the thinning moves edges by < 0.5 px
        // on a 250 px perimeter: 3% is well above both.
        if (!outline) {
            EXPECT_NEAR(t.alphaSum(), std::numbers::pi * 1600, 0.03 * std::numbers::pi * 1600);
        }
    }
}

}  // namespace
}  // namespace orbis::vector
