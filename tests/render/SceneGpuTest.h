#pragma once
// A render test over scenes given as JSON: the built-in layer types registered, a scene built
// from text, rendered once everything its view needs has loaded.
#include "layers/BuiltinLayers.h"
#include "tests/render/RenderHelpers.h"
#include "tests/support/GpuTest.h"

#include <memory>
#include <string>

namespace orbis::test {

class SceneGpuTest : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        layers::registerBuiltinLayers(registry_);
    }
    std::unique_ptr<scene::Scene> load(const std::string& json) { return buildScene(json, registry_); }
    ImageRgba8 renderScene(scene::Scene& scene, uint32_t w, uint32_t h) { return renderSettled(renderer_, device(), scene, w, h); }
    /// Why a scene that parses cannot be built (a layer's bad key); empty when it builds.
    std::string buildError(const std::string& json) {
        auto desc = scene::parseSceneText(json, "bad.json", ".");
        EXPECT_TRUE(desc) << desc.message();
        if (!desc) return {};
        auto built = scene::Scene::build(std::move(*desc), registry_);
        return built ? std::string() : built.message();
    }

    scene::LayerRegistry registry_;
    std::unique_ptr<render::Renderer> renderer_;
};

}  // namespace orbis::test
