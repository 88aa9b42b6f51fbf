#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/ViewshedTypes.h"

// The viewshed on a CPU device (lavapipe): viewshed.comp's rings (analysis/ViewshedRings.glsl)
// with a smaller workgroup.
// lavapipe runs a workgroup's invocations in SIMD batches, in turn between barriers: a small
// workgroup spends less on each ring's barrier (measured: 64 invocations 8.6 ms, 1024 about
// twice that, on 400 x 400 cells).
layout(local_size_x = kViewshedCpuGroupSize) in;

#include "analysis/ViewshedRings.glsl"
