// orbis bench SCENE: frame time statistics, CPU and GPU per pass.
#include "tools/orbis/Commands.h"

#include "engine/scene/CameraPath.h"
#include "tools/orbis/BenchModes.h"
#include "tools/orbis/BenchStats.h"
#include "tools/orbis/Session.h"

#include <nlohmann/json.hpp>

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <thread>

namespace orbis::cli {

namespace {
const char* kHelp =
    "usage: orbis bench SCENE [options]    or    orbis bench --video FILE [--seeks N]    or    orbis bench --poses FILE\n"
    "Renders SCENE repeatedly and reports frame times: CPU (update + record + submit), whole frame\n"
    "(until the GPU is done) and GPU time per pass, as min / median / p95 in milliseconds. A fixed\n"
    "view is measured after everything it shows has loaded.\n"
    "  --video FILE       FMV on the CPU, no scene: KLV packets/s, playback ms/frame, exact seeks\n"
    "                     (--seeks N random frames, default 50): median and p95\n"
    "  --poses FILE       glTF poses on the CPU, no scene: microseconds per pose of each animation\n"
    "                     (what an animated model layer pays per distinct animation time a frame)\n"
    "  --frames N         frames measured (default 100)\n"
    "  --warmup N         frames rendered first and not measured (default 5)\n"
    "  --size WxH         image size (default 1920x1080)\n"
    "  --time T           virtual time: ISO-8601 or seconds after the scene start\n"
    "  --json             print JSON instead of a table\n"
    "  --camera-path FILE the camera follows this path (orbis-camera-path JSON) over the measured\n"
    "                     frames, streaming as it goes: a fly-through\n"
    "  --sweep K=v1,v2,.. error against run time: for each value of the quality knob K (e.g.\n"
    "                     maxScreenSpaceError=1,2,4,8,16) wait for the data, time the frames, and\n"
    "                     compare the image with the first value's (the reference): RMSE, PSNR\n"
    "  --tiles LEVEL      tile throughput: the pager against a bare loop of GDAL reads over the same\n"
    "                     tiles of LEVEL (and their ancestors) on --threads N threads (default: cores)\n"
    "  --plot FILE        with --sweep: the PNG plot of RMSE against ms/frame (default orbis-sweep.png)\n"
    "  --iso-error N1,N2,.. isosurface position error against steps, for a scene with a volume in\n"
    "                     mode \"iso\": for each step count, with and without the secant/bisection\n"
    "                     refinement, ms/frame and the distance in voxels between each pixel's first\n"
    "                     hit and the reference's (refined, 4 x the largest count)\n";

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

/// Peak resident set size of this process, bytes.
uint64_t peakRssBytes() {
    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    return uint64_t(usage.ru_maxrss) * 1024;
}

/// Resident set size of this process now, bytes (0 where /proc is not there).
uint64_t currentRssBytes() {
    std::ifstream statm("/proc/self/statm");
    uint64_t size = 0, resident = 0;
    if (!(statm >> size >> resident)) return 0;
    return resident * uint64_t(sysconf(_SC_PAGESIZE));
}

/// Memory at one point of a run, for the "no growth once the caches are full" check.
struct MemorySample {
    double at = 0.0;   // fraction of the measured frames
    uint64_t rss = 0, layersGpu = 0, layersCache = 0;
    uint64_t deviceReserved = 0;   // every vkAllocateMemory block of the process
};

}  // namespace

int benchCommand(const std::vector<std::string>& argv) {
    std::set<std::string> valued = gpuValuedOptions();
    valued.insert({"--frames", "--warmup", "--size", "--time", "--camera-path", "--sweep", "--plot", "--tiles", "--threads",
                   "--iso-error", "--video", "--seeks", "--poses"});
    std::set<std::string> flags = gpuFlagOptions();
    flags.insert({"--help", "--json"});
    Args args(argv, valued, flags, {{"-h", "--help"}});
    if (args.flag("--help")) {
        std::printf("%s%s", kHelp, gpuOptionsHelp().c_str());
        return kOk;
    }
    if (auto video = args.value("--video")) {
        if (!args.positional().empty()) throw UsageError{"bench --video takes no SCENE"};
        return videoBench(*video, args.integer("--seeks", 1, 100000).value_or(50));
    }
    if (auto poses = args.value("--poses")) {
        if (!args.positional().empty()) throw UsageError{"bench --poses takes no SCENE"};
        return poseBench(*poses);
    }
    if (args.positional().size() != 1) throw UsageError{"bench expects exactly one SCENE file"};
    const long frames = args.integer("--frames", 1, 1000000).value_or(100);
    const long warmup = args.integer("--warmup", 0, 1000000).value_or(5);
    const auto [width, height] = args.size("--size").value_or(std::make_pair(1920u, 1080u));

    auto loaded = loadSceneForCommand(args);
    if (!loaded) return kBadInput;
    GpuSession gpu = openGpu(args);
    auto loadedPath = loadCameraPathOption(args);
    if (!loadedPath) return kBadInput;
    const std::optional<scene::CameraPath> path = std::move(loadedPath).value();
    std::unique_ptr<scene::Scene> scene = std::move(loaded).value();
    if (auto level = args.integer("--tiles", 0, 22)) {
        const unsigned threads = unsigned(args.integer("--threads", 1, 256).value_or(
            std::max(1u, std::thread::hardware_concurrency())));
        return tileBench(args, *scene, *level, threads);
    }
    if (args.value("--iso-error")) return isoErrorBench(args, gpu, width, height, frames, warmup);
    render::Renderer renderer(*gpu.device, width, height);
    if (args.value("--sweep")) return sweepBench(args, gpu, *scene, renderer, frames, warmup);
    std::vector<double> items;
    uint64_t maxGpuBytes = 0, maxCacheBytes = 0;
    std::vector<MemorySample> memory;   // at the first measured frame and every tenth of them

    std::vector<double> cpu, wall, gpuTotal;
    std::map<std::string, std::vector<double>> passes;
    std::vector<std::string> passOrder;
    // Virtual time moves by a fixed 1/60 s per frame, so runs are repeatable.
    constexpr double kFrameSeconds = 1.0 / 60.0;
    // A fixed view is measured once everything it shows has loaded (point clouds load on a
    // worker); a camera path measures the streaming as it flies.
    // The loading's times: to the first frame that draws anything, and until nothing loads.
    double firstContentS = -1.0, settledS = -1.0;
    if (!path) {
        const auto start = std::chrono::steady_clock::now();
        const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
        renderer.settle(*scene, 600.0, [&] {
            if (firstContentS < 0.0 && itemsDrawn(*scene) > 0) firstContentS = seconds();
        });
        settledS = seconds();
    }
    for (long i = 0; i < warmup + frames; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        scene->time().advance(i == 0 ? 0.0 : kFrameSeconds);
        if (path) {
            // The measured frames sweep the whole path; warm-up frames stay at its start.
            const double f = i < warmup || frames < 2 ? 0.0 : double(i - warmup) / double(frames - 1);
            scene->camera().setPose(
                scene->keptAboveGround(globe::poseFromViewpoint(path->at(path->startTime() + f * path->duration()))));
        }
        const auto frame = renderer.render(*scene, /*readback=*/false);
        const auto times = renderer.gpuTimes(frame);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (i < warmup) continue;
        cpu.push_back(frame.cpuMs);
        wall.push_back(ms);
        items.push_back(double(itemsDrawn(*scene)));
        maxGpuBytes = std::max(maxGpuBytes, layerGpuBytes(*scene));
        maxCacheBytes = std::max(maxCacheBytes, layerCacheBytes(*scene));
        const long done = i - warmup + 1;
        if (done == 1 || done * 10 / frames != (done - 1) * 10 / frames)
            memory.push_back({double(done) / double(frames), currentRssBytes(), layerGpuBytes(*scene),
                              layerCacheBytes(*scene), gpu.device->allocator().stats().bytesReserved});
        double total = 0.0;
        for (const auto& p : times) {
            if (!passes.count(p.name)) passOrder.push_back(p.name);
            passes[p.name].push_back(p.ms);
            total += p.ms;
        }
        gpuTotal.push_back(total);
    }

    const auto& info = gpu.device->info();
    if (args.flag("--json")) {
        nlohmann::json out;
        out["scene"] = args.positional()[0];
        out["device"] = {{"name", info.name}, {"type", info.type}, {"driver", info.driverInfo}};
        out["size"] = {width, height};
        out["frames"] = frames;
        out["warmup"] = warmup;
        out["cpu_ms"] = toJson(summarize(cpu));
        out["frame_ms"] = toJson(summarize(wall));
        out["gpu_ms"]["total"] = toJson(summarize(gpuTotal));
        out["items_drawn"] = toJson(summarize(items));
        out["memory_mb"] = {{"layers_gpu_max", double(maxGpuBytes) / 1048576.0},
                            {"layers_cache_max", double(maxCacheBytes) / 1048576.0},
                            {"process_rss_peak", double(peakRssBytes()) / 1048576.0}};
        for (const auto& m : memory)
            out["memory_mb"]["timeline"].push_back({{"at", m.at},
                                                    {"rss", double(m.rss) / 1048576.0},
                                                    {"layers_gpu", double(m.layersGpu) / 1048576.0},
                                                    {"layers_cache", double(m.layersCache) / 1048576.0},
                                                    {"device_reserved", double(m.deviceReserved) / 1048576.0}});
        if (path) out["camera_path"] = *args.value("--camera-path");
        if (settledS >= 0.0) out["load_s"] = {{"first_content", firstContentS}, {"settled", settledS}};
        for (const auto& name : passOrder) out["gpu_ms"]["passes"][name] = toJson(summarize(passes[name]));
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        std::printf("orbis bench %s  %ux%u  %ld frames (+%ld warm-up)  device: %s (%s)\n", args.positional()[0].c_str(),
                    width, height, frames, warmup, info.name.c_str(), info.type.c_str());
        std::printf("%-22s %10s %10s %10s\n", "ms", "min", "median", "p95");
        auto row = [](const std::string& name, const Stats& s) {
            std::printf("%-22s %10.3f %10.3f %10.3f\n", name.c_str(), s.min, s.median, s.p95);
        };
        row("frame (wall)", summarize(wall));
        row("cpu", summarize(cpu));
        row("gpu total", summarize(gpuTotal));
        row("items drawn", summarize(items));
        if (settledS >= 0.0)
            std::printf("loading: first frame with content after %.2f s, everything in view after %.2f s\n", firstContentS,
                        settledS);
        std::printf("memory: layers' GPU %.1f MB max, layers' caches %.1f MB max, process RSS peak %.1f MB\n",
                    double(maxGpuBytes) / 1048576.0, double(maxCacheBytes) / 1048576.0, double(peakRssBytes()) / 1048576.0);
        const struct mallinfo2 heap = mallinfo2();   // where RSS beyond the budgets goes
        std::printf("heap (glibc): %.1f MB in use, %.1f MB freed but kept in its arenas, %.1f MB mapped blocks\n",
                    double(heap.uordblks) / 1048576.0, double(heap.fordblks) / 1048576.0,
                    double(heap.hblkhd) / 1048576.0);
        std::printf("memory over the run (MB: RSS / layers' GPU / layers' caches / device memory reserved):");
        for (const auto& m : memory)
            std::printf(" %.0f%%: %.0f/%.0f/%.0f/%.0f", m.at * 100.0, double(m.rss) / 1048576.0,
                        double(m.layersGpu) / 1048576.0, double(m.layersCache) / 1048576.0,
                        double(m.deviceReserved) / 1048576.0);
        std::printf("\n");
        for (const auto& name : passOrder) row("gpu " + name, summarize(passes[name]));
    }
    return validationExitCode(gpu);
}

}  // namespace orbis::cli
