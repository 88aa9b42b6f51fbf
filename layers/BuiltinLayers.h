#pragma once
// Registers every layer type this build knows. Apps call it once at start.

#include "engine/scene/LayerRegistry.h"

namespace orbis::layers {

void registerBuiltinLayers(scene::LayerRegistry& registry);

}  // namespace orbis::layers
