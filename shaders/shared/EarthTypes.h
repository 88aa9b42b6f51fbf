// The minimal ellipsoid layer (layers/earth): a vertex stream, push constants per patch, set 0 only.
#ifndef ORBIS_SHADERS_SHARED_GLOBE_TYPES_H
#define ORBIS_SHADERS_SHARED_GLOBE_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

// Vertex inputs: layers::EarthVertex.
ORBIS_CONST(uint, kEarthInputPosition, 0)   // relative to the patch origin
ORBIS_CONST(uint, kEarthInputNormal, 1)
ORBIS_CONST(uint, kEarthInputLonLat, 2)     // degrees

// std430 push constants (<= 128 bytes, the guaranteed minimum).
struct EarthPush {
    mat4 modelViewProj;       // patch origin relative to the eye, projection included (built in double)
    vec3 originFromEye;       // patch origin minus eye position, world axes (double -> float)
    float pad0;
    float graticuleDeg;       // line spacing
    float lineHalfWidthPx;
    uint drawLines;           // 1: the graticule is drawn
    uint sunLighting;         // 1: the sun, 0: a headlight
    vec3 baseColor;           // surface colour (linear)
    float pad1;
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::EarthPush) == 112, "EarthPush must fit 128 bytes of push constants");
static_assert(offsetof(orbis::shader::EarthPush, graticuleDeg) == 80, "std430 offset");
static_assert(offsetof(orbis::shader::EarthPush, baseColor) == 96, "std430 offset");
#endif

#endif
