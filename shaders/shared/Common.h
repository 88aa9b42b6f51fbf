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
namespace orbis::shader {
/// The kinds of descriptor a set layout declared in a shared header holds (engine/gpu maps them
/// to VkDescriptorType).
enum class DescriptorKind : uint32_t {
    UniformBuffer,
    StorageBuffer,
    StorageBufferDynamic,   ///< a storage buffer bound at an offset given when binding the set
    CombinedImageSampler,
    StorageImage,
};
/// Shader stages as bits: the values of VkShaderStageFlagBits (engine/gpu static_asserts them).
inline constexpr uint32_t kStageVertex = 0x1, kStageFragment = 0x10, kStageCompute = 0x20;
/// One binding of a descriptor set as the C++ side creates it. A shared header lists a set's
/// bindings in a table next to the binding numbers the GLSL uses: that table is the set layout
/// (gpu::createDescriptorSets) and the build checks it against the compiled SPIR-V.
struct DescriptorBinding {
    uint32_t binding = 0;
    DescriptorKind kind = DescriptorKind::UniformBuffer;
    uint32_t count = 1;
    uint32_t stages = 0;
};
/// The type of a specialisation constant (`layout(constant_id = ...) const T`): what the C++
/// side must pass to gpu::Specialization::set<T> (VkBool32, int32_t, uint32_t, float).
enum class SpecType : uint32_t { Bool, Int, Uint, Float };
/// A specialisation constant a shared header names: its ID and type. A header lists its
/// shaders' constants in a table that the build checks against the compiled SPIR-V.
struct SpecConstant {
    uint32_t id = 0;
    SpecType type = SpecType::Bool;
};
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
