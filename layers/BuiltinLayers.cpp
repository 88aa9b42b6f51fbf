#include "layers/BuiltinLayers.h"

#include "layers/globe/GlobeLayer.h"

namespace orbis::layers {

void registerBuiltinLayers(scene::LayerRegistry& registry) {
    registry.add("globe", "WGS84 ellipsoid with graticule, sun lighting and sky", &GlobeLayer::create);
}

}  // namespace orbis::layers
