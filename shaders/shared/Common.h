// Compiles as GLSL and as C++. In C++ the GLSL vector types map onto GLM, so one struct
// declaration is the layout on both sides; the C++ side static_asserts sizes and offsets.
#ifndef ORBIS_SHADERS_SHARED_COMMON_H
#define ORBIS_SHADERS_SHARED_COMMON_H

#ifdef __cplusplus
#include <glm/glm.hpp>
#include <cstddef>
#include <cstdint>
namespace orbis::shader {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
using uint = std::uint32_t;
}  // namespace orbis::shader
#define ORBIS_NAMESPACE_BEGIN namespace orbis::shader {
#define ORBIS_NAMESPACE_END }
#define ORBIS_CONST(type, name, value) constexpr type name = value;
#else
#define ORBIS_NAMESPACE_BEGIN
#define ORBIS_NAMESPACE_END
#define ORBIS_CONST(type, name, value) const type name = value;
#endif

#endif
