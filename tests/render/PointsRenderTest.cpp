// The points layer on lavapipe with validation: a coloured cloud over the terrain with eye-dome
// lighting off and on, the compute rasteriser against the point-list pipeline, depth against
// the opaque scene, the point budget, and precision at lon 179.9999 from 2 m away.
#include "engine/gpu/Device.h"
#include "globe/Ellipsoid.h"
#include "layers/points/Copc.h"
#include "layers/points/CopcWriter.h"
#include "layers/points/LasReader.h"
#include "layers/points/PointsLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

namespace orbis::test {
namespace {

std::string jsonString(const std::string& s) { return nlohmann::json(s).dump(); }

std::filesystem::path outDir() {
    const auto dir = std::filesystem::path(testOutputDir()) / "points";
    std::filesystem::create_directories(dir);
    return dir;
}

void writeLas(const std::string& path, const std::vector<points::LasPoint>& pts, points::LasWriteOptions o) {
    auto w = points::LasWriter::create(path, o);
    ASSERT_TRUE(w.ok()) << w.message();
    (*w)->write(pts);
    auto closed = (*w)->close();
    ASSERT_TRUE(closed.ok()) << closed.message();
}

// A 240 m x 240 m survey on the fixture mountain's eastern slope, in lon/lat/ellipsoidal height
// (EPSG:4979): ground points 0.1 m above the DEM, coloured by position, a building (class 6, a
// 40 m x 30 m x 15 m box of points) and trees (class 5, cones). Written once per run (and put in
// place whole: test processes run in parallel).
constexpr double kLon = 7.03, kLat = 46.0;
const std::string& mountainCloud() {
    static const std::string path = [] {
        const std::string p = (outDir() / "mountain-survey.las").string();
        std::vector<points::LasPoint> pts;
        const double mPerLon = 111320.0 * std::cos(glm::radians(kLat)), mPerLat = 111132.0;
        const auto at = [&](double e, double n, double up, uint8_t cls, glm::dvec3 rgb) {
            points::LasPoint q;
            const double lon = kLon + e / mPerLon, lat = kLat + n / mPerLat;
            q.position = {lon, lat, TerrainFixtures::height(lon, lat) + up};
            q.classification = cls;
            q.red = uint16_t(rgb.r * 65535), q.green = uint16_t(rgb.g * 65535), q.blue = uint16_t(rgb.b * 65535);
            q.intensity = uint16_t(1000 + 30 * up);
            q.returnNumber = q.numberOfReturns = 1;
            pts.push_back(q);
        };
        for (double n = -120; n <= 120; n += 1.0)
            for (double e = -120; e <= 120; e += 1.0) {
                const double stripe = 0.5 + 0.5 * std::sin(e * 0.08) * std::cos(n * 0.06);
                at(e, n, 0.1, 2, {0.35 + 0.3 * stripe, 0.45 + 0.2 * (n + 120) / 240, 0.25});
            }
        for (double x = -20; x <= 20; x += 0.7)   // the building: walls and a roof
            for (double y = -15; y <= 15; y += 0.7) {
                const bool wall = std::abs(x) > 19.5 || std::abs(y) > 14.5;
                if (wall)
                    for (double z = 0; z <= 15; z += 0.7) at(30 + x, -40 + y, z, 6, {0.75, 0.72, 0.68});
                at(30 + x, -40 + y, 15.0, 6, {0.8, 0.2, 0.15});
            }
        std::mt19937 rng(4);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int t = 0; t < 25; ++t) {   // trees: cones 12 m tall
            const double te = -100 + 90 * u(rng), tn = -100 + 200 * u(rng);
            for (int k = 0; k < 600; ++k) {
                const double h = 3 + 9 * u(rng), r = (12 - h) * 0.35 * std::sqrt(u(rng)), a = 6.2832 * u(rng);
                at(te + r * std::cos(a), tn + r * std::sin(a), h, 5, {0.1, 0.35 + 0.2 * u(rng), 0.12});
            }
        }
        points::LasWriteOptions o;
        o.pointFormat = 3;
        o.scale = glm::dvec3(1e-7, 1e-7, 1e-3);
        EXPECT_TRUE(makeFixture(p, [&](const std::string& tmp) {   // other test processes read it meanwhile
            writeLas(tmp, pts, o);
            return !::testing::Test::HasFailure();
        }));
        return p;
    }();
    return path;
}

std::string mountainLayer() {
    const auto& f = terrainFixtures();
    return R"({"type": "terrain", "name": "Mountain", "sky": false, "elevation": [)" + jsonString(f.dem) +
           R"(], "imagery": [{"path": )" + jsonString(f.image) + "}]}";
}

std::string pointsLayer(const std::string& path, const std::string& extra = "") {
    return R"({"type": "points", "name": "Survey", "path": )" + jsonString(path) + extra + "}";
}

std::string scene(const std::string& viewpoint, const std::string& layers, const char* background = "[0, 0, 0]") {
    return R"({"viewpoint": )" + viewpoint +
           R"(, "time": {"start": "2026-06-21T09:00:00Z", "end": "2026-06-21T09:00:00Z"}, "background": )" + background +
           R"(, "layers": [)" + layers + "]}";
}

std::string surveyView() {
    char v[200];
    std::snprintf(v, sizeof v, R"({"lon": %.6f, "lat": %.6f, "height": %.1f, "heading": 300, "pitch": -35, "range": 420})",
                  kLon, kLat, TerrainFixtures::height(kLon, kLat));
    return v;
}

class PointsRender : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        layers::registerBuiltinLayers(registry_);
    }
    std::unique_ptr<scene::Scene> load(const std::string& json) { return buildScene(json, registry_); }
    ImageRgba8 render(scene::Scene& s, uint32_t w = 320, uint32_t h = 240) {
        return renderSettled(renderer_, device(), s, w, h);
    }
    ImageRgba8 render(const std::string& json, uint32_t w = 320, uint32_t h = 240) {
        auto s = load(json);
        if (!s) return {};
        return render(*s, w, h);
    }
    static layers::PointsLayer& points(scene::Scene& s) {
        return dynamic_cast<layers::PointsLayer&>(*s.resources().back().layer);
    }

    scene::LayerRegistry registry_;
    std::unique_ptr<render::Renderer> renderer_;
};

size_t differing(const ImageRgba8& a, const ImageRgba8& b, int tolerance) {
    return a.pixels.size() == b.pixels.size() ? countDifferentPixels(a, b, tolerance) : size_t(-1);
}

TEST_F(PointsRender, SurveyOverTerrainMatchesGoldens) {
    const std::string layers = mountainLayer() + ", " + pointsLayer(mountainCloud(), R"(, "crs": "EPSG:4979")");
    auto s = load(scene(surveyView(), layers));
    ASSERT_TRUE(s);
    const auto plain = render(*s);
    EXPECT_EQ(points(*s).pointsDrawn(), points(*s).store()->info().points);
    EXPECT_TRUE(matchesGolden(plain, "points_survey"));
    // The cloud shows over the terrain.
    const auto terrainOnly = render(scene(surveyView(), mountainLayer()));
    EXPECT_GT(differing(plain, terrainOnly, 8), size_t(plain.width * plain.height / 6));

    ASSERT_TRUE(points(*s).setParameter("edl", 1));
    ASSERT_TRUE(points(*s).setParameter("pointSize", 2));
    const auto edl = render(*s);
    EXPECT_TRUE(matchesGolden(edl, "points_survey_edl"));
    EXPECT_GT(differing(edl, plain, 8), size_t(plain.width * plain.height / 50));
}

TEST_F(PointsRender, CloudFromTheCacheFileDrawsTheSame) {
    // 1 MB of working memory: the octree goes through a cache file and its nodes are read back
    // on workers; the image is the in-memory one. A second load reuses the cache.
    const std::string layers = pointsLayer(mountainCloud(), R"(, "crs": "EPSG:4979")");
    const auto inMemory = render(scene(surveyView(), layers));
    const auto cacheDir = outDir() / "cache";
    std::filesystem::remove_all(cacheDir);
    const std::string cached = pointsLayer(mountainCloud(), R"(, "crs": "EPSG:4979", "cpuMemoryMB": 1, "cacheFolder": )" +
                                                                jsonString(cacheDir.string()));
    for (int run = 0; run < 2; ++run) {
        auto s = load(scene(surveyView(), cached));
        ASSERT_TRUE(s);
        const auto img = render(*s);
        ASSERT_TRUE(points(*s).store()->onDisk());
        EXPECT_EQ(points(*s).pointsDrawn(), points(*s).store()->info().points);
        EXPECT_EQ(differing(img, inMemory, 0), 0u) << "run " << run;
    }
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(cacheDir)) files += e.path().extension() == ".orbis-points";
    EXPECT_EQ(files, 1u);
}

TEST_F(PointsRender, PagedNodeDataDrawsTheSame) {
    // The resident data (1.2 MB) in 320 KB pages (as lavapipe's 128 MB maxStorageBufferRange
    // splits a big budget): one splat dispatch per page, and the point list rebinds per page.
    // Same image.
    const std::string whole = pointsLayer(mountainCloud(), R"(, "crs": "EPSG:4979")");
    const auto inOne = render(scene(surveyView(), whole));
    for (const char* renderer : {"compute", "pointList"}) {
        SCOPED_TRACE(renderer);
        auto s = load(scene(surveyView(), pointsLayer(mountainCloud(), std::string(R"(, "crs": "EPSG:4979", "gpuPageMB": 0.3125, "renderer": ")")
                                                                           .append(renderer)
                                                                           .append("\""))));
        ASSERT_TRUE(s);
        const auto paged = render(*s);
        const auto& residency = *points(*s).residency();
        EXPECT_GE(residency.pages(), 4u);
        EXPECT_EQ(residency.pageBytes(), 320u << 10);
        EXPECT_EQ(points(*s).pointsDrawn(), points(*s).store()->info().points);
        if (std::string(renderer) == "compute") {
            EXPECT_EQ(differing(paged, inOne, 0), 0u);
        }
    }
    // A buffer of two pages: what is in view is drawn as far as it fits, and moving the view
    // from the survey's south-west corner to its north-east one evicts nodes for others.
    char corner[200];
    const double dLon = 100.0 / (111320.0 * std::cos(glm::radians(kLat))), dLat = 100.0 / 111132.0;
    std::snprintf(corner, sizeof corner, R"({"lon": %.6f, "lat": %.6f, "height": %.1f, "heading": 45, "pitch": -30, "range": 40})",
                  kLon - dLon, kLat - dLat, TerrainFixtures::height(kLon - dLon, kLat - dLat));
    auto s = load(scene(corner, pointsLayer(mountainCloud(), R"(, "crs": "EPSG:4979", "gpuMemoryMB": 0.625, "gpuPageMB": 0.3125, "pointBudget": 0)")));
    ASSERT_TRUE(s);
    const auto small = render(*s);
    auto& layer = points(*s);
    EXPECT_LE(layer.residency()->residentBytes(), uint64_t(640) << 10);
    EXPECT_GT(layer.pointsDrawn(), 0u);
    EXPECT_LT(layer.pointsDrawn(), layer.store()->info().points);
    EXPECT_GT(differing(small, ImageRgba8{small.width, small.height, std::vector<uint8_t>(small.pixels.size(), 0)}, 8), 1000u);
    const uint64_t evicted = layer.residency()->evictions();
    scene::Camera& camera = s->camera();
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    camera.setPosition(camera.position() + wgs84.toEcef(kLon + dLon, kLat + dLat) - wgs84.toEcef(kLon - dLon, kLat - dLat));
    const auto other = render(*s);
    EXPECT_GT(layer.residency()->evictions(), evicted);
    EXPECT_LE(layer.residency()->residentBytes(), uint64_t(640) << 10);
    EXPECT_GT(layer.pointsDrawn(), 0u);
    EXPECT_GT(differing(small, other, 8), 1000u);
    EXPECT_TRUE(writePng(outDir() / "paged-sw.png", small).ok());
    EXPECT_TRUE(writePng(outDir() / "paged-ne.png", other).ok());
}

TEST_F(PointsRender, ColourModesAndPointListAgreeWithCompute) {
    const std::string layers = pointsLayer(mountainCloud(), R"(, "crs": "EPSG:4979")");
    auto s = load(scene(surveyView(), layers));
    ASSERT_TRUE(s);
    const auto compute = render(*s);
    ASSERT_TRUE(points(*s).setParameter("renderer", 1));
    const auto list = render(*s);
    // The same points land on the same pixels; only ties between points in one pixel (the
    // list keeps the first drawn at equal depth, compute the highest index) may differ.
    EXPECT_LT(differing(compute, list, 6), compute.pixels.size() / 4 / 100) << "more than 1 % of the pixels differ";
    ASSERT_TRUE(points(*s).setParameter("renderer", 0));
    std::map<std::string, ImageRgba8> byMode;
    for (const char* mode : {"rgb", "intensity", "classification", "height", "constant"}) {
        ASSERT_TRUE(points(*s).setOption("color", mode));
        byMode[mode] = render(*s);
    }
    EXPECT_FALSE(points(*s).setOption("color", "rainbow"));
    for (auto& [a, ia] : byMode)
        for (auto& [b, ib] : byMode)
            if (a < b) {
                EXPECT_GT(differing(ia, ib, 8), 2000u) << a << " vs " << b;
            }
}

TEST_F(PointsRender, OpacityBlendsTheCloudOverTheTerrain) {
    // Half opacity, compute path: each pixel the cloud covers is the mean (in linear light) of
    // the opaque cloud's colour and the terrain's (one point a pixel is resolved). The point
    // list blends every point that passes the depth test, so where points overlap in a pixel
    // (drawn far to near) the cloud comes out more opaque: between the two, never outside.
    // Opacity 0 leaves the terrain alone on both.
    const std::string layers = mountainLayer() + ", " + pointsLayer(mountainCloud(), R"(, "crs": "EPSG:4979")");
    auto s = load(scene(surveyView(), layers));
    ASSERT_TRUE(s);
    const auto terrainOnly = render(scene(surveyView(), mountainLayer()));
    const auto toLinear = [](uint8_t v) {
        const double c = v / 255.0;
        return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    };
    for (const double renderer : {0.0, 1.0}) {
        const bool compute = renderer == 0.0;
        SCOPED_TRACE(compute ? "compute" : "point list");
        ASSERT_TRUE(points(*s).setParameter("renderer", renderer));
        ASSERT_TRUE(points(*s).setParameter("opacity", 1.0));
        const auto opaque = render(*s);
        ASSERT_TRUE(points(*s).setParameter("opacity", 0.5));
        const auto half = render(*s);
        size_t covered = 0, off = 0;
        for (size_t i = 0; i < half.pixels.size(); i += 4) {
            if (std::abs(int(opaque.pixels[i]) - int(terrainOnly.pixels[i])) < 40) continue;   // no point here
            ++covered;
            for (size_t c = 0; c < 3; ++c) {
                const double o = toLinear(opaque.pixels[i + c]), t = toLinear(terrainOnly.pixels[i + c]);
                const double got = toLinear(half.pixels[i + c]);
                const bool ok = compute ? std::abs(got - 0.5 * (o + t)) <= 0.02
                                        : got >= std::min(o, t) - 0.02 && got <= std::max(o, t) + 0.02 &&
                                              std::abs(got - t) >= 0.4 * std::abs(o - t) - 0.02;
                if (!ok) ++off;
            }
        }
        EXPECT_GT(covered, size_t(1000));
        EXPECT_LT(off, 3 * covered / 50) << "channels not blended between the cloud and the terrain (over 2 %)";
        ASSERT_TRUE(points(*s).setParameter("opacity", 0.0));
        EXPECT_LT(differing(render(*s), terrainOnly, 1), size_t(10));
    }
    EXPECT_FALSE(points(*s).setParameter("opacity", 1.5));
}

TEST_F(PointsRender, TheOpaqueSceneHidesPointsBehindIt) {
    // The same cloud 300 m under the ground: the terrain hides it entirely.
    std::vector<points::LasPoint> pts;
    auto file = points::LasFile::open(mountainCloud());
    ASSERT_TRUE(file.ok());
    EXPECT_TRUE((*file)->read(0, (*file)->points(), pts).ok());
    for (auto& p : pts) p.position.z -= 300.0;
    const std::string buried = (outDir() / "buried.las").string();
    points::LasWriteOptions o;
    o.scale = glm::dvec3(1e-7, 1e-7, 1e-3);
    writeLas(buried, pts, o);
    const auto terrainOnly = render(scene(surveyView(), mountainLayer()));
    const auto hidden = render(scene(surveyView(), mountainLayer() + ", " + pointsLayer(buried, R"(, "crs": "EPSG:4979")")));
    EXPECT_EQ(differing(hidden, terrainOnly, 0), 0u);
    // Without the terrain the same points show.
    const auto bare = render(scene(surveyView(), pointsLayer(buried, R"(, "crs": "EPSG:4979")")));
    size_t lit = 0;
    for (size_t i = 0; i < bare.pixels.size(); i += 4) lit += bare.pixels[i] + bare.pixels[i + 1] > 30 ? 1 : 0;
    EXPECT_GT(lit, size_t(bare.width * bare.height / 20));
}

// The survey written as LAZ (format 7, layered chunks) draws exactly as its LAS twin: the same
// points, decoded by Orbis's LAZ reader, through the same octree.
TEST_F(PointsRender, LazCloudDrawsExactlyAsItsLasTwin) {
    const std::string laz = (outDir() / "mountain-survey.laz").string();
    ASSERT_TRUE(makeFixture(laz, [&](const std::string& tmp) {
        auto las = points::LasFile::open(mountainCloud());
        std::vector<points::LasPoint> pts;
        if (!las || !(*las)->read(0, UINT64_MAX, pts)) return false;
        points::LasWriteOptions o;
        o.versionMinor = 4;
        o.pointFormat = 7;
        o.scale = glm::dvec3(1e-7, 1e-7, 1e-3);
        o.laz = true;
        writeLas(tmp, pts, o);
        return !::testing::Test::HasFailure();
    }));
    const auto plain = render(scene(surveyView(), mountainLayer() + ", " + pointsLayer(mountainCloud(), R"(, "crs": "EPSG:4979")")));
    auto s = load(scene(surveyView(), mountainLayer() + ", " + pointsLayer(laz, R"(, "crs": "EPSG:4979")")));
    ASSERT_TRUE(s);
    const auto compressed = render(*s);
    EXPECT_EQ(points(*s).pointsDrawn(), points(*s).store()->info().points);
    EXPECT_EQ(differing(compressed, plain, 0), 0u);
    EXPECT_TRUE(matchesGolden(compressed, "points_survey"));   // the LAS cloud's golden
}

// A COPC file is drawn from its own octree (15 nodes read from the file, nothing built): the
// picture equals the same points loaded from a LAS file through Orbis's octree build, to within
// the quantisation of node positions.
TEST_F(PointsRender, CopcCloudFromItsOwnOctreeDrawsAsTheBuiltOne) {
    const std::string copc = std::string(ORBIS_SHARED_DATA_DIR) + "/lidar/lone-star.copc.laz";
    if (!std::filesystem::exists(copc)) GTEST_SKIP() << "../shared/data is absent";
    const std::string las = (outDir() / "lone-star.las").string();
    ASSERT_TRUE(makeFixture(las, [&](const std::string& tmp) {
        auto f = points::LasFile::open(copc);
        std::vector<points::LasPoint> pts;
        if (!f || !(*f)->read(0, UINT64_MAX, pts)) return false;
        points::LasWriteOptions o;
        o.versionMinor = 4;
        o.pointFormat = 6;
        o.scale = (*f)->header().scale;
        o.offset = (*f)->header().offset;
        writeLas(tmp, pts, o);
        return !::testing::Test::HasFailure();
    }));
    // Lone Star Geyser, Yellowstone: the file's WKT names a geocentric CRS its coordinates are
    // not in; they are UTM 12N (NAD83).
    const char* view = R"({"lon": -110.806744, "lat": 44.418375, "height": 2330, "heading": 30, "pitch": -45, "range": 80})";
    // Classes (a fixed palette): the colour ramps of intensity and height depend on the ranges
    // each store measures (the COPC store from its root node, the build from every point).
    const std::string extra = R"(, "crs": "EPSG:26912", "color": "classification", "edl": true)";
    auto s = load(scene(view, pointsLayer(copc, extra)));
    ASSERT_TRUE(s);
    const auto streamed = render(*s);
    const auto& store = *points(*s).store();
    EXPECT_TRUE(store.streamed());
    EXPECT_EQ(store.nodes().size(), 15u);
    EXPECT_EQ(store.info().depth, 2u);
    EXPECT_EQ(points(*s).pointsDrawn(), 518862u);
    EXPECT_TRUE(matchesGolden(streamed, "points_copc_lone_star"));
    const auto built = render(scene(view, pointsLayer(las, extra)));
    EXPECT_LT(differing(streamed, built, 8), size_t(streamed.width * streamed.height / 200));
    size_t lit = 0;
    for (size_t i = 0; i < streamed.pixels.size(); i += 4) lit += streamed.pixels[i] > 0 ? 1 : 0;
    EXPECT_GT(lit, size_t(streamed.width * streamed.height / 20));
}

TEST_F(PointsRender, BudgetDrawsTheNearestNodesFirst) {
    const std::string layers = pointsLayer(mountainCloud(), R"(, "crs": "EPSG:4979", "pointBudget": 20000)");
    auto s = load(scene(surveyView(), layers));
    ASSERT_TRUE(s);
    const auto limited = render(*s);
    auto& layer = points(*s);
    EXPECT_LE(layer.pointsDrawn(), 20000u);
    EXPECT_GT(layer.pointsDrawn(), 16384u);   // at least the root
    ASSERT_TRUE(layer.setParameter("pointBudget", 0));
    const auto full = render(*s);
    EXPECT_EQ(layer.pointsDrawn(), layer.store()->info().points);
    EXPECT_GT(layer.nodesDrawn(), 4u);
    // A fifth of the points still cover the survey's silhouette: the images are alike in shape.
    size_t litLimited = 0, litFull = 0;
    for (size_t i = 0; i < full.pixels.size(); i += 4) {
        litLimited += limited.pixels[i] + limited.pixels[i + 1] + limited.pixels[i + 2] > 0 ? 1 : 0;
        litFull += full.pixels[i] + full.pixels[i + 1] + full.pixels[i + 2] > 0 ? 1 : 0;
    }
    EXPECT_GT(litLimited, litFull / 4);
    EXPECT_GT(litFull, litLimited);
}

// A COPC file with one damaged node (its chunk overwritten): the layer warns once and draws every
// other node; nothing stops, nothing crashes.
TEST_F(PointsRender, ADamagedCopcNodeIsSkippedAndTheOthersDraw) {
    const std::string good = std::string(ORBIS_SHARED_DATA_DIR) + "/lidar/lone-star.copc.laz";
    if (!std::filesystem::exists(good)) GTEST_SKIP() << "../shared/data is absent";
    auto f = points::LasFile::open(good);
    ASSERT_TRUE(f.ok()) << f.message();
    auto nodes = points::copc::readHierarchy(**f, *(*f)->copc());
    ASSERT_TRUE(nodes.ok()) << nodes.message();
    const points::copc::Node* victim = nullptr;   // a node below the root
    for (const auto& n : *nodes)
        if (n.key.d == 1 && (!victim || n.points > victim->points)) victim = &n;
    ASSERT_NE(victim, nullptr);
    const std::string bad = (outDir() / "lone-star-damaged.copc.laz").string();
    std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
    {
        std::fstream io(bad, std::ios::in | std::ios::out | std::ios::binary);
        io.seekp(std::streamoff(victim->offset + 40));
        const std::string junk(std::min<uint32_t>(victim->bytes - 40, 4000), '\x5a');
        io.write(junk.data(), std::streamsize(junk.size()));
    }
    const char* view = R"({"lon": -110.806744, "lat": 44.418375, "height": 2330, "heading": 30, "pitch": -45, "range": 80})";
    auto s = load(scene(view, pointsLayer(bad, R"(, "crs": "EPSG:26912", "pointBudget": 0)")));
    ASSERT_TRUE(s);
    const auto img = render(*s);
    auto& layer = points(*s);
    EXPECT_TRUE(layer.store()->streamed());
    EXPECT_GT(layer.pointsDrawn(), 518862u / 3);
    EXPECT_LE(layer.pointsDrawn(), 518862u - victim->points);
    size_t lit = 0;
    for (size_t i = 0; i < img.pixels.size(); i += 4) lit += img.pixels[i] + img.pixels[i + 1] + img.pixels[i + 2] > 0 ? 1 : 0;
    EXPECT_GT(lit, size_t(img.width * img.height / 20));
}

// The survey written by Orbis as COPC (its own octree, LAZ nodes) and drawn from that octree over
// the terrain: the picture of the LAS file through the octree build, to within the quantisation
// of the two trees' node positions.
TEST_F(PointsRender, OrbisWrittenCopcOverTerrainDrawsAsTheLas) {
    const std::string copc = (outDir() / "mountain-survey.copc.laz").string();
    ASSERT_TRUE(makeFixture(copc, [&](const std::string& tmp) {
        // The survey with its CRS in the file (COPC requires one; the LAS fixture has it from the scene).
        auto plain = points::LasFile::open(mountainCloud());
        std::vector<points::LasPoint> pts;
        if (!plain || !(*plain)->read(0, UINT64_MAX, pts)) return false;
        points::LasWriteOptions w;
        w.versionMinor = 4;
        w.pointFormat = 7;
        w.scale = glm::dvec3(1e-7, 1e-7, 1e-3);
        w.wkt = "EPSG:4979";
        writeLas(tmp + ".las", pts, w);
        auto las = points::LasFile::open(tmp + ".las");
        if (!las) return false;
        points::CopcWriteOptions o;
        o.maxNodePoints = 20000;
        auto written = points::writeCopc(**las, tmp, o);
        EXPECT_TRUE(written.ok()) << (written.ok() ? "" : written.message());
        std::filesystem::remove(tmp + ".las");
        return written.ok();
    }));
    const std::string extra = R"(, "crs": "EPSG:4979", "pointBudget": 0)";
    auto s = load(scene(surveyView(), mountainLayer() + ", " + pointsLayer(copc, extra)));
    ASSERT_TRUE(s);
    const auto streamed = render(*s);
    EXPECT_TRUE(points(*s).store()->streamed());
    EXPECT_EQ(points(*s).pointsDrawn(), points(*s).store()->info().points);
    EXPECT_TRUE(matchesGolden(streamed, "points_copc_survey"));
    const auto built = render(scene(surveyView(), mountainLayer() + ", " + pointsLayer(mountainCloud(), extra)));
    EXPECT_LT(differing(streamed, built, 8), size_t(streamed.width * streamed.height / 200));
}

// Level-aware sizes: under a budget that leaves out the finer nodes, the points of the coarser
// ones grow to the spacing of what is drawn at their place, so the survey's footprint (where the
// full cloud covers the ground) keeps few background pixels; with fixed one-pixel points it is
// full of holes. With no budget the full cloud looks as it does with fixed sizes, give or take
// the leaves' larger points.
TEST_F(PointsRender, AdaptiveSizesFillTheHolesABudgetLeaves) {
    const std::string base = R"(, "crs": "EPSG:4979", "color": "classification")";
    const auto full = render(scene(surveyView(), pointsLayer(mountainCloud(), base + R"(, "pointBudget": 0)")));
    const auto fixed = render(scene(surveyView(), pointsLayer(mountainCloud(), base + R"(, "pointBudget": 17000)")));
    auto s = load(scene(surveyView(), pointsLayer(mountainCloud(), base + R"(, "pointBudget": 17000, "adaptiveSize": true)")));
    ASSERT_TRUE(s);
    const auto adaptive = render(*s);
    EXPECT_LE(points(*s).pointsDrawn(), 17000u);
    size_t footprint = 0, holesFixed = 0, holesAdaptive = 0;
    const auto lit = [](const ImageRgba8& img, size_t i) { return img.pixels[i] + img.pixels[i + 1] + img.pixels[i + 2] > 0; };
    for (size_t i = 0; i < full.pixels.size(); i += 4) {
        if (!lit(full, i)) continue;
        ++footprint;
        holesFixed += lit(fixed, i) ? 0 : 1;
        holesAdaptive += lit(adaptive, i) ? 0 : 1;
    }
    ASSERT_GT(footprint, full.pixels.size() / 4 / 8);
    EXPECT_GT(holesFixed, footprint / 5) << holesFixed << " of " << footprint;
    EXPECT_LT(holesAdaptive, footprint / 50) << holesAdaptive << " of " << footprint;
    EXPECT_TRUE(matchesGolden(adaptive, "points_adaptive_budget"));
    // The point-list fallback sizes its points the same way.
    ASSERT_TRUE(points(*s).setOption("renderer", "pointList"));
    const auto list = render(*s);
    size_t holesList = 0;
    for (size_t i = 0; i < full.pixels.size(); i += 4) holesList += lit(full, i) && !lit(list, i) ? 1 : 0;
    EXPECT_LT(holesList, footprint / 20) << holesList << " of " << footprint;
}

TEST_F(PointsRender, MetreCloudAtTheAntimeridianHasNoJitter) {
    // 64 points on an 8 x 8 grid 1 m across at lon 179.9999, lat 0, 8000 m, seen from 2 m: each
    // point's pixel must be where the double-precision projection puts it, and stay so when the
    // camera moves by 1 mm (float ECEF would snap these points to a 0.5 m lattice).
    std::vector<points::LasPoint> pts;
    for (int i = 0; i < 64; ++i) {
        points::LasPoint p;
        p.position = {(i % 8) / 7.0 - 0.5, (i / 8) / 7.0 - 0.5, 0.0};
        p.red = uint16_t((20 + 3 * i) << 8), p.green = 255 << 8, p.blue = 0;
        pts.push_back(p);
    }
    const std::string path = (outDir() / "metre.las").string();
    points::LasWriteOptions o;
    o.scale = glm::dvec3(1e-4);
    writeLas(path, pts, o);
    const std::string layer = pointsLayer(path, R"(, "origin": {"lon": 179.9999, "lat": 0, "height": 8000})");
    for (double shift : {0.0, 0.001}) {
        char view[200];
        std::snprintf(view, sizeof view, R"({"lon": 179.9999, "lat": %.12f, "height": 8000, "pitch": -89.9, "range": 2})",
                      shift / 110574.0);
        auto s = load(scene(view, layer));
        ASSERT_TRUE(s);
        const auto img = render(*s, 320, 240);
        (void)writePng(outDir() / (shift > 0 ? "metre-moved.png" : "metre.png"), img);
        const auto& cam = s->camera();
        const glm::dmat4 viewProj = cam.projection(320.0 / 240.0) * cam.viewRotation();
        const auto& ell = globe::Ellipsoid::wgs84();
        const glm::dvec3 origin = ell.toEcef(179.9999, 0.0, 8000.0);
        const glm::dmat3 enu = ell.enuFrame(179.9999, 0.0);
        int found = 0;
        for (int i = 0; i < 64; ++i) {
            const glm::dvec4 c = viewProj * glm::dvec4(origin + enu * pts[size_t(i)].position - cam.position(), 1.0);
            const double x = (c.x / c.w * 0.5 + 0.5) * 320.0, y = (c.y / c.w * 0.5 + 0.5) * 240.0;
            if (x < 1 || y < 1 || x > 319 || y > 239) continue;
            // Where the point's own colour is, in the 3 x 3 pixels around the expected one.
            bool here = false;
            for (int dy = -1; dy <= 1 && !here; ++dy)
                for (int dx = -1; dx <= 1 && !here; ++dx) {
                    const size_t k = (size_t(int(y) + dy) * 320 + size_t(int(x) + dx)) * 4;
                    here = std::abs(int(img.pixels[k]) - (20 + 3 * i)) <= 1 && img.pixels[k + 1] > 250;
                }
            EXPECT_TRUE(here) << "point " << i << " not at (" << x << ", " << y << ") with shift " << shift;
            ++found;
        }
        EXPECT_GT(found, 30) << "too few points in view";
    }
}

TEST_F(PointsRender, BadLayersGiveClearErrors) {
    const auto error = [&](const std::string& layer) {
        auto desc = scene::parseSceneText(scene(surveyView(), layer), "test.json", ".");
        if (!desc) return desc.message();
        auto s = scene::Scene::build(std::move(desc).value(), registry_);
        return s ? std::string() : s.message();
    };
    EXPECT_NE(error(R"({"type": "points", "name": "P"})").find("path"), std::string::npos);
    const std::string notLas = (outDir() / "not-a-cloud.las").string();
    std::FILE* f = std::fopen(notLas.c_str(), "wb");
    ASSERT_TRUE(f);
    std::fputs("this is not a LAS file at all, just some text that is long enough to hold a header? no.", f);
    std::fclose(f);
    EXPECT_NE(error(pointsLayer(notLas)).find("not-a-cloud.las"), std::string::npos);
    // No CRS anywhere: the message says how to give one.
    std::vector<points::LasPoint> pts(3);
    const std::string bare = (outDir() / "no-crs.las").string();
    writeLas(bare, pts, {});
    const std::string noCrs = error(pointsLayer(bare));
    EXPECT_NE(noCrs.find("no-crs.las"), std::string::npos) << noCrs;
    EXPECT_NE(noCrs.find("\"crs\""), std::string::npos) << noCrs;
    EXPECT_NE(error(pointsLayer(bare, R"(, "crs": "EPSG:999999")")).find("999999"), std::string::npos);
    EXPECT_NE(error(pointsLayer(bare, R"(, "crs": "EPSG:4979", "color": "rainbow")")).find("color"), std::string::npos);
    EXPECT_NE(error(pointsLayer(bare, R"(, "crs": "EPSG:4979", "pointSize": 40)")).find("pointSize"), std::string::npos);
    EXPECT_NE(error(pointsLayer(bare, R"(, "crs": "EPSG:4979", "renderer": "magic")")).find("renderer"), std::string::npos);
    // An empty cloud is valid: it draws nothing.
    const std::string empty = (outDir() / "empty.las").string();
    writeLas(empty, {}, {});
    const auto img = render(scene(surveyView(), pointsLayer(empty, R"(, "crs": "EPSG:4979")")));
    ASSERT_FALSE(img.pixels.empty());
    for (size_t i = 0; i < img.pixels.size(); i += 4) ASSERT_EQ(img.pixels[i] + img.pixels[i + 1] + img.pixels[i + 2], 0);
}

}  // namespace
}  // namespace orbis::test
