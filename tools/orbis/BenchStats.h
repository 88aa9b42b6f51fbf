#pragma once
// What the modes of `orbis bench` share: order statistics of a series, the items the layers
// draw, number lists on the command line, and timing a run of frames.

#include "engine/gpu/GpuTimer.h"
#include "engine/render/Renderer.h"
#include "engine/scene/Scene.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>
#include <vector>

namespace orbis::cli {

struct Stats {
    double min = 0, median = 0, p95 = 0, mean = 0;
};

Stats summarize(std::vector<double> v);
/// The q-quantile (0..1, nearest rank) of `v`; 0 when it is empty.
double percentile(std::vector<double> v, double q);
nlohmann::json toJson(const Stats& s);

/// What the visible layers drew in the last frame (points, tiles, ...), summed.
uint64_t itemsDrawn(const scene::Scene& scene);

/// The comma-separated numbers of `option`'s value ("1,2.5,4"). Throws UsageError.
std::vector<double> numberList(const std::string& option, const std::string& text);

/// Milliseconds from `t0` to now.
double millisecondsSince(std::chrono::steady_clock::time_point t0);

/// The sum of a frame's per-pass GPU times.
double gpuTotalMs(const std::vector<gpu::PassTime>& passes);

/// Per measured frame: wall time (render until the GPU is done), CPU time, GPU time.
struct FrameTimes {
    std::vector<double> wall, cpu, gpuTotal;
};

/// Renders `warmup + frames` frames of a scene that does not move and times the last `frames`.
/// Main thread only.
FrameTimes timeFrames(render::Renderer& renderer, scene::Scene& scene, long frames, long warmup);

}  // namespace orbis::cli
