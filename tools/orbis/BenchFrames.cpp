#include "tools/orbis/BenchFrames.h"

#include "globe/Viewpoint.h"
#include "tools/orbis/BenchStats.h"

#include <chrono>

namespace orbis::cli {
namespace {

// Virtual time moves by a fixed 1/60 s per frame, so runs are repeatable.
constexpr double kFrameSeconds = 1.0 / 60.0;

/// The camera of frame `i`: the measured frames sweep the whole path; warm-up frames stay at
/// its start.
void followPath(scene::Scene& scene, const scene::CameraPath& path, long i, long frames, long warmup) {
    const double f = i < warmup || frames < 2 ? 0.0 : double(i - warmup) / double(frames - 1);
    scene.camera().setPose(
        scene.keptAboveGround(globe::poseFromViewpoint(path.at(path.startTime() + f * path.duration()))));
}

/// Records measured frame `done` (1-based) of `frames`.
void record(FrameSeries& s, const render::FrameResult& frame, double wallMs, const std::vector<gpu::PassTime>& times,
            const scene::Scene& scene, gpu::Device& device, long done, long frames) {
    s.cpu.push_back(frame.cpuMs);
    s.wall.push_back(wallMs);
    s.items.push_back(double(itemsDrawn(scene)));
    s.memory.afterFrame(scene, device, done, frames);
    for (const auto& p : times) {
        if (!s.passes.count(p.name)) s.passOrder.push_back(p.name);
        s.passes[p.name].push_back(p.ms);
    }
    s.gpuTotal.push_back(gpuTotalMs(times));
}

}  // namespace

LoadTimes settleTimed(render::Renderer& renderer, scene::Scene& scene) {
    LoadTimes load;
    const auto start = std::chrono::steady_clock::now();
    const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    renderer.settle(scene, 600.0, [&] {
        if (load.firstContentS < 0.0 && itemsDrawn(scene) > 0) load.firstContentS = seconds();
    });
    load.settledS = seconds();
    return load;
}

FrameSeries measureFrames(render::Renderer& renderer, scene::Scene& scene, gpu::Device& device,
                          const std::optional<scene::CameraPath>& path, long frames, long warmup) {
    FrameSeries series;
    for (long i = 0; i < warmup + frames; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        scene.time().advance(i == 0 ? 0.0 : kFrameSeconds);
        if (path) followPath(scene, *path, i, frames, warmup);
        const auto frame = renderer.render(scene, /*readback=*/false);
        const auto times = renderer.gpuTimes(frame);
        const double ms = millisecondsSince(t0);
        if (i < warmup) continue;
        record(series, frame, ms, times, scene, device, i - warmup + 1, frames);
    }
    return series;
}

}  // namespace orbis::cli
