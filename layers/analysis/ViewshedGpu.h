#pragma once
// The viewshed on the GPU: globe/Viewshed.h's ring propagation in one dispatch of four
// workgroups, a quadrant each, walking the rings outward with a barrier between rings (the
// cells of a ring at once: each reads the horizons the ring inside it wrote). The grid's heights go up once; the observer can then move anywhere in the grid and
// the viewshed is computed again from the same heights (dragging the observer in the viewer).
// Float on the GPU: heights are made relative to the eye first, so the numbers stay small.
//
//   ViewshedGpu gpu(device);
//   gpu.setGrid(grid);                          // uploads the heights
//   auto v = gpu.run(options, &timing);         // dispatches, waits, reads back
//
// or record() into a frame's command buffer and read sights() there (the viewer's overlay).

#include "base/Result.h"
#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/GpuTimer.h"
#include "engine/gpu/Handle.h"
#include "globe/Viewshed.h"

#include <vulkan/vulkan.h>

#include <memory>

namespace orbis::gpu {
class Device;
}

namespace orbis::layers {

struct ViewshedTiming {
    double gpuMs = 0.0;        ///< the dispatches, from GPU timestamps (0 where the device has none)
    double submitMs = 0.0;     ///< record, submit and wait, on the CPU's clock
    double readbackMs = 0.0;   ///< the copy back and the conversion to globe::Viewshed
    int rings = 0;             ///< rings walked (the observer's cell included)
};

class ViewshedGpu {
public:
    /// The workgroup: wide (viewshed.comp, for GPUs), narrow (viewshed_cpu.comp, for CPU
    /// devices), or chosen from the device.
    enum class Workgroup { Auto, Wide, Narrow };
    explicit ViewshedGpu(gpu::Device& device, Workgroup workgroup = Workgroup::Auto);
    ~ViewshedGpu();

    /// Uploads the grid's heights (the buffers grow to fit; a smaller grid reuses them).
    Result<void> setGrid(const globe::ViewshedGrid& grid);
    const globe::ViewshedGrid* grid() const { return grid_ ? &*grid_ : nullptr; }

    /// Records the viewshed for `options` (checked first) into `cmd`; the result is in sights()
    /// (one uint a cell, globe::Sight codes) once it has run.
    Result<void> record(VkCommandBuffer cmd, const globe::ViewshedOptions& options);
    /// record() on a one-shot command buffer, waits, and reads the result back.
    Result<globe::Viewshed> run(const globe::ViewshedOptions& options, ViewshedTiming* timing = nullptr);

    const gpu::Buffer& sights() const { return sights_; }

private:
    gpu::Device& device_;
    gpu::DescriptorSets descriptors_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline pipeline_;
    gpu::GpuTimer timer_;
    gpu::Buffer heights_, horizon_, sights_, readback_;
    std::optional<globe::ViewshedGrid> grid_;
    size_t capacity_ = 0;   ///< cells the buffers hold
    int lastRings_ = 0;
};

}  // namespace orbis::layers
