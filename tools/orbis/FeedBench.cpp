// orbis bench SCENE --feeds SECONDS: for a scene with live FMV layers ("url"), whose senders
// stamp each packet with the wall clock (orbis-make-fmv --stream ... --wall-clock): frames are
// rendered back to back for SECONDS; after each (the GPU done: the frame is on screen), every
// feed whose video frame changed adds a glass-to-drape latency: now minus the frame's KLV time
// stamp (its send time). Prints per feed and for all: latency median, p95 and max; video frames
// draped per second; footprint updates per second; frames lost and damaged packets (LiveVideo's
// counts); and the frame time over the run.
#include "layers/fmv/FmvLayer.h"
#include "tools/orbis/BenchModes.h"
#include "tools/orbis/BenchStats.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace orbis::cli {

int feedBench(GpuSession& gpu, scene::Scene& scene, render::Renderer& renderer, double seconds) {
    struct Feed {
        std::string name;
        const layers::FmvLayer* layer = nullptr;
        uint64_t lastSerial = 0, footprints0 = 0;
        std::vector<double> latency;
        uint64_t draped = 0;
    };
    std::vector<Feed> feeds;
    for (const auto& r : scene.resources())
        if (const auto* f = dynamic_cast<const layers::FmvLayer*>(r.layer.get()); f && r.visible && f->isLive())
            feeds.push_back({r.name, f});
    if (feeds.empty()) {
        std::fprintf(stderr, "orbis: bench --feeds: the scene has no visible live fmv layer (\"url\")\n");
        return kBadInput;
    }
    renderer.settle(scene, 30.0);   // connected, first frames shown
    for (Feed& f : feeds) {
        f.footprints0 = f.layer->footprintUpdates();
        f.lastSerial = f.layer->liveFrame() ? f.layer->liveFrame()->index : 0;
    }
    std::vector<double> frameMs;
    const auto start = std::chrono::steady_clock::now();
    while (millisecondsSince(start) < seconds * 1000.0) {
        const auto t0 = std::chrono::steady_clock::now();
        scene.time().advance(0.0);
        const render::FrameResult r = renderer.render(scene, false);
        gpu.device->wait(r.timelineValue);
        frameMs.push_back(millisecondsSince(t0));
        const double now = fmv::wallClockSeconds();
        for (Feed& f : feeds) {
            const fmv::VideoFrame* v = f.layer->liveFrame();
            if (!v || v->index == f.lastSerial) continue;
            f.lastSerial = v->index;
            ++f.draped;
            if (const auto utc = f.layer->liveFrameUtc(); utc && fmv::plausibleLatency(now - *utc)) f.latency.push_back((now - *utc) * 1e3);
        }
    }
    const double elapsed = millisecondsSince(start) * 1e-3;
    std::printf("device      %s\n", gpu.device->info().name.c_str());
    std::printf("run         %.1f s, %zu frames at %ux%u: frame %.1f ms median, %.1f p95\n", elapsed, frameMs.size(), renderer.width(),
                renderer.height(), summarize(frameMs).median, summarize(frameMs).p95);
    std::vector<double> all;
    for (const Feed& f : feeds) {
        const fmv::LiveStats& s = f.layer->liveStats();
        const Stats l = summarize(f.latency);
        std::printf("%-10s  latency ms median %.1f  p95 %.1f  max %.1f (%zu frames)   draped %.1f/s  footprint %.1f/s   lost %llu  "
                    "damaged %llu  gaps %llu  klv rejected %llu  %s\n",
                    f.name.c_str(), l.median, l.p95, f.latency.empty() ? 0.0 : *std::max_element(f.latency.begin(), f.latency.end()),
                    f.latency.size(), double(f.draped) / elapsed, double(f.layer->footprintUpdates() - f.footprints0) / elapsed,
                    (unsigned long long)s.framesLost, (unsigned long long)(s.framesDamaged + s.corruptPackets), (unsigned long long)s.continuityGaps,
                    (unsigned long long)s.klvRejected,
                    fmv::toString(s.state));
        all.insert(all.end(), f.latency.begin(), f.latency.end());
    }
    if (feeds.size() > 1) {
        const Stats l = summarize(all);
        std::printf("all feeds   latency ms median %.1f  p95 %.1f (%zu frames)\n", l.median, l.p95, all.size());
    }
    if (all.empty()) std::printf("no latency: the senders' packets carry no wall-clock time stamps (orbis-make-fmv --wall-clock)\n");
    return validationExitCode(gpu);
}

}  // namespace orbis::cli
