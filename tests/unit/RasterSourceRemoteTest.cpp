// Raster sources over HTTP: XYZ tiles from the test server (tests/support/HttpServer), healthy,
// empty, and misbehaving in every way a server can (503, garbage, a reset, a stall, refused).
#include "globe/RasterSource.h"
#include "globe/TileCacheFs.h"

#include "tests/support/HttpServer.h"
#include "tests/support/ScopedGdalConfig.h"
#include "tests/support/XyzTiles.h"
#include "tests/support/ProcessTempDir.h"

#include <cpl_conv.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace orbis;
using namespace orbis::globe;

namespace {

/// One temporary folder per test process.
const fs::path& tempDir() {
    static const fs::path p = test::processTempDir("orbis-raster-remote-test");
    return p;
}

/// An XYZ source of `base`/{z}/{x}/{y}.png down to `maxZoom`, its GDAL cache in `cacheName`.
Result<std::shared_ptr<RasterSource>> openXyz(const std::string& base, int maxZoom, const std::string& cacheName) {
    RasterSourceOptions o;
    o.xyzUrl = base + "/{z}/{x}/{y}.png";
    o.xyzMaxZoom = maxZoom;
    o.cacheDir = (tempDir() / cacheName).string();
    return RasterSource::open(o);
}

/// An HTTP server of the test ramp's XYZ tiles (levels 0 to 2) written under tempDir()/name;
/// null when it cannot start.
std::unique_ptr<test::HttpServer> serveRamp(const std::string& name) {
    const fs::path root = tempDir() / name;
    if (!test::writeXyzTiles(root, 2).empty()) return nullptr;
    auto server = std::make_unique<test::HttpServer>(root);
    if (!server->running()) return nullptr;
    return server;
}

/// Reads 0..45 x 0..45 at 64 px from `src` and checks its colours against the server's ramp.
void expectRampColours(RasterSource& src) {
    const GeoExtent e{0, 0, 45, 45};
    auto t = src.readImagery(e, 64);
    ASSERT_TRUE(t.ok()) << t.message();
    ASSERT_TRUE(t->anyValid);
    for (const auto& [i, j] : {std::pair{5, 5}, {32, 32}, {60, 10}, {10, 58}}) {
        const double lon = e.west + (i + 0.5) * e.width() / 64, lat = e.north - (j + 0.5) * e.height() / 64;
        const uint8_t* p = &t->rgba[size_t((j * 64 + i) * 4)];
        // 3 levels: resampling of a ramp through 0.35 deg source pixels plus rounding.
        EXPECT_NEAR(p[0], test::xyzRedAt(lon), 3) << lon << ", " << lat;
        EXPECT_NEAR(p[1], test::xyzGreenAt(lat), 3) << lon << ", " << lat;
        EXPECT_NEAR(p[2], 128, 2);
        EXPECT_EQ(p[3], 255);
    }
}

}  // namespace


TEST(RasterSourceRemote, XyzTilesMatchTheSourceColours) {
    auto server = serveRamp("xyz");
    ASSERT_TRUE(server);
    auto src = openXyz(server->url(), 2, "wms-cache");
    ASSERT_TRUE(src.ok()) << src.message();
    EXPECT_NEAR((*src)->coverage().north, 85.0511, 1e-3);
    expectRampColours(**src);
    EXPECT_GT(server->requestCount(), 0);
}

TEST(RasterSourceRemote, XyzServerWithoutTilesGivesEmptyTiles) {
    const fs::path root = tempDir() / "empty-server";
    fs::create_directories(root);
    test::HttpServer server(root);
    ASSERT_TRUE(server.running()) << server.error();
    auto src = openXyz(server.url(), 3, "wms-cache-empty");
    ASSERT_TRUE(src.ok()) << src.message();
    const auto t0 = std::chrono::steady_clock::now();
    auto t = (*src)->readImagery({0, 0, 45, 45}, 64);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(t.ok()) << t.message();
    EXPECT_FALSE(t->anyValid);
    EXPECT_GT(server.notFoundCount(), 0);
    EXPECT_LT(s, 20.0);
}

// A server that answers badly: 503, bytes that are no image, a reset connection, a request never
// answered (the HTTP timeout ends it), or nothing listening at all. Every read ends, within its bound, with a
// message or an empty tile; nothing hangs or crashes, and the next read from a healthy server
// works.
TEST(RasterSourceRemote, BadServersEndEachReadWithinItsTimeout) {
    const fs::path root = tempDir() / "xyz-faults";
    ASSERT_EQ(test::writeXyzTiles(root, 1), "");
    const test::ScopedGdalConfig timeout("GDAL_HTTP_TIMEOUT", "2");
    const test::ScopedGdalConfig retryDelay("GDAL_HTTP_RETRY_DELAY", "0.2");
    using Fault = test::HttpServer::Fault;
    struct Case {
        const char* name;
        Fault fault;
    };
    for (const Case c : {Case{"503", Fault::Unavailable503}, Case{"garbage", Fault::Garbage}, Case{"reset", Fault::Reset},
                         Case{"stall", Fault::Stall}}) {
        SCOPED_TRACE(c.name);
        test::HttpServer server(root);
        ASSERT_TRUE(server.running()) << server.error();
        server.setFault(c.fault);
        auto src = openXyz(server.url(), 1, std::string("wms-cache-fault-") + c.name);
        ASSERT_TRUE(src.ok()) << src.message();
        const auto t0 = std::chrono::steady_clock::now();
        auto t = (*src)->readImagery({0, 0, 45, 45}, 32);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        EXPECT_TRUE(!t.ok() || !t->anyValid) << "a bad answer must not become an image";
        if (!t.ok()) {   // named: the source and the area (the pager tries it again later)
            EXPECT_NE(t.message().find(server.url()), std::string::npos) << t.message();
        }
        EXPECT_GT(server.requestCount(), 0);
        EXPECT_LT(s, 20.0) << "bounded by the timeout and the retries";
        // The same server healthy again: the next read (another tile) gets its pixels.
        server.setFault(Fault::None);
        auto good = (*src)->readImagery({-90, -45, -45, 0}, 32);
        ASSERT_TRUE(good.ok()) << good.message();
        EXPECT_TRUE(good->anyValid);
    }
    // Nothing listening: refused at once.
    int port = 0;
    {
        test::HttpServer gone(root);
        port = gone.port();
    }
    auto src = openXyz("http://127.0.0.1:" + std::to_string(port), 1, "wms-cache-refused");
    ASSERT_TRUE(src.ok()) << src.message();
    const auto t0 = std::chrono::steady_clock::now();
    auto t = (*src)->readImagery({0, 0, 45, 45}, 32);
    EXPECT_TRUE(!t.ok() || !t->anyValid);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 20.0);
}

// A password in a source's URL (user info) is used but never shown: not in the source's name,
// not in a failed read's message (GDAL quotes the request it made).
TEST(RasterSourceRemote, APasswordInTheUrlIsNeverInAMessage) {
    int port = 0;
    {
        test::HttpServer gone(tempDir());
        port = gone.port();
    }
    const std::string url = "WMS:http://orbis:s3cret-pw@127.0.0.1:" + std::to_string(port) +
                            "/ows?SERVICE=WMS&VERSION=1.1.1&REQUEST=GetMap&LAYERS=x&SRS=EPSG:4326&BBOX=-180,-90,180,90&FORMAT=image/png";
    globe::RasterSourceOptions o;
    o.path = url;
    o.cacheDir = (tempDir() / "wms-cache-secret").string();
    auto src = globe::RasterSource::open(o);
    ASSERT_TRUE(src.ok()) << src.message();
    EXPECT_EQ((*src)->name().find("s3cret-pw"), std::string::npos) << (*src)->name();
    EXPECT_NE((*src)->name().find("orbis:***@127.0.0.1"), std::string::npos) << (*src)->name();
    auto t = (*src)->readImagery({0, 0, 45, 45}, 32);
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.message().find("s3cret-pw"), std::string::npos) << t.message();
    EXPECT_EQ((*src)->describe().find("s3cret-pw"), std::string::npos);
}

namespace {

/// The tiles in a tile cache folder (no temporary files of tiles being written).
std::vector<fs::path> cachedTiles(const fs::path& dir) {
    std::vector<fs::path> out;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
        if (it->is_regular_file()) out.push_back(it->path());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

// A full disk under GDAL's tile cache: the file-size limit stands in for it (writes past it
// fail with EFBIG where a full disk gives ENOSPC). The tiles still come from the server, and no
// cut-short tile is left in the cache for a later read to trust.
TEST(RasterSourceRemote, FullDiskUnderTheTileCacheNeitherFailsReadsNorKeepsCutTiles) {
    auto server = serveRamp("xyz-full");
    ASSERT_TRUE(server);
    {
        auto src = openXyz(server->url(), 2, "wms-cache-full");
        ASSERT_TRUE(src.ok()) << src.message();
        struct rlimit old {};
        ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
        const auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);
        struct rlimit limited = old;
        limited.rlim_cur = 200;   // every tile is larger
        ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
        {
            SCOPED_TRACE("with the disk full");
                expectRampColours(**src);
        }
        ::setrlimit(RLIMIT_FSIZE, &old);
        std::signal(SIGXFSZ, oldHandler);
    }
    const int asked = server->requestCount();
    EXPECT_GT(orbis::globe::tileCacheWriteFailures(), 0u);
    EXPECT_TRUE(cachedTiles(tempDir() / "wms-cache-full").empty()) << "a cut tile was kept";
    // A new source over the same cache: every tile it takes from the cache must be whole.
    auto again = openXyz(server->url(), 2, "wms-cache-full");
    ASSERT_TRUE(again.ok()) << again.message();
    expectRampColours(**again);
    EXPECT_GT(server->requestCount(), asked) << "the cut tiles were not asked for again";
    EXPECT_FALSE(cachedTiles(tempDir() / "wms-cache-full").empty()) << "with room again, the tiles are cached";
}

// Tiles damaged in the cache (a flipped byte, a cut end) and tiles from an older cache without
// Orbis's trailer: each is removed and fetched again, never decoded.
TEST(RasterSourceRemote, DamagedOrForeignCachedTilesAreFetchedAgain) {
    auto server = serveRamp("xyz-damaged");
    ASSERT_TRUE(server);
    const fs::path cache = tempDir() / "wms-cache-damaged";
    {
        auto src = openXyz(server->url(), 2, "wms-cache-damaged");
        ASSERT_TRUE(src.ok()) << src.message();
        expectRampColours(**src);
    }
    const int fetched = server->requestCount();
    {
        auto src = openXyz(server->url(), 2, "wms-cache-damaged");
        ASSERT_TRUE(src.ok()) << src.message();
        expectRampColours(**src);
        ASSERT_EQ(server->requestCount(), fetched) << "whole tiles come from the cache";
    }
    const std::vector<fs::path> tiles = cachedTiles(cache);
    ASSERT_GE(tiles.size(), 3u);
    {   // a flipped byte in the middle of the first
        std::fstream f(tiles[0], std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(std::streamoff(fs::file_size(tiles[0]) / 2));
        char c = 0;
        f.read(&c, 1);
        f.seekp(std::streamoff(fs::file_size(tiles[0]) / 2));
        c = char(c ^ 0x10);
        f.write(&c, 1);
    }
    fs::resize_file(tiles[1], fs::file_size(tiles[1]) / 2);   // cut short
    fs::resize_file(tiles[2], fs::file_size(tiles[2]) - orbis::globe::kTileCacheTrailerBytes);   // no trailer: an older cache
    auto src = openXyz(server->url(), 2, "wms-cache-damaged");
    ASSERT_TRUE(src.ok()) << src.message();
    expectRampColours(**src);
    EXPECT_EQ(server->requestCount(), fetched + 3) << "each bad tile, and only those, is fetched again";
}

// A tile cache folder that cannot be made (its parent is a file; root ignores permissions, a
// file in the path stops everyone): the tiles come from the server, nothing is written.
TEST(RasterSourceRemote, UnwritableTileCacheStillReadsEveryTile) {
    auto server = serveRamp("xyz-unwritable");
    ASSERT_TRUE(server);
    const fs::path blocker = tempDir() / "a-file";
    { std::ofstream(blocker) << "not a folder"; }
    auto src = openXyz(server->url(), 2, "a-file/cache");
    ASSERT_TRUE(src.ok()) << src.message();
    expectRampColours(**src);
    EXPECT_TRUE(fs::is_regular_file(blocker));
}
