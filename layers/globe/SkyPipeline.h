#pragma once
// The sky behind the Earth, shared by the globe and terrain layers (both draw it when their
// scene asks for it): one pipeline description, in one place.
#include "engine/gpu/Pipeline.h"
#include "engine/scene/Layer.h"
#include "spv/globe/sky.frag.h"
#include "spv/globe/sky.vert.h"

namespace orbis::layers {

/// The sky pipeline for a layer whose pipeline layout holds the frame set. Drawn last at the
/// far plane (depth 0, reversed-Z): only pixels nothing else covered pass the depth test, so
/// the sky costs nothing under the surface.
inline gpu::Pipeline createSkyPipeline(gpu::Device& device, VkPipelineLayout layout,
                                       const scene::RenderServices& services, const char* name) {
    gpu::GraphicsPipelineDesc sky;
    sky.vertexSpirv = kSpv_globe_sky_vert;
    sky.fragmentSpirv = kSpv_globe_sky_frag;
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

}  // namespace orbis::layers
