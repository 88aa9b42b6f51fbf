#pragma once
// What the renderer lends to layers: the services to build GPU objects with (prepare), and the
// context of one frame's recording (recordTransfers, recordCompute, record).

#include "engine/scene/FrameContext.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>

namespace orbis::gpu {
class Device;
class Uploader;
class Image;
}  // namespace orbis::gpu
namespace orbis::jobs {
class ThreadPool;
}

namespace orbis::render {

/// What the renderer lends to layers for building GPU objects. Main thread only.
struct RenderServices {
    gpu::Device* device = nullptr;
    gpu::Uploader* uploader = nullptr;
    VkFormat colorFormat = VK_FORMAT_UNDEFINED;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;
    VkDescriptorSetLayout frameSetLayout = VK_NULL_HANDLE;   ///< set 0: FrameUniforms
    uint32_t framesInFlight = 2;                              ///< RecordContext::slot < this
    /// The shared worker pool, started on first call (a scene that needs no threads starts none).
    std::function<jobs::ThreadPool&()> jobs;
};

/// One frame's recording, for one layer. Called while recording, on the main thread.
struct RecordContext {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    const scene::FrameContext* frame = nullptr;
    VkDescriptorSet frameSet = VK_NULL_HANDLE;
    gpu::Uploader* uploader = nullptr;
    uint32_t slot = 0;   ///< frame-in-flight index: per-frame buffers written by the CPU use it
    /// recordCompute only: the scene depth so far (reversed-Z, D32), in ImageUse::SampledCompute.
    gpu::Image* sceneDepth = nullptr;
};

}  // namespace orbis::render
