#include "engine/render/SkyPipeline.h"

#include "spv/common/sky.frag.h"
#include "spv/common/sky.vert.h"

namespace orbis::render {

gpu::Pipeline createSkyPipeline(gpu::Device& device, VkPipelineLayout layout, const render::RenderServices& services,
                                const char* name) {
    gpu::GraphicsPipelineDesc sky;
    sky.vertexSpirv = kSpv_common_sky_vert;
    sky.fragmentSpirv = kSpv_common_sky_frag;
    sky.layout = layout;
    sky.cullMode = VK_CULL_MODE_NONE;
    sky.depthTest = true;
    sky.depthCompare = VK_COMPARE_OP_EQUAL;
    sky.depthWrite = false;
    sky.colorFormat = services.colorFormat;
    sky.depthFormat = services.depthFormat;
    sky.name = name;
    return gpu::createGraphicsPipeline(device, sky);
}

}  // namespace orbis::render
