// Building a PointStore from a LAS file: in memory for small clouds; for large ones, out of
// core in bounded memory (PointCacheBuild.cpp), into a cache file reused by later loads, which
// this file names and keys by what it was built from. Pass 1 (readRecords), the packing and the
// node table are shared by both builds (PointStoreBuild.h).
#include "layers/points/PointStoreBuild.h"

#include "base/Log.h"
#include "globe/Ellipsoid.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace orbis::points {
namespace fs = std::filesystem;

namespace store {

namespace {

/// Spreads the 21 low bits of v to every third bit.
uint64_t spread3(uint64_t v) {
    v &= 0x1FFFFF;
    v = (v | v << 32) & 0x1F00000000FFFFull;
    v = (v | v << 16) & 0x1F0000FF0000FFull;
    v = (v | v << 8) & 0x100F00F00F00F00Full;
    v = (v | v << 4) & 0x10C30C30C30C30C3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

}  // namespace

uint64_t mortonCode(glm::uvec3 q) { return spread3(q.x) | spread3(q.y) << 1 | spread3(q.z) << 2; }

double encodeNode(std::span<const PointRecord> points, std::span<const uint32_t> indices, const Cube& cube,
                  const Packing& packing, std::vector<uint8_t>& out) {
    const size_t n = indices.size();
    const double step = quantisationStep(cube.halfSize);
    const bool quantised = step <= packing.tolerance;
    // Z order: the points of one workgroup land in one small part of the screen, so the splat's
    // 64-bit atomics hit the same cache lines instead of scattering over the frame.
    std::vector<uint32_t> sorted;
    if (packing.morton && n > 1) {
        std::vector<std::pair<uint64_t, uint32_t>> keyed(n);
        for (size_t k = 0; k < n; ++k) {
            const glm::dvec3 q = glm::clamp(glm::round((points[indices[k]].ecef - cube.centre) / step) + double(kQuantisedCentre), 0.0,
                                            double((1u << kQuantisedBits) - 1));
            keyed[k] = {mortonCode(glm::uvec3(q)), indices[k]};
        }
        std::sort(keyed.begin(), keyed.end());
        sorted.resize(n);
        for (size_t k = 0; k < n; ++k) sorted[k] = keyed[k].second;
        indices = sorted;
    }
    const size_t at = out.size();
    out.resize(at + n * (quantised ? 16 : 20));
    uint8_t* attrs = out.data() + at;
    uint8_t* pos = attrs + 8 * n;
    const auto& ell = globe::Ellipsoid::wgs84();
    for (size_t k = 0; k < n; ++k) {
        const PointRecord& p = points[indices[k]];
        const double h = ell.toGeodetic(p.ecef).height;
        const double f = std::clamp((h - packing.heightMin) / packing.heightSpan, 0.0, 1.0);
        const uint32_t a[2] = {p.rgbClass, (p.intensity & 0xFFFFu) | uint32_t(std::lround(f * 65535.0)) << 16};
        std::memcpy(attrs + 8 * k, a, sizeof a);
        const glm::dvec3 rel = p.ecef - cube.centre;
        if (quantised) {
            const glm::dvec3 q = glm::clamp(glm::round(rel / step) + double(kQuantisedCentre), 0.0,
                                            double((1u << kQuantisedBits) - 1));
            uint32_t w[2];
            packPosition(glm::uvec3(q), w[0], w[1]);
            std::memcpy(pos + 8 * k, w, sizeof w);
        } else {
            const float v[3] = {float(rel.x), float(rel.y), float(rel.z)};
            std::memcpy(pos + 12 * k, v, sizeof v);
        }
    }
    return quantised ? step : 0.0;
}

}  // namespace store

namespace build {

Error cancelled(const LasFile& file) { return Error{std::string(file.path()).append(": loading cancelled")}; }

Result<Statistics> readRecords(const LasFile& file, const PointGeoreference& georef, const PointLoadOptions& options,
                               double progressTo, const RecordSink& sink) {
    const LasHeader& h = file.header();
    Statistics s;
    s.info.read = file.points();
    s.info.rgb = h.hasRgb() ? 1 : 0;
    const uint64_t n = file.points(), per = std::max<uint64_t>(1, options.pointsPerRead);
    const auto& ell = globe::Ellipsoid::wgs84();
    std::vector<uint32_t> intensityHistogram(65536, 0);
    std::vector<LasPoint> batch;
    std::vector<glm::dvec3> xyz;
    std::vector<PointRecord> records;
    double hMin = std::numeric_limits<double>::max(), hMax = -hMin;
    for (uint64_t first = 0; first < n; first += per) {
        if (options.cancel && options.cancel->load()) return cancelled(file);
        if (auto r = file.read(first, per, batch); !r) return r.error();
        // Colours stored in 8 bits inside the 16-bit fields are common: decided on the first batch.
        if (first == 0 && s.info.rgb)
            for (const LasPoint& p : batch) s.info.rgb16 |= std::max({p.red, p.green, p.blue}) > 255 ? 1 : 0;
        xyz.resize(batch.size());
        for (size_t i = 0; i < batch.size(); ++i) xyz[i] = batch[i].position;
        georef.toEcef(xyz);
        records.clear();
        for (size_t i = 0; i < batch.size(); ++i) {
            const LasPoint& p = batch[i];
            ++intensityHistogram[p.intensity];
            if (!std::isfinite(xyz[i].x) || !std::isfinite(xyz[i].y) || !std::isfinite(xyz[i].z)) {
                ++s.info.dropped;
                continue;
            }
            const double height = ell.toGeodetic(xyz[i]).height;
            hMin = std::min(hMin, height), hMax = std::max(hMax, height);
            s.lo = glm::min(s.lo, xyz[i]), s.hi = glm::max(s.hi, xyz[i]);
            const auto channel = [&](uint16_t v) { return uint32_t(s.info.rgb16 ? v >> 8 : std::min<uint16_t>(v, 255)); };
            const uint32_t rgb = s.info.rgb ? channel(p.red) | channel(p.green) << 8 | channel(p.blue) << 16 : 0xFFFFFFu;
            records.push_back({xyz[i], rgb | uint32_t(p.classification) << 24, p.intensity, first + i});
        }
        s.kept += records.size();
        if (auto r = sink(std::span<const PointRecord>(records)); !r) return r.error();
        if (options.progress) options.progress(progressTo * double(std::min(n, first + per)) / double(n));
    }
    if (hMin > hMax) hMin = hMax = 0.0;
    s.info.heightMin = hMin, s.info.heightMax = hMax;
    // Intensity gain: the 99th percentile maps to white (a few bright returns do not grey out the rest).
    uint64_t seen = 0, p99 = 0;
    for (uint32_t v = 0; v < 65536; ++v) {
        seen += intensityHistogram[v];
        if (seen * 100 >= n * 99) {
            p99 = v;
            break;
        }
    }
    s.info.intensityGain = 1.0f / float(std::max<uint64_t>(p99, 1));
    s.info.points = s.kept;
    return s;
}

store::Packing packingFor(const Statistics& s, double tolerance, bool morton) {
    store::Packing p;
    p.heightMin = s.info.heightMin;
    p.heightSpan = s.info.heightMax > s.info.heightMin ? s.info.heightMax - s.info.heightMin : 1.0;
    p.tolerance = tolerance;
    p.morton = morton;
    return p;
}

/// Appends the nodes of `tree` (built over `points`) to `nodes`, their data to `data` (its
/// size so far is where they start); the subtree's root gets `parent`. Returns the root's index.
int32_t appendTree(const PointOctree& tree, std::span<const PointRecord> points, const store::Packing& packing, int32_t parent,
                   uint64_t dataBase, std::vector<StoredNode>& nodes, std::vector<uint8_t>& data) {
    const int32_t base = int32_t(nodes.size());
    for (const OctreeNode& o : tree.nodes()) {
        StoredNode s;
        s.centre = o.centre;
        s.halfSize = o.halfSize;
        s.level = o.level;
        s.count = o.count;
        s.offset = dataBase + data.size();
        s.parent = o.parent >= 0 ? base + o.parent : parent;
        for (int c = 0; c < 8; ++c) s.children[c] = o.children[c] >= 0 ? base + o.children[c] : -1;
        const size_t at = data.size();
        s.step = store::encodeNode(points, std::span(tree.order()).subspan(o.first, o.count), o.cube(), packing, data);
        s.crc = store::checksum(data.data() + at, data.size() - at);
        nodes.push_back(s);
    }
    return base;
}

}  // namespace build

namespace {

using namespace build;

/// Everything in memory (small clouds).
Result<std::shared_ptr<PointStore>> buildInMemory(const LasFile& file, const PointGeoreference& georef,
                                                  const PointLoadOptions& options, double tolerance) {
    std::vector<PointRecord> records;
    records.reserve(file.points());
    auto stats = readRecords(file, georef, options, 0.8, [&](std::span<const PointRecord> r) -> Result<void> {
        records.insert(records.end(), r.begin(), r.end());
        return {};
    });
    if (!stats) return stats.error();
    const PointOctree tree = PointOctree::build(records, options.octree);
    std::vector<StoredNode> nodes;
    std::vector<uint8_t> data;
    appendTree(tree, records, packingFor(*stats, tolerance, options.mortonOrder), -1, 0, nodes, data);
    stats->info.depth = tree.depth();
    stats->info.tolerance = float(tolerance);
    if (options.progress) options.progress(1.0);
    return PointStore::inMemory(std::move(nodes), std::move(data), stats->info);
}

std::string hex(uint64_t v) {
    char t[17];
    std::snprintf(t, sizeof t, "%016llx", static_cast<unsigned long long>(v));
    return t;
}

bool folderWritable(const std::string& folder) { return ::access(folder.c_str(), W_OK) == 0; }

}  // namespace

std::string defaultPointCacheDir() {
    if (const char* d = std::getenv("ORBIS_CACHE_DIR"); d && *d) return (fs::path(d) / "points").string();
    if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return (fs::path(d) / "orbis" / "points").string();
    if (const char* d = std::getenv("HOME"); d && *d) return (fs::path(d) / ".cache" / "orbis" / "points").string();
    std::error_code ec;
    return (fs::temp_directory_path(ec) / "orbis-points-cache").string();
}

Result<std::shared_ptr<PointStore>> loadPointStore(const LasFile& file, const PointGeoreference& georef,
                                                   const PointLoadOptions& options) {
    // Quantised where that keeps within half the file's own coordinate grid (at most 1 cm).
    double tolerance = 0.5 * georef.resolutionMetres(file);
    if (!std::isfinite(tolerance)) tolerance = 0.0005;
    tolerance = std::clamp(tolerance, 1e-6, 0.01);
    if (file.points() <= options.inMemoryPoints) return buildInMemory(file, georef, options, tolerance);

    // The cache: where, and what it must have been built from.
    std::error_code ec;
    const fs::path las = fs::absolute(file.path(), ec);
    const auto size = fs::file_size(las, ec);
    const auto modified = fs::last_write_time(las, ec).time_since_epoch().count();
    char opts[160];
    std::snprintf(opts, sizeof opts, "capacity %u, maxLevel %u, seed %llu, tolerance %.9g m, order %s", options.octree.capacity,
                  options.octree.maxLevel, static_cast<unsigned long long>(options.octree.seed), tolerance,
                  options.mortonOrder ? "morton" : "key");
    const std::string key = std::string("Orbis point cache\nfile: ")
                                .append(las.string())
                                .append("\nsize: ")
                                .append(std::to_string(size))
                                .append("\nmodified: ")
                                .append(std::to_string(modified))
                                .append("\nplacement: ")
                                .append(georef.description())
                                .append("\noctree: ")
                                .append(opts)
                                .append("\n");
    std::string folder = options.cacheFolder, name;
    if (folder.empty() && folderWritable(las.parent_path().string())) {
        folder = las.parent_path().string();
        name = las.filename().string().append(".orbis-points");
    } else {
        if (folder.empty()) folder = defaultPointCacheDir();
        name = las.stem().string().append("-").append(hex(std::hash<std::string>{}(las.string()))).append(".orbis-points");
    }
    fs::create_directories(folder, ec);
    const std::string path = (fs::path(folder) / name).string();
    if (fs::exists(path, ec)) {
        auto opened = PointStore::open(path, key);
        if (opened) {
            if (options.progress) options.progress(1.0);
            return opened;
        }
        log::info(opened.message(), "; building it again");
    }
    log::info(file.path(), ": ", file.points(), " points: building the octree cache ", path);
    BuildContext ctx{file, georef, options, folder, name};
    const auto start = std::chrono::steady_clock::now();
    if (auto built = buildCacheFile(ctx, path, key, tolerance); !built) {
        if (options.cancel && options.cancel->load()) return built.error();
        // A folder that is read-only or full: go on without the cache while the cloud fits in
        // memory (the temporary files are gone; nothing half written keeps the cache's name).
        if (file.points() > options.fallbackInMemoryPoints)
            return makeError(std::string(file.path()).append(": building the point cache failed: ").append(built.message())
                                 .append(" (the cloud is too large to load without it: give the layer a writable \"cacheFolder\")"));
        log::warn(file.path(), ": cannot write the point cache (", built.message(), "): loading the cloud in memory without it");
        return buildInMemory(file, georef, options, tolerance);
    }
    auto opened = PointStore::open(path, key);
    if (opened) {
        char text[160];
        std::snprintf(text, sizeof text, ": octree built in %.1f s: %zu nodes, depth %u, %.0f MB", 
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                      (*opened)->nodes().size(), (*opened)->info().depth, double(fs::file_size(path, ec)) / 1048576.0);
        log::info(file.path(), text);
    }
    return opened;
}

}  // namespace orbis::points
