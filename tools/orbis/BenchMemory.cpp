#include "tools/orbis/BenchMemory.h"

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>

namespace orbis::cli {
namespace {

constexpr double kMB = 1048576.0;

double mb(uint64_t bytes) { return double(bytes) / kMB; }

}  // namespace

uint64_t peakRssBytes() {
    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    return uint64_t(usage.ru_maxrss) * 1024;
}

uint64_t currentRssBytes() {
    std::ifstream statm("/proc/self/statm");
    uint64_t size = 0, resident = 0;
    if (!(statm >> size >> resident)) return 0;
    return resident * uint64_t(sysconf(_SC_PAGESIZE));
}

uint64_t layerGpuBytes(const scene::Scene& scene) {
    uint64_t n = 0;
    for (const auto& r : scene.resources())
        if (const scene::LayerStats* stats = r.layer->asStats(); stats && r.layer->prepared()) n += stats->gpuBytes();
    return n;
}

uint64_t layerCacheBytes(const scene::Scene& scene) {
    uint64_t n = 0;
    for (const auto& r : scene.resources())
        if (const scene::LayerStats* stats = r.layer->asStats()) n += stats->cacheBytes();
    return n;
}

void MemoryWatch::afterFrame(const scene::Scene& scene, gpu::Device& device, long done, long frames) {
    maxGpuBytes_ = std::max(maxGpuBytes_, layerGpuBytes(scene));
    maxCacheBytes_ = std::max(maxCacheBytes_, layerCacheBytes(scene));
    if (done == 1 || done * 10 / frames != (done - 1) * 10 / frames)
        timeline_.push_back({double(done) / double(frames), currentRssBytes(), layerGpuBytes(scene),
                             layerCacheBytes(scene), device.allocator().stats().bytesReserved});
}

nlohmann::json MemoryWatch::toJson() const {
    nlohmann::json out = {{"layers_gpu_max", mb(maxGpuBytes_)},
                          {"layers_cache_max", mb(maxCacheBytes_)},
                          {"process_rss_peak", mb(peakRssBytes())}};
    for (const auto& m : timeline_)
        out["timeline"].push_back({{"at", m.at},
                                   {"rss", mb(m.rss)},
                                   {"layers_gpu", mb(m.layersGpu)},
                                   {"layers_cache", mb(m.layersCache)},
                                   {"device_reserved", mb(m.deviceReserved)}});
    return out;
}

void MemoryWatch::print() const {
    std::printf("memory: layers' GPU %.1f MB max, layers' caches %.1f MB max, process RSS peak %.1f MB\n",
                mb(maxGpuBytes_), mb(maxCacheBytes_), mb(peakRssBytes()));
    const struct mallinfo2 heap = mallinfo2();   // where RSS beyond the budgets goes
    std::printf("heap (glibc): %.1f MB in use, %.1f MB freed but kept in its arenas, %.1f MB mapped blocks\n",
                mb(heap.uordblks), mb(heap.fordblks), mb(heap.hblkhd));
    std::printf("memory over the run (MB: RSS / layers' GPU / layers' caches / device memory reserved):");
    for (const auto& m : timeline_)
        std::printf(" %.0f%%: %.0f/%.0f/%.0f/%.0f", m.at * 100.0, mb(m.rss), mb(m.layersGpu), mb(m.layersCache),
                    mb(m.deviceReserved));
    std::printf("\n");
}

}  // namespace orbis::cli
