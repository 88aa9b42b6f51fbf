// orbis bench --labels N: label placement (layers/vector/LabelPlacement.h) on the CPU, no GPU:
// N candidate labels (text-sized boxes, priorities spread like city populations) over a
// 1920x1080 screen and a tenth beyond each edge, panned 0.5 px a frame for --frames frames
// (default 300): milliseconds per frame (min, median, p95), labels placed, and how many labels
// appeared or went per frame while the view moved (the flicker the hysteresis holds down).
#include "tools/orbis/BenchModes.h"
#include "tools/orbis/BenchStats.h"

#include "layers/vector/LabelPlacement.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <unordered_set>
#include <vector>

namespace orbis::cli {
namespace {

std::vector<vector::LabelCandidate> syntheticLabels(long count) {
    std::mt19937_64 rng(20261202);
    std::uniform_real_distribution<double> x(-192.0, 2112.0), y(-108.0, 1188.0), chars(3.0, 18.0), unit(0.0, 1.0);
    std::vector<vector::LabelCandidate> out(static_cast<size_t>(count));
    for (size_t i = 0; i < out.size(); ++i) {
        const double w = 7.0 * chars(rng) + 16.0, h = 18.0;   // glyphs, icon and halo
        const glm::dvec2 at{x(rng), y(rng)};
        out[i] = {.id = i, .priority = std::pow(unit(rng), 4.0) * 1e7, .min = at, .max = at + glm::dvec2(w, h)};
    }
    return out;
}

}  // namespace

int labelBench(long count, long frames, double marginPx) {
    auto labels = syntheticLabels(count);
    const vector::LabelPlacementOptions options{.screen = {1920.0, 1080.0}, .marginPx = marginPx};
    vector::LabelPlacer placer;
    std::vector<double> ms, placed, changes;
    std::unordered_set<uint64_t> before;
    for (long f = 0; f < frames; ++f) {
        for (auto& l : labels) {
            l.min += glm::dvec2(0.5, 0.25);
            l.max += glm::dvec2(0.5, 0.25);
        }
        const auto t0 = std::chrono::steady_clock::now();
        const auto chosen = placer.place(labels, options);
        ms.push_back(millisecondsSince(t0));
        std::unordered_set<uint64_t> now;
        for (uint32_t i : chosen) now.insert(labels[i].id);
        if (f > 0) {
            size_t changed = 0;
            for (uint64_t id : now) changed += before.count(id) ? 0 : 1;
            for (uint64_t id : before) changed += now.count(id) ? 0 : 1;
            changes.push_back(double(changed));
        }
        placed.push_back(double(chosen.size()));
        before = std::move(now);
    }
    std::printf("orbis bench --labels %ld  (CPU only, one thread; 1920x1080, panned 0.5 px a frame, margin %.1f px)\n", count,
                marginPx);
    std::printf("%-28s %10s %10s %10s\n", "", "min", "median", "p95");
    const auto row = [](const char* name, const char* format, const std::vector<double>& values) {
        const Stats s = summarize(values);
        std::printf(format, name, s.min, s.median, s.p95);
    };
    row("placement ms/frame", "%-28s %10.3f %10.3f %10.3f\n", ms);
    row("labels placed", "%-28s %10.0f %10.0f %10.0f\n", placed);
    row("labels in or out per frame", "%-28s %10.0f %10.0f %10.0f\n", changes);
    return kOk;
}

}  // namespace orbis::cli
