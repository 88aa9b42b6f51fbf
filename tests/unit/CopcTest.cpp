// COPC: the hierarchy of the real files in ../shared/data/lidar (node counts sum to the header's,
// every node's points lie in its cube, keys and levels as the writers made them) and hostile
// hierarchies (a page that loops, entries outside the file or their level): clear errors.
#include "layers/points/Copc.h"
#include "layers/points/LasReader.h"
#include "tests/support/ProcessTempDir.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

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
