#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/ViewshedTypes.h"

// The viewshed in one dispatch of four workgroups, one a quadrant around the observer
// (globe/Viewshed.h has the model and the CPU twin). A workgroup walks its quadrant ring by
// ring outward: the 2 d + 1 cells at Chebyshev distance d, spread over its invocations. A cell's
// horizon is interpolated from the horizons of the one or two cells next to it on the observer's
// side, all on ring d - 1 and in the same quadrant (gdal_viewshed's "edge" mode); the cell is
// seen when its ground plus the target height is not below that horizon, and its own horizon is
// the higher of the two. A barrier between rings is all the ordering needed: no dispatch a ring.
// The axes belong to two quadrants each: both workgroups write the same values there.

// A GPU's workgroups: kViewshedGroupSize invocations spread each ring (viewshed_cpu.comp: fewer,
// where a CPU device runs the invocations of a workgroup in turn between barriers).
layout(local_size_x = kViewshedGroupSize) in;

#include "analysis/ViewshedRings.glsl"
