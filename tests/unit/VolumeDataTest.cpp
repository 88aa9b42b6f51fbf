// What the volume renderer prepares on the CPU: axis lookups, the min/max brick grid and the
// transfer function.
#include "layers/volume/VolumeData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

namespace orbis::layers {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// Worst |lookup - exact| in voxels over dense coordinates of an axis.
double worstVoxelError(const std::vector<double>& c, size_t tableSize) {
    const AxisLookup a = AxisLookup::build(c, tableSize);
    double worst = 0.0;
    for (int s = 0; s <= 10000; ++s) {
        const double x = c.front() + (c.back() - c.front()) * s / 10000.0;
        worst = std::max(worst, std::abs(a.lookup(x) - a.exact(c, x)) * double(c.size()));
    }
    return worst;
}

VolumeField fieldOf(size_t nx, size_t ny, size_t nz) {
    VolumeField f;
    for (size_t i = 0; i < nx; ++i) f.lonDeg.push_back(double(i));
    for (size_t j = 0; j < ny; ++j) f.latDeg.push_back(double(j));
    for (size_t k = 0; k < nz; ++k) f.heightM.push_back(double(k) * 100.0);
    f.values.assign(nx * ny * nz, 0.0f);
    return f;
}

}  // namespace

TEST(AxisLookup, UniformAxesAreExactAndSamplesSitAtTexelCentres) {
    const std::vector<double> c{-180, -90, 0, 90};
    const AxisLookup a = AxisLookup::build(c);
    EXPECT_TRUE(a.uniform);
    EXPECT_TRUE(a.table.empty());
    for (size_t i = 0; i < c.size(); ++i) EXPECT_DOUBLE_EQ(a.lookup(c[i]), (double(i) + 0.5) / 4.0);
    EXPECT_DOUBLE_EQ(a.lookup(-135), 1.0 / 4.0);
    EXPECT_DOUBLE_EQ(a.lookup(-1000), 0.5 / 4.0);   // clamped to the first sample
    EXPECT_DOUBLE_EQ(a.lookup(1000), 3.5 / 4.0);
}

TEST(AxisLookup, IrregularAxesGoThroughATableWithSmallError) {
    // Gaussian-like latitudes (ECHAM5's T63 grid is within 0.01 deg of uniform) and pressure
    // levels turned into heights (spacing grows from 700 m to 5 km).
    std::vector<double> gauss;
    for (int j = 0; j < 96; ++j) gauss.push_back(-88.572 + j * (2 * 88.572 / 95) + 0.01 * std::sin(j * 0.3));
    std::vector<double> heights;
    for (double p : {100000., 92500., 85000., 77500., 70000., 60000., 50000., 40000., 30000., 25000., 20000., 15000.,
                     10000., 7000., 5000., 3000., 1000.})
        heights.push_back(standardAtmosphereHeight(p));
    EXPECT_FALSE(AxisLookup::build(gauss).uniform);
    EXPECT_FALSE(AxisLookup::build(heights).uniform);
    const double gauss256 = worstVoxelError(gauss, 256), heights256 = worstVoxelError(heights, 256);
    const double heights1024 = worstVoxelError(heights, 1024);
    std::printf("axis lookup, worst error in voxels: Gaussian lat (256) %.5f, heights (256) %.4f, (1024) %.5f\n",
                gauss256, heights256, heights1024);
    EXPECT_LT(gauss256, 0.01);
    EXPECT_LT(heights256, 0.05);
    EXPECT_LT(heights1024, heights256 / 3.0);
    // Samples still land on texel centres (to the table's resolution).
    const AxisLookup a = AxisLookup::build(heights, 1024);
    for (size_t k = 0; k < heights.size(); ++k)
        EXPECT_NEAR(a.lookup(heights[k]), (double(k) + 0.5) / double(heights.size()), 0.02 / double(heights.size()));
}

TEST(BrickGrid, MinMaxCoverEachBrickAndItsFilterMargin) {
    VolumeField f = fieldOf(20, 10, 9);
    for (size_t k = 0; k < 9; ++k)
        for (size_t j = 0; j < 10; ++j)
            for (size_t i = 0; i < 20; ++i) f.values[(k * 10 + j) * 20 + i] = float(i + 100 * j + 10000 * k);
    // A hole of no data filling the bricks (1, 0, 0) and (1, 1, 0) but not their margins.
    for (size_t k = 0; k < 8; ++k)
        for (size_t j = 0; j < 10; ++j)
            for (size_t i = 8; i < 16; ++i) f.values[(k * 10 + j) * 20 + i] = kNaN;
    const BrickGrid g = buildBrickGrid(f, 8);
    EXPECT_EQ(g.bx, 3u);
    EXPECT_EQ(g.by, 2u);
    EXPECT_EQ(g.bz, 2u);
    // Brick (0,0,0) covers voxels 0..8 in each axis (the margin included).
    EXPECT_EQ(g.at(0, 0, 0).first, 0.0f);
    // Its largest value is at (8, 8, 8): i = 8 is no data below k = 8 but valid at k = 8.
    EXPECT_EQ(g.at(0, 0, 0).second, float(8 + 100 * 8 + 10000 * 8));
    // The holed brick still sees its margin voxels (i = 16) and the k = 8 layer.
    EXPECT_EQ(g.at(1, 0, 0).first, 16.0f);
    EXPECT_EQ(g.at(2, 1, 1).second, float(19 + 100 * 9 + 10000 * 8));
    EXPECT_EQ(g.emptyBricks(), 0u);

    VolumeField empty = fieldOf(4, 4, 4);
    std::fill(empty.values.begin(), empty.values.end(), kNaN);
    const BrickGrid e = buildBrickGrid(empty, 2);
    EXPECT_EQ(e.emptyBricks(), e.minMax.size());
    EXPECT_GT(e.at(0, 0, 0).first, e.at(0, 0, 0).second);
}

TEST(BrickGrid, OccupancyFollowsTheTransferFunctionIsovaluesAndTime) {
    // Four bricks along x with value ranges [0,1], [1,2], [2,3] and no data.
    BrickGrid g;
    g.bx = 4, g.by = 1, g.bz = 1;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    g.minMax = {{0.0f, 1.0f}, {1.0f, 2.0f}, {2.0f, 3.0f}, {kInf, -kInf}};
    // Opacity only above 2.5 (table over 0..4): only brick 2 can show.
    TransferFunctionDesc tf;
    tf.rangeMin = 0.0, tf.rangeMax = 4.0;
    tf.opacity = {{0.0, 0.0}, {2.5, 0.0}, {3.0, 0.5}, {4.0, 0.5}};
    const auto table = buildTransferTable(tf);
    ASSERT_TRUE(table);
    EXPECT_EQ(brickOccupancy(g, *table, 0.0, 4.0, true, {}), std::vector<uint32_t>{0b0100u});
    // Without DVR only isovalues count: 1.5 lies in brick 1; 1.0 in bricks 0 and 1 (an isovalue
    // equal to a brick's end); 9 in none. The no-data brick never shows.
    EXPECT_EQ(brickOccupancy(g, *table, 0.0, 4.0, false, {1.5}), std::vector<uint32_t>{0b0010u});
    EXPECT_EQ(brickOccupancy(g, *table, 0.0, 4.0, false, {1.0}), std::vector<uint32_t>{0b0011u});
    EXPECT_EQ(brickOccupancy(g, *table, 0.0, 4.0, true, {1.0, 9.0}), std::vector<uint32_t>{0b0111u});
    // The same table spread over 0..2 instead: opacity above 1.25. Brick 2 (values 2..3, past
    // the end) reads the last entry (clamped); brick 1 reaches 2.
    EXPECT_EQ(brickOccupancy(g, *table, 0.0, 2.0, true, {}), std::vector<uint32_t>{0b0110u});
    // Time: the union over steps widens the ranges; brick 0 now reaches 2.6.
    BrickGrid later = g;
    later.minMax[0] = {2.6f, 2.6f};
    mergeBrickGrid(g, later);
    EXPECT_EQ(g.minMax[0], (std::pair<float, float>{0.0f, 2.6f}));
    EXPECT_EQ(brickOccupancy(g, *table, 0.0, 4.0, true, {}), std::vector<uint32_t>{0b0101u});
    // Bits past 32 bricks go to the next word.
    BrickGrid big;
    big.bx = 40, big.by = 1, big.bz = 1;
    big.minMax.assign(40, {3.5f, 3.5f});
    const auto bits = brickOccupancy(big, *table, 0.0, 4.0, true, {});
    ASSERT_EQ(bits.size(), 2u);
    EXPECT_EQ(bits[0], ~0u);
    EXPECT_EQ(bits[1], 0xffu);
}

TEST(TransferFunction, ColourMapEndsOpacityPointsAndErrors) {
    TransferFunctionDesc d;
    d.colorMap = "greys";
    d.rangeMin = 200;
    d.rangeMax = 300;
    auto t = buildTransferTable(d, 256);
    ASSERT_TRUE(t.ok()) << t.message();
    ASSERT_EQ(t->size(), 256u);
    EXPECT_FLOAT_EQ((*t)[0][0], 0.0f);
    EXPECT_FLOAT_EQ((*t)[255][1], 1.0f);
    // Interpolated in linear light: the middle entry is halfway in linear units.
    EXPECT_NEAR((*t)[128][2], 128.0 / 255.0, 1e-6);
    EXPECT_FLOAT_EQ((*t)[0][3], 0.0f);   // default ramp
    EXPECT_FLOAT_EQ((*t)[255][3], 1.0f);

    d.colorMap = "viridis";
    d.opacity = {{250, 0.0}, {260, 0.8}, {270, 0.0}};
    d.opacityScale = 0.5;
    t = buildTransferTable(d, 101);   // one entry per data unit
    ASSERT_TRUE(t.ok()) << t.message();
    EXPECT_FLOAT_EQ((*t)[0][3], 0.0f);
    EXPECT_NEAR((*t)[55][3], 0.2, 1e-6);   // 255: halfway up, scaled by 0.5
    EXPECT_NEAR((*t)[60][3], 0.4, 1e-6);
    EXPECT_FLOAT_EQ((*t)[100][3], 0.0f);
    // viridis: dark purple to yellow, in linear light.
    EXPECT_LT((*t)[0][1], 0.01f);
    EXPECT_GT((*t)[100][0], 0.9f);
    EXPECT_GT((*t)[100][1], 0.75f);

    d.colorMap = "rainbow-ish";
    EXPECT_NE(buildTransferTable(d).message().find("unknown colour map \"rainbow-ish\" (known: viridis"),
              std::string::npos);
    d.colorMap = "magma";
    d.rangeMin = d.rangeMax = 5;
    EXPECT_NE(buildTransferTable(d).message().find("low < high"), std::string::npos);
    d.rangeMax = 6;
    d.opacity = {{5, 1.5}};
    EXPECT_FALSE(buildTransferTable(d).ok());
    for (const auto& name : colorMapNames()) EXPECT_TRUE(hasColorMap(name)) << name;
}

/// Front-to-back compositing of a segment `length` long (normalised units) along which the
/// table position runs linearly from `from` to `to`, in `n` point samples (the brute force the
/// pre-integrated table stands for): premultiplied colour and opacity.
std::array<double, 4> bruteForceSegment(const std::vector<std::array<float, 4>>& table, double from, double to,
                                        double length, double opacityPerUnit, int n) {
    std::array<double, 4> acc{0.0, 0.0, 0.0, 0.0};
    for (int k = 0; k < n; ++k) {
        const double x = from + (to - from) * (k + 0.5) / n;
        const size_t i0 = std::min(size_t(x), table.size() - 1), i1 = std::min(i0 + 1, table.size() - 1);
        const double w = x - double(i0);
        const auto at = [&](size_t c) { return double(table[i0][c]) + (double(table[i1][c]) - double(table[i0][c])) * w; };
        const double l0 = std::log2(1.0 - std::min(double(table[i0][3]), 0.9999));
        const double l1 = std::log2(1.0 - std::min(double(table[i1][3]), 0.9999));
        const double alpha = 1.0 - std::exp2((l0 + (l1 - l0) * w) * length / n * opacityPerUnit);
        for (size_t c = 0; c < 3; ++c) acc[c] += (1.0 - acc[3]) * alpha * at(c);
        acc[3] += (1.0 - acc[3]) * alpha;
    }
    return acc;
}

TEST(TransferFunction, PreIntegratedSegmentsMatchABruteForceMarch) {
    // The VTK peer's opacity curve and a narrow peak: segments across the peak, along it, back
    // to front, short and long, against 4096 point samples of the same segment.
    TransferFunctionDesc d;
    d.colorMap = "coolwarm";
    d.rangeMin = 0.0, d.rangeMax = 1.0;
    d.opacity = {{0.0, 0.6}, {0.25, 0.0}, {0.5, 0.05}, {0.62, 0.0}, {0.64, 0.95}, {0.66, 0.0}, {0.75, 0.8}, {1.0, 1.0}};
    const auto table = buildTransferTable(d, 256).value();
    const double step = std::sqrt(3.0) / 25.0, perUnit = 4.0;
    const auto pre = buildPreIntegratedTable(table, step, perUnit);
    ASSERT_EQ(pre.size(), 256u * 256u);
    const size_t pairs[][2] = {{10, 200}, {200, 10}, {150, 170}, {170, 150}, {160, 164}, {0, 255}, {255, 0}, {90, 91}, {40, 40}};
    double worst = 0.0, worstAlpha = 0.0;
    for (const auto& p : pairs) {
        const auto& e = pre[p[1] * 256 + p[0]];
        for (double length : {step, 0.5 * step, 2.0 * step}) {
            const double alpha = 1.0 - std::exp2(double(e[3]) * length * perUnit);
            const auto ref = bruteForceSegment(table, double(p[0]), double(p[1]), length, perUnit, 4096);
            worstAlpha = std::max(worstAlpha, std::abs(alpha - ref[3]));
            // The colour is exact for the table's own length; for others the self-attenuation
            // inside the segment is that of `step` (the march keeps its steps near it).
            if (length == step)
                for (size_t c = 0; c < 3; ++c) worst = std::max(worst, std::abs(alpha * double(e[c]) - ref[c]));
        }
    }
    EXPECT_LT(worstAlpha, 2e-5);   // the opacity: exact for any length (float rounding only)
    EXPECT_LT(worst, 2e-3);        // premultiplied colour, 0..1 (half a level of 8 bits)
    // A segment that stays at one value is that entry of the plain table.
    for (size_t c = 0; c < 4; ++c) EXPECT_NEAR(pre[40 * 256 + 40][c], c < 3 ? table[40][c] : std::log2(1.0 - table[40][3]), 1e-6);
}

TEST(TransferFunction, OpacityCorrectionDoesNotDependOnTheStepCount) {
    const double a = 0.3;
    EXPECT_DOUBLE_EQ(correctOpacity(a, 1.0, 1.0), a);
    const double half = correctOpacity(a, 0.5, 1.0);
    EXPECT_NEAR(1.0 - (1.0 - half) * (1.0 - half), a, 1e-12);   // two half steps = one step
    const double tenth = correctOpacity(a, 0.1, 1.0);
    EXPECT_NEAR(1.0 - std::pow(1.0 - tenth, 10.0), a, 1e-12);
    EXPECT_EQ(correctOpacity(1.0, 0.01, 1.0), 1.0);
    EXPECT_EQ(correctOpacity(0.0, 7.0, 1.0), 0.0);
}

}  // namespace orbis::layers
