// Point clouds: compute rasterisation (before the points pass) and its resolve (fragment, in the
// pass), or the point-list fallback. Set kPointSet: the frame's PointUniforms; a page of the
// resident nodes' data (dynamic storage buffers at the page's offset, bound as uint words for
// the positions and as uvec2 for the attributes; layout in layers/points/PointStore.h); the
// frame's batches (PointBatch); the drawn nodes (PointNode); the screen buffer (one uint64 a pixel: depth bits << 32 | sRGB r | g << 8 |
// b << 16; 0 = empty); the scene depth (sampler2D).
#ifndef ORBIS_SHADERS_SHARED_POINT_TYPES_H
#define ORBIS_SHADERS_SHARED_POINT_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kPointSet, 1)
ORBIS_CONST(uint, kPointBindingUniforms, 0)
ORBIS_CONST(uint, kPointBindingWords, 1)        // positions of a page (uint words)
ORBIS_CONST(uint, kPointBindingAttributes, 2)   // attributes of a page (uvec2)
ORBIS_CONST(uint, kPointBindingBatches, 3)
ORBIS_CONST(uint, kPointBindingNodes, 4)
ORBIS_CONST(uint, kPointBindingScreen, 5)
ORBIS_CONST(uint, kPointBindingSceneDepth, 6)

// Specialisation constants: what changes the shader's code paths is fixed per pipeline (a CPU
// device runs every side of a branch).
ORBIS_CONST(uint, kPointSpecRadius, 0)      // int: splat radius in pixels (splat.comp)
ORBIS_CONST(uint, kPointSpecColorMode, 1)   // uint: kPointColor*
ORBIS_CONST(uint, kPointSpecEdl, 2)         // bool: eye-dome lighting (resolve.frag)
ORBIS_CONST(uint, kPointSpecQuantised, 3)   // bool: quantised positions, else floats
ORBIS_CONST(uint, kPointSpecAdaptive, 4)    // bool: each point's size from the level drawn at its place (splat.comp)

// Level-aware sizes: a splat's radius at most (pixels).
ORBIS_CONST(int, kPointMaxAdaptiveRadius, 6)

ORBIS_CONST(uint, kPointGroupSize, 256)      // compute workgroup: 256 invocations
ORBIS_CONST(uint, kPointsPerInvocation, 8)   // each invocation splats up to 8 points of a batch
ORBIS_CONST(uint, kPointBatch, 2048)         // points per batch = kPointGroupSize * kPointsPerInvocation

// Colour modes (kPointSpecColorMode), in the order of layers::PointsSettings::Color.
ORBIS_CONST(uint, kPointColorRgb, 0)
ORBIS_CONST(uint, kPointColorIntensity, 1)
ORBIS_CONST(uint, kPointColorClassification, 2)
ORBIS_CONST(uint, kPointColorHeight, 3)
ORBIS_CONST(uint, kPointColorConstant, 4)

// A drawn node (std430).
struct PointNode {
    vec3 centre;            // relative to the eye (from doubles on the CPU)
    float step;             // the quantisation step (m), 0 for float positions
    uint firstAttribute;    // its first point's attribute (uvec2 units), within its page
    uint firstWord;         // its positions' first word, within its page
    uint count;             // its points
    uint octants;           // per octant (4 bits each, octant 0 lowest): the levels drawn below it there
    float spacing;          // the node's point spacing (m): its points' size where nothing finer is drawn
    uint pad0, pad1, pad2;
};

// A workgroup's work (std430): up to kPointBatch points of one drawn node.
struct PointBatch {
    uint node;    // the drawn node (index into the nodes)
    uint first;   // its first point within the node
    uint count;
    uint pad0;
};

// std140.
struct PointUniforms {
    mat4 viewProj;         // projection * view rotation: positions relative to the eye -> clip
    float opacity;         // of the cloud (the colour is premultiplied by it)
    float intensityGain;   // 1 / the cloud's 99th percentile intensity
    float heightLow;       // the height ramp over the stored 0..1 heights: (h - heightLow) * heightScale
    float heightScale;
    vec4 constantColor;    // rgb: sRGB colour for kPointColorConstant; a: 1
    float edlStrength;     // eye-dome lighting (on or off: kPointSpecEdl)
    float edlRadiusPx;
    float pointSizePx;     // the point list's gl_PointSize; the smallest size with level-aware sizes
    float adaptivePixels;  // level-aware sizes: pixels a metre at 1 m (0: every point pointSizePx)
    vec2 screenSize;       // pixels
    vec2 pad1;
};

// Push constants (splat.comp and pointlist.vert).
struct PointPush {
    uint node;         // pointlist.vert: the drawn node
    uint firstBatch;   // splat.comp: the dispatch's first batch
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
namespace orbis::shader {
inline constexpr uint32_t kPointStages = kStageCompute | kStageVertex | kStageFragment;
/// Set kPointSet, one per frame in flight (layers/points/PointsLayer.cpp).
inline constexpr DescriptorBinding kPointBindings[] = {
    {kPointBindingUniforms, DescriptorKind::UniformBuffer, 1, kPointStages},
    {kPointBindingWords, DescriptorKind::StorageBufferDynamic, 1, kPointStages},
    {kPointBindingAttributes, DescriptorKind::StorageBufferDynamic, 1, kPointStages},
    {kPointBindingBatches, DescriptorKind::StorageBuffer, 1, kPointStages},
    {kPointBindingNodes, DescriptorKind::StorageBuffer, 1, kPointStages},
    {kPointBindingScreen, DescriptorKind::StorageBuffer, 1, kPointStages},
    {kPointBindingSceneDepth, DescriptorKind::CombinedImageSampler, 1, kStageCompute},
};
inline constexpr SpecConstant kPointSpecConstants[] = {
    {kPointSpecRadius, SpecType::Int},
    {kPointSpecColorMode, SpecType::Uint},
    {kPointSpecEdl, SpecType::Bool},
    {kPointSpecQuantised, SpecType::Bool},
    {kPointSpecAdaptive, SpecType::Bool},
};
}  // namespace orbis::shader
static_assert(sizeof(orbis::shader::PointUniforms) == 128, "PointUniforms layout changed");
static_assert(offsetof(orbis::shader::PointUniforms, opacity) == 64, "std140 offset");
static_assert(offsetof(orbis::shader::PointUniforms, constantColor) == 80, "std140 offset");
static_assert(offsetof(orbis::shader::PointUniforms, edlStrength) == 96, "std140 offset");
static_assert(offsetof(orbis::shader::PointUniforms, screenSize) == 112, "std140 offset: vec2 aligned to 8");
static_assert(sizeof(orbis::shader::PointPush) == 8, "PointPush layout changed");
static_assert(sizeof(orbis::shader::PointNode) == 48, "PointNode layout changed");
static_assert(offsetof(orbis::shader::PointNode, step) == 12 && offsetof(orbis::shader::PointNode, firstAttribute) == 16,
              "std430 offset: a float after a vec3");
static_assert(sizeof(orbis::shader::PointBatch) == 16, "PointBatch layout changed");
static_assert(orbis::shader::kPointBatch == orbis::shader::kPointGroupSize * orbis::shader::kPointsPerInvocation);
#endif

#endif
