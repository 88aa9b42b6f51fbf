// A terrain image layer whose source is replaced (a vector layer's drape repainted on a pick or
// a rule switched off) keeps showing each tile's old image until its new one is painted: never
// a hole. Loads of the old source in flight are dropped; the newest source wins.
#include "base/ThreadPool.h"
#include "globe/TerrainTiles.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace orbis::globe {
namespace {

/// Paints every tile one grey level; waits while `hold` is set.
class SolidSource : public TileImageSource {
public:
    SolidSource(uint8_t grey, std::atomic<bool>* hold = nullptr, uint32_t maxLevel = 3) : grey_(grey), hold_(hold), maxLevel_(maxLevel) {}
    const std::string& name() const override { return name_; }
    uint32_t maxLevel(int) const override { return maxLevel_; }
    uint32_t minLevel() const override { return 0; }
    bool covers(const GeoExtent&) const override { return true; }
    Result<ImageryTile> readTile(const TileImageRequest& r, const jobs::CancelToken*) const override {
        while (hold_ && hold_->load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        return ImageryTile{r.size, std::vector<uint8_t>(size_t(r.size) * r.size * 4, grey_), true};
    }

private:
    std::string name_ = "solid";
    uint8_t grey_;
    std::atomic<bool>* hold_;
    uint32_t maxLevel_;
};

/// One frame asking for `key` in layer 1.
void frameAsking(TerrainTiles& tiles, const TileKey& key, uint64_t& frame) {
    tiles.beginFrame(frame++);
    tiles.request(1, key, 1000.0);
    tiles.endFrame();
}

/// Frames asking for `key` in layer 1, each waited for.
void settle(TerrainTiles& tiles, const TileKey& key, uint64_t& frame, int frames) {
    for (int i = 0; i < frames; ++i) {
        frameAsking(tiles, key, frame);
        tiles.waitIdle();
    }
}

uint8_t greyAt(const TerrainTiles& tiles, const TileKey& key) {
    const auto data = tiles.imagery(1, key);
    return data ? data->rgba[0] : 0;
}

/// One image layer of 16-pixel tiles, first painted grey 10, loaded on one worker.
TerrainTilesSettings smallImages() {
    TerrainTilesSettings settings;
    settings.imageSize = 16;
    return settings;
}

class TerrainTilesRepaint : public ::testing::Test {
protected:
    jobs::ThreadPool pool{1};
    TerrainTiles tiles{smallImages(), {}, {std::make_shared<SolidSource>(10)}, &pool};
};

TEST_F(TerrainTilesRepaint, TheOldImageServesUntilTheNewOneIsPainted) {
    const TileKey key{2, 3, 1};
    uint64_t frame = 1;
    const auto frameOf = [&] { frameAsking(tiles, key, frame); };
    settle(tiles, key, frame, 4);
    ASSERT_EQ(greyAt(tiles, key), 10);
    EXPECT_EQ(tiles.dataGeneration(1, key), 0u);

    std::atomic<bool> hold{true};
    tiles.replaceImagery(1, std::make_shared<SolidSource>(20, &hold));
    for (int i = 0; i < 5; ++i) {
        frameOf();
        EXPECT_EQ(tiles.state(1, key), DataState::Ready) << "the stale tile is still ready";
        EXPECT_EQ(greyAt(tiles, key), 10) << "the old image while the new one is painted";
        EXPECT_EQ(tiles.readyAncestor(1, key), key);
    }
    EXPECT_TRUE(tiles.loading());
    // Replaced again while the repaint runs: that repaint is dropped, the newest source wins.
    tiles.replaceImagery(1, std::make_shared<SolidSource>(30));
    hold = false;
    for (int i = 0; i < 6 && (greyAt(tiles, key) != 30 || tiles.loading()); ++i) {
        frameOf();
        tiles.waitIdle();
    }
    EXPECT_EQ(greyAt(tiles, key), 30);
    EXPECT_EQ(tiles.dataGeneration(1, key), 2u);
    EXPECT_FALSE(tiles.loading());
}

TEST_F(TerrainTilesRepaint, ARepaintWithinRegionsPaintsOnlyTheTilesThatReachThem) {
    // Two level-2 tiles far apart (90 degrees wide): a change near the first repaints it, the
    // second keeps its image and its data generation (its GPU slot is not uploaded again).
    const TileKey near{2, 4, 1}, far{2, 0, 2};
    uint64_t frame = 1;
    const auto both = [&] {
        tiles.beginFrame(frame++);
        tiles.request(1, near, 1000.0);
        tiles.request(1, far, 1000.0);
        tiles.endFrame();
        tiles.waitIdle();
    };
    for (int i = 0; i < 4; ++i) both();
    ASSERT_EQ(greyAt(tiles, near), 10);
    ASSERT_EQ(greyAt(tiles, far), 10);
    const GeoExtent e = near.extent();
    const GeoExtent region{e.west + 1.0, e.south + 1.0, e.west + 2.0, e.south + 2.0};
    tiles.repaintImagery(1, std::make_shared<SolidSource>(40), std::span(&region, 1), 0.25);
    for (int i = 0; i < 4; ++i) both();
    EXPECT_EQ(greyAt(tiles, near), 40);
    EXPECT_EQ(tiles.dataGeneration(1, near), 1u);
    EXPECT_EQ(greyAt(tiles, far), 10) << "a tile the change does not reach is not painted again";
    EXPECT_EQ(tiles.dataGeneration(1, far), 0u);
    // A region just past the far tile's edge, within its margin, reaches it; a turn away too.
    const GeoExtent f = far.extent();
    const GeoExtent past{f.east + 360.0 + 1.0, f.south, f.east + 360.0 + 2.0, f.south + 1.0};
    tiles.repaintImagery(1, std::make_shared<SolidSource>(50), std::span(&past, 1), 0.25);
    for (int i = 0; i < 4; ++i) both();
    EXPECT_EQ(greyAt(tiles, far), 50);
    EXPECT_EQ(greyAt(tiles, near), 40);
    // A source with another finest level: everything is painted again.
    tiles.repaintImagery(1, std::make_shared<SolidSource>(60, nullptr, 5), std::span(&past, 1), 0.25);
    for (int i = 0; i < 4; ++i) both();
    EXPECT_EQ(greyAt(tiles, near), 60);
}

TEST_F(TerrainTilesRepaint, TilesFinerThanTheNewSourcePaintsGoWithTheirOldImages) {
    // A drape whose finest level drops (the vector layer's maxLevel lowered): the finer tiles
    // it painted before are never asked for again, so they must not keep serving old images.
    const TileKey fine{3, 6, 2};
    uint64_t frame = 1;
    settle(tiles, fine, frame, 5);
    ASSERT_EQ(tiles.readyAncestor(1, fine), fine);
    tiles.replaceImagery(1, std::make_shared<SolidSource>(20, nullptr, 1));
    EXPECT_EQ(tiles.state(1, fine), DataState::Missing);
    settle(tiles, fine, frame, 5);
    const auto ready = tiles.readyAncestor(1, fine);
    ASSERT_TRUE(ready);
    EXPECT_EQ(ready->level, 1u);
    EXPECT_EQ(greyAt(tiles, *ready), 20);
}

/// Fails (as a server that is down or times out) while `down` is set; then paints grey 40.
class FlakySource : public TileImageSource {
public:
    explicit FlakySource(std::atomic<bool>& down) : down_(down) {}
    const std::string& name() const override { return name_; }
    uint32_t maxLevel(int) const override { return 0; }
    uint32_t minLevel() const override { return 0; }
    bool covers(const GeoExtent&) const override { return true; }
    Result<ImageryTile> readTile(const TileImageRequest& r, const jobs::CancelToken*) const override {
        ++reads;
        if (down_) return makeError("http://127.0.0.1/0/0/0.png: HTTP 503");
        return ImageryTile{r.size, std::vector<uint8_t>(size_t(r.size) * r.size * 4, 40), true};
    }
    mutable std::atomic<int> reads{0};

private:
    std::string name_ = "flaky";
    std::atomic<bool>& down_;
};

// A tile whose load failed is tried again while it is wanted, after a back-off that doubles
// (1 s, 2 s, ...), kTileRetries times at most: a server that comes back fills it in, one that
// stays down is not hammered.
TEST(TerrainTilesRetry, AFailedTileIsTriedAgainWithBackOffAndABound) {
    std::atomic<bool> down{true};
    auto source = std::make_shared<FlakySource>(down);
    TerrainTiles tiles{smallImages(), {}, {source}, nullptr};   // loads inline
    const TileKey key{0, 0, 0};
    uint64_t frame = 1;
    const auto frameOf = [&] { frameAsking(tiles, key, frame); };
    frameOf();
    EXPECT_EQ(tiles.state(1, key), DataState::Failed);
    EXPECT_EQ(source->reads.load(), 1);
    for (int i = 0; i < 20; ++i) frameOf();   // within the first second: no new attempt
    EXPECT_EQ(source->reads.load(), 1);
    down = false;
    std::this_thread::sleep_for(kTileRetryDelay + std::chrono::milliseconds(50));
    frameOf();
    EXPECT_EQ(source->reads.load(), 2);
    EXPECT_EQ(tiles.state(1, key), DataState::Ready);
    ASSERT_TRUE(tiles.imagery(1, key));
    EXPECT_EQ(tiles.imagery(1, key)->rgba[0], 40);
    EXPECT_EQ(tiles.stats().retried, 1u);
    EXPECT_EQ(tiles.errors().size(), 1u);

    // A server that stays down: kTileRetries more attempts, each after twice the wait before.
    std::atomic<bool> gone{true};
    auto dead = std::make_shared<FlakySource>(gone);
    TerrainTiles other{smallImages(), {}, {dead}, nullptr};
    const auto start = std::chrono::steady_clock::now();
    std::vector<double> attempts;
    int seen = 0;
    while (std::chrono::steady_clock::now() - start < kTileRetryDelay * 40) {
        frameAsking(other, key, frame);
        if (dead->reads.load() != seen) {
            seen = dead->reads.load();
            attempts.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        }
        if (seen == int(kTileRetries) + 1 && std::chrono::steady_clock::now() - start > kTileRetryDelay * 20) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_EQ(attempts.size(), size_t(kTileRetries) + 1) << "the first load and kTileRetries more, then no more";
    const double unit = std::chrono::duration<double>(kTileRetryDelay).count();
    for (size_t k = 1; k < attempts.size(); ++k)
        EXPECT_GE(attempts[k] - attempts[k - 1], unit * double(1u << (k - 1)) - 0.01) << "attempt " << k;
    EXPECT_EQ(other.state(1, key), DataState::Failed);
}

}  // namespace
}  // namespace orbis::globe
