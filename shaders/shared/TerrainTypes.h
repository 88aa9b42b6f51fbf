// Terrain tiles: one TileDraw per drawn tile in a per-frame storage buffer (set kTerrainSet),
// picked by gl_InstanceIndex (the draw's firstInstance); elevation and imagery each live in one
// array texture whose layers are the slots (layers/terrain/TileSlotPool.h).
#ifndef ORBIS_SHADERS_SHARED_TERRAIN_TYPES_H
#define ORBIS_SHADERS_SHARED_TERRAIN_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kTerrainSet, 1)
ORBIS_CONST(uint, kTerrainBindingDraws, 0)       // TileDraw[] (storage buffer)
ORBIS_CONST(uint, kTerrainBindingElevation, 1)   // sampler2DArray: a layer per elevation slot
ORBIS_CONST(uint, kTerrainBindingImagery, 2)     // sampler2DArray: a layer per imagery slot

ORBIS_CONST(uint, kTerrainSpecImageryLayers, 0)   // int: imagery layers the pipeline blends
ORBIS_CONST(uint, kTerrainSpecFirstDrape, 1)      // int: the first of them that is a layer's drape

// Vertex inputs: globe::TileVertex.
ORBIS_CONST(uint, kTerrainInputPosition, 0)
ORBIS_CONST(uint, kTerrainInputNormal, 1)
ORBIS_CONST(uint, kTerrainInputUv, 2)
ORBIS_CONST(uint, kTerrainInputCellMetres, 3)

ORBIS_CONST(uint, kTerrainMaxImagery, 4)
ORBIS_CONST(uint, kElevationMaxSlots, 512)   // array layers, at most
ORBIS_CONST(uint, kImageryMaxSlots, 256)

// std430; every vector 16-byte aligned.
struct TileDraw {
    mat4 modelViewProj;        // tile centre relative to the eye, projection included (built in double)
    vec3 originFromEye;        // tile centre minus eye, world axes
    float skirtDepth;          // metres
    vec4 elevationScaleBias;   // this tile's uv -> the elevation tile's uv (an ancestor while loading)
    int elevationSlot;         // -1: none (height 0)
    int elevationGridSize;     // samples a side of the elevation tile
    int pad0;
    int pad1;
    vec4 imageryScaleBias[kTerrainMaxImagery];   // per imagery layer, as above
    ivec4 imagerySlot;         // per imagery layer: slot, or -1 (nothing loaded yet, or hidden)
};

// Push constants, once per terrain layer.
struct TerrainPush {
    vec3 baseColor;               // where no imagery (linear)
    float verticalExaggeration;
    vec4 imageryOpacity;          // per imagery layer
    uint sunLighting;             // 1: the sun, 0: a headlight
    uint tileBorders;             // 1: draw the tiles' borders (debug)
    float imageSizePx;            // imagery tile size
    uint nightLayers;             // bit i: imagery layer i is the night side's lights
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
namespace orbis::shader {
/// Set kTerrainSet, one per frame in flight (layers/terrain/TerrainLayer.cpp).
inline constexpr DescriptorBinding kTerrainBindings[] = {
    {kTerrainBindingDraws, DescriptorKind::StorageBuffer, 1, kStageVertex | kStageFragment},
    {kTerrainBindingElevation, DescriptorKind::CombinedImageSampler, 1, kStageVertex},
    {kTerrainBindingImagery, DescriptorKind::CombinedImageSampler, 1, kStageFragment},
};
inline constexpr SpecConstant kTerrainSpecConstants[] = {{kTerrainSpecImageryLayers, SpecType::Int},
                                                        {kTerrainSpecFirstDrape, SpecType::Int}};
}  // namespace orbis::shader
static_assert(sizeof(orbis::shader::TileDraw) == 192, "TileDraw layout changed");
static_assert(offsetof(orbis::shader::TileDraw, skirtDepth) == 76, "std430 offset: a float after a vec3");
static_assert(offsetof(orbis::shader::TileDraw, elevationSlot) == 96, "std430 offset");
static_assert(offsetof(orbis::shader::TileDraw, imageryScaleBias) == 112, "std430 offset");
static_assert(sizeof(orbis::shader::TerrainPush) == 48, "TerrainPush must fit push constants");
static_assert(offsetof(orbis::shader::TerrainPush, sunLighting) == 32, "std430 offset");
#endif

#endif
