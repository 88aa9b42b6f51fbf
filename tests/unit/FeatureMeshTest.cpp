// Extruded buildings and polygons at altitude as meshes: heights (roof, walls down to the ground
// with a skirt, surfaces at Z), walls facing out of the solid (holes included), triangles wound
// to face their normal, long edges cut to follow the Earth's curve, times, chunks and their
// bounding spheres, across the antimeridian.
#include "globe/Ellipsoid.h"
#include "layers/vector/FeatureMesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace orbis::vector {
namespace {

Feature polygon(std::vector<std::vector<glm::dvec3>> rings, bool hasZ = false) {
    Feature f;
    f.kind = GeometryKind::Polygons;
    f.polygons = {0};
    for (auto& r : rings) {
        f.parts.push_back(uint32_t(f.coords.size()));
        f.coords.insert(f.coords.end(), r.begin(), r.end());
        f.containsPole.push_back(0);
    }
    f.hasZ = hasZ;
    return f;
}

/// A square `sizeDeg` a side at (lon, lat), closed, counter-clockwise or not.
std::vector<glm::dvec3> square(double lon, double lat, double sizeDeg, bool ccw = true, double z = 0.0) {
    std::vector<glm::dvec3> r = {{lon, lat, z}, {lon + sizeDeg, lat, z}, {lon + sizeDeg, lat + sizeDeg, z}, {lon, lat + sizeDeg, z}};
    if (!ccw) std::reverse(r.begin(), r.end());
    r.push_back(r.front());
    return r;
}

struct Fixture {
    VectorContent content;
    ContentStyles styles;
    void add(Feature f, FeatureStyle s) {
        if (content.layers.empty()) content.layers.emplace_back(), styles.emplace_back();
        content.layers[0].data.features.push_back(std::move(f));
        styles[0].push_back(s);
        ++content.featureCount;
    }
    FeatureMesh build(AltitudeMode mode, double groundM, MeshOptions options = {}) {
        MeshGround ground(content, styles, mode);
        EXPECT_TRUE(ground.sample([groundM](double, double) { return std::optional<double>(groundM); }, 1'000'000));
        options.mode = mode;
        return buildFeatureMesh(content, styles, ground, options);
    }
};

FeatureStyle extruded(double metres) {
    FeatureStyle s;
    s.extrudeM = metres;
    return s;
}

globe::Geodetic geodetic(const MeshChunk& c, const shader::VectorMeshVertex& v) {
    return globe::Ellipsoid::wgs84().toGeodetic(c.origin + glm::dvec3(v.position));
}

glm::dvec3 normalOf(const shader::VectorMeshVertex& v) {
    const auto s = [&](int shift) { return double(int8_t(uint8_t(v.normal >> shift))) / 127.0; };
    return {s(0), s(8), s(16)};
}

/// A two-sided surface: each triangle listed twice, first facing its normal, then away.
void expectTwoSided(const MeshChunk& c) {
    ASSERT_EQ(c.indices.size() % 6, 0u);
    for (size_t t = 0; t < c.indices.size(); t += 6) {
        const glm::dvec3 a(c.vertices[c.indices[t]].position), b(c.vertices[c.indices[t + 1]].position),
            d(c.vertices[c.indices[t + 2]].position);
        const glm::dvec3 n = normalOf(c.vertices[c.indices[t]]);
        EXPECT_GT(glm::dot(glm::cross(b - a, d - a), n), 0.0) << "triangle " << t / 3;
        EXPECT_EQ(c.indices[t + 3], c.indices[t]);
        EXPECT_EQ(c.indices[t + 4], c.indices[t + 2]);
        EXPECT_EQ(c.indices[t + 5], c.indices[t + 1]);
    }
}

TEST(FeatureMesh, ABuildingHasItsRoofAtHeightAndItsWallsDownToTheGround) {
    Fixture f;
    f.add(polygon({square(7.0, 45.0, 0.0002)}), extruded(20.0));   // ~16 x 22 m
    const FeatureMesh mesh = f.build(AltitudeMode::Clamped, 100.0);
    ASSERT_EQ(mesh.chunks.size(), 1u);
    EXPECT_EQ(mesh.features, 1u);
    EXPECT_EQ(mesh.triangles, 2u + 4u * 2u) << "a roof of two triangles, four walls of two";
    const MeshChunk& c = mesh.chunks[0];
    double top = -1e9, bottom = 1e9;
    for (const auto& v : c.vertices) {
        const double h = geodetic(c, v).height;
        top = std::max(top, h), bottom = std::min(bottom, h);
    }
    EXPECT_NEAR(top, 120.0, 0.01);
    EXPECT_NEAR(bottom, 100.0 - kSkirtMetres, 0.01) << "the skirt: 2 m, more than a tenth of 20 m";
    // Walls face away from the building's centre; every triangle faces its normal.
    const glm::dvec3 centre = globe::Ellipsoid::wgs84().toEcef(7.0001, 45.0001, 110.0);
    for (size_t t = 0; t < c.indices.size(); t += 3) {
        const auto& v0 = c.vertices[c.indices[t]];
        const glm::dvec3 a(v0.position), b(c.vertices[c.indices[t + 1]].position), d(c.vertices[c.indices[t + 2]].position);
        const glm::dvec3 n = normalOf(v0);
        EXPECT_GT(glm::dot(glm::cross(b - a, d - a), n), 0.0) << "triangle " << t / 3 << " wound against its normal";
        const glm::dvec3 mid = c.origin + (a + b + d) / 3.0;
        EXPECT_GT(glm::dot(mid - centre, n), 0.0) << "triangle " << t / 3 << " faces into the building";
    }
    // The bounding sphere holds every vertex.
    for (const auto& v : c.vertices) EXPECT_LE(glm::length(c.origin + glm::dvec3(v.position) - c.center), c.radius + 1e-6);
    EXPECT_EQ(c.vertices[0].feature, 1u);
}

TEST(FeatureMesh, WallsOfAHoleFaceIntoTheHoleWhicheverWayTheRingsRun) {
    for (const bool ccw : {true, false}) {
        Fixture f;
        f.add(polygon({square(10.0, 0.0, 0.001, ccw), square(10.0004, 0.0004, 0.0002, ccw)}), extruded(30.0));
        const FeatureMesh mesh = f.build(AltitudeMode::Clamped, 0.0);
        ASSERT_EQ(mesh.chunks.size(), 1u);
        const MeshChunk& c = mesh.chunks[0];
        const glm::dvec3 holeCentre = globe::Ellipsoid::wgs84().toEcef(10.0005, 0.0005, 15.0);
        size_t inner = 0;
        for (size_t t = 0; t < c.indices.size(); t += 3) {
            const glm::dvec3 a(c.vertices[c.indices[t]].position), b(c.vertices[c.indices[t + 1]].position),
                d(c.vertices[c.indices[t + 2]].position);
            const glm::dvec3 n = normalOf(c.vertices[c.indices[t]]);
            EXPECT_GT(glm::dot(glm::cross(b - a, d - a), n), 0.0);
            const glm::dvec3 mid = c.origin + (a + b + d) / 3.0;
            // A hole's wall: within 15 m of the hole's centre horizontally, facing it.
            const glm::dvec3 toHole = holeCentre - mid;
            if (glm::length(toHole) < 20.0) {
                ++inner;
                EXPECT_GT(glm::dot(toHole, n), 0.0) << (ccw ? "ccw" : "cw") << " rings: a hole's wall faces out of the hole";
            }
        }
        EXPECT_EQ(inner, 8u) << "four walls of the hole, two triangles each";
    }
}

TEST(FeatureMesh, ExtrusionScaleAndRelativeAndAbsoluteHeights) {
    Fixture f;
    f.add(polygon({square(7.0, 45.0, 0.0002, true, 50.0)}, true), extruded(20.0));
    const auto roofOf = [&](AltitudeMode mode, double scale) {
        const FeatureMesh mesh = f.build(mode, 100.0, {.extrusionScale = scale});
        double top = -1e9;
        for (const auto& v : mesh.chunks.at(0).vertices) top = std::max(top, geodetic(mesh.chunks[0], v).height);
        return top;
    };
    EXPECT_NEAR(roofOf(AltitudeMode::Clamped, 1.0), 120.0, 0.01) << "clamped: Z is ignored";
    EXPECT_NEAR(roofOf(AltitudeMode::Clamped, 2.5), 150.0, 0.01);
    EXPECT_NEAR(roofOf(AltitudeMode::Relative, 1.0), 170.0, 0.01) << "ground 100 + Z 50 + 20";
    EXPECT_NEAR(roofOf(AltitudeMode::Absolute, 1.0), 70.0, 0.01) << "Z 50 + 20";
}

TEST(FeatureMesh, APolygonAtAltitudeIsTwoSidedAndFollowsTheCurve) {
    Fixture f;
    FeatureStyle opaque;
    opaque.fillOpacity = 1.0;
    f.add(polygon({square(20.0, -10.0, 2.0, true, 3000.0)}, true), opaque);
    const FeatureMesh mesh = f.build(AltitudeMode::Absolute, 0.0);
    ASSERT_FALSE(mesh.chunks.empty());
    const MeshChunk& c = mesh.chunks[0];
    for (const auto& v : c.vertices) EXPECT_NEAR(geodetic(c, v).height, 3000.0, 0.05);
    // Each triangle twice (both faces), and no edge longer than the cut allows (2 degrees / 20).
    expectTwoSided(c);
    EXPECT_GE(mesh.triangles, 2u * 2u * 20u * 20u);
    for (size_t t = 0; t < c.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            const glm::dvec3 a(c.vertices[c.indices[t + e]].position), b(c.vertices[c.indices[t + (e + 1) % 3]].position);
            EXPECT_LT(glm::length(a - b), kMaxEdgeDeg * 111'320.0 * 1.5);
        }
    EXPECT_TRUE(c.translucent.empty());
    // Below fillOpacity 1: the same triangles once each, to blend, its opacity in alpha.
    f.styles[0][0].fillOpacity = 0.4;
    const FeatureMesh blended = f.build(AltitudeMode::Absolute, 0.0);
    ASSERT_EQ(blended.chunks.size(), mesh.chunks.size());
    EXPECT_TRUE(blended.chunks[0].indices.empty());
    EXPECT_EQ(blended.chunks[0].translucent.size() * 2, c.indices.size());
    EXPECT_EQ(blended.chunks[0].vertices[0].color >> 24, 102u);
    EXPECT_EQ(blended.triangles * 2, mesh.triangles);
    // In the clamped mode the same polygon is not a mesh: the drape paints it.
    MeshGround clamped(f.content, f.styles, AltitudeMode::Clamped);
    EXPECT_TRUE(clamped.features().empty());
}

TEST(FeatureMesh, FeaturesOutsideTheirTimeAndHiddenOnesAreLeftOut) {
    Fixture f;
    f.add(polygon({square(7.0, 45.0, 0.0002)}), extruded(10.0));
    f.add(polygon({square(7.001, 45.0, 0.0002)}), extruded(10.0));
    FeatureStyle hidden = extruded(10.0);
    hidden.visible = false;
    f.add(polygon({square(7.002, 45.0, 0.0002)}), hidden);
    f.content.layers[0].times.spans = {{}, {.begin = TimeNs(1000), .end = TimeNs(2000)}, {}};
    EXPECT_EQ(f.build(AltitudeMode::Clamped, 0.0, {.time = 500}).features, 1u);
    EXPECT_EQ(f.build(AltitudeMode::Clamped, 0.0, {.time = 1500}).features, 2u);
}

TEST(FeatureMesh, ABuildingAcrossTheAntimeridianIsWhole) {
    Fixture f;
    // Unwrapped by the reader: 179.9999 to 180.0001.
    f.add(polygon({square(179.9999, -17.0, 0.0002)}), extruded(10.0));
    const FeatureMesh mesh = f.build(AltitudeMode::Clamped, 5.0);
    ASSERT_EQ(mesh.chunks.size(), 1u);
    EXPECT_EQ(mesh.triangles, 10u);
    EXPECT_LT(mesh.chunks[0].radius, 50.0) << "not stretched around the world";
}

TEST(FeatureMesh, TheGroundIsSampledASliceAtATime) {
    Fixture f;
    f.add(polygon({square(7.0, 45.0, 0.0002)}), extruded(10.0));   // 5 coordinates
    f.add(polygon({square(8.0, 45.0, 0.0002)}), extruded(10.0));
    MeshGround ground(f.content, f.styles, AltitudeMode::Clamped);
    ASSERT_EQ(ground.samples(), 10u);
    size_t calls = 0;
    const auto fn = [&](double lon, double) {
        ++calls;
        return lon < 7.5 ? std::optional<double>(1.0) : std::nullopt;
    };
    EXPECT_FALSE(ground.sample(fn, 3));
    EXPECT_FALSE(ground.sample(fn, 3));
    EXPECT_FALSE(ground.sample(fn, 3));
    EXPECT_TRUE(ground.sample(fn, 3));
    EXPECT_EQ(calls, 10u);
    EXPECT_FLOAT_EQ(ground.heights(0)[4], 1.0f);
    EXPECT_FLOAT_EQ(ground.heights(1)[0], 0.0f) << "unknown ground: the ellipsoid";
}

TEST(FeatureMesh, LinesAndPointsAtAltitudeAreSegmentsAndMarkers) {
    Fixture f;
    Feature line;
    line.kind = GeometryKind::Lines;
    line.parts = {0};
    line.coords = {{30.0, 10.0, 500.0}, {30.35, 10.0, 700.0}, {30.35, 10.001, 700.0}};
    line.hasZ = true;
    FeatureStyle wide;
    wide.widthPx = 4.0;
    wide.opacity = 0.5;
    f.add(line, wide);
    Feature points;
    points.kind = GeometryKind::Points;
    points.parts = {0, 1};
    points.coords = {{30.1, 10.1, 50.0}, {30.2, 10.1, 60.0}};
    points.hasZ = true;
    f.add(points, FeatureStyle{});
    // Clamped: both draped, nothing in 3-D.
    EXPECT_TRUE(MeshGround(f.content, f.styles, AltitudeMode::Clamped).features().empty());

    const FeatureMesh mesh = f.build(AltitudeMode::Relative, 100.0);
    EXPECT_EQ(mesh.features, 2u);
    EXPECT_EQ(mesh.markers, 2u);
    // 0.35 degrees at 10 N: cut into 4 pieces of at most 0.1 degree; the short leg in one.
    EXPECT_EQ(mesh.segments, 4u + 1u);
    const auto& ell = globe::Ellipsoid::wgs84();
    std::vector<double> heights;
    for (const MeshChunk& c : mesh.chunks) {
        for (const auto& s : c.segments) {
            EXPECT_FLOAT_EQ(s.widthPx, 4.0f);
            EXPECT_EQ(s.color >> 24, 128u) << "the opacity in alpha";
            heights.push_back(ell.toGeodetic(c.origin + glm::dvec3(s.a)).height);
            heights.push_back(ell.toGeodetic(c.origin + glm::dvec3(s.b)).height);
            EXPECT_LE(glm::length(c.origin + glm::dvec3(s.a) - c.center), c.radius + 1.0);
        }
        for (const auto& m : c.markers) {
            EXPECT_EQ(m.feature, 2u);
            const double h = ell.toGeodetic(c.origin + glm::dvec3(m.position)).height;
            EXPECT_TRUE(std::abs(h - 150.0) < 0.05 || std::abs(h - 160.0) < 0.05) << h;
        }
    }
    // Ground 100 + Z: 600 to 800 m, the heights interpolated along the long leg.
    ASSERT_EQ(heights.size(), 10u);
    EXPECT_NEAR(*std::min_element(heights.begin(), heights.end()), 600.0, 0.05);
    EXPECT_NEAR(*std::max_element(heights.begin(), heights.end()), 800.0, 0.05);
    EXPECT_NEAR(heights[1], 650.0, 0.05) << "a quarter of the way: 600 + 200 / 4";
}

TEST(FeatureMesh, AltitudeModeNames) {
    for (const AltitudeMode m : {AltitudeMode::Clamped, AltitudeMode::Relative, AltitudeMode::Absolute})
        EXPECT_EQ(parseAltitudeMode(altitudeModeName(m)), m);
    EXPECT_EQ(parseAltitudeMode("floating"), std::nullopt);
}

}  // namespace
}  // namespace orbis::vector
