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
                                          << R"(", "crs": "EPSG:26912", "color": "intensity", "pointBudget": 200000}]})";
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
    fs::remove_all(dir);
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
