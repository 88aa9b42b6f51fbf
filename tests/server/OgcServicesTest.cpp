// OGC services from a real MapServer (CGI behind lighttpd, started on loopback by the fixture,
// tests/support/MapServer.h): a WMS layer read as terrain imagery matches the same GeoTIFF read
// locally; a WFS 2.0 layer reads as the same features as the GeoPackage it serves, asks the
// server for the box of a tile read, and pages its GetFeature requests. Skipped, with the
// reason, when the packages or the generated world are missing.
#include "globe/OgcCapabilities.h"
#include "globe/RasterSource.h"
#include "globe/TerrainTiles.h"
#include "layers/vector/VectorReader.h"
#include "tests/support/MapServer.h"
#include "tests/support/ScopedGdalConfig.h"
#include "tests/support/ProcessTempDir.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ogrsf_frmts.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace orbis {
namespace {

namespace fs = std::filesystem;

/// The requests the server saw, in lower case (clients spell parameters as they like).
std::string requests(const test::MapServer& ms) {
    std::string log = ms.accessLog();
    std::transform(log.begin(), log.end(), log.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return log;
}

const fs::path kWorld = fs::path(ORBIS_SOURCE_DIR) / "assets" / "generated" / "world-colour.tif";
const fs::path kRelief = fs::path(ORBIS_SOURCE_DIR) / "assets" / "generated" / "world-relief.tif";

/// 100 parcels of 400 m in Web Mercator around lon 10, lat 45 (as the PostGIS tests).
fs::path writeParcels(const fs::path& path) {
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(GetGDALDriverManager()->GetDriverByName("GPKG")->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    OGRSpatialReference srs;
    srs.importFromEPSG(3857);
    OGRLayer* layer = ds->CreateLayer("parcels", &srs, wkbPolygon, nullptr);
    OGRFieldDefn name("name", OFTString);
    layer->CreateField(&name);
    for (int r = 0; r < 10; ++r)
        for (int c = 0; c < 10; ++c) {
            const double x = 1113194.9 + c * 500.0, y = 5621521.5 + r * 500.0;
            char wkt[256];
            std::snprintf(wkt, sizeof wkt, "POLYGON((%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f))", x, y, x + 400, y,
                          x + 400, y + 400, x, y + 400, x, y);
            OGRFeature f(layer->GetLayerDefn());
            f.SetFID(r * 10 + c + 1);
            f.SetField("name", ("parcel " + std::to_string(r * 10 + c + 1)).c_str());
            OGRGeometry* g = nullptr;
            OGRGeometryFactory::createFromWkt(wkt, &srs, &g);
            f.SetGeometryDirectly(g);
            if (layer->CreateFeature(&f) != OGRERR_NONE) ADD_FAILURE() << "parcel not written";
        }
    return path;
}

struct OgcServices : ::testing::Test {
    void SetUp() override {
        if (!fs::exists(kWorld)) GTEST_SKIP() << "assets/generated is not built: no " << kWorld;
        dir = test::processTempDir("orbis-ogc-test");
        const fs::path parcels = writeParcels(dir / "parcels.gpkg");
        ms = std::make_unique<test::MapServer>(std::vector<std::string>{
            R"(LAYER NAME "world" TYPE RASTER STATUS ON DATA ")" + kWorld.string() + R"(" PROJECTION AUTO END
                 METADATA "ows_title" "World colour" END END)",
            R"(LAYER NAME "relief" TYPE RASTER STATUS ON DATA ")" + kRelief.string() + R"(" PROJECTION AUTO END
                 METADATA "ows_title" "World relief in metres" END END)",
            R"(LAYER NAME "parcels" TYPE POLYGON STATUS ON CONNECTIONTYPE OGR CONNECTION ")" + parcels.string() +
                R"(" DATA "parcels" PROJECTION AUTO END
                 METADATA "ows_title" "Parcels" "wfs_srs" "EPSG:3857" "gml_include_items" "all" "gml_featureid" "fid"
                 END
                 CLASS STYLE COLOR 255 200 0 OUTLINECOLOR 200 50 0 END END END)"},
            std::vector<std::string>{"world"});
        if (!ms->available()) GTEST_SKIP() << ms->error();
        ASSERT_TRUE(ms->running()) << ms->error();
    }
    void TearDown() override {
        ms.reset();
        std::error_code ec;
        if (!dir.empty()) fs::remove_all(dir, ec);
    }
    fs::path dir;
    std::unique_ptr<test::MapServer> ms;
};

/// The generated world as a WMS GetMap layer of `url`.
globe::RasterSourceOptions worldWms(const std::string& url, const fs::path& cache) {
    globe::RasterSourceOptions o;
    o.path = "WMS:" + url + "SERVICE=WMS&VERSION=1.1.1&REQUEST=GetMap&LAYERS=world&SRS=EPSG:4326&BBOX=-180,-90,180,90&FORMAT=image/png";
    o.cacheDir = cache.string();
    return o;
}

// Europe, at about the file's own resolution (4096 x 2048 over the world: 11.4 px a degree).
const globe::GeoExtent kEurope{0.0, 40.0, 22.5, 62.5};

/// How a remote source's tile over Europe differs from the world file's own: the mean absolute
/// difference (of 255) and the share of values more than 48 apart; the remote tile in `tile`.
struct Difference {
    double mean = 0.0, farShare = 0.0;
};
Difference differenceFromTheFile(const globe::RasterSourceOptions& remote, globe::ImageryTile& tile) {
    auto a = globe::RasterSource::open({.path = kWorld.string()});
    auto b = globe::RasterSource::open(remote);
    EXPECT_TRUE(a) << a.message();
    EXPECT_TRUE(b) << b.message();
    if (!a || !b) return {255.0, 1.0};
    auto ta = (*a)->readImagery(kEurope, 256, nullptr);
    auto tb = (*b)->readImagery(kEurope, 256, nullptr);
    EXPECT_TRUE(ta) << ta.message();
    EXPECT_TRUE(tb) << tb.message();
    if (!ta || !tb || !tb->anyValid) return {255.0, 1.0};
    double sum = 0.0;
    size_t far = 0;
    for (size_t i = 0; i < ta->rgba.size(); ++i) {
        if (i % 4 == 3) continue;
        const int d = std::abs(int(ta->rgba[i]) - int(tb->rgba[i]));
        sum += d;
        far += d > 48;
    }
    tile = *tb;
    const double n = double(ta->rgba.size() / 4 * 3);
    return {sum / n, double(far) / n};
}

TEST_F(OgcServices, AWmsLayerReadsAsTheImageItServes) {
    globe::ImageryTile tile;
    const Difference d = differenceFromTheFile(worldWms(ms->url(), dir / "cache"), tile);
    // The server resamples with its own filter (nearest neighbour) where the local read warps
    // with GDAL's cubic: the same picture, not the same pixels.
    EXPECT_LT(d.mean, 6.0);
    EXPECT_LT(d.farShare, 0.01);
    EXPECT_NE(requests(*ms).find("request=getmap"), std::string::npos) << ms->accessLog();
}

// Elevation from a WMS that sends heights (GeoTIFF, Float32): the same terrain as the file.
TEST_F(OgcServices, AWmsLayerOfHeightsReadsAsTheDemItServes) {
    globe::RasterSourceOptions wms, local;
    wms.role = local.role = globe::RasterRole::Elevation;
    wms.path = "WMS:" + ms->url() + "SERVICE=WMS&VERSION=1.1.1&REQUEST=GetMap&LAYERS=relief&SRS=EPSG:4326&BBOX=-180,-90,180,90&FORMAT=image/tiff";
    wms.cacheDir = (dir / "cache").string();
    local.path = kRelief.string();
    auto a = globe::RasterSource::open(local);
    auto b = globe::RasterSource::open(wms);
    ASSERT_TRUE(a) << a.message();
    ASSERT_TRUE(b) << b.message();
    auto ta = (*a)->readElevation(kEurope, 65, nullptr);
    auto tb = (*b)->readElevation(kEurope, 65, nullptr);
    ASSERT_TRUE(ta) << ta.message();
    ASSERT_TRUE(tb) << tb.message();
    ASSERT_TRUE(tb->anyValid);
    double sum = 0.0;
    for (size_t i = 0; i < ta->heights.size(); ++i) sum += std::abs(double(ta->heights[i]) - double(tb->heights[i]));
    const double mean = sum / double(ta->heights.size());
    // Heights, not bytes: the relief's metres, up to thousands. (The WMS's overview here has the
    // file's own grid, 4096 samples round the world, so the server's samples are the file's.)
    EXPECT_GT(ta->maxHeight - ta->minHeight, 500.0f);
    EXPECT_NEAR(tb->maxHeight, ta->maxHeight, 0.1 * (ta->maxHeight - ta->minHeight));
    EXPECT_LT(mean, 0.02 * (ta->maxHeight - ta->minHeight)) << "mean difference " << mean << " m";
    EXPECT_NE(requests(*ms).find("format=image/tiff"), std::string::npos) << ms->accessLog();
}

TEST_F(OgcServices, AWmtsLayerReadsAsTheImageItServes) {
    globe::RasterSourceOptions wmts;
    wmts.path = "WMTS:" + ms->wmtsCapabilitiesUrl() + ",layer=world";
    wmts.cacheDir = (dir / "cache").string();
    globe::ImageryTile tile;
    const Difference d = differenceFromTheFile(wmts, tile);
    // MapCache's level-3 tiles sample the file at its own resolution (as the local warp does).
    EXPECT_LT(d.mean, 6.0);
    const std::string log = ms->accessLog();
    EXPECT_NE(log.find("/wmts/1.0.0/world/default/WGS84/3/"), std::string::npos) << log;
    // The tiles went into the source's cache: a second source over the same cache asks for none.
    size_t cached = 0;
    for (const auto& f : fs::recursive_directory_iterator(dir / "cache")) cached += f.is_regular_file();
    EXPECT_GE(cached, 4u);
    auto again = globe::RasterSource::open(wmts);
    ASSERT_TRUE(again) << again.message();
    auto tc = (*again)->readImagery(kEurope, 256, nullptr);
    ASSERT_TRUE(tc) << tc.message();
    EXPECT_EQ(tc->rgba, tile.rgba);
    const std::string after = ms->accessLog();
    EXPECT_EQ(after.find("/wmts/1.0.0/", log.size()), std::string::npos) << "tiles fetched again:\n" << after.substr(log.size());
}

TEST_F(OgcServices, AWfsLayerReadsAsTheFeaturesItServesAskingForTheBoxAndPaging) {
    vector::VectorReadOptions local, wfs;
    local.source = (dir / "parcels.gpkg").string();
    wfs.source = "WFS:" + ms->url();
    wfs.layers = {"parcels"};
    auto a = vector::readVector(local);
    // Paged (Orbis asks for it: GdalSetup), here 30 at a time.
    test::ScopedGdalConfig pageSize("OGR_WFS_PAGE_SIZE", "30");
    auto b = vector::readVector(wfs);
    ASSERT_TRUE(a) << a.message();
    ASSERT_TRUE(b) << b.message();
    ASSERT_EQ(b->layers.size(), 1u);
    const auto& fa = a->layers[0].features;
    const auto& fb = b->layers[0].features;
    ASSERT_EQ(fb.size(), 100u);
    // MapServer writes GML coordinates in degrees with 6 decimals (0.1 m): that close.
    for (size_t k = 0; k < fa.size(); ++k) {
        const size_t na = *vector::findField(a->layers[0].fields, "name"), nb = *vector::findField(b->layers[0].fields, "name");
        EXPECT_EQ(std::get<std::string>(fa[k].attributes[na]), std::get<std::string>(fb[k].attributes[nb]));
        ASSERT_EQ(fa[k].coords.size(), fb[k].coords.size()) << k;
        for (size_t v = 0; v < fa[k].coords.size(); ++v) {
            EXPECT_NEAR(fa[k].coords[v].x, fb[k].coords[v].x, 1e-6) << k;
            EXPECT_NEAR(fa[k].coords[v].y, fb[k].coords[v].y, 1e-6) << k;
        }
    }
    // Paged: GetFeature asked 30 at a time.
    const std::string log = requests(*ms);
    EXPECT_NE(log.find("startindex=30&count=30"), std::string::npos) << log;
    EXPECT_NE(log.find("startindex=90&count=30"), std::string::npos) << log;
    // A tile's read asks the server for its box only.
    vector::VectorReadOptions tile = wfs;
    tile.within = vector::LonLatBounds{9.99, 44.0, 10.0037, 46.0, false};
    auto c = vector::readVector(tile);
    ASSERT_TRUE(c) << c.message();
    EXPECT_EQ(c->layers[0].features.size(), 10u);
    EXPECT_NE(requests(*ms).find("bbox"), std::string::npos) << ms->accessLog();
}

TEST_F(OgcServices, AServerFaultIsAClearErrorAndTheNextReadGetsTheTile) {
    test::ScopedGdalConfig timeout("GDAL_HTTP_TIMEOUT", "2");
    struct Case {
        test::MapServer::Fault fault;
        const char* says;   // what the message must name
    };
    const Case cases[] = {{test::MapServer::Fault::Status500, "HTTP 500"},
                          {test::MapServer::Fault::Slow, "timed out"},
                          {test::MapServer::Fault::Truncated, "damaged"},
                          {test::MapServer::Fault::Exception, "Invalid layer(s)"}};
    const globe::GeoExtent europe = kEurope;
    int k = 0;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.says);
        // A cache of its own each time: no tile comes from an earlier case.
        auto source = globe::RasterSource::open(worldWms(ms->faultyUrl(), dir / ("cache" + std::to_string(k++))));
        ASSERT_TRUE(source) << source.message();
        const int before = ms->faultsServed();
        ms->setFault(c.fault, 1000, 4);
        auto bad = (*source)->readImagery(europe, 256, nullptr);
        ASSERT_FALSE(bad) << "a faulty answer read as a tile";
        EXPECT_GT(ms->faultsServed(), before);
        EXPECT_NE(bad.message().find("/faulty?"), std::string::npos) << bad.message();
        EXPECT_NE(bad.message().find(c.says), std::string::npos) << bad.message();
        // The server mends: the same read now gets the tile (nothing broken was kept in the cache).
        ms->setFault(c.fault, 0);
        auto good = (*source)->readImagery(europe, 256, nullptr);
        ASSERT_TRUE(good) << good.message();
        EXPECT_TRUE(good->anyValid);
    }
}

// A WFS that fails: the read is a clear error naming the source, and the next read, once the
// server mends, gets the features (the pager's pages retry after 1 s, doubling: FeatureTiles).
TEST_F(OgcServices, AWfsFaultIsAClearErrorAndTheNextReadGetsTheFeatures) {
    test::ScopedGdalConfig timeout("GDAL_HTTP_TIMEOUT", "2");
    vector::VectorReadOptions wfs;
    wfs.source = "WFS:" + ms->faultyUrl();
    wfs.layers = {"parcels"};
    for (const auto& [fault, says] : {std::pair{test::MapServer::Fault::Status500, "the server answered HTTP 500"},
                                      std::pair{test::MapServer::Fault::Exception,
                                                "the server reports an exception: msWMSLoadGetMapParams(): WMS server error. Invalid layer(s)"},
                                      std::pair{test::MapServer::Fault::Slow, "no answer from the server (Operation timed out"}}) {
        SCOPED_TRACE(says);
        ms->setFault(fault, 1000, 4);
        auto bad = vector::readVector(wfs);
        ASSERT_FALSE(bad) << "a faulty answer read as features";
        EXPECT_NE(bad.message().find("/faulty?"), std::string::npos) << bad.message();
        EXPECT_NE(bad.message().find(says), std::string::npos) << bad.message();
        EXPECT_EQ(bad.message().find("<?xml"), std::string::npos) << bad.message();
        ms->setFault(fault, 0);
        auto good = vector::readVector(wfs);
        ASSERT_TRUE(good) << good.message();
        EXPECT_EQ(good->layers.at(0).features.size(), 100u);
    }
}

// In the terrain: a tile that failed is reported, the other layer's tile is drawn meanwhile, and
// the pager's retries (TerrainTiles: kTileRetries, back-off from 1 s) fill it in once the
// server answers again.
TEST_F(OgcServices, AFailedWmsTileIsReportedAndRetriedWhileTheRestIsDrawn) {
    auto local = globe::RasterSource::open({.path = kWorld.string()});
    auto wms = globe::RasterSource::open(worldWms(ms->faultyUrl(), dir / "cache"));
    ASSERT_TRUE(local) << local.message();
    ASSERT_TRUE(wms) << wms.message();
    ms->setFault(test::MapServer::Fault::Status500, 1000);
    globe::TerrainTiles tiles{{}, {}, {*local, *wms}, nullptr};   // loads inline
    const globe::TileKey key = globe::TileKey::containing(10.0, 50.0, 3);
    uint64_t frame = 0;
    const auto frameOf = [&] {
        tiles.beginFrame(++frame);
        tiles.request(1, key, 1.0);
        tiles.request(2, key, 1.0);
        tiles.endFrame();
    };
    // Coarse first: a frame loads the next level on the way down.
    for (int i = 0; i < 8; ++i) frameOf();
    EXPECT_EQ(tiles.state(1, key), globe::DataState::Ready);
    const globe::TileKey root = globe::TileKey::containing(10.0, 50.0, 0);
    EXPECT_EQ(tiles.state(2, root), globe::DataState::Failed);
    EXPECT_EQ(tiles.state(2, key), globe::DataState::Missing);
    ASSERT_FALSE(tiles.errors().empty());
    EXPECT_NE(tiles.errors().front().find("/faulty?"), std::string::npos) << tiles.errors().front();
    EXPECT_NE(tiles.errors().front().find("HTTP 500"), std::string::npos) << tiles.errors().front();
    ms->setFault(test::MapServer::Fault::Status500, 0);
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (tiles.state(2, key) != globe::DataState::Ready && std::chrono::steady_clock::now() < end) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        frameOf();
    }
    EXPECT_EQ(tiles.state(2, key), globe::DataState::Ready);
    EXPECT_GE(tiles.stats().retried, 1u);
    ASSERT_TRUE(tiles.imagery(2, key));
}

/// Sets an environment variable for a scope.
struct ScopedEnv {
    ScopedEnv(const char* name, const std::string& value) : name(name) { ::setenv(name, value.c_str(), 1); }
    ~ScopedEnv() { ::unsetenv(name); }
    const char* name;
};

// HTTP basic authentication and a header, both from the environment: without them the server
// refuses (401, 403) and the message says so; with them the tiles and features come. The
// secrets appear in no message.
TEST_F(OgcServices, CredentialsFromTheEnvironmentOpenProtectedServices) {
    const globe::GeoExtent europe = kEurope;
    const std::string secret = test::MapServer::password(), token = "t0ken-5ecret";
    {
        auto refused = globe::RasterSource::open(worldWms(ms->basicUrl(), dir / "c1"));
        ASSERT_TRUE(refused) << refused.message();
        auto tile = (*refused)->readImagery(europe, 64, nullptr);
        ASSERT_FALSE(tile);
        EXPECT_NE(tile.message().find("HTTP 401"), std::string::npos) << tile.message();
    }
    ScopedEnv basic("ORBIS_TEST_WMS_USERPWD", test::MapServer::user() + ":" + secret);
    ScopedEnv header("ORBIS_TEST_WMS_HEADER", test::MapServer::tokenHeader());
    ScopedEnv wrongHeader("ORBIS_TEST_WMS_WRONG", "X-Orbis-Token: not-it");
    std::vector<std::string> messages;
    for (const auto& [url, auth] : {std::pair{ms->basicUrl(), globe::HttpAuth{.basicEnv = "ORBIS_TEST_WMS_USERPWD"}},
                                    std::pair{ms->tokenUrl(), globe::HttpAuth{.headerEnv = "ORBIS_TEST_WMS_HEADER"}}}) {
        auto o = worldWms(url, dir / ("c-" + auth.basicEnv + auth.headerEnv));
        o.httpAuth = auth;
        auto source = globe::RasterSource::open(o);
        ASSERT_TRUE(source) << source.message();
        auto tile = (*source)->readImagery(europe, 64, nullptr);
        ASSERT_TRUE(tile) << tile.message();
        EXPECT_TRUE(tile->anyValid);
    }
    {
        auto o = worldWms(ms->tokenUrl(), dir / "c3");
        o.httpAuth.headerEnv = "ORBIS_TEST_WMS_WRONG";
        auto source = globe::RasterSource::open(o);
        ASSERT_TRUE(source) << source.message();
        auto tile = (*source)->readImagery(europe, 64, nullptr);
        ASSERT_FALSE(tile);
        EXPECT_NE(tile.message().find("HTTP 403"), std::string::npos) << tile.message();
        messages.push_back(tile.message());
    }
    // A WFS behind basic authentication: the same 100 parcels.
    vector::VectorReadOptions wfs;
    wfs.source = "WFS:" + ms->basicUrl();
    wfs.layers = {"parcels"};
    auto refused = vector::readVector(wfs);
    ASSERT_FALSE(refused);
    messages.push_back(refused.message());
    wfs.httpAuth.basicEnv = "ORBIS_TEST_WMS_USERPWD";
    auto parcels = vector::readVector(wfs);
    ASSERT_TRUE(parcels) << parcels.message();
    EXPECT_EQ(parcels->layers.at(0).features.size(), 100u);
    // A variable that is not set, or not "user:password": named, its value never shown.
    auto o = worldWms(ms->basicUrl(), dir / "c4");
    o.httpAuth.basicEnv = "ORBIS_TEST_NOT_SET";
    auto unset = globe::RasterSource::open(o);
    ASSERT_FALSE(unset);
    EXPECT_NE(unset.message().find("ORBIS_TEST_NOT_SET"), std::string::npos) << unset.message();
    ScopedEnv bare("ORBIS_TEST_BARE", secret.substr(0, 4));
    o.httpAuth.basicEnv = "ORBIS_TEST_BARE";
    auto malformed = globe::RasterSource::open(o);
    ASSERT_FALSE(malformed);
    EXPECT_NE(malformed.message().find("user:password"), std::string::npos) << malformed.message();
    messages.push_back(unset.message());
    messages.push_back(malformed.message());
    for (const std::string& m : messages) {
        EXPECT_EQ(m.find(secret), std::string::npos) << m;
        EXPECT_EQ(m.find(token), std::string::npos) << m;
        EXPECT_EQ(m.find(secret.substr(0, 4)), std::string::npos) << m;
    }
}

TEST_F(OgcServices, CapabilitiesListTheLayersWithTheirCrsAndExtents) {
    auto described = globe::describeOgcServices(ms->url());
    ASSERT_TRUE(described) << described.message();
    const auto j = nlohmann::json::parse(*described);
    EXPECT_EQ(j["kind"], "ogc-services");
    ASSERT_TRUE(j.contains("wms")) << *described;
    ASSERT_TRUE(j.contains("wfs")) << *described;
    EXPECT_EQ(j["wms"]["title"], "Orbis test services");
    bool world = false;
    for (const auto& l : j["wms"]["layers"])
        if (l["name"] == "world") {
            world = true;
            EXPECT_EQ(l["title"], "World colour");
            ASSERT_TRUE(l["wgs84Bounds"].is_array()) << l.dump();
            EXPECT_NEAR(l["wgs84Bounds"][0].get<double>(), -180.0, 1e-6);
            EXPECT_NEAR(l["wgs84Bounds"][3].get<double>(), 90.0, 1e-6);
            EXPECT_NE(l["crs"].dump().find("EPSG:4326"), std::string::npos) << l.dump();
        }
    EXPECT_TRUE(world) << *described;
    ASSERT_EQ(j["wfs"]["layers"].size(), 1u) << *described;
    EXPECT_EQ(j["wfs"]["layers"][0]["name"].get<std::string>().find("parcels") != std::string::npos, true);
    ASSERT_TRUE(j["wfs"]["layers"][0]["wgs84Bounds"].is_array()) << *described;
    EXPECT_NEAR(j["wfs"]["layers"][0]["wgs84Bounds"][0].get<double>(), 10.0, 1e-3);
    EXPECT_TRUE(j.contains("wmtsError")) << "MapServer's own address serves no WMTS";
    // MapCache's WMTS, from the address GDAL takes.
    auto wmts = globe::describeOgcServices("WMTS:" + ms->wmtsCapabilitiesUrl());
    ASSERT_TRUE(wmts) << wmts.message();
    const auto t = nlohmann::json::parse(*wmts);
    ASSERT_TRUE(t.contains("wmts")) << *wmts;
    EXPECT_FALSE(t.contains("wms"));
    ASSERT_EQ(t["wmts"]["layers"].size(), 1u) << *wmts;
    const auto& tiles = t["wmts"]["layers"][0];
    EXPECT_EQ(tiles["name"], "world");
    EXPECT_EQ(tiles["tileMatrixSets"][0], "WGS84");
    EXPECT_EQ(tiles["formats"][0], "image/png");
    EXPECT_NE(tiles["crs"][0].get<std::string>().find("4326"), std::string::npos) << tiles.dump();
    EXPECT_NEAR(tiles["wgs84Bounds"][2].get<double>(), 180.0, 1e-6);
    // Only the service the URL names; a server that is not there: the reason, named.
    auto wfsOnly = globe::describeOgcServices(ms->url() + "SERVICE=WFS");
    ASSERT_TRUE(wfsOnly) << wfsOnly.message();
    EXPECT_FALSE(nlohmann::json::parse(*wfsOnly).contains("wms"));
    auto nobody = globe::describeOgcServices("http://127.0.0.1:1/ows?");
    ASSERT_FALSE(nobody);
    EXPECT_NE(nobody.message().find("http://127.0.0.1:1/ows?"), std::string::npos) << nobody.message();
}

TEST(OgcCapabilities, ExceptionsAndOtherDocumentsAreClearErrors) {
    auto e = globe::parseOgcCapabilities(
        R"(<?xml version="1.0"?><ServiceExceptionReport version="1.1.1"><ServiceException code="LayerNotDefined">no layer 'x'</ServiceException></ServiceExceptionReport>)",
        globe::OgcService::Wms, "http://h/ows?");
    ASSERT_FALSE(e);
    EXPECT_EQ(e.message(), "http://h/ows?: the server reports an exception: no layer 'x'");
    auto html = globe::parseOgcCapabilities("<html><body>Not Found</body></html>", globe::OgcService::Wms, "u");
    ASSERT_FALSE(html);
    EXPECT_EQ(html.message(), "u: not a WMS capabilities document");
    EXPECT_FALSE(globe::parseOgcCapabilities("garbage <", globe::OgcService::Wfs, "u"));
    // WMS 1.1.1: SRS and LatLonBoundingBox, inherited CRSs, a time dimension.
    auto old = globe::parseOgcCapabilities(
        R"(<WMT_MS_Capabilities version="1.1.1"><Service><Title>T</Title></Service><Capability><Layer><SRS>EPSG:4326</SRS>
           <Layer><Name>sst</Name><Title>Sea</Title><LatLonBoundingBox minx="-10" miny="-5" maxx="10" maxy="5"/>
           <Dimension name="time" units="ISO8601"/><Extent name="time">2026-01-01/2026-12-31/P1D</Extent></Layer></Layer></Capability></WMT_MS_Capabilities>)",
        globe::OgcService::Wms, "u");
    ASSERT_TRUE(old) << old.message();
    const auto j = nlohmann::json::parse(*old);
    ASSERT_EQ(j["layers"].size(), 1u);
    EXPECT_EQ(j["layers"][0]["crs"][0], "EPSG:4326");
    EXPECT_EQ(j["layers"][0]["time"], "2026-01-01/2026-12-31/P1D");
    EXPECT_EQ(j["layers"][0]["wgs84Bounds"][2], 10.0);
}

}  // namespace
}  // namespace orbis
