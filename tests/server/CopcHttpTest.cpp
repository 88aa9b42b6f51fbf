// Clouds over HTTP: COPC and LAZ files on a real web server (lighttpd, honouring range requests)
// on loopback read as the same files on disk: header, hierarchy, every point, and the rendered
// picture; opening a COPC file fetches its head and its hierarchy, not its points. Servers that
// answer 404, ignore ranges or stall give a clear error in bounded time.
#include "base/Png.h"
#include "layers/points/Copc.h"
#include "layers/points/LasReader.h"
#include "tests/support/HttpServer.h"
#include "tests/support/ScopedGdalConfig.h"
#include "tests/support/Shell.h"
#include "tests/support/StaticWebServer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;

fs::path lidar(const char* name) { return fs::path(ORBIS_SOURCE_DIR) / ".." / "shared" / "data" / "lidar" / name; }

TEST(CopcHttp, RemoteFilesReadAsTheLocalOnes) {
    if (!fs::exists(lidar("lone-star.copc.laz"))) GTEST_SKIP() << "../shared/data is absent";
    StaticWebServer web;
    if (!web.available()) GTEST_SKIP() << web.error();
    for (const char* name : {"lone-star.copc.laz", "simple.laz", "1.2-with-color.las", "1.2-with-color.las.wkt"}) fs::copy_file(lidar(name), web.folder() / name);
    ASSERT_TRUE(web.start()) << web.error();
    for (const char* name : {"lone-star.copc.laz", "simple.laz", "1.2-with-color.las"}) {
        SCOPED_TRACE(name);
        auto local = points::LasFile::open(lidar(name).string());
        auto remote = points::LasFile::open(web.url() + "/" + name);
        ASSERT_TRUE(local.ok()) << local.message();
        ASSERT_TRUE(remote.ok()) << remote.message();
        EXPECT_TRUE((*remote)->remote());
        EXPECT_EQ((*remote)->header().pointCount, (*local)->header().pointCount);
        EXPECT_EQ((*remote)->header().compression, (*local)->header().compression);
        EXPECT_EQ((*remote)->crs().wkt, (*local)->crs().wkt);
        std::vector<points::LasPoint> a, b;
        ASSERT_TRUE((*local)->read(0, UINT64_MAX, a).ok());
        auto r = (*remote)->read(0, UINT64_MAX, b);
        ASSERT_TRUE(r.ok()) << r.message();
        ASSERT_EQ(a.size(), b.size());
        for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i].position, b[i].position) << i;
    }
    // A COPC file opened and its hierarchy and root node read: a small part of it fetched.
    auto copc = points::LasFile::open(web.url() + "/lone-star.copc.laz");
    ASSERT_TRUE(copc.ok()) << copc.message();
    ASSERT_TRUE((*copc)->copc());
    auto nodes = points::copc::readHierarchy(**copc, *(*copc)->copc());
    ASSERT_TRUE(nodes.ok()) << nodes.message();
    EXPECT_EQ(nodes->size(), 15u);
    std::vector<points::LasPoint> root;
    const points::copc::Node& n = nodes->front();
    EXPECT_EQ(n.key.d, 0);
    ASSERT_TRUE((*copc)->readChunk(n.offset, n.bytes, n.points, root).ok());
    EXPECT_EQ(root.size(), n.points);
    EXPECT_LT((*copc)->bytesFetched(), (*copc)->fileBytes() / 4) << (*copc)->bytesFetched() << " of " << (*copc)->fileBytes();
    web.stop();
    EXPECT_GT(web.requests(), 3u);
}

// The COPC scene rendered from the server equals the one rendered from the file (the orbis CLI,
// lavapipe), and the server sent less than the file for a view that needs part of it.
TEST(CopcHttp, RemoteCopcRendersAsTheLocalFile) {
    if (!fs::exists(lidar("lone-star.copc.laz"))) GTEST_SKIP() << "../shared/data is absent";
    StaticWebServer web;
    if (!web.available()) GTEST_SKIP() << web.error();
    fs::copy_file(lidar("lone-star.copc.laz"), web.folder() / "lone-star.copc.laz");
    ASSERT_TRUE(web.start()) << web.error();
    const fs::path dir = fs::temp_directory_path() / ("orbis-copc-http-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const auto render = [&](const std::string& path, const std::string& png) {
        std::ofstream(dir / "scene.json") << R"({"orbis": 1, "viewpoint": {"lon": -110.806744, "lat": 44.418375, "height": 2330, "heading": 30, "pitch": -45, "range": 40},
            "time": {"start": "2026-06-21T09:00:00Z", "end": "2026-06-21T09:00:00Z"},
            "layers": [{"type": "points", "name": "Lone Star", "path": ")" << path
                                          << R"(", "crs": "EPSG:26912", "color": "intensity", "pointBudget": 200000, "cacheFolder": ")"
                                          << (dir / "cache").string() << R"("}]})";
        const ShellRun run = runShell(std::string(ORBIS_BINARY) + " render " + (dir / "scene.json").string() + " -o " + (dir / png).string() +
                                      " --device cpu --size 320x240 2>&1");
        EXPECT_EQ(run.exitCode, 0) << run.output;
        auto image = readPng(dir / png);
        EXPECT_TRUE(image.ok()) << (image.ok() ? "" : image.message());
        return image.ok() ? *image : ImageRgba8{};
    };
    const ImageRgba8 local = render(lidar("lone-star.copc.laz").string(), "local.png");
    const ImageRgba8 remote = render(web.url() + "/lone-star.copc.laz", "remote.png");
    ASSERT_FALSE(local.pixels.empty());
    EXPECT_EQ(local.pixels, remote.pixels);
    size_t lit = 0;
    for (size_t i = 0; i < local.pixels.size(); i += 4) lit += local.pixels[i] > 0 ? 1 : 0;
    EXPECT_GT(lit, local.pixels.size() / 4 / 10);
    web.stop();
    EXPECT_LT(web.bytesSent(), fs::file_size(lidar("lone-star.copc.laz")));
    // The nodes the server sent are in the layer's cache folder; the local file cached nothing.
    size_t cached = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir / "cache" / "remote")) cached += e.is_regular_file() ? 1 : 0;
    EXPECT_GT(cached, 0u);
    fs::remove_all(dir);
}

// Nodes fetched once are read from the disk cache after (this run or the next): the same points,
// nothing more asked of the server; a damaged cached node is fetched again; a file changed on the
// server gets a cache of its own; an unwritable cache folder leaves reads as they are; a cache
// over its size loses its oldest ranges.
TEST(CopcHttp, FetchedNodesAreKeptOnTheDisk) {
    if (!fs::exists(lidar("lone-star.copc.laz"))) GTEST_SKIP() << "../shared/data is absent";
    StaticWebServer web;
    if (!web.available()) GTEST_SKIP() << web.error();
    fs::copy_file(lidar("lone-star.copc.laz"), web.folder() / "cloud.copc.laz");
    ASSERT_TRUE(web.start()) << web.error();
    const fs::path cache = fs::temp_directory_path() / ("orbis-copc-cache-" + std::to_string(::getpid()));
    fs::remove_all(cache);
    const std::string url = web.url() + "/cloud.copc.laz";
    struct Read {
        std::vector<points::LasPoint> points;
        uint64_t openFetched = 0, fetched = 0, fromCache = 0, nodeBytes = 0;
    };
    const auto readAll = [&](const std::string& folder) {
        Read r;
        auto f = points::LasFile::open(url);
        EXPECT_TRUE(f.ok()) << f.message();
        if (!f.ok()) return r;
        r.openFetched = (*f)->bytesFetched();
        (*f)->cacheRemoteReads(folder);
        auto nodes = points::copc::readHierarchy(**f, *(*f)->copc());
        EXPECT_TRUE(nodes.ok()) << nodes.message();
        if (!nodes.ok()) return r;
        std::vector<points::LasPoint> node;
        for (const points::copc::Node& n : *nodes) {
            EXPECT_TRUE((*f)->readChunk(n.offset, n.bytes, n.points, node).ok());
            r.points.insert(r.points.end(), node.begin(), node.end());
            r.nodeBytes += n.bytes;
        }
        r.fetched = (*f)->bytesFetched() - r.openFetched;
        r.fromCache = (*f)->bytesFromCache();
        return r;
    };
    const auto same = [](const Read& a, const Read& b) {
        if (a.points.size() != b.points.size()) return false;
        for (size_t i = 0; i < a.points.size(); ++i)
            if (a.points[i].position != b.points[i].position || a.points[i].intensity != b.points[i].intensity) return false;
        return true;
    };
    const Read first = readAll(cache.string());
    ASSERT_EQ(first.points.size(), 518862u);
    EXPECT_EQ(first.fromCache, 0u);
    EXPECT_GE(first.fetched, first.nodeBytes);
    const Read second = readAll(cache.string());
    EXPECT_TRUE(same(first, second));
    EXPECT_EQ(second.fetched, 0u);
    EXPECT_GE(second.fromCache, first.nodeBytes);   // (and the hierarchy page read after the open)

    // One cached node damaged: fetched again (and cached again), the points unchanged.
    fs::path largest;
    for (const auto& e : fs::recursive_directory_iterator(cache))
        if (e.is_regular_file() && (largest.empty() || e.file_size() > fs::file_size(largest))) largest = e.path();
    ASSERT_FALSE(largest.empty());
    const uint64_t damagedBytes = fs::file_size(largest) - 8;
    {
        std::fstream f(largest, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(100);
        const int c = f.get();
        f.seekp(100);
        f.put(char(c ^ 0xFF));
    }
    const Read repaired = readAll(cache.string());
    EXPECT_TRUE(same(first, repaired));
    EXPECT_EQ(repaired.fetched, damagedBytes);
    EXPECT_EQ(readAll(cache.string()).fetched, 0u);

    // An unwritable folder: every node from the server, nothing cached.
    const Read uncached = readAll("/proc/orbis-no-such-folder");
    EXPECT_TRUE(same(first, uncached));
    EXPECT_EQ(uncached.fromCache, 0u);

    // The file changed on the server (the same URL): another cache folder, its nodes fetched.
    fs::copy_file(lidar("1.2-with-color.copc.laz"), web.folder() / "cloud.tmp");
    fs::rename(web.folder() / "cloud.tmp", web.folder() / "cloud.copc.laz");
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));   // past lighttpd's one-second stat cache
    const Read changed = readAll(cache.string());
    EXPECT_EQ(changed.points.size(), 1065u);
    EXPECT_EQ(changed.fromCache, 0u);
    size_t folders = 0;
    for (const auto& e : fs::directory_iterator(cache)) folders += e.is_directory() ? 1 : 0;
    EXPECT_EQ(folders, 2u);

    // Over its size: the oldest ranges go first, down to 3/4 of the size.
    uint64_t total = 0;
    for (const auto& e : fs::recursive_directory_iterator(cache)) total += e.is_regular_file() ? e.file_size() : 0;
    auto f = points::LasFile::open(url);
    ASSERT_TRUE(f.ok()) << f.message();
    (*f)->cacheRemoteReads(cache.string(), total / 2);
    uint64_t after = 0;
    for (const auto& e : fs::recursive_directory_iterator(cache)) after += e.is_regular_file() ? e.file_size() : 0;
    EXPECT_LE(after, total / 2 / 4 * 3);
    EXPECT_GT(after, 0u);
    web.stop();
    fs::remove_all(cache);
}

TEST(CopcHttp, BadServersGiveAClearErrorInBoundedTime) {
    if (!fs::exists(lidar("lone-star.copc.laz"))) GTEST_SKIP() << "../shared/data is absent";
    const fs::path dir = fs::temp_directory_path() / ("orbis-copc-bad-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fs::copy_file(lidar("lone-star.copc.laz"), dir / "lone-star.copc.laz", fs::copy_options::overwrite_existing);
    HttpServer plain(dir);   // GET without ranges
    ASSERT_TRUE(plain.running()) << plain.error();
    auto f = points::LasFile::open(plain.url() + "/lone-star.copc.laz");
    ASSERT_FALSE(f.ok());
    EXPECT_NE(f.message().find("does not honour range requests"), std::string::npos) << f.message();
    f = points::LasFile::open(plain.url() + "/absent.copc.laz");
    ASSERT_FALSE(f.ok());
    EXPECT_NE(f.message().find("absent.copc.laz: cannot open"), std::string::npos) << f.message();
    {
        ScopedGdalConfig timeout("GDAL_HTTP_TIMEOUT", "2");
        ScopedGdalConfig retries("GDAL_HTTP_MAX_RETRY", "0");
        plain.setFault(HttpServer::Fault::Stall);
        const auto start = std::chrono::steady_clock::now();
        f = points::LasFile::open(plain.url() + "/stalled.copc.laz");
        EXPECT_FALSE(f.ok());
        EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(15));
        plain.setFault(HttpServer::Fault::None);
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace orbis::test
