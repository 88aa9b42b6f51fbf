// The viewshed on the GPU (layers/analysis/ViewshedGpu.h), lavapipe with validation: the same
// cells as the CPU's rings in double and as GDAL's viewshed on the same grid, with the observer
// moved inside one uploaded grid (GDAL 3.6 within its known differences), a radius, cells without data, a flat Earth that sees
// everything, and bad options refused before anything is recorded.
#include "globe/Viewshed.h"
#include "globe/ViewshedGdal.h"
#include "layers/analysis/ViewshedGpu.h"
#include "tests/support/GpuTest.h"

#include <cmath>

namespace orbis::test {
namespace {

class ViewshedGpuTest : public GpuTest {};

globe::ViewshedGrid hills(int radiusCells) {
    globe::ViewshedGrid g;
    g.centre = {-70.0, -33.4};
    g.cellM = 25.0;
    g.radiusCells = radiusCells;
    const int side = g.side();
    g.heights.resize(size_t(side) * size_t(side));
    for (int r = 0; r < side; ++r)
        for (int c = 0; c < side; ++c)
            g.heights[size_t(r) * size_t(side) + size_t(c)] = 2500.0f + 150.0f * std::sin(float(c) * 0.045f) * std::cos(float(r) * 0.031f) +
                                                              40.0f * std::sin(float(3 * c - r) * 0.09f);
    return g;
}

TEST_F(ViewshedGpuTest, TheGpuSeesWhatTheCpuAndGdalSeeWhereverTheObserverStands) {
    const globe::ViewshedGrid g = hills(150);
    for (auto workgroup : {layers::ViewshedGpu::Workgroup::Auto, layers::ViewshedGpu::Workgroup::Wide}) {
        SCOPED_TRACE(workgroup == layers::ViewshedGpu::Workgroup::Wide ? "the wide workgroup (GPUs)" : "the device's choice");
        layers::ViewshedGpu gpu(device(), workgroup);
        ASSERT_TRUE(gpu.setGrid(g));
        for (const globe::ViewshedOptions o : {globe::ViewshedOptions{.observerCol = 150, .observerRow = 150, .observerHeight = 10.0},
                                               globe::ViewshedOptions{.observerCol = 20, .observerRow = 260, .observerHeight = 2.0, .targetHeight = 4.0},
                                               globe::ViewshedOptions{.observerCol = 200, .observerRow = 100, .observerHeight = 50.0, .radiusM = 3000.0}}) {
            layers::ViewshedTiming timing;
            auto onGpu = gpu.run(o, &timing);
            ASSERT_TRUE(onGpu) << onGpu.message();
            EXPECT_GT(timing.rings, 100);
            auto cpu = globe::viewshedRings(g, o);
            auto gdal = globe::viewshedGdal(g, o);
            ASSERT_TRUE(cpu && gdal);
            const auto withCpu = globe::compareViewsheds(*onGpu, *cpu), withGdal = globe::compareViewsheds(*onGpu, *gdal);
            EXPECT_GT(withCpu.compared, 20000u);
            // Float against double: a cell whose ground is within rounding of its horizon may go
            // either way; no more than one in ten thousand.
            EXPECT_LE(withCpu.differ, withCpu.compared / 10000) << o.observerCol << "," << o.observerRow;
            // GDAL 3.6 differs from the model next to the observer and in the column south of it
            // (tests/unit/ViewshedTest.cpp), and what depends on those cells: a percent at most.
            EXPECT_GT(withGdal.percent(), 99.0) << o.observerCol << "," << o.observerRow << ": " << withGdal.differ << " differ";
            EXPECT_EQ(onGpu->count(globe::Sight::OutOfRange), cpu->count(globe::Sight::OutOfRange));
            EXPECT_GT(onGpu->count(globe::Sight::Hidden), withCpu.compared / 10);
            EXPECT_EQ(onGpu->at(o.observerCol, o.observerRow), globe::Sight::Visible);
        }
    }
}

TEST_F(ViewshedGpuTest, CellsWithoutDataAndAFlatEarth) {
    globe::ViewshedGrid g;
    g.centre = {179.9, 64.0};
    g.cellM = 10.0;
    g.radiusCells = 60;
    g.heights.assign(size_t(g.side()) * size_t(g.side()), 12.0f);
    for (int c = 70; c < 80; ++c) g.heights[size_t(60) * size_t(g.side()) + size_t(c)] = NAN;
    layers::ViewshedGpu gpu(device());
    ASSERT_TRUE(gpu.setGrid(g));
    auto v = gpu.run({.observerCol = 60, .observerRow = 60, .observerHeight = 1.5, .curvature = 0.0});
    ASSERT_TRUE(v) << v.message();
    EXPECT_EQ(v->at(75, 60), globe::Sight::NoData);
    EXPECT_EQ(v->count(globe::Sight::NoData), 10u);
    EXPECT_EQ(v->count(globe::Sight::Hidden), 0u) << "a flat Earth hides nothing";
    EXPECT_EQ(v->count(globe::Sight::Visible), size_t(g.side()) * size_t(g.side()) - 10u);
}

TEST_F(ViewshedGpuTest, BadOptionsAreRefusedBeforeAnythingRuns) {
    layers::ViewshedGpu gpu(device());
    auto none = gpu.run({.observerCol = 1, .observerRow = 1});
    ASSERT_FALSE(none);
    EXPECT_NE(none.message().find("no grid"), std::string::npos) << none.message();
    ASSERT_TRUE(gpu.setGrid(hills(10)));
    auto outside = gpu.run({.observerCol = 21, .observerRow = 3});
    ASSERT_FALSE(outside);
    EXPECT_NE(outside.message().find("outside the viewshed grid"), std::string::npos) << outside.message();
    EXPECT_FALSE(gpu.run({.observerCol = 3, .observerRow = 3, .curvature = -1.0}));
    EXPECT_FALSE(gpu.setGrid(globe::ViewshedGrid{}));
}

}  // namespace
}  // namespace orbis::test
