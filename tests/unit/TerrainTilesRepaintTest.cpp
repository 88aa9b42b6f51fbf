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

/// Frames asking for `key` in layer 1, each waited for.
void settle(TerrainTiles& tiles, const TileKey& key, uint64_t& frame, int frames) {
    for (int i = 0; i < frames; ++i) {
        tiles.beginFrame(frame++);
        tiles.request(1, key, 1000.0);
        tiles.endFrame();
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
    const auto frameOf = [&] {
        tiles.beginFrame(frame++);
        tiles.request(1, key, 1000.0);
        tiles.endFrame();
    };
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

}  // namespace
}  // namespace orbis::globe
