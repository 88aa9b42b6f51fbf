// Point clouds: compute rasterisation (before the points pass) and its resolve (fragment, in the
// pass), or the point-list fallback. Set 1 bindings: 0 PointUniforms (per frame), 1 positions
// (3 floats a point, relative to its node's centre), 2 attributes (2 uints a point), 3 the
// frame's batches (uvec4: drawn node, first point, count), 4 the drawn nodes' centres relative to
// the eye (vec4, from doubles on the CPU), 5 the screen buffer (one uint64 a pixel: depth bits
// << 32 | point index; 0 = empty), 6 the scene depth (sampler2D).
#ifndef ORBIS_SHADERS_SHARED_POINT_TYPES_H
#define ORBIS_SHADERS_SHARED_POINT_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kPointGroupSize, 256)      // compute workgroup: 256 invocations
ORBIS_CONST(uint, kPointsPerInvocation, 8)   // each invocation splats up to 8 points of a batch
ORBIS_CONST(uint, kPointBatch, 2048)         // points per batch = kPointGroupSize * kPointsPerInvocation

// Colour modes (specialisation constant 1 of the resolve and point-list shaders).
ORBIS_CONST(uint, kPointColorRgb, 0)
ORBIS_CONST(uint, kPointColorIntensity, 1)
ORBIS_CONST(uint, kPointColorClassification, 2)
ORBIS_CONST(uint, kPointColorHeight, 3)
ORBIS_CONST(uint, kPointColorConstant, 4)

// std140: vec4 and mat4 members only.
struct PointUniforms {
    mat4 viewProj;        // projection * view rotation: positions relative to the eye -> clip
    vec4 colorInfo;       // x: unused, y: intensity gain (1 / the cloud's 99th percentile),
                          // z, w: height ramp over the stored 0..1 heights: (h - z) * w
    vec4 constantColor;   // rgb: linear colour for kPointColorConstant
    vec4 edl;             // x: unused (EDL on/off is specialisation constant 2), y: strength, z: radius (px), w: point size (px)
    vec4 screen;          // x, y: width, height (pixels)
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::PointUniforms) == 64 + 4 * 16, "PointUniforms layout changed");
static_assert(orbis::shader::kPointBatch == orbis::shader::kPointGroupSize * orbis::shader::kPointsPerInvocation);
#endif

#endif
