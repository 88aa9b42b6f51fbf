// The point octree: every point lands in exactly one node, inside its node's cube; nodes hold
// at most their capacity (but the deepest); the result depends only on the seed; NaN positions
// are left out.
#include "globe/Ellipsoid.h"
#include "layers/points/PointOctree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace orbis::points {
namespace {

std::vector<PointRecord> cloudAt(double lon, double lat, double h, double size, size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.5 * size, 0.5 * size);
    const auto& ell = globe::Ellipsoid::wgs84();
    const glm::dvec3 o = ell.toEcef(lon, lat, h);
    const glm::dmat3 enu = ell.enuFrame(lon, lat);
    std::vector<PointRecord> pts(n);
    for (size_t i = 0; i < n; ++i) {
        pts[i].ecef = o + enu * glm::dvec3(u(rng), u(rng), 0.1 * u(rng));
        pts[i].id = i;
    }
    return pts;
}

TEST(PointOctree, EveryPointOnceInsideItsNode) {
    const auto pts = cloudAt(179.9999, 45.0, 8000.0, 2000.0, 100000, 7);
    PointOctree::Options o;
    o.capacity = 1000;
    const PointOctree tree = PointOctree::build(pts, o);
    ASSERT_EQ(tree.points(), pts.size());
    EXPECT_GT(tree.nodes().size(), 50u);
    std::set<uint32_t> seen;
    uint64_t total = 0;
    for (const OctreeNode& n : tree.nodes()) {
        EXPECT_GT(n.count, 0u);
        if (n.level < o.maxLevel) {
            EXPECT_LE(n.count, o.capacity);
        }
        total += n.count;
        uint64_t lastKey = 0;
        for (uint64_t i = n.first; i < n.first + n.count; ++i) {
            const uint32_t input = tree.order()[i];
            EXPECT_TRUE(seen.insert(input).second);
            const uint64_t key = pointKey(pts[input].id, o.seed);
            EXPECT_GE(key, lastKey);   // in key order
            lastKey = key;
            const glm::dvec3 d = glm::abs(pts[input].ecef - n.centre);
            EXPECT_LE(std::max({d.x, d.y, d.z}), n.halfSize * (1 + 1e-9) + 1e-6);
        }
        for (int32_t c : n.children)
            if (c >= 0) {
                const OctreeNode& child = tree.nodes()[size_t(c)];
                EXPECT_EQ(child.halfSize, 0.5 * n.halfSize);
                EXPECT_EQ(child.level, n.level + 1);
                EXPECT_EQ(tree.nodes()[size_t(child.parent)].first, n.first);
            }
    }
    EXPECT_EQ(total, pts.size());
    EXPECT_EQ(seen.size(), pts.size());
}

TEST(PointOctree, NodesAreUniformSubsamples) {
    // The root keeps `capacity` points spread over the whole cloud, not the first ones read:
    // each quadrant of the cloud gets about a quarter of them.
    auto pts = cloudAt(10.0, 46.0, 500.0, 1000.0, 40000, 3);
    std::sort(pts.begin(), pts.end(), [](const PointRecord& a, const PointRecord& b) { return a.ecef.x < b.ecef.x; });
    for (size_t i = 0; i < pts.size(); ++i) pts[i].id = i;   // file order: west to east
    const PointOctree tree = PointOctree::build(pts, {4000, 20, 1});
    const OctreeNode& root = tree.nodes()[0];
    ASSERT_EQ(root.count, 4000u);
    size_t low = 0;
    for (uint64_t i = root.first; i < root.first + root.count; ++i) low += tree.order()[i] < 20000 ? 1 : 0;
    EXPECT_NEAR(double(low) / root.count, 0.5, 0.05);
}

TEST(PointOctree, DeterministicAndNanFree) {
    auto pts = cloudAt(-70.0, -89.9, 0.0, 100.0, 5000, 11);
    pts[10].ecef = glm::dvec3(std::nan(""), 0.0, 0.0);
    pts[20].ecef.z = std::numeric_limits<double>::infinity();
    const PointOctree a = PointOctree::build(pts, {256, 20, 5});
    const PointOctree b = PointOctree::build(pts, {256, 20, 5});
    const PointOctree c = PointOctree::build(pts, {256, 20, 6});
    EXPECT_EQ(a.points(), pts.size() - 2);
    ASSERT_EQ(a.nodes().size(), b.nodes().size());
    EXPECT_EQ(a.order(), b.order());
    EXPECT_NE(a.order(), c.order());   // another seed, another sample
    for (uint32_t i : a.order()) EXPECT_TRUE(i != 10 && i != 20);
}

TEST(PointOctree, DuplicatePointsStopAtTheDeepestLevel) {
    // 50 000 copies of one point: the tree stops at maxLevel instead of splitting forever.
    std::vector<PointRecord> pts(50000);
    for (size_t i = 0; i < pts.size(); ++i) pts[i] = {globe::Ellipsoid::wgs84().toEcef(0.0, 0.0, 0.0), 0, 0, i};
    pts.push_back({pts[0].ecef + glm::dvec3(1.0, 0.0, 0.0), 0, 0, 50000});
    const PointOctree tree = PointOctree::build(pts, {1000, 12, 1});
    EXPECT_EQ(tree.points(), pts.size());
    EXPECT_LE(tree.depth(), 12u);
}

TEST(PointOctree, EmptyInput) {
    const PointOctree tree = PointOctree::build({}, {});
    EXPECT_TRUE(tree.order().empty());
    EXPECT_EQ(tree.points(), 0u);
    EXPECT_TRUE(tree.nodes().empty());
}

}  // namespace
}  // namespace orbis::points
