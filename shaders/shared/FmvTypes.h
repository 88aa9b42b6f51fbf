// Full-motion video draped on the terrain (layers/fmv/FmvLayer.h). Set kFmvSet: the frame's
// FmvUniforms, the scene depth (sampler2D), the video frame (sampler2D, sRGB), the sensor's
// distance map (sampler2D R32F: metres along the boresight to the ground it sees), the
// heightfield (sampler2D R32F: heights above the ellipsoid on the local grid), the decal
// (storage image, written by drape.comp; sampled by shaders/common/composite.frag at the
// binding CompositeTypes.h gives), the footprint (storage buffer of vec4: kFmvFootprintRays
// ground points relative to the origin, w = 1 where the ray met the ground, 0 where it was
// clamped to the horizon).
//
// Positions on the GPU are relative to the layer's origin O (on the ellipsoid at the middle of
// the heightfield), or to the eye: small numbers, differences taken in double on the CPU.
#ifndef ORBIS_SHADERS_SHARED_FMV_TYPES_H
#define ORBIS_SHADERS_SHARED_FMV_TYPES_H

#include "shared/Common.h"
#include "shared/CompositeTypes.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kFmvSet, 1)
ORBIS_CONST(uint, kFmvBindingUniforms, 0)
ORBIS_CONST(uint, kFmvBindingSceneDepth, 1)
ORBIS_CONST(uint, kFmvBindingVideoFrame, 2)
ORBIS_CONST(uint, kFmvBindingDistanceMap, 3)
ORBIS_CONST(uint, kFmvBindingHeightfield, 4)
ORBIS_CONST(uint, kFmvBindingDecal, 5)          // storage image (drape.comp)
ORBIS_CONST(uint, kFmvBindingDecalSampled, kCompositeBindingImage)   // the same, sampled (the composite)
ORBIS_CONST(uint, kFmvBindingFootprint, 7)

ORBIS_CONST(uint, kFmvSpecFrustum, 0)   // bool (lines.vert): the frustum's edges, else the footprint's outline
ORBIS_CONST(uint, kFmvInputPosition, 0)   // sensordepth.vert: a heightfield vertex relative to O

ORBIS_CONST(uint, kFmvGroupSize, 8)        // drape.comp: 8 x 8 pixels a workgroup
ORBIS_CONST(uint, kFmvEdgeRays, 32)        // footprint: rays along each image edge
ORBIS_CONST(uint, kFmvFootprintRays, 129)  // 4 edges (from corner 1 clockwise), then the centre
ORBIS_CONST(uint, kFmvFootprintGroup, 64)
ORBIS_CONST(uint, kFmvHullEdges, 8)        // the screen polygon the video can cover: at most 8 edges

// std140: each vec3 shares its 16 bytes with the float after it.
struct FmvUniforms {
    mat4 sensorClip;              // position relative to O -> the sensor distance map's clip space
    vec3 originFromEye;           // O - eye (float from doubles)
    float opacity;
    vec3 sensor;                  // the sensor relative to O
    float occlusionBias;          // metres, at 0 m from the sensor
    vec3 boresight;               // the sensor's axes (world): x, along its view
    float tanHalfFovX;
    vec3 imageRight;              // y, the image's right
    float tanHalfFovY;
    vec3 imageDown;               // z, the image's down
    float mapFovScale;            // the distance map's field of view over the video's (>= 1)
    vec3 east;                    // local east at O
    float halfSize;               // the heightfield's half size (metres)
    vec3 north;                   // local north at O
    float sphereRadius;           // the sphere that osculates the ellipsoid at O
    vec3 up;                      // local up at O
    float heightfieldSamples;     // a side
    float lowestHeight;           // of the terrain in the heightfield
    float highestHeight;
    float marchStep;              // metres (footprint.comp)
    uint frameShown;              // 1 when a video frame is on the GPU
    vec3 outlineColor;            // footprint colour (linear)
    float occlusionBiasPerMetre;  // of distance from the sensor
    vec2 rectOrigin;              // the screen rectangle the video can cover (pixels)
    vec2 rectSize;
    vec4 hull[kFmvHullEdges];     // the convex polygon within it: a pixel p is inside when
                                  // dot(hull[i].xy, p) + hull[i].z >= 0 for i < hullEdges
    uint hullEdges;               // edges in use (0: the rectangle alone)
    uint pad0;
    uint pad1;
    uint pad2;
};

// Push constants of the distance map (sensordepth.vert).
struct FmvDistancePush {
    mat4 sensorClip;   // relative to O -> clip (reversed-Z, infinite far)
    vec3 sensor;       // relative to O
    float pad0;
    vec3 boresight;
    float pad1;
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
namespace orbis::shader {
/// Set kFmvSet, one per frame in flight (layers/fmv/FmvLayer.cpp).
inline constexpr DescriptorBinding kFmvBindings[] = {
    {kFmvBindingUniforms, DescriptorKind::UniformBuffer, 1, kStageCompute | kStageVertex | kStageFragment},
    {kFmvBindingSceneDepth, DescriptorKind::CombinedImageSampler, 1, kStageCompute},
    {kFmvBindingVideoFrame, DescriptorKind::CombinedImageSampler, 1, kStageCompute},
    {kFmvBindingDistanceMap, DescriptorKind::CombinedImageSampler, 1, kStageCompute},
    {kFmvBindingHeightfield, DescriptorKind::CombinedImageSampler, 1, kStageCompute},
    {kFmvBindingDecal, DescriptorKind::StorageImage, 1, kStageCompute},
    {kFmvBindingDecalSampled, DescriptorKind::CombinedImageSampler, 1, kStageFragment},
    {kFmvBindingFootprint, DescriptorKind::StorageBuffer, 1, kStageCompute | kStageVertex},
};
inline constexpr SpecConstant kFmvSpecConstants[] = {{kFmvSpecFrustum, SpecType::Bool}};
}  // namespace orbis::shader
static_assert(sizeof(orbis::shader::FmvUniforms) == 64 + 20 * 16, "FmvUniforms layout changed");
static_assert(offsetof(orbis::shader::FmvUniforms, opacity) == 76, "std140 offset: a float after a vec3");
static_assert(offsetof(orbis::shader::FmvUniforms, lowestHeight) == 192, "std140 offset");
static_assert(offsetof(orbis::shader::FmvUniforms, outlineColor) == 208, "std140 offset");
static_assert(offsetof(orbis::shader::FmvUniforms, rectSize) == 232, "std140 offset");
static_assert(offsetof(orbis::shader::FmvUniforms, hull) == 240, "std140 offset");
static_assert(offsetof(orbis::shader::FmvUniforms, hullEdges) == 368, "std140 offset");
static_assert(sizeof(orbis::shader::FmvDistancePush) == 96, "FmvDistancePush layout changed");
static_assert(offsetof(orbis::shader::FmvDistancePush, boresight) == 80, "std430 offset");
static_assert(orbis::shader::kFmvFootprintRays == 4 * orbis::shader::kFmvEdgeRays + 1);
static_assert(orbis::shader::kFmvSet == orbis::shader::kCompositeSet, "the composite reads the decal from the FMV's set");
#endif

#endif
