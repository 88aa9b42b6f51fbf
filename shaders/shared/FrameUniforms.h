// Per-frame constants every layer can read: set 0, binding 0 (kFrameSet/kFrameBinding).
#ifndef ORBIS_SHADERS_SHARED_FRAME_UNIFORMS_H
#define ORBIS_SHADERS_SHARED_FRAME_UNIFORMS_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kFrameSet, 0)
ORBIS_CONST(uint, kFrameBinding, 0)

// std140: only vec4 and mat4 members, so C++ and GLSL agree without padding rules.
struct FrameUniforms {
    mat4 viewRotation;     // world -> view, rotation only (the eye is the origin)
    mat4 projection;       // reversed-Z, infinite far plane
    mat4 clipToWorldDir;   // inverse(projection * viewRotation): clip position -> world direction
    vec4 eyeEcef;          // xyz: eye in ECEF metres as float, ONLY for analytic sky shading; w: eye height above ellipsoid
    vec4 sunDirection;     // xyz: unit vector to the sun (world); w: 1 = sun lighting on, 0 = headlight
    vec4 viewport;         // width, height, 1/width, 1/height
    vec4 ellipsoid;        // equatorial radius, polar radius, 1/a^2, 1/b^2
    vec4 background;       // rgb: clear colour (linear); a: time in seconds within the day (UTC)
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
namespace orbis::shader {
/// Set 0, the renderer's (engine/render/Renderer.cpp): every stage of every layer may read it.
inline constexpr DescriptorBinding kFrameBindings[] = {
    {kFrameBinding, DescriptorKind::UniformBuffer, 1, kStageVertex | kStageFragment | kStageCompute},
};
}  // namespace orbis::shader
static_assert(sizeof(orbis::shader::FrameUniforms) == 3 * 64 + 5 * 16, "FrameUniforms layout changed");
static_assert(offsetof(orbis::shader::FrameUniforms, eyeEcef) == 192, "std140 offset");
#endif

#endif
