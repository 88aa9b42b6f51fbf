// orbis bench SCENE --tiles LEVEL: tile throughput of the pager against a bare loop.
//
// The pager (TerrainTiles on a worker pool: priorities, chained coarse-to-fine loading,
// cancellation bookkeeping, cache, mip building) loads every tile of LEVEL over the scene's
// terrain sources, with their ancestors. The bare loop then reads exactly the same (layer,
// tile) list with RasterSource (GDAL's warper with the transformer kept per handle) on as many
// plain threads, nothing else. Both runs are repeated and the second of each is reported, so
// GDAL's block cache is equally warm for both.
//
// Sources behind a server (WMS, WMTS, XYZ, http) are measured twice: cold (each run opens its
// sources on an empty disk cache of its own, so every tile is a request) and warm (both runs on
// the cache the cold bare run filled, sources opened again: every tile from the disk).
#include "tools/orbis/BenchModes.h"

#include "base/Log.h"
#include "base/ThreadPool.h"
#include "globe/TerrainTiles.h"
#include "layers/terrain/TerrainLayer.h"
#include "tools/orbis/Session.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

namespace orbis::cli {
namespace {

/// The terrain's sources, opened as the pager opens them, and the extent they cover together.
struct TileSources {
    std::vector<std::shared_ptr<globe::RasterSource>> dems, images;
    globe::GeoExtent coverage{180, 90, -180, -90};

    void grow(const globe::RasterSource& s) {
        const auto c = s.coverage();
        coverage = {std::min(coverage.west, c.west), std::min(coverage.south, c.south),
                    std::max(coverage.east, c.east), std::max(coverage.north, c.north)};
    }
};

/// The last terrain layer of the scene, or null.
const layers::TerrainLayer* findTerrain(const scene::Scene& scene) {
    const layers::TerrainLayer* terrain = nullptr;
    for (const auto& r : scene.resources())
        if (auto* t = dynamic_cast<const layers::TerrainLayer*>(r.layer.get())) terrain = t;
    return terrain;
}

/// Every source that opens (remote ones caching in `cacheDir` when it is given); the others are
/// reported on stderr.
TileSources openSources(const layers::TerrainSettings& settings, const std::string& cacheDir = {}) {
    TileSources out;
    const auto options = [&](globe::RasterSourceOptions o) {
        if (!cacheDir.empty() && globe::isRemoteSource(o)) o.cacheDir = cacheDir;
        return o;
    };
    for (const auto& o : settings.elevation)
        if (auto s = globe::RasterSource::open(options(o))) out.dems.push_back(*s), out.grow(**s);
        else std::fprintf(stderr, "orbis: %s\n", s.message().c_str());
    for (const auto& l : settings.imagery)
        if (auto s = globe::RasterSource::open(options(l.source))) out.images.push_back(*s), out.grow(**s);
        else std::fprintf(stderr, "orbis: %s\n", s.message().c_str());
    return out;
}

/// The tiles of `level` over `coverage`, nearest the middle first, at most 256.
std::vector<globe::TileKey> tilesOver(const globe::GeoExtent& coverage, uint32_t level) {
    std::vector<globe::TileKey> tiles;
    const auto first = globe::TileKey::containing(coverage.west, coverage.north, level);
    const auto last = globe::TileKey::containing(coverage.east, coverage.south, level);
    for (uint32_t y = first.y; y <= last.y; ++y)
        for (uint32_t x = first.x; x <= last.x && tiles.size() < 65536; ++x) tiles.push_back({level, x, y});
    const double cx = coverage.centerLon(), cy = coverage.centerLat();
    std::sort(tiles.begin(), tiles.end(), [&](const globe::TileKey& a, const globe::TileKey& b) {
        const auto da = std::hypot(a.extent().centerLon() - cx, a.extent().centerLat() - cy);
        const auto db = std::hypot(b.extent().centerLon() - cx, b.extent().centerLat() - cy);
        return da < db;
    });
    if (tiles.size() > 256) tiles.resize(256);
    return tiles;
}

globe::TerrainTilesSettings modelSettings(const layers::TerrainSettings& settings) {
    globe::TerrainTilesSettings ms;
    ms.gridSize = settings.gridSize;
    ms.imageSize = settings.imageSize;
    ms.maxLevel = settings.maxLevel;
    ms.cpuBudgetBytes = uint64_t(8) << 30;   // keep everything: the list of loaded tiles is the workload
    return ms;
}

struct PagerRun {
    double seconds = 0.0;
    uint64_t produced = 0;   // loads completed
};

/// The pager loads `tiles` with their ancestors on a pool of `threads`; `loaded`, if given,
/// receives what it loaded.
PagerRun runPager(const globe::TerrainTilesSettings& ms, const TileSources& sources,
                  const std::vector<globe::TileKey>& tiles, unsigned threads, std::vector<globe::DataKey>* loaded) {
    jobs::ThreadPool pool(threads, "orbis-tiles");
    globe::TerrainTiles model(ms, sources.dems, {sources.images.begin(), sources.images.end()}, &pool);
    const auto t0 = std::chrono::steady_clock::now();
    for (uint64_t frame = 1;; ++frame) {
        model.beginFrame(frame);
        for (const auto& t : tiles)
            for (uint32_t layer = 0; layer < model.layerCount(); ++layer) model.request(layer, t, 0.0);
        if (!model.loading()) break;
        model.waitIdle();
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (loaded) *loaded = model.loadedKeys();
    return {s, model.stats().completed};
}

/// The pager's read of one key, and nothing else.
void readBare(const globe::TerrainTilesSettings& ms, const TileSources& sources, const globe::DataKey& key) {
    const auto extent = key.tile.extent();
    if (key.layer == 0) {
        // The pager's read: the tile's grid with a one-sample border.
        const double dx = extent.width() / (ms.gridSize - 1), dy = extent.height() / (ms.gridSize - 1);
        const globe::GeoExtent grown{extent.west - dx, extent.south - dy, extent.east + dx, extent.north + dy};
        for (const auto& s : sources.dems)
            if (s->covers(extent)) (void)s->readElevation(grown, ms.gridSize + 2);
    } else if (sources.images[key.layer - 1]->covers(extent)) {
        (void)sources.images[key.layer - 1]->readImagery(extent, ms.imageSize);
    }
}

/// Reads `keys` on `threads` plain threads; the seconds it took.
double runBare(const globe::TerrainTilesSettings& ms, const TileSources& sources,
               const std::vector<globe::DataKey>& keys, unsigned threads) {
    std::atomic<size_t> next{0};
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (unsigned i = 0; i < threads; ++i)
        pool.emplace_back([&] {
            for (size_t k; (k = next.fetch_add(1)) < keys.size();) readBare(ms, sources, keys[k]);
        });
    for (auto& t : pool) t.join();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct TileRunPair {
    const char* label;   // "" for local sources, "cold "/"warm " for remote ones
    PagerRun pager;
    double bareSeconds = 0.0;
};

void printReport(const Args& args, long level, unsigned threads, size_t tiles, size_t loads, const std::vector<TileRunPair>& runs) {
    if (args.flag("--json")) {
        nlohmann::json out{{"scene", args.positional()[0]}, {"level", level}, {"threads", threads}, {"tiles", loads}};
        for (const TileRunPair& r : runs) {
            const double pagerRate = double(r.pager.produced) / r.pager.seconds, bareRate = double(loads) / r.bareSeconds;
            std::string prefix = r.label;
            if (!prefix.empty()) prefix.back() = '_';
            out[prefix + "pager_tiles_per_s"] = pagerRate;
            out[prefix + "bare_tiles_per_s"] = bareRate;
            out[prefix + "ratio"] = pagerRate / bareRate;
        }
        std::printf("%s\n", out.dump(2).c_str());
        return;
    }
    std::printf("orbis bench %s --tiles %ld: %zu tiles of level %ld over the sources, their ancestors and layers "
                "= %zu loads, %u threads\n",
                args.positional()[0].c_str(), level, tiles, level, loads, threads);
    for (const TileRunPair& r : runs) {
        const double pagerRate = double(r.pager.produced) / r.pager.seconds, bareRate = double(loads) / r.bareSeconds;
        std::printf("%spager      %8.1f tiles/s  (%.3f s)\n", r.label, pagerRate, r.pager.seconds);
        std::printf("%sbare loop  %8.1f tiles/s  (%.3f s)\n", r.label, bareRate, r.bareSeconds);
        std::printf("%spager / bare = %.2f\n", r.label, pagerRate / bareRate);
    }
}

/// A fresh, empty folder under the temporary directory (removed with its tree by ~TempDir).
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        std::string p = (std::filesystem::temp_directory_path() / "orbis-tile-bench-XXXXXX").string();
        if (::mkdtemp(p.data())) path = p;
    }
    ~TempDir() {
        std::error_code ec;
        if (!path.empty()) std::filesystem::remove_all(path, ec);
    }
};

}  // namespace

int tileBench(const Args& args, scene::Scene& scene, long level, unsigned threads) {
    const layers::TerrainLayer* terrain = findTerrain(scene);
    if (!terrain) {
        std::fprintf(stderr, "orbis: %s: --tiles needs a terrain layer\n", args.positional()[0].c_str());
        return kBadInput;
    }
    const TileSources sources = openSources(terrain->settings());
    if (sources.dems.empty() && sources.images.empty()) {
        std::fprintf(stderr, "orbis: %s: the terrain has no readable source\n", args.positional()[0].c_str());
        return kBadInput;
    }
    const std::vector<globe::TileKey> tiles = tilesOver(sources.coverage, uint32_t(level));
    const globe::TerrainTilesSettings ms = modelSettings(terrain->settings());
    const auto& settings = terrain->settings();
    const bool remote = std::any_of(settings.elevation.begin(), settings.elevation.end(), globe::isRemoteSource) ||
                        std::any_of(settings.imagery.begin(), settings.imagery.end(),
                                    [](const layers::ImageryLayerSettings& l) { return globe::isRemoteSource(l.source); });
    std::vector<globe::DataKey> keys;
    std::vector<TileRunPair> runs;
    if (!remote) {
        // Each run twice, the second reported, so that GDAL's block cache is equally warm for both.
        runPager(ms, sources, tiles, threads, &keys);
        runBare(ms, sources, keys, threads);
        const PagerRun pager = runPager(ms, sources, tiles, threads, nullptr);
        runs.push_back({"", pager, runBare(ms, sources, keys, threads)});
    } else {
        // Cold: each run on sources opened over an empty cache of its own.
        TempDir coldPager, cache;
        if (coldPager.path.empty() || cache.path.empty()) {
            std::fprintf(stderr, "orbis: cannot make a temporary folder for the tile caches\n");
            return kBadInput;
        }
        const PagerRun cold = runPager(ms, openSources(settings, coldPager.path.string()), tiles, threads, &keys);
        const double coldBare = runBare(ms, openSources(settings, cache.path.string()), keys, threads);
        runs.push_back({"cold ", cold, coldBare});
        // Warm: the cache the bare run filled, sources opened again (their block caches empty).
        const PagerRun warm = runPager(ms, openSources(settings, cache.path.string()), tiles, threads, nullptr);
        runs.push_back({"warm ", warm, runBare(ms, openSources(settings, cache.path.string()), keys, threads)});
    }
    printReport(args, level, threads, tiles.size(), keys.size(), runs);
    return kOk;
}

}  // namespace orbis::cli
