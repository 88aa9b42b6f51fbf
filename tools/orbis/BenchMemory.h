#pragma once
// Memory over a bench run: the layers' GPU memory and caches at their largest, and samples of
// the process and the device over the run, for the "no growth once the caches are full" check.

#include "engine/gpu/Device.h"
#include "engine/scene/Scene.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace orbis::cli {

/// Memory at one point of a run.
struct MemorySample {
    double at = 0.0;   // fraction of the measured frames
    uint64_t rss = 0, layersGpu = 0, layersCache = 0;
    uint64_t deviceReserved = 0;   // every vkAllocateMemory block of the process
};

/// Peak resident set size of this process, bytes.
uint64_t peakRssBytes();
/// Resident set size of this process now, bytes (0 where /proc is not there).
uint64_t currentRssBytes();
/// GPU memory of the prepared layers, bytes.
uint64_t layerGpuBytes(const scene::Scene& scene);
/// CPU caches of the layers, bytes.
uint64_t layerCacheBytes(const scene::Scene& scene);

class MemoryWatch {
public:
    /// After measured frame `done` (1-based) of `frames`: the layers' peaks, and a sample at
    /// the first frame and at every tenth of the run. Main thread only.
    void afterFrame(const scene::Scene& scene, gpu::Device& device, long done, long frames);

    /// {"layers_gpu_max", "layers_cache_max", "process_rss_peak", "timeline"}, in MB.
    nlohmann::json toJson() const;
    /// The report's lines: peaks, the glibc heap, and the samples over the run.
    void print() const;

private:
    uint64_t maxGpuBytes_ = 0, maxCacheBytes_ = 0;
    std::vector<MemorySample> timeline_;
};

}  // namespace orbis::cli
