// Volume ray casting (compute, before the volume pass) and its composite (fragment, in the pass).
// Set 1 bindings: 0 VolumeUniforms (per frame), 1 the field (sampler3D, R32F or R16F, NaN = no data),
// 2 axis lookup tables (storage buffer), 3 transfer function (sampler1D), 4 scene depth
// (sampler2D), 5 the ray-cast image (rgba16f storage, premultiplied), 6 the same image sampled
// by the composite, 7 first-hit distances (measurement), 8 one bit per brick: can it show
// anything (empty-space skipping).
#ifndef ORBIS_SHADERS_SHARED_VOLUME_TYPES_H
#define ORBIS_SHADERS_SHARED_VOLUME_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kVolumeSet, 1)
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
    vec4 timeInfo;          // x, y: time steps shown (stacked along the texture's z), z: weight of y, w: steps
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::VolumeUniforms) == 27 * 16, "VolumeUniforms layout changed");
#endif

#endif
