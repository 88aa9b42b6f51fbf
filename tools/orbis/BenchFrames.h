#pragma once
// The measured frames of `orbis bench SCENE`: how long the view takes to load, then each
// frame's times (wall, CPU, GPU per pass), what it drew, and the memory over the run.

#include "engine/gpu/Device.h"
#include "engine/render/Renderer.h"
#include "engine/scene/CameraPath.h"
#include "engine/scene/Scene.h"
#include "tools/orbis/BenchMemory.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace orbis::cli {

/// Seconds from the start of loading to the first frame that draws anything, and until nothing
/// loads any more (both -1 when not measured: a camera path streams as it flies).
struct LoadTimes {
    double firstContentS = -1.0, settledS = -1.0;
};

/// Renders a fixed view until everything it shows has loaded (point clouds load on a worker),
/// timing the loading. Main thread only.
LoadTimes settleTimed(render::Renderer& renderer, scene::Scene& scene);

struct FrameSeries {
    std::vector<double> cpu, wall, gpuTotal, items;
    std::map<std::string, std::vector<double>> passes;
    std::vector<std::string> passOrder;   // the order the renderer first reported them in
    MemoryWatch memory;
};

/// Renders `warmup + frames` frames, virtual time moving by a fixed 1/60 s a frame, the camera
/// along `path` if given, and records the last `frames`. Main thread only.
FrameSeries measureFrames(render::Renderer& renderer, scene::Scene& scene, gpu::Device& device,
                          const std::optional<scene::CameraPath>& path, long frames, long warmup);

}  // namespace orbis::cli
