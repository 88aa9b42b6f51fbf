// Volume ray casting (compute, before the volume pass) and its composite (fragment, in the pass):
// every number the GLSL and the C++ must agree on (set, bindings, specialisation constants,
// workgroup size, the uniform block), and on the C++ side the set's layout as a table.
#ifndef ORBIS_SHADERS_SHARED_VOLUME_TYPES_H
#define ORBIS_SHADERS_SHARED_VOLUME_TYPES_H

#include "shared/Common.h"
#include "shared/CompositeTypes.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kVolumeSet, 1)
// The set's bindings (kVolumeBindings below is its layout).
ORBIS_CONST(uint, kVolumeBindingUniforms, 0)     // VolumeUniforms, one buffer per frame in flight
ORBIS_CONST(uint, kVolumeBindingField, 1)        // sampler3D, R32F or R16F, NaN = no data
ORBIS_CONST(uint, kVolumeBindingAxes, 2)         // storage buffer: the irregular axes' lookup tables
ORBIS_CONST(uint, kVolumeBindingTransfer, 3)     // sampler1D: the transfer function
ORBIS_CONST(uint, kVolumeBindingSceneDepth, 4)   // sampler2D: the scene's depth (rays end there)
ORBIS_CONST(uint, kVolumeBindingCastImage, 5)    // rgba16f storage image: the ray-cast colour, premultiplied
ORBIS_CONST(uint, kVolumeBindingCastSampled, kCompositeBindingImage)  // the same, sampled by common/composite.frag
ORBIS_CONST(uint, kVolumeBindingHits, 7)         // r32f storage image: first-hit distances (measurement)
ORBIS_CONST(uint, kVolumeBindingBricks, 8)       // storage buffer: one bit per brick, "can show something"
ORBIS_CONST(uint, kVolumeBindingPreIntegrated, 9)   // sampler2D: the pre-integrated transfer function (1 x 1 unused)
ORBIS_CONST(uint, kVolumeBindingLowRes, 10)      // rgba16f storage image: the reduced-resolution rays (1 x 1 unused)
// The ray caster's specialisation constants: what the scene's modes use is compiled in.
ORBIS_CONST(uint, kVolumeSpecDvr, 0)             // bool: direct volume rendering
ORBIS_CONST(uint, kVolumeSpecIsoCount, 1)        // int: isosurfaces (0 .. kVolumeMaxIso)
ORBIS_CONST(uint, kVolumeSpecSliceCount, 2)      // int: slice planes (0 .. kVolumeMaxSlices)
ORBIS_CONST(uint, kVolumeSpecHitOutput, 3)       // bool: write first-hit distances (measurement)
ORBIS_CONST(uint, kVolumeSpecRefine, 4)          // bool: refine isosurface crossings
ORBIS_CONST(uint, kVolumeSpecBlendTimeSteps, 5)  // bool: blend two time steps per sample
ORBIS_CONST(uint, kVolumeSpecUniformAxes, 6)     // int: evenly spaced axes, bit 1 << kVolumeAxis*
ORBIS_CONST(uint, kVolumeSpecSkipEmpty, 7)       // bool: empty-space skipping
ORBIS_CONST(uint, kVolumeSpecPreIntegrate, 8)    // bool: DVR steps read the pre-integrated table
ORBIS_CONST(uint, kVolumeSpecPass, 9)            // int: kVolumePass*, which of the ray caster's passes
// The ray caster's passes: one ray per pixel; or rays at a reduced resolution, then a pass at
// full resolution that interpolates them where they agree and casts its own ray elsewhere.
ORBIS_CONST(int, kVolumePassFull, 0)
ORBIS_CONST(int, kVolumePassLowRes, 1)
ORBIS_CONST(int, kVolumePassRefine, 2)
// Sizes.
ORBIS_CONST(uint, kVolumeAxisTable, 256)   // entries per irregular axis
ORBIS_CONST(uint, kVolumeTransferSize, 256)   // texels of the transfer function (sampler1D), and each
                                              // side of the pre-integrated one (sampler2D)
ORBIS_CONST(uint, kVolumeGroupSize, 8)     // compute workgroup: 8 x 8 pixels
ORBIS_CONST(uint, kVolumeMaxIso, 8)        // isovalues per volume
ORBIS_CONST(uint, kVolumeMaxSlices, 4)     // slice planes per volume

// The grid's axes: their order in the lookup tables (kVolumeBindingAxes, kVolumeAxisTable
// entries each) and their bits (1 << axis) in kVolumeSpecUniformAxes.
ORBIS_CONST(int, kVolumeAxisLon, 0)
ORBIS_CONST(int, kVolumeAxisLat, 1)
ORBIS_CONST(int, kVolumeAxisHeight, 2)

// Slice kinds (VolumeSlice::kind).
ORBIS_CONST(int, kVolumeSliceLon, 0)
ORBIS_CONST(int, kVolumeSliceLat, 1)
ORBIS_CONST(int, kVolumeSliceHeight, 2)

// One slice, an exact surface in a form relative to the volume's origin O. What `vector` and
// `terms` hold depends on the kind:
//   lon (meridian half-plane): vector the plane's normal; terms.x normal . O, y the lon (deg)
//   lat (cone of constant geodetic latitude, apex on the axis): vector (Ox, Oy, Oz - apex);
//       terms.x tan^2(lat), y the cone's constant term for an eye at the origin, z the lat (deg)
//   height (the surface at drawn height H): vector O scaled by 1 / (a + H, a + H, b + H);
//       terms.x |that|^2 - 1, y 1 / (a + H), z 1 / (b + H), w the height (m of data)
struct VolumeSlice {
    vec3 vector;
    float kind;   // kVolumeSliceLon, Lat or Height
    vec4 terms;
};

// std140. A vec3 and the float after it share 16 bytes on both sides; the C++ side asserts
// every row's offset below.
struct VolumeUniforms {
    // The volume's frame: an origin O on the ellipsoid (ECEF, double on the CPU). Rays are
    // marched relative to it, in ECEF axes, in float.
    vec3 eyeFromOrigin;           // the eye minus O (m)
    float stepLength;             // the longest step (m): the box's diagonal / steps
    vec3 forward;                 // the view direction (world)
    float nearPlane;              // (m): turns the scene's reversed-Z depth into a distance
    vec3 boxMin;                  // bounding box of the curved box, ECEF axes, relative to O (m)
    float maxSteps;               // steps per segment (a cap)
    vec3 boxMax;
    float frameIndex;             // the frame, modulo 65536 (the start's jitter)
    float originRho;              // O's distance from the polar axis (m)
    float originZ;                // O's z (m)
    float originLon;              // O's longitude (rad)
    float verticalExaggeration;
    // The ellipsoid.
    float equatorialRadius;       // a (m)
    float polarRadius;            // b (m)
    float oneMinusE2;             // 1 - e^2 = (b / a)^2: geodetic latitude from rho and z
    float pad0;
    // The grid, in the coordinates of its axes.
    float lonFirst, lonLast;      // deg; continuous (the last may pass 180)
    float latFirst, latLast;      // deg
    float heightFirst, heightLast;   // m of data (not exaggerated)
    float valueScale, valueOffset;   // field value = stored * scale + offset (half floats are stored relative to the range)
    vec3 samples;                 // samples along lon (with the wrap column of a periodic field), lat, height
    float brickSize;              // voxels along each edge of a brick
    vec3 bricks;                  // bricks along lon, lat, height (one bit each: can it show something)
    float pad1;
    // What is drawn.
    float rangeMin;               // the transfer function's range: its first value,
    float rangeInvSpan;           // and 1 / (max - min)
    float isoOpacity;
    float sliceOpacity;
    vec4 isovalues[kVolumeMaxIso / 4];   // isovalue i in isovalues[i / 4][i % 4] (the pipeline's kIsoCount are used)
    // The height range as two surfaces (ellipsoids with semi-axes a + H, a + H, b + H, H the
    // drawn bottom and top heights): rays are clipped to the shell between them, in a form
    // relative to O (no large numbers cancel).
    vec2 shellLoInvAxes;          // 1 / (a + Hlo), 1 / (b + Hlo)
    vec2 shellHiInvAxes;          // the same for the top surface
    vec3 shellLoOrigin;           // O scaled by the bottom surface's inverse axes
    float shellLoC0;              // |shellLoOrigin|^2 - 1 (from doubles)
    vec3 shellHiOrigin;           // the same for the top surface
    float shellHiC0;
    // The march.
    float normalisedStep;         // the step in the box's normalised coordinates: sqrt 3 / steps
    float minStep;                // the shortest step (m)
    float opacityPerUnit;         // 1 / opacityUnit: opacity steps per normalised unit
    float probeLength;            // (m): how far ahead the rate of change is probed at an entry
    float jumpMax;                // the longest jump over empty bricks (m),
    float jumpPerRho;             // and the same per metre from the polar axis
    float refineThreshold;        // kVolumePassRefine: the largest spread of the four rays' RGBA interpolated
    float pad3;
    // Time steps, stacked along the texture's z.
    float timeStepA, timeStepB;   // the time steps shown
    float timeStepWeight;         // the weight of B
    float timeStepCount;
    VolumeSlice slices[kVolumeMaxSlices];
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
namespace orbis::shader {
// std140 as the GLSL sees it: each 16-byte row's first member, a vec3 and the float after it
// in one row, two vec2 in one row, arrays of vec4 and of VolumeSlice with a stride of 16 and 32.
static_assert(offsetof(VolumeUniforms, eyeFromOrigin) == 0 * 16);
static_assert(offsetof(VolumeUniforms, forward) == 1 * 16);
static_assert(offsetof(VolumeUniforms, boxMin) == 2 * 16);
static_assert(offsetof(VolumeUniforms, boxMax) == 3 * 16);
static_assert(offsetof(VolumeUniforms, originRho) == 4 * 16);
static_assert(offsetof(VolumeUniforms, equatorialRadius) == 5 * 16);
static_assert(offsetof(VolumeUniforms, lonFirst) == 6 * 16);
static_assert(offsetof(VolumeUniforms, heightFirst) == 7 * 16);
static_assert(offsetof(VolumeUniforms, samples) == 8 * 16);
static_assert(offsetof(VolumeUniforms, bricks) == 9 * 16);
static_assert(offsetof(VolumeUniforms, rangeMin) == 10 * 16);
static_assert(offsetof(VolumeUniforms, isovalues) == 11 * 16);
static_assert(offsetof(VolumeUniforms, shellLoInvAxes) == 13 * 16);
static_assert(offsetof(VolumeUniforms, shellLoOrigin) == 14 * 16);
static_assert(offsetof(VolumeUniforms, shellHiOrigin) == 15 * 16);
static_assert(offsetof(VolumeUniforms, normalisedStep) == 16 * 16);
static_assert(offsetof(VolumeUniforms, jumpMax) == 17 * 16);
static_assert(offsetof(VolumeUniforms, timeStepA) == 18 * 16);
static_assert(offsetof(VolumeUniforms, slices) == 19 * 16);
static_assert(offsetof(VolumeUniforms, stepLength) == 12 && offsetof(VolumeUniforms, shellHiInvAxes) == 13 * 16 + 8);
static_assert(sizeof(VolumeSlice) == 32 && sizeof(VolumeUniforms) == 27 * 16, "VolumeUniforms layout changed");

static_assert(kVolumeSet == kCompositeSet, "the composite reads the cast image from the volume's set");
/// Set kVolumeSet's layout (gpu::createDescriptorSets); the composite reads the cast image.
inline constexpr DescriptorBinding kVolumeBindings[] = {
    {kVolumeBindingUniforms, DescriptorKind::UniformBuffer, 1, kStageCompute},
    {kVolumeBindingField, DescriptorKind::CombinedImageSampler, 1, kStageCompute},
    {kVolumeBindingAxes, DescriptorKind::StorageBuffer, 1, kStageCompute},
    {kVolumeBindingTransfer, DescriptorKind::CombinedImageSampler, 1, kStageCompute},
    {kVolumeBindingSceneDepth, DescriptorKind::CombinedImageSampler, 1, kStageCompute},
    {kVolumeBindingCastImage, DescriptorKind::StorageImage, 1, kStageCompute},
    {kVolumeBindingCastSampled, DescriptorKind::CombinedImageSampler, 1, kStageFragment},
    {kVolumeBindingHits, DescriptorKind::StorageImage, 1, kStageCompute},
    {kVolumeBindingBricks, DescriptorKind::StorageBuffer, 1, kStageCompute},
    {kVolumeBindingPreIntegrated, DescriptorKind::CombinedImageSampler, 1, kStageCompute},
    {kVolumeBindingLowRes, DescriptorKind::StorageImage, 1, kStageCompute},
};
/// The ray caster's specialisation constants (VolumeLayer::rayCasterModes sets each).
inline constexpr SpecConstant kVolumeSpecConstants[] = {
    {kVolumeSpecDvr, SpecType::Bool},
    {kVolumeSpecIsoCount, SpecType::Int},
    {kVolumeSpecSliceCount, SpecType::Int},
    {kVolumeSpecHitOutput, SpecType::Bool},
    {kVolumeSpecRefine, SpecType::Bool},
    {kVolumeSpecBlendTimeSteps, SpecType::Bool},
    {kVolumeSpecUniformAxes, SpecType::Int},
    {kVolumeSpecSkipEmpty, SpecType::Bool},
    {kVolumeSpecPreIntegrate, SpecType::Bool},
    {kVolumeSpecPass, SpecType::Int},
};
}  // namespace orbis::shader
#endif

#endif
