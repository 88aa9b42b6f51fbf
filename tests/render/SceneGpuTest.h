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

    scene::LayerRegistry registry_;
    std::unique_ptr<render::Renderer> renderer_;
};

}  // namespace orbis::test
