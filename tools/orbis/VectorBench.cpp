// orbis bench --vector FILE [--level L] [--runs N]: the vector layer's CPU work on a file, no
// GPU: reading every feature through OGR into lon/lat features, triangulating every polygon (a
// ring around a pole closed through it), cutting every feature into the quadtree's tiles of
// level L (default 14), reading the middle tile of level L alone (through OGR's spatial
// filter), and simplifying it for the texel of a 256-pixel tile at levels 4, 8, 12
// and 16. Each step runs N times (default 3): median, min and p95 in ms, the counts, and the
// memory the features hold (resident set growth after the read).
#include "tools/orbis/BenchModes.h"

#include "layers/vector/FeatureClip.h"
#include "layers/vector/FeatureTiles.h"
#include "layers/vector/Simplify.h"
#include "layers/vector/Triangulate.h"
#include "layers/vector/VectorReader.h"
#include "tools/orbis/BenchMemory.h"
#include "tools/orbis/BenchStats.h"
#include "tools/orbis/Session.h"

#include <chrono>
#include <cstdio>
#include <functional>
#include <vector>

namespace orbis::cli {
namespace {

/// The step's milliseconds over `runs` runs.
Stats timeRuns(long runs, const std::function<void()>& step) {
    std::vector<double> ms;
    for (long r = 0; r < runs; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        step();
        ms.push_back(millisecondsSince(t0));
    }
    return summarize(std::move(ms));
}

/// Triangles of every polygon of the layers (in the lon/lat plane).
size_t triangulateAll(const vector::VectorData& data, size_t& forced) {
    size_t triangles = 0;
    std::vector<glm::dvec2> points;
    std::vector<uint32_t> starts;
    for (const vector::VectorLayer& layer : data.layers)
        for (const vector::Feature& f : layer.features)
            for (size_t k = 0; k < f.polygons.size(); ++k) {
                points.clear();
                starts.clear();
                for (size_t p = f.polygons[k]; p < f.polygonEnd(k); ++p) {
                    starts.push_back(uint32_t(points.size()));
                    std::vector<glm::dvec3> ring(f.coords.begin() + f.parts[p], f.coords.begin() + f.partEnd(p));
                    vector::closeThroughPole(ring, f.containsPole[p]);   // a ring around a pole bounds its cap
                    for (const glm::dvec3& c : ring) points.emplace_back(c);
                }
                vector::TriangulateStats stats;
                if (auto tris = vector::triangulate(points, starts, 10'000'000, &stats)) triangles += tris->size() / 3;
                forced += stats.forced;
            }
    return triangles;
}

}  // namespace

int vectorBench(const std::string& file, long level, long runs) {
    vector::VectorReadOptions options;
    options.source = file;
    // The memory of one read (before the timed runs, which replace it).
    const uint64_t rssBefore = currentRssBytes();
    Result<vector::VectorData> data = vector::readVector(options);
    if (!data) return badInput(data.message());
    const uint64_t rssAfter = currentRssBytes();
    const Stats read = timeRuns(runs, [&] {
        data = makeError("not read");
        data = vector::readVector(options);
    });
    if (!data) return badInput(data.message());
    size_t features = 0, vertices = 0;
    for (const auto& layer : data->layers) features += layer.features.size(), vertices += layer.vertexCount;

    size_t triangles = 0, forced = 0;
    const Stats cut = timeRuns(runs, [&] {
        forced = 0;
        triangles = triangulateAll(*data, forced);
    });
    size_t tiles = 0, pieces = 0;
    const Stats tiling = timeRuns(runs, [&] {
        tiles = pieces = 0;
        for (const auto& layer : data->layers)
            for (const vector::Feature& f : layer.features)
                for (const globe::TileKey& key : vector::tilesCovering(f, uint32_t(level))) {
                    ++tiles;
                    pieces += vector::clipFeature(f, key.extent()) ? 1 : 0;
                }
    });
    std::printf("orbis bench --vector %s  (CPU only, one thread, %ld runs)\n", file.c_str(), runs);
    std::printf("%zu layers, %zu features, %zu vertices; features hold %.1f MB (resident set growth)\n", data->layers.size(),
                features, vertices, double(rssAfter > rssBefore ? rssAfter - rssBefore : 0) / (1024.0 * 1024.0));
    std::printf("%-34s %10s %10s %10s\n", "step", "median ms", "min", "p95");
    std::printf("%-34s %10.1f %10.1f %10.1f\n", "read (OGR to lon/lat features)", read.median, read.min, read.p95);
    std::printf("%-34s %10.1f %10.1f %10.1f   %zu triangles, %zu forced ears\n", "triangulate every polygon", cut.median, cut.min,
                cut.p95, triangles, forced);
    std::printf("%-34s %10.1f %10.1f %10.1f   %zu tiles of level %ld met, %zu pieces\n", "cut into tiles", tiling.median, tiling.min,
                tiling.p95, tiles, level, pieces);
    // One feature tile read on its own (OGR's spatial filter: a spatial index reads only what is
    // near), the tile of level L at the middle of the data.
    if (!data->layers.empty() && !data->layers[0].bounds.empty) {
        const vector::LonLatBounds& b = data->layers[0].bounds;
        double lon = 0.5 * (b.west + b.east);
        if (lon >= 180.0) lon -= 360.0;
        const globe::TileKey key = globe::TileKey::containing(lon, 0.5 * (b.south + b.north), uint32_t(level));
        const globe::GeoExtent e = key.extent();
        vector::VectorReadOptions tileOptions = options;
        tileOptions.within = vector::LonLatBounds{.west = e.west, .south = e.south, .east = e.east, .north = e.north, .empty = false};
        size_t tileFeatures = 0;
        const Stats tileRead = timeRuns(runs, [&] {
            auto tile = vector::readVector(tileOptions);
            tileFeatures = 0;
            if (tile)
                for (const auto& layer : tile->layers) tileFeatures += layer.features.size();
        });
        char label[64];
        std::snprintf(label, sizeof label, "read tile %s alone", key.toString().c_str());
        std::printf("%-34s %10.1f %10.1f %10.1f   %zu features\n", label, tileRead.median, tileRead.min, tileRead.p95, tileFeatures);
        // The same tile as the pager reads it: its box grown by the margin, each feature clipped
        // (and styled, timed) as it is read.
        vector::FeatureTilesOptions pageOptions;
        pageOptions.content.read = options;
        pageOptions.pageLevel = uint32_t(level);
        size_t pageFeatures = 0;
        const Stats pageRead = timeRuns(runs, [&] {
            auto page = vector::loadFeatureTile(pageOptions, key);
            pageFeatures = page ? size_t(page->content->featureCount) : 0;
        });
        std::printf("%-34s %10.1f %10.1f %10.1f   %zu features\n", "read it as a page (grown, clipped)", pageRead.median, pageRead.min,
                    pageRead.p95, pageFeatures);
    }
    // Simplification for a 256-pixel tile's texel at a few levels: what it keeps, and its cost.
    std::printf("%-34s %10s %10s %10s   %s\n", "simplify to a 256-px tile's texel", "median ms", "min", "p95", "vertices kept");
    for (int simplifyLevel : {4, 8, 12, 16}) {
        const double texelDeg = 180.0 / double(1u << simplifyLevel) / 256.0;
        size_t kept = 0;
        const Stats simplify = timeRuns(runs, [&] {
            kept = 0;
            for (const auto& layer : data->layers)
                for (const vector::Feature& f : layer.features)
                    if (auto s = vector::simplifyFeature(f, texelDeg)) kept += s->coords.size();
        });
        char label[64];
        std::snprintf(label, sizeof label, "  level %d (%.2g deg)", simplifyLevel, texelDeg);
        std::printf("%-34s %10.1f %10.1f %10.1f   %zu (%.1f %%)\n", label, simplify.median, simplify.min, simplify.p95, kept,
                    vertices ? 100.0 * double(kept) / double(vertices) : 0.0);
    }
    return kOk;
}

}  // namespace orbis::cli
