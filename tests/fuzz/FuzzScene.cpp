// Scene files: the description (viewpoint, time, layers, annotations) and each layer's own
// settings as its type reads them when the scene is made (no GPU: create, not prepare). Paths
// resolve under a folder that does not exist.
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/SceneDesc.h"
#include "layers/BuiltinLayers.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const orbis::scene::LayerRegistry registry = [] {
        orbis::scene::LayerRegistry r;
        orbis::layers::registerBuiltinLayers(r);
        return r;
    }();
    auto desc = orbis::scene::parseSceneText(orbis::fuzz::text(data, size), "/nonexistent/fuzz.json", "/nonexistent");
    if (!desc) return 0;
    for (const auto& layer : desc->layers)
        if (registry.has(layer.type)) (void)registry.create(layer, *desc);
    return 0;
}
