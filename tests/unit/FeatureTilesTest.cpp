#include "layers/vector/FeatureTiles.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

namespace orbis::vector {
namespace {

namespace fs = std::filesystem;
using globe::TileKey;

const fs::path kCountries = fs::path(ORBIS_SHARED_DATA_DIR) / "vector" / "naturalearth_lowres.shp";

#define REQUIRE_COUNTRIES() \
    if (!fs::exists(kCountries)) GTEST_SKIP() << "../shared/data is absent: no " << kCountries

/// Requests `keys` frame after frame until all are loaded (or failed), at most 10 s.
bool loadAll(FeatureTiles& tiles, const std::vector<TileKey>& keys, uint64_t& frame) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline) {
        ++frame;
        size_t ready = 0;
        for (const TileKey& k : keys) ready += tiles.request(k, 1.0, frame) ? 1 : 0;
        tiles.poll(frame);
        if (ready == keys.size()) return true;
        if (ready + tiles.errors().size() >= keys.size() && tiles.pendingCount() == 0) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
}

TEST(FeatureTiles, TilesLoadOnThePoolClippedToTheirExtent) {
    REQUIRE_COUNTRIES();
    jobs::ThreadPool pool(2, "test-vector");
    FeatureTilesOptions o;
    o.read.source = kCountries.string();
    FeatureTiles tiles(o, pool);
    const TileKey europe = TileKey::containing(10.0, 50.0, 3);
    uint64_t frame = 0;
    EXPECT_EQ(tiles.request(europe, 1.0, ++frame), nullptr);   // queued
    ASSERT_TRUE(loadAll(tiles, {europe}, frame));
    const FeatureTile* tile = tiles.request(europe, 1.0, ++frame);
    ASSERT_TRUE(tile);
    EXPECT_GT(tile->features.size(), 5u);
    EXPECT_LT(tile->features.size(), 40u);
    const globe::GeoExtent e = europe.extent();
    for (const Feature& f : tile->features)
        for (const glm::dvec3& c : f.coords) ASSERT_TRUE(c.x >= e.west && c.x <= e.east && c.y >= e.south && c.y <= e.north);
    EXPECT_GT(tiles.bytes(), 0u);
    EXPECT_EQ(tiles.bytes(), tile->bytes);
}

TEST(FeatureTiles, PastTheBudgetTheLeastRecentlyUsedTilesGoAndComeBackWhenAskedFor) {
    REQUIRE_COUNTRIES();
    jobs::ThreadPool pool(2, "test-vector");
    FeatureTilesOptions o;
    o.read.source = kCountries.string();
    o.budgetBytes = 1;   // only the tiles of the current frame stay
    FeatureTiles tiles(o, pool);
    uint64_t frame = 0;
    const TileKey a = TileKey::containing(10.0, 50.0, 3), b = TileKey::containing(-60.0, -10.0, 3);
    ASSERT_TRUE(loadAll(tiles, {a}, frame));
    ASSERT_TRUE(loadAll(tiles, {b}, frame));   // a is no longer asked for: evicted
    EXPECT_EQ(tiles.loadedCount(), 1u);
    EXPECT_EQ(tiles.request(a, 1.0, ++frame), nullptr);   // gone, queued again
    ASSERT_TRUE(loadAll(tiles, {a}, frame));
    EXPECT_TRUE(tiles.request(a, 1.0, ++frame));
}

TEST(FeatureTiles, ALoadNoFrameWantsAnyMoreIsCancelled) {
    REQUIRE_COUNTRIES();
    jobs::ThreadPool pool(1, "test-vector");
    std::atomic<bool> release{false};
    auto blocker = pool.submit(10.0, jobs::CancelToken{}, [&](const jobs::CancelToken&) {
        while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        return 0;
    });
    FeatureTilesOptions o;
    o.read.source = kCountries.string();
    FeatureTiles tiles(o, pool);
    const TileKey k = TileKey::containing(10.0, 50.0, 3);
    EXPECT_EQ(tiles.request(k, 1.0, 1), nullptr);   // queued behind the blocker
    tiles.poll(1);
    tiles.poll(3);   // frames 2 and 3 did not ask for it
    release = true;
    blocker.wait();
    for (uint64_t frame = 4; frame < 2000 && tiles.pendingCount() > 0; ++frame) {
        tiles.poll(frame);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_EQ(tiles.pendingCount(), 0u);
    EXPECT_EQ(tiles.loadedCount(), 0u);   // it never loaded
    EXPECT_TRUE(tiles.errors().empty());
}

TEST(FeatureTiles, AFailedTileSaysWhyAndIsNotRetried) {
    jobs::ThreadPool pool(1, "test-vector");
    FeatureTilesOptions o;
    o.read.source = "/nonexistent/roads.gpkg";
    FeatureTiles tiles(o, pool);
    uint64_t frame = 0;
    const TileKey k = TileKey::containing(0.0, 0.0, 2);
    EXPECT_FALSE(loadAll(tiles, {k}, frame));
    ASSERT_EQ(tiles.errors().size(), 1u);
    EXPECT_NE(tiles.errors()[0].find("/nonexistent/roads.gpkg: no such file"), std::string::npos) << tiles.errors()[0];
    EXPECT_EQ(tiles.request(k, 1.0, ++frame), nullptr);   // not retried
    tiles.poll(frame);
    EXPECT_EQ(tiles.pendingCount(), 0u);
}

}  // namespace
}  // namespace orbis::vector
