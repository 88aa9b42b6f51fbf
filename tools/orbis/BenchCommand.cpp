// orbis bench SCENE: frame time statistics, CPU and GPU per pass.
#include "tools/orbis/Commands.h"

#include "tools/orbis/BenchFrames.h"
#include "tools/orbis/BenchModes.h"
#include "tools/orbis/BenchStats.h"
#include "tools/orbis/Session.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <thread>

namespace orbis::cli {

namespace {
const char* kHelp =
    "usage: orbis bench SCENE [options]    or    orbis bench --video FILE [--seeks N]    or    orbis bench --poses FILE\n"
    "       or    orbis bench --labels N [--layer] [--frames F] [--margin PX]    or    orbis bench --vector FILE [--level L]\n"
    "Renders SCENE repeatedly and reports frame times: CPU (update + record + submit), whole frame\n"
    "(until the GPU is done) and GPU time per pass, as min / median / p95 in milliseconds. A fixed\n"
    "view is measured after everything it shows has loaded.\n"
    "  --video FILE       FMV on the CPU, no scene: KLV packets/s, playback ms/frame, exact seeks\n"
    "                     (--seeks N random frames, default 50): median and p95\n"
    "  --poses FILE       glTF poses on the CPU, no scene: microseconds per pose of each animation\n"
    "                     (what an animated model layer pays per distinct animation time a frame)\n"
    "  --labels N         label placement on the CPU, no scene: N labels over a panning 1920x1080\n"
    "                     view (--frames, default 300; --margin PX, the hysteresis, default 4): ms/frame,\n"
    "                     labels placed, labels in or out per frame; with --layer, the vector layer's\n"
    "                     whole label step (projection, layout, placement, glyphs) for N labelled points\n"
    "  --vector FILE      vector data on the CPU, no scene: reading it through OGR, triangulating its\n"
    "                     polygons, cutting it into tiles of --level L (default 14); --runs N (default 3)\n"
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
    "  --set K=V          a layer's live setting (as the viewer's panel sets it) on every visible\n"
    "                     layer that has it, before anything is measured; may be repeated\n"
    "  --reference K=V    with --sweep: the reference (the first value) also has this live setting,\n"
    "                     the other values the layer's own (e.g. --set rayResolution=0.5 --reference\n"
    "                     rayResolution=1: reduced rays against a full-resolution reference); may be\n"
    "                     repeated\n"
    "  --plot FILE        with --sweep: the PNG plot of RMSE against ms/frame (default orbis-sweep.png);\n"
    "                     with --soak: the timelines (default orbis-soak.png)\n"
    "  --soak SECONDS     a long run as the viewer plays it (time playing, the camera looping along\n"
    "                     --camera-path): RSS, the layers' GPU memory and caches, device memory,\n"
    "                     threads, descriptors and frame-time p99 sampled through the run; exit 1\n"
    "                     when, after the first quarter, memory is not flat within +-5 %, threads or\n"
    "                     descriptors grew, the p99 rose past 1.5x, or validation spoke\n"
    "  --live N --update SQL  for a scene with a live vector layer (\"refresh\": {\"listen\"}): N times,\n"
    "                     commit SQL ({i}: the run's number) on the layer's database and time until\n"
    "                     a frame read back shows it: median, p95, max (ms)\n"
    "  --feeds SECONDS    for a scene with live FMV layers (\"url\") whose senders stamp packets with the\n"
    "                     wall clock: frames back to back for SECONDS; per feed, the glass-to-drape\n"
    "                     latency (send time to the frame on screen: median, p95, max), video frames\n"
    "                     draped and footprint updates per second, frames lost, damaged packets\n"
    "  --iso-error N1,N2,.. isosurface position error against steps, for a scene with a volume in\n"
    "                     mode \"iso\": for each step count, with and without the secant/bisection\n"
    "                     refinement, ms/frame and the distance in voxels between each pixel's first\n"
    "                     hit and the reference's (refined, 4 x the largest count)\n";

/// What a plain run measured, for its report.
struct FrameReport {
    uint32_t width, height;
    long frames, warmup;
    const FrameSeries& series;
    LoadTimes load;
};

void printJson(const Args& args, const gpu::PhysicalDeviceInfo& info, const FrameReport& r) {
    const FrameSeries& s = r.series;
    nlohmann::json out;
    out["scene"] = args.positional()[0];
    out["device"] = {{"name", info.name}, {"type", info.type}, {"driver", info.driverInfo}};
    out["size"] = {r.width, r.height};
    out["frames"] = r.frames;
    out["warmup"] = r.warmup;
    out["cpu_ms"] = toJson(summarize(s.cpu));
    out["frame_ms"] = toJson(summarize(s.wall));
    out["gpu_ms"]["total"] = toJson(summarize(s.gpuTotal));
    out["items_drawn"] = toJson(summarize(s.items));
    out["memory_mb"] = s.memory.toJson();
    if (auto path = args.value("--camera-path")) out["camera_path"] = *path;
    if (r.load.settledS >= 0.0) out["load_s"] = {{"first_content", r.load.firstContentS}, {"settled", r.load.settledS}};
    for (const auto& name : s.passOrder) out["gpu_ms"]["passes"][name] = toJson(summarize(s.passes.at(name)));
    std::printf("%s\n", out.dump(2).c_str());
}

void printTable(const Args& args, const gpu::PhysicalDeviceInfo& info, const FrameReport& r) {
    const FrameSeries& s = r.series;
    std::printf("orbis bench %s  %ux%u  %ld frames (+%ld warm-up)  device: %s (%s)\n", args.positional()[0].c_str(),
                r.width, r.height, r.frames, r.warmup, info.name.c_str(), info.type.c_str());
    std::printf("%-22s %10s %10s %10s\n", "ms", "min", "median", "p95");
    auto row = [](const std::string& name, const Stats& st) {
        std::printf("%-22s %10.3f %10.3f %10.3f\n", name.c_str(), st.min, st.median, st.p95);
    };
    row("frame (wall)", summarize(s.wall));
    row("cpu", summarize(s.cpu));
    row("gpu total", summarize(s.gpuTotal));
    row("items drawn", summarize(s.items));
    if (r.load.settledS >= 0.0)
        std::printf("loading: first frame with content after %.2f s, everything in view after %.2f s\n",
                    r.load.firstContentS, r.load.settledS);
    s.memory.print();
    for (const auto& name : s.passOrder) row("gpu " + name, summarize(s.passes.at(name)));
}

/// The options of every mode; --help prints kHelp.
Args parseBenchArgs(const std::vector<std::string>& argv) {
    std::set<std::string> valued = gpuValuedOptions();
    valued.insert({"--frames", "--warmup", "--size", "--time", "--camera-path", "--sweep", "--plot", "--tiles", "--threads",
                   "--iso-error", "--video", "--seeks", "--poses", "--labels", "--margin", "--vector", "--level", "--runs",
                   "--soak", "--live", "--update", "--feeds", "--set", "--reference"});
    std::set<std::string> flags = gpuFlagOptions();
    flags.insert({"--help", "--json", "--layer"});
    return Args(argv, valued, flags, {{"-h", "--help"}});
}

/// The modes that need no scene: --video, --poses, --labels, --vector.
std::optional<int> sceneFreeBench(const Args& args) {
    if (auto video = args.value("--video")) {
        if (!args.positional().empty()) throw UsageError{"bench --video takes no SCENE"};
        return videoBench(*video, args.integer("--seeks", 1, 100000).value_or(50));
    }
    if (auto poses = args.value("--poses")) {
        if (!args.positional().empty()) throw UsageError{"bench --poses takes no SCENE"};
        return poseBench(*poses);
    }
    if (auto labels = args.integer("--labels", 1, 10000000)) {
        if (!args.positional().empty()) throw UsageError{"bench --labels takes no SCENE"};
        const long frames = args.integer("--frames", 1, 1000000).value_or(300);
        const double margin = args.number("--margin", 0.0, 1000.0).value_or(4.0);
        return args.flag("--layer") ? labelLayerBench(*labels, frames, margin) : labelBench(*labels, frames, margin);
    }
    if (auto file = args.value("--vector")) {
        if (!args.positional().empty()) throw UsageError{"bench --vector takes no SCENE"};
        return vectorBench(*file, args.integer("--level", 0, 22).value_or(14), args.integer("--runs", 1, 100).value_or(3));
    }
    return std::nullopt;
}

}  // namespace

int benchCommand(const std::vector<std::string>& argv) {
    const Args args = parseBenchArgs(argv);
    if (args.flag("--help")) {
        std::printf("%s%s", kHelp, gpuOptionsHelp().c_str());
        return kOk;
    }
    if (auto exitCode = sceneFreeBench(args)) return *exitCode;
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
    if (const int set = applySetOptions(args, *scene); set != kOk) return set;
    render::Renderer renderer(*gpu.device, width, height);
    if (args.value("--sweep")) return sweepBench(args, gpu, *scene, renderer, frames, warmup);
    if (auto seconds = args.number("--soak", 1.0, 1e6)) return soakBench(args, gpu, *scene, renderer, path, *seconds);
    if (auto runs = args.integer("--live", 1, 100000)) return liveBench(args, gpu, *scene, renderer, *runs);
    if (auto seconds = args.number("--feeds", 1.0, 1e5)) return feedBench(gpu, *scene, renderer, *seconds);

    // A fixed view is measured once everything it shows has loaded; a camera path measures the
    // streaming as it flies.
    const LoadTimes load = path ? LoadTimes{} : settleTimed(renderer, *scene);
    const FrameSeries series = measureFrames(renderer, *scene, *gpu.device, path, frames, warmup);
    const FrameReport report{width, height, frames, warmup, series, load};
    if (args.flag("--json")) printJson(args, gpu.device->info(), report);
    else printTable(args, gpu.device->info(), report);
    return validationExitCode(gpu);
}

}  // namespace orbis::cli
