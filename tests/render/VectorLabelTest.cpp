// The vector layer's labels on lavapipe with validation: real glyphs (accented, Greek and
// Cyrillic names) with a halo over the world (golden); no two drawn labels overlap, across
// layers; a slow pan changes the labels only where a box crosses a threshold of the hysteresis;
// a label behind the globe or behind a mountain is not drawn; a style without a label builds
// nothing for labels; the "labels" setting and scene key.
#include "engine/gpu/Device.h"
#include "globe/Ellipsoid.h"
#include "layers/vector/VectorLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/SceneGpuTest.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/render/VectorScenes.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace orbis::test {
namespace {

using vector::LabelCandidate;
constexpr double kPi = 3.14159265358979323846;
using vector::PlacedLabel;

std::string writeGeoJson(const std::string& name, const std::string& features) {
    return test::writeGeoJson("vector-label", name, features);
}

std::string feature(const std::string& name, const std::string& type, const std::string& coords) {
    return R"({"type": "Feature", "properties": {"name": )" + jsonString(name) + R"(}, "geometry": {"type": ")" + type +
           R"(", "coordinates": )" + coords + "}}";
}

// Built with streams: GCC 12 warns (wrongly, -Wrestrict) about `"..." + std::to_string(x)` here.
std::string cityName(const char* prefix, int n) {
    std::ostringstream s;
    s << prefix << n;
    return s.str();
}

std::string pointFeature(const std::string& name, double lon, double lat) {
    std::ostringstream coords;
    coords << "[" << lon << ", " << lat << "]";
    return feature(name, "Point", coords.str());
}

void addFeature(std::string& list, const std::string& feature) {
    if (!list.empty()) list += ',';
    list += feature;
}

std::string sceneJson(const std::string& viewpoint, const std::string& layers, const std::string& time = "2026-06-21T12:00:00Z") {
    return vectorSceneJson(viewpoint, layers, time);
}

bool haveWorld() { return std::filesystem::exists(std::string(ORBIS_SOURCE_DIR) + "/assets/generated/world-relief.tif"); }

std::string world() { return worldTerrain(); }

std::string mountain() { return mountainTerrain(); }

const char* kGlobe = R"({"type": "globe", "name": "Earth"})";

std::string vectorLayer(const std::string& name, const std::string& path, const std::string& extra) {
    return vectorLayerJson(name, path, extra);
}

/// Cities (points, with their icons) and regions (polygons and a line), in two layers.
std::string cities() {
    return writeGeoJson("cities.geojson", pointFeature("São Paulo", -46.63, -23.55) + "," + pointFeature("Αθήνα", 23.73, 37.98) +
                                              "," + pointFeature("Москва", 37.62, 55.75) + "," +
                                              pointFeature("Reykjavík", -21.94, 64.15) + "," + pointFeature("Dakar", -17.45, 14.69) +
                                              "," + pointFeature("Zürich", 8.54, 47.37));
}

std::string regions() {
    return writeGeoJson(
        "regions.geojson",
        // A "C" open to the east: its centroid is outside it, its label must not be.
        feature("Sahara", "Polygon", "[[[-12, 16], [28, 16], [28, 20], [-4, 20], [-4, 27], [28, 27], [28, 31], [-12, 31], [-12, 16]]]") +
            "," + feature("Amazônia", "Polygon", "[[[-72, -12], [-48, -12], [-48, 2], [-72, 2], [-72, -12]], [[-64, -7], [-56, -7], [-56, -3], [-64, -3], [-64, -7]]]") +
            "," + feature("Equatorial", "LineString", "[[4, 3], [-13, 1], [-28, -3], [-40, -9]]"));
}

const char* kCityStyle = R"(, "style": {"color": [1, 0.85, 0.1], "iconSize": 8, "label": "{name}", "labelSize": 14})";
const char* kRegionStyle =
    R"(, "style": {"color": [1, 1, 1], "width": 1.5, "fill": [0.2, 0.6, 1.0], "fillOpacity": 0.3, "label": "{name}",)"
    R"( "labelSize": 13, "labelColor": [0.75, 0.95, 1.0]})";
const char* kWorldView = R"({"lon": -12, "lat": 18, "range": 15000000})";

class VectorLabel : public SceneGpuTest {
protected:
    ImageRgba8 render(scene::Scene& scene, uint32_t w = 480, uint32_t h = 320) { return renderScene(scene, w, h); }
    static layers::VectorLayer& vectorAt(scene::Scene& scene, size_t i) {
        return dynamic_cast<layers::VectorLayer&>(*scene.resources()[i].layer);
    }
    /// Every label drawn this frame by the scene's vector layers.
    static std::vector<PlacedLabel> placedLabels(scene::Scene& scene) {
        std::vector<PlacedLabel> out;
        for (auto& r : scene.resources())
            if (auto* v = dynamic_cast<layers::VectorLayer*>(r.layer.get()); v && v->labels())
                out.insert(out.end(), v->labels()->placed().begin(), v->labels()->placed().end());
        return out;
    }
};

bool overlap(glm::dvec2 amin, glm::dvec2 amax, glm::dvec2 bmin, glm::dvec2 bmax) {
    return amin.x < bmax.x && bmin.x < amax.x && amin.y < bmax.y && bmin.y < amax.y;
}

TEST_F(VectorLabel, GlyphsWithHalosOverTheWorld) {
    if (!haveWorld()) GTEST_SKIP() << "assets/generated not built";
    auto scene = load(sceneJson(kWorldView, world() + "," + vectorLayer("Regions", regions(), kRegionStyle) + "," +
                                                vectorLayer("Cities", cities(), kCityStyle)));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    // Text edges are smoothed over a pixel from the distance field: lavapipe is deterministic,
    // the default tolerance (5/255 on 0.1 % of the pixels) absorbs rounding.
    EXPECT_TRUE(matchesGolden(img, "vector_labels_world"));

    // Every city is labelled: the names in Latin with accents, Greek and Cyrillic.
    auto& cityLayer = vectorAt(*scene, 2);
    ASSERT_NE(cityLayer.labels(), nullptr);
    std::set<uint32_t> cityFeatures;
    for (const PlacedLabel& p : cityLayer.labels()->placed()) cityFeatures.insert(p.feature);
    EXPECT_TRUE(cityFeatures.count(0) && cityFeatures.count(1) && cityFeatures.count(2)) << "São Paulo, Αθήνα, Москва";
    EXPECT_TRUE(cityLayer.drawsIn(scene::Pass::Overlay));
    // The regions' polygons are labelled at interior points: the Sahara's "C" around its arms,
    // Amazônia away from its hole.
    auto& regionLayer = vectorAt(*scene, 1);
    ASSERT_NE(regionLayer.labels(), nullptr);
    EXPECT_GE(regionLayer.labels()->placed().size(), 2u);
    ASSERT_NE(regionLayer.content(), nullptr);
    const vector::ContentAnchors anchors = vector::labelAnchors(*regionLayer.content());
    const vector::LabelAnchor& sahara = anchors[0][0];
    const bool inArm = (sahara.lonLat.y > 16 && sahara.lonLat.y < 20) || (sahara.lonLat.y > 27 && sahara.lonLat.y < 31) ||
                       (sahara.lonLat.x > -12 && sahara.lonLat.x < -4);
    EXPECT_TRUE(inArm) << sahara.lonLat.x << ", " << sahara.lonLat.y;
}

TEST_F(VectorLabel, NoTwoDrawnLabelsOverlapAcrossLayers) {
    // Many labels in little room: a grid of cities over Europe and the regions under them, on
    // the bare globe (no terrain needed for placement).
    std::string grid;
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 12; ++i)
            addFeature(grid, pointFeature(cityName("Città ", j * 12 + i), -5.0 + 3.0 * i, 38.0 + 2.0 * j));
    const std::string path = writeGeoJson("grid.geojson", grid);
    auto scene = load(sceneJson(R"({"lon": 12, "lat": 47, "range": 5000000})",
                                std::string(kGlobe) + "," + vectorLayer("Regions", regions(), kRegionStyle) + "," +
                                    vectorLayer("Grid", path, kCityStyle)));
    ASSERT_TRUE(scene);
    render(*scene);
    const auto placed = placedLabels(*scene);
    const size_t candidates = vectorAt(*scene, 1).labels()->stats().candidates + vectorAt(*scene, 2).labels()->stats().candidates;
    ASSERT_GT(placed.size(), 10u);
    EXPECT_LT(placed.size(), candidates) << "more candidates than room: some must be left out";
    for (size_t a = 0; a < placed.size(); ++a) {
        EXPECT_TRUE(placed[a].min.x >= 0.0 && placed[a].min.y >= 0.0 && placed[a].max.x <= 480.0 && placed[a].max.y <= 320.0);
        for (size_t b = a + 1; b < placed.size(); ++b)
            ASSERT_FALSE(overlap(placed[a].min, placed[a].max, placed[b].min, placed[b].max))
                << std::hex << placed[a].id << " and " << placed[b].id;
    }
}

/// What the placer's hysteresis reacts to, for one frame's candidates: for each candidate, whether
/// its box is on screen and whether it is on screen by the margin; for each pair, whether the
/// boxes overlap and whether they come within the margin of each other.
struct Thresholds {
    std::map<uint64_t, std::pair<bool, bool>> edges;
    std::set<std::pair<uint64_t, uint64_t>> overlapping, withinMargin;

    static Thresholds of(std::span<const LabelCandidate> c, glm::dvec2 screen, double m) {
        Thresholds t;
        for (const LabelCandidate& a : c) {
            const auto inside = [&](double g) {
                return a.min.x - g >= 0.0 && a.min.y - g >= 0.0 && a.max.x + g <= screen.x && a.max.y + g <= screen.y;
            };
            t.edges[a.id] = {inside(0.0), inside(m)};
        }
        for (const LabelCandidate& a : c)
            for (const LabelCandidate& b : c) {
                if (a.id >= b.id) continue;
                if (overlap(a.min, a.max, b.min, b.max)) t.overlapping.insert({a.id, b.id});
                if (overlap(a.min - m, a.max + m, b.min, b.max)) t.withinMargin.insert({a.id, b.id});
            }
        return t;
    }
    bool operator==(const Thresholds& o) const {
        return edges == o.edges && overlapping == o.overlapping && withinMargin == o.withinMargin;
    }
};

TEST_F(VectorLabel, ASlowPanChangesTheLabelsOnlyWhereABoxCrossesAThreshold) {
    // 21 x 11 labelled points over a region wider than the view: labels cross the screen's
    // edges as the view pans 0.2 px a frame for 40 frames (8 px).
    std::string grid;
    for (int j = 0; j < 11; ++j)
        for (int i = 0; i < 21; ++i)
            addFeature(grid, pointFeature(cityName("Ort ", j * 21 + i), -30.0 + 4.0 * i, 30.0 + 3.0 * j));
    const std::string path = writeGeoJson("pan.geojson", grid);
    auto scene = load(sceneJson(R"({"lon": 10, "lat": 45, "range": 3000000})", std::string(kGlobe) + "," + vectorLayer("Grid", path, kCityStyle)));
    ASSERT_TRUE(scene);
    const uint32_t w = 480, h = 320;
    render(*scene, w, h);
    auto& layer = vectorAt(*scene, 1);
    ASSERT_NE(layer.labels(), nullptr);
    const double margin = layer.labels()->options().marginPx;

    // Sideways by the distance that moves the view's centre 0.2 px.
    scene::Camera& camera = scene->camera();
    const double toCentre = glm::length(camera.position()) - globe::Ellipsoid::wgs84().equatorialRadius();
    const double metresPerPixel = 2.0 * toCentre * std::tan(0.5 * camera.verticalFovRad()) / h;
    const glm::dvec3 step = camera.right() * (0.2 * metresPerPixel);

    const auto snapshot = [&] {
        std::vector<LabelCandidate> c(layer.labels()->candidates().begin(), layer.labels()->candidates().end());
        std::set<uint64_t> shown;
        for (const PlacedLabel& p : layer.labels()->placed()) shown.insert(p.id);
        return std::pair{c, shown};
    };
    auto [candidates, shown] = snapshot();
    ASSERT_GT(shown.size(), 10u);
    Thresholds before = Thresholds::of(candidates, {w, h}, margin);
    const glm::dvec2 firstCentre = 0.5 * (candidates[0].min + candidates[0].max);
    int changes = 0, crossings = 0;
    for (int f = 1; f <= 40; ++f) {
        camera.setPosition(camera.position() + step);
        renderer_->render(*scene, false);
        auto [c, now] = snapshot();
        const Thresholds after = Thresholds::of(c, {w, h}, margin);
        const bool crossed = !(after == before);
        crossings += crossed ? 1 : 0;
        if (now != shown) {
            ++changes;
            EXPECT_TRUE(crossed) << "frame " << f << ": the labels changed though no box crossed a threshold";
        }
        shown = std::move(now);
        before = after;
        candidates = std::move(c);
    }
    // The pan really moved the labels about 8 px, and crossed thresholds in some frames only.
    const glm::dvec2 lastCentre = 0.5 * (candidates[0].min + candidates[0].max);
    EXPECT_NEAR(glm::length(lastCentre - firstCentre), 8.0, 4.0);
    EXPECT_GE(crossings, 1);
    EXPECT_LE(crossings, 30) << "too many crossings for the test to say anything";
    EXPECT_GE(changes, 1) << "labels crossed the screen's edge: some must have changed";
    EXPECT_LE(changes, crossings);
    EXPECT_LE(changes, 8) << "a slow pan flickers";
}

TEST_F(VectorLabel, ALineLabelFollowsTheLineWhereItBendsAndStaysUpright) {
    // A rainbow: half a circle of 10 degrees around (0, 0), drawn from east to west, seen from
    // 3000 km. Its label reads left to right over the top, each glyph turned with the arc (the
    // first rising, the last falling); a line straight on the screen (the equator under the
    // eye) has all its glyphs at one angle.
    std::ostringstream arc, straight;
    arc << "[";
    for (int i = 0; i <= 36; ++i) {
        const double t = kPi * i / 36.0;
        arc << (i ? ", " : "") << "[" << 10.0 * std::cos(t) << ", " << 10.0 * std::sin(t) << "]";
    }
    arc << "]";
    straight << "[[-12, 0], [12, 0]]";   // the equator below the eye: straight on the screen
    const char* style = R"(, "style": {"width": 2, "label": "{name}", "labelSize": 16})";
    const auto angles = [&](const std::string& coords) {
        const std::string path = writeGeoJson("bend.geojson", feature("Curving river", "LineString", coords));
        auto scene = load(sceneJson(R"({"lon": 0, "lat": 0, "range": 3000000})", std::string(kGlobe) + "," + vectorLayer("Bend", path, style)));
        std::vector<double> out;
        if (!scene) return out;
        render(*scene);
        for (const shader::LabelGlyph& g : vectorAt(*scene, 1).labels()->glyphs()) out.push_back(std::atan2(g.axisX.y, g.axisX.x) * 180.0 / kPi);
        return out;
    };
    const std::vector<double> bent = angles(arc.str());
    ASSERT_GE(bent.size(), 10u) << "the label is drawn";
    for (size_t i = 0; i < bent.size(); ++i) {
        EXPECT_LT(std::abs(bent[i]), 90.0) << "upright";
        if (i > 0) {
            EXPECT_LE(std::abs(bent[i] - bent[i - 1]), 25.0) << "a gentle bend between neighbours";
        }
    }
    // Over the top of the rainbow: rising (negative: the window's y points down), then falling.
    EXPECT_LT(bent.front(), -8.0);
    EXPECT_GT(bent.back(), 8.0);
    const std::vector<double> flat = angles(straight.str());
    ASSERT_GE(flat.size(), 10u);
    for (double a : flat) EXPECT_NEAR(a, flat.front(), 0.5);
}

TEST_F(VectorLabel, ALabelBehindTheGlobeIsNotDrawn) {
    // From 20 000 km over (0, 0) the near side reaches ~76 degrees: a point at 95 E projects
    // inside the globe's disk but lies behind it; one at 60 E is in sight.
    const std::string path = writeGeoJson("far.geojson", pointFeature("Near", 60.0, 0.0) + "," + pointFeature("Far", 95.0, 0.0));
    auto scene = load(sceneJson(R"({"lon": 0, "lat": 0, "range": 20000000})", std::string(kGlobe) + "," + vectorLayer("Far", path, kCityStyle)));
    ASSERT_TRUE(scene);
    render(*scene);
    const auto& labels = *vectorAt(*scene, 1).labels();
    ASSERT_EQ(labels.placed().size(), 1u);
    EXPECT_EQ(labels.placed()[0].feature, 0u);
    EXPECT_EQ(labels.stats().candidates, 1u) << "the far one is below the horizon: not even a candidate";
}

TEST_F(VectorLabel, ALabelBehindAMountainIsNotDrawn) {
    // Low (1200 m) south of the fixture's 4000 m peak at (7, 46), looking north: a point on the
    // far side, right behind the peak, is on the screen and above the horizon, but the mountain
    // hides it; one on the near slope is drawn.
    const std::string path = writeGeoJson(
        "behind.geojson", pointFeature("Hinter dem Berg", 7.0, 46.5) + "," + pointFeature("Vorne", 6.85, 45.8));
    auto scene = load(sceneJson(R"({"lon": 7.0, "lat": 45.5, "height": 1200, "heading": 0, "pitch": 2, "range": 1})",
                                mountain() + "," + vectorLayer("Labels", path, kCityStyle)));
    ASSERT_TRUE(scene);
    render(*scene);
    const auto& labels = *vectorAt(*scene, 1).labels();
    EXPECT_EQ(labels.stats().candidates, 2u) << "both are on the screen and in front of the eye";
    ASSERT_EQ(labels.placed().size(), 1u);
    EXPECT_EQ(labels.placed()[0].feature, 1u);
    EXPECT_EQ(labels.stats().hidden, 1u) << "the one behind the peak was hidden by the terrain";
}

TEST_F(VectorLabel, AStyleWithoutALabelBuildsNothingForLabels) {
    const std::string path = writeGeoJson("plain.geojson", pointFeature("Athína", 23.73, 37.98));
    const int pipelinesBefore = device().counters().pipelinesEverCreated.load();
    auto plain = load(sceneJson(R"({"lon": 23, "lat": 38, "range": 3000000})",
                                std::string(kGlobe) + "," + vectorLayer("Plain", path, R"(, "style": {"iconSize": 8})")));
    ASSERT_TRUE(plain);
    render(*plain);
    auto& layer = vectorAt(*plain, 1);
    EXPECT_FALSE(layer.hasLabelRenderer());
    EXPECT_EQ(layer.labels(), nullptr);
    EXPECT_FALSE(layer.drawsIn(scene::Pass::Overlay));
    const int pipelinesPlain = device().counters().pipelinesEverCreated.load() - pipelinesBefore;

    // The same with a label: the two label pipelines more, and it draws in the Overlay pass.
    auto labelled = load(sceneJson(R"({"lon": 23, "lat": 38, "range": 3000000})",
                                   std::string(kGlobe) + "," + vectorLayer("Labelled", path, kCityStyle)));
    ASSERT_TRUE(labelled);
    renderer_.reset();   // a new renderer for each scene: the same pipelines of its own
    const int before = device().counters().pipelinesEverCreated.load();
    render(*labelled);
    EXPECT_EQ(device().counters().pipelinesEverCreated.load() - before, pipelinesPlain + 2);
    EXPECT_TRUE(vectorAt(*labelled, 1).hasLabelRenderer());
    EXPECT_TRUE(vectorAt(*labelled, 1).drawsIn(scene::Pass::Overlay));
}

TEST_F(VectorLabel, TheLabelsSettingAndSceneKeyHideThem) {
    const std::string path = writeGeoJson("toggle.geojson", pointFeature("Αθήνα", 23.73, 37.98));
    auto scene = load(sceneJson(R"({"lon": 23, "lat": 38, "range": 3000000})",
                                std::string(kGlobe) + "," + vectorLayer("Cities", path, std::string(kCityStyle) + R"(, "labels": false)")));
    ASSERT_TRUE(scene);
    const auto hidden = render(*scene);
    auto& layer = vectorAt(*scene, 1);
    EXPECT_FALSE(layer.drawsIn(scene::Pass::Overlay));
    EXPECT_TRUE(layer.labels()->placed().empty());
    const auto settings = layer.liveSettings();
    const auto it = std::find_if(settings.begin(), settings.end(), [](const scene::LayerSetting& s) { return s.name == "labels"; });
    ASSERT_NE(it, settings.end());
    EXPECT_EQ(it->kind, scene::LayerSetting::Kind::Toggle);
    EXPECT_EQ(it->value, 0.0);
    EXPECT_EQ(it->jsonPointer(), "/labels");

    ASSERT_TRUE(layer.setParameter("labels", 1.0));
    const auto shown = render(*scene);
    EXPECT_TRUE(layer.drawsIn(scene::Pass::Overlay));
    EXPECT_EQ(layer.labels()->placed().size(), 1u);
    EXPECT_GT(countDifferentPixels(hidden, shown, 40), 50u) << "the label's pixels";
    EXPECT_FALSE(layer.setParameter("labels", 0.5));
}

}  // namespace
}  // namespace orbis::test
