#pragma once
// Renders a scene given as JSON text on the test device and returns the image.

#include "base/Png.h"
#include "engine/render/Renderer.h"
#include "engine/scene/Scene.h"
#include "layers/BuiltinLayers.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace orbis::test {

inline std::unique_ptr<scene::Scene> buildScene(const std::string& json, const scene::LayerRegistry& registry) {
    auto desc = scene::parseSceneText(json, "test.json", ".");
    EXPECT_TRUE(desc.ok()) << (desc.ok() ? "" : desc.message());
    if (!desc) return nullptr;
    auto scene = scene::Scene::build(std::move(desc).value(), registry);
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.message());
    if (!scene) return nullptr;
    return std::move(scene).value();
}

inline ImageRgba8 renderOnce(render::Renderer& renderer, scene::Scene& scene) {
    scene.time().advance(0.0);
    const auto frame = renderer.render(scene, true);
    return ImageRgba8{renderer.width(), renderer.height(), renderer.readPixels(frame)};
}

/// Renders `scene` at w x h once everything its view needs has loaded (at most 120 s), with
/// `renderer` made (again) for that size when it has another.
inline ImageRgba8 renderSettled(std::unique_ptr<render::Renderer>& renderer, gpu::Device& device, scene::Scene& scene,
                                uint32_t w, uint32_t h) {
    if (!renderer || renderer->width() != w || renderer->height() != h)
        renderer = std::make_unique<render::Renderer>(device, w, h);
    scene.time().advance(0.0);
    renderer->settle(scene, 120.0);
    EXPECT_FALSE(scene.busy()) << "still loading after 120 s";
    const auto frame = renderer->render(scene, true);
    return ImageRgba8{w, h, renderer->readPixels(frame)};
}

/// A globe-only scene looking at `viewpoint` (a JSON object) at a fixed time.
inline std::string globeScene(const std::string& viewpoint, const std::string& layerExtra = "",
                              const std::string& time = "2026-03-20T12:00:00Z") {
    return R"({"viewpoint": )" + viewpoint + R"(, "time": {"start": ")" + time + R"(", "end": ")" + time +
           R"("}, "layers": [{"type": "globe", "name": "Earth")" + layerExtra + "}]}";
}

}  // namespace orbis::test
