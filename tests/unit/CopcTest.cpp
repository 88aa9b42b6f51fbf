// COPC: the hierarchy of the real files in ../shared/data/lidar (node counts sum to the header's,
// every node's points lie in its cube, keys and levels as the writers made them) and hostile
// hierarchies (a page that loops, entries outside the file or their level): clear errors.
#include "layers/points/Copc.h"
#include "layers/points/CopcWriter.h"
#include "layers/points/LasReader.h"
#include "tests/support/ProcessTempDir.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <map>
#include <functional>
#include <tuple>

namespace orbis::points {
namespace {

namespace fs = std::filesystem;

fs::path lidar(const char* name) { return fs::path(ORBIS_SHARED_DATA_DIR) / "lidar" / name; }

TEST(Copc, RealFilesHierarchiesHoldEveryPointInsideTheirCubes) {
    if (!fs::exists(lidar("lone-star.copc.laz"))) GTEST_SKIP() << "../shared/data is absent";
    struct Expect {
        const char* name;
        size_t nodes;
        int32_t depth;
    };
    for (const Expect& e : {Expect{"lone-star.copc.laz", 15, 2}, Expect{"1.2-with-color.copc.laz", 65, 3}}) {
        SCOPED_TRACE(e.name);
        auto f = LasFile::open(lidar(e.name).string());
        ASSERT_TRUE(f.ok()) << f.message();
        ASSERT_TRUE((*f)->copc().has_value());
        const copc::Info& info = *(*f)->copc();
        auto nodes = copc::readHierarchy(**f, info);
        ASSERT_TRUE(nodes.ok()) << nodes.message();
        EXPECT_EQ(nodes->size(), e.nodes);
        uint64_t sum = 0;
        int32_t depth = 0;
        for (const copc::Node& n : *nodes) {
            sum += n.points;
            depth = std::max(depth, n.key.d);
            glm::dvec3 centre;
            double half;
            copc::cube(info, n.key, centre, half);
            std::vector<LasPoint> pts;
            ASSERT_TRUE((*f)->readChunk(n.offset, n.bytes, n.points, pts).ok());
            ASSERT_EQ(pts.size(), n.points);
            const glm::dvec3 slack = (*f)->header().scale;
            for (const LasPoint& p : pts)
                ASSERT_TRUE(glm::all(glm::lessThanEqual(glm::abs(p.position - centre), glm::dvec3(half) + slack)))
                    << "node " << n.key.d << "-" << n.key.x << "-" << n.key.y << "-" << n.key.z;
        }
        EXPECT_EQ(sum, (*f)->header().pointCount);
        EXPECT_EQ(depth, e.depth);
        // The root's cube holds the header's box.
        EXPECT_TRUE(glm::all(glm::lessThanEqual(info.centre - info.halfSize, (*f)->header().min + 1e-6)));
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(info.centre + info.halfSize, (*f)->header().max - 1e-6)));
        EXPECT_GT(info.spacing, 0.0);
    }
}

std::vector<char> bytesOf(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Copc, HostileHierarchiesGiveClearErrors) {
    if (!fs::exists(lidar("lone-star.copc.laz"))) GTEST_SKIP() << "../shared/data is absent";
    const std::vector<char> good = bytesOf(lidar("lone-star.copc.laz"));
    auto f = LasFile::open(lidar("lone-star.copc.laz").string());
    ASSERT_TRUE(f.ok()) << f.message();
    const copc::Info info = *(*f)->copc();
    const size_t root = size_t(info.rootPageOffset);
    ASSERT_GE(info.rootPageBytes, 64u);
    const size_t last = root + size_t(info.rootPageBytes) - 32;   // the page's last entry
    const auto entry = [](std::vector<char>& b, size_t at, int32_t d, int32_t x, uint64_t offset, int32_t bytes, int32_t count) {
        const int32_t key[4] = {d, x, 0, 0};
        std::memcpy(b.data() + at, key, 16);
        std::memcpy(b.data() + at + 16, &offset, 8);
        std::memcpy(b.data() + at + 24, &bytes, 4);
        std::memcpy(b.data() + at + 28, &count, 4);
    };
    struct Case {
        const char* name;
        std::function<void(std::vector<char>&)> patch;
        const char* says;
    };
    const Case cases[] = {
        {"loop.copc.laz", [&](std::vector<char>& b) { entry(b, last, 1, 0, info.rootPageOffset, int32_t(info.rootPageBytes), -1); },
         "is referred to twice (a loop in the hierarchy)"},
        {"page-outside.copc.laz", [&](std::vector<char>& b) { entry(b, last, 1, 0, uint64_t(1) << 40, 320, -1); }, "lies outside the file"},
        {"chunk-outside.copc.laz", [&](std::vector<char>& b) { entry(b, last, 3, 5, good.size() - 10, 100, 50); }, "lies outside the point data"},
        {"key-outside.copc.laz", [&](std::vector<char>& b) { entry(b, last, 1, 2, 2000, 100, 50); }, "the key lies outside its level"},
        {"negative.copc.laz", [&](std::vector<char>& b) { entry(b, last, 3, 4, 2000, -5, 50); }, "a negative point count or size"},
        {"counts.copc.laz", [&](std::vector<char>& b) { entry(b, last, 3, 6, 0, 0, 0); }, "the header says 518862"},
        {"ragged-page.copc.laz", [&](std::vector<char>& b) {
             const uint64_t bytes = info.rootPageBytes - 1;
             std::memcpy(b.data() + 375 + 54 + 48, &bytes, 8);   // the info VLR's root page size
         }, "not a whole number of 32-byte entries"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        std::vector<char> b = good;
        c.patch(b);
        const fs::path path = test::processTempDir("orbis-copc") / c.name;
        std::ofstream(path, std::ios::binary).write(b.data(), std::streamsize(b.size()));
        auto g = LasFile::open(path.string());
        ASSERT_TRUE(g.ok()) << g.message();
        auto nodes = copc::readHierarchy(**g, *(*g)->copc());
        ASSERT_FALSE(nodes.ok());
        EXPECT_NE(nodes.message().find(c.says), std::string::npos) << nodes.message();
    }
}

}  // namespace
}  // namespace orbis::points

namespace orbis::points {
namespace {

/// LAS 1.4 in UTM 32N, centimetre steps: the generated clouds' file options.
LasWriteOptions utm32(uint8_t format) {
    LasWriteOptions o;
    o.versionMinor = 4;
    o.pointFormat = format;
    o.scale = glm::dvec3(0.01);
    o.offset = {500000.0, 5100000.0, 0.0};
    o.epsg = 32632;
    return o;
}

void writeLas(const fs::path& path, const LasWriteOptions& o, std::span<const LasPoint> pts) {
    auto w = LasWriter::create(path.string(), o);
    ASSERT_TRUE(w.ok()) << w.message();
    (*w)->write(pts);
    ASSERT_TRUE((*w)->close().ok());
}

// What Orbis writes as COPC passes the specification's structural checks and holds exactly the
// input's points: the info VLR first (at byte 375), hierarchy entries inside the file and equal to
// the chunk table's chunks, every node's points inside its cube, the points as a set.
TEST(Copc, OrbisWrittenCopcIsValidAndHoldsTheInputsPoints) {
    // A generated cloud in UTM with colours and every flag, several levels of nodes.
    std::vector<LasPoint> pts(30000);
    uint32_t seed = 11;
    const auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
    for (size_t i = 0; i < pts.size(); ++i) {
        LasPoint& p = pts[i];
        p.position = {500000.0 + 0.01 * double(next() % 100000), 5100000.0 + 0.01 * double(next() % 50000), 200.0 + 0.01 * double(next() % 3000)};
        p.intensity = uint16_t(next());
        p.returnNumber = 1, p.numberOfReturns = uint8_t(1 + next() % 3);
        p.classification = uint8_t(next() % 200);
        p.flags = uint8_t(next() % 64);
        p.scannerChannel = uint8_t(next() % 4);
        p.gpsTime = 1e5 + double(i) * 1e-4;
        p.red = uint16_t(next()), p.green = uint16_t(next()), p.blue = uint16_t(next());
    }
    const fs::path dir = test::processTempDir("orbis-copc-write");
    const LasWriteOptions o = utm32(7);
    writeLas(dir / "input.las", o, pts);
    if (HasFatalFailure()) return;
    std::vector<std::pair<fs::path, fs::path>> cases{{dir / "input.las", dir / "generated.copc.laz"}};
    if (fs::exists(lidar("1.2-with-color.las"))) cases.push_back({lidar("1.2-with-color.las"), dir / "oregon.copc.laz"});
    for (const auto& [input, output] : cases) {
        SCOPED_TRACE(input.string());
        auto in = LasFile::open(input.string());
        ASSERT_TRUE(in.ok()) << in.message();
        CopcWriteOptions options;
        options.maxNodePoints = 1000;   // several levels
        auto stats = writeCopc(**in, output.string(), options);
        ASSERT_TRUE(stats.ok()) << stats.message();
        EXPECT_EQ(stats->points, (*in)->points());
        EXPECT_GE(stats->depth, 1u);
        auto out = LasFile::open(output.string());
        ASSERT_TRUE(out.ok()) << out.message();
        const LasHeader& h = (*out)->header();
        ASSERT_TRUE((*out)->copc().has_value());
        ASSERT_FALSE(h.vlrs.empty());
        EXPECT_EQ(h.vlrs[0].userId, "copc");   // the info VLR first, right after the 375-byte header
        std::vector<uint8_t> at375;
        ASSERT_TRUE((*out)->readBytes(375 + 2, 4, at375).ok());
        EXPECT_EQ(std::string(at375.begin(), at375.end()), "copc");
        EXPECT_EQ(h.versionMinor, 4);
        EXPECT_FALSE((*out)->crs().wkt.empty());
        auto nodes = copc::readHierarchy(**out, *(*out)->copc());
        ASSERT_TRUE(nodes.ok()) << nodes.message();
        EXPECT_EQ(nodes->size(), stats->nodes);
        std::vector<LasPoint> all, node;
        for (const copc::Node& n : *nodes) {
            ASSERT_TRUE((*out)->readChunk(n.offset, n.bytes, n.points, node).ok());
            ASSERT_EQ(node.size(), n.points);
            glm::dvec3 centre;
            double half;
            copc::cube(*(*out)->copc(), n.key, centre, half);
            for (const LasPoint& p : node) ASSERT_TRUE(glm::all(glm::lessThanEqual(glm::abs(p.position - centre), glm::dvec3(half))));
            all.insert(all.end(), node.begin(), node.end());
        }
        // The same points, also through the plain reader (the chunk table).
        std::vector<LasPoint> original, viaTable;
        ASSERT_TRUE((*in)->read(0, UINT64_MAX, original).ok());
        ASSERT_TRUE((*out)->read(0, UINT64_MAX, viaTable).ok());
        ASSERT_EQ(all.size(), original.size());
        ASSERT_EQ(viaTable.size(), original.size());
        const auto order = [](const LasPoint& a, const LasPoint& b) {
            return std::tie(a.position.x, a.position.y, a.position.z, a.gpsTime) < std::tie(b.position.x, b.position.y, b.position.z, b.gpsTime);
        };
        for (auto* v : {&all, &original, &viaTable}) std::sort(v->begin(), v->end(), order);
        for (size_t i = 0; i < all.size(); ++i) {
            const LasPoint &a = all[i], &b = original[i];
            ASSERT_EQ(a.position, b.position) << i;
            ASSERT_EQ(viaTable[i].position, b.position) << i;
            ASSERT_EQ(a.intensity, b.intensity) << i;
            ASSERT_EQ(a.classification, b.classification) << i;
            ASSERT_EQ(a.flags, b.flags) << i;
            ASSERT_EQ(a.scannerChannel, b.scannerChannel) << i;
            ASSERT_EQ(a.gpsTime, b.gpsTime) << i;
            ASSERT_EQ(a.red, b.red) << i;
            ASSERT_EQ(a.blue, b.blue) << i;
        }
    }
    // No CRS: refused by name.
    LasWriteOptions bare = o;
    bare.epsg = 0;
    {
        auto w = LasWriter::create((dir / "bare.las").string(), bare);
        ASSERT_TRUE(w.ok());
        (*w)->write(std::span<const LasPoint>(pts).first(10));
        ASSERT_TRUE((*w)->close().ok());
    }
    auto in = LasFile::open((dir / "bare.las").string());
    ASSERT_TRUE(in.ok());
    auto refused = writeCopc(**in, (dir / "bare.copc.laz").string(), {});
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.message().find("bare.las"), std::string::npos) << refused.message();
    EXPECT_FALSE(fs::exists(dir / "bare.copc.laz"));
}

// The out-of-core build (the cloud in batches of cells, the nodes above them filled from each
// batch's first points in key order) makes the tree one batch makes: the same nodes with the same
// points in the same order, so the same chunk bytes; and every temporary file is gone.
TEST(Copc, BatchedBuildWritesTheOneBatchTree) {
    // A survey strip with a dense cluster: the tree is deeper in one place than elsewhere.
    std::vector<LasPoint> pts(60000);
    uint32_t seed = 5;
    const auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
    for (size_t i = 0; i < pts.size(); ++i) {
        LasPoint& p = pts[i];
        const bool cluster = i % 3 == 0;
        p.position = cluster ? glm::dvec3{501000.0 + 0.01 * double(next() % 2000), 5101000.0 + 0.01 * double(next() % 2000), 250.0 + 0.01 * double(next() % 500)}
                             : glm::dvec3{500000.0 + 0.01 * double(next() % 400000), 5100000.0 + 0.01 * double(next() % 200000), 200.0 + 0.01 * double(next() % 9000)};
        p.intensity = uint16_t(next());
        p.returnNumber = 1, p.numberOfReturns = 1;
        p.classification = uint8_t(next() % 20);
        p.gpsTime = 2e5 + double(i) * 1e-4;
    }
    const fs::path dir = test::processTempDir("orbis-copc-batched");
    writeLas(dir / "input.las", utm32(6), pts);
    if (HasFatalFailure()) return;
    auto in = LasFile::open((dir / "input.las").string());
    ASSERT_TRUE(in.ok()) << in.message();
    // Node key -> (points, chunk bytes).
    using Tree = std::map<std::tuple<int32_t, int32_t, int32_t, int32_t>, std::pair<uint32_t, std::vector<uint8_t>>>;
    const auto write = [&](const std::string& name, uint64_t batchPoints, Tree& tree) -> CopcWriteStats {
        CopcWriteOptions options;
        options.maxNodePoints = 500;
        options.batchPoints = batchPoints;
        const fs::path path = dir / name;
        auto stats = writeCopc(**in, path.string(), options);
        EXPECT_TRUE(stats.ok()) << stats.message();
        if (!stats.ok()) return {};
        auto out = LasFile::open(path.string());
        EXPECT_TRUE(out.ok()) << out.message();
        if (!out.ok()) return {};
        auto nodes = copc::readHierarchy(**out, *(*out)->copc());
        EXPECT_TRUE(nodes.ok()) << nodes.message();
        if (!nodes.ok()) return {};
        uint64_t sum = 0;
        std::vector<LasPoint> node;
        for (const copc::Node& n : *nodes) {
            std::vector<uint8_t> bytes;
            EXPECT_TRUE((*out)->readBytes(n.offset, n.bytes, bytes).ok());
            tree[{n.key.d, n.key.x, n.key.y, n.key.z}] = {n.points, bytes};
            EXPECT_TRUE((*out)->readChunk(n.offset, n.bytes, n.points, node).ok());
            glm::dvec3 centre;
            double half;
            copc::cube(*(*out)->copc(), n.key, centre, half);
            for (const LasPoint& p : node) EXPECT_TRUE(glm::all(glm::lessThanEqual(glm::abs(p.position - centre), glm::dvec3(half))));
            sum += n.points;
            if (n.key.d > 0) {   // every node's parent is in the hierarchy too
                EXPECT_EQ(std::count_if(nodes->begin(), nodes->end(), [&](const copc::Node& m) { return m.key == n.key.parent(); }), 1);
            }
        }
        EXPECT_EQ(sum, pts.size());
        return *stats;
    };
    Tree whole, batched;
    const CopcWriteStats one = write("whole.copc.laz", 100000000, whole);
    const CopcWriteStats many = write("batched.copc.laz", 4000, batched);
    EXPECT_EQ(one.batches, 1u);
    EXPECT_GT(many.batches, 8u);
    EXPECT_GE(one.depth, 3u);
    EXPECT_EQ(one.nodes, many.nodes);
    ASSERT_EQ(whole.size(), batched.size());
    for (const auto& [key, node] : whole) {
        SCOPED_TRACE(std::to_string(std::get<0>(key)) + "-" + std::to_string(std::get<1>(key)) + "-" + std::to_string(std::get<2>(key)) + "-" +
                     std::to_string(std::get<3>(key)));
        auto it = batched.find(key);
        ASSERT_NE(it, batched.end());
        EXPECT_EQ(it->second.first, node.first);
        EXPECT_TRUE(it->second.second == node.second);
    }
    // No temporary file left next to the outputs.
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_NE(e.path().extension(), ".tmp") << e.path();
}

}  // namespace
}  // namespace orbis::points
