// The terrain's ground height (layers/terrain/TerrainGround.h) is the same for the same point
// whatever has been streamed: after different loading histories, cache evictions and camera
// paths. What clamped vehicles and camera collision stand on depends on the scene alone.
#include "globe/TerrainTiles.h"
#include "layers/terrain/TerrainGround.h"
#include "layers/terrain/TerrainLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/support/GpuTest.h"

#include <nlohmann/json.hpp>

#include <utility>
#include <vector>

namespace orbis::test {
namespace {

std::shared_ptr<globe::RasterSource> mountainDem() {
    globe::RasterSourceOptions o;
    o.path = terrainFixtures().dem;
    o.role = globe::RasterRole::Elevation;
    auto s = globe::RasterSource::open(o);
    EXPECT_TRUE(s.ok()) << s.message();
    return s.ok() ? *s : nullptr;
}

const std::vector<std::pair<double, double>> kProbes = {
    {7.0, 46.0}, {6.93, 45.97}, {7.1, 46.05}, {6.2, 45.3}, {7.77, 46.61}, {8.5, 40.0} /* off the DEM */};

std::string mountainScene(const std::string& viewpoint) {
    return R"({"viewpoint": )" + viewpoint + R"(, "time": {"start": "2026-06-21T06:30:00Z", "end": "2026-06-21T06:30:00Z"},
        "layers": [{"type": "terrain", "name": "Mountain", "elevation": [)" + nlohmann::json(terrainFixtures().dem).dump() + "]}]}";
}

}  // namespace

TEST(TerrainGround, SameHeightsAfterDifferentLoadingHistories) {
    auto dem = mountainDem();
    ASSERT_TRUE(dem);
    // History A: the probes first, in a fresh cache.
    layers::TerrainGround a(65, 22, {dem});
    std::vector<double> first;
    for (const auto& [lon, lat] : kProbes) first.push_back(a.heightAt(lon, lat).value_or(-1e9));
    // History B: a cache of 1 MiB (a few dozen tiles) filled by a sweep over the whole DEM,
    // frame after frame, so that the probes' tiles are read, evicted and read again.
    layers::TerrainGround b(65, 22, {dem}, 1ull << 20);
    uint64_t most = 0;
    for (int frame = 0; frame < 4; ++frame) {
        for (double lon = 6.0; lon <= 8.0; lon += 0.05)
            for (double lat = 45.0 + 0.013 * frame; lat <= 47.0; lat += 0.1) (void)b.heightAt(lon, lat);
        most = std::max(most, b.cacheBytes());
        b.endFrame();
    }
    EXPECT_GT(b.tilesRead(), 200u) << "the sweep read and evicted tiles";
    // Bounded: twice the budget within a frame, plus the tile chain of one query.
    EXPECT_LT(most, (2ull << 20) + (1ull << 20));
    for (size_t i = 0; i < kProbes.size(); ++i) {
        const auto [lon, lat] = kProbes[i];
        EXPECT_EQ(b.heightAt(lon, lat).value_or(-1e9), first[i]) << lon << ", " << lat;
    }
    // The answers are the DEM's (Int16 posts 0.005 degrees apart, bilinear between them: 25 m
    // on the mountain's flanks), and the ellipsoid off it.
    for (size_t i = 0; i + 1 < kProbes.size(); ++i)
        EXPECT_NEAR(first[i], TerrainFixtures::height(kProbes[i].first, kProbes[i].second), 25.0) << i;
    EXPECT_EQ(first.back(), 0.0);
    EXPECT_EQ(a.level(), b.level());
    EXPECT_FALSE(a.heightAt(7.0, 95.0));
}

TEST(TerrainGround, TheRenderersCacheAloneWouldDependOnHistory) {
    // Why TerrainGround exists: the streaming model answers from the finest tile it holds, so
    // one point has one height after coarse loads and another after fine ones.
    auto dem = mountainDem();
    ASSERT_TRUE(dem);
    globe::TerrainTiles model({}, {dem}, {}, nullptr);
    model.beginFrame(1);
    const double lon = 6.93, lat = 45.97;
    model.request(0, globe::TileKey::containing(lon, lat, 5), 0.0);
    const double coarse = model.heightAt(lon, lat).value_or(-1e9);
    model.request(0, globe::TileKey::containing(lon, lat, model.maxDataLevel(0)), 0.0);
    const double fine = model.heightAt(lon, lat).value_or(-1e9);
    EXPECT_GT(std::abs(fine - coarse), 1.0);
    layers::TerrainGround ground(65, 22, {dem});
    EXPECT_EQ(ground.heightAt(lon, lat).value_or(-2e9), fine) << "the ground is the DEM at its own level";
}

class TerrainGroundRender : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        layers::registerBuiltinLayers(registry_);
    }
    void settle(scene::Scene& s) {
        if (!renderer_) renderer_ = std::make_unique<render::Renderer>(device(), 160, 120);
        s.time().advance(0.0);
        renderer_->settle(s, 120.0);
        renderer_->render(s, true);
    }
    scene::LayerRegistry registry_;
    std::unique_ptr<render::Renderer> renderer_;
};

TEST_F(TerrainGroundRender, SceneHeightsDoNotDependOnTheCameraPath) {
    // Scene A sees the whole DEM from 400 km (coarse tiles only); scene B goes down to 2 km over
    // each probe first (fine tiles), then back out. Scene::heightAt agrees to the bit.
    const std::string far = R"({"lon": 7, "lat": 46, "pitch": -89, "range": 400000})";
    auto a = buildScene(mountainScene(far), registry_);
    auto b = buildScene(mountainScene(far), registry_);
    ASSERT_TRUE(a && b);
    settle(*a);
    auto& terrainA = dynamic_cast<layers::TerrainLayer&>(*a->resources().front().layer);
    const uint64_t versionA = terrainA.groundVersion();
    std::vector<double> heightsA;
    for (const auto& [lon, lat] : kProbes) heightsA.push_back(a->heightAt(lon, lat).value_or(-1e9));
    for (const auto& [lon, lat] : kProbes) {
        b->camera().setPose(globe::poseFromEye({lon, lat, 6000.0}, 0.0, -60.0));
        settle(*b);
    }
    b->camera().setPose(globe::poseFromEye({7.0, 44.0, 300000.0}, 0.0, -60.0));
    settle(*b);
    for (size_t i = 0; i < kProbes.size(); ++i)
        EXPECT_EQ(b->heightAt(kProbes[i].first, kProbes[i].second).value_or(-1e9), heightsA[i]) << i;
    // Streaming more tiles does not change the answers, so the ground's version stays; the
    // vertical exaggeration does change them.
    settle(*a);
    EXPECT_EQ(terrainA.groundVersion(), versionA);
    ASSERT_TRUE(terrainA.setParameter("verticalExaggeration", 2.0));
    EXPECT_NE(terrainA.groundVersion(), versionA);
    EXPECT_EQ(a->heightAt(kProbes[0].first, kProbes[0].second).value_or(-1e9), 2.0 * heightsA[0]);
}

}  // namespace orbis::test
