// COPC 1.0 writing (see CopcWriter.h): read the cloud into packed records in one pass, build the
// octree over their indices, encode a layered LAZ chunk per node (on worker threads, written in
// order), then the chunk table, the hierarchy EVLR and finally the header and VLRs.
#include "layers/points/CopcWriter.h"

#include "layers/points/LasBytes.h"

#include "layers/points/Copc.h"
#include "layers/points/LasReader.h"
#include "layers/points/LazChunks.h"
#include "layers/points/PointOctree.h"

#include <cpl_error.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <limits>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

namespace orbis::points {
namespace {

constexpr uint16_t kHeaderSize = 375;   // LAS 1.4
constexpr uint32_t kInfoBytes = 160;    // the copc info VLR's payload
constexpr uint32_t kEntryBytes = 32;    // a hierarchy entry
constexpr int32_t kDeepest = 30;        // keys hold 2^d cells per axis in an int32 (as Copc.cpp reads)
constexpr uint64_t kSeed = 1;           // the points' keys (as PointOctree's default)

template <typename T>
void put(uint8_t* r, size_t at, T v) {
    std::memcpy(r + at, &v, sizeof(T));
}
template <typename T>
T get(const uint8_t* r, size_t at) {
    T v;
    std::memcpy(&v, r + at, sizeof(T));
    return v;
}

void putString(uint8_t* b, size_t at, const std::string& s, size_t n) { std::memcpy(b + at, s.data(), std::min(n, s.size())); }

/// A VLR (LAS 1.4 R15 Table 13): 54-byte header then the payload.
void vlr(std::vector<uint8_t>& out, const std::string& user, uint16_t id, const std::vector<uint8_t>& payload, const std::string& description) {
    uint8_t h[54] = {};
    putString(h, 2, user, 16);
    put<uint16_t>(h, 18, id);
    put<uint16_t>(h, 20, uint16_t(payload.size()));
    putString(h, 22, description, 32);
    out.insert(out.end(), h, h + 54);
    out.insert(out.end(), payload.begin(), payload.end());
}

/// The CRS as WKT1 (OGC 01-009, what LAS 1.4 and COPC readers parse): kept as it is when it is
/// WKT1 already (a sidecar's ESRI or OGC WKT), else converted by OGR (GeoTIFF keys read as WKT2,
/// "EPSG:n"); the text as it came when OGR cannot express it as WKT1.
std::string wkt1(const std::string& crs) {
    const size_t start = crs.find_first_not_of(" \t\r\n");
    if (start == std::string::npos) return {};
    for (const char* keyword : {"PROJCS[", "GEOGCS[", "GEOCCS[", "COMPD_CS[", "VERT_CS[", "LOCAL_CS["})
        if (crs.compare(start, std::strlen(keyword), keyword) == 0) return crs.substr(start);
    OGRSpatialReference srs;
    CPLPushErrorHandler(CPLQuietErrorHandler);
    std::string out = crs.substr(start);
    if (srs.SetFromUserInput(crs.c_str()) == OGRERR_NONE) {
        char* text = nullptr;
        const char* options[] = {"FORMAT=WKT1_GDAL", nullptr};
        if (srs.exportToWkt(&text, options) == OGRERR_NONE && text && *text) out = text;
        CPLFree(text);
    }
    CPLPopErrorHandler();
    return out;
}

/// An octree node while the tree is built.
struct Node {
    copc::Key key;
    glm::dvec3 centre{0.0};   // its cube's, as copc::cube gives it (the reader's arithmetic)
    uint32_t count = 0;
    uint32_t children[8] = {};   // 0: none (the root is no one's child)
    uint64_t first = 0;   // its points in the permutation
};

/// A file being written; removed unless committed (when it is a file: never a device or a pipe).
struct Output {
    std::string path;
    std::FILE* file = nullptr;
    bool failed = false;
    bool committed = false;
    ~Output() {
        if (file) std::fclose(file);
        std::error_code ec;
        if (!committed && std::filesystem::is_regular_file(path, ec)) std::filesystem::remove(path, ec);
    }
    void write(const void* data, size_t n) {
        if (n > 0 && std::fwrite(data, 1, n, file) != n) failed = true;
    }
};

}  // namespace

Result<CopcWriteStats> writeCopc(const LasFile& in, const std::string& path, const CopcWriteOptions& options) {
    const LasHeader& ih = in.header();
    const uint64_t n = in.points();
    const auto progress = [&](double f) {
        if (options.progress) options.progress(std::clamp(f, 0.0, 1.0));
    };
    if (in.crs().wkt.empty())
        return makeError(path + ": COPC needs a CRS: " + in.path() +
                         " has none (no WKT or GeoTIFF VLR, no .wkt or .prj sidecar); give it one (a sidecar next to it, or convert it with a CRS)");
    if (options.maxNodePoints == 0) return makeError(path + ": a COPC node must hold at least one point (maxNodePoints 0)");
    if (n >= (uint64_t(1) << 32))
        return makeError(path + ": " + in.path() + " has " + std::to_string(n) +
                         " points; Orbis writes COPC in memory, for clouds of fewer than 2^32 points");
    const std::string wkt = wkt1(in.crs().wkt);
    if (wkt.size() + 1 > 65535) return makeError(path + ": the CRS's WKT is too long for a VLR (65 534 bytes at most)");
    const uint32_t maxLevel = std::min<uint32_t>(options.maxLevel, kDeepest);
    const uint8_t format = ih.hasNir() ? 8 : ih.hasRgb() ? 7 : 6;
    const uint16_t recordLength = format == 8 ? 38 : format == 7 ? 36 : 30;
    const glm::dvec3 scale = ih.scale, offset = ih.offset;

    // 1. The points, packed as the output's records, with their bounds, GPS times and returns.
    std::vector<uint8_t> records;
    try {
        records.resize(size_t(n) * recordLength);
    } catch (const std::bad_alloc&) {
        return makeError(path + ": not enough memory for the " + std::to_string(n) + " points of " + in.path() + " (" +
                         std::to_string(n * recordLength >> 20) + " MB)");
    }
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    double gpsMin = std::numeric_limits<double>::max(), gpsMax = -std::numeric_limits<double>::max();
    std::array<uint64_t, 15> byReturn{};
    {
        constexpr uint64_t kBatch = 1u << 19;
        std::vector<LasPoint> batch;
        for (uint64_t first = 0; first < n; first += kBatch) {
            const uint64_t count = std::min(kBatch, n - first);
            if (auto r = in.read(first, count, batch); !r) return makeError(path + ": " + r.message());
            if (batch.size() != count)
                return makeError(path + ": " + in.path() + " gave " + std::to_string(batch.size()) + " points where " + std::to_string(count) +
                                 " were asked (points " + std::to_string(first) + " on; damaged chunks skipped?)");
            for (uint64_t i = 0; i < count; ++i) {
                const LasPoint& p = batch[i];
                const glm::dvec3 q = glm::round((p.position - offset) / scale);
                if (!glm::all(glm::lessThanEqual(glm::abs(q), glm::dvec3(2147483647.0))))
                    return makeError(path + ": point " + std::to_string(first + i) + " of " + in.path() +
                                     " does not fit in 32 bits with the file's scale and offset");
                const int32_t xyz[3] = {int32_t(q.x), int32_t(q.y), int32_t(q.z)};
                packLasRecord(p, xyz, format, records.data() + (first + i) * recordLength);
                // As a reader computes it (LasFile::decodeRecords): the bounds are the written points'.
                const glm::dvec3 at = glm::dvec3(xyz[0], xyz[1], xyz[2]) * scale + offset;
                lo = glm::min(lo, at);
                hi = glm::max(hi, at);
                gpsMin = std::min(gpsMin, p.gpsTime);
                gpsMax = std::max(gpsMax, p.gpsTime);
                if (p.returnNumber >= 1 && p.returnNumber <= 15) ++byReturn[size_t(p.returnNumber - 1)];
            }
            progress(0.3 * double(first + count) / double(n));
        }
    }
    if (n == 0) lo = hi = glm::dvec3(0.0), gpsMin = gpsMax = 0.0;
    const auto position = [&](uint32_t i) {
        const uint8_t* r = records.data() + size_t(i) * recordLength;
        return glm::dvec3(get<int32_t>(r, 0), get<int32_t>(r, 4), get<int32_t>(r, 8)) * scale + offset;
    };

    // 2. The octree. The root cube: centred on the bounds, its half size half the largest extent,
    // snapped so that a reader's arithmetic is exact: the half size rounded up to 11 significant
    // bits (0.1 % more at most), the centre to a multiple of the deepest cells' half size. Every
    // cube's bounds, as copc::cube computes them, are then exact doubles, and the cube a point is
    // sent to (by comparing it with its parent's centre) contains it exactly. That needs the
    // centre's coordinates below 2^(41 - maxLevel) times the half size, so a cloud smaller than
    // that (about 25 cm across at 4000 km from the origin, for maxLevel 16; one point, or all
    // in one place) gets a root of that size.
    copc::Info info;
    {
        const glm::dvec3 extent = hi - lo, middle = 0.5 * (lo + hi);
        const double far = std::max({std::abs(middle.x), std::abs(middle.y), std::abs(middle.z)});
        const double half = std::max({0.5 * std::max({extent.x, extent.y, extent.z}) * (1.0 + 1e-9), std::max({scale.x, scale.y, scale.z}),
                                      std::ldexp(far, int(maxLevel) - 41)});
        const int s = std::ilogb(half) - 10;                    // the half size's last significant bit
        const double q = std::ldexp(1.0, s - int(maxLevel));   // the deepest cells' half size is a multiple of it
        info.centre = glm::round(middle / q) * q;
        info.halfSize = std::ceil((half + q) / std::ldexp(1.0, s)) * std::ldexp(1.0, s);
    }
    info.spacing = 2.0 * info.halfSize / std::sqrt(double(options.maxNodePoints));
    info.gpsTimeMin = gpsMin;
    info.gpsTimeMax = gpsMax;

    std::vector<Node> nodes(1);
    std::vector<uint32_t> permutation;   // node by node, the points' indices (in the input's order in each)
    try {
        // The points in key order: each entry the key's high bits and the index (the low bits, so
        // every entry differs).
        const int indexBits = std::max(1, int(std::bit_width(n > 0 ? n - 1 : 0)));
        const uint64_t indexMask = (uint64_t(1) << indexBits) - 1;
        std::vector<uint32_t> nodeOf(static_cast<size_t>(n));   // by index
        {
            std::vector<uint64_t> order(static_cast<size_t>(n));
            for (uint64_t i = 0; i < n; ++i) order[i] = (pointKey(i, kSeed) & ~indexMask) | i;
            std::sort(order.begin(), order.end());
            progress(0.35);
            double rootHalf = 0.0;
            copc::cube(info, nodes[0].key, nodes[0].centre, rootHalf);
            for (uint64_t k = 0; k < n; ++k) {
                const uint32_t index = uint32_t(order[k] & indexMask);
                const glm::dvec3 p = position(index);
                uint32_t node = 0;
                for (;;) {
                    Node& nd = nodes[node];
                    if (nd.count < options.maxNodePoints || uint32_t(nd.key.d) >= maxLevel) {
                        ++nd.count;
                        break;
                    }
                    const int octant = (p.x >= nd.centre.x ? 1 : 0) | (p.y >= nd.centre.y ? 2 : 0) | (p.z >= nd.centre.z ? 4 : 0);
                    uint32_t child = nd.children[octant];
                    if (child == 0) {
                        Node c;
                        c.key = nd.key.child(octant);
                        double half = 0.0;
                        copc::cube(info, c.key, c.centre, half);
                        child = uint32_t(nodes.size());
                        nd.children[octant] = child;
                        nodes.push_back(c);   // (nd is not used after this)
                    }
                    node = child;
                }
                nodeOf[index] = node;
            }
        }
        uint64_t at = 0;
        for (Node& nd : nodes) {
            nd.first = at;
            at += nd.count;
        }
        std::vector<uint64_t> cursor(nodes.size());
        for (size_t i = 0; i < nodes.size(); ++i) cursor[i] = nodes[i].first;
        // Inside a node, the input's order (LAZ predicts each point from the one before).
        permutation.resize(size_t(n));
        for (uint64_t i = 0; i < n; ++i) permutation[cursor[nodeOf[i]]++] = uint32_t(i);
    } catch (const std::bad_alloc&) {
        return makeError(path + ": not enough memory to order the " + std::to_string(n) + " points of " + in.path());
    }
    for (const Node& nd : nodes)
        if (nd.count > uint32_t(std::numeric_limits<int32_t>::max()))
            return makeError(path + ": node " + std::to_string(nd.key.d) + "-" + std::to_string(nd.key.x) + "-" + std::to_string(nd.key.y) + "-" +
                             std::to_string(nd.key.z) + " would hold " + std::to_string(nd.count) +
                             " points, more than a COPC entry counts; allow a deeper tree (maxLevel)");
    progress(0.4);

    // The nodes with points, level by level: a reader that wants the coarse levels finds them first.
    std::vector<uint32_t> written;
    for (uint32_t i = 0; i < nodes.size(); ++i)
        if (nodes[i].count > 0) written.push_back(i);
    std::sort(written.begin(), written.end(), [&](uint32_t a, uint32_t b) {
        const copc::Key &p = nodes[a].key, &q = nodes[b].key;
        return std::tie(p.d, p.z, p.y, p.x) < std::tie(q.d, q.z, q.y, q.x);
    });

    // 3. The VLRs: the copc info (first, filled in once the hierarchy's place is known), laszip, WKT.
    laz::LaszipVlr z;
    z.compressor = 3;
    z.versionMajor = 3, z.versionMinor = 4, z.versionRevision = 3;
    z.chunkSize = 0xFFFFFFFFu;   // variable: each node's chunk holds its points
    z.items.push_back({laz::ItemType::Point14, 30, 3});
    if (format == 7) z.items.push_back({laz::ItemType::Rgb14, 6, 3});
    if (format == 8) z.items.push_back({laz::ItemType::RgbNir14, 8, 3});
    std::vector<uint8_t> laszip(34 + 6 * z.items.size(), 0);
    put<uint16_t>(laszip.data(), 0, z.compressor);
    laszip[4] = z.versionMajor, laszip[5] = z.versionMinor;
    put<uint16_t>(laszip.data(), 6, z.versionRevision);
    put<uint32_t>(laszip.data(), 12, z.chunkSize);
    put<int64_t>(laszip.data(), 16, -1);   // no special EVLRs
    put<int64_t>(laszip.data(), 24, -1);
    put<uint16_t>(laszip.data(), 32, uint16_t(z.items.size()));
    for (size_t i = 0; i < z.items.size(); ++i) {
        put<uint16_t>(laszip.data(), 34 + 6 * i, uint16_t(z.items[i].type));
        put<uint16_t>(laszip.data(), 36 + 6 * i, z.items[i].size);
        put<uint16_t>(laszip.data(), 38 + 6 * i, z.items[i].version);
    }
    std::vector<uint8_t> head(kHeaderSize, 0);
    vlr(head, "copc", 1, std::vector<uint8_t>(kInfoBytes, 0), "COPC info VLR");
    vlr(head, "laszip encoded", 22204, laszip, "Orbis LAZ (LASzip format)");
    std::vector<uint8_t> text(wkt.begin(), wkt.end());
    text.push_back(0);
    vlr(head, "LASF_Projection", 2112, text, "OGC WKT");
    const uint32_t vlrCount = 3;
    const uint64_t pointOffset = head.size();
    head.resize(head.size() + 8);   // the offset of the chunk table

    Output out{path};
    out.file = std::fopen(path.c_str(), "wb");
    if (!out.file) return makeError(path + ": cannot create the file: " + std::strerror(errno));
    out.write(head.data(), head.size());   // rewritten at the end

    // 4. The chunks: encoded on worker threads, written in order by this one.
    std::vector<laz::Chunk> chunks(written.size());
    uint64_t dataAt = pointOffset + 8;
    {
        const unsigned threads = std::clamp(std::thread::hardware_concurrency(), 1u, 8u);
        const size_t window = 2 * size_t(threads);   // chunks encoded ahead of the writing at most
        std::vector<std::vector<uint8_t>> encoded(written.size());
        std::vector<char> ready(written.size(), 0);
        std::string error;
        size_t next = 0, done = 0;
        bool stop = false;
        std::mutex mutex;
        std::condition_variable cv;
        const auto work = [&] {
            std::vector<uint8_t> gathered, bytes;
            for (;;) {
                size_t i;
                {
                    std::unique_lock lock(mutex);
                    cv.wait(lock, [&] { return stop || next >= written.size() || next < done + window; });
                    if (stop || next >= written.size()) return;
                    i = next++;
                }
                const Node& nd = nodes[written[i]];
                Result<void> r;
                try {
                    gathered.resize(size_t(nd.count) * recordLength);
                    for (uint32_t k = 0; k < nd.count; ++k)
                        std::memcpy(gathered.data() + size_t(k) * recordLength,
                                    records.data() + size_t(permutation[nd.first + k]) * recordLength, recordLength);
                    bytes.clear();
                    r = laz::encodeChunk(z, gathered.data(), nd.count, bytes);
                } catch (const std::bad_alloc&) {
                    r = makeError("not enough memory to encode the " + std::to_string(nd.count) + " points of a node");
                }
                std::lock_guard lock(mutex);
                if (!r) {
                    if (error.empty()) error = r.message();
                    stop = true;
                } else {
                    encoded[i].swap(bytes);
                    ready[i] = 1;
                }
                cv.notify_all();
            }
        };
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work);
        uint64_t pointsWritten = 0;
        for (size_t i = 0; i < written.size(); ++i) {
            std::vector<uint8_t> bytes;
            {
                std::unique_lock lock(mutex);
                cv.wait(lock, [&] { return stop || ready[i]; });
                if (stop) break;
                bytes.swap(encoded[i]);
            }
            const Node& nd = nodes[written[i]];
            out.write(bytes.data(), bytes.size());
            chunks[i] = {dataAt, bytes.size(), nd.count, pointsWritten};
            dataAt += bytes.size();
            pointsWritten += nd.count;
            {
                std::lock_guard lock(mutex);
                ++done;
                if (out.failed) stop = true;
            }
            cv.notify_all();
            progress(0.4 + 0.55 * double(pointsWritten) / double(std::max<uint64_t>(n, 1)));
        }
        {
            std::lock_guard lock(mutex);
            stop = true;
        }
        cv.notify_all();
        for (std::thread& t : pool) t.join();
        if (!error.empty()) return makeError(path + ": " + error);
        if (out.failed) return makeError(path + ": write failed (disk full?)");
        for (const laz::Chunk& c : chunks)
            if (c.bytes > uint64_t(std::numeric_limits<int32_t>::max()))
                return makeError(path + ": a node's chunk is " + std::to_string(c.bytes) + " bytes, more than a COPC entry holds");
    }
    records = {};
    permutation = {};

    // 5. The chunk table, then the hierarchy: one page, in an EVLR.
    const uint64_t tableAt = dataAt;
    std::vector<uint8_t> table;
    laz::encodeChunkTable(z, chunks, table);
    out.write(table.data(), table.size());
    const uint64_t evlrAt = tableAt + table.size();
    // (An empty cloud: one entry, the root's, with no points.)
    const uint64_t pageBytes = uint64_t(kEntryBytes) * std::max<size_t>(written.size(), 1);
    std::vector<uint8_t> evlr(60 + pageBytes, 0);
    putString(evlr.data(), 2, "copc", 16);
    put<uint16_t>(evlr.data(), 18, 1000);
    put<uint64_t>(evlr.data(), 20, pageBytes);
    putString(evlr.data(), 28, "EPT hierarchy", 32);
    for (size_t i = 0; i < written.size(); ++i) {
        const Node& nd = nodes[written[i]];
        uint8_t* e = evlr.data() + 60 + kEntryBytes * i;
        put<int32_t>(e, 0, nd.key.d);
        put<int32_t>(e, 4, nd.key.x);
        put<int32_t>(e, 8, nd.key.y);
        put<int32_t>(e, 12, nd.key.z);
        put<uint64_t>(e, 16, chunks[i].offset);
        put<int32_t>(e, 24, int32_t(chunks[i].bytes));
        put<int32_t>(e, 28, int32_t(nd.count));
    }
    out.write(evlr.data(), evlr.size());
    info.rootPageOffset = evlrAt + 60;
    info.rootPageBytes = pageBytes;

    // 6. The header and the info VLR, now that everything is placed.
    uint8_t* h = head.data();
    putString(h, 0, "LASF", 4);
    put<uint16_t>(h, 6, uint16_t(16 | (ih.globalEncoding & 1)));   // WKT; the GPS time's kind as the input's
    h[24] = 1;
    h[25] = 4;
    putString(h, 26, "Orbis", 32);
    putString(h, 58, "Orbis CopcWriter", 32);
    {
        const std::time_t now = std::time(nullptr);
        std::tm utc{};
        gmtime_r(&now, &utc);
        put<uint16_t>(h, 90, uint16_t(utc.tm_yday + 1));
        put<uint16_t>(h, 92, uint16_t(utc.tm_year + 1900));
    }
    put<uint16_t>(h, 94, kHeaderSize);
    put<uint32_t>(h, 96, uint32_t(pointOffset));
    put<uint32_t>(h, 100, vlrCount);
    h[104] = uint8_t(format | 0x80);   // LASzip's mark of compressed points
    put<uint16_t>(h, 105, recordLength);
    // 107..130: the legacy counts, 0 for formats 6-10.
    for (int a = 0; a < 3; ++a) {
        put<double>(h, 131 + 8 * a, scale[a]);
        put<double>(h, 155 + 8 * a, offset[a]);
        put<double>(h, 179 + 16 * a, hi[a]);
        put<double>(h, 187 + 16 * a, lo[a]);
    }
    put<uint64_t>(h, 227, 0);   // no waveform data
    put<uint64_t>(h, 235, evlrAt);
    put<uint32_t>(h, 243, 1);
    put<uint64_t>(h, 247, n);
    for (int i = 0; i < 15; ++i) put<uint64_t>(h, 255 + 8 * i, byReturn[size_t(i)]);
    uint8_t* c = h + kHeaderSize + 54;
    for (int a = 0; a < 3; ++a) put<double>(c, 8 * size_t(a), info.centre[a]);
    put<double>(c, 24, info.halfSize);
    put<double>(c, 32, info.spacing);
    put<uint64_t>(c, 40, info.rootPageOffset);
    put<uint64_t>(c, 48, info.rootPageBytes);
    put<double>(c, 56, info.gpsTimeMin);
    put<double>(c, 64, info.gpsTimeMax);
    put<int64_t>(h, pointOffset, int64_t(tableAt));
    if (std::fseek(out.file, 0, SEEK_SET) != 0) out.failed = true;
    out.write(head.data(), head.size());
    const bool closed = std::fclose(out.file) == 0;
    out.file = nullptr;
    if (out.failed || !closed) return makeError(path + ": write failed (disk full?)");
    out.committed = true;
    progress(1.0);

    CopcWriteStats stats;
    stats.points = n;
    stats.nodes = uint32_t(written.size());
    for (uint32_t i : written) stats.depth = std::max(stats.depth, uint32_t(nodes[i].key.d));
    stats.bytes = evlrAt + evlr.size();
    return stats;
}

}  // namespace orbis::points
