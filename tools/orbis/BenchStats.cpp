#include "tools/orbis/BenchStats.h"

#include "tools/orbis/Args.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace orbis::cli {

namespace {

/// The nearest-rank q-quantile of sorted, non-empty `v`.
double percentileSorted(const std::vector<double>& v, double q) {
    return v[std::min(v.size() - 1, static_cast<size_t>(q * double(v.size() - 1) + 0.5))];
}

}  // namespace

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return percentileSorted(v, q);
}

Stats summarize(std::vector<double> v) {
    Stats s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s.min = v.front();
    s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    s.p95 = percentileSorted(v, 0.95);
    for (double x : v) s.mean += x;
    s.mean /= double(v.size());
    return s;
}

nlohmann::json toJson(const Stats& s) {
    return {{"min", s.min}, {"median", s.median}, {"p95", s.p95}, {"mean", s.mean}};
}

uint64_t itemsDrawn(const scene::Scene& scene) {
    uint64_t n = 0;
    for (const auto& r : scene.resources())
        if (const scene::LayerStats* stats = r.layer->asStats(); stats && r.visible) n += stats->itemsDrawn();
    return n;
}

std::vector<double> numberList(const std::string& option, const std::string& text) {
    std::vector<double> values;
    for (size_t start = 0; start <= text.size();) {
        const size_t end = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, end - start);
        char* stop = nullptr;
        const double v = std::strtod(item.c_str(), &stop);
        if (item.empty() || *stop != '\0' || !std::isfinite(v)) throw UsageError{option + ": '" + item + "' is not a number"};
        values.push_back(v);
        start = end + 1;
    }
    return values;
}

double millisecondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double gpuTotalMs(const std::vector<gpu::PassTime>& passes) {
    double total = 0.0;
    for (const auto& p : passes) total += p.ms;
    return total;
}

FrameTimes timeFrames(render::Renderer& renderer, scene::Scene& scene, long frames, long warmup) {
    FrameTimes out;
    for (long i = 0; i < warmup + frames; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        const auto frame = renderer.render(scene, false);
        const auto times = renderer.gpuTimes(frame);
        if (i < warmup) continue;
        out.wall.push_back(millisecondsSince(t0));
        out.cpu.push_back(frame.cpuMs);
        out.gpuTotal.push_back(gpuTotalMs(times));
    }
    return out;
}

}  // namespace orbis::cli
