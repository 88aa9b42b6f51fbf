// Extruded buildings and polygons at altitude on lavapipe with validation: a village of
// buildings on the mountain's slope, lit by the morning sun, with a polygon, a line and points
// floating above the ground (golden); each building's walls reach the terrain's ground;
// a picked building turns yellow; the extrusion scale raises the roofs; a point at altitude shows
// its icon upright, as wide as it is, scaled with the range; a line at altitude is dashed as its
// style says; a layer without meshes builds no mesh pipeline, and a layer made only of meshes
// no drape.
#include "base/Png.h"
#include "globe/Ellipsoid.h"
#include "layers/vector/VectorLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/SceneGpuTest.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/render/VectorScenes.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <sstream>

namespace orbis::test {
namespace {

/// A 5 x 5 village on the mountain's southern slope around (7.0, 45.86): squares of ~150 m,
/// 350 m apart, "height" from 40 to 280 m; the centre one has a courtyard (a hole).
std::string village() {
    std::ostringstream s;
    const double dLon = 0.0045, dLat = 0.00315, sizeLon = 0.0019, sizeLat = 0.00135;
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) {
            const double lon = 6.99 + i * dLon, lat = 45.85 + j * dLat;
            const int height = 40 + 10 * ((i * 7 + j * 3) % 25);
            if (i || j) s << ",";
            s << R"({"type": "Feature", "properties": {"name": "b)" << i << j << R"(", "height": )" << height
              << R"(}, "geometry": {"type": "Polygon", "coordinates": [[)";
            s << "[" << lon << "," << lat << "],[" << lon + sizeLon << "," << lat << "],[" << lon + sizeLon << "," << lat + sizeLat
              << "],[" << lon << "," << lat + sizeLat << "],[" << lon << "," << lat << "]]";
            if (i == 2 && j == 2) {
                const double a = lon + sizeLon * 0.3, b = lon + sizeLon * 0.7, c = lat + sizeLat * 0.3, d = lat + sizeLat * 0.7;
                s << ",[[" << a << "," << c << "],[" << a << "," << d << "],[" << b << "," << d << "],[" << b << "," << c << "],[" << a
                  << "," << c << "]]";
            }
            s << "]}}";
        }
    return writeGeoJson("vector-mesh", "village.geojson", s.str());
}

/// Relative to the ground: a rectangle of 1 x 0.7 km 400 m above it, west of the village; a
/// line 250 m above it across the village from west to east; three points 350 m above it.
std::string floating() {
    return writeGeoJson(
        "vector-mesh", "floating.geojson",
        R"({"type": "Feature", "properties": {"name": "zone"}, "geometry": {"type": "Polygon", "coordinates": )"
        R"([[[6.972, 45.858, 400], [6.985, 45.858, 400], [6.985, 45.864, 400], [6.972, 45.864, 400], [6.972, 45.858, 400]]]}},)"
        R"({"type": "Feature", "properties": {"name": "cable"}, "geometry": {"type": "LineString", "coordinates": )"
        R"([[6.975, 45.853, 250], [7.0, 45.858, 250], [7.02, 45.856, 250]]}},)"
        R"({"type": "Feature", "properties": {"name": "beacons"}, "geometry": {"type": "MultiPoint", "coordinates": )"
        R"([[6.995, 45.852, 350], [7.005, 45.852, 350], [7.015, 45.852, 350]]}})");
}

// From the south, 3 km from the village and above it, looking north and down.
const char* kVillageView = R"({"lon": 7.0, "lat": 45.835, "height": 3800, "heading": 0, "pitch": -12, "range": 1})";
const char* kBuildingStyle = R"(, "style": {"fill": [0.85, 0.78, 0.68], "extrude": "height"})";

class VectorMesh : public SceneGpuTest {
protected:
    ImageRgba8 render(scene::Scene& scene, uint32_t w = 320, uint32_t h = 240) { return renderScene(scene, w, h); }
    std::unique_ptr<scene::Scene> villageScene(const std::string& extra = "") {
        return load(vectorSceneJson(kVillageView,
                                    mountainTerrain() + "," + vectorLayerJson("Village", village(), kBuildingStyle + extra) + "," +
                                        vectorLayerJson("Zone", floating(),
                                                        R"(, "altitude": "relative", "style": {"fill": [0.2, 0.5, 1.0], "color": [1, 0.2, 0.1], "width": 3, "iconSize": 10})"),
                                    "2026-06-21T07:30:00Z"));
    }
};

layers::VectorLayer& vectorAt(scene::Scene& scene, size_t i) { return dynamic_cast<layers::VectorLayer&>(*scene.resources()[i].layer); }

double highestVertex(const vector::FeatureMesh& mesh) {
    double top = -1e9;
    for (const vector::MeshChunk& c : mesh.chunks)
        for (const auto& v : c.vertices)
            top = std::max(top, globe::Ellipsoid::wgs84().toGeodetic(c.origin + glm::dvec3(v.position)).height);
    return top;
}

TEST_F(VectorMesh, AVillageOfBuildingsAndAFloatingPolygonOverTheTerrain) {
    auto scene = villageScene();
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    EXPECT_TRUE(matchesGolden(img, "vector_buildings"));
    auto& village = vectorAt(*scene, 1);
    ASSERT_NE(village.mesh(), nullptr) << village.error();
    EXPECT_EQ(village.mesh()->features, 25u);
    EXPECT_TRUE(village.hasMeshRenderer());
    EXPECT_EQ(village.drapeSource(), nullptr) << "every feature is a building: nothing to paint on the terrain";
    auto& zone = vectorAt(*scene, 2);
    ASSERT_NE(zone.mesh(), nullptr) << zone.error();
    EXPECT_EQ(zone.mesh()->features, 3u);
    EXPECT_EQ(zone.mesh()->markers, 3u);
    EXPECT_EQ(zone.mesh()->segments, 2u);
    EXPECT_EQ(zone.drapeSource(), nullptr) << "everything in 3-D";
    // The zone's surface: the ground under its corners plus 400 m (the highest corner's).
    double ground = -1e9;
    for (const double lon : {6.972, 6.985})
        for (const double lat : {45.858, 45.864}) ground = std::max(ground, TerrainFixtures::height(lon, lat));
    EXPECT_NEAR(highestVertex(*zone.mesh()), ground + 400.0, 2.0);
    // The line and the points stand out red over the grey terrain and the pale buildings.
    size_t red = 0;
    for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
        const uint8_t* p = &img.pixels[i * 4];
        red += int(p[0]) > 150 && int(p[1]) < 90 && int(p[2]) < 90;
    }
    EXPECT_GT(red, 150u);
}

TEST_F(VectorMesh, BuildingsStandOnTheGroundTheTerrainDraws) {
    // Each building's walls reach from below the lowest ground under its corners (the terrain
    // layer's ground, which the drawn terrain approximates) up to its roof: the highest
    // corner's ground plus its height.
    auto scene = villageScene();
    ASSERT_TRUE(scene);
    render(*scene);
    const vector::FeatureMesh* mesh = vectorAt(*scene, 1).mesh();
    ASSERT_NE(mesh, nullptr);
    std::map<uint32_t, std::pair<double, double>> span;   // feature id: lowest, highest vertex
    for (const vector::MeshChunk& c : mesh->chunks)
        for (const auto& v : c.vertices) {
            const double h = globe::Ellipsoid::wgs84().toGeodetic(c.origin + glm::dvec3(v.position)).height;
            auto [it, added] = span.try_emplace(v.feature, h, h);
            it->second = {std::min(it->second.first, h), std::max(it->second.second, h)};
        }
    ASSERT_EQ(span.size(), 25u);
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) {
            const double lon = 6.99 + i * 0.0045, lat = 45.85 + j * 0.00315;
            double low = 1e9, high = -1e9;
            for (const double x : {lon, lon + 0.0019})
                for (const double y : {lat, lat + 0.00135}) {
                    low = std::min(low, TerrainFixtures::height(x, y));
                    high = std::max(high, TerrainFixtures::height(x, y));
                }
            const double height = 40 + 10 * ((i * 7 + j * 3) % 25);
            // GeoJSON order: feature j * 5 + i, ids from 1.
            const auto [bottom, top] = span.at(uint32_t(j * 5 + i + 1));
            // The DEM holds whole metres (Int16): 0.5 m of rounding, and its bilinear samples.
            EXPECT_LT(bottom, low - vector::kSkirtMetres + 1.0) << "building " << i << j;
            EXPECT_GT(bottom, low - 0.1 * (height + high - low) - vector::kSkirtMetres - 1.0) << "building " << i << j;
            EXPECT_NEAR(top, high + height, 1.0) << "building " << i << j;
        }
}

TEST_F(VectorMesh, APickedBuildingTurnsYellowAndTheExtrusionScaleRaisesTheRoofs) {
    auto scene = villageScene();
    ASSERT_TRUE(scene);
    const auto before = render(*scene);
    auto& village = vectorAt(*scene, 1);
    const auto yellow = [](const ImageRgba8& img) {
        size_t n = 0;
        for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
            const uint8_t* p = &img.pixels[i * 4];
            n += int(p[0]) > int(p[2]) + 90 && int(p[1]) > int(p[2]) + 90;
        }
        return n;
    };
    // The centre building's courtyard wall: inside the footprint, outside the hole.
    const auto picked = village.asPickable()->pickAt(6.99 + 2 * 0.0045 + 0.0002, 45.85 + 2 * 0.00315 + 0.0002, 5.0);
    ASSERT_TRUE(picked.has_value());
    EXPECT_EQ(picked->feature.substr(0, 4), "fid ");
    const auto highlighted = render(*scene);
    EXPECT_EQ(yellow(before), 0u);
    EXPECT_GT(yellow(highlighted), 20u);
    village.asPickable()->clearPick();
    EXPECT_EQ(yellow(render(*scene)), 0u);

    const double top = highestVertex(*village.mesh());
    ASSERT_TRUE(village.setParameter("extrusionScale", 2.0));
    render(*scene);
    EXPECT_GT(highestVertex(*village.mesh()), top + 200.0) << "the tallest, 280 m, doubled";
    EXPECT_FALSE(village.setParameter("extrusionScale", -1.0));
    const auto settings = village.liveSettings();
    EXPECT_TRUE(std::any_of(settings.begin(), settings.end(), [](const auto& s) { return s.name == "extrusionScale" && s.value == 2.0; }));
}

TEST_F(VectorMesh, LayersBuildOnlyWhatTheyDraw) {
    // Flat polygons, clamped: draped, no mesh pipeline. Bad altitude modes are refused by name.
    auto flat = load(vectorSceneJson(kVillageView, mountainTerrain() + "," + vectorLayerJson("Village", village(), ""),
                                     "2026-06-21T07:30:00Z"));
    ASSERT_TRUE(flat);
    render(*flat);
    auto& layer = vectorAt(*flat, 1);
    EXPECT_FALSE(layer.hasMeshRenderer());
    EXPECT_NE(layer.drapeSource(), nullptr);
    const auto settings = layer.liveSettings();
    EXPECT_FALSE(std::any_of(settings.begin(), settings.end(), [](const auto& s) { return s.name == "extrusionScale"; }));

    auto desc = scene::parseSceneText(
        vectorSceneJson(kVillageView, vectorLayerJson("Village", village(), R"(, "altitude": "floating")"), "2026-06-21T07:30:00Z"),
        "bad.json", ".");
    ASSERT_TRUE(desc.ok());
    auto bad = scene::Scene::build(std::move(desc).value(), registry_);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.message().find("/layers/0/altitude"), std::string::npos) << bad.message();
    EXPECT_NE(bad.message().find("\"floating\""), std::string::npos) << bad.message();
}

/// The bounding boxes and centres of the four colours of the test icon in `img` (0 magenta,
/// 1 cyan, 2 yellow, 3 green).
struct ColourBox {
    double x = 0, y = 0;
    size_t n = 0;
    uint32_t x0 = 1u << 30, x1 = 0, y0 = 1u << 30, y1 = 0;
};
std::map<int, ColourBox> iconQuarters(const ImageRgba8& img) {
    std::map<int, ColourBox> boxes;
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x) {
            const uint8_t* p = &img.pixels[(size_t(y) * img.width + x) * 4];
            const bool hi[3] = {p[0] > 200, p[1] > 200, p[2] > 200}, lo[3] = {p[0] < 60, p[1] < 60, p[2] < 60};
            int kind = -1;
            if (hi[0] && lo[1] && hi[2]) kind = 0;
            if (lo[0] && hi[1] && hi[2]) kind = 1;
            if (hi[0] && hi[1] && lo[2]) kind = 2;
            if (lo[0] && hi[1] && lo[2]) kind = 3;
            if (kind < 0) continue;
            ColourBox& b = boxes[kind];
            b.x += x, b.y += y, ++b.n;
            b.x0 = std::min(b.x0, x), b.x1 = std::max(b.x1, x), b.y0 = std::min(b.y0, y), b.y1 = std::max(b.y1, y);
        }
    for (auto& [kind, b] : boxes) b.x /= double(b.n), b.y /= double(b.n);
    return boxes;
}

TEST_F(VectorMesh, APointAtAltitudeShowsItsIconUprightAsWideAsItIsAndScaledWithRange) {
    // A 2:1 icon in four colours (magenta and cyan on top, yellow and green below), 24 px high,
    // on a point 350 m above the ground: drawn 48 x 24 pixels, the right way up; with an
    // iconScale of 0.5 beyond 2 km (the camera is 3 km away), 24 x 12.
    const auto quad = writeIcon("vector-mesh", "quad.png", 32, 16, [](uint32_t x, uint32_t y, uint8_t* p) {
        const bool right = x >= 16, bottom = y >= 8;   // magenta, cyan / yellow, green
        p[0] = right ? 0 : 255, p[1] = !bottom && !right ? 0 : 255, p[2] = bottom ? 0 : 255, p[3] = 255;
    });
    ASSERT_FALSE(quad.empty());
    const std::string point = writeGeoJson("vector-mesh", "beacon.geojson",
                                           R"({"type": "Feature", "properties": {"name": "beacon"}, "geometry": {"type": "Point", "coordinates": [7.0, 45.852, 350]}})");
    const auto extent = [&](const std::string& scale) {
        auto scene = load(vectorSceneJson(
            kVillageView,
            mountainTerrain() + "," +
                vectorLayerJson("Beacon", point,
                                R"(, "altitude": "relative", "style": {"icon": )" + jsonString(quad.string()) + R"(, "iconSize": 24)" +
                                    scale + "}"),
            "2026-06-21T07:30:00Z"));
        EXPECT_TRUE(scene);
        if (!scene) return glm::dvec2(0.0);
        const auto img = render(*scene);
        EXPECT_TRUE(vectorAt(*scene, 1).hasMeshRenderer());
        auto boxes = iconQuarters(img);
        EXPECT_EQ(boxes.size(), 4u) << "each quarter of the icon shows";
        if (boxes.size() != 4) return glm::dvec2(0.0);
        EXPECT_LT(boxes[0].x, boxes[1].x);   // magenta left of cyan
        EXPECT_LT(boxes[2].x, boxes[3].x);
        EXPECT_LT(boxes[0].y, boxes[2].y);   // magenta above yellow
        EXPECT_LT(boxes[1].y, boxes[3].y);
        return glm::dvec2(double(std::max(boxes[1].x1, boxes[3].x1) - std::min(boxes[0].x0, boxes[2].x0) + 1),
                          double(std::max(boxes[2].y1, boxes[3].y1) - std::min(boxes[0].y0, boxes[1].y0) + 1));
    };
    const glm::dvec2 full = extent("");
    EXPECT_NEAR(full.y, 24.0, 3.0);
    EXPECT_NEAR(full.x, 48.0, 4.0);
    const glm::dvec2 far = extent(R"(, "iconScale": {"near": 1000, "far": 2000, "scale": 0.5})");
    EXPECT_NEAR(far.y, 12.0, 2.0);
    EXPECT_NEAR(far.x, 24.0, 3.0);
}

TEST_F(VectorMesh, ALineAtAltitudeIsDashedAsItsStyleSays) {
    // The cable 250 m above the village, solid and dashed 8 on, 8 off: about half its pixels.
    const std::string cable = writeGeoJson("vector-mesh", "cable.geojson",
                                           R"({"type": "Feature", "properties": {"name": "cable"}, "geometry": {"type": "LineString", "coordinates": )"
                                           R"([[6.975, 45.853, 250], [7.0, 45.858, 250], [7.02, 45.856, 250]]}})");
    const auto red = [&](const std::string& dash) {
        auto scene = load(vectorSceneJson(kVillageView,
                                          mountainTerrain() + "," +
                                              vectorLayerJson("Cable", cable, R"(, "altitude": "relative", "style": {"color": [1, 0, 0], "width": 4)" + dash + "}"),
                                          "2026-06-21T07:30:00Z"));
        if (!scene) return size_t(0);
        const auto img = render(*scene);
        size_t n = 0;
        for (size_t i = 0; i < img.pixels.size(); i += 4) n += img.pixels[i] > 150 && img.pixels[i + 1] < 80 && img.pixels[i + 2] < 80;
        return n;
    };
    const size_t solid = red(""), dashed = red(R"(, "dash": [8, 8])");
    ASSERT_GT(solid, 200u);
    EXPECT_GT(dashed, solid * 3 / 10) << "the dashes";
    EXPECT_LT(dashed, solid * 7 / 10) << "the gaps";
}

}  // namespace
}  // namespace orbis::test
