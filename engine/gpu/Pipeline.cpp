#include "engine/gpu/Pipeline.h"

#include "engine/gpu/VkCheck.h"

namespace orbis::gpu {

ShaderModule createShaderModule(Device& device, std::span<const uint32_t> spirv) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = spirv.size_bytes();
    info.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    VK_CHECK(vkCreateShaderModule(device.vk(), &info, nullptr, &module));
    return ShaderModule(device, module);
}

PipelineLayout createPipelineLayout(Device& device, std::span<const VkDescriptorSetLayout> sets,
                                    std::span<const VkPushConstantRange> pushConstants) {
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = static_cast<uint32_t>(sets.size());
    info.pSetLayouts = sets.data();
    info.pushConstantRangeCount = static_cast<uint32_t>(pushConstants.size());
    info.pPushConstantRanges = pushConstants.data();
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VK_CHECK(vkCreatePipelineLayout(device.vk(), &info, nullptr, &layout));
    return PipelineLayout(device, layout);
}

namespace {
VkSpecializationInfo toInfo(const Specialization* s) {
    VkSpecializationInfo info{};
    if (!s) return info;
    info.mapEntryCount = static_cast<uint32_t>(s->entries.size());
    info.pMapEntries = s->entries.data();
    info.dataSize = s->data.size();
    info.pData = s->data.data();
    return info;
}
}  // namespace

Pipeline createGraphicsPipeline(Device& device, const GraphicsPipelineDesc& d) {
    ShaderModule vert = createShaderModule(device, d.vertexSpirv);
    ShaderModule frag = createShaderModule(device, d.fragmentSpirv);
    const VkSpecializationInfo spec = toInfo(d.specialization);

    VkPipelineShaderStageCreateInfo stages[2]{};
    stages[0].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vert.vk();
    stages[0].pName = "main";
    stages[0].pSpecializationInfo = d.specialization ? &spec : nullptr;
    stages[1] = stages[0];
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = frag.vk();

    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vertexInput.vertexBindingDescriptionCount = static_cast<uint32_t>(d.bindings.size());
    vertexInput.pVertexBindingDescriptions = d.bindings.data();
    vertexInput.vertexAttributeDescriptionCount = static_cast<uint32_t>(d.attributes.size());
    vertexInput.pVertexAttributeDescriptions = d.attributes.data();

    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = d.topology;

    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;

    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = d.polygonMode;
    raster.cullMode = d.cullMode;
    raster.frontFace = d.frontFace;
    raster.lineWidth = 1.0f;

    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;

    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = d.depthTest;
    depth.depthWriteEnable = d.depthWrite;
    depth.depthCompareOp = d.depthCompare;

    VkPipelineColorBlendAttachmentState blend{};
    blend.colorWriteMask = d.colorWrite ? VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                                              VK_COLOR_COMPONENT_A_BIT
                                        : 0;
    if (d.alphaBlend) {
        blend.blendEnable = VK_TRUE;
        blend.srcColorBlendFactor = VK_BLEND_FACTOR_ONE;
        blend.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        blend.colorBlendOp = VK_BLEND_OP_ADD;
        blend.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
        blend.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        blend.alphaBlendOp = VK_BLEND_OP_ADD;
    }
    VkPipelineColorBlendStateCreateInfo colorBlend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    colorBlend.attachmentCount = 1;
    colorBlend.pAttachments = &blend;

    const VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamicStates;

    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = d.colorFormat != VK_FORMAT_UNDEFINED ? 1 : 0;
    rendering.pColorAttachmentFormats = &d.colorFormat;
    rendering.depthAttachmentFormat = d.depthFormat;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = &rendering;
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = rendering.colorAttachmentCount ? &colorBlend : nullptr;
    info.pDynamicState = &dynamic;
    info.layout = d.layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VK_CHECK(vkCreateGraphicsPipelines(device.vk(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    device.setDebugName(reinterpret_cast<uint64_t>(pipeline), VK_OBJECT_TYPE_PIPELINE, d.name);
    return Pipeline(device, pipeline);
}

Pipeline createComputePipeline(Device& device, VkPipelineLayout layout, std::span<const uint32_t> spirv,
                               const Specialization* specialization, const char* name) {
    ShaderModule module = createShaderModule(device, spirv);
    const VkSpecializationInfo spec = toInfo(specialization);
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module.vk();
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = specialization ? &spec : nullptr;
    info.layout = layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VK_CHECK(vkCreateComputePipelines(device.vk(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    device.setDebugName(reinterpret_cast<uint64_t>(pipeline), VK_OBJECT_TYPE_PIPELINE, name);
    return Pipeline(device, pipeline);
}

}  // namespace orbis::gpu
