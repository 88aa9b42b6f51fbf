// Saving a scene (SceneSave.h) without a GPU: relative paths rebased for the new folder, live
// settings written at their JSON pointers, the camera, time and camera mode as they are now,
// unknown keys kept, and clear errors for folders that cannot take the file.
#include "engine/scene/SceneSave.h"

#include "engine/scene/LayerRegistry.h"
#include "engine/scene/Scene.h"
#include "layers/BuiltinLayers.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace orbis::scene {
namespace {

namespace fs = std::filesystem;
using Kind = LayerSetting::Kind;

/// The file paths the built-in layer types declare (LayerType::filePaths): `type`'s, or every
/// type's together.
std::vector<std::string> builtinFilePaths(const std::string& type = {}) {
    LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    std::vector<std::string> out;
    for (const std::string& t : registry.types())
        if (type.empty() || t == type) out.insert(out.end(), registry.filePaths(t).begin(), registry.filePaths(t).end());
    return out;
}

TEST(ScenePaths, RelativePathsFollowTheNewFolder) {
    EXPECT_EQ(rebasePath("dem.tif", "/data/a", "/data/b"), "../a/dem.tif");
    EXPECT_EQ(rebasePath("dem.tif", "/data/a", "/data/a"), "dem.tif");
    EXPECT_EQ(rebasePath("tiles/dem.tif", "/data/a", "/data/a/deeper/still"), "../../tiles/dem.tif");
    EXPECT_EQ(rebasePath("../x/dem.tif", "/data/a/sub", "/data/a"), "x/dem.tif");
    EXPECT_EQ(rebasePath("./dem.tif", "/data/a/", "/data/b/."), "../a/dem.tif") << "dots and trailing separators";
    EXPECT_EQ(rebasePath("cache/", "/data/a", "/data/b"), "../a/cache/") << "a folder keeps its separator";
}

TEST(ScenePaths, PathsSharingOnlyTheRootBecomeAbsolute) {
    EXPECT_EQ(rebasePath("dem.tif", "/data/a", "/tmp/b"), "/data/a/dem.tif");
    EXPECT_EQ(rebasePath("../../dem.tif", "/data/a/b", "/home/u"), "/data/dem.tif");
}

TEST(ScenePaths, AbsolutePathsUrlsAndEmptyStringsStay) {
    EXPECT_EQ(rebasePath("/srv/dem.tif", "/data/a", "/data/b"), "/srv/dem.tif");
    EXPECT_EQ(rebasePath("http://127.0.0.1:8080/{z}/{x}/{y}.png", "/data/a", "/data/b"), "http://127.0.0.1:8080/{z}/{x}/{y}.png");
    EXPECT_EQ(rebasePath("", "/data/a", "/data/b"), "");
}

TEST(ScenePaths, ConnectionStringsStayButTheirPasswordsAreNotSaved) {
    EXPECT_EQ(rebasePath("PG:host=db dbname=gis", "/data/a", "/data/b"), "PG:host=db dbname=gis");
    EXPECT_EQ(rebasePath("PG:host=db password=s3cret dbname=gis", "/data/a", "/data/b"), "PG:host=db dbname=gis");
    EXPECT_EQ(rebasePath("WFS:https://me:s3cret@host/wfs", "/data/a", "/data/b"), "WFS:https://me@host/wfs");
    EXPECT_EQ(rebasePath("https://host/wms?password=s3cret&layers=a", "/data/a", "/data/b"), "https://host/wms?layers=a");
    // Files whose names hold a colon are still files.
    EXPECT_EQ(rebasePath("a:b.tif", "/data/a", "/data/b"), "../a/a:b.tif");
    EXPECT_EQ(rebasePath("x/y:z.tif", "/data/a", "/data/b"), "../a/x/y:z.tif");
}

TEST(ScenePaths, RelativeSceneFolderResolvesAgainstTheWorkingFolder) {
    const fs::path cwd = fs::current_path();
    EXPECT_EQ(rebasePath("dem.tif", ".", cwd / "sub"), "../dem.tif");
}

TEST(ScenePaths, EveryFileKeyOfEveryLayerIsRebased) {
    auto layer = nlohmann::json::parse(R"({
        "type": "x", "name": "dem.tif",
        "elevation": ["dem.tif", {"path": "more/dem2.tif", "band": 1}],
        "imagery": [{"name": "Colours", "path": "img.tif"}, {"xyz": "http://h/{z}/{x}/{y}.png"}, "plain.tif"],
        "path": "cloud.las", "cacheFolder": "cache", "poses": "flight.csv", "file": "models/m.glb",
        "trajectory": {"file": "track.csv", "interpolation": "linear"},
        "nested": {"deeper": [{"path": "d.nc"}]},
        "opacity": [[0, 0], [1, 0.5]], "colorMap": "viridis", "label": "img.tif"})");
    // The file paths every built-in layer type declares, and a pointer through an array deeper down.
    std::vector<std::string> filePaths = builtinFilePaths();
    filePaths.push_back("/nested/deeper/*/path");
    rebaseLayerPaths(layer, "/data/a", "/data/b", filePaths);
    EXPECT_EQ(layer["elevation"][0], "../a/dem.tif");
    EXPECT_EQ(layer["elevation"][1]["path"], "../a/more/dem2.tif");
    EXPECT_EQ(layer["imagery"][0]["path"], "../a/img.tif");
    EXPECT_EQ(layer["imagery"][1]["xyz"], "http://h/{z}/{x}/{y}.png");
    EXPECT_EQ(layer["imagery"][2], "../a/plain.tif");
    EXPECT_EQ(layer["path"], "../a/cloud.las");
    EXPECT_EQ(layer["cacheFolder"], "../a/cache");
    EXPECT_EQ(layer["poses"], "../a/flight.csv");
    EXPECT_EQ(layer["file"], "../a/models/m.glb");
    EXPECT_EQ(layer["trajectory"]["file"], "../a/track.csv");
    EXPECT_EQ(layer["nested"]["deeper"][0]["path"], "../a/d.nc");
    // Not paths: names, labels, colour maps, numbers.
    EXPECT_EQ(layer["name"], "dem.tif");
    EXPECT_EQ(layer["label"], "img.tif");
    EXPECT_EQ(layer["imagery"][0]["name"], "Colours");
    EXPECT_EQ(layer["colorMap"], "viridis");
    EXPECT_EQ(layer["opacity"], nlohmann::json::parse("[[0, 0], [1, 0.5]]"));

    auto model = nlohmann::json::parse(R"({"trajectory": "track.gpx", "path": {"show": true, "trail": 10}})");
    rebaseLayerPaths(model, "/data/a", "/data/b", builtinFilePaths("model"));
    EXPECT_EQ(model["trajectory"], "../a/track.gpx");
    EXPECT_EQ(model["path"], nlohmann::json::parse(R"({"show": true, "trail": 10})")) << "the model's path line is no file";
}

TEST(SceneLiveSettings, EachKindIsWrittenAsTheSceneReadsIt) {
    nlohmann::json layer = {{"keep", "me"}, {"steps", 10}};
    writeLiveSettings(layer, {{.name = "opacity", .kind = Kind::Number, .value = 0.25},
                              {.name = "steps", .kind = Kind::Integer, .value = 199.9999999},
                              {.name = "edl", .kind = Kind::Toggle, .value = 1.0},
                              {.name = "footprint", .kind = Kind::Toggle, .value = 0.0},
                              {.name = "colorMap", .kind = Kind::Choice, .choice = "magma"},
                              {.name = "transfer", .kind = Kind::Curve, .points = {{2.0, 0.0}, {5.5, 0.75}}}});
    EXPECT_EQ(layer["opacity"], 0.25);
    EXPECT_EQ(layer["transfer"], nlohmann::json::parse("[[2.0, 0.0], [5.5, 0.75]]"));
    ASSERT_TRUE(layer["steps"].is_number_integer());
    EXPECT_EQ(layer["steps"], 200);
    EXPECT_EQ(layer["edl"], true);
    EXPECT_EQ(layer["footprint"], false);
    EXPECT_EQ(layer["colorMap"], "magma");
    EXPECT_EQ(layer["keep"], "me");
}

TEST(SceneLiveSettings, ImageryLayersTakeTheirOpacityAndVisibility) {
    nlohmann::json layer = {{"imagery", {"a.tif", {{"path", "b.tif"}, {"opacity", 1.0}}}}};
    writeLiveSettings(layer, {{.name = "imageryOpacity0", .kind = Kind::Number, .value = 0.25, .pointer = "/imagery/0/opacity"},
                              {.name = "imageryVisible0", .kind = Kind::Toggle, .value = 1.0, .pointer = "/imagery/0/visible"},
                              {.name = "imageryOpacity1", .kind = Kind::Number, .value = 0.5, .pointer = "/imagery/1/opacity"},
                              {.name = "imageryVisible1", .kind = Kind::Toggle, .value = 0.0, .pointer = "/imagery/1/visible"},
                              {.name = "imageryOpacity7", .kind = Kind::Number, .value = 0.5, .pointer = "/imagery/7/opacity"}});
    EXPECT_EQ(layer["imagery"], nlohmann::json::parse(R"([{"path": "a.tif", "opacity": 0.25, "visible": true},
                                                         {"path": "b.tif", "opacity": 0.5, "visible": false}])"));
}

TEST(SceneLiveSettings, VolumeArrayElementsAreMapped) {
    auto layer = nlohmann::json::parse(R"({"isovalues": [1, 2, 3], "slices": [{"lon": 5}, {"height": 1000}],
                                           "sliceOpacity": 1, "isoOpacity": 1})");
    writeLiveSettings(layer, {{.name = "rangeMin", .value = -2.0, .pointer = "/range/0"},
                              {.name = "rangeMax", .value = 7.5, .pointer = "/range/1"},
                              {.name = "isovalue1", .value = 2.5, .pointer = "/isovalues/1"},
                              {.name = "slice1", .value = 2000.0, .pointer = "/slices/1/height"},
                              {.name = "slice0", .value = 6.0, .pointer = "/slices/0/lon"},
                              {.name = "sliceOpacity", .value = 0.5},
                              {.name = "isoOpacity", .value = 0.75}});
    EXPECT_EQ(layer["range"], nlohmann::json::parse("[-2.0, 7.5]"));
    EXPECT_EQ(layer["isovalues"], nlohmann::json::parse("[1, 2.5, 3]"));
    EXPECT_EQ(layer["slices"], nlohmann::json::parse(R"([{"lon": 6.0}, {"height": 2000.0}])"));
    EXPECT_EQ(layer["sliceOpacity"], 0.5);
    EXPECT_EQ(layer["isoOpacity"], 0.75);
    EXPECT_FALSE(layer.contains("rangeMin"));
    EXPECT_FALSE(layer.contains("isovalue1"));
    EXPECT_FALSE(layer.contains("slice0"));

    auto given = nlohmann::json::parse(R"({"range": [0, 1]})");
    writeLiveSettings(given, {{.name = "rangeMax", .value = 3.0, .pointer = "/range/1"}});
    EXPECT_EQ(given["range"], nlohmann::json::parse("[0, 3.0]")) << "the other end is kept";
}

/// A layer with one setting of each kind, live, and no GPU.
class KnobLayer final : public Layer, public LiveSettings {
public:
    std::string_view type() const override { return "knobs"; }
    LiveSettings* asLiveSettings() override { return this; }
    bool drawsIn(Pass) const override { return false; }
    void record(Pass, const render::RecordContext&) override {}
    bool setParameter(std::string_view name, double value) override {
        if (name == "quality") quality_ = value;
        else if (name == "count") count_ = value;
        else if (name == "outline") outline_ = value != 0.0;
        else return false;
        return true;
    }
    bool setOption(std::string_view name, std::string_view value) override {
        if (name != "palette") return false;
        palette_ = std::string(value);
        return true;
    }
    std::vector<LayerSetting> liveSettings() const override {
        return {{.name = "quality", .label = "Quality", .kind = Kind::Number, .value = quality_, .min = 0.0, .max = 10.0},
                {.name = "count", .label = "Count", .kind = Kind::Integer, .value = count_, .min = 0.0, .max = 100.0},
                {.name = "outline", .label = "Outline", .kind = Kind::Toggle, .value = outline_ ? 1.0 : 0.0},
                {.name = "palette", .label = "Palette", .kind = Kind::Choice, .choice = palette_, .choices = {"grey", "viridis"}}};
    }

private:
    void onPrepare(const render::RenderServices&) override {}

    double quality_ = 1.0, count_ = 4.0;
    bool outline_ = false;
    std::string palette_ = "grey";
};

constexpr const char* kScene = R"({"name": "Knobs",
    "viewpoint": {"lon": 7, "lat": 46, "height": 0, "heading": 30, "pitch": -40, "range": 50000},
    "time": {"start": "2026-06-21T00:00:00Z", "end": "2026-06-22T00:00:00Z"},
    "background": [0.1, 0.2, 0.3],
    "annotations": [{"name": "Summit", "lon": 7, "lat": 46, "height": 4000}],
    "layers": [{"type": "knobs", "name": "A", "path": "data/a.bin", "extra": {"keep": [1, 2]}, "quality": 2},
               {"type": "knobs", "name": "B", "visible": false, "viewpoint": {"lon": 1, "lat": 2, "range": 3}}]})";

class SceneSave : public ::testing::Test {
protected:
    void SetUp() override {
        // A type whose objects name one file, at "path".
        registry_.add(LayerType{"knobs", "test", [](const LayerDesc&, const SceneDesc&) -> Result<std::unique_ptr<Layer>> {
            return std::unique_ptr<Layer>(new KnobLayer);
        }, {"/path"}});
        auto desc = parseSceneText(kScene, "/data/scenes/knobs.json", "/data/scenes");
        ASSERT_TRUE(desc.ok()) << desc.message();
        auto built = Scene::build(std::move(desc).value(), registry_);
        ASSERT_TRUE(built.ok()) << built.message();
        scene_ = std::move(built).value();
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() / ("orbis-save-" + std::to_string(::getpid()) + "-" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::permissions(dir_, fs::perms::owner_all, ec);
        fs::remove_all(dir_, ec);
    }

    LayerRegistry registry_;
    std::unique_ptr<Scene> scene_;
    fs::path dir_;
};

TEST_F(SceneSave, CurrentStateIsWrittenOverTheLoadedScene) {
    LiveSettings& a = *scene_->resources()[0].layer->asLiveSettings();
    ASSERT_TRUE(a.setParameter("quality", 7.5));
    ASSERT_TRUE(a.setParameter("count", 12));
    ASSERT_TRUE(a.setParameter("outline", 1));
    ASSERT_TRUE(a.setOption("palette", "viridis"));
    scene_->resources()[0].visible = false;
    scene_->resources()[1].visible = true;
    const TimeNs start = scene_->time().start();
    scene_->time().seek(start + 3600'000'000'000ll + 123'456'789);
    scene_->time().setRate(-60.0);
    scene_->time().setLoop(true);
    scene_->time().play();

    const nlohmann::json j = sceneToJson(*scene_, "/data/saved/knobs.json");
    EXPECT_EQ(j["orbis"], 1);
    EXPECT_EQ(j["name"], "Knobs");
    EXPECT_EQ(j["background"], nlohmann::json::parse("[0.1, 0.2, 0.3]"));
    EXPECT_EQ(j["fovDeg"], 45.0);
    EXPECT_EQ(j["time"]["start"], "2026-06-21T00:00:00Z");
    EXPECT_EQ(j["time"]["end"], "2026-06-22T00:00:00Z");
    EXPECT_EQ(j["time"]["current"], "2026-06-21T01:00:00.123456789Z") << "exact to the nanosecond";
    EXPECT_EQ(j["time"]["rate"], -60.0);
    EXPECT_EQ(j["time"]["loop"], true);
    EXPECT_EQ(j["time"]["playing"], true);
    EXPECT_FALSE(j.contains("camera")) << "free camera: no mode to write";
    EXPECT_EQ(j["annotations"], nlohmann::json::parse(R"([{"name": "Summit", "lon": 7.0, "lat": 46.0, "height": 4000.0}])"));

    const auto& la = j["layers"][0];
    EXPECT_EQ(la["type"], "knobs");
    EXPECT_EQ(la["visible"], false);
    EXPECT_EQ(la["quality"], 7.5);
    EXPECT_EQ(la["count"], 12);
    EXPECT_EQ(la["outline"], true);
    EXPECT_EQ(la["palette"], "viridis");
    EXPECT_EQ(la["extra"], nlohmann::json::parse(R"({"keep": [1, 2]})")) << "keys the saver does not know survive";
    EXPECT_EQ(la["path"], "../scenes/data/a.bin");
    const auto& lb = j["layers"][1];
    EXPECT_EQ(lb["visible"], true);
    EXPECT_EQ(lb["viewpoint"], nlohmann::json::parse(R"({"lon": 1, "lat": 2, "range": 3})")) << "a layer's own viewpoint stays";

    // What is written parses back to the same state.
    auto back = parseSceneText(j.dump(), "/data/saved/knobs.json", "/data/saved");
    ASSERT_TRUE(back.ok()) << back.message();
    EXPECT_EQ(back->time.current, scene_->time().now());
    EXPECT_EQ(back->time.start, start);
    EXPECT_DOUBLE_EQ(back->time.rate, -60.0);
    EXPECT_EQ(back->resolve(back->layers[0].settings["path"].get<std::string>()), "/data/scenes/data/a.bin");
    ASSERT_EQ(back->annotations.size(), 1u);
    EXPECT_EQ(back->annotations[0].name, "Summit");
}

TEST_F(SceneSave, ALayerAddedWhileShownIsSavedWithItsProvenanceBeforeThePins) {
    registry_.add(LayerType{kAnnotationLayerType, "test pins", [](const LayerDesc&, const SceneDesc&) -> Result<std::unique_ptr<Layer>> {
        return std::unique_ptr<Layer>(new KnobLayer);
    }, {}});
    ASSERT_TRUE(scene_->ensureAnnotationLayer(registry_));
    LayerDesc result;
    result.type = "knobs";
    result.name = "A";   // taken: becomes "A (2)"
    result.settings = {{"path", "results/slope.tif"}, {"quality", 3}};
    result.provenance = {{"wps", "http://127.0.0.1:5000/wps"}, {"process", "terrain"}, {"reference", "http://127.0.0.1:5000/outputs/x.tif"}};
    auto added = scene_->addLayer(result, registry_);
    ASSERT_TRUE(added) << added.message();
    EXPECT_EQ((*added)->name, "A (2)");
    auto again = scene_->addLayer(result, registry_);
    ASSERT_TRUE(again);
    EXPECT_EQ((*again)->name, "A (3)");
    LayerDesc unknown;
    unknown.type = "no-such-type";
    EXPECT_FALSE(scene_->addLayer(unknown, registry_)) << "an unknown type is an error and adds nothing";

    const auto& r = scene_->resources();
    ASSERT_EQ(r.size(), 5u);
    EXPECT_EQ(r[2].name, "A (2)");
    EXPECT_EQ(r[3].name, "A (3)");
    EXPECT_EQ(r[4].type, kAnnotationLayerType) << "the pins stay last, drawn over the results";

    const nlohmann::json j = sceneToJson(*scene_, "/data/saved/knobs.json");
    ASSERT_EQ(j["layers"].size(), 4u) << j["layers"].dump() << ": the pins' layer is not in the file";
    const auto& saved = j["layers"][2];
    EXPECT_EQ(saved["name"], "A (2)");
    EXPECT_EQ(saved["type"], "knobs");
    EXPECT_EQ(saved["path"], "../scenes/results/slope.tif") << "relative to the scene it was added to";
    EXPECT_EQ(saved["provenance"]["process"], "terrain");
    EXPECT_EQ(j["layers"][3]["name"], "A (3)");

    auto back = parseSceneText(j.dump(), "/data/saved/knobs.json", "/data/saved");
    ASSERT_TRUE(back.ok()) << back.message();
    ASSERT_EQ(back->layers.size(), 4u);
    EXPECT_EQ(back->layers[2].provenance["reference"], "http://127.0.0.1:5000/outputs/x.tif");
    EXPECT_FALSE(back->layers[2].settings.contains("provenance")) << "the layer's own reader never sees it";
    EXPECT_TRUE(back->layers[0].provenance.is_null());
    EXPECT_FALSE(parseSceneText(R"({"layers": [{"type": "knobs", "provenance": 3}]})", "bad.json", "/data"))
        << "a provenance that is not an object";
}

/// Position within 1 µm and the view and up axes within 1e-9 rad: rounding of the pose ->
/// viewpoint -> pose round trip in double at 10^3..10^7 m.
void expectSamePose(const globe::Pose& a, const globe::Pose& b) {
    EXPECT_LT(glm::length(a.position - b.position), 1e-6);
    for (const glm::dvec3 axis : {glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0)})
        EXPECT_LT(glm::length(a.orientation * axis - b.orientation * axis), 1e-9);
}

TEST_F(SceneSave, ViewpointGivesTheCameraPoseBack) {
    const globe::Viewpoint views[] = {
        {7.0, 46.0, 0.0, 30.0, -40.0, 50000.0},
        {-179.9, 89.5, 0.0, 250.0, -10.0, 2000.0},   // near the pole, across the antimeridian
        {120.0, -30.0, 0.0, 0.0, -90.0, 4.0e7},      // straight down from far out
    };
    for (const auto& vp : views) {
        SCOPED_TRACE("viewpoint at lon " + std::to_string(vp.lonDeg) + ", lat " + std::to_string(vp.latDeg));
        scene_->camera().setPose(globe::poseFromViewpoint(vp));
        const nlohmann::json j = sceneToJson(*scene_, "/data/saved/knobs.json");
        Error error;
        const auto saved = readViewpoint(j["viewpoint"], "saved", "/viewpoint", &error);
        ASSERT_TRUE(saved) << error.message;
        expectSamePose(globe::poseFromViewpoint(*saved), scene_->camera().pose());
    }
    // Looking past the globe, up into space: the viewpoint is about a point in the air on the
    // centre ray. (Eastward along the equator, so that the camera has no roll about any point of
    // that ray: a viewpoint has no roll to keep.)
    for (const globe::Viewpoint& up : {globe::Viewpoint{0.0, 0.0, 2.0e7, 90.0, 10.0, 1.0e7},
                                       globe::Viewpoint{0.0, 0.0, 3.0e7, 90.0, 80.0, 1.0e6}}) {
        SCOPED_TRACE("looking up at " + std::to_string(up.pitchDeg) + " degrees");
        scene_->camera().setPose(globe::poseFromViewpoint(up));
        const nlohmann::json j = sceneToJson(*scene_, "/data/saved/knobs.json");
        Error error;
        const auto saved = readViewpoint(j["viewpoint"], "saved", "/viewpoint", &error);
        ASSERT_TRUE(saved) << error.message;
        expectSamePose(globe::poseFromViewpoint(*saved), scene_->camera().pose());
    }
}

TEST_F(SceneSave, CameraModeAndFieldOfViewAreWritten) {
    CameraModeSettings follow;
    follow.mode = CameraMode::Follow;
    follow.target = "A";
    follow.distance = 120.0;
    follow.pitchDeg = -20.0;
    follow.eye = {1.0, 2.0, 3.0};
    scene_->setCameraMode(follow);
    scene_->camera().setVerticalFovDeg(30.0);
    const nlohmann::json j = sceneToJson(*scene_, "/data/saved/knobs.json");
    EXPECT_NEAR(j["fovDeg"].get<double>(), 30.0, 1e-12);
    EXPECT_EQ(j["camera"]["mode"], "follow");
    EXPECT_EQ(j["camera"]["target"], "A");
    EXPECT_EQ(j["camera"]["distance"], 120.0);
    EXPECT_EQ(j["camera"]["pitch"], -20.0);
    EXPECT_EQ(j["camera"]["eye"], nlohmann::json::parse("[1.0, 2.0, 3.0]"));
    auto back = parseSceneText(j.dump(), "saved.json", "/data/saved");
    ASSERT_TRUE(back.ok()) << back.message();
    EXPECT_EQ(back->camera.mode, CameraMode::Follow);
    EXPECT_EQ(back->camera.target, "A");
}

TEST_F(SceneSave, SavedFileLoadsBackAndNoTemporaryIsLeft) {
    ASSERT_TRUE(scene_->resources()[0].layer->asLiveSettings()->setParameter("quality", 3.0));
    const fs::path file = dir_ / "out.json";
    std::ofstream(file) << "old contents";
    auto saved = saveScene(*scene_, file);
    ASSERT_TRUE(saved.ok()) << saved.message();
    auto back = parseSceneFile(file);
    ASSERT_TRUE(back.ok()) << back.message();
    EXPECT_EQ(back->layers[0].settings["quality"], 3.0);
    EXPECT_EQ(back->resolve(back->layers[0].settings["path"].get<std::string>()), "/data/scenes/data/a.bin");
    size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir_)) entries += e.path() == file ? 1 : 100;
    EXPECT_EQ(entries, 1u) << "only the scene file is in the folder";
}

TEST_F(SceneSave, MissingFolderIsAClearError) {
    const fs::path file = dir_ / "no-such-folder" / "out.json";
    auto saved = saveScene(*scene_, file);
    ASSERT_FALSE(saved.ok());
    EXPECT_EQ(saved.message(), file.string() + ": cannot save the scene: the folder " + (dir_ / "no-such-folder").string() +
                                   " does not exist");
}

TEST_F(SceneSave, FileInPlaceOfTheFolderIsAClearError) {
    std::ofstream(dir_ / "plain") << "x";
    auto saved = saveScene(*scene_, dir_ / "plain" / "out.json");
    ASSERT_FALSE(saved.ok());
    EXPECT_NE(saved.message().find((dir_ / "plain").string() + " is not a folder"), std::string::npos) << saved.message();
}

TEST_F(SceneSave, FolderAsTheFileIsAClearError) {
    auto saved = saveScene(*scene_, dir_);
    ASSERT_FALSE(saved.ok());
    EXPECT_NE(saved.message().find("this is a folder; give a file name"), std::string::npos) << saved.message();
    EXPECT_FALSE(saveScene(*scene_, "").ok());
}

TEST_F(SceneSave, ReadOnlyFolderIsAClearError) {
    fs::path locked = dir_ / "locked";
    fs::create_directories(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    // Root writes into read-only folders; sysfs takes no new files from anyone.
    if (::access(locked.c_str(), W_OK) == 0) locked = "/sys";
    if (!fs::is_directory(locked)) GTEST_SKIP() << "no folder this user cannot write into (root without /sys)";
    auto saved = saveScene(*scene_, locked / "out.json");
    ASSERT_FALSE(saved.ok());
    EXPECT_NE(saved.message().find((locked / "out.json").string() + ": cannot save the scene: cannot create a file in " +
                                   locked.string() + " ("),
              std::string::npos)
        << saved.message();
    EXPECT_FALSE(fs::exists(locked / ".out.json.saving"));
}

}  // namespace
}  // namespace orbis::scene
