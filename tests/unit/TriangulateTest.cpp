#include "layers/vector/Triangulate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

using orbis::vector::ringArea2;
using orbis::vector::triangulate;
using orbis::vector::TriangulateStats;

namespace {

struct Polygon {
    std::vector<glm::dvec2> points;
    std::vector<uint32_t> starts;
    void ring(const std::vector<glm::dvec2>& r) {
        starts.push_back(uint32_t(points.size()));
        points.insert(points.end(), r.begin(), r.end());
    }
};

double cross(glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

/// Twice the area the triangles cover, and that each is counter-clockwise and not degenerate.
double trianglesArea2(const Polygon& p, const std::vector<uint32_t>& tris) {
    double sum = 0.0;
    for (size_t t = 0; t + 2 < tris.size(); t += 3) {
        const double a = cross(p.points[tris[t]], p.points[tris[t + 1]], p.points[tris[t + 2]]);
        EXPECT_GT(a, 0.0) << "triangle " << t / 3;
        sum += a;
    }
    return sum;
}

double polygonArea2(const Polygon& p) {
    double sum = 0.0;
    for (size_t r = 0; r < p.starts.size(); ++r) {
        const size_t end = r + 1 < p.starts.size() ? p.starts[r + 1] : p.points.size();
        const double a = std::abs(ringArea2(std::span(p.points).subspan(p.starts[r], end - p.starts[r])));
        sum += r == 0 ? a : -a;
    }
    return sum;
}

std::vector<glm::dvec2> circle(glm::dvec2 c, double radius, int n, bool clockwise = false) {
    std::vector<glm::dvec2> out;
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * std::numbers::pi * i / n * (clockwise ? -1.0 : 1.0);
        out.push_back(c + radius * glm::dvec2(std::cos(a), std::sin(a)));
    }
    return out;
}

/// A star-shaped ring with random radii: simple, with many reflex vertices.
std::vector<glm::dvec2> star(int n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> r(0.2, 1.0);
    std::vector<glm::dvec2> out;
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * std::numbers::pi * i / n;
        out.push_back(r(rng) * glm::dvec2(std::cos(a), std::sin(a)));
    }
    return out;
}

constexpr size_t kLimit = 10'000'000;

}  // namespace

TEST(Triangulate, ASquareIsTwoTrianglesInEitherOrientation) {
    for (bool clockwise : {false, true}) {
        Polygon p;
        std::vector<glm::dvec2> sq = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        if (clockwise) std::reverse(sq.begin(), sq.end());
        p.ring(sq);
        const auto tris = triangulate(p.points, p.starts, kLimit);
        ASSERT_TRUE(tris.ok()) << tris.message();
        EXPECT_EQ(tris->size(), 6u);
        EXPECT_DOUBLE_EQ(trianglesArea2(p, *tris), 2.0);
    }
}

TEST(Triangulate, StarShapedRingsAreCoveredExactly) {
    for (uint32_t seed = 1; seed <= 20; ++seed) {
        Polygon p;
        p.ring(star(50 + int(seed) * 37, seed));
        TriangulateStats stats;
        const auto tris = triangulate(p.points, p.starts, kLimit, &stats);
        ASSERT_TRUE(tris.ok());
        EXPECT_EQ(tris->size(), 3 * (p.points.size() - 2)) << seed;
        EXPECT_NEAR(trianglesArea2(p, *tris), polygonArea2(p), 1e-9) << seed;
        EXPECT_EQ(stats.forced, 0u) << seed;
    }
}

TEST(Triangulate, HolesAreLeftOpen) {
    // A square with two square holes and a round one: n + 2h - 2 triangles, the area without them.
    Polygon p;
    p.ring({{0, 0}, {10, 0}, {10, 10}, {0, 10}});
    p.ring({{1, 1}, {1, 3}, {3, 3}, {3, 1}});
    p.ring({{6, 6}, {8, 6}, {8, 8}, {6, 8}});   // counter-clockwise: reversed as a hole
    p.ring(circle({4.5, 7.0}, 1.0, 24, true));
    TriangulateStats stats;
    const auto tris = triangulate(p.points, p.starts, kLimit, &stats);
    ASSERT_TRUE(tris.ok());
    EXPECT_EQ(tris->size() / 3, p.points.size() + 2 * 3 - 2);
    EXPECT_NEAR(trianglesArea2(p, *tris), polygonArea2(p), 1e-9);
    EXPECT_EQ(stats.forced, 0u);
    // No triangle's centroid falls in a hole.
    for (size_t t = 0; t < tris->size(); t += 3) {
        const glm::dvec2 c = (p.points[(*tris)[t]] + p.points[(*tris)[t + 1]] + p.points[(*tris)[t + 2]]) / 3.0;
        EXPECT_FALSE(c.x > 1 && c.x < 3 && c.y > 1 && c.y < 3);
        EXPECT_FALSE(c.x > 6 && c.x < 8 && c.y > 6 && c.y < 8);
        EXPECT_GT(glm::distance(c, glm::dvec2(4.5, 7.0)), 0.95);
    }
}

TEST(Triangulate, ManyHolesInARing) {
    Polygon p;
    p.ring(circle({0, 0}, 100.0, 400));
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) p.ring(circle({-56.0 + 16.0 * i, -56.0 + 16.0 * j}, 5.0, 12, true));
    const auto tris = triangulate(p.points, p.starts, kLimit);
    ASSERT_TRUE(tris.ok());
    EXPECT_NEAR(trianglesArea2(p, *tris), polygonArea2(p), 1e-6 * polygonArea2(p));
}

TEST(Triangulate, RepeatedAndCollinearPointsAddNoDegenerateTriangles) {
    Polygon p;
    p.ring({{0, 0}, {0, 0}, {1, 0}, {2, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}, {0, 0}});
    const auto tris = triangulate(p.points, p.starts, kLimit);
    ASSERT_TRUE(tris.ok());
    EXPECT_DOUBLE_EQ(trianglesArea2(p, *tris), 8.0);   // every triangle checked non-degenerate
}

TEST(Triangulate, DegenerateRingsGiveNoTriangles) {
    for (const std::vector<glm::dvec2>& ring : std::vector<std::vector<glm::dvec2>>{
             {}, {{0, 0}}, {{0, 0}, {1, 1}}, {{0, 0}, {1, 1}, {2, 2}, {3, 3}}, {{5, 5}, {5, 5}, {5, 5}}}) {
        Polygon p;
        if (!ring.empty()) p.ring(ring);
        const auto tris = triangulate(p.points, p.starts, kLimit);
        ASSERT_TRUE(tris.ok());
        EXPECT_TRUE(tris->empty()) << ring.size();
    }
}

TEST(Triangulate, SelfIntersectingRingsEndWithTriangles) {
    // A bow tie and a random scribble: no clean answer exists; the cut ends and says it forced.
    Polygon bow;
    bow.ring({{0, 0}, {2, 2}, {2, 0}, {0, 2}});
    TriangulateStats stats;
    auto tris = triangulate(bow.points, bow.starts, kLimit, &stats);
    ASSERT_TRUE(tris.ok());
    EXPECT_EQ(tris->size(), 6u);
    Polygon scribble;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<glm::dvec2> r;
    for (int i = 0; i < 20000; ++i) r.push_back({u(rng), u(rng)});
    scribble.ring(r);
    tris = triangulate(scribble.points, scribble.starts, kLimit, &stats);
    ASSERT_TRUE(tris.ok());
    EXPECT_LE(tris->size(), 3 * r.size());
    EXPECT_GT(stats.forced, 0u);
}

TEST(Triangulate, ALargeRingIsCutInNearLinearTime) {
    // 200 000 points on a ragged coastline (half of them reflex): the grid keeps it fast; a
    // quadratic cut would take minutes here.
    Polygon p;
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> jitter(0.98, 1.02);
    std::vector<glm::dvec2> coast = circle({0, 0}, 1.0, 200000);
    for (glm::dvec2& q : coast) q *= jitter(rng);
    p.ring(coast);
    TriangulateStats stats;
    const auto tris = triangulate(p.points, p.starts, kLimit, &stats);
    ASSERT_TRUE(tris.ok());
    EXPECT_EQ(tris->size(), 3 * (p.points.size() - 2));
    EXPECT_NEAR(trianglesArea2(p, *tris), polygonArea2(p), 1e-9 * polygonArea2(p));
    EXPECT_EQ(stats.forced, 0u);
}

TEST(Triangulate, BadInputIsAnErrorThatSaysWhat) {
    Polygon p;
    p.ring({{0, 0}, {1, 0}, {1, 1}});
    EXPECT_NE(triangulate(p.points, p.starts, 2).message().find("over the limit of 2"), std::string::npos);
    p.points[1].x = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(triangulate(p.points, p.starts, kLimit).message().find("point 1"), std::string::npos);
    p.points[1].x = 1.0;
    const std::vector<uint32_t> badStarts = {0, 5};
    EXPECT_NE(triangulate(p.points, badStarts, kLimit).message().find("ring 1 starts at point 5"), std::string::npos);
}

TEST(Triangulate, GarbageRingsAndHolesNeverHangOrCrash) {
    // Random outer rings and holes anywhere (outside, crossing, touching, repeated points): each
    // call ends, and every index it returns is a point of the input.
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> count(0, 40), holes(0, 4), snap(0, 3);
    for (int trial = 0; trial < 300; ++trial) {
        Polygon p;
        for (int r = 0, rings = 1 + holes(rng); r < rings; ++r) {
            std::vector<glm::dvec2> ring;
            for (int i = 0, n = count(rng); i < n; ++i) {
                glm::dvec2 q{u(rng), u(rng)};
                if (snap(rng) == 0) q = glm::round(q * 4.0) / 4.0;   // repeated and collinear points
                ring.push_back(q);
            }
            if (!ring.empty()) p.ring(ring);
        }
        TriangulateStats stats;
        const auto tris = triangulate(p.points, p.starts, kLimit, &stats);
        ASSERT_TRUE(tris.ok()) << trial;
        for (uint32_t i : *tris) ASSERT_LT(i, p.points.size()) << trial;
        EXPECT_LE(tris->size(), 3 * (p.points.size() + 2 * p.starts.size())) << trial;
    }
}
