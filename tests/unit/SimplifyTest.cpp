#include "layers/vector/Simplify.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

namespace orbis::vector {
namespace {

double segmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

/// Every dropped vertex lies within `tolerance` of the kept segment that spans it.
void expectWithinTolerance(const std::vector<glm::dvec3>& part, const std::vector<uint32_t>& kept, double tolerance) {
    for (size_t k = 0; k + 1 < kept.size(); ++k)
        for (uint32_t i = kept[k] + 1; i < kept[k + 1]; ++i)
            ASSERT_LE(segmentDistance(glm::dvec2(part[i]), glm::dvec2(part[kept[k]]), glm::dvec2(part[kept[k + 1]])), tolerance + 1e-12)
                << "vertex " << i;
}

std::vector<glm::dvec3> wiggle(int n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> step(0.0, 0.01);
    std::vector<glm::dvec3> out{{0, 0, 0}};
    for (int i = 1; i < n; ++i) out.push_back(out.back() + glm::dvec3(0.001, step(rng), 0.0));
    return out;
}

TEST(Simplify, ALineKeepsItsEndsAndEveryDroppedVertexIsWithinTheTolerance) {
    const auto line = wiggle(5000, 3);
    for (double tolerance : {0.0, 0.001, 0.01, 0.1}) {
        const auto kept = simplifyPart(line, tolerance, false);
        ASSERT_GE(kept.size(), 2u);
        EXPECT_EQ(kept.front(), 0u);
        EXPECT_EQ(kept.back(), line.size() - 1);
        expectWithinTolerance(line, kept, tolerance);
        if (tolerance == 0.0) {
            EXPECT_GT(kept.size(), 4900u);   // only exactly collinear points go
        }
        if (tolerance == 0.1) {
            EXPECT_LT(kept.size(), 200u);
        }
    }
}

TEST(Simplify, AStraightLineBecomesItsEnds) {
    std::vector<glm::dvec3> line;
    for (int i = 0; i <= 100; ++i) line.push_back({i * 0.5, i * 0.25, 0});
    EXPECT_EQ(simplifyPart(line, 1e-9, false), (std::vector<uint32_t>{0, 100}));
}

TEST(Simplify, ACircleKeepsAsFewVerticesAsItsToleranceAllows) {
    // A regular polygon inscribed in a circle of radius r deviates from it by r (1 - cos(pi / n)):
    // the simplified ring needs about pi / acos(1 - t / r) vertices.
    std::vector<glm::dvec3> ring;
    const int n = 3600;
    for (int i = 0; i < n; ++i) ring.push_back({std::cos(2 * std::numbers::pi * i / n), std::sin(2 * std::numbers::pi * i / n), 0});
    ring.push_back(ring.front());   // closed as stored
    const double t = 0.01;
    const auto kept = simplifyPart(ring, t, true);
    expectWithinTolerance(ring, kept, t);
    EXPECT_EQ(kept.back(), uint32_t(n));   // still closed
    const double ideal = std::numbers::pi / std::acos(1.0 - t);
    EXPECT_GE(double(kept.size() - 1), ideal);
    EXPECT_LE(double(kept.size() - 1), 2.0 * ideal);
}

TEST(Simplify, RingsSmallerThanTheToleranceGoWithTheirHoles) {
    Feature f;
    f.kind = GeometryKind::Polygons;
    const auto square = [&](glm::dvec2 c, double half) {
        f.parts.push_back(uint32_t(f.coords.size()));
        f.containsPole.push_back(0);
        for (glm::dvec2 d : {glm::dvec2(-1, -1), glm::dvec2(1, -1), glm::dvec2(1, 1), glm::dvec2(-1, 1), glm::dvec2(-1, -1)})
            f.coords.emplace_back(c.x + half * d.x, c.y + half * d.y, 0.0);
    };
    f.polygons = {0};
    square({0, 0}, 1.0);     // big: stays
    square({0, 0}, 0.001);   // a tiny hole: a square's corners are within 0.0015 of its diagonal
    f.polygons.push_back(2);
    square({5, 5}, 0.001);   // a tiny island: goes
    auto s = simplifyFeature(f, 0.01);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->polygons.size(), 1u);
    // The big square keeps its 4 corners (closed: 5 vertices); the hole is gone.
    EXPECT_EQ(s->parts.size(), 1u);
    EXPECT_EQ(s->coords.size(), 5u);
    EXPECT_FALSE(simplifyFeature([&] {
        Feature tiny = f;
        tiny.polygons = {0};
        tiny.parts = {0};
        tiny.coords.assign(f.coords.begin() + 10, f.coords.end());
        return tiny;
    }(), 0.01));
}

TEST(Simplify, NaturalEarthKeepsFewerVerticesAsTheToleranceGrows) {
    const auto file = std::filesystem::path(ORBIS_SHARED_DATA_DIR) / "vector" / "naturalearth_lowres.shp";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "../shared/data is absent: no " << file;
    VectorReadOptions o;
    o.source = file.string();
    auto data = readVector(o);
    ASSERT_TRUE(data) << data.message();
    size_t previous = SIZE_MAX;
    for (double tolerance : {0.0, 0.05, 0.2, 1.0}) {
        size_t vertices = 0, features = 0;
        for (const Feature& f : data->layers[0].features)
            if (auto s = simplifyFeature(f, tolerance)) vertices += s->coords.size(), ++features;
        EXPECT_LT(vertices, previous) << tolerance;
        previous = vertices;
        if (tolerance == 0.0) {
            EXPECT_EQ(features, 177u);
        }
        if (tolerance == 1.0) {
            EXPECT_GT(features, 100u);   // small islands go, countries stay
        }
    }
}

}  // namespace
}  // namespace orbis::vector
