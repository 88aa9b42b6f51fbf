// The point store: positions decode within the quantisation step (or float precision); the
// out-of-core build, chunk by chunk through the cache file, makes the same tree as the
// in-memory build, node for node and byte for byte; the cache is reused while it matches its
// file and options and rebuilt when not; damaged caches give clear errors; residency evicts
// the least recently wanted nodes and reuses their room only after the frames in flight.
#include "globe/Ellipsoid.h"
#include "layers/points/NodeResidency.h"
#include "layers/points/PointCloud.h"
#include "layers/points/PointStoreFormat.h"
#include "tests/support/ProcessTempDir.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstddef>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <thread>

namespace orbis::points {
namespace {
namespace fs = std::filesystem;

fs::path tempDir() { return test::processTempDir("orbis-pointstore"); }

// A survey in local metres (east, north, up of an origin): a wavy ground 300 m x 200 m, a
// tower of points, and a dense patch; scale 1 mm.
std::string writeSurvey(const std::string& name, size_t n, uint32_t seed) {
    const std::string path = (tempDir() / name).string();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<LasPoint> pts(n);
    for (size_t i = 0; i < n; ++i) {
        LasPoint& p = pts[i];
        const double kind = u(rng);
        if (kind < 0.8) {
            const double e = 300 * u(rng), nn = 200 * u(rng);
            p.position = {e, nn, 5 * std::sin(e * 0.05) * std::cos(nn * 0.03)};
        } else if (kind < 0.9) {
            p.position = {150 + 2 * u(rng), 100 + 2 * u(rng), 80 * u(rng)};
        } else {
            p.position = {20 + u(rng), 20 + u(rng), 0.1 * u(rng)};
        }
        p.intensity = uint16_t(i % 4000);
        p.classification = uint8_t(2 + i % 4);
        p.red = uint16_t(i * 7), p.green = uint16_t(i * 13), p.blue = uint16_t(i * 17);
    }
    LasWriteOptions o;
    o.pointFormat = 2;
    o.scale = glm::dvec3(0.001);
    auto w = LasWriter::create(path, o);
    EXPECT_TRUE(w.ok()) << w.message();
    if (!w) return path;
    (*w)->write(pts);
    auto closed = (*w)->close();
    EXPECT_TRUE(closed.ok()) << closed.message();
    return path;
}

struct Loaded {
    std::unique_ptr<LasFile> file;
    std::shared_ptr<PointStore> store;
};

Loaded load(const std::string& path, PointLoadOptions o) {
    Loaded l;
    auto file = LasFile::open(path);
    EXPECT_TRUE(file.ok()) << file.message();
    if (!file) return l;
    l.file = std::move(*file);
    PointPlacement placement;
    placement.origin = globe::Geodetic{179.99, -45.0, 300.0};
    auto georef = PointGeoreference::create(*l.file, placement);
    EXPECT_TRUE(georef.ok());
    auto store = loadPointStore(*l.file, *georef, o);
    EXPECT_TRUE(store.ok()) << store.message();
    if (store) l.store = *store;
    return l;
}

PointLoadOptions smallChunks(const fs::path& cache) {
    PointLoadOptions o;
    o.octree.capacity = 500;
    o.inMemoryPoints = 0;          // out of core
    o.chunkPoints = 1;             // chunks of at least 8 x 500 points
    o.pointsPerRead = 7000;        // several reads
    o.cacheFolder = cache.string();
    return o;
}

std::vector<uint8_t> nodeData(const PointStore& s, size_t i) {
    std::vector<uint8_t> d;
    EXPECT_TRUE(s.read(i, d));
    return d;
}

TEST(PointStore, OutOfCoreBuildIsTheInMemoryTree) {
    const std::string las = writeSurvey("equal.las", 60000, 3);
    PointLoadOptions memory;
    memory.octree.capacity = 500;
    const Loaded a = load(las, memory);
    const fs::path cache = tempDir() / "cache-equal";
    const Loaded b = load(las, smallChunks(cache));
    ASSERT_TRUE(a.store && b.store);
    EXPECT_FALSE(a.store->onDisk());
    EXPECT_TRUE(b.store->onDisk());
    EXPECT_EQ(fs::path(b.store->path()).parent_path(), cache);
    EXPECT_EQ(a.store->info().points, 60000u);
    EXPECT_EQ(b.store->info().points, 60000u);
    EXPECT_EQ(a.store->info().heightMin, b.store->info().heightMin);
    EXPECT_EQ(a.store->info().intensityGain, b.store->info().intensityGain);
    EXPECT_EQ(a.store->info().depth, b.store->info().depth);
    ASSERT_EQ(a.store->nodes().size(), b.store->nodes().size());
    EXPECT_GT(a.store->nodes().size(), 100u);
    // The same nodes (by level and centre), holding the same points in the same order.
    std::map<std::tuple<uint32_t, double, double, double>, size_t> byCube;
    for (size_t i = 0; i < b.store->nodes().size(); ++i) {
        const StoredNode& n = b.store->nodes()[i];
        byCube[{n.level, n.centre.x, n.centre.y, n.centre.z}] = i;
    }
    for (size_t i = 0; i < a.store->nodes().size(); ++i) {
        const StoredNode& n = a.store->nodes()[i];
        auto it = byCube.find({n.level, n.centre.x, n.centre.y, n.centre.z});
        ASSERT_NE(it, byCube.end()) << "node " << i << " (level " << n.level << ") missing from the out-of-core tree";
        const StoredNode& m = b.store->nodes()[it->second];
        EXPECT_EQ(n.count, m.count);
        EXPECT_EQ(n.step, m.step);
        EXPECT_EQ(nodeData(*a.store, i), nodeData(*b.store, it->second)) << "node " << i;
        int children = 0;
        for (int c = 0; c < 8; ++c) children += (n.children[c] >= 0) == (m.children[c] >= 0) ? 1 : 0;
        EXPECT_EQ(children, 8);
    }
}

TEST(PointStore, PositionsDecodeWithinTheirStep) {
    const std::string las = writeSurvey("decode.las", 20000, 5);
    PointLoadOptions o;
    o.octree.capacity = 2000;
    const Loaded l = load(las, o);
    ASSERT_TRUE(l.store);
    // Tolerance: half the file's 1 mm grid.
    EXPECT_NEAR(l.store->info().tolerance, 0.0005, 1e-5);
    // Every point of the file is in one node, where the file puts it.
    const auto& ell = globe::Ellipsoid::wgs84();
    const glm::dvec3 origin = ell.toEcef(179.99, -45.0, 300.0);
    const glm::dmat3 enu = ell.enuFrame(179.99, -45.0);
    std::vector<glm::dvec3> expected;
    ASSERT_TRUE(l.file->readPositions(0, l.file->points(), expected).ok());
    std::multimap<double, glm::dvec3> byX;
    for (const glm::dvec3& p : expected) {
        const glm::dvec3 e = origin + enu * p;
        byX.insert({e.x, e});
    }
    size_t quantised = 0, total = 0;
    for (const StoredNode& n : l.store->nodes()) {
        std::vector<uint8_t> d;
        ASSERT_TRUE(l.store->read(size_t(&n - l.store->nodes().data()), d));
        const double tolerance = n.step > 0.0 ? 0.87 * n.step + 1e-9 : 1e-4;
        quantised += n.step > 0.0 ? 1 : 0;
        for (uint32_t k = 0; k < n.count; ++k, ++total) {
            const glm::dvec3 p = PointStore::position(n, d, k);
            double best = 1e9;
            for (auto it = byX.lower_bound(p.x - 0.01); it != byX.end() && it->first <= p.x + 0.01; ++it)
                best = std::min(best, glm::length(it->second - p));
            ASSERT_LT(best, tolerance) << "point " << k << " of a node at level " << n.level << ", step " << n.step;
        }
    }
    EXPECT_EQ(total, 20000u);
    EXPECT_GT(quantised, 0u);
}

TEST(PointStore, LargeNodesKeepFloatPositions) {
    // A node 100 km across quantised to 21 bits would step 5 cm: above a 1 mm file's
    // tolerance, so it stays float; a 10 m node is quantised.
    std::vector<PointRecord> pts(3);
    pts[0].ecef = {6378137.0, 0.0, 0.0};
    pts[1].ecef = {6378137.0 + 1234.5678, 10.0, -20.0};
    pts[2].ecef = {6378137.0 - 3.25, 1.0, 2.0};
    const uint32_t idx[3] = {0, 1, 2};
    store::Packing packing;
    packing.tolerance = 0.0005;
    packing.morton = false;   // the points in the order given (Z order: the next test)
    for (double half : {50000.0, 5.0}) {
        Cube cube{pts[0].ecef, half, 0};
        std::vector<uint8_t> data;
        StoredNode n;
        n.centre = cube.centre, n.halfSize = half, n.count = half > 10 ? 3 : 1;
        n.step = store::encodeNode(pts, std::span(idx, n.count), cube, packing, data);
        EXPECT_EQ(data.size(), n.bytes());
        EXPECT_EQ(n.step > 0.0, half < 10.0);
        for (uint32_t k = 0; k < n.count; ++k)
            EXPECT_LT(glm::length(PointStore::position(n, data, k) - pts[k].ecef), half < 10.0 ? 1e-5 : 1e-3);
    }
}

// In Z order a node holds the same points, sorted by the Morton code of their grid cells: points
// next to each other in memory are next to each other in space.
TEST(PointStore, MortonOrderKeepsEveryPointAndSortsThem) {
    std::vector<PointRecord> pts(2000);
    uint32_t seed = 3;
    const auto next = [&] { return double((seed = seed * 1664525u + 1013904223u) >> 8) / double(1u << 24); };
    const Cube cube{{6378137.0, 0.0, 0.0}, 8.0, 0};
    std::vector<uint32_t> idx(pts.size());
    for (size_t k = 0; k < pts.size(); ++k) {
        pts[k].ecef = cube.centre + (glm::dvec3(next(), next(), next()) * 2.0 - 1.0) * 7.9;
        pts[k].intensity = uint32_t(k);
        idx[k] = uint32_t(k);
    }
    store::Packing packing;
    packing.tolerance = 0.001;
    std::vector<uint8_t> data;
    StoredNode n;
    n.centre = cube.centre, n.halfSize = cube.halfSize, n.count = uint32_t(pts.size());
    n.step = store::encodeNode(pts, idx, cube, packing, data);
    ASSERT_GT(n.step, 0.0);
    std::vector<bool> seen(pts.size(), false);
    uint64_t last = 0;
    double travelled = 0.0, randomTravel = 0.0;
    for (uint32_t k = 0; k < n.count; ++k) {
        uint32_t a[2];
        std::memcpy(a, data.data() + 8 * size_t(k), sizeof a);
        const uint32_t i = a[1] & 0xFFFFu;   // the intensity says which point it is
        ASSERT_LT(i, pts.size());
        EXPECT_FALSE(seen[i]);
        seen[i] = true;
        const glm::dvec3 p = PointStore::position(n, data, k);
        EXPECT_LT(glm::length(p - pts[i].ecef), 1e-3);
        const uint64_t code = store::mortonCode(glm::uvec3(glm::round((p - cube.centre) / n.step) + double(store::kQuantisedCentre)));
        EXPECT_GE(code, last);
        last = code;
        if (k > 0) {
            travelled += glm::length(p - PointStore::position(n, data, k - 1));
            randomTravel += glm::length(pts[k].ecef - pts[k - 1].ecef);
        }
    }
    // Walking the node in memory order stays local: far less distance than the random order.
    EXPECT_LT(travelled, randomTravel / 5.0);
    EXPECT_EQ(store::mortonCode({1, 0, 0}), 1u);
    EXPECT_EQ(store::mortonCode({0, 1, 0}), 2u);
    EXPECT_EQ(store::mortonCode({0, 0, 1}), 4u);
    EXPECT_EQ(store::mortonCode({0x1FFFFF, 0x1FFFFF, 0x1FFFFF}), (uint64_t(1) << 63) - 1);
}

TEST(PointStore, CacheIsReusedAndRebuiltWhenStale) {
    const std::string las = writeSurvey("reuse.las", 30000, 9);
    const fs::path cache = tempDir() / "cache-reuse";
    PointLoadOptions o = smallChunks(cache);
    std::string path;
    {
        const Loaded first = load(las, o);
        ASSERT_TRUE(first.store);
        path = first.store->path();
    }
    const auto built = fs::last_write_time(path);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    {
        const Loaded second = load(las, o);   // reused: not written again
        ASSERT_TRUE(second.store);
        EXPECT_EQ(fs::last_write_time(path), built);
    }
    {
        PointLoadOptions other = o;   // other options: another tree, built again
        other.octree.seed = 2;
        const Loaded third = load(las, other);
        ASSERT_TRUE(third.store);
        EXPECT_NE(fs::last_write_time(path), built);
    }
    // A damaged cache (cut short) is rebuilt, not trusted.
    fs::resize_file(path, fs::file_size(path) - 100);
    const Loaded fourth = load(las, o);
    ASSERT_TRUE(fourth.store);
    EXPECT_EQ(fourth.store->info().points, 30000u);
    // No temporary files are left behind.
    for (const auto& e : fs::directory_iterator(cache)) EXPECT_EQ(e.path().extension(), ".orbis-points") << e.path();
}

TEST(PointStore, DamagedCachesGiveClearErrors) {
    const std::string las = writeSurvey("damaged.las", 20000, 11);
    const fs::path cache = tempDir() / "cache-damaged";
    const Loaded l = load(las, smallChunks(cache));
    ASSERT_TRUE(l.store);
    const std::string good = l.store->path();
    std::ifstream in(good, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    store::FileHeader header;
    std::memcpy(&header, bytes.data(), sizeof header);
    std::string key(bytes.data() + sizeof header, header.keyBytes);
    // A change that keeps the checksum right (a file written wrongly, not damaged later) must
    // still be caught by the structural checks.
    const auto resealed = [&](const std::function<void(std::vector<char>&)>& change) {
        return [&, change](std::vector<char>& b) {
            change(b);
            store::FileHeader h;
            std::memcpy(&h, b.data(), sizeof h);
            std::vector<StoredNode> table(h.nodeCount);
            std::memcpy(table.data(), b.data() + h.nodeTableOffset, table.size() * sizeof(StoredNode));
            h.tableCrc = store::tableChecksum(h, key, table);
            std::memcpy(b.data(), &h, sizeof h);
        };
    };
    const auto damaged = [&](const std::function<void(std::vector<char>&)>& change) {
        std::vector<char> b = bytes;
        change(b);
        const std::string path = (cache / "damaged.bin").string();
        std::ofstream(path, std::ios::binary).write(b.data(), std::streamsize(b.size()));
        auto r = PointStore::open(path, key);
        EXPECT_FALSE(r.ok());
        return r.ok() ? std::string() : r.message();
    };
    EXPECT_NE(damaged([](auto& b) { b[0] = 'X'; }).find("not an Orbis point cache"), std::string::npos);
    EXPECT_NE(damaged([](auto& b) { b.resize(100); }).find("shorter than its header"), std::string::npos);
    EXPECT_NE(damaged([](auto& b) { b.resize(b.size() - 96); }).find("truncated"), std::string::npos);
    EXPECT_NE(damaged([&](auto& b) { b[sizeof header + 3] ^= 1; }).find("built from another"), std::string::npos);
    EXPECT_NE(damaged(resealed([&](auto& b) {   // the last node's first child points at the root
                  StoredNode n;
                  char* at = b.data() + b.size() - sizeof n;
                  std::memcpy(&n, at, sizeof n);
                  n.children[0] = 0;
                  std::memcpy(at, &n, sizeof n);
              })).find("bad child"),
              std::string::npos);
    EXPECT_NE(damaged(resealed([&](auto& b) {   // a node's data beyond the data
                  StoredNode n;
                  char* at = b.data() + header.nodeTableOffset;
                  std::memcpy(&n, at, sizeof n);
                  n.offset = header.dataBytes;
                  std::memcpy(at, &n, sizeof n);
              })).find("data outside the file"),
              std::string::npos);
    // One bit flipped in the node table or the header, as a disk or a copy might: the checksum.
    EXPECT_NE(damaged([&](auto& b) { b[header.nodeTableOffset + 5] ^= 4; }).find("fails the checksum"), std::string::npos);
    EXPECT_NE(damaged([&](auto& b) { b[offsetof(store::FileHeader, info) + 2] ^= 1; }).find("fails the checksum"),
              std::string::npos);
    // A cache from an older Orbis (version 1 had no checksums).
    EXPECT_NE(damaged([&](auto& b) { b[offsetof(store::FileHeader, version)] = 1; }).find("another version of Orbis"),
              std::string::npos);
    EXPECT_NE(PointStore::open((cache / "none").string(), key).message().find("none"), std::string::npos);
}

// Node data damaged on disk after the build (its table intact): opening cannot see it, but
// reading that node fails its checksum, the file is removed, and the next load builds it again.
TEST(PointStore, CorruptedNodeDataIsCaughtAndTheCacheRebuilt) {
    const std::string las = writeSurvey("corrupt.las", 20000, 12);
    const fs::path cache = tempDir() / "cache-corrupt";
    std::string path;
    size_t victim = 0;
    {
        const Loaded l = load(las, smallChunks(cache));
        ASSERT_TRUE(l.store && l.store->onDisk());
        path = l.store->path();
        const auto& nodes = l.store->nodes();
        while (victim < nodes.size() && nodes[victim].count == 0) ++victim;
        ASSERT_LT(victim, nodes.size());
        store::FileHeader h;
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.read(reinterpret_cast<char*>(&h), sizeof h);
        const auto at = std::streamoff(h.dataOffset + nodes[victim].offset + 3);
        char c = 0;
        f.seekg(at);
        f.read(&c, 1);
        c = char(c ^ 0x10);
        f.seekp(at);
        f.write(&c, 1);
    }
    {
        const Loaded l = load(las, smallChunks(cache));   // the table is intact: opens
        ASSERT_TRUE(l.store && l.store->onDisk());
        std::vector<uint8_t> d;
        std::string error;
        EXPECT_FALSE(l.store->read(victim, d, &error));
        EXPECT_NE(error.find("corrupted"), std::string::npos) << error;
        EXPECT_NE(error.find(path), std::string::npos) << error;
        EXPECT_FALSE(fs::exists(path)) << "a corrupted cache must not be reused";
        for (size_t i = 0; i < l.store->nodes().size(); ++i) {   // the rest still reads (the open file)
            if (i != victim) {
                EXPECT_TRUE(l.store->read(i, d)) << "node " << i;
            }
        }
    }
    const Loaded again = load(las, smallChunks(cache));
    ASSERT_TRUE(again.store && again.store->onDisk());
    EXPECT_TRUE(fs::exists(path));
    std::vector<uint8_t> d;
    for (size_t i = 0; i < again.store->nodes().size(); ++i) EXPECT_TRUE(again.store->read(i, d)) << "node " << i;
}

// A full disk: the file-size limit stands in for it (writes past it fail with EFBIG where a
// full disk gives ENOSPC; the same code path). The cloud loads in memory, and neither a cache
// nor a temporary file is left.
TEST(PointStore, FullDiskLoadsTheCloudWithoutTheCache) {
    const std::string las = writeSurvey("full.las", 20000, 13);   // written before the limit
    const fs::path cache = tempDir() / "cache-full";
    fs::create_directories(cache);
    struct rlimit old {};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    const auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit limited = old;
    limited.rlim_cur = 64 * 1024;   // the spill file alone is ten times this
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
    const Loaded l = load(las, smallChunks(cache));
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldHandler);
    ASSERT_TRUE(l.store);
    EXPECT_FALSE(l.store->onDisk());
    EXPECT_EQ(l.store->info().points, 20000u);
    EXPECT_TRUE(fs::is_empty(cache));
    // With room again, the same load writes its cache.
    const Loaded roomy = load(las, smallChunks(cache));
    ASSERT_TRUE(roomy.store);
    EXPECT_TRUE(roomy.store->onDisk());
}

// A read-only cache folder: the cloud loads in memory too. Root ignores permissions, so as
// root the load runs in a child process that has given its rights up (user nobody).
TEST(PointStore, ReadOnlyFolderLoadsTheCloudWithoutTheCache) {
    const std::string las = writeSurvey("readonly.las", 20000, 14);
    const fs::path cache = tempDir() / "cache-readonly";
    fs::create_directories(cache);
    fs::permissions(cache, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                               fs::perms::others_read | fs::perms::others_exec);
    // 0: loaded in memory with nothing written; else what went wrong. No gtest macros: this may
    // run in a forked child.
    const auto attempt = [&]() -> int {
        auto file = LasFile::open(las);
        if (!file) return 1;
        PointPlacement placement;
        placement.origin = globe::Geodetic{179.99, -45.0, 300.0};
        auto georef = PointGeoreference::create(**file, placement);
        if (!georef) return 2;
        auto store = loadPointStore(**file, *georef, smallChunks(cache));
        if (!store) return 3;
        if ((*store)->onDisk()) return 4;
        return (*store)->info().points == 20000u ? 0 : 5;
    };
    int code = -1;
    if (::geteuid() == 0) {
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            if (::setgid(65534) != 0 || ::setuid(65534) != 0) ::_exit(90);
            ::_exit(attempt());
        }
        int status = 0;
        ASSERT_EQ(::waitpid(child, &status, 0), child);
        code = WIFEXITED(status) ? WEXITSTATUS(status) : 100 + WTERMSIG(status);
    } else {
        code = attempt();
    }
    EXPECT_EQ(code, 0) << "1: LAS, 2: placement, 3: load failed, 4: wrote a cache, 5: points, 90: setuid";
    EXPECT_TRUE(fs::is_empty(cache));
    fs::permissions(cache, fs::perms::owner_all, fs::perm_options::add);
}

// Residency over a store of 10 nodes of 100 points (1600 bytes each, quantised).
std::shared_ptr<PointStore> tenNodes() {
    std::vector<StoredNode> nodes(10);
    for (size_t i = 0; i < nodes.size(); ++i) {
        nodes[i].count = 100;
        nodes[i].step = 0.001;
        nodes[i].halfSize = 1.0;
        nodes[i].level = i == 0 ? 0 : 1;
        nodes[i].parent = i == 0 ? -1 : 0;
        nodes[i].offset = i * 1600;
    }
    CloudInfo info;
    info.points = 1000;
    return PointStore::inMemory(std::move(nodes), std::vector<uint8_t>(16000, 7), info);
}

TEST(NodeResidency, EvictsTheLeastRecentlyWantedAfterTheFramesInFlight) {
    NodeResidency r(tenNodes(), 4 * 1600, 0, 2);   // room for 4 nodes
    EXPECT_EQ(r.capacity(), 4u * 1600);
    std::map<int32_t, uint64_t> copied;
    const auto copy = [&](int32_t n, std::span<const uint8_t> d, uint64_t offset) {
        EXPECT_EQ(d.size(), 1600u);
        copied[n] = offset;
    };
    uint64_t frame = 0;
    const auto step = [&](std::vector<int32_t> want) {
        r.beginFrame(++frame);
        r.want(want, nullptr);
        return r.upload(~uint64_t(0), copy);
    };
    EXPECT_EQ(step({0, 1, 2, 3}), 4u * 1600);
    EXPECT_EQ(r.residentNodes(), 4u);
    EXPECT_TRUE(r.busy());   // uploaded this frame
    EXPECT_EQ(step({0, 1, 2, 3}), 0u);
    EXPECT_FALSE(r.busy());
    step({0, 1, 2});   // node 3 is now the least recently wanted
    // Node 4 needs room: node 3 goes, but its range comes back only two frames later.
    EXPECT_EQ(step({0, 1, 4}), 0u);
    EXPECT_FALSE(r.resident(3));
    EXPECT_FALSE(r.resident(4));
    EXPECT_TRUE(r.busy());
    EXPECT_EQ(r.evictions(), 1u);
    EXPECT_EQ(step({0, 1, 4}), 0u);
    EXPECT_EQ(step({0, 1, 4}), 1600u);
    EXPECT_TRUE(r.resident(4));
    EXPECT_EQ(copied[4], copied[3]);   // node 3's range
    EXPECT_TRUE(r.resident(0) && r.resident(1) && r.resident(2));
    // Wanted nodes are never evicted: with all four wanted, a fifth waits for nothing.
    EXPECT_EQ(step({0, 1, 2, 4, 5}), 0u);
    EXPECT_FALSE(r.resident(5));
    EXPECT_FALSE(r.busy());   // no room can come: not busy for ever
    EXPECT_EQ(r.evictions(), 1u);
}

TEST(NodeResidency, UploadsWithinTheFrameBudget) {
    NodeResidency r(tenNodes(), 1 << 20, 0, 2);
    EXPECT_EQ(r.capacity(), 16000u);   // the whole cloud, not the budget
    std::vector<int32_t> all{0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
    int frames = 0;
    do {
        r.beginFrame(uint64_t(++frames));
        r.want(all, nullptr);
        EXPECT_LE(r.upload(3 * 1600, [](int32_t, std::span<const uint8_t>, uint64_t) {}), 3u * 1600);
    } while (r.busy() && frames < 10);
    EXPECT_EQ(frames, 5);   // 3 + 3 + 3 + 1 nodes, then a frame that finds nothing to do
    EXPECT_EQ(r.residentNodes(), 10u);
}

TEST(NodeResidency, NoNodeStraddlesAPage) {
    // Pages of 4000 bytes hold two 1600-byte nodes each (800 bytes left over); three pages.
    NodeResidency r(tenNodes(), 12000, 4000, 2);
    EXPECT_EQ(r.capacity(), 12000u);
    EXPECT_EQ(r.pages(), 3u);
    std::map<int32_t, uint64_t> copied;
    std::vector<int32_t> all{0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
    for (uint64_t frame = 1; frame <= 4; ++frame) {
        r.beginFrame(frame);
        r.want(all, nullptr);
        r.upload(~uint64_t(0), [&](int32_t n, std::span<const uint8_t>, uint64_t offset) { copied[n] = offset; });
    }
    EXPECT_EQ(r.residentNodes(), 6u);   // not 7: no node uses two pages' leftovers
    for (const auto& [node, offset] : copied) {
        EXPECT_EQ(offset / 4000, (offset + 1600 - 1) / 4000) << "node " << node << " at " << offset;
        EXPECT_EQ(r.offset(node), offset);
    }
    // Evicted ranges coalesce within their page only: the nodes that take them stay in a page.
    for (uint64_t frame = 5; frame <= 20; ++frame) {
        r.beginFrame(frame);
        r.want(std::vector<int32_t>{7, 8, 9}, nullptr);
        r.upload(~uint64_t(0), [&](int32_t n, std::span<const uint8_t>, uint64_t offset) { copied[n] = offset; });
    }
    for (int32_t n : {7, 8, 9}) {
        ASSERT_TRUE(r.resident(n));
        EXPECT_EQ(r.offset(n) / 4000, (r.offset(n) + 1600 - 1) / 4000);
    }
}

TEST(NodeResidency, AWholeCloudThatFitsHasItsPagesPackedUpFront) {
    // 16000 bytes in pages of 4000 would be four pages, but two nodes fill a page: five pages,
    // each node in its place, so all ten are resident whatever order they arrive in.
    NodeResidency r(tenNodes(), 1 << 20, 4000, 2);
    EXPECT_EQ(r.pages(), 5u);
    EXPECT_EQ(r.capacity(), 20000u);
    r.beginFrame(1);
    r.want(std::vector<int32_t>{9, 3, 7, 0, 1, 2, 4, 5, 6, 8}, nullptr);
    std::set<uint64_t> offsets;
    r.upload(~uint64_t(0), [&](int32_t, std::span<const uint8_t>, uint64_t offset) {
        EXPECT_EQ(offset / 4000, (offset + 1600 - 1) / 4000);
        offsets.insert(offset);
    });
    EXPECT_EQ(r.residentNodes(), 10u);
    EXPECT_EQ(offsets.size(), 10u);
}

TEST(NodeResidency, ANodeLargerThanAPageIsNeverUploaded) {
    NodeResidency r(tenNodes(), 12000, 1000, 2);
    EXPECT_EQ(r.oversizedNodes(), 10u);
    r.beginFrame(1);
    r.want(std::vector<int32_t>{0, 1}, nullptr);
    EXPECT_EQ(r.upload(~uint64_t(0), [](int32_t, std::span<const uint8_t>, uint64_t) { FAIL(); }), 0u);
    EXPECT_FALSE(r.resident(0));
    EXPECT_FALSE(r.busy());   // and it does not wait for room for ever
}

}  // namespace
}  // namespace orbis::points
