// Where labels stand (LabelAnchors) and how a frame's labels are seen, chosen and drawn on the
// CPU (VectorLabels): interior points of concave, holed, antimeridian and polar polygons, a
// line's middle and direction, the rank, the globe and a hill hiding a label, the halo colour,
// and a frame of labels from synthetic features.
#include "globe/Ellipsoid.h"
#include "layers/vector/LabelAnchors.h"
#include "layers/vector/VectorLabels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <vector>

using namespace orbis::vector;

namespace {

Feature point(double lon, double lat) {
    Feature f;
    f.kind = GeometryKind::Points;
    f.coords = {{lon, lat, 0.0}};
    f.parts = {0};
    return f;
}

/// One polygon per entry of `polygons`, each a list of rings (outer first), closed as given.
Feature polygons(const std::vector<std::vector<std::vector<glm::dvec2>>>& polygons, int8_t pole = 0) {
    Feature f;
    f.kind = GeometryKind::Polygons;
    for (const auto& rings : polygons) {
        f.polygons.push_back(uint32_t(f.parts.size()));
        for (const auto& ring : rings) {
            f.parts.push_back(uint32_t(f.coords.size()));
            f.containsPole.push_back(f.parts.size() == f.polygons.back() + 1 ? pole : 0);
            for (const glm::dvec2& p : ring) f.coords.push_back({p.x, p.y, 0.0});
        }
    }
    return f;
}

Feature line(const std::vector<glm::dvec2>& points) {
    Feature f;
    f.kind = GeometryKind::Lines;
    f.parts = {0};
    for (const glm::dvec2& p : points) f.coords.push_back({p.x, p.y, 0.0});
    return f;
}

std::vector<glm::dvec2> box(double w, double s, double e, double n) { return {{w, s}, {e, s}, {e, n}, {w, n}, {w, s}}; }

/// The anchor's distance to the polygon's edges (degrees, in the plane the test built), signed.
double insideBy(glm::dvec2 p, const std::vector<std::vector<glm::dvec2>>& rings) { return signedDistanceToPolygon(p, rings); }

}  // namespace

TEST(LabelAnchors, APointIsItsOwnAnchorAndRanksAboveEveryPolygon) {
    const LabelAnchor a = labelAnchor(point(12.5, 41.9));
    ASSERT_TRUE(a.valid);
    EXPECT_EQ(a.lonLat, glm::dvec2(12.5, 41.9));
    EXPECT_EQ(a.sizeM, 0.0);
    // Points first, whatever the size of the rest; then size; then the later rule.
    EXPECT_GT(labelPriority(GeometryKind::Points, 0.0, -1), labelPriority(GeometryKind::Polygons, 4e7, 100));
    EXPECT_GT(labelPriority(GeometryKind::Polygons, 2e6, -1), labelPriority(GeometryKind::Lines, 1e6, 100));
    EXPECT_GT(labelPriority(GeometryKind::Lines, 1e6, 3), labelPriority(GeometryKind::Polygons, 1e6, 2));
    EXPECT_GT(labelPriority(GeometryKind::Points, 0.0, 0), labelPriority(GeometryKind::Points, 0.0, -1));
}

TEST(LabelAnchors, AConcavePolygonIsLabelledInsideWhereItsCentroidIsNot) {
    // A "C" open to the east, 10 x 10 degrees with arms 2 degrees thick at the equator: the
    // centroid lies in the opening; the anchor must lie in the shape, in its thickest part.
    const std::vector<glm::dvec2> c = {{0, 0}, {10, 0}, {10, 2}, {2, 2}, {2, 8}, {10, 8}, {10, 10}, {0, 10}, {0, 0}};
    const LabelAnchor a = labelAnchor(polygons({{c}}));
    ASSERT_TRUE(a.valid);
    EXPECT_GT(insideBy(a.lonLat, {c}), 0.8) << a.lonLat.x << ", " << a.lonLat.y;   // the arms are 2 thick: ~1 from each edge
    // sqrt(area): 10 x 10 minus the 8 x 6 opening, 52 square degrees (cos 5 deg ~ 1).
    EXPECT_NEAR(a.sizeM, std::sqrt(52.0 * std::cos(5.0 * M_PI / 180.0)) * 111195.0, 2000.0);
}

TEST(LabelAnchors, AHoleIsAvoided) {
    // A square with a square hole in its middle: the anchor is between the hole and the edge.
    const auto outer = box(0, 0, 12, 12), hole = box(3, 3, 9, 9);
    const LabelAnchor a = labelAnchor(polygons({{outer, hole}}));
    ASSERT_TRUE(a.valid);
    EXPECT_GT(insideBy(a.lonLat, {outer, hole}), 1.3) << a.lonLat.x << ", " << a.lonLat.y;   // the band is 3 wide
}

TEST(LabelAnchors, TheLargestPolygonIsLabelledAcrossTheAntimeridian) {
    // Fiji as Natural Earth cuts it: a small part west of 180 and a large one unwrapped east of it.
    const LabelAnchor a = labelAnchor(polygons({{box(-180, -20, -179, -19)}, {box(176, -20, 181, -14)}}));
    ASSERT_TRUE(a.valid);
    EXPECT_GT(a.lonLat.x, 176.5);
    EXPECT_LT(a.lonLat.x, 180.5);
    EXPECT_NEAR(a.lonLat.y, -17.0, 0.6);
}

TEST(LabelAnchors, ARingAroundTheSouthPoleIsLabelledNearThePole) {
    // Antarctica: a ring at about 70 S whose longitude turns once, enclosing the pole.
    std::vector<glm::dvec2> ring;
    for (int lon = -180; lon <= 180; lon += 10) ring.push_back({double(lon), -70.0 + 2.0 * std::sin(lon * M_PI / 60.0)});
    const LabelAnchor a = labelAnchor(polygons({{ring}}, -1));
    ASSERT_TRUE(a.valid);
    EXPECT_LT(a.lonLat.y, -85.0) << "the thick of a polar cap is near its pole";
    // Its size: a cap of about 20 degrees of colatitude, pi * (20 * 111 km)^2.
    EXPECT_NEAR(a.sizeM, std::sqrt(M_PI) * 20.0 * 111195.0, 0.05 * std::sqrt(M_PI) * 20.0 * 111195.0);
}

TEST(LabelAnchors, ALineIsLabelledAtItsMiddleByLengthAlongItsDirection) {
    // An L at the equator: 4 degrees east, then 2 north. The middle (3 degrees along) is on the
    // first leg, heading east; the path samples run from end to end.
    const LabelAnchor a = labelAnchor(line({{0, 0}, {4, 0}, {4, 2}}));
    ASSERT_TRUE(a.valid);
    EXPECT_NEAR(a.lonLat.x, 3.0, 1e-3);
    EXPECT_NEAR(a.lonLat.y, 0.0, 1e-9);
    EXPECT_GT(a.ahead.x, a.lonLat.x);
    EXPECT_NEAR(a.ahead.y, 0.0, 1e-9);
    EXPECT_NEAR(a.sizeM, 6.0 * 111195.0, 100.0);
    ASSERT_EQ(a.path.size(), LabelAnchor::kPathSamples);
    EXPECT_EQ(a.path.front(), glm::dvec2(0, 0));
    EXPECT_NEAR(a.path.back().y, 2.0, 1e-9);
    // Longest part of a multi-line; a line across the antimeridian keeps its unwrapped longitudes.
    Feature two = line({{179, 10}, {181, 10}});
    two.parts.push_back(2);
    two.coords.push_back({0, 0, 0});
    two.coords.push_back({0.5, 0, 0});
    EXPECT_NEAR(labelAnchor(two).lonLat.x, 180.0, 1e-6);
}

TEST(LabelAnchors, EmptyFeaturesHaveNoAnchor) {
    EXPECT_FALSE(labelAnchor(Feature{}).valid);
    EXPECT_FALSE(labelAnchor(line({{1, 1}})).valid);
    EXPECT_FALSE(labelAnchor(polygons({{{{0, 0}, {1, 1}}}})).valid);
}

TEST(LabelVisibility, TheGlobeHidesTheFarSideAndAHillHidesWhatIsBehindIt) {
    const auto& wgs84 = orbis::globe::Ellipsoid::wgs84();
    const glm::dvec3 eye = wgs84.toEcef(0.0, 0.0, 2.0e7);
    EXPECT_FALSE(hiddenByEllipsoid(eye, wgs84.toEcef(30.0, 20.0, 0.0)));
    EXPECT_TRUE(hiddenByEllipsoid(eye, wgs84.toEcef(120.0, 0.0, 0.0)));
    EXPECT_TRUE(hiddenByEllipsoid(eye, wgs84.toEcef(180.0, 45.0, 0.0)));
    // 2000 m over the plain at 0 E (the horizon 160 km away), looking east at a point 1 degree
    // away, over a 3000 m ridge at 0.5 E (and none): the ridge hides it; the ground the point
    // stands on does not.
    const glm::dvec3 low = wgs84.toEcef(0.0, 0.0, 2000.0), target = wgs84.toEcef(1.0, 0.0, 0.0);
    const orbis::scene::GroundHeightFn ridge = [](double lon, double) {
        return std::optional<double>(std::abs(lon - 0.5) < 0.05 ? 3000.0 : 0.0);
    };
    const orbis::scene::GroundHeightFn plain = [](double, double) { return std::optional<double>(0.0); };
    EXPECT_TRUE(hiddenByGround(low, target, ridge));
    EXPECT_FALSE(hiddenByGround(low, target, plain));
    EXPECT_FALSE(hiddenByGround(low, target, nullptr));
    // From high above the ridge is seen over, not through.
    EXPECT_FALSE(hiddenByGround(wgs84.toEcef(1.0, 0.0, 4.0e6), target, ridge));
}

TEST(LabelVisibility, LightTextGetsADarkHaloAndDarkTextALightOne) {
    EXPECT_LT(haloColor({1.0, 1.0, 1.0}).r, 0.2);
    EXPECT_LT(haloColor({1.0, 0.95, 0.7}).r, 0.2);
    EXPECT_GT(haloColor({0.0, 0.0, 0.0}).r, 0.8);
    EXPECT_GT(haloColor({0.1, 0.1, 0.6}).r, 0.8);
    EXPECT_EQ(haloColor({1.0, 1.0, 1.0}).a, 1.0);
}

TEST(VectorLabelsCpu, AFrameOfLabelsHasNoOverlapsPointsFirstAndGlyphsForEachLabel) {
    if (!std::filesystem::exists(kDefaultFontPath)) GTEST_SKIP() << kDefaultFontPath << " is absent (Debian: fonts-dejavu-core)";
    // 400 labelled points on a 20 x 20 grid over 40 x 40 degrees, and one large polygon under
    // them, seen from 8 000 km: far more than fit.
    auto content = std::make_shared<VectorContent>();
    ContentLayer& layer = content->layers.emplace_back();
    auto styles = std::make_shared<ContentStyles>(1);
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 20; ++i) {
            layer.data.features.push_back(point(-20.0 + 2.0 * i, -20.0 + 2.0 * j));
            FeatureStyle s;
            s.label = "Πόλη " + std::to_string(j * 20 + i);
            (*styles)[0].push_back(s);
        }
    layer.data.features.push_back(polygons({{box(-25, -25, 25, 25)}}));
    FeatureStyle big;
    big.label = "Москва";
    (*styles)[0].push_back(big);
    auto anchors = std::make_shared<const ContentAnchors>(labelAnchors(*content));

    auto labels = VectorLabels::create();
    ASSERT_TRUE(labels.ok()) << labels.message();
    labels->setContent(content, styles, anchors);
    EXPECT_EQ(labels->stats().labelled, 401u);

    orbis::scene::Camera camera;
    const auto& wgs84 = orbis::globe::Ellipsoid::wgs84();
    camera.lookAt(wgs84.toEcef(0.0, 0.0, 8.0e6), glm::dvec3(0.0), glm::dvec3(0, 0, 1));
    orbis::scene::FrameContext frame;
    frame.camera = &camera;
    frame.width = 960;
    frame.height = 540;
    labels->update(frame);

    const VectorLabelStats& stats = labels->stats();
    EXPECT_EQ(stats.candidates, 401u);
    EXPECT_GT(stats.placed, 20u);
    EXPECT_LT(stats.placed, 401u);
    const auto placed = labels->placed();
    for (size_t a = 0; a < placed.size(); ++a) {
        EXPECT_LT(placed[a].feature, 400u) << "the polygon's label ranks below every point's and has no room left";
        for (size_t b = a + 1; b < placed.size(); ++b) {
            const bool overlap = placed[a].min.x < placed[b].max.x && placed[b].min.x < placed[a].max.x &&
                                 placed[a].min.y < placed[b].max.y && placed[b].min.y < placed[a].max.y;
            ASSERT_FALSE(overlap) << placed[a].id << " and " << placed[b].id;
        }
    }
    // "Πόλη N": 4 letters, a space (no quad) and 1 to 3 digits.
    EXPECT_GE(labels->glyphs().size(), 5 * placed.size());
    EXPECT_LE(labels->glyphs().size(), 7 * placed.size());
    // Switched off: nothing, and the next frame starts afresh.
    labels->clear();
    EXPECT_TRUE(labels->glyphs().empty());
    EXPECT_TRUE(labels->placed().empty());
}
