// Animated glTF models on lavapipe with validation: the real AnimatedMorphCube (morph targets
// and a weights animation) and a synthetic two-joint skin at two scene times, poses shared by
// copies at one animation time, the same time through different seeks, and bad "animation"
// settings that must give clear errors.
#include "layers/models/ModelLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"
#include "tests/unit/GltfTestFiles.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;

const fs::path kMorphCube = fs::path(ORBIS_SOURCE_DIR) / ".." / "shared" / "data" / "models" / "AnimatedMorphCube" / "AnimatedMorphCube.gltf";
const TimeNs kStart = parseIso8601("2026-03-20T10:00:00Z").value();

std::string jsonString(const fs::path& p) { return nlohmann::json(p.string()).dump(); }

/// A globe and one model at (7, 46), looked at from 6 m; `extra` adds keys to the model layer.
std::string modelScene(const fs::path& file, const std::string& extra, double range = 6.0, double height = 0.0) {
    return R"({"viewpoint": {"lon": 7.0, "lat": 46.0, "height": )" + std::to_string(height) +
           R"(, "heading": 30, "pitch": -20, "range": )" + std::to_string(range) +
           R"(}, "time": {"start": "2026-03-20T10:00:00Z", "end": "2026-03-20T10:10:00Z"},
        "layers": [{"type": "globe", "name": "Earth"},
                   {"type": "model", "name": "M", "file": )" + jsonString(file) + R"(, "position": [7.0, 46.0, 0.5])" + extra + "}]}";
}

class ModelAnimationRender : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        layers::registerBuiltinLayers(registry_);
        dir_ = fs::path(testOutputDir()) / ("model-anim-" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        fs::remove_all(dir_);
        GpuTest::TearDown();
    }
    std::unique_ptr<scene::Scene> load(const std::string& json) { return buildScene(json, registry_); }
    ImageRgba8 renderAt(scene::Scene& s, double seconds, uint32_t w = 240, uint32_t h = 160) {
        if (!renderer_ || renderer_->width() != w || renderer_->height() != h)
            renderer_ = std::make_unique<render::Renderer>(device(), w, h);
        s.time().seek(kStart + fromSeconds(seconds));
        s.time().advance(0.0);
        renderer_->settle(s, 60.0);
        const auto frame = renderer_->render(s, true);
        return ImageRgba8{w, h, renderer_->readPixels(frame)};
    }
    static layers::ModelLayer& model(scene::Scene& s) { return dynamic_cast<layers::ModelLayer&>(*s.find("M")->layer); }
    fs::path writeArm() {
        const fs::path f = dir_ / "arm.gltf";
        std::ofstream(f) << twoJointArmGltf();
        return f;
    }
    void expectError(const std::string& json, const std::string& needle) {
        auto desc = scene::parseSceneText(json, "test.json", ".");
        ASSERT_TRUE(desc) << desc.message();
        auto s = scene::Scene::build(std::move(*desc), registry_);
        ASSERT_FALSE(s) << json;
        EXPECT_NE(s.message().find(needle), std::string::npos) << s.message();
    }

    scene::LayerRegistry registry_;
    std::unique_ptr<render::Renderer> renderer_;
    fs::path dir_;
};

TEST_F(ModelAnimationRender, MorphCubeChangesShapeWithSceneTime) {
    if (!fs::exists(kMorphCube)) GTEST_SKIP() << "shared data absent: " << kMorphCube;
    auto s = load(modelScene(kMorphCube, ""));
    ASSERT_TRUE(s);
    // Animation time 0 is the scene's start: both weights 0 (the plain cube); at 1.5 s the
    // "thin" target is at about 0.7.
    const auto cube = renderAt(*s, 0.0);
    EXPECT_EQ(model(*s).posesThisFrame(), 1u);
    const auto morphed = renderAt(*s, 1.5);
    EXPECT_TRUE(matchesGolden(cube, "model_morph_cube_0s"));
    EXPECT_TRUE(matchesGolden(morphed, "model_morph_cube_1.5s"));
    EXPECT_GT(countDifferentPixels(cube, morphed, 8), 200u) << "the two poses look the same";
    // Looped: one duration (4.2 s) later is the same picture.
    const auto looped = renderAt(*s, 1.5 + 4.2 * 3);
    EXPECT_LT(countDifferentPixels(morphed, looped, 2), 10u);
}

TEST_F(ModelAnimationRender, SkinnedArmBendsWithSceneTime) {
    auto s = load(modelScene(writeArm(), R"(, "attitude": [30, 0, 0])", 6.0, 1.5));
    ASSERT_TRUE(s);
    const auto straight = renderAt(*s, 0.0);
    const auto bent = renderAt(*s, 0.75);
    EXPECT_TRUE(matchesGolden(straight, "model_skin_arm_0s"));
    EXPECT_TRUE(matchesGolden(bent, "model_skin_arm_0.75s"));
    EXPECT_GT(countDifferentPixels(straight, bent, 8), 100u);
    // "animation": false keeps the bind pose: the picture of time 0 at any time.
    auto rest = load(modelScene(dir_ / "arm.gltf", R"(, "attitude": [30, 0, 0], "animation": false)", 6.0, 1.5));
    ASSERT_TRUE(rest);
    EXPECT_LT(countDifferentPixels(straight, renderAt(*rest, 0.75), 2), 10u);
}

// A mesh file's node animation (COLLADA through Assimp) plays on the scene's time as glTF's do:
// the moving triangle is elsewhere at 1 s than at 0 s, looped after its 2 s; "animation": false
// keeps the rest pose.
TEST_F(ModelAnimationRender, MeshFileNodeAnimationPlaysOnSceneTime) {
    const fs::path file = dir_ / "moving.dae";
    std::ofstream(file) << movingNodesCollada(1.5, 0.6);
    auto s = load(modelScene(file, ""));
    ASSERT_TRUE(s);
    const auto start = renderAt(*s, 0.0);
    const auto later = renderAt(*s, 1.0);
    EXPECT_GT(countDifferentPixels(start, later, 8), 100u) << "the mover did not move";
    EXPECT_LT(countDifferentPixels(later, renderAt(*s, 1.0 + 2.0 * 3), 2), 10u) << "looped every 2 s";
    auto rest = load(modelScene(file, R"(, "animation": false)"));
    ASSERT_TRUE(rest);
    EXPECT_LT(countDifferentPixels(start, renderAt(*rest, 1.0), 2), 10u);
    EXPECT_TRUE(matchesGolden(later, "model_mesh_animation_1s"));
}

TEST_F(ModelAnimationRender, CopiesAtOneAnimationTimeShareAPose) {
    // Five copies one loop apart (spacing = the 1 s animation with speed 1... looped) share one
    // pose; 0.3 s apart they need five; not looped and past the end they share the last.
    const fs::path arm = writeArm();
    auto poses = [&](const std::string& animation, double spacing) {
        auto s = load(modelScene(arm, R"(, "copies": {"count": 5, "spacing": )" + std::to_string(spacing) + "}" + animation, 7.0));
        EXPECT_TRUE(s);
        if (!s) return 0u;
        renderAt(*s, 20.25, 64, 48);
        EXPECT_EQ(model(*s).itemsDrawn(), 5u);
        return model(*s).posesThisFrame();
    };
    EXPECT_EQ(poses("", 1.0), 1u);
    EXPECT_EQ(poses("", 0.3), 5u);
    EXPECT_EQ(poses(R"(, "animation": {"loop": false})", 0.3), 1u);
    EXPECT_EQ(poses(R"(, "animation": {"speed": 0})", 0.3), 1u);
}

TEST_F(ModelAnimationRender, SameTimeThroughDifferentSeeksGivesTheSameImage) {
    const fs::path arm = writeArm();
    const std::string json = modelScene(arm, R"(, "attitude": [30, 0, 0], "animation": {"speed": 0.37})", 6.0, 1.5);
    auto a = load(json);
    auto b = load(json);
    ASSERT_TRUE(a && b);
    const auto direct = renderAt(*a, 2.0);
    for (double t : {9.0, 0.1, 5.5}) renderAt(*b, t);
    EXPECT_EQ(countDifferentPixels(direct, renderAt(*b, 2.0), 0), 0u);
}

TEST_F(ModelAnimationRender, BadAnimationSettingsGiveClearErrors) {
    const fs::path arm = writeArm();
    expectError(modelScene(arm, R"(, "animation": {"name": "Run"})"), "no animation \"Run\"");
    expectError(modelScene(arm, R"(, "animation": {"name": "Run"})"), "arm.gltf");
    expectError(modelScene(arm, R"(, "animation": {"name": "Run"})"), "/layers/1/animation/name");
    expectError(modelScene(arm, R"(, "animation": {"index": 3})"), "3 is past the 1 animations");
    expectError(modelScene(arm, R"(, "animation": {"index": 0, "name": "Bend"})"), "not both");
    expectError(modelScene(arm, R"(, "animation": {"speed": 1e9})"), "speed");
    expectError(modelScene(arm, R"(, "animation": {"loops": true})"), "unknown key 'loops'");
    expectError(modelScene(arm, R"(, "animation": {"start": "yesterday"})"), "start");
    expectError(modelScene(arm, R"(, "animation": "Bend")"), "expected false or an object");
    const fs::path wagon = fs::path(ORBIS_SOURCE_DIR) / "assets/models/wagon.gltf";
    expectError(modelScene(wagon, R"(, "animation": {"name": "Bend"})"), "has no animations");
}

}  // namespace
}  // namespace orbis::test
