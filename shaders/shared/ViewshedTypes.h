// The viewshed on the GPU (layers/analysis/ViewshedGpu.h; the model in globe/Viewshed.h). Set
// kViewshedSet: the grid's heights (float a cell, row-major, NaN: no data), the horizon of each
// cell (float, written ring by ring: ring d reads ring d - 1), and the result (uint a cell: the
// codes of globe::Sight). One dispatch of four workgroups, a quadrant each.
#ifndef ORBIS_SHADERS_SHARED_VIEWSHED_TYPES_H
#define ORBIS_SHADERS_SHARED_VIEWSHED_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kViewshedSet, 0)
ORBIS_CONST(uint, kViewshedBindingHeights, 0)
ORBIS_CONST(uint, kViewshedBindingHorizon, 1)
ORBIS_CONST(uint, kViewshedBindingSight, 2)

ORBIS_CONST(uint, kViewshedGroupSize, 1024)     // viewshed.comp (GPUs)
ORBIS_CONST(uint, kViewshedCpuGroupSize, 64)   // viewshed_cpu.comp (CPU devices)
ORBIS_CONST(uint, kViewshedGroups, 4)   // one a quadrant

// globe::Sight.
ORBIS_CONST(uint, kSightHidden, 0)
ORBIS_CONST(uint, kSightVisible, 1)
ORBIS_CONST(uint, kSightOutOfRange, 2)
ORBIS_CONST(uint, kSightNoData, 3)

// Push constants (viewshed.comp). Heights are made relative to the eye on the GPU: h - eye -
// drop * (cells from the observer)^2, small numbers.
struct ViewshedPush {
    int observerCol;
    int observerRow;
    int side;              // cells a side
    int ring;              // the last ring (Chebyshev distance from the observer) to compute
    float eye;             // the eye's height (ground + observer height), metres
    float dropPerCell2;    // curvature / diameter * cell^2: the drop at one cell, metres
    float radius2Cells;    // (radius / cell)^2; 0: no limit
    float targetHeight;    // metres above the ground
    float observerHeight;  // metres above the ground
    float pad0;
    float pad1;
    float pad2;
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
namespace orbis::shader {
/// Set kViewshedSet (layers/analysis/ViewshedGpu.cpp).
inline constexpr DescriptorBinding kViewshedBindings[] = {
    {kViewshedBindingHeights, DescriptorKind::StorageBuffer, 1, kStageCompute},
    {kViewshedBindingHorizon, DescriptorKind::StorageBuffer, 1, kStageCompute},
    {kViewshedBindingSight, DescriptorKind::StorageBuffer, 1, kStageCompute},
};
}  // namespace orbis::shader
static_assert(sizeof(orbis::shader::ViewshedPush) == 48, "ViewshedPush layout changed");
#endif

#endif
