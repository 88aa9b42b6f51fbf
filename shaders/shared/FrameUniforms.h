// Per-frame constants every layer can read: set 0, binding 0 (kFrameSet/kFrameBinding).
#ifndef ORBIS_SHADERS_SHARED_FRAME_UNIFORMS_H
#define ORBIS_SHADERS_SHARED_FRAME_UNIFORMS_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kFrameSet, 0)
ORBIS_CONST(uint, kFrameBinding, 0)

// std140. Each vec3 shares its 16 bytes with the float after it on both sides; the C++ side
// asserts the offsets below.
struct FrameUniforms {
    mat4 viewRotation;     // world -> view, rotation only (the eye is the origin)
    mat4 projection;       // reversed-Z, infinite far plane
    mat4 clipToWorldDir;   // inverse(projection * viewRotation): clip position -> world direction
    vec3 eyeEcef;          // the eye in ECEF metres as float: ONLY for analytic shading (sky, day side)
    float eyeHeight;       // the eye's height above the ellipsoid (m)
    vec3 sunDirection;     // unit vector to the sun (world)
    float sunLighting;     // 1: lit by the sun; 0: headlight
    vec2 viewportSize;     // pixels
    vec2 invViewportSize;  // 1 / pixels
    float equatorialRadius;   // a (m)
    float polarRadius;        // b (m)
    float invEquatorialRadius2;   // 1 / a^2
    float invPolarRadius2;        // 1 / b^2
    vec3 background;       // the clear colour (linear)
    float secondsOfDay;    // the scene's time within its day (UTC, s)
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
static_assert(offsetof(orbis::shader::FrameUniforms, eyeEcef) == 192 && offsetof(orbis::shader::FrameUniforms, eyeHeight) == 204,
              "std140 offset");
static_assert(offsetof(orbis::shader::FrameUniforms, sunDirection) == 208 && offsetof(orbis::shader::FrameUniforms, sunLighting) == 220,
              "std140 offset");
static_assert(offsetof(orbis::shader::FrameUniforms, viewportSize) == 224 && offsetof(orbis::shader::FrameUniforms, invViewportSize) == 232,
              "std140 offset");
static_assert(offsetof(orbis::shader::FrameUniforms, equatorialRadius) == 240, "std140 offset");
static_assert(offsetof(orbis::shader::FrameUniforms, background) == 256 && offsetof(orbis::shader::FrameUniforms, secondsOfDay) == 268,
              "std140 offset");
#endif

#endif
