// Point clouds: compute rasterisation (before the points pass) and its resolve (fragment, in the
// pass), or the point-list fallback. Set 1 bindings: 0 PointUniforms (per frame), 1 and 2 a page
// of the resident nodes' data (dynamic storage buffers at the page's offset, bound as uint words
// for the positions and as uvec2 for the attributes; layout in layers/points/PointStore.h), 3 the
// frame's batches (uvec4: drawn node, first point of the node, count, 0), 4 the drawn nodes
// (PointNode), 5 the screen buffer (one uint64 a pixel: depth bits << 32 | sRGB r | g << 8 |
// b << 16; 0 = empty), 6 the scene depth (sampler2D).
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

// A drawn node (std430).
struct PointNode {
    vec4 centreStep;   // xyz: the node's centre relative to the eye (from doubles on the CPU);
                       // w: the quantisation step (m), 0 for float positions
    uvec4 data;        // x: its first point's attribute index (uvec2 units), y: its positions'
                       // first word, both within its page; z: its point count, w: 0
};

// std140: vec4 and mat4 members only.
struct PointUniforms {
    mat4 viewProj;        // projection * view rotation: positions relative to the eye -> clip
    vec4 colorInfo;       // x: opacity of the cloud, y: intensity gain (1 / the cloud's 99th percentile),
                          // z, w: height ramp over the stored 0..1 heights: (h - z) * w
    vec4 constantColor;   // rgb: sRGB colour for kPointColorConstant
    vec4 edl;             // x: unused (EDL on/off is specialisation constant 2), y: strength, z: radius (px), w: point size (px)
    vec4 screen;          // x, y: width, height (pixels)
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::PointUniforms) == 64 + 4 * 16, "PointUniforms layout changed");
static_assert(sizeof(orbis::shader::PointNode) == 32, "PointNode layout changed");
static_assert(orbis::shader::kPointBatch == orbis::shader::kPointGroupSize * orbis::shader::kPointsPerInvocation);
#endif

#endif
