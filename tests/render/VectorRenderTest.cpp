// Vector features clamped to the terrain on lavapipe with validation: a line over a ridge seen
// obliquely (on the near slope, hidden behind the ridge, never floating), polygons across the
// antimeridian and around the South Pole, the ground under a drawn line pixel within a pixel of
// the line, no shimmer when the camera moves 1 mm, a rule switched off, bad inputs.
#include "globe/Ellipsoid.h"
#include "layers/terrain/TerrainLayer.h"
#include "layers/vector/VectorLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/SceneGpuTest.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/render/VectorScenes.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace orbis::test {
namespace {

std::string writeGeoJson(const std::string& name, const std::string& features) {
    return test::writeGeoJson("vector-render", name, features);
}

std::string lineFeature(const std::string& name, const std::string& coords) {
    return R"({"type": "Feature", "properties": {"name": ")" + name + R"("}, "geometry": {"type": "LineString", "coordinates": )" +
           coords + "}}";
}

std::string polygonFeature(const std::string& name, const std::string& rings) {
    return R"({"type": "Feature", "properties": {"name": ")" + name + R"("}, "geometry": {"type": "Polygon", "coordinates": )" +
           rings + "}}";
}

std::string sceneJson(const std::string& viewpoint, const std::string& layers, const std::string& time = "2026-06-21T09:30:00Z") {
    return vectorSceneJson(viewpoint, layers, time);
}

std::string mountain(const std::string& extra = "") { return mountainTerrain(extra); }

std::string world() { return worldTerrain(); }

std::string vectorLayer(const std::string& path, const std::string& extra) { return vectorLayerJson("Features", path, extra); }

/// Red-dominant pixels: the test lines' colour over a grey terrain (hazed with distance).
bool isRed(const uint8_t* p) { return int(p[0]) - (int(p[1]) + int(p[2])) / 2 > 40; }

size_t countRed(const ImageRgba8& img) {
    size_t n = 0;
    for (size_t i = 0; i < size_t(img.width) * img.height; ++i) n += isRed(&img.pixels[i * 4]);
    return n;
}

class VectorRender : public SceneGpuTest {
protected:
    ImageRgba8 render(scene::Scene& scene, uint32_t w = 320, uint32_t h = 240) { return renderScene(scene, w, h); }
};

// A line from south to north over the summit, seen from the south, low: it climbs the near
// slope in view and goes behind the ridge. A polygon with a hole on the east flank.
// The mountain three times as high, for a steep near slope.
const char* kRidgeView = R"({"lon": 7.0, "lat": 45.1, "height": 3500, "heading": 0, "pitch": -4, "range": 1})";
const char* kSteep = R"(, "verticalExaggeration": 3)";

std::string ridgeFeatures() {
    return writeGeoJson("ridge.geojson",
                        lineFeature("meridian", "[[7.0, 45.2], [7.0, 46.0], [7.0, 46.7]]") + "," +
                            polygonFeature("flank", "[[[7.2, 45.6], [7.6, 45.6], [7.6, 45.9], [7.2, 45.9], [7.2, 45.6]],"
                                                    "[[7.3, 45.7], [7.5, 45.7], [7.5, 45.8], [7.3, 45.8], [7.3, 45.7]]]"));
}

const char* kRedStyle = R"(, "style": {"color": [1, 0, 0], "width": 3, "fill": [0.1, 0.3, 1.0], "fillOpacity": 0.6})";

TEST_F(VectorRender, LineOverARidgeLiesOnTheSlopeAndHidesBehindIt) {
    auto scene = load(sceneJson(kRidgeView, mountain(kSteep) + "," + vectorLayer(ridgeFeatures(), kRedStyle)));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    EXPECT_TRUE(matchesGolden(img, "vector_ridge"));
    auto& layer = dynamic_cast<layers::VectorLayer&>(*scene->resources()[1].layer);
    ASSERT_NE(layer.content(), nullptr) << layer.error();
    EXPECT_EQ(layer.content()->featureCount, 2u);
    EXPECT_GT(countRed(img), 50u);
}

/// The ground point seen through pixel (x, y): the camera ray marched to the terrain's DEM.
std::optional<globe::Geodetic> groundAt(scene::Scene& scene, double x, double y, uint32_t w, uint32_t h) {
    const auto& ell = globe::Ellipsoid::wgs84();
    const scene::Camera& cam = scene.camera();
    const glm::dvec3 d = cam.rayDirection(2.0 * x / w - 1.0, 2.0 * y / h - 1.0, double(w) / h);
    const auto above = [&](double t) {
        const globe::Geodetic g = ell.toGeodetic(cam.position() + d * t);
        return g.height - scene.heightAt(g.lonDeg, g.latDeg).value_or(0.0);
    };
    double t0 = 0.0;
    for (double t = 10.0; t < 4.0e5; t += std::max(10.0, t * 0.002)) {
        if (above(t) < 0.0) {
            double lo = t0, hi = t;
            for (int i = 0; i < 60; ++i) (above(0.5 * (lo + hi)) < 0.0 ? hi : lo) = 0.5 * (lo + hi);
            return ell.toGeodetic(cam.position() + d * hi);
        }
        t0 = t;
    }
    return std::nullopt;
}

TEST_F(VectorRender, GroundUnderADrawnLineIsWithinAPixelOfTheLine) {
    // A line along the parallel 45.7 on the mountain's south slope, seen from the south:
    // in each column, the centre of the drawn line is where the ground under it is the line.
    const std::string path = writeGeoJson("parallel.geojson", lineFeature("parallel", "[[6.4, 45.7], [7.6, 45.7]]"));
    const char* view = R"({"lon": 7.1, "lat": 45.55, "height": 9000, "heading": 0, "pitch": -30, "range": 1})";
    auto scene = load(sceneJson(view, mountain(R"(, "maxScreenSpaceError": 0.5)") + "," +
                                          vectorLayer(path, R"(, "style": {"color": [1, 0, 0], "width": 3})")));
    ASSERT_TRUE(scene);
    const uint32_t w = 320, h = 240;
    const auto img = render(*scene, w, h);
    const double pixelRad = scene->camera().verticalFovRad() / h;
    size_t columns = 0;
    for (uint32_t x = 0; x < w; x += 4) {
        double sum = 0.0, weighted = 0.0;
        for (uint32_t y = 0; y < h; ++y) {
            const uint8_t* p = &img.pixels[(size_t(y) * w + x) * 4];
            const double redness = std::max(0.0, double(p[0]) - 0.5 * (double(p[1]) + p[2])) / 255.0;
            if (redness < 0.15) continue;
            sum += redness;
            weighted += redness * (y + 0.5);
        }
        if (sum < 0.5) continue;
        const double yc = weighted / sum;
        const auto g = groundAt(*scene, x + 0.5, yc, w, h);
        ASSERT_TRUE(g.has_value()) << "column " << x;
        // The line's point nearest the ground point (same longitude, on the ground), and the angle
        // between the two seen from the eye, in pixels.
        const auto& ell = globe::Ellipsoid::wgs84();
        const glm::dvec3 eye = scene->camera().position();
        const glm::dvec3 ground = ell.toEcef(*g);
        const glm::dvec3 onLine = ell.toEcef(g->lonDeg, 45.7, scene->heightAt(g->lonDeg, 45.7).value_or(0.0));
        const double angle = std::acos(std::clamp(glm::dot(glm::normalize(ground - eye), glm::normalize(onLine - eye)), -1.0, 1.0));
        EXPECT_LT(angle / pixelRad, 1.0) << "column " << x << ": the ground under the line is "
                                         << (g->latDeg - 45.7) * 111132.0 << " m north of it";
        ++columns;
    }
    EXPECT_GT(columns, 40u);
}

TEST_F(VectorRender, MovingTheCameraOneMillimetreChangesNoLinePixel) {
    const auto at = [&](double eastMetres) {
        auto scene = load(sceneJson(kRidgeView, mountain(kSteep) + "," + vectorLayer(ridgeFeatures(), kRedStyle)));
        globe::Pose pose = scene->camera().pose();
        const glm::dvec3 east = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), pose.position));
        scene->camera().setPosition(pose.position + east * eastMetres);
        return scene;
    };
    auto a = at(0.0), b = at(0.001);
    const auto imgA = render(*a), imgB = render(*b);
    ASSERT_GT(countRed(imgA), 50u);
    size_t changed = 0;
    for (size_t i = 0; i < size_t(imgA.width) * imgA.height; ++i) {
        const uint8_t *p = &imgA.pixels[i * 4], *q = &imgB.pixels[i * 4];
        if (!isRed(p) && !isRed(q)) continue;
        for (int c = 0; c < 3; ++c) changed += std::abs(int(p[c]) - int(q[c])) > 2 ? 1 : 0;
    }
    EXPECT_EQ(changed, 0u) << "line pixels shimmer when the camera moves 1 mm";
}

TEST_F(VectorRender, PolygonsAcrossTheAntimeridianAndAroundTheSouthPoleAreWhole) {
    if (!std::filesystem::exists(std::string(ORBIS_SOURCE_DIR) + "/assets/generated/world-relief.tif"))
        GTEST_SKIP() << "assets/generated not built";
    // An island box cut at 180 in two parts (as Natural Earth stores Fiji), and a ring around
    // the South Pole (as Antarctica's outline: its longitude turns once).
    const std::string path = writeGeoJson(
        "whole.geojson",
        R"({"type": "Feature", "properties": {"name": "fiji"}, "geometry": {"type": "MultiPolygon", "coordinates": [)"
        R"([[[176, -20], [180, -20], [180, -14], [176, -14], [176, -20]]], [[[-180, -20], [-177, -20], [-177, -14], [-180, -14], [-180, -20]]]]}},)" +
            polygonFeature("antarctica", "[[[-180, -70], [-90, -72], [0, -70], [90, -72], [180, -70], [-180, -70]]]"));
    const char* style = R"(, "style": {"color": [1, 0, 0], "width": 2, "fill": [1, 0.9, 0.1], "fillOpacity": 0.8})";
    const std::pair<const char*, const char*> views[] = {
        {"vector_antimeridian", R"({"lon": 180, "lat": -17, "range": 2500000})"},
        {"vector_south_pole", R"({"lon": 0, "lat": -90, "range": 9000000})"},
    };
    for (const auto& [name, vp] : views) {
        auto scene = load(sceneJson(vp, world() + "," + vectorLayer(path, style), "2026-12-21T00:00:00Z"));
        ASSERT_TRUE(scene);
        const auto img = render(*scene);
        EXPECT_TRUE(matchesGolden(img, name)) << name;
    }
}

TEST_F(VectorRender, ARuleSwitchedOffHidesItsFeatures) {
    const std::string style =
        R"(, "style": {"color": [1, 0, 0], "width": 3, "fillOpacity": 0, "outline": false,)"
        R"( "rules": [{"name": "hide the meridian", "when": {"name": "meridian"}, "visible": false, "enabled": false}]})";
    auto scene = load(sceneJson(kRidgeView, mountain(kSteep) + "," + vectorLayer(ridgeFeatures(), style)));
    ASSERT_TRUE(scene);
    EXPECT_GT(countRed(render(*scene)), 50u);
    auto* live = scene->resources()[1].layer->asLiveSettings();
    ASSERT_TRUE(live->setParameter("rule0", 1.0));
    EXPECT_EQ(countRed(render(*scene)), 0u);
    const auto settings = live->liveSettings();
    const auto rule = std::find_if(settings.begin(), settings.end(), [](const scene::LayerSetting& x) { return x.name == "rule0"; });
    ASSERT_NE(rule, settings.end());
    EXPECT_EQ(rule->pointer, "/style/rules/0/enabled");
}

TEST_F(VectorRender, DefaultSceneIsTheRealEarthWithItsBorders) {
    // The README's first command: the Blue Marble and the city lights (xplanet-images) placed by
    // "bounds", Natural Earth's borders (qgis-common) on them, dusk over the Middle East.
    for (const char* file : {"/usr/share/xplanet/images/earth.jpg", "/usr/share/xplanet/images/night.jpg",
                             "/usr/share/qgis/resources/data/world_map.gpkg"})
        if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " absent: run tools/install-deps.sh";
    auto desc = scene::parseSceneFile(std::string(ORBIS_SOURCE_DIR) + "/assets/scenes/default.json");
    ASSERT_TRUE(desc.ok()) << desc.message();
    auto scene = scene::Scene::build(std::move(desc).value(), registry_);
    ASSERT_TRUE(scene.ok()) << scene.message();
    const auto img = render(**scene, 640, 360);
    EXPECT_TRUE(matchesGolden(img, "default_real_earth"));
    auto& borders = dynamic_cast<layers::VectorLayer&>(*(*scene)->resources()[1].layer);
    ASSERT_NE(borders.content(), nullptr) << borders.error();
    EXPECT_EQ(borders.content()->layers.size(), 3u);
    EXPECT_GT(borders.content()->featureCount, 4000u);
}

TEST_F(VectorRender, APickedFeatureShowsItsAttributesAndIsHighlighted) {
    auto scene = load(sceneJson(kRidgeView, mountain(kSteep) + "," + vectorLayer(ridgeFeatures(), kRedStyle)));
    ASSERT_TRUE(scene);
    const auto before = render(*scene);
    auto* pickable = scene->resources()[1].layer->asPickable();
    ASSERT_NE(pickable, nullptr);
    // Inside the flank polygon (not in its hole): its attributes, and yellow on the screen.
    const auto picked = pickable->pickAt(7.25, 45.75, 50.0);
    ASSERT_TRUE(picked.has_value());
    EXPECT_EQ(picked->layer, "Features / ridge");
    ASSERT_EQ(picked->fields.size(), 1u);
    EXPECT_EQ(picked->fields[0], (std::pair<std::string, std::string>{"name", "flank"}));
    const auto yellow = [](const ImageRgba8& img) {
        size_t n = 0;
        for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
            const uint8_t* p = &img.pixels[i * 4];
            n += int(p[0]) > int(p[2]) + 30 && int(p[1]) > int(p[2]) + 30;   // yellowish, even hazed
        }
        return n;
    };
    // The frame right after the pick still shows every drape tile (its old image) while the
    // tiles are painted again: no flicker.
    const auto firstFrame = renderOnce(*renderer_, *scene);
    EXPECT_GE(countRed(firstFrame), countRed(before) * 9 / 10) << "drape tiles missing while they were repainted";
    const auto highlighted = render(*scene);
    EXPECT_EQ(yellow(before), 0u);
    EXPECT_GT(yellow(highlighted), 30u);
    // In the hole: nothing, and the highlight goes.
    EXPECT_FALSE(pickable->pickAt(7.4, 45.75, 50.0).has_value());
    EXPECT_EQ(yellow(render(*scene)), 0u);
    // The line, within its width.
    const auto line = pickable->pickAt(7.0 + 20.0 / 78000.0, 45.5, 50.0);
    ASSERT_TRUE(line.has_value());
    EXPECT_EQ(line->fields[0].second, "meridian");
    pickable->clearPick();
}

TEST_F(VectorRender, AKmlKeepsItsOwnStylesUnlessTheSceneOverridesThem) {
    // Shared and inline KML styles (LineStyle, PolyStyle, IconStyle) on the mountain's flank,
    // seen from above; the scene's rule then overrides one feature's line colour only.
    const auto dir = std::filesystem::path(testOutputDir()) / "vector-render";
    std::filesystem::create_directories(dir);
    const std::string kml = (dir / "styled.kml").string();
    std::ofstream(kml) << R"KML(<?xml version="1.0" encoding="UTF-8"?>
<kml xmlns="http://www.opengis.net/kml/2.2"><Document>
  <Style id="park"><LineStyle><color>ff00c000</color><width>3</width></LineStyle><PolyStyle><color>9900ff00</color></PolyStyle></Style>
  <Style id="hut"><IconStyle><color>ff00ffff</color><scale>1.6</scale></IconStyle></Style>
  <Placemark><name>Park</name><styleUrl>#park</styleUrl><Polygon><outerBoundaryIs><LinearRing>
    <coordinates>6.7,45.8 6.9,45.8 6.9,45.95 6.7,45.95 6.7,45.8</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>
  <Placemark><name>Trail</name><Style><LineStyle><color>ffff00ff</color><width>4</width></LineStyle></Style>
    <LineString><coordinates>6.75,46.05 7.0,46.0 7.25,46.1</coordinates></LineString></Placemark>
  <Placemark><name>Road</name><Style><LineStyle><color>ffffffff</color><width>3</width></LineStyle></Style>
    <LineString><coordinates>6.7,46.15 7.3,46.15</coordinates></LineString></Placemark>
  <Placemark><name>Hut</name><styleUrl>#hut</styleUrl><Point><coordinates>7.1,45.85,0</coordinates></Point></Placemark>
</Document></kml>)KML";
    const char* top = R"({"lon": 7.0, "lat": 46.0, "pitch": -90, "range": 90000})";
    auto scene = load(sceneJson(top, mountain() + "," + vectorLayer(kml,
        R"(, "style": {"rules": [{"name": "roads in orange", "when": {"Name": "Road"}, "color": [1, 0.5, 0]}]})")));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    EXPECT_TRUE(matchesGolden(img, "vector_kml_styles"));
    auto& layer = dynamic_cast<layers::VectorLayer&>(*scene->resources()[1].layer);
    ASSERT_NE(layer.content(), nullptr) << layer.error();
    EXPECT_EQ(layer.content()->featureCount, 4u);
}

TEST_F(VectorRender, PointsShowTheirIconsWithTheirLabelsBesideAndATrailIsDashed) {
    // A KML whose IconStyle names a PNG beside it (a hut: a dark red roof over an orange wall,
    // transparent around), labelled from the scene; one placemark's icon is missing: a marker.
    // A dashed trail joins the huts.
    const auto hut = writeIcon("vector-render", "hut.png", 32, 32, [](int x, int y, uint8_t* t) {
        const bool roof = y >= 2 && y < 14 && std::abs(x - 16) <= (y - 2) * 14 / 12;
        const bool wall = y >= 14 && y < 30 && x >= 6 && x < 26;
        if (roof) t[0] = 150, t[1] = 20, t[2] = 20, t[3] = 255;
        if (wall) t[0] = 255, t[1] = 140, t[2] = 0, t[3] = 255;
    });
    ASSERT_FALSE(hut.empty());
    const auto dir = hut.parent_path();
    const std::string kml = (dir / "huts.kml").string();
    std::ofstream(kml) << R"KML(<?xml version="1.0" encoding="UTF-8"?>
<kml xmlns="http://www.opengis.net/kml/2.2"><Document>
  <Style id="hut"><IconStyle><scale>1.5</scale><Icon><href>hut.png</href></Icon></IconStyle></Style>
  <Style id="lost"><IconStyle><Icon><href>no-such-icon.png</href></Icon></IconStyle></Style>
  <Placemark><name>Refuge A</name><styleUrl>#hut</styleUrl><Point><coordinates>6.85,45.9,0</coordinates></Point></Placemark>
  <Placemark><name>Refuge B</name><styleUrl>#hut</styleUrl><Point><coordinates>7.15,46.1,0</coordinates></Point></Placemark>
  <Placemark><name>Refuge C</name><styleUrl>#hut</styleUrl><Point><coordinates>6.95,46.2,0</coordinates></Point></Placemark>
  <Placemark><name>Lost</name><styleUrl>#lost</styleUrl><Point><coordinates>7.2,45.85,0</coordinates></Point></Placemark>
  <Placemark><name>Trail</name><LineString><coordinates>6.85,45.9 6.95,46.05 7.15,46.1 6.95,46.2</coordinates></LineString></Placemark>
</Document></kml>)KML";
    const char* top = R"({"lon": 7.0, "lat": 46.0, "pitch": -90, "range": 90000})";
    auto scene = load(sceneJson(top, mountain() + "," +
                                         vectorLayer(kml, R"(, "style": {"color": [0.2, 0.6, 1], "label": "{Name}", "rules": [)"
                                                          R"({"when": {"Name": "Trail"}, "color": [1, 1, 1], "width": 3, "dash": [10, 6]}]})")));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    EXPECT_TRUE(matchesGolden(img, "vector_icons"));
    auto& layer = dynamic_cast<layers::VectorLayer&>(*scene->resources()[1].layer);
    ASSERT_NE(layer.content(), nullptr) << layer.error();
    size_t orange = 0;
    for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
        const uint8_t* p = &img.pixels[i * 4];
        orange += int(p[0]) > int(p[1]) + 40 && int(p[1]) > int(p[2]) + 30;   // the walls, shaded by the terrain
    }
    EXPECT_GT(orange, 3u * 60u) << "three huts' walls, some 9 x 8 px each at this size";
    EXPECT_NE(layer.status().find("1 icon(s) unreadable"), std::string::npos) << layer.status();
    EXPECT_NE(layer.status().find("no-such-icon.png"), std::string::npos) << layer.status();
}

TEST_F(VectorRender, BadInputsNameTheFileAndTheKey) {
    // A missing file: the scene names it.
    auto desc = scene::parseSceneText(sceneJson(kRidgeView, mountain() + "," + vectorLayer("/nonexistent/roads.shp", "")), "test.json", ".");
    ASSERT_TRUE(desc.ok());
    auto missing = scene::Scene::build(std::move(desc).value(), registry_);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.message().find("/nonexistent/roads.shp"), std::string::npos) << missing.message();
    // An unknown altitude mode, a value out of range and a bad key: errors naming the key.
    for (const char* extra : {R"(, "altitude": "above")", R"(, "opacity": 3)", R"(, "extrusionScale": -1)", R"(, "colour": [1, 0, 0])"}) {
        auto d = scene::parseSceneText(sceneJson(kRidgeView, mountain(kSteep) + "," + vectorLayer(ridgeFeatures(), extra)), "test.json", ".");
        ASSERT_TRUE(d.ok());
        auto s = scene::Scene::build(std::move(d).value(), registry_);
        ASSERT_FALSE(s.ok()) << extra;
        EXPECT_NE(s.message().find("/layers/1/"), std::string::npos) << s.message();
    }
    // A glide that is neither "auto", seconds from 0 to 60 nor false: the key and what it takes.
    for (const char* glide : {R"("fast")", "-1", "61", "true", "[1]"}) {
        auto d = scene::parseSceneText(
            sceneJson(kRidgeView, mountain() + "," + vectorLayer(ridgeFeatures(), std::string(R"(, "refresh": {"everySeconds": 1, "glide": )") + glide + "}")),
            "test.json", ".");
        ASSERT_TRUE(d.ok());
        auto s = scene::Scene::build(std::move(d).value(), registry_);
        ASSERT_FALSE(s.ok()) << glide;
        EXPECT_NE(s.message().find("/layers/1/refresh/glide"), std::string::npos) << s.message();
        EXPECT_NE(s.message().find("seconds from 0 to 60"), std::string::npos) << s.message();
    }
    // A rule on a field the data lacks: the layer reports it and draws nothing.
    auto scene = load(sceneJson(kRidgeView, mountain() + "," +
                                              vectorLayer(ridgeFeatures(), R"(, "style": {"rules": [{"when": {"lanes": 2}}]})")));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    auto& layer = dynamic_cast<layers::VectorLayer&>(*scene->resources()[1].layer);
    EXPECT_EQ(layer.content(), nullptr);
    EXPECT_NE(layer.error().find("lanes"), std::string::npos) << layer.error();
    EXPECT_NE(layer.status().find("error"), std::string::npos);
}

}  // namespace
}  // namespace orbis::test
