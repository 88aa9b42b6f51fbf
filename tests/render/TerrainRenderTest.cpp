// The streamed terrain on lavapipe with validation: golden images, no background through the
// globe on the first frame, no cracks once loaded, poles and antimeridian, a camera 1 m above a
// mountain top (no jitter), 40 000 km out, bad inputs, memory budgets, and real data from
// ../shared/data when it is there.
#include "engine/gpu/Device.h"
#include "base/ThreadPool.h"
#include "globe/Ellipsoid.h"
#include "layers/terrain/TerrainLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"
#include "tests/support/HttpServer.h"
#include "tests/support/XyzTiles.h"

#include <gdal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace orbis::test {
namespace {

std::string jsonString(const std::string& s) { return nlohmann::json(s).dump(); }

/// A terrain scene over the mountain fixture (or `layerJson` when given).
std::string terrainScene(const std::string& viewpoint, const std::string& layerJson, const std::string& background,
                         const std::string& time = "2026-06-21T06:30:00Z") {
    return R"({"viewpoint": )" + viewpoint + R"(, "time": {"start": ")" + time + R"(", "end": ")" + time +
           R"("}, "background": )" + background + R"(, "layers": [)" + layerJson + "]}";
}

std::string mountainLayer(const std::string& extra = "") {
    const auto& f = terrainFixtures();
    return R"({"type": "terrain", "name": "Mountain", "elevation": [)" + jsonString(f.dem) +
           R"(], "imagery": [{"path": )" + jsonString(f.image) + "}]" + extra + "}";
}

std::string worldLayer(const std::string& extra = "") {
    const std::string dir = std::string(ORBIS_SOURCE_DIR) + "/assets/generated/";
    return R"({"type": "terrain", "name": "World", "elevation": [)" + jsonString(dir + "world-relief.tif") +
           R"(], "imagery": [{"path": )" + jsonString(dir + "world-colour.tif") + "}]" + extra + "}";
}

const char* kRed = "[1, 0, 0]";
const char* kDark = "[0, 0, 0.012]";

class TerrainRender : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        layers::registerBuiltinLayers(registry_);
    }

    std::unique_ptr<scene::Scene> load(const std::string& json) { return buildScene(json, registry_); }

    /// Renders after loading everything the view needs (settle), or the very first frame.
    ImageRgba8 render(scene::Scene& scene, bool settle = true, uint32_t w = 320, uint32_t h = 240) {
        if (!renderer_ || renderer_->width() != w || renderer_->height() != h)
            renderer_ = std::make_unique<render::Renderer>(device(), w, h);
        scene.time().advance(0.0);
        if (settle) {
            renderer_->settle(scene, 120.0);
            EXPECT_FALSE(scene.busy()) << "still loading after 120 s";
        }
        const auto frame = renderer_->render(scene, true);
        return ImageRgba8{w, h, renderer_->readPixels(frame)};
    }

    static layers::TerrainLayer& terrain(scene::Scene& scene) {
        return dynamic_cast<layers::TerrainLayer&>(*scene.resources().front().layer);
    }

    /// Pixels inside the ellipsoid's silhouette (the pixel and its 4 neighbours see the
    /// ellipsoid) that still show the pure red background.
    static size_t redInsideGlobe(const ImageRgba8& img, const scene::Camera& camera) {
        const auto& ell = globe::Ellipsoid::wgs84();
        const double aspect = double(img.width) / img.height;
        const auto hits = [&](double x, double y) {
            const glm::dvec3 d = camera.rayDirection(2.0 * x / img.width - 1.0, 2.0 * y / img.height - 1.0, aspect);
            return ell.intersectRay(camera.position(), d).has_value();
        };
        size_t red = 0;
        for (uint32_t y = 0; y < img.height; ++y)
            for (uint32_t x = 0; x < img.width; ++x) {
                const uint8_t* p = &img.pixels[(size_t(y) * img.width + x) * 4];
                if (!(p[0] > 250 && p[1] < 5 && p[2] < 5)) continue;
                const double cx = x + 0.5, cy = y + 0.5;
                if (hits(cx, cy) && hits(cx - 1, cy) && hits(cx + 1, cy) && hits(cx, cy - 1) && hits(cx, cy + 1)) ++red;
            }
        return red;
    }

    scene::LayerRegistry registry_;
    std::unique_ptr<render::Renderer> renderer_;
};

bool worldAvailable() {
    return std::filesystem::exists(std::string(ORBIS_SOURCE_DIR) + "/assets/generated/world-relief.tif");
}

TEST_F(TerrainRender, FirstFrameShowsNoBackgroundThroughTheGlobe) {
    // Nothing is loaded on the first frame: every selected tile stands on the ellipsoid.
    auto scene = load(terrainScene(R"({"lon": 7, "lat": 46, "range": 12000000})", mountainLayer(R"(, "sky": false)"), kRed));
    ASSERT_TRUE(scene);
    const auto img = render(*scene, /*settle=*/false);
    EXPECT_EQ(redInsideGlobe(img, scene->camera()), 0u);
    EXPECT_GT(terrain(*scene).stats().tilesDrawn, 0u);
}

TEST_F(TerrainRender, MountainMatchesGoldenWithoutCracks) {
    auto scene = load(terrainScene(R"({"lon": 7, "lat": 46, "height": 1500, "heading": 30, "pitch": -25, "range": 90000})",
                                   mountainLayer(R"(, "sky": false)"), kRed));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    EXPECT_EQ(redInsideGlobe(img, scene->camera()), 0u) << "cracks or holes between tiles";
    EXPECT_TRUE(matchesGolden(img, "terrain_mountain"));
    const auto& stats = terrain(*scene).stats();
    EXPECT_GT(stats.deepestLevel, 6u);
    EXPECT_GT(stats.tilesWithOwnElevation, 0u);
    // Settled: every drawn tile over the DEM has its own data (or, past the DEM's finest
    // level, its ancestor at that level), never a coarser stand-in.
    const auto* model = terrain(*scene).tiles();
    const globe::GeoExtent dem{6.0, 45.0, 8.0, 47.0};
    size_t overDem = 0;
    for (const auto& t : terrain(*scene).selection()) {
        if (!t.key.extent().intersects(dem)) continue;
        ++overDem;
        const globe::TileKey own = t.key.ancestor(std::min(t.key.level, model->maxDataLevel(0)));
        EXPECT_EQ(model->state(0, own), globe::DataState::Ready) << own.toString();
    }
    EXPECT_GT(overDem, 4u);
    EXPECT_TRUE(terrain(*scene).errors().empty());
}

TEST_F(TerrainRender, HeightAtMatchesTheDem) {
    auto scene = load(terrainScene(R"({"lon": 7, "lat": 46, "height": 1500, "pitch": -60, "range": 40000})",
                                   mountainLayer(), kDark));
    ASSERT_TRUE(scene);
    render(*scene);
    for (const auto& [lon, lat] : {std::pair{7.0, 46.0}, {6.93, 45.97}, {7.1, 46.05}}) {
        const auto h = scene->heightAt(lon, lat);
        ASSERT_TRUE(h.has_value()) << lon << ", " << lat;
        EXPECT_NEAR(*h, TerrainFixtures::height(lon, lat), 25.0) << lon << ", " << lat;
    }
    // Outside the DEM: the ellipsoid.
    const auto sea = scene->heightAt(-30.0, 10.0);
    EXPECT_TRUE(!sea || *sea == 0.0);
}

TEST_F(TerrainRender, GradientsMatchAcrossTileEdges) {
    // Loaded neighbours share their edge samples; with the one-sample border read with each
    // tile, both compute the same central differences there, so lighting has no seam. (GDAL's
    // approximate transformer moves samples by up to 1/8 pixel between reads: centimetres.)
    auto scene = load(terrainScene(R"({"lon": 7, "lat": 46, "height": 1500, "pitch": -60, "range": 40000})",
                                   mountainLayer(), kDark));
    ASSERT_TRUE(scene);
    render(*scene);
    const auto* model = terrain(*scene).tiles();
    const int n = model->settings().gridSize;
    int pairs = 0;
    double worst = 0.0, largest = 0.0, worstHeight = 0.0, worstOneSided = 0.0;
    for (const auto& t : terrain(*scene).selection()) {
        if (t.key.level > model->maxDataLevel(0)) continue;
        const auto a = model->elevation(t.key);
        const auto east = t.key.neighbour(1, 0), south = t.key.neighbour(0, 1);
        if (!a) continue;
        for (int dir = 0; dir < 2; ++dir) {
            const auto& nk = dir == 0 ? east : south;
            const auto b = nk ? model->elevation(*nk) : nullptr;
            if (!b) continue;
            ++pairs;
            const globe::GeoExtent e = t.key.extent();
            for (int k = 0; k < n; ++k) {
                // Only where both tiles have the DEM's own samples around the edge (outside it
                // they are filled from ancestors, which differ between neighbours).
                const double lon = dir == 0 ? e.east : e.west + k * e.width() / (n - 1);
                const double lat = dir == 0 ? e.north - k * e.height() / (n - 1) : e.south;
                const double margin = 2.0 * e.width() / (n - 1);
                if (!(lon > 6.0 + margin && lon < 8.0 - margin && lat > 45.0 + margin && lat < 47.0 - margin)) continue;
                // East pair: A's column n-1 is B's column 0; south pair: A's row n-1 is B's row 0.
                const size_t ia = dir == 0 ? size_t(k * n + n - 1) : size_t((n - 1) * n + k);
                const size_t ib = dir == 0 ? size_t(k * n) : size_t(k);
                worstHeight = std::max(worstHeight, double(std::abs(a->heights[ia] - b->heights[ib])));
                // What one-sided differences at the edge (no border) would give, for scale.
                const size_t step = dir == 0 ? 1 : size_t(n);
                const double oneSidedA = a->heights[ia] - a->heights[ia - step];
                const double oneSidedB = b->heights[ib + step] - b->heights[ib];
                worstOneSided = std::max(worstOneSided, std::abs(oneSidedA - oneSidedB));
                for (int c = 0; c < 2; ++c) {
                    worst = std::max(worst, double(std::abs(a->gradients[ia * 2 + c] - b->gradients[ib * 2 + c])));
                    largest = std::max(largest, double(std::abs(a->gradients[ia * 2 + c])));
                }
            }
        }
    }
    ASSERT_GT(pairs, 3);
    EXPECT_GT(largest, 5.0);   // metres per sample: the slopes are real
    std::printf("%d pairs: edge heights differ by %.4f m at most, gradients by %.4f m (one-sided ones would by "
                "%.4f m; largest %.1f m per sample)\n",
                pairs, worstHeight, worst, worstOneSided, largest);
    EXPECT_LE(worstHeight, 0.5);
    EXPECT_LE(worst, 5e-3 * largest) << "over " << pairs << " neighbouring pairs";
    EXPECT_LT(worst * 5.0, worstOneSided);
}

TEST_F(TerrainRender, OneMetreAboveTheSummitDoesNotJitter) {
    // Find the summit's height from a first load, then put the eye 1 m above it.
    auto probe = load(terrainScene(R"({"lon": 7, "lat": 46, "pitch": -89, "range": 5000})", mountainLayer(), kDark));
    ASSERT_TRUE(probe);
    render(*probe);
    const auto peak = probe->heightAt(TerrainFixtures::kPeakLon, TerrainFixtures::kPeakLat);
    ASSERT_TRUE(peak.has_value());
    // The eye 1 m above the summit looking east, 10 degrees down; then the same moved 1 mm east.
    const auto eyeAt = [&](double eastMetres) {
        const double dLon = eastMetres / (6378137.0 * std::cos(glm::radians(TerrainFixtures::kPeakLat))) * 180.0 /
                            glm::pi<double>();
        return globe::poseFromEye({TerrainFixtures::kPeakLon + dLon, TerrainFixtures::kPeakLat, *peak + 1.0}, 90.0, -10.0);
    };
    auto a = load(terrainScene(R"({"lon": 7, "lat": 46, "range": 1000})", mountainLayer(), kDark));
    auto b = load(terrainScene(R"({"lon": 7, "lat": 46, "range": 1000})", mountainLayer(), kDark));
    ASSERT_TRUE(a && b);
    a->camera().setPose(eyeAt(0.0));
    b->camera().setPose(eyeAt(0.001));
    const auto imgA = render(*a);
    const auto imgB = render(*b);
    EXPECT_TRUE(matchesGolden(imgA, "terrain_one_metre"));
    EXPECT_TRUE(imagesAgree(imgA, imgB, "terrain_one_metre_moved", 5, size_t(0.001 * imgA.width * imgA.height)));
}

TEST(TerrainModel, DemsStackFinestWinsAndCoarserFillsHoles) {
    const auto& f = terrainFixtures();
    std::vector<std::shared_ptr<globe::RasterSource>> dems;
    for (const auto& path : {f.coarse, f.holed}) {   // coarse first: the model sorts finest first
        globe::RasterSourceOptions o;
        o.path = path;
        o.role = globe::RasterRole::Elevation;
        auto s = globe::RasterSource::open(o);
        ASSERT_TRUE(s.ok()) << s.message();
        dems.push_back(*s);
    }
    globe::TerrainTiles model({}, dems, {}, nullptr);   // no pool: loads run inline
    model.beginFrame(1);
    const auto load = [&](double lon, double lat, bool covered = true) {
        const auto key = globe::TileKey::containing(lon, lat, 10);
        model.request(0, key, 0.0);
        // Outside every source the chain stops at the first empty ancestor.
        if (covered) {
            EXPECT_EQ(model.state(0, key), globe::DataState::Ready);
        }
        return model.heightAt(lon, lat).value_or(-1e9);
    };
    // The fine DEM where it has data.
    EXPECT_NEAR(load(7.5, 46.5), TerrainFixtures::height(7.5, 46.5), 25.0);
    EXPECT_NEAR(load(6.5, 45.4), TerrainFixtures::height(6.5, 45.4), 25.0);
    // Its nodata hole: the coarser DEM, not a spike to the ellipsoid.
    EXPECT_NEAR(load(7.0, 46.0), TerrainFixtures::kCoarseHeight, 1.0);
    // Outside the fine DEM, inside the coarse one.
    EXPECT_NEAR(load(5.5, 44.5), TerrainFixtures::kCoarseHeight, 1.0);
    // Outside both: the ellipsoid.
    EXPECT_EQ(load(20.0, 10.0, false), 0.0);
    EXPECT_EQ(model.state(0, globe::TileKey::containing(20.0, 10.0, 10)), globe::DataState::Missing);
}

TEST_F(TerrainRender, CameraPathPosesAreKeptAboveTheGround) {
    auto scene = load(terrainScene(R"({"lon": 7, "lat": 46, "height": 1500, "pitch": -60, "range": 40000})",
                                   mountainLayer(), kDark));
    ASSERT_TRUE(scene);
    render(*scene);
    const auto& ell = globe::Ellipsoid::wgs84();
    const auto ground = scene->heightAt(7.0, 46.0);
    ASSERT_TRUE(ground.has_value());
    ASSERT_GT(*ground, 3000.0);
    // An eye inside the mountain comes out 2 m above its surface, straight up, same orientation.
    const globe::Pose inside = globe::poseFromEye({7.0, 46.0, 100.0}, 30.0, -10.0);
    const globe::Pose kept = scene->keptAboveGround(inside);
    const globe::Geodetic g = ell.toGeodetic(kept.position);
    EXPECT_NEAR(g.height, *ground + 2.0, 1e-6);
    EXPECT_NEAR(g.lonDeg, 7.0, 1e-9);
    EXPECT_NEAR(g.latDeg, 46.0, 1e-9);
    EXPECT_EQ(kept.orientation, inside.orientation);
    // An eye in the air is left alone.
    const globe::Pose above = globe::poseFromEye({7.0, 46.0, *ground + 50.0}, 30.0, -10.0);
    EXPECT_EQ(scene->keptAboveGround(above).position, above.position);
}

TEST_F(TerrainRender, FortyThousandKilometresOut) {
    if (!worldAvailable()) GTEST_SKIP() << "assets/generated not built";
    auto scene = load(terrainScene(R"({"lon": -60, "lat": -10, "range": 40000000})", worldLayer(), kDark));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    EXPECT_TRUE(matchesGolden(img, "terrain_far"));
}

TEST_F(TerrainRender, PolesAndAntimeridianHaveNoHoles) {
    if (!worldAvailable()) GTEST_SKIP() << "assets/generated not built";
    const std::pair<const char*, const char*> views[] = {
        {"terrain_north_pole", R"({"lon": 0, "lat": 90, "range": 4000000})"},
        {"terrain_south_pole", R"({"lon": 30, "lat": -90, "range": 600000, "pitch": -60})"},
        {"terrain_antimeridian", R"({"lon": 180, "lat": 0, "range": 800000, "pitch": -50, "heading": 270})"},
    };
    for (const auto& [name, vp] : views) {
        auto scene = load(terrainScene(vp, worldLayer(R"(, "sky": false)"), kRed, "2026-03-20T00:00:00Z"));
        ASSERT_TRUE(scene);
        const auto img = render(*scene);
        EXPECT_EQ(redInsideGlobe(img, scene->camera()), 0u) << name;
        EXPECT_TRUE(matchesGolden(img, name)) << name;
    }
}

TEST_F(TerrainRender, SyntheticPlanetSceneMatchesGolden) {
    if (!worldAvailable()) GTEST_SKIP() << "assets/generated not built";
    auto desc = scene::parseSceneFile(std::string(ORBIS_SOURCE_DIR) + "/assets/scenes/synthetic-planet.json");
    ASSERT_TRUE(desc.ok()) << desc.message();
    auto scene = scene::Scene::build(std::move(desc).value(), registry_);
    ASSERT_TRUE(scene.ok()) << scene.message();
    const auto img = render(**scene);
    EXPECT_TRUE(matchesGolden(img, "terrain_default"));
}

TEST_F(TerrainRender, BadSourcesAreReportedAndLeftOut) {
    const auto& f = terrainFixtures();
    const std::string layer = R"({"type": "terrain", "name": "Bad", "sky": false, "elevation": [)" +
                              jsonString((f.dir / "missing.tif").string()) + ", " + jsonString(f.corrupt) + ", " +
                              jsonString(f.noCrs) + ", " + jsonString(f.huge) + "]}";
    auto scene = load(terrainScene(R"({"lon": 7, "lat": 46, "range": 3000000})", layer, kRed));
    ASSERT_TRUE(scene);
    const auto t0 = std::chrono::steady_clock::now();
    const auto img = render(*scene);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& errors = terrain(*scene).errors();
    ASSERT_EQ(errors.size(), 3u);
    EXPECT_NE(errors[0].find("missing.tif"), std::string::npos) << errors[0];
    EXPECT_NE(errors[1].find("corrupt.tif"), std::string::npos) << errors[1];
    EXPECT_NE(errors[2].find("no-crs.tif"), std::string::npos) << errors[2];
    // The placeholder: the ellipsoid, whole.
    EXPECT_EQ(redInsideGlobe(img, scene->camera()), 0u);
    EXPECT_LT(seconds, 60.0) << "the 10^6 x 10^6 file must not be read in full";
}

TEST_F(TerrainRender, XyzImageryFromALocalServerLandsWhereTheSameImageFromAFileDoes) {
    // The same colour field twice: XYZ PNG tiles (web mercator) served over HTTP on 127.0.0.1,
    // and a local geodetic GeoTIFF. Rendered from the same view, the two images must agree.
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(testOutputDir()) / ("xyz-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    ASSERT_EQ(writeXyzTiles(dir / "tiles", 3), "");
    const std::string local = (dir / "same-colours.tif").string();
    {
        GDALAllRegister();
        const int w = 1440, h = 720;   // 0.25 deg pixels
        GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), local.c_str(), w, h, 3, GDT_Byte, nullptr);
        ASSERT_NE(ds, nullptr);
        const double gt[6] = {-180.0, 0.25, 0, 90.0, 0, -0.25};
        GDALSetGeoTransform(ds, const_cast<double*>(gt));
        GDALSetProjection(ds, "EPSG:4326");
        std::vector<uint8_t> px(size_t(w) * h * 3);
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                uint8_t* p = &px[(size_t(j) * w + i) * 3];
                p[0] = xyzRedAt(-180.0 + (i + 0.5) * 0.25);
                p[1] = xyzGreenAt(90.0 - (j + 0.5) * 0.25);
                p[2] = 128;
            }
        ASSERT_EQ(GDALDatasetRasterIO(ds, GF_Write, 0, 0, w, h, px.data(), w, h, GDT_Byte, 3, nullptr, 3, 3 * w, 1),
                  CE_None);
        GDALClose(ds);
    }
    HttpServer server(dir / "tiles");
    ASSERT_TRUE(server.running()) << server.error();
    ::setenv("ORBIS_CACHE_DIR", (dir / "cache").c_str(), 1);   // GDAL's WMS disk cache

    const char* view = R"({"lon": 30, "lat": 10, "pitch": -90, "range": 6000000})";
    const auto layer = [](const std::string& source) {
        return R"({"type": "terrain", "name": "Imagery", "sky": false, "lighting": "headlight", "imagery": [)" +
               source + "]}";
    };
    auto remote = load(terrainScene(view, layer(R"({"xyz": )" + jsonString(server.url() + "/{z}/{x}/{y}.png") +
                                                 R"(, "maxZoom": 3})"),
                                    kDark));
    ASSERT_TRUE(remote);
    const auto a = render(*remote);
    EXPECT_TRUE(terrain(*remote).errors().empty());
    EXPECT_GT(server.requestCount(), 0);
    EXPECT_EQ(server.notFoundCount(), 0);
    auto file = load(terrainScene(view, layer(R"({"path": )" + jsonString(local) + "}"), kDark));
    ASSERT_TRUE(file);
    const auto b = render(*file);
    ::unsetenv("ORBIS_CACHE_DIR");

    // The field is a smooth ramp, so both resamplings agree to rounding; a tile in the wrong
    // place, flipped or in the wrong projection would be tens of levels off.
    size_t globePixels = 0, over2 = 0;
    int worst = 0;
    for (size_t i = 0; i < a.pixels.size(); i += 4) {
        if (b.pixels[i + 2] < 20) continue;   // background
        ++globePixels;
        for (int c = 0; c < 3; ++c) {
            const int d = std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c]));
            worst = std::max(worst, d);
            if (d > 2) ++over2;
        }
    }
    EXPECT_GT(globePixels, a.pixels.size() / 4 / 2);
    EXPECT_LE(worst, 6);
    EXPECT_LT(over2, globePixels / 100) << "pixels differing by more than 2 levels";
    // And the image is the field, not a flat colour: red grows eastward across the view.
    const auto red = [&](uint32_t x) { return int(a.pixels[(size_t(a.height / 2) * a.width + x) * 4]); };
    EXPECT_GT(red(a.width * 3 / 4) - red(a.width / 4), 12);
    EXPECT_TRUE(matchesGolden(a, "terrain_xyz"));
    fs::remove_all(dir);
}

TEST(TerrainSettings, BadSourceEntriesNameTheKeyAndTheProblem) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    const auto build = [&](const std::string& imagery) -> std::string {
        const std::string json = R"({"layers": [{"type": "terrain", "imagery": [)" + imagery + "]}]}";
        auto desc = scene::parseSceneText(json, "bad.json", ".");
        if (!desc) return desc.message();
        auto scene = scene::Scene::build(std::move(desc).value(), registry);
        return scene ? std::string() : scene.message();
    };
    EXPECT_EQ(build(R"({"xyz": "http://127.0.0.1:1/{z}/{x}/{y}.png", "maxZoom": 5})"), "");
    const struct { const char* imagery; const char* key; const char* problem; } cases[] = {
        {R"({"path": "a.tif", "maxZoom": 5})", "maxZoom", "only applies to an \"xyz\" source"},
        {R"({"xyz": "http://h/{z}/{x}/{y}.png", "maxZoom": 2.5})", "maxZoom", "integer"},
        {R"({"xyz": "http://h/{z}/{x}/{y}.png", "maxZoom": 40})", "maxZoom", "30"},
        {R"({"xyz": "http://h/{z}/{x}/{y}.png", "path": "a.tif"})", "xyz", "exactly one of"},
        {R"({"name": "nothing"})", "path", "exactly one of"},
        {R"({"path": "WMS:http://h/ows?", "auth": {}})", "auth", "basicEnv"},
        {R"({"path": "WMS:http://h/ows?", "auth": {"basic": "X"}})", "auth", "unknown key"},
        {R"({"path": "WMS:http://h/ows?", "auth": {"basicEnv": "ORBIS_TEST_SURELY_NOT_SET"}})", "auth",
         "ORBIS_TEST_SURELY_NOT_SET (HTTP basic credentials) is not set"},
        {R"({"path": "a.tif", "time": "2026-01-01"})", "time", "applies to a WMS source"},
        {R"({"path": "WMS:http://h/ows?", "time": "2026-01-01/2026-02-01"})", "time", "no period"},
        {R"({"path": "WMS:http://h/ows?", "time": [1]})", "time", "as strings"},
    };
    for (const auto& c : cases) {
        const std::string message = build(c.imagery);
        EXPECT_NE(message.find("bad.json"), std::string::npos) << c.imagery << " -> " << message;
        EXPECT_NE(message.find(c.key), std::string::npos) << c.imagery << " -> " << message;
        EXPECT_NE(message.find(c.problem), std::string::npos) << c.imagery << " -> " << message;
    }
}

TEST_F(TerrainRender, ImageryLayersBlendInOrderWithOpacityAndVisibility) {
    // Flat colours over the whole globe: red, then blue at half opacity on top. Blending is in
    // linear light, so it must look exactly like one layer of the linear mix (0.5, 0, 0.5),
    // which is sRGB (188, 0, 188). A hidden or fully transparent layer must change nothing.
    namespace fs = std::filesystem;
    GDALAllRegister();
    const fs::path dir = fs::path(testOutputDir()) / ("blend-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const auto flat = [&](const char* name, uint8_t r, uint8_t g, uint8_t b) {
        const std::string file = (dir / name).string();
        GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), file.c_str(), 8, 4, 3, GDT_Byte, nullptr);
        EXPECT_NE(ds, nullptr);
        const double gt[6] = {-180.0, 45.0, 0, 90.0, 0, -45.0};
        GDALSetGeoTransform(ds, const_cast<double*>(gt));
        GDALSetProjection(ds, "EPSG:4326");
        for (int band = 1; band <= 3; ++band) {
            std::vector<uint8_t> v(32, band == 1 ? r : band == 2 ? g : b);
            EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(ds, band), GF_Write, 0, 0, 8, 4, v.data(), 8, 4, GDT_Byte, 0, 0),
                      CE_None);
        }
        GDALClose(ds);
        return jsonString(file);
    };
    const std::string red = flat("red.tif", 255, 0, 0), blue = flat("blue.tif", 0, 0, 255),
                      mixed = flat("mixed.tif", 188, 0, 188);
    const auto renderWith = [&](const std::string& imagery) {
        auto scene = load(terrainScene(R"({"lon": 20, "lat": 10, "range": 12000000})",
                                       R"({"type": "terrain", "name": "Blend", "sky": false, "imagery": [)" + imagery + "]}",
                                       kDark));
        EXPECT_TRUE(scene);
        return scene ? render(*scene) : ImageRgba8{};
    };
    const auto maxDifference = [](const ImageRgba8& a, const ImageRgba8& b) {
        int worst = 0;
        for (size_t i = 0; i < a.pixels.size() && i < b.pixels.size(); ++i)
            worst = std::max(worst, std::abs(int(a.pixels[i]) - int(b.pixels[i])));
        return a.pixels.size() == b.pixels.size() ? worst : 256;
    };
    const auto blended = renderWith(R"({"path": )" + red + R"(}, {"path": )" + blue + R"(, "opacity": 0.5})");
    const auto reference = renderWith(R"({"path": )" + mixed + "}");
    const auto redOnly = renderWith(R"({"path": )" + red + "}");
    EXPECT_LE(maxDifference(blended, reference), 2);
    EXPECT_GT(maxDifference(blended, redOnly), 60);   // the blue layer does show
    EXPECT_LE(maxDifference(renderWith(R"({"path": )" + red + R"(}, {"path": )" + blue + R"(, "visible": false})"), redOnly),
              0);
    EXPECT_LE(maxDifference(renderWith(R"({"path": )" + red + R"(}, {"path": )" + blue + R"(, "opacity": 0})"), redOnly),
              0);
    // Order matters: blue under red at full opacity is red.
    EXPECT_LE(maxDifference(renderWith(R"({"path": )" + blue + R"(}, {"path": )" + red + "}"), redOnly), 0);

    // The same changes live, as the viewer's panel makes them (one setting per imagery layer).
    auto live = load(terrainScene(R"({"lon": 20, "lat": 10, "range": 12000000})",
                                  R"({"type": "terrain", "name": "Blend", "sky": false, "imagery": [{"path": )" + red +
                                      R"(}, {"path": )" + blue + "}]}",
                                  kDark));
    ASSERT_TRUE(live);
    scene::LiveSettings& terrain = *live->find("Blend")->layer->asLiveSettings();
    ASSERT_TRUE(terrain.setParameter("imageryOpacity1", 0.5));
    EXPECT_LE(maxDifference(render(*live), reference), 2);
    ASSERT_TRUE(terrain.setParameter("imageryVisible1", 0.0));
    EXPECT_LE(maxDifference(render(*live), redOnly), 0);
    EXPECT_FALSE(terrain.setParameter("imageryOpacity2", 0.5)) << "there is no third layer";
    EXPECT_FALSE(terrain.setParameter("imageryOpacity0", 1.5));
    fs::remove_all(dir);
}

TEST_F(TerrainRender, MemoryStaysWithinBudgetsOnALongFlight) {
    if (!worldAvailable()) GTEST_SKIP() << "assets/generated not built";
    auto scene = load(terrainScene(R"({"lon": 0, "lat": 0, "range": 20000000})",
                                   worldLayer(R"(, "cpuCacheMB": 16, "gpuCacheMB": 48, "sky": false)"), kDark));
    ASSERT_TRUE(scene);
    auto& layer = terrain(*scene);
    uint64_t peakCpu = 0, peakGpu = 0;
    // Low over many places: far more tiles than the budgets hold.
    for (int i = 0; i < 16; ++i) {
        globe::Viewpoint vp;
        vp.lonDeg = -170.0 + i * 23.0;
        vp.latDeg = -60.0 + (i % 8) * 17.0;
        vp.range = 60000.0;
        vp.pitchDeg = -40.0;
        scene->camera().setPose(globe::poseFromViewpoint(vp));
        render(*scene, true, 256, 192);
        peakCpu = std::max(peakCpu, layer.tiles()->cpuBytes());
        peakGpu = std::max(peakGpu, layer.gpuBytes());
    }
    EXPECT_LE(peakCpu, uint64_t(16.0 * 1.1 * (1 << 20)));
    EXPECT_LE(peakGpu, uint64_t(48.0 * 1.1 * (1 << 20)));
    EXPECT_GT(layer.tiles()->stats().evicted, 0u) << "the flight should have needed evictions";
}

// ---- real data from ../shared/data (skipped when absent) -------------------------------

class SharedDataTerrain : public TerrainRender {
protected:
    void SetUp() override {
        TerrainRender::SetUp();
        data_ = sharedDataDir();
        if (data_.empty()) GTEST_SKIP() << "../shared/data is absent";
    }
    std::string path(const char* rel) const { return jsonString((data_ / rel).string()); }
    std::filesystem::path data_;
};

TEST_F(SharedDataTerrain, OlindaUtmDemWithLandsatBands321) {
    const std::string layer = R"({"type": "terrain", "name": "Olinda", "verticalExaggeration": 10, "elevation": [)" +
                              path("dem/olinda_dem_utm25s.tif") + R"(], "imagery": [{"path": )" +
                              path("imagery/L7_ETMs.tif") + R"(, "bands": [3, 2, 1]}]})";
    auto scene = load(terrainScene(R"({"lon": -34.87, "lat": -8.0, "pitch": -45, "heading": 20, "range": 14000})", layer, kDark,
                                   "2026-06-21T13:00:00Z"));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    EXPECT_TRUE(matchesGolden(img, "terrain_olinda"));
    EXPECT_TRUE(terrain(*scene).errors().empty());
    // Where GDAL says: gdallocationinfo -wgs84 gives the nearest pixel; the bilinear height lies
    // within its 3x3 neighbourhood's range (values read with gdal_translate -srcwin).
    struct Probe { double lon, lat, lo, hi; };
    for (const Probe& p : {Probe{-34.88, -8.02, 2, 9}, Probe{-34.86, -8.00, 14, 22}}) {
        const auto h = terrain(*scene).tiles()->heightAt(p.lon, p.lat);
        ASSERT_TRUE(h.has_value());
        EXPECT_GE(*h, p.lo - 1.0) << p.lon << ", " << p.lat;
        EXPECT_LE(*h, p.hi + 1.0) << p.lon << ", " << p.lat;
    }
}

TEST_F(SharedDataTerrain, LuxembourgNodataHolesFallBackWithoutSpikes) {
    const std::string layer = R"({"type": "terrain", "name": "Lux", "verticalExaggeration": 8, "elevation": [)" +
                              path("dem/lux_elev.tif") + "]}";
    auto scene = load(terrainScene(R"({"lon": 6.13, "lat": 49.8, "pitch": -40, "range": 90000})", layer, kDark));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    EXPECT_TRUE(matchesGolden(img, "terrain_luxembourg"));
    // No spikes: every loaded height is within the DEM's valid range (or the ellipsoid).
    for (double lat = 49.45; lat < 50.19; lat += 0.01)
        for (double lon = 5.75; lon < 6.53; lon += 0.01) {
            const auto h = terrain(*scene).tiles()->heightAt(lon, lat);
            if (!h) continue;
            EXPECT_GE(*h, 0.0);
            EXPECT_LE(*h, 560.0);
        }
}

TEST_F(SharedDataTerrain, WorldImageryOverTheWholeGlobe) {
    const std::string layer = R"({"type": "terrain", "name": "World", "imagery": [{"path": )" +
                              path("imagery/world.tif") + R"(}, {"path": )" + path("imagery/boston-inset-wgs84.tif") + "}]}";
    auto scene = load(terrainScene(R"({"lon": -40, "lat": 35, "range": 15000000})", layer, kDark,
                                   "2026-03-20T14:00:00Z"));
    ASSERT_TRUE(scene);
    const auto img = render(*scene);
    EXPECT_TRUE(matchesGolden(img, "terrain_world"));
}

}  // namespace
}  // namespace orbis::test
