// orbis bench SCENE: frame time statistics, CPU and GPU per pass.
#include "tools/orbis/Commands.h"

#include "engine/core/Log.h"
#include "tools/orbis/Session.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

namespace orbis::cli {

namespace {
const char* kHelp =
    "usage: orbis bench SCENE [options]\n"
    "Renders SCENE repeatedly and reports frame times: CPU (update + record + submit), whole frame\n"
    "(until the GPU is done) and GPU time per pass, as min / median / p95 in milliseconds.\n"
    "  --frames N         frames measured (default 100)\n"
    "  --warmup N         frames rendered first and not measured (default 5)\n"
    "  --size WxH         image size (default 1920x1080)\n"
    "  --time T           virtual time: ISO-8601 or seconds after the scene start\n"
    "  --json             print JSON instead of a table\n";

struct Stats {
    double min = 0, median = 0, p95 = 0, mean = 0;
};

Stats summarize(std::vector<double> v) {
    Stats s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s.min = v.front();
    s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    s.p95 = v[std::min(v.size() - 1, static_cast<size_t>(0.95 * double(v.size() - 1) + 0.5))];
    for (double x : v) s.mean += x;
    s.mean /= double(v.size());
    return s;
}

nlohmann::json toJson(const Stats& s) {
    return {{"min", s.min}, {"median", s.median}, {"p95", s.p95}, {"mean", s.mean}};
}
}  // namespace

int benchCommand(const std::vector<std::string>& argv) {
    std::set<std::string> valued = gpuValuedOptions();
    valued.insert({"--frames", "--warmup", "--size", "--time"});
    std::set<std::string> flags = gpuFlagOptions();
    flags.insert({"--help", "--json"});
    Args args(argv, valued, flags, {{"-h", "--help"}});
    if (args.flag("--help")) {
        std::printf("%s%s", kHelp, gpuOptionsHelp().c_str());
        return kOk;
    }
    if (args.positional().size() != 1) throw UsageError{"bench expects exactly one SCENE file"};
    const long frames = args.integer("--frames", 1, 1000000).value_or(100);
    const long warmup = args.integer("--warmup", 0, 1000000).value_or(5);
    const auto [width, height] = args.size("--size").value_or(std::make_pair(1920u, 1080u));

    auto loaded = loadSceneForCommand(args);
    if (!loaded) return kBadInput;
    GpuSession gpu = openGpu(args);
    std::unique_ptr<scene::Scene> scene = std::move(loaded).value();
    render::Renderer renderer(*gpu.device, width, height);

    std::vector<double> cpu, wall, gpuTotal;
    std::map<std::string, std::vector<double>> passes;
    std::vector<std::string> passOrder;
    // Virtual time moves by a fixed 1/60 s per frame, so runs are repeatable.
    constexpr double kFrameSeconds = 1.0 / 60.0;
    for (long i = 0; i < warmup + frames; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        scene->time().advance(i == 0 ? 0.0 : kFrameSeconds);
        const auto frame = renderer.render(*scene, /*readback=*/false);
        const auto times = renderer.gpuTimes(frame);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (i < warmup) continue;
        cpu.push_back(frame.cpuMs);
        wall.push_back(ms);
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
        for (const auto& name : passOrder) row("gpu " + name, summarize(passes[name]));
    }
    return validationExitCode(gpu);
}

}  // namespace orbis::cli
