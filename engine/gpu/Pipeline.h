#pragma once
// Pipeline construction from SPIR-V embedded at build time. Graphics pipelines use dynamic
// rendering (no VkRenderPass), dynamic viewport/scissor and reversed-Z depth by default.

#include "engine/gpu/Handle.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <vector>

namespace orbis::gpu {

/// Constant values for the shader's `layout(constant_id = N)`: leave out what a setting does
/// not use at pipeline-build time instead of branching at run time.
struct Specialization {
    std::vector<VkSpecializationMapEntry> entries;
    std::vector<uint8_t> data;
    template <typename T>
    Specialization& set(uint32_t id, const T& value) {
        entries.push_back({id, static_cast<uint32_t>(data.size()), sizeof(T)});
        const auto* p = reinterpret_cast<const uint8_t*>(&value);
        data.insert(data.end(), p, p + sizeof(T));
        return *this;
    }
};

struct GraphicsPipelineDesc {
    std::span<const uint32_t> vertexSpirv;
    std::span<const uint32_t> fragmentSpirv;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    std::vector<VkVertexInputBindingDescription> bindings;
    std::vector<VkVertexInputAttributeDescription> attributes;
    VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPolygonMode polygonMode = VK_POLYGON_MODE_FILL;
    VkCullModeFlags cullMode = VK_CULL_MODE_BACK_BIT;
    VkFrontFace frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    bool depthTest = true;
    bool depthWrite = true;
    VkCompareOp depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;   ///< reversed-Z: near = 1, far = 0
    bool alphaBlend = false;                                      ///< premultiplied "over"
    bool colorWrite = true;                                       ///< false: a depth-only pass
    VkFormat colorFormat = VK_FORMAT_R8G8B8A8_SRGB;
    VkFormat depthFormat = VK_FORMAT_D32_SFLOAT;
    const Specialization* specialization = nullptr;
    const char* name = nullptr;
};

ShaderModule createShaderModule(Device& device, std::span<const uint32_t> spirv);
PipelineLayout createPipelineLayout(Device& device, std::span<const VkDescriptorSetLayout> sets,
                                    std::span<const VkPushConstantRange> pushConstants);
Pipeline createGraphicsPipeline(Device& device, const GraphicsPipelineDesc& desc);
Pipeline createComputePipeline(Device& device, VkPipelineLayout layout, std::span<const uint32_t> spirv,
                               const Specialization* specialization = nullptr, const char* name = nullptr);

}  // namespace orbis::gpu
