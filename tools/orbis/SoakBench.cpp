// orbis bench SCENE --soak SECONDS: a long run of the scene as the viewer would play it (time
// playing at the scene's rate, the camera along a looping path), sampling the process and the
// layers, then checking that nothing grows once the caches have filled.
//
// Samples (about 100 over the run, at least 1 s apart): RSS, the layers' GPU memory and caches,
// the device memory reserved, threads and open descriptors, and the frame times since the
// previous sample (median, p99). The bounds, checked over the samples after the warm-up (while
// caches fill: the first quarter of the run, or the first loop of the camera path or of the
// scene's time if that is longer; soak.json's path and time both loop every 30 s, so every view
// of the run is shown in its first 30 s):
//   - memory (each of RSS, layers' GPU, layers' caches, device reserved): flat within +-5 %
//     of the middle of its range, (max - min) <= 5 % of (max + min); RSS in a run shorter than
//     10 minutes: RSS less the allocator's free memory not growing instead (rssNotGrowing:
//     the allocator has not settled yet);
//   - threads and descriptors: none more at the end than at the first quarter;
//   - frame time: the p99 of each third of what follows the warm-up within 1.5x the first's;
//   - the validation layer (with --validation): no message.
// A bound that fails is named on stderr and the exit code is 1.

#include "globe/Viewpoint.h"
#include "tools/orbis/BenchFrames.h"
#include "tools/orbis/BenchMemory.h"
#include "tools/orbis/BenchModes.h"
#include "tools/orbis/BenchStats.h"
#include "tools/orbis/Plot.h"

#include <dirent.h>
#include <malloc.h>
#include <gdal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace orbis::cli {
namespace {

constexpr double kMB = 1048576.0;
constexpr double kWarmUpFraction = 0.25;
constexpr double kRssSettleSeconds = 600.0;   // shorter runs check RSS for growth, not flatness
constexpr double kFlatWithin = 0.05;
constexpr double kP99Ratio = 1.5;

/// Entries of a /proc folder (threads in /proc/self/task, descriptors in /proc/self/fd), not
/// counting "." and ".." (nor, for fd, the one opendir itself holds).
int countEntries(const char* folder, bool minusOwn) {
    DIR* dir = ::opendir(folder);
    if (!dir) return -1;
    int n = 0;
    while (const dirent* e = ::readdir(dir))
        if (e->d_name[0] != '.') ++n;
    ::closedir(dir);
    return minusOwn ? n - 1 : n;
}

struct SoakSample {
    double t = 0.0;   // seconds since the start
    long frames = 0;  // frames rendered so far
    double rss = 0, layersGpu = 0, layersCache = 0, deviceReserved = 0;   // MB
    double gdalCache = 0;   // MB in GDAL's raster block cache (bounded by GDAL_CACHEMAX)
    double heapInUse = 0, heapFree = 0;   // MB: glibc's heap in use, and freed but kept in its arenas
    int threads = 0, fds = 0;
    double p50 = 0, p99 = 0;   // frame ms since the previous sample
};

SoakSample takeSample(double t, long frames, const scene::Scene& scene, gpu::Device& device, std::vector<double>& window) {
    SoakSample s;
    s.t = t;
    s.frames = frames;
    s.rss = double(currentRssBytes()) / kMB;
    s.layersGpu = double(layerGpuBytes(scene)) / kMB;
    s.layersCache = double(layerCacheBytes(scene)) / kMB;
    s.deviceReserved = double(device.allocator().stats().bytesReserved) / kMB;
    s.gdalCache = double(GDALGetCacheUsed64()) / kMB;
    const struct mallinfo2 heap = mallinfo2();
    s.heapInUse = double(heap.uordblks + heap.hblkhd) / kMB;
    s.heapFree = double(heap.fordblks) / kMB;
    s.threads = countEntries("/proc/self/task", false);
    s.fds = countEntries("/proc/self/fd", true);
    if (!window.empty()) {
        const Stats st = summarize(window);
        s.p50 = st.median;
        s.p99 = percentile(window, 0.99);
    }
    window.clear();
    return s;
}

/// The sample nearest to fraction f of the run.
const SoakSample& at(const std::vector<SoakSample>& samples, double f) {
    const double t = f * samples.back().t;
    return *std::min_element(samples.begin(), samples.end(),
                             [&](const SoakSample& a, const SoakSample& b) { return std::abs(a.t - t) < std::abs(b.t - t); });
}

struct Check {
    std::string name;
    bool ok = true;
    std::string detail;
};

/// (max - min) / (max + min) of a quantity over the samples after the warm-up.
Check flat(const std::vector<SoakSample>& after, const char* name, double SoakSample::*field) {
    double lo = after.front().*field, hi = lo;
    for (const auto& s : after) lo = std::min(lo, s.*field), hi = std::max(hi, s.*field);
    const double spread = hi + lo > 0 ? (hi - lo) / (hi + lo) : 0.0;
    char text[160];
    std::snprintf(text, sizeof text, "%.1f .. %.1f MB: +-%.1f %% (bound +-%.0f %%)", lo, hi, 100.0 * spread, 100.0 * kFlatWithin);
    return {std::string(name) + " flat", spread <= kFlatWithin, text};
}

/// RSS in a short run: glibc keeps freed memory at each arena's high-water mark and steps it up
/// and down by tens of MB while the heap in use stays flat (CI's 2-minute soak: 469 MB, then 512,
/// then 457, with 316 MB in use throughout; another: 435 MB, then 486 to the end, its arenas
/// holding 114 MB free instead of 72), so flatness is checked only once it has had time to
/// settle (kRssSettleSeconds). Before that the check is for growth, which is what a leak does,
/// of the memory the process uses: RSS less what the allocator holds free (a leak grows the heap
/// in use, and so this), the lowest of the last third after the warm-up within 5 % of the
/// highest of the first.
Check rssNotGrowing(const std::vector<SoakSample>& after) {
    const double t0 = after.front().t, third = (after.back().t - t0) / 3.0;
    double firstHigh = 0.0, lastLow = 1e300;
    for (const auto& s : after) {
        const double used = s.rss - s.heapFree;
        if (s.t <= t0 + third) firstHigh = std::max(firstHigh, used);
        if (s.t >= t0 + 2.0 * third) lastLow = std::min(lastLow, used);
    }
    char text[240];
    std::snprintf(text, sizeof text,
                  "RSS less the allocator's free memory: lowest of the last third %.1f MB, highest of the first %.1f MB (bound +%.0f %%; "
                  "flatness of RSS needs a run of %.0f s or more)",
                  lastLow, firstHigh, 100.0 * kFlatWithin, kRssSettleSeconds);
    return {"RSS not growing", lastLow <= firstHigh * (1.0 + kFlatWithin), text};
}

Check noGrowth(const SoakSample& warm, const SoakSample& end, const char* name, int SoakSample::*field) {
    char text[96];
    std::snprintf(text, sizeof text, "%d after the warm-up, %d at the end", warm.*field, end.*field);
    return {std::string("no more ") + name, end.*field <= warm.*field, text};
}

/// The p99 of the frames of each later quarter against the second quarter's.
/// The p99 of the frames of each third after the warm-up against the first third's.
Check steadyP99(const std::vector<double>& frameMs, const std::vector<double>& frameT, double warmUp, double total) {
    std::vector<double> p99(3, 0.0);
    const double third = (total - warmUp) / 3.0;
    for (int q = 0; q < 3; ++q) {
        std::vector<double> in;
        for (size_t i = 0; i < frameMs.size(); ++i)
            if (frameT[i] >= warmUp + q * third && frameT[i] < warmUp + (q + 1) * third + 1e-9) in.push_back(frameMs[i]);
        p99[size_t(q)] = in.empty() ? 0.0 : percentile(in, 0.99);
    }
    const double worst = std::max(p99[1], p99[2]);
    char text[160];
    std::snprintf(text, sizeof text, "p99 %.1f / %.1f / %.1f ms in each third after the warm-up (bound %.1fx the first)", p99[0],
                  p99[1], p99[2], kP99Ratio);
    return {"frame-time p99 steady", p99[0] > 0 && worst <= kP99Ratio * p99[0], text};
}

void printSample(const char* label, const SoakSample& s) {
    std::printf("%-5s %8.1f %7ld %9.1f %9.1f %9.1f %9.1f %7d %5d %8.1f %8.1f\n", label, s.t, s.frames, s.rss, s.layersGpu,
                s.layersCache, s.deviceReserved, s.threads, s.fds, s.p50, s.p99);
}

nlohmann::json sampleJson(const SoakSample& s) {
    return {{"t", s.t},       {"frames", s.frames},   {"rss_mb", s.rss}, {"layers_gpu_mb", s.layersGpu},
            {"layers_cache_mb", s.layersCache},        {"device_reserved_mb", s.deviceReserved}, {"gdal_cache_mb", s.gdalCache},
            {"heap_in_use_mb", s.heapInUse}, {"heap_free_mb", s.heapFree},
            {"threads", s.threads}, {"fds", s.fds}, {"frame_p50_ms", s.p50}, {"frame_p99_ms", s.p99}};
}

int writeTimelinePlot(const std::string& file, const std::vector<SoakSample>& samples) {
    std::vector<PlotSeries> panels(7);
    panels[0].title = "RSS (MB)";
    panels[6].title = "heap in use (MB)";
    panels[1].title = "layers GPU memory (MB)";
    panels[2].title = "layers caches (MB)";
    panels[3].title = "device memory reserved (MB)";
    panels[4].title = "threads + descriptors";
    panels[5].title = "frame time p99 (ms)";
    for (const auto& s : samples) {
        const double minutes = s.t / 60.0;
        panels[0].points.push_back({minutes, s.rss});
        panels[1].points.push_back({minutes, s.layersGpu});
        panels[2].points.push_back({minutes, s.layersCache});
        panels[3].points.push_back({minutes, s.deviceReserved});
        panels[4].points.push_back({minutes, double(s.threads + s.fds)});
        if (s.frames > 0 && s.p99 > 0) panels[5].points.push_back({minutes, s.p99});
        panels[6].points.push_back({minutes, s.heapInUse});
    }
    if (auto ok = writePng(file, plotPanels(panels, "minutes")); !ok) return badInput(ok.message());
    return kOk;
}

/// Wall seconds for the scene's time to go round once when it loops (0 when it does not).
double timeLoopSeconds(const scene::TimeServer& time) {
    if (!time.loop() || time.rate() <= 0.0 || time.end() <= time.start()) return 0.0;
    return double(time.end() - time.start()) * 1e-9 / time.rate();
}

}  // namespace

int soakBench(const Args& args, GpuSession& gpu, scene::Scene& scene, render::Renderer& renderer,
              const std::optional<scene::CameraPath>& path, double seconds) {
    const double interval = std::max(1.0, seconds / 100.0);
    scene.time().play();
    std::vector<SoakSample> samples;
    std::vector<double> window, frameMs, frameT;
    const auto start = std::chrono::steady_clock::now();
    const auto since = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    samples.push_back(takeSample(0.0, 0, scene, *gpu.device, window));
    long frames = 0;
    double last = 0.0, nextSample = interval;
    for (double now = 0.0; now < seconds; now = since()) {
        const auto t0 = std::chrono::steady_clock::now();
        scene.time().advance(frames == 0 ? 0.0 : now - last);
        last = now;
        if (path) {
            const double along = path->duration() > 0 ? std::fmod(now, path->duration()) : 0.0;
            scene.camera().setPose(scene.keptAboveGround(globe::poseFromViewpoint(path->at(path->startTime() + along))));
        }
        renderer.render(scene, /*readback=*/false);
        const double ms = millisecondsSince(t0);
        ++frames;
        window.push_back(ms);
        frameMs.push_back(ms);
        frameT.push_back(now);
        if (since() >= nextSample) {
            samples.push_back(takeSample(since(), frames, scene, *gpu.device, window));
            nextSample += interval;
        }
    }
    if (!window.empty() || samples.size() < 2) samples.push_back(takeSample(since(), frames, scene, *gpu.device, window));
    const double total = samples.back().t;

    // The bounds, over the samples after the warm-up: by then the camera has flown its path once
    // and the scene's time has gone round once, so every view the run shows has been shown.
    const double warmUp = std::max({kWarmUpFraction * total, path ? path->duration() : 0.0, timeLoopSeconds(scene.time())});
    std::vector<SoakSample> after;
    for (const auto& s : samples)
        if (s.t >= warmUp) after.push_back(s);
    if (after.size() < 2) {
        std::fprintf(stderr, "orbis: --soak %.0f is too short: the first loop of the camera path and of the scene's time (%.0f s) leaves nothing to check\n",
                     seconds, warmUp);
        return kBadInput;
    }
    const SoakSample& warm = after.front();
    std::vector<Check> checks{total >= kRssSettleSeconds ? flat(after, "RSS", &SoakSample::rss) : rssNotGrowing(after), flat(after, "layers' GPU memory", &SoakSample::layersGpu),
                              flat(after, "layers' caches", &SoakSample::layersCache),
                              flat(after, "device memory reserved", &SoakSample::deviceReserved),
                              noGrowth(warm, samples.back(), "threads", &SoakSample::threads),
                              noGrowth(warm, samples.back(), "descriptors", &SoakSample::fds),
                              steadyP99(frameMs, frameT, warmUp, total)};
    const int validation = gpu.instance->validationMessages();
    checks.push_back({"no validation message", validation == 0,
                      gpu.instance->validationEnabled() ? std::to_string(validation) + " message(s)" : "validation off"});

    const gpu::PhysicalDeviceInfo& info = gpu.device->info();
    const std::string plotFile = args.value("--plot").value_or("orbis-soak.png");
    if (const int plotted = writeTimelinePlot(plotFile, samples); plotted != kOk) return plotted;
    if (args.flag("--json")) {
        nlohmann::json out;
        out["scene"] = args.positional()[0];
        out["device"] = {{"name", info.name}, {"type", info.type}, {"driver", info.driverInfo}};
        out["seconds"] = total;
        out["frames"] = frames;
        out["frame_ms"] = toJson(summarize(frameMs));
        for (const auto& s : samples) out["samples"].push_back(sampleJson(s));
        for (double f : {0.0, 0.25, 0.5, 0.75, 1.0}) out["at"][std::to_string(int(f * 100)) + "%"] = sampleJson(at(samples, f));
        for (const auto& c : checks) out["checks"].push_back({{"name", c.name}, {"ok", c.ok}, {"detail", c.detail}});
        for (const auto& r : scene.resources()) out["layers"][r.name] = r.layer->status();
        out["plot"] = plotFile;
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        std::printf("orbis bench %s --soak %.0f  %ld frames in %.1f s  device: %s (%s)\n", args.positional()[0].c_str(),
                    seconds, frames, total, info.name.c_str(), info.type.c_str());
        std::printf("%-5s %8s %7s %9s %9s %9s %9s %7s %5s %8s %8s\n", "at", "s", "frames", "RSS MB", "GPU MB", "cache MB",
                    "dev MB", "threads", "fds", "p50 ms", "p99 ms");
        for (double f : {0.0, 0.25, 0.5, 0.75, 1.0}) printSample((std::to_string(int(f * 100)) + "%").c_str(), at(samples, f));
        for (const auto& r : scene.resources())
            if (auto status = r.layer->status(); !status.empty()) std::printf("layer %s: %s\n", r.name.c_str(), status.c_str());
        for (const auto& c : checks) std::printf("%-4s %-26s %s\n", c.ok ? "ok" : "FAIL", c.name.c_str(), c.detail.c_str());
        std::printf("plot: %s\n", plotFile.c_str());
    }
    int failed = 0;
    for (const auto& c : checks)
        if (!c.ok) {
            std::fprintf(stderr, "orbis: soak of %s: %s: %s\n", args.positional()[0].c_str(), c.name.c_str(), c.detail.c_str());
            ++failed;
        }
    return failed ? kBadInput : kOk;
}

}  // namespace orbis::cli
