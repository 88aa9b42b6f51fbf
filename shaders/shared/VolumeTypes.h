// Volume ray casting (compute, before the volume pass) and its composite (fragment, in the pass):
// every number the GLSL and the C++ must agree on (set, bindings, specialisation constants,
// workgroup size, the uniform block), and on the C++ side the set's layout as a table.
#ifndef ORBIS_SHADERS_SHARED_VOLUME_TYPES_H
#define ORBIS_SHADERS_SHARED_VOLUME_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kVolumeSet, 1)
// The set's bindings (kVolumeBindings below is its layout).
ORBIS_CONST(uint, kVolumeBindingUniforms, 0)     // VolumeUniforms, one buffer per frame in flight
ORBIS_CONST(uint, kVolumeBindingField, 1)        // sampler3D, R32F or R16F, NaN = no data
ORBIS_CONST(uint, kVolumeBindingAxes, 2)         // storage buffer: the irregular axes' lookup tables
ORBIS_CONST(uint, kVolumeBindingTransfer, 3)     // sampler1D: the transfer function
ORBIS_CONST(uint, kVolumeBindingSceneDepth, 4)   // sampler2D: the scene's depth (rays end there)
ORBIS_CONST(uint, kVolumeBindingCastImage, 5)    // rgba16f storage image: the ray-cast colour, premultiplied
ORBIS_CONST(uint, kVolumeBindingCastSampled, 6)  // the same image, sampled by the composite (fragment)
ORBIS_CONST(uint, kVolumeBindingHits, 7)         // r32f storage image: first-hit distances (measurement)
ORBIS_CONST(uint, kVolumeBindingBricks, 8)       // storage buffer: one bit per brick, "can show something"
// The ray caster's specialisation constants: what the scene's modes use is compiled in.
ORBIS_CONST(uint, kVolumeSpecDvr, 0)             // bool: direct volume rendering
ORBIS_CONST(uint, kVolumeSpecIsoCount, 1)        // int: isosurfaces (0 .. kVolumeMaxIso)
ORBIS_CONST(uint, kVolumeSpecSliceCount, 2)      // int: slice planes (0 .. kVolumeMaxSlices)
ORBIS_CONST(uint, kVolumeSpecHitOutput, 3)       // bool: write first-hit distances (measurement)
ORBIS_CONST(uint, kVolumeSpecRefine, 4)          // bool: refine isosurface crossings
ORBIS_CONST(uint, kVolumeSpecBlendTimeSteps, 5)  // bool: blend two time steps per sample
ORBIS_CONST(uint, kVolumeSpecUniformAxes, 6)     // int: evenly spaced axes, bit 0 lon, 1 lat, 2 height
ORBIS_CONST(uint, kVolumeSpecSkipEmpty, 7)       // bool: empty-space skipping
// Sizes.
ORBIS_CONST(uint, kVolumeAxisTable, 256)   // entries per irregular axis
ORBIS_CONST(uint, kVolumeGroupSize, 8)     // compute workgroup: 8 x 8 pixels
ORBIS_CONST(uint, kVolumeMaxIso, 8)        // isovalues per volume
ORBIS_CONST(uint, kVolumeMaxSlices, 4)     // slice planes per volume

// std140: vec4 members only.
struct VolumeUniforms {
    // The volume's frame: an origin on the ellipsoid (ECEF, double on the CPU) and its local
    // east/north/up axes. Rays are marched relative to the origin, in ECEF axes, in float.
    vec4 eyeFromOrigin;     // xyz: eye minus origin (ECEF axes); w: step length (m)
    vec4 originAxis;        // x: distance of the origin from the polar axis, y: its z, z: its longitude (rad), w: reference step (m)
    vec4 boxMin;            // xyz: bounding box of the curved box in ECEF axes relative to the origin; w: near plane (m)
    vec4 boxMax;            // xyz: as above; w: number of steps (cap)
    vec4 lonRange;          // x: first lon (deg), y: last lon (deg, continuous), z: 1 if it wraps, w: vertical exaggeration
    vec4 latRange;          // x: first lat, y: last lat (deg); z, w: first and last height (m, drawn: exaggerated)
    vec4 dataRange;         // x: min, y: 1 / (max - min) for the transfer function; z: opacity scale; w: frame (jitter)
    vec4 bricks;            // xyz: bricks along lon, lat, height (min/max bricks, one bit each); w: brick size (voxels)
    vec4 samples;           // x, y, z: samples in lon (incl. a wrap column), lat, height; w: 1 - e^2
    vec4 forward;           // xyz: view direction (world); w: equatorial radius a
    vec4 radii;             // x, y: field value = stored * x + y (half floats are stored relative to the range); z: polar radius b, w: isosurface opacity
    vec4 isovalues[2];      // up to kVolumeMaxIso isovalues (the pipeline's kIsoCount are used)
    // The height range as two surfaces (ellipsoids with semi-axes a + H, b + H, H the drawn
    // bottom and top heights): rays are clipped to the shell between them, in a form relative to
    // the origin (no large numbers cancel).
    vec4 shellScale;        // x: 1 / (a + Hlo), y: 1 / (b + Hlo), z: 1 / (a + Hhi), w: 1 / (b + Hhi)
    vec4 shellLo;           // xyz: the origin scaled by the bottom surface's axes; w: |that|^2 - 1
    vec4 shellHi;           // the same for the top surface
    vec4 march;             // x: normalised step (sqrt 3 / steps); y: smallest step (m); z: opacity steps per normalised unit; w: probe (m)
    // Slices, each an exact surface in origin-relative form (w of sliceA: 0 lon, 1 lat, 2 height):
    //   lon (meridian half-plane): sliceA.xyz plane normal; sliceB.x normal . origin, y lon (deg)
    //   lat (cone of constant geodetic latitude, apex on the axis): sliceA.xyz (Ox, Oy, Oz - apex);
    //       sliceB.x tan^2(lat), y the constant term for the eye at the origin, z lat (deg)
    //   height (surface at H): sliceA.xyz the origin scaled by 1 / axes; sliceB.x |that|^2 - 1,
    //       y, z 1 / (a + H), 1 / (b + H), w height (m of data)
    vec4 sliceA[4];
    vec4 sliceB[4];
    vec4 sliceInfo;         // x: slice opacity; y: longest jump over empty bricks (m), z: the same per metre from the axis
    vec4 timeInfo;          // x, y: time steps shown (stacked along the texture's z), z: weight of y, w: time steps
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::VolumeUniforms) == 27 * 16, "VolumeUniforms layout changed");

namespace orbis::shader {
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
};
}  // namespace orbis::shader
#endif

#endif
