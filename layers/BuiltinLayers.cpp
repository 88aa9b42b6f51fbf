#include "layers/BuiltinLayers.h"

#include "layers/annotations/AnnotationLayer.h"
#include "layers/fmv/FmvLayer.h"
#include "layers/earth/EarthLayer.h"
#include "layers/models/ModelLayer.h"
#include "layers/points/PointsLayer.h"
#include "layers/terrain/TerrainLayer.h"
#include "layers/volume/VolumeLayer.h"

namespace orbis::layers {

void registerBuiltinLayers(scene::LayerRegistry& registry) {
    registry.add("globe", "WGS84 ellipsoid with graticule, sun lighting and sky", &EarthLayer::create);
    registry.add("terrain", "WGS84 quadtree terrain streaming DEMs and imagery through GDAL", &TerrainLayer::create);
    registry.add("volume", "netCDF scalar field in a curved geo-box, ray cast on the GPU", &VolumeLayer::create);
    registry.add("points", "LAS point cloud, splatted by compute shaders with eye-dome lighting", &PointsLayer::create);
    registry.add("model", "glTF 2.0 model, fixed or moving along a trajectory or a live position feed", &ModelLayer::create);
    registry.add(scene::kAnnotationLayerType, "the scene's labelled pins (added by itself when the scene has any)",
                 &AnnotationLayer::create);
    registry.add("fmv", "full-motion video (MISB ST 0601 KLV) draped on the terrain from its sensor", &FmvLayer::create);
}

}  // namespace orbis::layers
