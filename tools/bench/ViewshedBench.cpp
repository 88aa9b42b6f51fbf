// orbis-viewshed-bench: the GPU viewshed (layers/analysis/ViewshedGpu.h) on generated fractal
// hills (globe/SyntheticTerrain.h), timed, against the same rings on the CPU and, with --sweep,
// the error against run time as the cells grow (against the exact sight lines at the finest
// cell). Needs neither GDAL nor a DEM: small enough to carry to a machine with a GPU. The
// comparison with GDAL's own viewshed is `orbis viewshed --synthetic SEED --compare`.
//
//   orbis-viewshed-bench [--radius-cells N] [--cell M] [--height H] [--repeat N] [--device SEL]
//                        [--workgroup wide|narrow] [--sweep]
#include "engine/gpu/Device.h"
#include "engine/gpu/Instance.h"
#include "globe/SyntheticTerrain.h"
#include "globe/Viewshed.h"
#include "layers/analysis/ViewshedGpu.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

using namespace orbis;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

int usage(const char* why) {
    std::fprintf(stderr, "orbis-viewshed-bench: %s\nusage: orbis-viewshed-bench [--radius-cells N] [--cell M] [--height H] [--repeat N] [--device SEL] [--workgroup wide|narrow] [--sweep]\n", why);
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    int radiusCells = 500, repeat = 10;
    double cell = 30.0, height = 10.0;
    bool sweep = false;
    std::string device;
    layers::ViewshedGpu::Workgroup workgroup = layers::ViewshedGpu::Workgroup::Auto;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        const char* v = nullptr;
        if (a == "--sweep") sweep = true;
        else if ((a == "--radius-cells" || a == "--cell" || a == "--height" || a == "--repeat" || a == "--device" || a == "--workgroup") &&
                 !(v = next()))
            return usage((a + " needs a value").c_str());
        else if (a == "--radius-cells") radiusCells = std::atoi(v);
        else if (a == "--cell") cell = std::atof(v);
        else if (a == "--height") height = std::atof(v);
        else if (a == "--repeat") repeat = std::atoi(v);
        else if (a == "--device") device = v;
        else if (a == "--workgroup" && std::string(v) == "wide") workgroup = layers::ViewshedGpu::Workgroup::Wide;
        else if (a == "--workgroup" && std::string(v) == "narrow") workgroup = layers::ViewshedGpu::Workgroup::Narrow;
        else if (a == "--workgroup") return usage("--workgroup is wide or narrow");
        else return usage(("unknown option " + a).c_str());
    }
    if (radiusCells < 2 || radiusCells > 8000 || repeat < 1 || repeat > 1000 || !(cell > 0.0)) return usage("an option is out of range");

    const auto t0 = std::chrono::steady_clock::now();
    auto grid = globe::sampleViewshedGrid(globe::syntheticTerrain({.seed = 1}), {8.5, 46.5}, radiusCells * cell, cell, size_t(300) << 20);
    if (!grid) return usage(grid.message().c_str());
    std::printf("grid      %d x %d cells of %.1f m, synthetic hills (seed 1) at 8.5 E 46.5 N, sampled in %.0f ms\n", grid->side(), grid->side(),
                cell, msSince(t0));
    const globe::ViewshedOptions options{.observerCol = grid->radiusCells, .observerRow = grid->radiusCells, .observerHeight = height,
                                         .radiusM = radiusCells * cell};
    try {
        gpu::Instance instance(gpu::InstanceOptions{});
        gpu::DeviceOptions dopt;
        dopt.select = device;
        gpu::Device dev(instance, dopt);
        layers::ViewshedGpu compute(dev, workgroup);
        auto runGpu = [&](const globe::ViewshedGrid& g, const globe::ViewshedOptions& o, std::vector<double>& gpuMs,
                          std::vector<double>& wallMs) -> Result<globe::Viewshed> {
            if (auto s = compute.setGrid(g); !s) return s.error();
            Result<globe::Viewshed> out = makeError("not run");
            for (int i = 0; i <= repeat; ++i) {
                layers::ViewshedTiming t;
                out = compute.run(o, &t);
                if (!out) return out;
                if (i == 0) continue;   // warm-up
                gpuMs.push_back(t.gpuMs);
                wallMs.push_back(t.submitMs);
            }
            return out;
        };
        std::vector<double> gpuMs, wallMs;
        auto onGpu = runGpu(*grid, options, gpuMs, wallMs);
        if (!onGpu) return usage(onGpu.message().c_str());
        std::printf("gpu       %s: median %.3f ms on the GPU (%.3f .. %.3f), %.3f ms submit to finish, %d rings, %d runs\n",
                    dev.info().name.c_str(), median(gpuMs), *std::min_element(gpuMs.begin(), gpuMs.end()),
                    *std::max_element(gpuMs.begin(), gpuMs.end()), median(wallMs), grid->radiusCells + 1, repeat);
        auto s = std::chrono::steady_clock::now();
        auto cpu = globe::viewshedRings(*grid, options);
        const double cpuMs = msSince(s);
        if (!cpu) return usage(cpu.message().c_str());
        const auto a = globe::compareViewsheds(*onGpu, *cpu);
        std::printf("cpu       the same rings in double, one thread: %.1f ms; the GPU agrees on %.4f %% of %zu cells (%zu differ)\n", cpuMs,
                    a.percent(), a.compared, a.differ);
        std::printf("seen      %.2f %% of the ground in range\n",
                    100.0 * double(onGpu->count(globe::Sight::Visible)) / double(std::max<size_t>(1, a.compared)));
        if (sweep) {
            s = std::chrono::steady_clock::now();
            auto exact = globe::viewshedSightlines(*grid, options);
            if (!exact) return usage(exact.message().c_str());
            std::printf("exact     sight lines to every cell: %.0f ms on %u threads; the GPU agrees on %.3f %%\n", msSince(s),
                        std::max(1u, std::thread::hardware_concurrency()), globe::compareViewsheds(*onGpu, *exact).percent());
            std::printf("\n%-8s %-10s %-12s %-12s %-12s\n", "factor", "cell_m", "grid", "gpu_ms", "agree_%");
            for (int factor : {1, 2, 4, 8, 16}) {
                const globe::ViewshedGrid coarse = globe::coarsenViewshedGrid(*grid, factor);
                if (coarse.radiusCells < 2) break;
                globe::ViewshedOptions o = options;
                o.observerCol = o.observerRow = coarse.radiusCells;
                std::vector<double> g, w;
                auto v = runGpu(coarse, o, g, w);
                if (!v) return usage(v.message().c_str());
                char side[32];
                std::snprintf(side, sizeof side, "%dx%d", coarse.side(), coarse.side());
                std::printf("%-8d %-10.1f %-12s %-12.3f %-12.3f\n", factor, coarse.cellM, side, median(g),
                            globe::compareViewsheds(globe::refineViewshed(*v, factor, grid->side()), *exact).percent());
            }
        }
        dev.waitIdle();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "orbis-viewshed-bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
