// Terrain tiles: one TileDraw per drawn tile in a per-frame storage buffer (set 1, binding 0),
// picked by gl_InstanceIndex (the draw's firstInstance); tile data lives in pages of array
// textures (bindings 1 and 2); the shaders pick a page with a switch over constant indices.
#ifndef ORBIS_SHADERS_SHARED_TERRAIN_TYPES_H
#define ORBIS_SHADERS_SHARED_TERRAIN_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kTerrainSet, 1)
ORBIS_CONST(uint, kTerrainMaxImagery, 4)
ORBIS_CONST(uint, kElevationPages, 4)
ORBIS_CONST(uint, kElevationSlotsPerPage, 128)
ORBIS_CONST(uint, kImageryPages, 8)
ORBIS_CONST(uint, kImagerySlotsPerPage, 32)

// std430; every member 16-byte aligned.
struct TileDraw {
    mat4 modelViewProj;        // tile centre relative to the eye, projection included (built in double)
    vec4 originFromEye;        // xyz: tile centre minus eye, world axes; w: skirt depth (m)
    vec4 elevationScaleBias;   // this tile's uv -> the elevation tile's uv (an ancestor while loading)
    ivec4 elevation;           // x: slot (-1: none, height 0), y: grid size of the elevation tile
    vec4 imageryScaleBias[4];  // per imagery layer, as above
    ivec4 imagerySlot;         // per imagery layer: slot, or -1 (nothing loaded yet, or hidden)
};

// Push constants, once per terrain layer.
struct TerrainPush {
    vec4 baseColor;            // rgb: colour where no imagery (linear); a: vertical exaggeration
    vec4 imageryOpacity;       // per imagery layer
    vec4 params;               // x: 1 = sun lighting, 0 = headlight; y: 1 = tile borders (debug); z: imagery tile size (px)
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::TileDraw) == 192, "TileDraw layout changed");
static_assert(offsetof(orbis::shader::TileDraw, imageryScaleBias) == 112, "std430 offset");
static_assert(sizeof(orbis::shader::TerrainPush) == 48, "TerrainPush must fit push constants");
#endif

#endif
