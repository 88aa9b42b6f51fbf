// Which feature lies under a point of the ground: markers, lines within their width, polygons
// with holes, across the antimeridian and around the South Pole; hidden features are not picked.
#include "layers/vector/FeaturePick.h"

#include <gtest/gtest.h>

namespace orbis::vector {
namespace {

Feature feature(GeometryKind kind, std::vector<std::vector<glm::dvec3>> parts, std::vector<int8_t> poles = {}) {
    Feature f;
    f.kind = kind;
    for (auto& p : parts) {
        f.parts.push_back(uint32_t(f.coords.size()));
        f.coords.insert(f.coords.end(), p.begin(), p.end());
    }
    if (kind == GeometryKind::Polygons) {
        f.polygons = {0};
        f.containsPole = poles.empty() ? std::vector<int8_t>(parts.size(), 0) : poles;
    }
    f.bounds = {1e9, 1e9, -1e9, -1e9, false};
    for (const auto& c : f.coords) {
        f.bounds.west = std::min(f.bounds.west, c.x), f.bounds.east = std::max(f.bounds.east, c.x);
        f.bounds.south = std::min(f.bounds.south, c.y), f.bounds.north = std::max(f.bounds.north, c.y);
    }
    for (int8_t p : f.containsPole)
        if (p != 0) f.bounds = {-180, p < 0 ? -90.0 : f.bounds.south, 180, p > 0 ? 90.0 : f.bounds.north, false};
    return f;
}

struct Fixture {
    VectorContent content;
    ContentStyles styles;
    void add(Feature f, FeatureStyle s = {}) {
        if (content.layers.empty()) content.layers.emplace_back(), styles.emplace_back();
        content.layers[0].data.features.push_back(std::move(f));
        styles[0].push_back(s);
    }
    std::optional<size_t> at(double lon, double lat, double metresPerPixel = 100.0) const {
        auto p = pickFeature(content, styles, {.lonDeg = lon, .latDeg = lat, .metresPerPixel = metresPerPixel});
        return p ? std::optional<size_t>(p->feature) : std::nullopt;
    }
};

TEST(FeaturePick, MarkersLinesAndPolygonsWithAHole) {
    Fixture f;
    f.add(feature(GeometryKind::Polygons, {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}},
                                           {{0.4, 0.4, 0}, {0.6, 0.4, 0}, {0.6, 0.6, 0}, {0.4, 0.6, 0}, {0.4, 0.4, 0}}}));
    FeatureStyle wide;
    wide.widthPx = 10.0;
    f.add(feature(GeometryKind::Lines, {{{2, 0, 0}, {2, 1, 0}}}), wide);
    FeatureStyle big;
    big.iconSizePx = 20.0;
    f.add(feature(GeometryKind::Points, {{{0.2, 0.2, 0}}}), big);
    EXPECT_EQ(f.at(0.8, 0.8), 0u);
    EXPECT_EQ(f.at(0.5, 0.5), std::nullopt) << "inside the hole";
    EXPECT_EQ(f.at(1.5, 0.5), std::nullopt);
    // 100 m a pixel: the line reaches 5 px + 3 px of slop = 800 m either side.
    EXPECT_EQ(f.at(2.0 + 700.0 / 111320.0, 0.5), 1u);
    EXPECT_EQ(f.at(2.0 + 900.0 / 111320.0, 0.5), std::nullopt);
    // The marker over the polygon wins; 10 px + 3 px = 1300 m.
    EXPECT_EQ(f.at(0.2, 0.2 + 1200.0 / 111320.0), 2u);
    EXPECT_EQ(f.at(0.2, 0.2 + 1400.0 / 111320.0), 0u) << "past the marker: the polygon under it";
}

TEST(FeaturePick, AcrossTheAntimeridianAndAroundTheSouthPole) {
    Fixture f;
    // Fiji-like: unwrapped from 178 to 182.
    f.add(feature(GeometryKind::Polygons, {{{178, -18, 0}, {182, -18, 0}, {182, -16, 0}, {178, -16, 0}, {178, -18, 0}}}));
    // Antarctica-like: the longitude turns once around the pole along -70.
    std::vector<glm::dvec3> ring;
    for (int lon = -180; lon <= 180; lon += 30) ring.push_back({double(lon), -70.0 + (lon % 60 == 0 ? 0.0 : -1.0), 0});
    f.add(feature(GeometryKind::Polygons, {ring}, {-1}));
    EXPECT_EQ(f.at(-179.0, -17.0), 0u);
    EXPECT_EQ(f.at(179.0, -17.0), 0u);
    EXPECT_EQ(f.at(-177.0, -17.0), std::nullopt);
    EXPECT_EQ(f.at(45.0, -85.0), 1u);
    EXPECT_EQ(f.at(-135.0, -89.9), 1u);
    EXPECT_EQ(f.at(45.0, -60.0), std::nullopt);
}

TEST(FeaturePick, HiddenFeaturesAndBadQueriesPickNothing) {
    Fixture f;
    FeatureStyle hidden;
    hidden.visible = false;
    f.add(feature(GeometryKind::Polygons, {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}}}), hidden);
    EXPECT_EQ(f.at(0.7, 0.2), std::nullopt);
    f.styles[0][0].visible = true;
    EXPECT_EQ(f.at(0.7, 0.2), 0u);
    // Shown only from t = 100: not at t = 0.
    f.content.layers[0].times.spans = {FeatureTimeSpan{.begin = TimeNs(100)}};
    EXPECT_EQ(f.at(0.7, 0.2), std::nullopt);
    EXPECT_EQ(f.at(std::nan(""), 0.2), std::nullopt);
    EXPECT_FALSE(pickFeature(f.content, f.styles, {.lonDeg = 0.7, .latDeg = 0.2, .metresPerPixel = 0.0}));
}

}  // namespace
}  // namespace orbis::vector
