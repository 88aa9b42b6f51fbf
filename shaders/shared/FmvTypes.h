// Full-motion video draped on the terrain (layers/fmv/FmvLayer.h). Set 1 bindings: 0 FmvUniforms
// (per frame), 1 the scene depth (sampler2D), 2 the video frame (sampler2D, sRGB), 3 the sensor's
// distance map (sampler2D R32F: metres along the boresight to the ground it sees), 4 the
// heightfield (sampler2D R32F: heights above the ellipsoid on the local grid), 5 the decal
// (storage image, written by drape.comp), 6 the decal (sampler2D, read by the composite), 7 the
// footprint (storage buffer of vec4: kFmvFootprintRays ground points relative to the origin,
// w = 1 where the ray met the ground, 0 where it was clamped to the horizon).
//
// Positions on the GPU are relative to the layer's origin O (on the ellipsoid at the middle of
// the heightfield), or to the eye: small numbers, differences taken in double on the CPU.
#ifndef ORBIS_SHADERS_SHARED_FMV_TYPES_H
#define ORBIS_SHADERS_SHARED_FMV_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kFmvGroupSize, 8)        // drape.comp: 8 x 8 pixels a workgroup
ORBIS_CONST(uint, kFmvEdgeRays, 32)        // footprint: rays along each image edge
ORBIS_CONST(uint, kFmvFootprintRays, 129)  // 4 edges (from corner 1 clockwise), then the centre
ORBIS_CONST(uint, kFmvFootprintGroup, 64)
ORBIS_CONST(uint, kFmvHullEdges, 8)        // the screen polygon the video can cover: at most 8 edges

// std140: vec4 and mat4 members only.
struct FmvUniforms {
    mat4 sensorClip;      // position relative to O -> the sensor distance map's clip space
    vec4 originFromEye;   // xyz: O - eye (float from doubles); w: opacity
    vec4 sensor;          // xyz: the sensor relative to O; w: occlusion bias at 0 m (metres)
    vec4 axisX;           // the sensor's boresight (world); w: tan(hfov / 2)
    vec4 axisY;           // image right; w: tan(vfov / 2)
    vec4 axisZ;           // image down; w: the distance map's field of view over the video's (>= 1)
    vec4 east;            // local east at O; w: the heightfield's half size (metres)
    vec4 north;           // local north at O; w: the radius of the sphere that osculates the ellipsoid at O
    vec4 up;              // local up at O; w: heightfield samples a side
    vec4 heights;         // x: lowest terrain height, y: highest, z: march step (m), w: 1 when a frame is shown
    vec4 outline;         // rgb: footprint colour (linear); a: occlusion bias per metre of distance
    vec4 rect;            // the screen rectangle the video can cover (pixels): x, y, width, height
    vec4 hull[kFmvHullEdges];   // the convex polygon within it: a pixel p is inside when
                                // dot(hull[i].xy, p) + hull[i].z >= 0 for i < hullCount.x
    vec4 hullCount;             // x: edges in use (0: the rectangle alone)
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::FmvUniforms) == 64 + 20 * 16, "FmvUniforms layout changed");
static_assert(orbis::shader::kFmvFootprintRays == 4 * orbis::shader::kFmvEdgeRays + 1);
#endif

#endif
