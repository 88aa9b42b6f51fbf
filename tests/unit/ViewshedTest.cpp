// Viewsheds on the CPU (globe/Viewshed.h): the ring propagation against GDAL's own viewshed on
// the same grid (cell for cell), against the exact sight lines, and on grounds with known
// answers: a flat Earth sees everything, the bare curved Earth hides what lies past the horizon
// (sqrt(h D / cc)), a wall hides what is behind it; grids at a pole and across the
// antimeridian; bad observers, radii and grids refused with their reason.
#include "globe/Viewshed.h"
#include "globe/ViewshedGdal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace orbis::globe {
namespace {

/// Rolling hills with some noise: a grid of `side` cells of 30 m.
ViewshedGrid hills(int radiusCells, unsigned seed = 7) {
    ViewshedGrid g;
    g.centre = {8.5, 46.5};
    g.cellM = 30.0;
    g.radiusCells = radiusCells;
    const int side = g.side();
    g.heights.resize(size_t(side) * size_t(side));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(-3.0f, 3.0f);
    for (int r = 0; r < side; ++r)
        for (int c = 0; c < side; ++c)
            g.heights[size_t(r) * size_t(side) + size_t(c)] =
                1000.0f + 120.0f * std::sin(float(c) * 0.05f) * std::cos(float(r) * 0.037f) + 60.0f * std::sin(float(c + 2 * r) * 0.11f) + noise(rng);
    return g;
}

ViewshedGrid flat(int radiusCells, double cellM) {
    ViewshedGrid g;
    g.centre = {0.0, 0.0};
    g.cellM = cellM;
    g.radiusCells = radiusCells;
    g.heights.assign(size_t(g.side()) * size_t(g.side()), 250.0f);
    return g;
}

/// Agreement over the rows north of the observer and over the rows south of it, leaving out the
/// eight cells around the observer.
std::pair<ViewshedAgreement, ViewshedAgreement> halves(const Viewshed& a, const Viewshed& b, int observerCol, int observerRow) {
    Viewshed an = a, as = a;
    for (int r = 0; r < a.side; ++r)
        for (int c = 0; c < a.side; ++c) {
            const size_t i = size_t(r) * size_t(a.side) + size_t(c);
            (r <= observerRow ? as : an).cells[i] = Sight::OutOfRange;
            if (std::abs(r - observerRow) <= 1 && std::abs(c - observerCol) <= 1) an.cells[i] = as.cells[i] = Sight::OutOfRange;
        }
    return {compareViewsheds(an, b), compareViewsheds(as, b)};
}

TEST(Viewshed, TheRingsAgreeWithGdalsViewshedCellForCell) {
    // GDAL 3.6 (Debian 12's) extrapolates the observer's column southwards with a negative
    // distance (CalcHeightLine(nY - iLine, ...) where later versions take its absolute value),
    // which raises the horizon there: cells south of the observer that depend on that column come
    // out hidden where the model sees them. And 3.6 compares the eight cells around the observer
    // with the observer's ground (later versions: with their own, so that they are always seen).
    // Elsewhere north of the observer the two agree cell for cell.
    const ViewshedGrid g = hills(120);
    for (const auto& o : {ViewshedOptions{.observerCol = 120, .observerRow = 120, .observerHeight = 10.0},
                          ViewshedOptions{.observerCol = 40, .observerRow = 200, .observerHeight = 2.0, .targetHeight = 5.0},
                          ViewshedOptions{.observerCol = 150, .observerRow = 90, .observerHeight = 30.0, .radiusM = 2500.0, .curvature = 0.0}}) {
        auto ours = viewshedRings(g, o);
        ASSERT_TRUE(ours) << ours.message();
        auto gdal = viewshedGdal(g, o);
        ASSERT_TRUE(gdal) << gdal.message();
        const ViewshedAgreement a = compareViewsheds(*ours, *gdal);
        const auto [north, south] = halves(*ours, *gdal, o.observerCol, o.observerRow);
        EXPECT_GT(north.compared, 5000u);
        EXPECT_EQ(north.differ, 0u) << "observer " << o.observerCol << "," << o.observerRow;
        EXPECT_EQ(south.seenOnlyByB, 0u) << "GDAL 3.6's south column only ever hides more";
        EXPECT_GT(a.percent(), 99.5) << a.differ << " of " << a.compared;
        EXPECT_GT(ours->count(Sight::Hidden), a.compared / 10) << "the hills hide some of the ground";
        EXPECT_GT(ours->count(Sight::Visible), a.compared / 40);
        EXPECT_EQ(ours->count(Sight::OutOfRange), gdal->count(Sight::OutOfRange));
        EXPECT_EQ(ours->at(o.observerCol, o.observerRow + 1), Sight::Visible) << "the cell next to the observer";
    }
}

TEST(Viewshed, TheRingsAreCloseToTheExactSightLines) {
    const ViewshedGrid g = hills(100, 3);
    const ViewshedOptions o{.observerCol = 100, .observerRow = 100, .observerHeight = 5.0};
    auto rings = viewshedRings(g, o);
    auto exact = viewshedSightlines(g, o);
    ASSERT_TRUE(rings && exact);
    const ViewshedAgreement a = compareViewsheds(*rings, *exact);
    EXPECT_GT(a.percent(), 93.0) << a.differ << " of " << a.compared;
    EXPECT_LT(a.percent(), 100.0) << "the propagation interpolates horizons: it is not exact";
}

TEST(Viewshed, AFlatEarthSeesEverythingAndACurvedOneHidesWhatIsPastTheHorizon) {
    const ViewshedGrid g = flat(400, 20.0);   // 8 km around
    ViewshedOptions o{.observerCol = 400, .observerRow = 400, .observerHeight = 2.0, .curvature = 0.0};
    for (auto* method : {&viewshedRings}) {
        auto v = (*method)(g, o);
        ASSERT_TRUE(v);
        EXPECT_EQ(v->count(Sight::Hidden), 0u);
    }
    auto exactFlat = viewshedSightlines(g, o);
    ASSERT_TRUE(exactFlat);
    EXPECT_EQ(exactFlat->count(Sight::Hidden), 0u);

    o.curvature = 0.85714;
    const double horizon = std::sqrt(o.observerHeight * kViewshedEarthDiameter / o.curvature);   // sqrt(2 R h), R = D / 2cc
    EXPECT_NEAR(horizon, 5455.0, 5.0);
    for (bool exactLines : {false, true}) {
        auto v = exactLines ? viewshedSightlines(g, o) : viewshedRings(g, o);
        ASSERT_TRUE(v);
        size_t nearHidden = 0, farSeen = 0, near = 0, far = 0;
        for (int r = 0; r < g.side(); ++r)
            for (int c = 0; c < g.side(); ++c) {
                const double d = std::hypot(g.east(c), g.north(r));
                if (d < 0.95 * horizon) near++, nearHidden += v->at(c, r) == Sight::Hidden;
                if (d > 1.05 * horizon && d < 8000.0) far++, farSeen += v->at(c, r) == Sight::Visible;
            }
        EXPECT_EQ(nearHidden, 0u) << (exactLines ? "exact" : "rings") << ": of " << near;
        EXPECT_EQ(farSeen, 0u) << (exactLines ? "exact" : "rings") << ": of " << far;
    }
}

TEST(Viewshed, AWallHidesTheGroundBehindItButNotATallTarget) {
    ViewshedGrid g = flat(100, 10.0);
    for (int r = 0; r < g.side(); ++r) g.heights[size_t(r) * size_t(g.side()) + 130] = 290.0f;   // 40 m wall 300 m east
    ViewshedOptions o{.observerCol = 100, .observerRow = 100, .observerHeight = 2.0, .curvature = 0.0};
    auto v = viewshedRings(g, o);
    ASSERT_TRUE(v);
    EXPECT_EQ(v->at(130, 100), Sight::Visible) << "the wall's face";
    EXPECT_EQ(v->at(160, 100), Sight::Hidden);
    EXPECT_EQ(v->at(200, 100), Sight::Hidden);
    EXPECT_EQ(v->at(50, 100), Sight::Visible) << "the other way";
    // Masts of 100 m: the line over the wall's top (38 m above the eye at 300 m) is 50.7 m above
    // the eye 400 m out and 126.7 m 1 km out.
    o.targetHeight = 100.0;
    auto tall = viewshedRings(g, o);
    ASSERT_TRUE(tall);
    EXPECT_EQ(tall->at(140, 100), Sight::Visible);
    EXPECT_EQ(tall->at(200, 100), Sight::Hidden);
}

TEST(Viewshed, CellsWithoutDataAreMarkedAndDoNotBlock) {
    ViewshedGrid g = flat(50, 10.0);
    for (int c = 60; c < 70; ++c) g.heights[size_t(50) * size_t(g.side()) + size_t(c)] = NAN;
    auto v = viewshedRings(g, {.observerCol = 50, .observerRow = 50, .observerHeight = 2.0});
    ASSERT_TRUE(v);
    EXPECT_EQ(v->at(65, 50), Sight::NoData);
    EXPECT_EQ(v->at(80, 50), Sight::Visible);
    auto gdal = viewshedGdal(g, {.observerCol = 50, .observerRow = 50});
    ASSERT_FALSE(gdal);
    EXPECT_NE(gdal.message().find("no-data"), std::string::npos) << gdal.message();
}

TEST(Viewshed, GridsAtAPoleAndAcrossTheAntimeridianAreSquareOnTheGround) {
    // The ground rises 1 m per metre east of the grid's centre plane: sampled at a pole and on
    // the antimeridian it must still read east 1:1 (the plane, not lon/lat).
    for (const LonLat centre : {LonLat{0.0, 90.0}, LonLat{179.999, -16.0}, LonLat{-45.0, -89.9995}}) {
        ViewshedGrid probe;
        probe.centre = centre;
        probe.cellM = 5.0;
        probe.radiusCells = 20;
        HeightAt ground = [&](double lon, double lat) -> std::optional<double> {
            const auto cell = probe.cellOf(lon, lat);
            if (!cell) return std::nullopt;
            return double(cell->first);
        };
        auto g = sampleViewshedGrid(ground, centre, 100.0, 5.0);
        ASSERT_TRUE(g) << g.message();
        ASSERT_EQ(g->side(), 41);
        for (int r = 0; r < 41; r += 8)
            for (int c = 0; c < 41; c += 4) EXPECT_EQ(g->at(c, r), float(c)) << centre.x << "," << centre.y << " cell " << c << "," << r;
        const LonLat corner = g->lonLatOf(40, 0);
        EXPECT_TRUE(std::abs(corner.y) <= 90.0 && std::abs(corner.x) <= 180.0);
        EXPECT_NEAR(geodesicBetween(g->lonLatOf(20, 20), corner).metres, std::hypot(100.0, 100.0), 0.01);
    }
}

TEST(Viewshed, ACoarseViewshedSpreadBackOntoTheFineGrid) {
    const ViewshedGrid g = hills(64);
    const ViewshedGrid c = coarsenViewshedGrid(g, 4);
    EXPECT_EQ(c.radiusCells, 16);
    EXPECT_DOUBLE_EQ(c.cellM, 120.0);
    EXPECT_EQ(c.at(16, 16), g.at(64, 64));
    EXPECT_EQ(c.at(17, 15), g.at(68, 60));
    auto coarse = viewshedRings(c, {.observerCol = 16, .observerRow = 16, .observerHeight = 10.0});
    auto fine = viewshedRings(g, {.observerCol = 64, .observerRow = 64, .observerHeight = 10.0});
    ASSERT_TRUE(coarse && fine);
    const Viewshed back = refineViewshed(*coarse, 4, g.side());
    EXPECT_EQ(back.at(68, 60), coarse->at(17, 15));
    EXPECT_GT(compareViewsheds(back, *fine).percent(), 70.0);
}

TEST(Viewshed, BadInputsAreRefusedWithTheirReason) {
    const ViewshedGrid g = hills(10);
    const struct { ViewshedOptions o; const char* says; } cases[] = {
        {{.observerCol = 30, .observerRow = 5}, "outside the viewshed grid"},
        {{.observerCol = 5, .observerRow = 5, .observerHeight = NAN}, "observer height"},
        {{.observerCol = 5, .observerRow = 5, .radiusM = -1.0}, "radius"},
        {{.observerCol = 5, .observerRow = 5, .curvature = 7.0}, "curvature"},
    };
    for (const auto& c : cases) {
        auto r = viewshedRings(g, c.o);
        ASSERT_FALSE(r) << c.says;
        EXPECT_NE(r.message().find(c.says), std::string::npos) << r.message();
    }
    ViewshedGrid hole = g;
    hole.heights[size_t(10) * size_t(hole.side()) + 10] = NAN;
    auto r = viewshedRings(hole, {.observerCol = 10, .observerRow = 10});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("no data under the observer"), std::string::npos) << r.message();

    HeightAt zero = [](double, double) -> std::optional<double> { return 0.0; };
    EXPECT_FALSE(sampleViewshedGrid(zero, {0.0, 95.0}, 100.0, 5.0));
    EXPECT_FALSE(sampleViewshedGrid(zero, {0.0, 0.0}, 1.0, 5.0));
    EXPECT_FALSE(sampleViewshedGrid(zero, {0.0, 0.0}, 100.0, 0.0));
    auto huge = sampleViewshedGrid(zero, {0.0, 0.0}, 100000.0, 1.0);
    ASSERT_FALSE(huge);
    EXPECT_NE(huge.message().find("larger cells"), std::string::npos) << huge.message();
}

}  // namespace
}  // namespace orbis::globe
