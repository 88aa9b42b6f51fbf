// orbis bench SCENE --iso-error N1,N2,...: isosurface position error against the step count.
// For each count, with and without the secant/bisection refinement: ms per frame, and the
// distance in voxels between each pixel's first hit and the reference's (refined, 4 x the
// largest count).
#include "tools/orbis/BenchModes.h"

#include "layers/volume/VolumeLayer.h"
#include "tools/orbis/BenchStats.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

namespace orbis::cli {
namespace {

/// Each pixel's first hit of one configuration.
struct Hits {
    std::vector<float> t;              // distance along the pixel's ray; < 0: no hit
    std::vector<glm::dvec3> voxel;     // where t >= 0
    double frameMs = 0.0;
};

struct IsoRow {
    int steps;
    bool refine;
    double frameMs, median, p95, mean, far, disagree;
};

/// --iso-error's step counts, each in 1 .. 4096. Throws UsageError.
std::vector<int> parseStepCounts(const Args& args) {
    std::vector<int> counts;
    for (double v : numberList("--iso-error", *args.value("--iso-error"))) {
        if (v != std::floor(v) || v < 1 || v > 4096) {
            char text[64];
            std::snprintf(text, sizeof text, "--iso-error: %g is not a step count (1 .. 4096)", v);
            throw UsageError{text};
        }
        counts.push_back(int(v));
    }
    return counts;
}

/// The first volume layer with isovalues, or null.
layers::VolumeLayer* isoVolume(scene::Scene& scene) {
    for (auto& r : scene.resources())
        if (auto* v = dynamic_cast<layers::VolumeLayer*>(r.layer.get()); v && !v->settings().isovalues.empty()) return v;
    return nullptr;
}

/// The voxel of each pixel's hit: its ray from the camera, `t` along it.
std::vector<glm::dvec3> hitVoxels(const layers::VolumeLayer& volume, const scene::Camera& cam,
                                  const std::vector<float>& t, uint32_t width, uint32_t height) {
    std::vector<glm::dvec3> voxel(t.size());
    const double aspect = double(width) / double(height);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const size_t i = size_t(y) * width + x;
            if (i >= t.size() || t[i] < 0.0f) continue;
            const glm::dvec3 dir = cam.rayDirection(2.0 * (x + 0.5) / width - 1.0, 2.0 * (y + 0.5) / height - 1.0, aspect);
            voxel[i] = volume.voxelAt(cam.position() + double(t[i]) * dir);
        }
    return voxel;
}

/// Runs one configuration. One scene each: the measurement is compiled into the ray caster.
struct IsoRunner {
    const Args& args;
    GpuSession& gpu;
    uint32_t width, height;
    long warmup;

    /// Nothing (the problem printed) when the scene does not load or has no isosurface.
    std::optional<Hits> run(int steps, bool refine, long timed) const {
        auto loaded = loadSceneForCommand(args);
        if (!loaded) return std::nullopt;
        std::unique_ptr<scene::Scene> scene = std::move(loaded).value();
        layers::VolumeLayer* volume = isoVolume(*scene);
        if (!volume) {
            std::fprintf(stderr, "orbis: %s has no volume layer in mode \"iso\" (--iso-error)\n", args.positional()[0].c_str());
            return std::nullopt;
        }
        volume->setMeasurement(true, refine);
        volume->setParameter("steps", steps);
        render::Renderer renderer(*gpu.device, width, height);
        renderer.settle(*scene, 600.0);
        const FrameTimes times = timeFrames(renderer, *scene, timed, warmup);
        const auto frame = renderer.render(*scene, true);
        (void)renderer.readPixels(frame);   // waits for the frame
        Hits h;
        h.t = volume->hitDistances();
        h.voxel = hitVoxels(*volume, scene->camera(), h.t, width, height);
        h.frameMs = times.wall.empty() ? 0.0 : summarize(times.wall).median;
        return h;
    }
};

/// How far one configuration's hits are from the reference's.
IsoRow compare(int steps, bool refine, const Hits& hits, const Hits& reference) {
    std::vector<double> err;
    size_t disagree = 0, any = 0;
    for (size_t i = 0; i < hits.t.size() && i < reference.t.size(); ++i) {
        const bool a = hits.t[i] >= 0.0f, b = reference.t[i] >= 0.0f;
        any += a || b ? 1 : 0;
        if (a != b) ++disagree;
        if (a && b) err.push_back(glm::length(hits.voxel[i] - reference.voxel[i]));
    }
    std::sort(err.begin(), err.end());
    double sum = 0.0;
    size_t far = 0;
    for (double e : err) sum += e, far += e > 2.0 ? 1 : 0;
    const auto quantile = [&](double q) { return err.empty() ? 0.0 : err[std::min(err.size() - 1, size_t(q * double(err.size())))]; };
    return {steps, refine, hits.frameMs, quantile(0.5), quantile(0.95),
            err.empty() ? 0.0 : sum / double(err.size()),
            err.empty() ? 0.0 : 100.0 * double(far) / double(err.size()),
            any ? 100.0 * double(disagree) / double(any) : 0.0};
}

void printJson(const Args& args, const gpu::PhysicalDeviceInfo& info, uint32_t width, uint32_t height,
               int referenceSteps, const std::vector<IsoRow>& rows) {
    nlohmann::json out;
    out["scene"] = args.positional()[0];
    out["device"] = {{"name", info.name}, {"type", info.type}};
    out["size"] = {width, height};
    out["reference_steps"] = referenceSteps;
    for (const auto& r : rows)
        out["rows"].push_back({{"steps", r.steps}, {"refine", r.refine}, {"frame_ms", r.frameMs},
                               {"median_voxels", r.median}, {"p95_voxels", r.p95}, {"mean_voxels", r.mean},
                               {"other_surface_percent", r.far},
                               {"hit_disagree_percent", r.disagree}});
    std::printf("%s\n", out.dump(2).c_str());
}

void printTable(const Args& args, const gpu::PhysicalDeviceInfo& info, uint32_t width, uint32_t height, long frames,
                int referenceSteps, const std::vector<IsoRow>& rows) {
    std::printf("orbis bench %s --iso-error  %ux%u  %ld frames each  reference: %d steps, refined  device: %s (%s)\n",
                args.positional()[0].c_str(), width, height, frames, referenceSteps, info.name.c_str(), info.type.c_str());
    std::printf("%6s %7s %9s %11s %11s %11s %9s %9s\n", "steps", "refine", "frame ms", "median vox", "p95 vox",
                "mean vox", "> 2 vox %", "hit/miss %");
    for (const auto& r : rows)
        std::printf("%6d %7s %9.2f %11.4f %11.4f %11.4f %9.3f %9.3f\n", r.steps, r.refine ? "yes" : "no", r.frameMs,
                    r.median, r.p95, r.mean, r.far, r.disagree);
    std::printf("(distance from each pixel's first hit to the reference's, in voxels, over the pixels where both hit;\n"
                " > 2 vox: share of hits more than 2 voxels off (refined: on another part of the surface, a thin\n"
                " part stepped over); hit/miss: pixels where only one of them hits, of those where either\n"
                " does; frames timed with the measurement on)\n");
}

}  // namespace

int isoErrorBench(const Args& args, GpuSession& gpu, uint32_t width, uint32_t height, long frames, long warmup) {
    const std::vector<int> counts = parseStepCounts(args);
    const IsoRunner runner{args, gpu, width, height, warmup};
    const int referenceSteps = std::min(4096, 4 * *std::max_element(counts.begin(), counts.end()));
    const auto reference = runner.run(referenceSteps, true, 0);
    if (!reference) return kBadInput;
    std::vector<IsoRow> rows;
    for (int steps : counts)
        for (bool refine : {false, true}) {
            const auto hits = runner.run(steps, refine, frames);
            if (!hits) return kBadInput;
            rows.push_back(compare(steps, refine, *hits, *reference));
        }
    const auto& info = gpu.device->info();
    if (args.flag("--json")) printJson(args, info, width, height, referenceSteps, rows);
    else printTable(args, info, width, height, frames, referenceSteps, rows);
    return validationExitCode(gpu);
}

}  // namespace orbis::cli
