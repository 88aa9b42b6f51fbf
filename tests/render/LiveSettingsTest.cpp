// The layers' live settings (Layer::liveSettings) as the viewer's panels show them: each layer
// lists the settings it has, with labels, ranges that hold the current value and the full list
// of choices; every one can be set through setParameter/setOption to values in its range and
// reads back; and every one, moved off its value, is saved at its JSON pointer and loads back.
// Built from scene text; no frame is drawn (the layers are not prepared).
#include "engine/scene/SceneSave.h"
#include "layers/fmv/FmvLayer.h"
#include "layers/models/ModelLayer.h"
#include "layers/points/LasReader.h"
#include "layers/points/PointsLayer.h"
#include "layers/terrain/TerrainLayer.h"
#include "layers/volume/VolumeLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/support/GoldenImage.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;
using Kind = scene::LayerSetting::Kind;

const fs::path kSource = ORBIS_SOURCE_DIR;

std::string jsonString(const fs::path& p) { return nlohmann::json(p.string()).dump(); }

std::optional<scene::LayerSetting> current(const scene::LiveSettings& layer, const std::string& name) {
    for (const auto& s : layer.liveSettings())
        if (s.name == name) return s;
    return std::nullopt;
}

std::vector<std::string> names(const scene::LiveSettings& layer) {
    std::vector<std::string> out;
    for (const auto& s : layer.liveSettings()) out.push_back(s.name);
    return out;
}

/// Every listed setting, set to values within its range (a quarter and three quarters of the
/// way, whole numbers for Integer; both states of a Toggle; every choice), reads back exactly,
/// then is put back. "rangeMax" goes high and "rangeMin" low first, so that low < high holds.
void expectEverySettingRoundTrips(scene::LiveSettings& layer) {
    for (const scene::LayerSetting& s : layer.liveSettings()) {
        SCOPED_TRACE("setting \"" + s.name + "\"");
        EXPECT_FALSE(s.label.empty());
        switch (s.kind) {
            case Kind::Choice: {
                ASSERT_FALSE(s.choices.empty());
                EXPECT_NE(std::find(s.choices.begin(), s.choices.end(), s.choice), s.choices.end()) << s.choice;
                for (const std::string& c : s.choices) {
                    EXPECT_TRUE(layer.setOption(s.name, c)) << c;
                    EXPECT_EQ(current(layer, s.name)->choice, c);
                }
                EXPECT_FALSE(layer.setOption(s.name, "no-such-choice"));
                EXPECT_TRUE(layer.setOption(s.name, s.choice));
                break;
            }
            case Kind::Toggle:
                for (double v : {1.0 - s.value, s.value}) {
                    EXPECT_TRUE(layer.setParameter(s.name, v));
                    EXPECT_EQ(current(layer, s.name)->value, v);
                }
                break;
            case Kind::Number:
            case Kind::Integer: {
                EXPECT_LT(s.min, s.max);
                EXPECT_GE(s.value, s.min);
                EXPECT_LE(s.value, s.max);
                const bool high = s.name.ends_with("Max");
                const std::array<double, 2> fractions = high ? std::array{0.75, 0.25} : std::array{0.25, 0.75};
                for (double f : fractions) {
                    double v = s.min + f * (s.max - s.min);
                    if (s.kind == Kind::Integer) v = std::round(v);
                    EXPECT_TRUE(layer.setParameter(s.name, v)) << v;
                    const auto now = current(layer, s.name);
                    EXPECT_DOUBLE_EQ(now->value, v);
                    EXPECT_GE(now->value, now->min);
                    EXPECT_LE(now->value, now->max);
                }
                EXPECT_TRUE(layer.setParameter(s.name, s.value));
                EXPECT_DOUBLE_EQ(current(layer, s.name)->value, s.value);
                break;
            }
            case Kind::Curve: {
                EXPECT_LT(s.min, s.max);
                ASSERT_GE(s.points.size(), 1u);
                for (size_t i = 1; i < s.points.size(); ++i) EXPECT_LE(s.points[i - 1].x, s.points[i].x);
                for (const glm::dvec2& p : s.points) EXPECT_TRUE(p.y >= 0.0 && p.y <= 1.0) << p.y;
                const double mid = 0.5 * (s.min + s.max);
                const std::vector<glm::dvec2> tent = {{s.min, 0.0}, {mid, 0.8}, {s.max, 0.1}};
                EXPECT_TRUE(layer.setCurve(s.name, tent));
                EXPECT_EQ(current(layer, s.name)->points, tent);
                // Out of order: sorted; alpha outside 0..1, NaN, or no point: refused, unchanged.
                EXPECT_TRUE(layer.setCurve(s.name, {{s.max, 0.5}, {s.min, 0.25}}));
                EXPECT_EQ(current(layer, s.name)->points, (std::vector<glm::dvec2>{{s.min, 0.25}, {s.max, 0.5}}));
                EXPECT_FALSE(layer.setCurve(s.name, {{s.min, 1.5}}));
                EXPECT_FALSE(layer.setCurve(s.name, {{std::nan(""), 0.5}}));
                EXPECT_FALSE(layer.setCurve(s.name, {}));
                EXPECT_FALSE(layer.setCurve("no-such-curve", tent));
                EXPECT_TRUE(layer.setCurve(s.name, s.points));
                EXPECT_EQ(current(layer, s.name)->points, s.points);
                break;
            }
        }
    }
}

/// 16 points in a row near (7, 46), made once.
fs::path tinyLas() {
    const fs::path las = fs::path(testOutputDir()) / "live-settings" / "tiny.las";
    fs::create_directories(las.parent_path());
    const bool made = makeFixture(las.string(), [](const std::string& tmp) {
        points::LasWriteOptions o;
        o.scale = glm::dvec3(1e-7, 1e-7, 1e-3);
        auto writer = points::LasWriter::create(tmp, o);
        if (!writer) return false;
        std::vector<points::LasPoint> pts(16);
        for (size_t i = 0; i < pts.size(); ++i) pts[i].position = {7.0 + 1e-4 * double(i), 46.0, 500.0};
        (*writer)->write(pts);
        return (*writer)->close().ok();
    });
    return made ? las : fs::path();
}

/// Moves every setting off its value (a quarter or three quarters of its range, the other state
/// of a toggle, another choice, a tent-shaped curve) and returns them as set.
std::vector<scene::LayerSetting> moveEverySetting(scene::LiveSettings& layer) {
    for (const scene::LayerSetting& s : layer.liveSettings()) {
        switch (s.kind) {
            case Kind::Choice:
                for (const std::string& c : s.choices)
                    if (c != s.choice) {
                        EXPECT_TRUE(layer.setOption(s.name, c)) << s.name << " = " << c;
                        break;
                    }
                break;
            case Kind::Toggle: EXPECT_TRUE(layer.setParameter(s.name, 1.0 - s.value)) << s.name; break;
            case Kind::Number:
            case Kind::Integer: {
                double v = s.min + (s.name.ends_with("Max") ? 0.75 : 0.25) * (s.max - s.min);
                if (s.kind == Kind::Integer) v = std::round(v);
                EXPECT_TRUE(layer.setParameter(s.name, v)) << s.name << " = " << v;
                break;
            }
            case Kind::Curve: {
                const double mid = 0.5 * (s.min + s.max);
                EXPECT_TRUE(layer.setCurve(s.name, {{s.min, 0.0}, {mid, 0.8}, {s.max, 0.1}})) << s.name;
                break;
            }
        }
    }
    return layer.liveSettings();
}

class LiveSettings : public ::testing::Test {
protected:
    void SetUp() override { layers::registerBuiltinLayers(registry_); }

    /// The first layer of a scene made of `layer`.
    scene::LiveSettings& load(const std::string& layer) {
        scene_ = buildScene(R"({"time": {"start": "2026-06-21T09:00:00Z", "end": "2026-06-21T10:00:00Z"}, "layers": [)" +
                                layer + "]}",
                            registry_);
        if (!scene_) throw std::runtime_error("the scene did not build");
        scene::LiveSettings* live = scene_->resources().front().layer->asLiveSettings();
        if (!live) throw std::runtime_error("the layer has no live settings");
        return *live;
    }

    /// Moves every setting of the loaded layer (moveEverySetting), saves the scene, and expects
    /// each setting's value at its JSON pointer in the saved file and, once the file is loaded
    /// again, the same settings with the same values.
    void expectEverySettingSavedAndLoadedBack(const std::string& name) {
        scene::LiveSettings* live = scene_->resources().front().layer->asLiveSettings();
        ASSERT_NE(live, nullptr);
        const std::vector<scene::LayerSetting> moved = moveEverySetting(*live);
        const fs::path file = fs::path(testOutputDir()) / "live-settings" / (name + "-saved.json");
        fs::create_directories(file.parent_path());
        ASSERT_TRUE(scene::saveScene(*scene_, file).ok());

        const nlohmann::json saved = scene::sceneToJson(*scene_, file)["layers"][0];
        for (const scene::LayerSetting& s : moved) {
            SCOPED_TRACE("setting \"" + s.name + "\" at " + s.jsonPointer());
            EXPECT_TRUE(saved.contains(nlohmann::json::json_pointer(s.jsonPointer()))) << saved.dump();
        }
        auto desc = scene::parseSceneFile(file);
        ASSERT_TRUE(desc.ok()) << desc.message();
        auto again = scene::Scene::build(std::move(desc).value(), registry_);
        ASSERT_TRUE(again.ok()) << again.message();
        const scene::LiveSettings* back = (*again)->resources().front().layer->asLiveSettings();
        ASSERT_NE(back, nullptr);
        const std::vector<scene::LayerSetting> loaded = back->liveSettings();
        ASSERT_EQ(loaded.size(), moved.size());
        for (size_t i = 0; i < moved.size(); ++i) {
            SCOPED_TRACE("setting \"" + moved[i].name + "\"");
            EXPECT_EQ(loaded[i].name, moved[i].name);
            EXPECT_EQ(loaded[i].jsonPointer(), moved[i].jsonPointer());
            // Integers and toggles are written as such; numbers as doubles: exact.
            EXPECT_EQ(loaded[i].value, moved[i].value);
            EXPECT_EQ(loaded[i].choice, moved[i].choice);
            EXPECT_EQ(loaded[i].points, moved[i].points);
        }
    }

    scene::LayerRegistry registry_;
    std::unique_ptr<scene::Scene> scene_;
};

TEST_F(LiveSettings, EverySettingOfEveryLayerIsSavedAtItsPointerAndLoadsBack) {
    const std::string dem = jsonString(terrainFixtures().dem), image = jsonString(terrainFixtures().image);
    const fs::path las = tinyLas();
    ASSERT_FALSE(las.empty());
    const fs::path video = kSource / "assets/generated/fmv/flight.ts";
    ASSERT_TRUE(fs::exists(video)) << video << " is made by the build (orbis_fmv_showcase)";
    const std::vector<std::pair<std::string, std::string>> layers = {
        {"terrain", R"({"type": "terrain", "elevation": [)" + dem + R"(], "imagery": [)" + image + R"(, {"path": )" +
                        image + R"(, "opacity": 0.4}]})"},
        {"volume", R"({"type": "volume", "synthetic": {"field": "sphere", "size": [16, 16, 16], "lon": [-10, 10],
            "lat": [40, 60], "height": [0, 800000]}, "mode": ["dvr", "iso", "slice"], "isovalues": [3, 6],
            "slices": [{"lon": 5}, {"lat": 45}, {"height": 1000}]})"},
        {"volume-no-range", R"({"type": "volume", "synthetic": {"field": "waves", "size": [8, 8, 8]}})"},
        {"points", R"({"type": "points", "path": )" + jsonString(las) + R"(, "crs": "EPSG:4979"})"},
        {"fmv", R"({"type": "fmv", "path": )" + jsonString(video) + "}"},
        {"model", R"({"type": "model", "file": )" + jsonString(kSource / "assets/models/wagon.gltf") +
                      R"(, "position": [7, 46, 0]})"},
        {"annotations", R"({"type": "annotations", "labels": true})"},
    };
    for (const auto& [name, layer] : layers) {
        SCOPED_TRACE(name);
        load(layer);
        expectEverySettingSavedAndLoadedBack(name);
    }
}

TEST_F(LiveSettings, TerrainListsEachImageryLayersVisibilityAndOpacity) {
    auto& layer = load(R"({"type": "terrain", "elevation": [)" + jsonString(terrainFixtures().dem) +
                       R"(], "imagery": [{"name": "Base", "path": )" + jsonString(terrainFixtures().image) +
                       R"(}, {"path": )" + jsonString(terrainFixtures().image) + R"(, "opacity": 0.4, "visible": false}]})");
    EXPECT_EQ(names(layer), (std::vector<std::string>{"maxScreenSpaceError", "verticalExaggeration", "imageryVisible0",
                                                      "imageryOpacity0", "imageryVisible1", "imageryOpacity1"}));
    EXPECT_EQ(current(layer, "imageryOpacity0")->label, "Base opacity");
    EXPECT_EQ(current(layer, "imageryOpacity1")->value, 0.4);
    EXPECT_EQ(current(layer, "imageryVisible1")->value, 0.0);
    expectEverySettingRoundTrips(layer);
}

TEST_F(LiveSettings, TerrainListsErrorAndExaggeration) {
    auto& layer = load(R"({"type": "terrain", "elevation": [)" + jsonString(terrainFixtures().dem) +
                       R"(], "maxScreenSpaceError": 4, "verticalExaggeration": 2})");
    EXPECT_EQ(names(layer), (std::vector<std::string>{"maxScreenSpaceError", "verticalExaggeration"}));
    EXPECT_EQ(current(layer, "maxScreenSpaceError")->value, 4.0);
    EXPECT_EQ(current(layer, "verticalExaggeration")->value, 2.0);
    EXPECT_TRUE(current(layer, "maxScreenSpaceError")->logarithmic);
    expectEverySettingRoundTrips(layer);
    // Outside the scene file's ranges: refused, so that a saved scene always loads again.
    EXPECT_FALSE(layer.setParameter("maxScreenSpaceError", 0.1));
    EXPECT_FALSE(layer.setParameter("verticalExaggeration", 2000.0));
}

TEST_F(LiveSettings, VolumeListsOneSettingPerIsovalueAndSlice) {
    auto& layer = load(R"({"type": "volume", "synthetic": {"field": "sphere", "size": [16, 16, 16],
        "lon": [-10, 10], "lat": [40, 60], "height": [0, 800000]}, "colorMap": "magma",
        "mode": ["dvr", "iso", "slice"], "isovalues": [3, 6], "slices": [{"lon": 5}, {"lat": 45}, {"height": 1000}]})");
    EXPECT_EQ(names(layer), (std::vector<std::string>{"steps", "opacityScale", "opacityUnit", "rangeMin", "rangeMax",
                                                      "colorMap", "emptySkipping", "isovalue0", "isovalue1", "isoOpacity",
                                                      "slice0", "slice1", "slice2", "opacity", "sliceOpacity", "rayResolution",
                                                      "preIntegration"}));
    const auto map = current(layer, "colorMap");
    EXPECT_EQ(map->choice, "magma");
    EXPECT_EQ(map->choices, layers::colorMapNames());
    EXPECT_EQ(current(layer, "isovalue1")->value, 6.0);
    const auto range = current(layer, "rangeMin");   // the sphere's distances: 0 .. ~13 voxels
    EXPECT_EQ(range->value, range->min);
    EXPECT_NEAR(range->max, std::sqrt(3.0) * 7.5, 1e-4);
    const auto lat = current(layer, "slice1");
    EXPECT_EQ(lat->value, 45.0);
    EXPECT_EQ(lat->min, 40.0);
    EXPECT_EQ(lat->max, 60.0);
    EXPECT_NE(lat->label.find("latitude"), std::string::npos);
    const auto height = current(layer, "slice2");
    EXPECT_EQ(height->max, 800000.0);
    EXPECT_EQ(current(layer, "emptySkipping")->kind, Kind::Toggle);
    expectEverySettingRoundTrips(layer);
}

TEST_F(LiveSettings, VolumeWithoutIsoOrSlicesListsNeither) {
    auto& layer = load(R"({"type": "volume", "synthetic": {"field": "waves", "size": [8, 8, 8]}})");
    EXPECT_EQ(names(layer), (std::vector<std::string>{"steps", "opacityScale", "opacityUnit", "rangeMin", "rangeMax",
                                                      "colorMap", "emptySkipping", "opacity", "rayResolution", "preIntegration"}));
    EXPECT_FALSE(layer.setParameter("isovalue0", 1.0));
    expectEverySettingRoundTrips(layer);
}

TEST_F(LiveSettings, PointsListColourRendererAndLighting) {
    const fs::path las = tinyLas();
    ASSERT_FALSE(las.empty());
    auto& layer = load(R"({"type": "points", "path": )" + jsonString(las) +
                       R"(, "crs": "EPSG:4979", "color": "classification", "pointSize": 3, "edl": true})");
    EXPECT_EQ(names(layer), (std::vector<std::string>{"color", "pointBudget", "pointSize", "adaptiveSize", "opacity", "edl", "edlStrength",
                                                      "edlRadius", "renderer"}));
    const auto color = current(layer, "color");
    EXPECT_EQ(color->choice, "classification");
    EXPECT_EQ(color->choices, (std::vector<std::string>{"rgb", "intensity", "classification", "height", "constant"}));
    EXPECT_EQ(current(layer, "renderer")->choices, (std::vector<std::string>{"compute", "pointList"}));
    EXPECT_EQ(current(layer, "pointSize")->value, 3.0);
    EXPECT_EQ(current(layer, "pointSize")->kind, Kind::Integer);
    EXPECT_EQ(current(layer, "edl")->value, 1.0);
    expectEverySettingRoundTrips(layer);
    EXPECT_FALSE(layer.setParameter("edlStrength", 101.0));
}

TEST_F(LiveSettings, FmvListsOpacityFootprintFrustumAndPoseOffsets) {
    const fs::path video = kSource / "assets/generated/fmv/flight.ts";
    ASSERT_TRUE(fs::exists(video)) << video << " is made by the build (orbis_fmv_showcase)";
    auto& layer = load(R"({"type": "fmv", "path": )" + jsonString(video) + R"(, "opacity": 0.5, "frustum": false, "poseOffset": {"roll": -1.5}})");
    EXPECT_EQ(names(layer), (std::vector<std::string>{"opacity", "footprint", "frustum", "headingOffset", "pitchOffset", "rollOffset",
                                                      "altitudeOffset"}));
    EXPECT_EQ(current(layer, "rollOffset")->value, -1.5);
    EXPECT_EQ(current(layer, "headingOffset")->value, 0.0);
    EXPECT_EQ(current(layer, "opacity")->value, 0.5);
    EXPECT_EQ(current(layer, "footprint")->value, 1.0);
    EXPECT_EQ(current(layer, "frustum")->value, 0.0);
    expectEverySettingRoundTrips(layer);
}

TEST_F(LiveSettings, ModelListsScaleAndMinimumSize) {
    auto& layer = load(R"({"type": "model", "file": )" + jsonString(kSource / "assets/models/wagon.gltf") +
                       R"(, "position": [7, 46, 0], "scale": 2.5})");
    EXPECT_EQ(names(layer), (std::vector<std::string>{"scale", "minimumPixelSize", "opacity"}));
    EXPECT_EQ(current(layer, "scale")->value, 2.5);
    expectEverySettingRoundTrips(layer);
    const auto& model = dynamic_cast<layers::ModelLayer&>(layer);
    ASSERT_TRUE(layer.setParameter("scale", 4.0));
    EXPECT_EQ(model.settings().scale, 4.0) << "the layer draws with what it lists";
    EXPECT_FALSE(layer.setParameter("scale", 0.0));
}

}  // namespace
}  // namespace orbis::test
