#pragma once
// The sky behind the Earth, shared by the globe and terrain layers (both draw it when their
// scene asks for it): one pipeline description, in one place.
#include "engine/gpu/Pipeline.h"
#include "engine/render/RenderContext.h"

namespace orbis::render {

/// The sky pipeline for a layer whose pipeline layout holds the frame set. Drawn last at the
/// far plane (depth 0, reversed-Z): only pixels nothing else covered pass the depth test, so
/// the sky costs nothing under the surface. Main thread only.
gpu::Pipeline createSkyPipeline(gpu::Device& device, VkPipelineLayout layout, const render::RenderServices& services,
                                const char* name);

}  // namespace orbis::render
