// orbis bench SCENE --tiles LEVEL: tile throughput of the pager against a bare loop.
//
// The pager (TerrainTiles on a worker pool: priorities, chained coarse-to-fine loading,
// cancellation bookkeeping, cache, mip building) loads every tile of LEVEL over the scene's
// terrain sources, with their ancestors. The bare loop then reads exactly the same (layer,
// tile) list with RasterSource (GDAL's warper with the transformer kept per handle) on as many
// plain threads, nothing else. Both runs are repeated and the second of each is reported, so
// GDAL's block cache is equally warm for both.
#include "tools/orbis/Commands.h"

#include "base/Log.h"
#include "base/ThreadPool.h"
#include "globe/TerrainTiles.h"
#include "layers/terrain/TerrainLayer.h"
#include "tools/orbis/Session.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

namespace orbis::cli {

int tileBench(const Args& args, scene::Scene& scene, long level, unsigned threads) {
    const layers::TerrainLayer* terrain = nullptr;
    for (const auto& r : scene.resources())
        if (auto* t = dynamic_cast<const layers::TerrainLayer*>(r.layer.get())) terrain = t;
    if (!terrain) {
        std::fprintf(stderr, "orbis: %s: --tiles needs a terrain layer\n", args.positional()[0].c_str());
        return kBadInput;
    }
    const auto& settings = terrain->settings();
    std::vector<std::shared_ptr<globe::RasterSource>> dems, images;
    globe::GeoExtent coverage{180, 90, -180, -90};
    const auto grow = [&](const globe::RasterSource& s) {
        const auto c = s.coverage();
        coverage = {std::min(coverage.west, c.west), std::min(coverage.south, c.south),
                    std::max(coverage.east, c.east), std::max(coverage.north, c.north)};
    };
    for (const auto& o : settings.elevation)
        if (auto s = globe::RasterSource::open(o)) dems.push_back(*s), grow(**s);
        else std::fprintf(stderr, "orbis: %s\n", s.message().c_str());
    for (const auto& l : settings.imagery)
        if (auto s = globe::RasterSource::open(l.source)) images.push_back(*s), grow(**s);
        else std::fprintf(stderr, "orbis: %s\n", s.message().c_str());
    if (dems.empty() && images.empty()) {
        std::fprintf(stderr, "orbis: %s: the terrain has no readable source\n", args.positional()[0].c_str());
        return kBadInput;
    }
    // The tiles of LEVEL over the sources, nearest the middle first, at most 256.
    std::vector<globe::TileKey> tiles;
    const auto first = globe::TileKey::containing(coverage.west, coverage.north, uint32_t(level));
    const auto last = globe::TileKey::containing(coverage.east, coverage.south, uint32_t(level));
    for (uint32_t y = first.y; y <= last.y; ++y)
        for (uint32_t x = first.x; x <= last.x && tiles.size() < 65536; ++x) tiles.push_back({uint32_t(level), x, y});
    const double cx = coverage.centerLon(), cy = coverage.centerLat();
    std::sort(tiles.begin(), tiles.end(), [&](const globe::TileKey& a, const globe::TileKey& b) {
        const auto da = std::hypot(a.extent().centerLon() - cx, a.extent().centerLat() - cy);
        const auto db = std::hypot(b.extent().centerLon() - cx, b.extent().centerLat() - cy);
        return da < db;
    });
    if (tiles.size() > 256) tiles.resize(256);

    globe::TerrainTilesSettings ms;
    ms.gridSize = settings.gridSize;
    ms.imageSize = settings.imageSize;
    ms.maxLevel = settings.maxLevel;
    ms.cpuBudgetBytes = uint64_t(8) << 30;   // keep everything: the list of loaded tiles is the workload

    const auto runPager = [&](std::vector<globe::DataKey>* loaded) {
        jobs::ThreadPool pool(threads, "orbis-tiles");
        globe::TerrainTiles model(ms, dems, images, &pool);
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
        return std::make_pair(s, model.stats().completed);
    };
    const auto runBare = [&](const std::vector<globe::DataKey>& keys) {
        std::atomic<size_t> next{0};
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::thread> pool;
        for (unsigned i = 0; i < threads; ++i)
            pool.emplace_back([&] {
                for (size_t k; (k = next.fetch_add(1)) < keys.size();) {
                    const auto& key = keys[k];
                    const auto extent = key.tile.extent();
                    if (key.layer == 0) {
                        // The pager's read: the tile's grid with a one-sample border.
                        const double dx = extent.width() / (ms.gridSize - 1), dy = extent.height() / (ms.gridSize - 1);
                        const globe::GeoExtent grown{extent.west - dx, extent.south - dy, extent.east + dx,
                                                     extent.north + dy};
                        for (const auto& s : dems)
                            if (s->covers(extent)) (void)s->readElevation(grown, ms.gridSize + 2);
                    } else if (images[key.layer - 1]->covers(extent)) {
                        (void)images[key.layer - 1]->readImagery(extent, ms.imageSize);
                    }
                }
            });
        for (auto& t : pool) t.join();
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };

    std::vector<globe::DataKey> keys;
    runPager(&keys);
    runBare(keys);
    const auto [pagerSeconds, produced] = runPager(nullptr);
    const double bareSeconds = runBare(keys);
    const double pagerRate = double(produced) / pagerSeconds, bareRate = double(keys.size()) / bareSeconds;
    if (args.flag("--json")) {
        nlohmann::json out{{"scene", args.positional()[0]}, {"level", level}, {"threads", threads},
                           {"tiles", keys.size()}, {"pager_tiles_per_s", pagerRate}, {"bare_tiles_per_s", bareRate},
                           {"ratio", pagerRate / bareRate}};
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        std::printf("orbis bench %s --tiles %ld: %zu tiles of level %ld over the sources, their ancestors and layers "
                    "= %zu loads, %u threads\n",
                    args.positional()[0].c_str(), level, tiles.size(), level, keys.size(), threads);
        std::printf("pager      %8.1f tiles/s  (%.3f s)\n", pagerRate, pagerSeconds);
        std::printf("bare loop  %8.1f tiles/s  (%.3f s)\n", bareRate, bareSeconds);
        std::printf("pager / bare = %.2f\n", pagerRate / bareRate);
    }
    return kOk;
}

}  // namespace orbis::cli
