// orbis viewshed: what an observer sees of the ground around it, computed on the GPU
// (layers/analysis/ViewshedGpu.h) over a grid sampled from a DEM at its own resolution
// (globe/ElevationSampler.h, globe/Viewshed.h), written as a GeoTIFF; --compare runs GDAL's
// viewshed (what gdal_viewshed runs) and the exact sight lines on the same grid in the same run
// and prints agreement and times; --sweep prints the error against run time as the cells grow.
#include "globe/ElevationSampler.h"
#include "globe/GdalSetup.h"
#include "globe/RasterSource.h"
#include "globe/SyntheticTerrain.h"
#include "globe/Viewshed.h"
#include "globe/ViewshedGdal.h"
#include "layers/analysis/ViewshedGpu.h"
#include "tools/orbis/Args.h"
#include "tools/orbis/Commands.h"
#include "tools/orbis/Session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace orbis::cli {
namespace {

const char* kHelp =
    "usage: orbis viewshed --dem DEM|--synthetic SEED --observer LON,LAT --radius M [options]\n"
    "What an observer H metres above the ground sees of the ground within M metres, computed on\n"
    "the GPU over a grid of --cell metres sampled from the DEM at its own resolution (a plane\n"
    "tangent to the ellipsoid at the observer: the same at the poles and across the antimeridian).\n"
    "The model is gdal_viewshed's: the ground drops by K d^2 / D with the distance d (the Earth's\n"
    "curve less refraction), and each cell's horizon comes from its neighbours nearer the observer.\n"
    "  --synthetic SEED  generated fractal hills instead of a DEM (globe/SyntheticTerrain.h)\n"
    "  --height H        the eye above the ground (default 2 m)\n"
    "  --target T        what must be seen above the ground at each cell (default 0 m)\n"
    "  --cell C          grid cell in metres (default: the DEM's pixel, at least 1 m; 30 m\n"
    "                    for --synthetic)\n"
    "  --curvature K     gdal_viewshed's -cc (default 0.85714; 0: a flat Earth)\n"
    "  --method M        gpu (default) | cpu (the same rings in double) | exact (sight lines to\n"
    "                    every cell, slow) | gdal (GDALViewshedGenerate)\n"
    "  --out FILE.tif    the viewshed (255 seen, 0 hidden, 1 out of range, 2 no data), in the\n"
    "                    grid's plane (an azimuthal equidistant CRS centred on the observer)\n"
    "  --grid FILE.tif   the sampled heights, for running gdal_viewshed on the same grid\n"
    "  --compare         also GDAL's viewshed and the exact sight lines: agreement and times\n"
    "  --sweep           the GPU viewshed at 1, 2, 4 and 8 times the cell: ms against the\n"
    "                    disagreement with the exact sight lines at the finest cell\n"
    "  --repeat N        runs timed for each median (default 5)\n";

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

std::string spread(const std::vector<double>& v) {
    if (v.empty()) return "";
    char s[96];
    std::snprintf(s, sizeof s, "median %.2f ms (%.2f .. %.2f, %zu runs)", median(v), *std::min_element(v.begin(), v.end()),
                  *std::max_element(v.begin(), v.end()), v.size());
    return s;
}

globe::LonLat lonLat(const std::string& text) {
    std::istringstream in(text);
    double lon = 0.0, lat = 0.0;
    char comma = 0;
    std::string rest;
    if (!(in >> lon >> comma >> lat) || comma != ',' || (in >> rest) || !std::isfinite(lon) || !std::isfinite(lat))
        throw UsageError{"--observer: \"" + text + "\" is not LON,LAT"};
    if (lat < -90.0 || lat > 90.0) throw UsageError{"--observer: the latitude " + std::to_string(lat) + " is outside -90..90"};
    if (lon < -540.0 || lon > 540.0) throw UsageError{"--observer: the longitude " + std::to_string(lon) + " is outside -540..540"};
    return {lon, lat};
}

void printAgreement(const char* name, const globe::ViewshedAgreement& a, const char* first, const char* second) {
    std::printf("%-12s%.3f %% of %zu cells (%zu differ: %zu seen by %s only, %zu by %s only)\n", name, a.percent(), a.compared, a.differ,
                a.seenOnlyByA, first, a.seenOnlyByB, second);
}

}  // namespace

int viewshedCommand(const std::vector<std::string>& argv) {
    std::set<std::string> valued = gpuValuedOptions();
    valued.insert({"--synthetic", "--dem", "--observer", "--radius", "--height", "--target", "--cell", "--curvature", "--method", "--out", "--grid", "--repeat"});
    std::set<std::string> flags = gpuFlagOptions();
    flags.insert({"--compare", "--sweep", "--help"});
    const Args args(argv, valued, flags, {{"-h", "--help"}, {"-o", "--out"}});
    if (args.flag("--help")) {
        std::printf("%s%s", kHelp, gpuOptionsHelp().c_str());
        return kOk;
    }
    if (!args.positional().empty()) throw UsageError{"unexpected argument " + args.positional().front()};
    const auto demPath = args.value("--dem"), observerText = args.value("--observer");
    const auto seed = args.integer("--synthetic", 0, 0xffffffffl);
    if (!!demPath == !!seed) throw UsageError{"give --dem or --synthetic (one of them)"};
    if (!observerText || !args.value("--radius")) throw UsageError{"give --observer and --radius"};
    const globe::LonLat observer = lonLat(*observerText);
    const double radius = *args.number("--radius", 1.0, 2e6);
    const double height = args.number("--height", -1e4, 1e6).value_or(2.0);
    const double target = args.number("--target", -1e4, 1e5).value_or(0.0);
    const double curvature = args.number("--curvature", 0.0, 2.0).value_or(0.85714);
    const int repeat = int(args.integer("--repeat", 1, 1000).value_or(5));
    const std::string method = args.value("--method").value_or("gpu");
    if (method != "gpu" && method != "cpu" && method != "exact" && method != "gdal")
        throw UsageError{"--method: \"" + method + "\" is not gpu, cpu, exact or gdal"};

    globe::configureGdal();
    std::shared_ptr<const globe::ElevationSampler> sampler;
    globe::HeightAt ground;
    double cell = 30.0;
    const std::string source = demPath ? *demPath : "synthetic terrain " + std::to_string(*seed);
    if (demPath) {
        auto dem = globe::RasterSource::open({.path = *demPath, .role = globe::RasterRole::Elevation});
        if (!dem) return badInput(dem.message());
        cell = std::max(1.0, (*dem)->resolutionDeg() * 111320.0 * std::max(0.01, std::cos(observer.y * M_PI / 180.0)));
        sampler = std::make_shared<const globe::ElevationSampler>(*dem);
        ground = globe::ElevationSampler::function(sampler);
    } else {
        ground = globe::syntheticTerrain({.seed = uint32_t(*seed)});
    }
    cell = args.number("--cell", 0.01, 1e5).value_or(cell);

    const auto t0 = std::chrono::steady_clock::now();
    auto grid = globe::sampleViewshedGrid(ground, observer, radius, cell);
    if (!grid) return badInput(source + ": " + grid.message());
    if (sampler && !sampler->error().empty()) return badInput(sampler->error());
    const double sampleMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const size_t noData = size_t(std::count_if(grid->heights.begin(), grid->heights.end(), [](float h) { return !std::isfinite(h); }));
    const globe::ViewshedOptions options{.observerCol = grid->radiusCells,
                                         .observerRow = grid->radiusCells,
                                         .observerHeight = height,
                                         .targetHeight = target,
                                         .radiusM = radius,
                                         .curvature = curvature};
    auto eye = globe::viewshedEyeHeight(*grid, options);
    if (!eye) return badInput(source + ": " + eye.error().message + " at " + *observerText);
    std::printf("observer    %.7f, %.7f: ground %.2f m, eye %.2f m; target %.2f m above the ground; curvature %.5f\n", observer.x, observer.y,
                *eye - height, *eye, target, curvature);
    std::printf("grid        %d x %d cells of %.3f m, %.0f m around, from %s (%.1f ms to sample; %zu cells without data)\n", grid->side(),
                grid->side(), cell, radius, source.c_str(), sampleMs, noData);
    if (const auto g = args.value("--grid")) {
        if (auto w = globe::writeViewshedGridTiff(*grid, *g); !w) return badInput(w.message());
        std::printf("wrote       %s (heights; observer at %.3f, %.3f in its CRS)\n", g->c_str(), 0.0, 0.0);
    }

    std::optional<GpuSession> gpu;
    std::unique_ptr<layers::ViewshedGpu> compute;
    auto openCompute = [&] {
        if (compute) return;
        gpu = openGpu(args);
        compute = std::make_unique<layers::ViewshedGpu>(*gpu->device);
    };
    // Runs the GPU viewshed `repeat` times on `g`: the result and the GPU times (timestamps, or
    // submit-to-finish where the device has none).
    auto runGpu = [&](const globe::ViewshedGrid& g, const globe::ViewshedOptions& o, std::vector<double>& ms) -> Result<globe::Viewshed> {
        openCompute();
        if (auto set = compute->setGrid(g); !set) return set.error();
        Result<globe::Viewshed> out = makeError("not run");
        for (int i = 0; i < repeat + 1; ++i) {
            layers::ViewshedTiming t;
            out = compute->run(o, &t);
            if (!out) return out;
            if (i > 0) ms.push_back(t.gpuMs > 0.0 ? t.gpuMs : t.submitMs);   // the first run warms up
        }
        return out;
    };
    auto timed = [&](auto&& f, std::vector<double>& ms) {
        decltype(f()) out = makeError("not run");
        for (int i = 0; i < repeat; ++i) {
            const auto s = std::chrono::steady_clock::now();
            out = f();
            ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s).count());
            if (!out) break;
        }
        return out;
    };

    std::vector<double> mainMs;
    Result<globe::Viewshed> result = makeError("not run");
    if (method == "gpu") result = runGpu(*grid, options, mainMs);
    else if (method == "cpu") result = timed([&] { return globe::viewshedRings(*grid, options); }, mainMs);
    else if (method == "exact") result = timed([&] { return globe::viewshedSightlines(*grid, options); }, mainMs);
    else result = timed([&] { return globe::viewshedGdal(*grid, options); }, mainMs);
    if (!result) return badInput(result.message());
    const size_t seen = result->count(globe::Sight::Visible), hidden = result->count(globe::Sight::Hidden);
    const double cellArea = cell * cell / 1e6;
    std::printf("%-12s%s%s: %zu cells seen (%.3f km^2), %zu hidden: %.2f %% of the ground in range seen; %s\n", method.c_str(),
                gpu ? gpu->device->info().name.c_str() : "", gpu ? "" : "CPU", seen, double(seen) * cellArea, hidden,
                seen + hidden ? 100.0 * double(seen) / double(seen + hidden) : 0.0, spread(mainMs).c_str());
    if (const auto out = args.value("--out")) {
        if (auto w = globe::writeViewshedTiff(*grid, *result, *out); !w) return badInput(w.message());
        std::printf("wrote       %s\n", out->c_str());
    }

    if (args.flag("--compare") || args.flag("--sweep")) {
        std::vector<double> exactMs;
        auto exact = timed([&] { return globe::viewshedSightlines(*grid, options); }, exactMs);
        if (!exact) return badInput(exact.message());
        std::printf("%-12s%s (sight lines to every cell, %u threads)\n", "exact", spread(exactMs).c_str(), std::max(1u, std::thread::hardware_concurrency()));
        if (args.flag("--compare")) {
            std::vector<double> gdalMs, cpuMs, gpuMs;
            auto gdal = timed([&] { return globe::viewshedGdal(*grid, options); }, gdalMs);
            if (!gdal) return badInput(gdal.message());
            std::printf("%-12s%s (GDALViewshedGenerate, gdal_viewshed's algorithm, in memory)\n", "gdal", spread(gdalMs).c_str());
            auto rings = timed([&] { return globe::viewshedRings(*grid, options); }, cpuMs);
            if (!rings) return badInput(rings.message());
            std::printf("%-12s%s (the same rings in double, one thread)\n", "cpu", spread(cpuMs).c_str());
            auto onGpu = method == "gpu" ? std::move(result) : runGpu(*grid, options, gpuMs);
            if (method == "gpu") gpuMs = mainMs;
            if (!onGpu) return badInput(onGpu.message());
            std::printf("%-12s%s (%s)\n", "gpu", spread(gpuMs).c_str(), gpu->device->info().name.c_str());
            printAgreement("gpu/gdal", globe::compareViewsheds(*onGpu, *gdal), "the GPU", "GDAL");
            printAgreement("gpu/cpu", globe::compareViewsheds(*onGpu, *rings), "the GPU", "the CPU");
            printAgreement("gpu/exact", globe::compareViewsheds(*onGpu, *exact), "the GPU", "the sight lines");
            printAgreement("gdal/exact", globe::compareViewsheds(*gdal, *exact), "GDAL", "the sight lines");
            std::printf("%-12sGDAL / GPU: %.1fx (medians)\n", "speed-up", median(gdalMs) / std::max(1e-6, median(gpuMs)));
        }
        if (args.flag("--sweep")) {
            std::printf("\nsweep: the GPU viewshed on coarser grids, spread back onto the finest, against the exact sight lines there\n");
            std::printf("%-8s %-10s %-10s %-12s %-12s\n", "factor", "cell_m", "grid", "gpu_ms", "agree_%");
            for (int factor : {1, 2, 4, 8}) {
                const globe::ViewshedGrid coarse = globe::coarsenViewshedGrid(*grid, factor);
                if (coarse.radiusCells < 2) break;
                globe::ViewshedOptions o = options;
                o.observerCol = o.observerRow = coarse.radiusCells;
                std::vector<double> ms;
                auto v = runGpu(coarse, o, ms);
                if (!v) return badInput(v.message());
                const globe::Viewshed back = globe::refineViewshed(*v, factor, grid->side());
                char g[32];
                std::snprintf(g, sizeof g, "%dx%d", coarse.side(), coarse.side());
                std::printf("%-8d %-10.2f %-10s %-12.3f %-12.3f\n", factor, coarse.cellM, g, median(ms),
                            globe::compareViewsheds(back, *exact).percent());
            }
        }
    }
    return gpu ? validationExitCode(*gpu) : kOk;
}

}  // namespace orbis::cli
