// The minimal ellipsoid layer: push constants per patch.
#ifndef ORBIS_SHADERS_SHARED_GLOBE_TYPES_H
#define ORBIS_SHADERS_SHARED_GLOBE_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

// std430 push constants (<= 128 bytes, the guaranteed minimum).
struct EarthPush {
    mat4 modelViewProj;     // patch origin relative to the eye, projection included (built in double)
    vec4 originFromEye;     // xyz: patch origin minus eye position, world axes (double -> float)
    vec4 graticule;         // x: spacing (deg), y: line half-width (px), z: 1 = draw lines, w: unused
    vec4 baseColor;         // rgb: surface colour (linear), a: unused
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::EarthPush) == 112, "EarthPush must fit 128 bytes of push constants");
static_assert(offsetof(orbis::shader::EarthPush, graticule) == 80, "std430 offset");
#endif

#endif
