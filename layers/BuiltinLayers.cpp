#include "layers/BuiltinLayers.h"

#include "layers/analysis/OverlayLayer.h"
#include "layers/analysis/ViewshedLayer.h"
#include "layers/annotations/AnnotationLayer.h"
#include "layers/fmv/FmvLayer.h"
#include "layers/earth/EarthLayer.h"
#include "layers/models/ModelLayer.h"
#include "layers/points/PointsLayer.h"
#include "layers/terrain/TerrainLayer.h"
#include "layers/vector/VectorLayer.h"
#include "layers/volume/VolumeLayer.h"

namespace orbis::layers {

void registerBuiltinLayers(scene::LayerRegistry& registry) {
    for (scene::LayerType type : {EarthLayer::layerType(), TerrainLayer::layerType(), VolumeLayer::layerType(),
                                  PointsLayer::layerType(), ModelLayer::layerType(), AnnotationLayer::layerType(),
                                  FmvLayer::layerType(), VectorLayer::layerType(), ViewshedLayer::layerType(),
                                  OverlayLayer::layerType()})
        registry.add(std::move(type));
}

}  // namespace orbis::layers
