// orbis bench SCENE --live N --update SQL: the latency from a committed change to the frame
// that shows it, for a scene with a live vector layer ("refresh": {"listen": ...}). N times:
// the view settles, a frame is read back, SQL runs on its own connection (libpq, autocommit:
// committed when it returns; "{i}" in it is the run's number, from 0), then frames are
// rendered and read back until one differs from the frame before the change (or 10 s pass).
// The latency is from the commit to the end of that frame's readback; frames are rendered
// back to back, so it includes up to one frame of waiting. Prints the median, p95 and max, the
// frames per change, and the frame time then.
#include "layers/vector/PgListener.h"
#include "layers/vector/VectorLayer.h"
#include "tools/orbis/BenchModes.h"
#include "tools/orbis/BenchStats.h"

#include <libpq-fe.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace orbis::cli {
namespace {

std::vector<uint8_t> frameOf(render::Renderer& renderer, scene::Scene& scene) {
    scene.time().advance(0.0);
    return renderer.readPixels(renderer.render(scene, true));
}

std::string replaced(std::string sql, const std::string& key, const std::string& value) {
    for (size_t at = sql.find(key); at != std::string::npos; at = sql.find(key, at + value.size())) sql.replace(at, key.size(), value);
    return sql;
}

}  // namespace

int liveBench(const Args& args, GpuSession& gpu, scene::Scene& scene, render::Renderer& renderer, long runs) {
    const auto update = args.value("--update");
    if (!update) throw UsageError{"bench --live needs --update SQL (the change to time; {i} is the run's number)"};
    const layers::VectorLayer* live = nullptr;
    for (const auto& r : scene.resources())
        if (const auto* v = dynamic_cast<const layers::VectorLayer*>(r.layer.get()); v && r.visible && v->hasListener()) live = v;
    if (!live) {
        std::fprintf(stderr, "orbis: bench --live: the scene has no visible vector layer with \"refresh\": {\"listen\": ...}\n");
        return kBadInput;
    }
    renderer.settle(scene, 120.0);
    auto connection = vector::libpqConnection(live->source());
    if (!connection) {
        std::fprintf(stderr, "orbis: bench --live: %s\n", connection.message().c_str());
        return kBadInput;
    }
    PGconn* c = PQconnectdb(connection->c_str());
    if (PQstatus(c) != CONNECTION_OK) {
        std::fprintf(stderr, "orbis: bench --live: cannot connect: %s", PQerrorMessage(c));
        PQfinish(c);
        return kBadInput;
    }
    for (int i = 0; i < 200 && live->listener() && !live->listener()->listening(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(25));
    std::vector<double> latency, framesPer, frameMs;
    long missed = 0;
    for (long i = 0; i < runs; ++i) {
        renderer.settle(scene, 30.0);
        const std::vector<uint8_t> before = frameOf(renderer, scene);
        PGresult* r = PQexec(c, replaced(*update, "{i}", std::to_string(i)).c_str());
        const auto committed = std::chrono::steady_clock::now();
        const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK || PQresultStatus(r) == PGRES_TUPLES_OK;
        PQclear(r);
        if (!ok) {
            std::fprintf(stderr, "orbis: bench --live: the update failed: %s", PQerrorMessage(c));
            PQfinish(c);
            return kBadInput;
        }
        long frames = 0;
        bool seen = false;
        while (!seen && millisecondsSince(committed) < 10000.0) {
            const auto t0 = std::chrono::steady_clock::now();
            seen = frameOf(renderer, scene) != before;
            frameMs.push_back(millisecondsSince(t0));
            ++frames;
        }
        if (!seen) {
            ++missed;
            continue;
        }
        latency.push_back(millisecondsSince(committed));
        framesPer.push_back(double(frames));
    }
    PQfinish(c);
    const Stats l = summarize(latency), f = summarize(frameMs), n = summarize(framesPer);
    std::printf("device      %s\n", gpu.device->info().name.c_str());
    std::printf("changes     %ld (%ld not seen within 10 s)\n", runs, missed);
    std::printf("latency ms  median %.1f  p95 %.1f  max %.1f  min %.1f   (commit to the changed frame read back)\n", l.median,
                l.p95, latency.empty() ? 0.0 : *std::max_element(latency.begin(), latency.end()), l.min);
    std::printf("frames      median %.0f per change; frame %.1f ms median, %.1f p95 (%ux%u)\n", n.median, f.median, f.p95,
                renderer.width(), renderer.height());
    return missed > 0 ? 1 : validationExitCode(gpu);
}

}  // namespace orbis::cli
