// orbis bench SCENE --sweep K=v1,v2,...: error against run time over the values of a quality
// knob. For each value: wait for the data, time the frames, and compare the image with the
// first value's (the reference).
#include "tools/orbis/BenchModes.h"

#include "base/Log.h"
#include "base/Png.h"
#include "tools/orbis/BenchStats.h"
#include "tools/orbis/Plot.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

namespace orbis::cli {
namespace {

struct SweepSpec {
    std::string name;             // the knob: a LayerSetting's name
    std::vector<double> values;   // the first is the reference
};

struct SweepRow {
    double value, loadMs, frameMs, gpuMs, cpuMs, rmse, psnr;
    uint64_t items;
};

/// "NAME=v1,v2,..." with at least two values. Throws UsageError.
SweepSpec parseSweep(const std::string& spec) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError{"--sweep expects NAME=v1,v2,... got '" + spec + "'"};
    SweepSpec out{spec.substr(0, eq), numberList("--sweep", spec.substr(eq + 1))};
    if (out.values.size() < 2) throw UsageError{"--sweep needs at least two values (the first is the reference)"};
    return out;
}

/// Root-mean-square difference over the RGB channels, in 0..255 units.
double rmse(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    double sum = 0.0;
    size_t n = 0;
    for (size_t i = 0; i + 3 < a.size() && i + 3 < b.size(); i += 4)
        for (size_t c = 0; c < 3; ++c, ++n) {
            const double d = double(a[i + c]) - double(b[i + c]);
            sum += d * d;
        }
    return n ? std::sqrt(sum / double(n)) : 0.0;
}

double psnr(double rmseValue) { return rmseValue > 0.0 ? 20.0 * std::log10(255.0 / rmseValue) : INFINITY; }

/// The row of the value just set: its data loaded, its frames timed, its image against the
/// reference (which the first call takes).
SweepRow measureValue(render::Renderer& renderer, scene::Scene& scene, double value, long frames, long warmup,
                      std::vector<uint8_t>& reference) {
    scene.time().advance(0.0);
    const auto start = std::chrono::steady_clock::now();
    renderer.settle(scene, 600.0);
    const double loadMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const FrameTimes times = timeFrames(renderer, scene, frames, warmup);
    const auto frame = renderer.render(scene, true);
    const std::vector<uint8_t> pixels = renderer.readPixels(frame);
    if (reference.empty()) reference = pixels;
    const double e = rmse(reference, pixels);
    return {value, loadMs, summarize(times.wall).median, summarize(times.gpuTotal).median, summarize(times.cpu).median, e,
            psnr(e), itemsDrawn(scene)};
}

void printJson(const Args& args, const gpu::PhysicalDeviceInfo& info, const render::Renderer& renderer,
               const std::string& name, const std::vector<SweepRow>& rows) {
    nlohmann::json out;
    out["scene"] = args.positional()[0];
    out["device"] = {{"name", info.name}, {"type", info.type}};
    out["size"] = {renderer.width(), renderer.height()};
    out["parameter"] = name;
    for (const auto& r : rows)
        out["rows"].push_back({{"value", r.value}, {"load_ms", r.loadMs}, {"frame_ms", r.frameMs}, {"gpu_ms", r.gpuMs}, {"cpu_ms", r.cpuMs},
                               {"items", r.items}, {"rmse", r.rmse}, {"psnr", std::isfinite(r.psnr) ? r.psnr : 999.0}});
    std::printf("%s\n", out.dump(2).c_str());
}

void printTable(const Args& args, const gpu::PhysicalDeviceInfo& info, const render::Renderer& renderer,
                const std::string& name, long frames, const std::vector<SweepRow>& rows) {
    std::printf("orbis bench %s --sweep %s  %ux%u  %ld frames each  device: %s (%s)\n", args.positional()[0].c_str(),
                name.c_str(), renderer.width(), renderer.height(), frames, info.name.c_str(), info.type.c_str());
    std::printf("%-12s %10s %12s %10s %10s %8s %10s %10s\n", name.substr(0, 12).c_str(), "load ms", "frame ms", "gpu ms", "cpu ms",
                "items", "RMSE", "PSNR dB");
    for (const auto& r : rows)
        std::printf("%-12g %10.0f %12.2f %10.2f %10.2f %8llu %10.3f %10.2f\n", r.value, r.loadMs, r.frameMs, r.gpuMs, r.cpuMs,
                    static_cast<unsigned long long>(r.items), r.rmse, r.psnr);
    std::printf("(medians; load: from setting the value until its data is in; error against the first value's image, in 0..255 units)\n");
}

/// The PNG plot of RMSE against ms per frame (--plot); kOk, or kBadInput when it cannot be written.
int writePlot(const Args& args, const SweepSpec& sweep, const std::vector<SweepRow>& rows) {
    std::vector<PlotPoint> points;
    for (const auto& r : rows) {
        char label[32];
        std::snprintf(label, sizeof label, "%g", r.value);
        points.push_back({r.frameMs, r.rmse, label});
    }
    // The curve runs from the fastest setting to the slowest, whatever order they were given in.
    std::stable_sort(points.begin(), points.end(), [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
    const std::string plotFile = args.value("--plot").value_or("orbis-sweep.png");
    if (auto ok = writePng(plotFile, plotPoints(points)); !ok) return badInput(ok.message());
    log::info("wrote the plot ", plotFile, " (x: ms per frame, y: RMSE against ", sweep.name, "=", sweep.values.front(),
              ")");
    return kOk;
}

}  // namespace

bool setOnVisibleLayers(scene::Scene& scene, const std::string& name, double value) {
    bool known = false;
    for (auto& r : scene.resources())
        if (scene::LiveSettings* live = r.layer->asLiveSettings(); live && r.visible)
            known = live->setParameter(name, value) || known;
    return known;
}

int applySetOptions(const Args& args, scene::Scene& scene) {
    for (const std::string& spec : args.values("--set")) {
        const auto eq = spec.find('=');
        if (eq == std::string::npos || eq == 0) throw UsageError{"--set expects NAME=VALUE, got '" + spec + "'"};
        const std::vector<double> value = numberList("--set", spec.substr(eq + 1));
        if (value.size() != 1) throw UsageError{"--set expects one number after '=', got '" + spec + "'"};
        if (!setOnVisibleLayers(scene, spec.substr(0, eq), value[0])) {
            std::fprintf(stderr, "orbis: no visible layer of %s takes %s\n", args.positional()[0].c_str(), spec.c_str());
            return kBadInput;
        }
    }
    return kOk;
}

namespace {

/// `--reference K=V` settings: each with the value the visible layers had before (the first
/// layer that lists it), to put back after the reference row.
struct ReferenceSetting {
    std::string name;
    double value, before;
};

std::vector<ReferenceSetting> parseReferenceSettings(const Args& args, scene::Scene& scene) {
    std::vector<ReferenceSetting> out;
    for (const std::string& spec : args.values("--reference")) {
        const auto eq = spec.find('=');
        if (eq == std::string::npos || eq == 0) throw UsageError{"--reference expects NAME=VALUE, got '" + spec + "'"};
        const std::vector<double> value = numberList("--reference", spec.substr(eq + 1));
        if (value.size() != 1) throw UsageError{"--reference expects one number after '=', got '" + spec + "'"};
        const std::string name = spec.substr(0, eq);
        std::optional<double> before;
        for (auto& r : scene.resources())
            if (const scene::LiveSettings* live = r.layer->asLiveSettings(); live && r.visible && !before)
                for (const scene::LayerSetting& setting : live->liveSettings())
                    if (setting.name == name) before = setting.value;
        if (!before) throw UsageError{"--reference " + spec + ": no visible layer lists a setting '" + name + "'"};
        out.push_back({name, value[0], *before});
    }
    return out;
}

}  // namespace

int sweepBench(const Args& args, GpuSession& gpu, scene::Scene& scene, render::Renderer& renderer, long frames,
               long warmup) {
    const SweepSpec sweep = parseSweep(*args.value("--sweep"));
    const std::vector<ReferenceSetting> referenceSettings = parseReferenceSettings(args, scene);
    for (const ReferenceSetting& r : referenceSettings)
        if (r.name == sweep.name) throw UsageError{"--reference " + r.name + ": that is the swept setting (its first value is the reference's)"};
    std::vector<SweepRow> rows;
    std::vector<uint8_t> reference;
    for (size_t i = 0; i < sweep.values.size(); ++i) {
        const double v = sweep.values[i];
        if (!setOnVisibleLayers(scene, sweep.name, v)) {
            std::fprintf(stderr, "orbis: no visible layer of %s has a parameter '%s'\n", args.positional()[0].c_str(),
                         sweep.name.c_str());
            return kBadInput;
        }
        // The reference row alone has the --reference settings (e.g. full-resolution rays).
        for (const ReferenceSetting& r : referenceSettings)
            if (!setOnVisibleLayers(scene, r.name, i == 0 ? r.value : r.before)) {
                std::fprintf(stderr, "orbis: no visible layer of %s takes %s=%g\n", args.positional()[0].c_str(),
                             r.name.c_str(), i == 0 ? r.value : r.before);
                return kBadInput;
            }
        rows.push_back(measureValue(renderer, scene, v, frames, warmup, reference));
    }
    const auto& info = gpu.device->info();
    if (args.flag("--json")) printJson(args, info, renderer, sweep.name, rows);
    else printTable(args, info, renderer, sweep.name, frames, rows);
    if (const int plotted = writePlot(args, sweep, rows); plotted != kOk) return plotted;
    return validationExitCode(gpu);
}

}  // namespace orbis::cli
