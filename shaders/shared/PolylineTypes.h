// Coloured polylines and screen quads (shaders/common/polyline.*): a model's path and label
// (layers/models), the scene's pins (layers/annotations). One vertex stream, set 0 only; the
// specialisation constant kPolylineSpecScreen says whether positions are already in clip space.
#ifndef ORBIS_SHADERS_SHARED_POLYLINE_TYPES_H
#define ORBIS_SHADERS_SHARED_POLYLINE_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kPolylineSpecScreen, 0)   // bool: positions are in clip space (screen quads)
ORBIS_CONST(uint, kPolylineInputPosition, 0)
ORBIS_CONST(uint, kPolylineInputColor, 1)

// One vertex, both streams.
struct PolylineVertex {
    vec4 position;     // xyz: relative to the eye (metres, world axes), w: 1; or clip space (screen quads)
    vec4 color;        // linear RGBA
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
namespace orbis::shader {
inline constexpr SpecConstant kPolylineSpecConstants[] = {{kPolylineSpecScreen, SpecType::Bool}};
}  // namespace orbis::shader
static_assert(sizeof(orbis::shader::PolylineVertex) == 32, "PolylineVertex layout changed");
#endif

#endif
