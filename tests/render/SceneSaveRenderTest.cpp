// Saving a scene (engine/scene/SceneSave.h) on lavapipe with validation: a terrain with two
// volumes is changed as a viewer user would (camera, time, settings, a layer hidden), saved into
// another folder, loaded from there and rendered: the picture is the one the changed scene shows.
#include "engine/scene/SceneSave.h"
#include "globe/Ellipsoid.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"

#include <nlohmann/json.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;

// The mountain fixture (its DEM and image copied next to the scene, named relatively), a sphere
// field above the peak and a second field beside it.
constexpr const char* kScene = R"({"name": "Mountain with volumes",
    "viewpoint": {"lon": 7, "lat": 46, "height": 1500, "heading": 30, "pitch": -25, "range": 90000},
    "time": {"start": "2026-06-21T04:00:00Z", "end": "2026-06-21T20:00:00Z", "current": "2026-06-21T06:30:00Z"},
    "background": [0, 0, 0.012],
    "layers": [
      {"type": "terrain", "name": "Mountain", "elevation": ["dem.tif"], "imagery": [{"path": "image.tif"}],
       "sky": false, "gridSize": 33},
      {"type": "volume", "name": "Plume", "synthetic": {"field": "sphere", "size": [24, 24, 24],
       "lon": [6.97, 7.05], "lat": [45.97, 46.03], "height": [4500, 9000]},
       "colorMap": "viridis", "opacity": [[0, 0.6], [12, 0.0]], "steps": 64, "mode": ["dvr", "iso"], "isovalues": [9]},
      {"type": "volume", "name": "Cloud", "synthetic": {"field": "waves", "size": [16, 16, 16],
       "lon": [7.05, 7.12], "lat": [45.99, 46.04], "height": [5000, 8000]},
       "colorMap": "magma", "opacity": [[-1, 0.0], [1, 0.5]]}]})";

class SceneSaveRender : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        if (HasFatalFailure()) return;
        renderer_ = std::make_unique<render::Renderer>(device(), 240, 160);
        layers::registerBuiltinLayers(registry_);
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::path(testOutputDir()) / ("scene-save-" + std::string(info->name()) + "-" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "original");
        fs::create_directories(dir_ / "saved" / "deeper");
        const auto& f = terrainFixtures();
        fs::copy_file(f.dem, dir_ / "original" / "dem.tif");
        fs::copy_file(f.image, dir_ / "original" / "image.tif");
        std::ofstream(dir_ / "original" / "scene.json") << kScene;
    }
    void TearDown() override {
        GpuTest::TearDown();
        if (!HasFailure()) fs::remove_all(dir_);
    }

    std::unique_ptr<scene::Scene> loadFile(const fs::path& file) {
        auto desc = scene::parseSceneFile(file);
        EXPECT_TRUE(desc.ok()) << (desc.ok() ? "" : desc.message());
        if (!desc) return nullptr;
        auto built = scene::Scene::build(std::move(desc).value(), registry_);
        EXPECT_TRUE(built.ok()) << (built.ok() ? "" : built.message());
        if (!built) return nullptr;
        return std::move(built).value();
    }

    /// Loads what the view needs. The volumes are hidden meanwhile: their ray start is jittered
    /// by the layer's own frame count, so that they must draw their first frame in the picture
    /// of both scenes to be compared pixel for pixel.
    void settle(scene::Scene& scene) {
        std::vector<bool> shown;
        for (auto& r : scene.resources()) {
            shown.push_back(r.visible);
            if (r.type == "volume") r.visible = false;
        }
        scene.time().advance(0.0);
        renderer_->settle(scene, 120.0);
        EXPECT_FALSE(scene.busy()) << "still loading after 120 s";
        for (size_t i = 0; i < shown.size(); ++i) scene.resources()[i].visible = shown[i];
    }

    ImageRgba8 frame(scene::Scene& scene) {
        const auto result = renderer_->render(scene, true);
        return ImageRgba8{renderer_->width(), renderer_->height(), renderer_->readPixels(result)};
    }

    scene::LayerRegistry registry_;
    std::unique_ptr<render::Renderer> renderer_;
    fs::path dir_;
};

TEST_F(SceneSaveRender, SavedSceneRendersWhatTheChangedSceneShowed) {
    auto changed = loadFile(dir_ / "original" / "scene.json");
    ASSERT_TRUE(changed);
    // What a viewer user does: move the camera, seek and play faster, coarser terrain, another
    // colour map and more opacity for one volume, hide the other.
    changed->camera().setPose(globe::poseFromViewpoint({7.02, 45.93, 2500.0, 15.0, -12.0, 30000.0}));
    changed->time().seek(parseIso8601("2026-06-21T15:20:00Z").value());
    changed->time().setRate(30.0);
    changed->time().setLoop(true);
    scene::Resource* terrain = changed->find("Mountain");
    scene::Resource* plume = changed->find("Plume");
    scene::Resource* cloud = changed->find("Cloud");
    ASSERT_TRUE(terrain && plume && cloud);
    ASSERT_TRUE(terrain->layer->asLiveSettings()->setParameter("maxScreenSpaceError", 6.0));
    ASSERT_TRUE(plume->layer->asLiveSettings()->setOption("colorMap", "magma"));
    ASSERT_TRUE(plume->layer->asLiveSettings()->setParameter("opacityScale", 3.0));
    ASSERT_TRUE(plume->layer->asLiveSettings()->setParameter("isovalue0", 7.0));
    ASSERT_TRUE(plume->layer->asLiveSettings()->setCurve("opacity", {{1.0, 0.0}, {6.0, 0.9}, {12.0, 0.2}}));   // the editor's points
    cloud->visible = false;
    settle(*changed);

    const fs::path savedFile = dir_ / "saved" / "deeper" / "scene.json";
    auto saved = scene::saveScene(*changed, savedFile);
    ASSERT_TRUE(saved.ok()) << saved.message();
    const ImageRgba8 expected = frame(*changed);

    // The file says what changed, with the files named from its own folder.
    std::ifstream in(savedFile);
    const auto json = nlohmann::json::parse(in);
    EXPECT_EQ(json["time"]["current"], "2026-06-21T15:20:00Z");
    EXPECT_EQ(json["time"]["rate"], 30.0);
    EXPECT_EQ(json["layers"][0]["maxScreenSpaceError"], 6.0);
    EXPECT_EQ(json["layers"][0]["elevation"][0], "../../original/dem.tif");
    EXPECT_EQ(json["layers"][0]["imagery"][0]["path"], "../../original/image.tif");
    EXPECT_EQ(json["layers"][0]["gridSize"], 33) << "keys without a live setting are kept";
    EXPECT_EQ(json["layers"][1]["colorMap"], "magma");
    EXPECT_EQ(json["layers"][1]["opacityScale"], 3.0);
    EXPECT_EQ(json["layers"][1]["isovalues"], nlohmann::json::parse("[7.0]"));
    EXPECT_EQ(json["layers"][1]["opacity"], nlohmann::json::parse("[[1.0, 0.0], [6.0, 0.9], [12.0, 0.2]]"));
    EXPECT_EQ(json["layers"][2]["visible"], false);

    auto reloaded = loadFile(savedFile);
    ASSERT_TRUE(reloaded);
    settle(*reloaded);
    const ImageRgba8 actual = frame(*reloaded);
    // Time and settings come back exactly, the camera from the saved viewpoint to within
    // micrometres (double rounding of pose -> viewpoint -> pose). That moves the float
    // interpolants by ~1e-7, which flips the 8-bit rounding of a few pixels (17 of 38 400 here)
    // by one step; and where the volume's rays end on the terrain's depth, under the steep
    // edited opacity curve, a sample more or less changes 2 pixels by a few steps. No more.
    EXPECT_TRUE(imagesAgree(expected, actual, "scene_save_reloaded", 1, 4));
    EXPECT_TRUE(imagesAgree(expected, actual, "scene_save_reloaded", 24, 0));
    // The hidden volume is in view: hiding it is part of what was saved.
    reloaded->find("Cloud")->visible = true;
    EXPECT_GT(countDifferentPixels(frame(*reloaded), actual, 8), 50u);

    // The changes show: the scene as first loaded looks different.
    auto original = loadFile(dir_ / "original" / "scene.json");
    ASSERT_TRUE(original);
    settle(*original);
    const ImageRgba8 before = frame(*original);
    EXPECT_GT(countDifferentPixels(before, expected, 8), size_t(expected.width) * expected.height / 4);
}

}  // namespace
}  // namespace orbis::test
