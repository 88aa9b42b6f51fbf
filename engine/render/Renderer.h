#pragma once
// Renders a Scene into an offscreen target: per-frame uniforms, the passes in order, GPU
// timestamps per pass, optional readback. The same frame serves the headless renderer, the
// benchmark and (blitted to a swapchain) the viewer.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/FrameRing.h"
#include "engine/gpu/GpuTimer.h"
#include "engine/gpu/Handle.h"
#include "engine/gpu/RenderTarget.h"
#include "engine/gpu/Uploader.h"
#include "engine/render/RenderContext.h"
#include "engine/scene/Layer.h"
#include "engine/scene/Scene.h"

#include <glm/glm.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace orbis::jobs {
class ThreadPool;
}

namespace orbis::render {

struct FrameResult {
    uint64_t frameNumber = 0;
    uint64_t timelineValue = 0;   ///< wait for it before reading pixels or GPU times
    uint32_t slot = 0;
    double cpuMs = 0.0;           ///< update + record + submit
};

/// What the viewer adds to a frame: its UI drawn over the picture, a copy to the window, and
/// the semaphores of the swapchain. All optional; the headless renderer uses none.
struct FrameHooks {
    /// Records after the passes, with the colour target in ImageUse::ColorAttachment (outside
    /// any rendering scope): the UI drawn over the picture. Timed as "ui". Before any readback,
    /// so screenshots show it.
    std::function<void(VkCommandBuffer, gpu::RenderTarget&)> overlay;
    /// Records last (after the readback): e.g. the blit of the colour target to a swapchain image.
    std::function<void(VkCommandBuffer, gpu::RenderTarget&)> finish;
    std::vector<VkSemaphoreSubmitInfo> waits;     ///< e.g. the swapchain image's acquire
    std::vector<VkSemaphoreSubmitInfo> signals;   ///< e.g. the semaphore presentation waits on
};

class Renderer {
public:
    Renderer(gpu::Device& device, uint32_t width, uint32_t height);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Updates the visible layers, records every pass and submits. Main thread only.
    FrameResult render(scene::Scene& scene, bool readback);
    /// The same, with the viewer's additions (FrameHooks).
    FrameResult render(scene::Scene& scene, bool readback, const FrameHooks& hooks);
    /// Runs frames that update, load and upload but draw nothing, until no visible layer is
    /// busy or `maxSeconds` have passed; returns the frames run. Batch renders call it before
    /// the frame they keep, so the picture has every tile the view needs. `afterFrame`, if
    /// given, runs after each of those frames (benchmarks time the loading with it).
    int settle(scene::Scene& scene, double maxSeconds, const std::function<void()>& afterFrame = {});
    /// Blocks until the frame is done, then returns its pixels (RGBA8 sRGB, top row first).
    std::vector<uint8_t> readPixels(const FrameResult& frame);
    /// Blocks until the frame is done, then returns its per-pass GPU times.
    std::vector<gpu::PassTime> gpuTimes(const FrameResult& frame);

    gpu::RenderTarget& target() { return *target_; }
    uint32_t width() const { return target_->width(); }
    uint32_t height() const { return target_->height(); }
    void resize(uint32_t width, uint32_t height);

    /// The worker pool, created on first use. Main thread only.
    jobs::ThreadPool& jobs();
    bool jobsStarted() const { return jobs_ != nullptr; }

private:
    FrameResult render(scene::Scene& scene, bool readback, bool draw, const FrameHooks* hooks);
    void prepareLayer(scene::Layer& layer);
    /// Puts the camera where its mode wants it and its near plane; returns the eye's height.
    double placeCamera(scene::Scene& scene);
    scene::FrameContext frameContext(scene::Scene& scene, uint64_t frameNumber, double eyeHeight) const;
    /// The passes in order, each only when a visible layer draws in it.
    void recordPasses(scene::Scene& scene, const RecordContext& rc);
    void writeFrameUniforms(uint32_t slot, const scene::Scene& scene, const scene::FrameContext& ctx);
    void recordPass(scene::Pass pass, const char* name, scene::Scene& scene, const RecordContext& rc,
                    bool clear, const glm::dvec3& background);

    gpu::Device& device_;
    std::unique_ptr<gpu::RenderTarget> target_;
    gpu::FrameRing ring_;
    gpu::GpuTimer timer_;
    gpu::Uploader uploader_;
    gpu::DescriptorSets frameSets_;   // set 0 (shader::kFrameBindings), one per frame in flight
    std::vector<gpu::Buffer> frameUniforms_;
    std::unique_ptr<jobs::ThreadPool> jobs_;
    RenderServices services_;
};

}  // namespace orbis::render
